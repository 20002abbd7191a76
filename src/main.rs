//! The `caymos` command line. Exit codes: 0 analysed; 1 unreadable or invalid
//! scene or bad arguments; 2 a valid scene outside the handled class.

use std::process::ExitCode;

use clap::{Args, Parser, Subcommand, ValueEnum};

use caymos::analysis::{Analysis, Scope, Solved, analyse, analyse_with};
use caymos::bundled;
use caymos::commands;
use caymos::present::{self, ComponentNo};
use caymos::report::Report;
use caymos::scene::Scene;
use caymos::schema::{ErrorBody, ErrorDoc, ErrorKind, ListDoc, ListedScene, SceneOrigin, Versioned};

/// See Cargo.toml and [`caymos::alloc`]: small vectors per certified question made glibc's
/// allocator about a fifth of a small scene's analysis.
#[global_allocator]
static ALLOCATOR: caymos::alloc::Allocator = caymos::alloc::Allocator;

#[derive(Parser, Debug)]
#[command(
    name = "caymos",
    version,
    about = "Cayley analysis of 1-dof tree-decomposable planar linkages",
    long_about = "Cayley analysis of 1-dof tree-decomposable planar linkages.\n\nWith no command, `caymos [SCENE]` opens the terminal UI (on the bundled Jansen leg by default).",
    args_conflicts_with_subcommands = true
)]
struct Cli {
    /// A scene file or bundled scene name to open in the terminal UI.
    scene: Option<String>,
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Clone, Copy, Debug, ValueEnum, PartialEq, Eq)]
enum Format {
    Text,
    Json,
}

/// Output of `caymos graph`.
#[derive(Clone, Copy, Debug, ValueEnum, PartialEq, Eq)]
enum GraphFormat {
    /// Graphviz DOT (`caymos graph jansen | dot -Tsvg > jansen.svg`).
    Dot,
    Json,
}

/// `report`'s formats: also Markdown, a CI job summary (headings and tables,
/// no colour, no box drawing).
#[derive(Clone, Copy, Debug, ValueEnum, PartialEq, Eq)]
enum ReportFormat {
    Text,
    Json,
    Markdown,
}

/// How the motion commands analyse the scene before they walk it.
#[derive(Args, Debug, Clone)]
struct AnalysisArgs {
    /// The base non-edge as two joint names, e.g. `--base A,B`.
    #[arg(long)]
    base: Option<String>,
    /// The full analysis (every type), so component numbers follow `report --all`.
    /// Without it, scenes with more than 2^16 types, or whose full sweep is
    /// estimated above its budget, are analysed lazily and further
    /// components are walked on demand.
    #[arg(long)]
    all: bool,
}

/// How far the walking commands go.
#[derive(Args, Debug, Clone)]
struct WalkArgs {
    /// Largest joint move between samples, in scene units (default: 1% of the drawing's bounding-box diagonal).
    #[arg(long)]
    step: Option<f64>,
    /// Sample budget: at most this many realizations are computed per walk; the output says when it is reached.
    #[arg(long, default_value_t = caymos::tolerance::DEFAULT_MAX_SAMPLES, value_parser = sample_budget)]
    max_samples: usize,
}

