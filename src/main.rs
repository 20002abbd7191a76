//! The `caymos` command line. Exit codes: 0 analysed; 1 unreadable or invalid
//! scene or bad arguments; 2 a valid scene outside the handled class.

use std::process::ExitCode;

use clap::{Args, Parser, Subcommand, ValueEnum};

use caymos::analysis::{Analysis, Scope, Solved, analyse, analyse_with};
use caymos::bundled;
use caymos::commands;
use caymos::report::Report;
use caymos::scene::Scene;

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

/// How the motion commands analyse the scene before they walk it.
#[derive(Args, Debug, Clone)]
struct AnalysisArgs {
    /// The base non-edge as two joint names, e.g. `--base A,B`.
    #[arg(long)]
    base: Option<String>,
    /// The full analysis (every type), so component numbers follow `report --all`.
    /// Without it, scenes with more than 2^16 types are analysed lazily and
    /// further components are walked on demand.
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
    #[arg(long, default_value_t = caymos::tolerance::DEFAULT_MAX_SAMPLES, value_parser = at_least_one)]
    max_samples: usize,
}

#[derive(Subcommand, Debug)]
enum Family {
    /// A chain of four-cycles, each step carried by the one before.
    Chain {
        #[arg(long)]
        steps: usize,
    },
    /// Jansen legs sharing one crank.
    Strandbeest {
        #[arg(long)]
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
        format: Format,
        /// The base non-edge as two joint names, e.g. `--base P,X`.
        #[arg(long)]
        base: Option<String>,
        /// The full analysis (every type, every component) and every oriented
        /// interval in the text, however many. Without it, scenes with more
        /// than 2^16 types get the lazy analysis (the drawn component only).
        #[arg(long)]
        all: bool,
        /// The lazy analysis (the component through the drawn realization)
        /// even for a small scene.
        #[arg(long, conflicts_with = "all")]
        lazy: bool,
    },
    /// List the bundled scenes.
    List,
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
        /// Component index as in the report (default: the drawn realization's).
        #[arg(long, conflicts_with_all = ["from", "to"])]
        component: Option<usize>,
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
        /// Two component indices as in the report, e.g. `0,3`.
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
    /// Speed against error: every method's time and error against the double-double reference.
    Bench {
        /// Scene files, bundled names or hard cases (`hard:sliver`, …); default: all bundled scenes and hard cases.
        scenes: Vec<String>,
        #[arg(long, value_enum, default_value = "text")]
        format: Format,
        /// Timed repetitions after a warm-up (the median is reported); at least 1.
        #[arg(long, default_value_t = 5, value_parser = at_least_one)]
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
        #[arg(long)]
        component: Option<usize>,
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

/// An error to print (one line) with its exit code.
struct Failure {
    message: String,
    code: u8,
}

impl From<caymos::scene::SceneError> for Failure {
    fn from(e: caymos::scene::SceneError) -> Self {
        Failure { message: e.to_string(), code: 1 }
    }
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
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
            eprintln!("caymos: {}", f.message);
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
                return Err(Failure {
                    message: "the terminal UI needs a terminal; for scripts use `caymos report` (see --help)".into(),
                    code: 1,
                });
            }
            caymos::tui::run(scene, base).map_err(|e| Failure { message: format!("terminal: {e}"), code: 1 })?;
            Ok(0)
        }
        Command::List => {
            for b in bundled::BUNDLED {
                let scene = bundled::load(b.name)?;
                emit(&format!("{:<24} {}\n", b.name, scene.description.unwrap_or_default()));
            }
            emit("\nHard cases (THEORY.md §6), generated; open them by name like the bundled scenes:\n");
            for h in caymos::generate::hard_cases() {
                emit(&format!("{:<24} {}\n", h.name, h.description.unwrap_or_default()));
            }
            Ok(0)
        }
        Command::Report { scene, format, base, all, lazy } => {
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
            let report = Report::new(&analysis);
            match format {
                Format::Json => emit(&format!("{}\n", report.to_json())),
                Format::Text => emit(&report.to_text_with(all)),
            }
            Ok(if report.one_dof_tree_decomposable { 0 } else { 2 })
        }
        Command::Graph { scene, format, base } => {
            let scene = bundled::resolve(scene.as_deref())?;
            let base = base.map(|b| parse_base(&scene, &b)).transpose()?;
            let graph = caymos::graph::graph_report(&scene, base)?;
            match format {
                GraphFormat::Json => emit(&format!("{}\n", serde_json::to_string_pretty(&graph).expect("serializes"))),
                GraphFormat::Dot => emit(&caymos::graph::to_dot(&graph)),
            }
            // Like `report`: outside the handled class exits 2 (the linkage is still exported).
            match &graph.outside {
                Some(o) => {
                    eprintln!("caymos: {}: outside the handled class: {}", scene.source, o.reason);
                    Ok(2)
                }
                None => Ok(0),
            }
        }
        Command::Path { scene, from, to, format, analysis, walk } => {
            let (a, mut s) = solved(scene.as_deref(), &analysis)?;
            commands::include_specs(&mut s, &[&from, &to]);
            let walk = walk_options(&walk, &a)?;
            let report = commands::path(&a, &s, &from, &to, walk).map_err(arg_error)?;
            match format {
                Format::Json => emit(&format!("{}\n", serde_json::to_string_pretty(&report).expect("serializes"))),
                Format::Text => emit(&report.to_text()),
            }
            note_all(commands::lazy_note(&s));
            Ok(0)
        }
        Command::Trace { scene, component, from, to, arc, joints, cayley, output, analysis, walk } => {
            let (a, mut s) = solved(scene.as_deref(), &analysis)?;
            commands::include_specs(&mut s, &[from.as_deref().unwrap_or("drawn"), to.as_deref().unwrap_or("drawn")]);
            if let Some(k) = component {
                commands::walk_components(&mut s, k + 1);
            }
            let walk = walk_options(&walk, &a)?;
            let joints = commands::parse_joints(&a, joints.as_deref()).map_err(arg_error)?;
            let between = from.as_deref().zip(to.as_deref()).map(|(f, t)| (f, t, arc));
            let segments = commands::trace_segments(&a, &s, component, between).map_err(arg_error)?;
            let summary =
                write_streamed(output, |out| commands::trace_csv(&a, &s, segments, &joints, walk, cayley, out))?;
            note_all(commands::lazy_note(&s).into_iter().chain(commands::walk_notes(&summary, walk.max_samples)));
            Ok(0)
        }
        Command::Closest { scene, components, gap, format, analysis } => {
            let (a, mut s) = solved(scene.as_deref(), &analysis)?;
            let pair: Vec<Option<usize>> = components.split(',').map(|x| x.trim().parse().ok()).collect();
            let [Some(i), Some(j)] = pair[..] else {
                return Err(arg_error(format!("--components {components}: give two component indices, e.g. 0,3")));
            };
            commands::walk_components(&mut s, i.max(j) + 1);
            let opts = caymos::distance::ClosestOptions { gap, ..Default::default() };
            let c = commands::closest_with(&a, &s, i, j, opts).map_err(arg_error)?;
            match format {
                Format::Json => {
                    emit(&format!("{}\n", serde_json::to_string_pretty(&c).expect("serializes")));
                    note_all(commands::lazy_note(&s));
                }
                Format::Text => {
                    emit(&c.to_text());
                    if let Some(note) = commands::lazy_note(&s) {
                        emit(&format!("  note: {note}\n"));
                    }
                }
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
                        reason: format!("outside the handled class: {}", o.describe(&analysis.linkage)),
                    }),
                }
            }
            if scaling {
                for (family, scene) in caymos::bench::scaling_scenes() {
                    report.scaling.extend(caymos::bench::scaling_row(&family, scene, repeat));
                }
            }
            match format {
                Format::Json => emit(&format!("{}\n", serde_json::to_string_pretty(&report).expect("serializes"))),
                Format::Text => emit(&report.to_text()),
            }
            // Like `report`: a named scene outside the class (or nothing benchmarked) exits 2.
            let nothing = report.methods.is_empty() && report.scaling.is_empty();
            Ok(if (named && !report.skipped.is_empty()) || nothing { 2 } else { 0 })
        }
        Command::Generate { family, output } => {
            let scene = match family {
                Family::Chain { steps } if steps >= 1 => caymos::generate::chain(steps),
                Family::Strandbeest { legs } if legs >= 1 => caymos::generate::strandbeest(legs),
                _ => return Err(arg_error("give a positive --steps or --legs".into())),
            };
            write_out(output, &caymos::generate::to_toml(&scene))?;
            Ok(0)
        }
        Command::Svg { scene, component, joints, output, analysis, walk } => {
            let (a, mut s) = solved(scene.as_deref(), &analysis)?;
            if let Some(k) = component {
                commands::walk_components(&mut s, k + 1);
            }
            let walk = walk_options(&walk, &a)?;
            let joints = commands::parse_joints(&a, joints.as_deref()).map_err(arg_error)?;
            let segments = commands::trace_segments(&a, &s, component, None).map_err(arg_error)?;
            let svg = commands::svg(&a, &s, segments, &joints, walk);
            write_out(output, &svg.text)?;
            if svg.points_cut {
                note_all([commands::svg_cut_note(joints.len())]);
            }
            note_all(commands::lazy_note(&s).into_iter().chain(commands::walk_notes(&svg.walk, walk.max_samples)));
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
fn solved(scene: Option<&str>, args: &AnalysisArgs) -> Result<(Analysis, Solved), Failure> {
    let scene = bundled::resolve(scene)?;
    let base = args.base.as_deref().map(|b| parse_base(&scene, b)).transpose()?;
    let analysis = analyse_with(scene, base, if args.all { Scope::Full } else { Scope::Auto })?;
    match analysis.outcome.clone() {
        Ok(s) => match commands::no_realization(&analysis, &s) {
            Some(why) => Err(Failure { message: format!("{}: {why}", analysis.scene.source), code: 1 }),
            None => Ok((analysis, s)),
        },
        Err(o) => Err(Failure {
            message: format!("{}: outside the handled class: {}", analysis.scene.source, o.describe(&analysis.linkage)),
            code: 2,
        }),
    }
}

/// Notes about the output (not errors) on stderr, one line each.
fn note_all(notes: impl IntoIterator<Item = String>) {
    for n in notes {
        eprintln!("caymos: note: {n}");
    }
}

fn arg_error(message: String) -> Failure {
    Failure { message, code: 1 }
}

/// Stream output to a file or stdout as it is made (buffered); a reader that
/// went away ends the program quietly, like [`emit`].
fn write_streamed<R>(
    output: Option<std::path::PathBuf>,
    write: impl FnOnce(&mut dyn std::io::Write) -> std::io::Result<R>,
) -> Result<R, Failure> {
    use std::io::Write;
    let failed = |what: &str, e: std::io::Error| Failure { message: format!("{what}: cannot write: {e}"), code: 1 };
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
            .map_err(|e| Failure { message: format!("{}: cannot write: {e}", path.display()), code: 1 }),
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

/// A count of at least 1 (`--repeat`, `--max-samples`).
fn at_least_one(text: &str) -> Result<usize, String> {
    match text.trim().parse::<usize>() {
        Ok(n) if n >= 1 => Ok(n),
        Ok(_) => Err("give at least 1".into()),
        Err(_) => Err("give a whole number, at least 1".into()),
    }
}

/// `A,B` → the two joints' indices.
fn parse_base(scene: &Scene, text: &str) -> Result<[usize; 2], Failure> {
    let bad = |m: String| Failure { message: format!("--base {text}: {m}"), code: 1 };
    let names: Vec<&str> = text.split(',').map(str::trim).collect();
    let [a, b] = names[..] else {
        return Err(bad("give two joint names separated by a comma, e.g. --base P,X".into()));
    };
    let find = |n: &str| scene.joint_index(n).ok_or_else(|| bad(format!("no joint named \"{n}\" in {}", scene.source)));
    let (a, b) = (find(a)?, find(b)?);
    if a == b {
        return Err(bad("the two joints must differ".into()));
    }
    if scene.bars.iter().any(|bar| bar.joints == [a, b] || bar.joints == [b, a]) {
        return Err(bad("that is a bar; the base must be a non-edge".into()));
    }
    Ok([a, b])
}
