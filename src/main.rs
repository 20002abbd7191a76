//! The `caymos` command line. Exit codes: 0 analysed; 1 unreadable or invalid
//! scene or bad arguments; 2 a valid scene outside the handled class.

use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};

use caymos::analysis::analyse;
use caymos::bundled;
use caymos::report::Report;
use caymos::scene::Scene;

#[derive(Parser, Debug)]
#[command(name = "caymos", version, about = "Cayley analysis of 1-dof tree-decomposable planar linkages")]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Clone, Copy, Debug, ValueEnum, PartialEq, Eq)]
enum Format {
    Text,
    Json,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Analyse a scene: class, base, steps, complexity, Cayley vector, drawn realization.
    Report {
        /// A scene file, or the name of a bundled scene (default: the Jansen leg).
        scene: Option<String>,
        #[arg(long, value_enum, default_value = "text")]
        format: Format,
        /// The base non-edge as two joint names, e.g. `--base P,X`.
        #[arg(long)]
        base: Option<String>,
        /// List every oriented interval in the text report, however many.
        #[arg(long)]
        all: bool,
    },
    /// List the bundled scenes.
    List,
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
    let command = cli.command.unwrap_or(Command::Report { scene: None, format: Format::Text, base: None, all: false });
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
        Command::List => {
            for b in bundled::BUNDLED {
                let scene = bundled::load(b.name)?;
                println!("{:<22} {}", b.name, scene.description.unwrap_or_default());
            }
            Ok(0)
        }
        Command::Report { scene, format, base, all } => {
            let scene = bundled::resolve(scene.as_deref())?;
            let base = base.map(|b| parse_base(&scene, &b)).transpose()?;
            let analysis = analyse(scene, base)?;
            let report = Report::new(&analysis);
            match format {
                Format::Json => println!("{}", report.to_json()),
                Format::Text => print!("{}", report.to_text_with(all)),
            }
            Ok(if report.one_dof_tree_decomposable { 0 } else { 2 })
        }
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