#[derive(Subcommand, Debug)]
enum Family {
    /// A chain of four-cycles, each step carried by the one before.
    Chain {
        /// 1 to 100000.
        #[arg(long, value_parser = generated_steps)]
        steps: usize,
    },
    /// Joints each built on the one base pair A, B by two bars.
    Fan {
        /// 1 to 100000.
        #[arg(long, value_parser = generated_steps)]
        joints: usize,
    },
    /// Jansen legs sharing one crank.
    Strandbeest {
        /// 1 to 10000.
        #[arg(long, value_parser = generated_legs)]
        legs: usize,
    },
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Explore a scene in the terminal UI (the default command).
    Tui {
        /// A scene file, or the name of a bundled scene (default: the Jansen leg).
        scene: Option<String>,
        /// The base non-edge as two joint names.
        #[arg(long)]
        base: Option<String>,
    },
    /// Analyse a scene: class, base, steps, complexity, Cayley vector, drawn realization.
    Report {
        /// A scene file, or the name of a bundled scene (default: the Jansen leg).
        scene: Option<String>,
        #[arg(long, value_enum, default_value = "text")]
        format: ReportFormat,
        /// The base non-edge as two joint names, e.g. `--base P,X`.
        #[arg(long)]
        base: Option<String>,
        /// The full analysis (every type, every component) and every oriented
        /// interval in the text, however many. Without it, scenes with more
        /// than 2^16 types, or whose full sweep is estimated above its budget
        /// (the report gives both numbers), get the lazy analysis (the drawn
        /// component only).
        #[arg(long)]
        all: bool,
        /// The lazy analysis (the component through the drawn realization)
        /// even for a small scene.
        #[arg(long, conflicts_with = "all")]
        lazy: bool,
        /// Include each phase's wall-clock time (`timings_us` in JSON); without
        /// it two runs print the same document.
        #[arg(long)]
        timings: bool,
    },
    /// List the bundled scenes and the hard cases.
    List {
        #[arg(long, value_enum, default_value = "text")]
        format: Format,
    },
    /// Print the JSON Schema of a `--format json` document.
    Schema {
        /// Which `--format json` document.
        #[arg(value_parser = clap::builder::PossibleValuesParser::new(caymos::schema::SCHEMAS.iter().map(|(n, _)| *n)))]
        name: String,
    },
    /// The linkage graph and its decomposition for Graphviz: joints, bars, clusters, base, construction steps.
    Graph {
        /// A scene file, or the name of a bundled scene (default: the Jansen leg).
        scene: Option<String>,
        #[arg(long, value_enum, default_value = "dot")]
        format: GraphFormat,
        /// The base non-edge as two joint names, e.g. `--base P,X`.
        #[arg(long)]
        base: Option<String>,
    },
    /// Both motion paths between two realizations (`drawn` or TYPE@LAMBDA), or the closest pair.
    Path {
        scene: Option<String>,
        /// `drawn` or TYPE@LAMBDA, e.g. `-+-+@41.2`.
        #[arg(long, allow_hyphen_values = true)]
        from: String,
        #[arg(long, allow_hyphen_values = true)]
        to: String,
        #[arg(long, value_enum, default_value = "text")]
        format: Format,
        #[command(flatten)]
        analysis: AnalysisArgs,
        #[command(flatten)]
        walk: WalkArgs,
    },
    /// CSV of joint positions along a component or a path.
    Trace {
        scene: Option<String>,
        /// Component number as in the report, from 1 (default: the drawn realization's).
        #[arg(long, conflicts_with_all = ["from", "to"], value_parser = component_no)]
        component: Option<ComponentNo>,
        #[arg(long, requires = "to", allow_hyphen_values = true)]
        from: Option<String>,
        #[arg(long, requires = "from", allow_hyphen_values = true)]
        to: Option<String>,
        /// Which arc between --from and --to: 1 (along the component) or 2 (against); default the shorter.
        #[arg(long, requires = "from")]
        arc: Option<usize>,
        /// Joints to trace, e.g. `F,K` (default: all).
        #[arg(long)]
        joints: Option<String>,
        /// Add the angle of bar `A,B` (one end a ground joint, the pivot) in degrees from the ground line: column `A-B.angle`.
        #[arg(long)]
        angle: Option<String>,
        /// Append the complete Cayley distance vector (the Cayley curve) to each row.
        #[arg(long)]
        cayley: bool,
        #[arg(long)]
        output: Option<std::path::PathBuf>,
        #[command(flatten)]
        analysis: AnalysisArgs,
        #[command(flatten)]
        walk: WalkArgs,
    },
    /// Closest pair of realizations between two components, by Cayley distance.
    Closest {
        scene: Option<String>,
        /// Two component numbers as in the report (from 1), e.g. `1,4`.
        #[arg(long)]
        components: String,
        /// Relative gap to certify the distance to (proven lower bound vs. the pair found).
        #[arg(long, default_value_t = caymos::tolerance::DEFAULT_GAP)]
        gap: f64,
        #[arg(long, value_enum, default_value = "text")]
        format: Format,
        #[command(flatten)]
        analysis: AnalysisArgs,
    },
    /// How the analysis changes as one bar's length (or a joint coordinate)
    /// varies: per sample the Cayley space, components and their sizes, and
    /// the exact values where the structure changes.
    Sweep {
        scene: Option<String>,
        /// The bar whose length varies, e.g. `A,B`.
        #[arg(long, conflicts_with = "joint", required_unless_present = "joint")]
        bar: Option<String>,
        /// The joint coordinate that varies instead, e.g. `C.x` or `C.y`.
        #[arg(long)]
        joint: Option<String>,
        /// The first value.
        #[arg(long, allow_hyphen_values = true)]
        from: f64,
        /// The last value (above --from).
        #[arg(long, allow_hyphen_values = true)]
        to: f64,
        /// Evenly spaced samples, both ends included (2 to 100000).
        #[arg(long, default_value_t = 64)]
        steps: usize,
        /// A bar with a ground joint: per component, whether it turns fully.
        #[arg(long)]
        input_bar: Option<String>,
        /// Take only the samples whose index is ≡ I − 1 (mod N), and the transitions after them.
        #[arg(long, default_value = "1/1")]
        shard: String,
        /// The base non-edge as two joint names (default: the scene's, else the one chosen).
        #[arg(long)]
        base: Option<String>,
        #[arg(long, value_enum, default_value = "text")]
        format: Format,
    },
    /// Speed against error: every method's time and error against the double-double reference.
    Bench {
        /// Scene files, bundled names or hard cases (`hard:sliver`, …); default: all bundled scenes and hard cases.
        scenes: Vec<String>,
        #[arg(long, value_enum, default_value = "text")]
        format: Format,
        /// Timed repetitions after a warm-up (the median is reported); 1 to 1000.
        #[arg(long, default_value_t = 5, value_parser = repeat_count)]
        repeat: usize,
        /// Also the lazy walk on generated chains (10…1000 steps) and Strandbeests (1…12 legs).
        #[arg(long)]
        scaling: bool,
    },
    /// Write a generated scene (TOML) for scaling experiments.
    Generate {
        #[command(subcommand)]
        family: Family,
        #[arg(long, global = true)]
        output: Option<std::path::PathBuf>,
    },
    /// SVG of the drawn linkage with the traces of its joints over a component.
    Svg {
        scene: Option<String>,
        /// Component number as in the report, from 1 (default: the drawn realization's).
        #[arg(long, value_parser = component_no)]
        component: Option<ComponentNo>,
        #[arg(long)]
        joints: Option<String>,
        #[arg(long)]
        output: Option<std::path::PathBuf>,
        #[command(flatten)]
        analysis: AnalysisArgs,
        #[command(flatten)]
        walk: WalkArgs,
    },
}

