//! Analyse a scene from code: its oriented Cayley configuration space
//! (one line per interval) and its connected components.
//!
//! ```sh
//! cargo run -p caymos-core --example analyse -- linkages/jansen.toml
//! ```
//! Without an argument it reads the bundled Jansen leg.

use std::path::PathBuf;
use std::process::ExitCode;

use caymos_core::analysis::analyse;
use caymos_core::scene::load_scene;

fn main() -> ExitCode {
    let path = std::env::args_os()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../linkages/jansen.toml"));
    let scene = match load_scene(&path) {
        Ok(scene) => scene,
        Err(e) => {
            eprintln!("{e}");
            return ExitCode::FAILURE;
        }
    };
    let name = scene.name.clone();
    let analysis = match analyse(scene, None) {
        Ok(a) => a,
        Err(e) => {
            eprintln!("{e}");
            return ExitCode::FAILURE;
        }
    };
    let solved = match &analysis.outcome {
        Ok(solved) => solved,
        Err(outside) => {
            eprintln!("{name}: not 1-dof tree-decomposable: {outside:?}");
            return ExitCode::FAILURE;
        }
    };
    let base = solved.dec.base;
    let names = &analysis.linkage.names;
    println!("{name}: base {}–{}", names[base[0]], names[base[1]]);
    println!("{} intervals", solved.space.intervals.len());
    for (i, iv) in solved.space.intervals.iter().enumerate() {
        println!("  {:>3}  {}  [{}, {}]", i + 1, iv.ty, iv.lower.lambda, iv.upper.lambda);
    }
    println!("{} components", solved.components.list.len());
    for (c, component) in solved.components.list.iter().enumerate() {
        let intervals: Vec<String> = component.intervals.iter().map(|i| (i + 1).to_string()).collect();
        println!("  {:>3}  intervals {}", c + 1, intervals.join(", "));
    }
    ExitCode::SUCCESS
}
