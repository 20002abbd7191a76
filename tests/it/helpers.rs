//! Shared helpers for the one integration-test crate: run the real binary,
//! solve a scene in process, scratch files.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use caymos::analysis::{Analysis, Scope, Solved, analyse_with};
use caymos::bundled;
use caymos::exact::Decimal;
use caymos::real::Dd;
use caymos::scene::Scene;

/// The real binary with `args`, colour off.
pub fn caymos(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_caymos")).args(args).env("NO_COLOR", "1").output().expect("binary runs")
}

pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).to_string()
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).to_string()
}

/// The binary's standard output as JSON (panics, showing it, when it is not).
pub fn json(out: &Output) -> serde_json::Value {
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("not JSON ({e}): {}", stdout(out)))
}

/// The analysis's own base, then every other valid base of the scene.
pub fn every_base(a: &Analysis, s: &Solved) -> Vec<[usize; 2]> {
    std::iter::once(s.dec.base).chain(s.dec.other_bases(&a.linkage)).collect()
}

/// A scratch directory for this test run's files.
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("caymos-it-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The analysis on base `base` (or the chosen one) in `scope`; panics with
/// the reason if the scene has no Cayley space.
pub fn solve_with(scene: Scene, base: Option<[usize; 2]>, scope: Scope) -> (Analysis, Solved) {
    let a = analyse_with(scene, base, scope).expect("a valid scene");
    let s = a.outcome.clone().unwrap_or_else(|o| panic!("{}", caymos::present::outside(&o, &a.linkage)));
    (a, s)
}

/// The full analysis on the chosen base.
pub fn solve(scene: Scene) -> (Analysis, Solved) {
    solve_with(scene, None, Scope::Full)
}

/// The full analysis of a scene written in the test (named `name`).
pub fn solve_text(text: &str, name: &str) -> (Analysis, Solved) {
    solve(caymos::scene::parse_scene(text, name, name).unwrap_or_else(|e| panic!("{name}: {e}")))
}

/// The full analysis of a bundled scene.
pub fn solved(name: &str) -> (Analysis, Solved) {
    solve(bundled::load(name).unwrap_or_else(|e| panic!("{name}: {e}")))
}

/// Write `text` to `dir/name`; the path as a string, for arguments.
pub fn write(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

/// `scene` with every length and coordinate multiplied by 10^exponent as
/// written: a decimal exponent appended, so exact relations among the
/// numbers as written stay exact (a product in f64 would round them).
pub fn scaled_as_written(mut scene: Scene, exponent: i32) -> Scene {
    let scaled = |x: f64| {
        let text = format!("{x}e{exponent}");
        (text.parse::<f64>().unwrap(), Dd::parse_decimal(&text).unwrap(), Decimal::parse(&text))
    };
    for j in &mut scene.joints {
        let (x, y) = (scaled(j.pos[0]), scaled(j.pos[1]));
        j.pos = [x.0, y.0];
        j.exact = [x.1, y.1];
        j.written = [x.2, y.2];
    }
    for b in &mut scene.bars {
        if let Some(l) = b.length {
            let (v, exact, written) = scaled(l);
            b.length = Some(v);
            b.exact_length = Some(exact);
            b.written_length = written;
        }
    }
    scene
}

/// A four-bar A-B-C-D with a dyad E ◁ (B, D) as scene text, every length
/// stated as written (`sides`: AB, BC, CD, DA; `dyad`: BE, DE), on `base`
/// or none; drawn as `generate::four_bar_with_dyad` draws it (the drawing
/// fixes only orientations).
pub fn four_bar_with_dyad_text(base: Option<[&str; 2]>, [ab, bc, cd, da]: [&str; 4], [be, de]: [&str; 2]) -> String {
    let base = base.map_or(String::new(), |[u, w]| format!("base = [\"{u}\", \"{w}\"]\n"));
    format!(
        "name = \"four-bar with dyad\"\n{base}bars = [\n  [\"A\", \"B\", {ab}], [\"B\", \"C\", {bc}], [\"C\", \"D\", {cd}], [\"D\", \"A\", {da}],\n  [\"B\", \"E\", {be}], [\"D\", \"E\", {de}],\n]\n[joints]\nA = [0.0, 0.0]\nB = [0.3, 2.0]\nC = [3.0, 0.4]\nD = [1.5, -1.8]\nE = [2.4, 2.6]\n"
    )
}