/// An error to print (one line on stderr; with `--format json` also a JSON
/// document on stdout) with its exit code.
struct Failure {
    body: ErrorBody,
    code: u8,
}

impl Failure {
    fn new(kind: ErrorKind, message: String) -> Self {
        let code = if kind == ErrorKind::OutsideClass { 2 } else { 1 };
        Failure { body: ErrorBody { kind, message, file: None, line: None, column: None }, code }
    }

    /// The line for stderr: `file:line:column: message` when there is a place.
    fn line(&self) -> String {
        let b = &self.body;
        match &b.file {
            Some(file) => caymos::scene::SceneError {
                file: file.clone(),
                line: b.line,
                column: b.column,
                message: b.message.clone(),
            }
            .to_string(),
            None => b.message.clone(),
        }
    }
}

impl From<caymos::scene::SceneError> for Failure {
    fn from(e: caymos::scene::SceneError) -> Self {
        let body = ErrorBody {
            kind: ErrorKind::Scene,
            message: e.message,
            file: Some(e.file),
            line: e.line,
            column: e.column,
        };
        Failure { body, code: 1 }
    }
}

/// Whether the command line asks for JSON (`--format json` or `--format=json`),
/// read from the raw arguments so that even an argument error can be JSON.
fn json_requested(args: &[String]) -> bool {
    args.windows(2).any(|w| w[0] == "--format" && w[1] == "json") || args.iter().any(|a| a == "--format=json")
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().collect();
    let json = json_requested(&args);
    let cli = match Cli::try_parse_from(&args) {
        Ok(cli) => cli,
        Err(e) if json && e.use_stderr() => {
            let text = e.to_string();
            let message = text.lines().next().unwrap_or("").trim_start_matches("error: ").to_string();
            let _ = e.print();
            emit(&format!(
                "{}\n",
                Versioned::new(ErrorDoc { error: Failure::new(ErrorKind::Arguments, message).body }).to_json()
            ));
            return ExitCode::from(1);
        }
        Err(e) => {
            let code = if e.use_stderr() { 1 } else { 0 };
            let _ = e.print();
            return ExitCode::from(code);
        }
    };
    let command = cli.command.unwrap_or(Command::Tui { scene: cli.scene, base: None });
    match run(command) {
        Ok(code) => ExitCode::from(code),
        Err(f) => {
            eprintln!("caymos: {}", f.line());
            if json {
                emit(&format!("{}\n", Versioned::new(ErrorDoc { error: f.body }).to_json()));
            }
            ExitCode::from(f.code)
        }
    }
}

