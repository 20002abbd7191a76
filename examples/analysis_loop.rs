//! The full analysis of one scene (recognition → components, no
//! self-check: what `bench` times as `full_analysis_us`), run N times, for
//! counting its instructions under callgrind. Instruction counts are exact
//! from run to run and the same on any machine, unlike times on a shared
//! one; `scripts/count-instructions` takes the difference of two loop
//! lengths, so the process's start-up cancels out.
//!
//! Usage: `analysis_loop SCENE N` (SCENE as for `caymos report`).

use std::hint::black_box;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().collect();
    let (Some(arg), Some(Ok(n))) = (args.get(1), args.get(2).map(|n| n.parse::<usize>())) else {
        eprintln!("usage: analysis_loop SCENE N");
        return ExitCode::from(2);
    };
    let scene = match caymos::bundled::resolve(Some(arg)) {
        Ok(scene) => scene,
        Err(e) => {
            eprintln!("{e}");
            return ExitCode::FAILURE;
        }
    };
    let requested = scene.base.map(|b| b.0);
    let mut components = 0;
    for _ in 0..n {
        components = caymos::bench::full_analysis(black_box(&scene), requested);
    }
    println!("{components} components");
    if components == 0 {
        // Outside the handled class, or no realization: the count is of a
        // partial analysis, not comparable with a full one.
        eprintln!("analysis_loop: {arg}: no component (outside the handled class, or no realization)");
    }
    ExitCode::SUCCESS
}

// The binary's allocator, so that the count is the binary's.
#[global_allocator]
static ALLOCATOR: caymos::alloc::Allocator = caymos::alloc::Allocator;
