//! The `caymos` command line. Exit codes: 0 analysed; 1 unreadable or invalid
//! scene or bad arguments; 2 a valid scene outside the handled class.

use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};

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
        /// Largest joint move between samples when measuring (default: 1% of the scene scale).
        #[arg(long)]
        step: Option<f64>,
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
        #[arg(long)]
        arc: Option<usize>,
        /// Joints to trace, e.g. `F,K` (default: all).
        #[arg(long)]
        joints: Option<String>,
        #[arg(long)]
        step: Option<f64>,
        /// Append the complete Cayley distance vector (the Cayley curve) to each row.
        #[arg(long)]
        cayley: bool,
        #[arg(long)]
        output: Option<std::path::PathBuf>,
    },
    /// Closest pair of realizations between two components, by Cayley distance.
    Closest {
        scene: Option<String>,
        /// Two component indices as in the report, e.g. `0,3`.
        #[arg(long)]
        components: String,
        /// Relative gap to certify the distance to (proven lower bound vs. the pair found).
        #[arg(long, default_value_t = caymos::distance::DEFAULT_GAP)]
        gap: f64,
        #[arg(long, value_enum, default_value = "text")]
        format: Format,
    },
    /// Speed against error: every method's time and error against the double-double reference.
    Bench {
        /// Scene files, bundled names or hard cases (`hard:sliver`, …); default: all bundled scenes and hard cases.
        scenes: Vec<String>,
        #[arg(long, value_enum, default_value = "text")]
        format: Format,
        /// Timed repetitions after a warm-up (the median is reported).
        #[arg(long, default_value_t = 5)]
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
        step: Option<f64>,
        #[arg(long)]
        output: Option<std::path::PathBuf>,
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
                emit(&format!("{:<22} {}\n", b.name, scene.description.unwrap_or_default()));
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
        Command::Path { scene, from, to, format, step } => {
            let (a, mut s) = solved(scene.as_deref())?;
            commands::include_specs(&mut s, &[&from, &to]);
            let step = positive_step(step, &a)?;
            let report = commands::path(&a, &s, &from, &to, step).map_err(arg_error)?;
            match format {
                Format::Json => emit(&format!("{}\n", serde_json::to_string_pretty(&report).expect("serializes"))),
                Format::Text => emit(&report.to_text()),
            }
            Ok(0)
        }
        Command::Trace { scene, component, from, to, arc, joints, step, cayley, output } => {
            let (a, mut s) = solved(scene.as_deref())?;
            commands::include_specs(&mut s, &[from.as_deref().unwrap_or("drawn"), to.as_deref().unwrap_or("drawn")]);
            let step = positive_step(step, &a)?;
            let joints = commands::parse_joints(&a, joints.as_deref()).map_err(arg_error)?;
            let between = from.as_deref().zip(to.as_deref()).map(|(f, t)| (f, t, arc));
            let segments = commands::trace_segments(&a, &s, component, between).map_err(arg_error)?;
            write_out(output, &commands::trace_csv(&a, &s, segments, &joints, step, cayley))?;
            Ok(0)
        }
        Command::Closest { scene, components, gap, format } => {
            let (a, s) = solved(scene.as_deref())?;
            let pair: Vec<Option<usize>> = components.split(',').map(|x| x.trim().parse().ok()).collect();
            let [Some(i), Some(j)] = pair[..] else {
                return Err(arg_error(format!("--components {components}: give two component indices, e.g. 0,3")));
            };
            let opts = caymos::distance::ClosestOptions { gap, ..Default::default() };
            let c = commands::closest_with(&a, &s, i, j, opts).map_err(arg_error)?;
            match format {
                Format::Json => emit(&format!("{}\n", serde_json::to_string_pretty(&c).expect("serializes"))),
                Format::Text => emit(&c.to_text()),
            }
            Ok(0)
        }
        Command::Bench { scenes, format, repeat, scaling } => {
            let mut inputs: Vec<caymos::scene::Scene> = Vec::new();
            if scenes.is_empty() {
                for b in bundled::BUNDLED {
                    inputs.push(bundled::load(b.name)?);
                }
                inputs.extend(caymos::generate::hard_cases());
            } else {
                for name in &scenes {
                    match caymos::generate::hard_cases().into_iter().find(|h| &h.name == name) {
                        Some(h) => inputs.push(h),
                        None => inputs.push(bundled::resolve(Some(name))?),
                    }
                }
            }
            let mut report =
                caymos::bench::BenchReport { repeat, methods: Vec::new(), stepping: Vec::new(), scaling: Vec::new() };
            for scene in inputs {
                let analysis = analyse(scene, None)?;
                let Ok(solved) = analysis.outcome.clone() else { continue };
                let (m, s) = caymos::bench::bench_scene(&analysis, &solved, repeat);
                report.methods.extend(m);
                report.stepping.extend(s);
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
            Ok(0)
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
        Command::Svg { scene, component, joints, step, output } => {
            let (a, s) = solved(scene.as_deref())?;
            let step = positive_step(step, &a)?;
            let joints = commands::parse_joints(&a, joints.as_deref()).map_err(arg_error)?;
            let segments = commands::trace_segments(&a, &s, component, None).map_err(arg_error)?;
            write_out(output, &commands::svg(&a, &s, segments, &joints, step))?;
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

/// Load and analyse a scene that must be in the handled class.
fn solved(scene: Option<&str>) -> Result<(Analysis, Solved), Failure> {
    let scene = bundled::resolve(scene)?;
    let analysis = analyse(scene, None)?;
    match analysis.outcome.clone() {
        Ok(s) => Ok((analysis, s)),
        Err(o) => Err(Failure {
            message: format!("{}: outside the handled class: {}", analysis.scene.source, o.describe(&analysis.linkage)),
            code: 2,
        }),
    }
}

fn arg_error(message: String) -> Failure {
    Failure { message, code: 1 }
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

fn positive_step(step: Option<f64>, a: &Analysis) -> Result<f64, Failure> {
    match step {
        None => Ok(commands::default_step(a)),
        Some(s) if s.is_finite() && s > 0.0 => Ok(s),
        Some(s) => Err(arg_error(format!("--step {s}: give a positive length in scene units"))),
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