fn run(command: Command) -> Result<u8, Failure> {
    match command {
        Command::Tui { scene, base } => {
            let scene = bundled::resolve(scene.as_deref())?;
            let base = base.map(|b| parse_base(&scene, &b)).transpose()?;
            if !std::io::IsTerminal::is_terminal(&std::io::stdout()) {
                return Err(Failure::new(
                    ErrorKind::Io,
                    "the terminal UI needs a terminal; for scripts use `caymos report` (see --help)".into(),
                ));
            }
            caymos::tui::run(scene, base).map_err(|e| Failure::new(ErrorKind::Io, format!("terminal: {e}")))?;
            Ok(0)
        }
        Command::List { format } => {
            let mut scenes = Vec::new();
            for b in bundled::BUNDLED {
                let scene = bundled::load(b.name)?;
                scenes.push(ListedScene {
                    name: b.name.to_string(),
                    description: scene.description,
                    origin: SceneOrigin::Bundled,
                });
            }
            for h in caymos::generate::hard_cases() {
                scenes.push(ListedScene { name: h.name, description: h.description, origin: SceneOrigin::HardCase });
            }
            match format {
                Format::Json => emit(&format!("{}\n", Versioned::new(ListDoc { scenes }).to_json())),
                Format::Text => {
                    let line = |s: &ListedScene| format!("{:<24} {}\n", s.name, s.description.as_deref().unwrap_or(""));
                    for s in scenes.iter().filter(|s| s.origin == SceneOrigin::Bundled) {
                        emit(&line(s));
                    }
                    emit("\nHard cases (THEORY.md §6), generated; open them by name like the bundled scenes:\n");
                    for s in scenes.iter().filter(|s| s.origin == SceneOrigin::HardCase) {
                        emit(&line(s));
                    }
                }
            }
            Ok(0)
        }
        Command::Schema { name } => {
            let schema = caymos::schema::schema(&name).ok_or_else(|| arg_error(format!("no schema called {name}")))?;
            emit(&format!("{}\n", serde_json::to_string_pretty(&schema).expect("schemas serialize")));
            Ok(0)
        }
        Command::Report { scene, format, base, all, lazy, timings } => {
            let scene = bundled::resolve(scene.as_deref())?;
            let base = base.map(|b| parse_base(&scene, &b)).transpose()?;
            let scope = if all {
                Scope::Full
            } else if lazy {
                Scope::Lazy
            } else {
                Scope::Auto
            };
            let analysis = analyse_with(scene, base, scope)?;
            let report = Report::with_timings(&analysis, timings);
            match format {
                ReportFormat::Json => emit(&format!("{}\n", report.to_json())),
                ReportFormat::Text => emit(&report.to_text_with(all)),
                ReportFormat::Markdown => emit(&report.to_markdown(all)),
            }
            let failed = matches!(
                report.no_realization.as_ref().map(|n| &n.data),
                Some(caymos::analysis::NoRealization::NumericFailure { .. })
            );
            Ok(if !report.one_dof_tree_decomposable {
                2
            } else if failed {
                3
            } else {
                0
            })
        }
        Command::Graph { scene, format, base } => {
            let scene = bundled::resolve(scene.as_deref())?;
            let base = base.map(|b| parse_base(&scene, &b)).transpose()?;
            let graph = caymos::graph::graph_report(&scene, base)?;
            match format {
                GraphFormat::Json => emit(&format!("{}\n", Versioned::new(&graph).to_json())),
                GraphFormat::Dot => emit(&caymos::graph::to_dot(&graph)),
            }
            // Like `report`: outside the handled class exits 2 (the linkage is still exported).
            match &graph.outside {
                Some(o) => {
                    eprintln!("caymos: {}: outside the handled class: {}", scene.source, o.message);
                    Ok(2)
                }
                None => Ok(0),
            }
        }
        Command::Path { scene, from, to, format, analysis, walk } => {
            let mut a = solved(scene.as_deref(), &analysis)?;
            let walk = walk_options(&walk, &a)?;
            let (linkage, s) = parts(&mut a)?;
            commands::include_specs(s, &[&from, &to]);
            let report = commands::path(linkage, s, &from, &to, walk).map_err(arg_error)?;
            match format {
                Format::Json => emit(&format!("{}\n", Versioned::new(&report).to_json())),
                Format::Text => emit(&report.to_text()),
            }
            note_all(present::lazy_note(s));
            Ok(0)
        }
        Command::Trace { scene, component, from, to, arc, joints, angle, cayley, output, analysis, walk } => {
            let mut a = solved(scene.as_deref(), &analysis)?;
            let angle = angle.map(|b| commands::input_bar(&a.scene, &b, "--angle")).transpose().map_err(arg_error)?;
            let walk = walk_options(&walk, &a)?;
            let (linkage, s) = parts(&mut a)?;
            commands::include_specs(s, &[from.as_deref().unwrap_or("drawn"), to.as_deref().unwrap_or("drawn")]);
            if let Some(k) = component {
                commands::walk_components(s, k.number());
            }
            let joints = commands::parse_joints(linkage, joints.as_deref()).map_err(arg_error)?;
            let between = from.as_deref().zip(to.as_deref()).map(|(f, t)| (f, t, arc));
            let component = component.map(ComponentNo::index);
            let segments = commands::trace_segments(linkage, s, component, between).map_err(arg_error)?;
            let columns = commands::TraceColumns { joints, angle, cayley };
            let branches = commands::branches_out(s, &segments);
            let summary = write_streamed(output, |out| commands::trace_csv(linkage, s, segments, &columns, walk, out))?;
            let walked = present::walk_notes(&summary, walk.max_samples);
            note_all(present::lazy_note(s).into_iter().chain(walked).chain(branches.iter().map(present::branch_taken)));
            Ok(0)
        }
        Command::Closest { scene, components, gap, format, analysis } => {
            let mut a = solved(scene.as_deref(), &analysis)?;
            let (linkage, s) = parts(&mut a)?;
            let pair: Vec<Option<ComponentNo>> = components.split(',').map(ComponentNo::parse).collect();
            let [Some(i), Some(j)] = pair[..] else {
                return Err(arg_error(format!(
                    "--components {components}: give two component numbers as in the report (from 1), e.g. 1,4"
                )));
            };
            commands::walk_components(s, i.max(j).number());
            let opts = caymos::distance::ClosestOptions { gap, ..Default::default() };
            let c = commands::closest_with(linkage, s, i.index(), j.index(), opts).map_err(arg_error)?;
            match format {
                Format::Json => {
                    emit(&format!("{}\n", Versioned::new(&c).to_json()));
                    note_all(present::lazy_note(s));
                }
                Format::Text => {
                    emit(&c.to_text());
                    if let Some(note) = present::lazy_note(s) {
                        emit(&format!("  note: {note}\n"));
                    }
                }
            }
            Ok(0)
        }
        Command::Sweep { scene, bar, joint, from, to, steps, input_bar, shard, base, format } => {
            let scene = bundled::resolve(scene.as_deref())?;
            let base = base.map(|b| parse_base(&scene, &b)).transpose()?;
            let parameter = commands::sweep_parameter(&scene, bar.as_deref(), joint.as_deref()).map_err(arg_error)?;
            commands::check_sweep_range(parameter, from, to, steps, commands::Naming::Flags).map_err(arg_error)?;
            let shard = commands::Shard::parse(&shard).map_err(arg_error)?;
            let input =
                input_bar.map(|b| commands::input_bar(&scene, &b, "--input-bar")).transpose().map_err(arg_error)?;
            let setup = caymos::sweep::Setup::new(scene, parameter, base, input);
            let report = commands::sweep_report(&setup, from, to, steps, shard);
            match format {
                Format::Json => emit(&format!("{}\n", Versioned::new(&report).to_json())),
                Format::Text => emit(&report.to_text()),
            }
            Ok(0)
        }
        Command::Bench { scenes, format, repeat, scaling } => {
            let named = !scenes.is_empty();
            let mut inputs: Vec<caymos::scene::Scene> = Vec::new();
            if named {
                for name in &scenes {
                    inputs.push(bundled::resolve(Some(name))?);
                }
            } else {
                for b in bundled::BUNDLED {
                    inputs.push(bundled::load(b.name)?);
                }
                inputs.extend(caymos::generate::hard_cases());
            }
            let mut report = caymos::bench::BenchReport {
                repeat,
                methods: Vec::new(),
                analysis: Vec::new(),
                stepping: Vec::new(),
                scaling: Vec::new(),
                skipped: Vec::new(),
            };
            for scene in inputs {
                report.analysis.extend(caymos::bench::analysis_row(&scene, repeat));
                let analysis = analyse(scene, None)?;
                match analysis.outcome.clone() {
                    Ok(solved) => {
                        let (m, s) = caymos::bench::bench_scene(&analysis, &solved, repeat);
                        report.methods.extend(m);
                        report.stepping.extend(s);
                    }
                    Err(o) => report.skipped.push(caymos::bench::Skipped {
                        scene: analysis.scene.name.clone(),
                        reason: format!("outside the handled class: {}", present::outside(&o, &analysis.linkage)),
                    }),
                }
            }
            if scaling {
                for (family, scene) in caymos::bench::scaling_scenes() {
                    report.scaling.extend(caymos::bench::scaling_row(&family, scene, repeat));
                }
            }
            match format {
                Format::Json => emit(&format!("{}\n", Versioned::new(&report).to_json())),
                Format::Text => emit(&report.to_text()),
            }
            // Like `report`: a named scene outside the class (or nothing benchmarked) exits 2.
            let nothing = report.methods.is_empty() && report.scaling.is_empty();
            Ok(if (named && !report.skipped.is_empty()) || nothing { 2 } else { 0 })
        }
        Command::Generate { family, output } => {
            let scene = match family {
                Family::Chain { steps } => caymos::generate::chain(steps),
                Family::Fan { joints } => caymos::generate::fan(joints),
                Family::Strandbeest { legs } => caymos::generate::strandbeest(legs),
            };
            write_out(output, &caymos::generate::to_toml(&scene))?;
            Ok(0)
        }
        Command::Svg { scene, component, joints, output, analysis, walk } => {
            let mut a = solved(scene.as_deref(), &analysis)?;
            let walk = walk_options(&walk, &a)?;
            let title = a.scene.name.clone();
            let (linkage, s) = parts(&mut a)?;
            if let Some(k) = component {
                commands::walk_components(s, k.number());
            }
            let joints = commands::parse_joints(linkage, joints.as_deref()).map_err(arg_error)?;
            let component = component.map(ComponentNo::index);
            let segments = commands::trace_segments(linkage, s, component, None).map_err(arg_error)?;
            let svg = commands::svg(&title, linkage, s, segments, &joints, walk);
            write_out(output, &svg.text)?;
            if svg.points_cut {
                note_all([present::svg_cut_note(joints.len())]);
            }
            note_all(present::lazy_note(s).into_iter().chain(present::walk_notes(&svg.walk, walk.max_samples)));
            Ok(0)
        }
    }
}

/// Write to stdout; a reader that went away (`caymos list | head`) ends the
/// program quietly instead of panicking.
fn emit(text: &str) {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    if let Err(e) = out.write_all(text.as_bytes()).and_then(|_| out.flush()) {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        eprintln!("caymos: cannot write output: {e}");
        std::process::exit(1);
    }
}

/// Load and analyse a scene that must be in the handled class and have a
/// realization (exit 2 outside the class, 1 with no realization, saying why).
fn solved(scene: Option<&str>, args: &AnalysisArgs) -> Result<Analysis, Failure> {
    let scene = bundled::resolve(scene)?;
    let base = args.base.as_deref().map(|b| parse_base(&scene, b)).transpose()?;
    let analysis = analyse_with(scene, base, if args.all { Scope::Full } else { Scope::Auto })?;
    let at_file = |mut f: Failure| {
        f.body.file = Some(analysis.scene.source.clone());
        f
    };
    let why = match &analysis.outcome {
        Ok(s) => match commands::require_component(&analysis.linkage, s) {
            Ok(()) => return Ok(analysis),
            Err(why) => Failure::new(ErrorKind::NoRealization, why),
        },
        Err(o) => Failure::new(
            ErrorKind::OutsideClass,
            format!("outside the handled class: {}", present::outside(o, &analysis.linkage)),
        ),
    };
    Err(at_file(why))
}

/// The linkage and the one solved analysis of `a`, borrowed apart so a
/// command can extend the analysis (walk more components) while naming joints.
fn parts(a: &mut Analysis) -> Result<(&caymos::linkage::Linkage, &mut Solved), Failure> {
    match &mut a.outcome {
        Ok(s) => Ok((&a.linkage, s)),
        Err(o) => Err(Failure::new(ErrorKind::OutsideClass, present::outside(o, &a.linkage))),
    }
}

/// Notes about the output (not errors) on stderr, one line each.
fn note_all(notes: impl IntoIterator<Item = String>) {
    for n in notes {
        eprintln!("caymos: note: {n}");
    }
}

fn arg_error(message: String) -> Failure {
    Failure::new(ErrorKind::Arguments, message)
}

/// A component number as in the report (from 1).
fn component_no(text: &str) -> Result<ComponentNo, String> {
    ComponentNo::parse(text).ok_or_else(|| "give a component number as in the report, from 1".into())
}

/// Stream output to a file or stdout as it is made (buffered); a reader that
/// went away ends the program quietly, like [`emit`].
fn write_streamed<R>(
    output: Option<std::path::PathBuf>,
    write: impl FnOnce(&mut dyn std::io::Write) -> std::io::Result<R>,
) -> Result<R, Failure> {
    use std::io::Write;
    let failed = |what: &str, e: std::io::Error| Failure::new(ErrorKind::Io, format!("{what}: cannot write: {e}"));
    match output {
        Some(path) => {
            let file = std::fs::File::create(&path).map_err(|e| failed(&path.display().to_string(), e))?;
            let mut out = std::io::BufWriter::new(file);
            let r = write(&mut out).and_then(|r| out.flush().map(|_| r));
            r.map_err(|e| failed(&path.display().to_string(), e))
        }
        None => {
            let mut out = std::io::BufWriter::new(std::io::stdout().lock());
            match write(&mut out).and_then(|r| out.flush().map(|_| r)) {
                Ok(r) => Ok(r),
                Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => std::process::exit(0),
                Err(e) => Err(failed("standard output", e)),
            }
        }
    }
}

fn write_out(output: Option<std::path::PathBuf>, text: &str) -> Result<(), Failure> {
    match output {
        Some(path) => std::fs::write(&path, text)
            .map_err(|e| Failure::new(ErrorKind::Io, format!("{}: cannot write: {e}", path.display()))),
        None => {
            emit(text);
            Ok(())
        }
    }
}

fn walk_options(args: &WalkArgs, a: &Analysis) -> Result<commands::Walk, Failure> {
    let step = match args.step {
        None => commands::default_step(a),
        Some(s) if s.is_finite() && s > 0.0 => s,
        Some(s) => return Err(arg_error(format!("--step {s}: give a positive length in scene units"))),
    };
    Ok(commands::Walk { step, max_samples: args.max_samples })
}

/// A count from 1 to `max`: every command has a bounded cost.
fn count_up_to(text: &str, max: usize) -> Result<usize, String> {
    match text.trim().parse::<usize>() {
        Ok(n) if (1..=max).contains(&n) => Ok(n),
        _ => Err(format!("give a whole number from 1 to {max} (a bounded cost)")),
    }
}

/// `--max-samples`: 1 to [`caymos::tolerance::MAX_SAMPLES_LIMIT`].
fn sample_budget(text: &str) -> Result<usize, String> {
    count_up_to(text, caymos::tolerance::MAX_SAMPLES_LIMIT)
}

/// `bench --repeat`: 1 to [`caymos::tolerance::MAX_REPEAT`].
fn repeat_count(text: &str) -> Result<usize, String> {
    count_up_to(text, caymos::tolerance::MAX_REPEAT)
}

/// `generate chain --steps`: 1 to [`caymos::tolerance::MAX_GENERATED_STEPS`].
fn generated_steps(text: &str) -> Result<usize, String> {
    count_up_to(text, caymos::tolerance::MAX_GENERATED_STEPS)
}

/// `generate strandbeest --legs`: 1 to [`caymos::tolerance::MAX_GENERATED_LEGS`].
fn generated_legs(text: &str) -> Result<usize, String> {
    count_up_to(text, caymos::tolerance::MAX_GENERATED_LEGS)
}

/// `A,B` → the two joints' indices.
fn parse_base(scene: &Scene, text: &str) -> Result<[usize; 2], Failure> {
    let bad = |m: String| arg_error(format!("--base {text}: {m}"));
    let names: Vec<&str> = text.split(',').map(str::trim).collect();
    let [a, b] = names[..] else {
        return Err(bad("give two joint names separated by a comma, e.g. --base P,X".into()));
    };
    let find = |n: &str| scene.joint_index(n).ok_or_else(|| bad(format!("no joint named \"{n}\" in {}", scene.source)));
    let (a, b) = (find(a)?, find(b)?);
    if a == b {
        return Err(bad("the two joints must differ".into()));
    }
    if scene.bar_index(a, b).is_some() {
        return Err(bad("that is a bar; the base must be a non-edge".into()));
    }
    Ok([a, b])
}
