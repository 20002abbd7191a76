//! Issue 10, through the real binary: no realization said in words (item 1),
//! bounded walks with marked jumps (item 7), lazy honesty (item 8), λ in
//! significant digits and the same-point test at large coordinates (item 10),
//! and the small items (12). Resource tests assert sample counts and bytes,
//! never wall-clock times.

use crate::helpers::*;
use std::path::Path;

/// CSV rows (header dropped), each split into cells.
fn csv_rows(text: &str) -> Vec<Vec<String>> {
    text.lines().skip(1).map(|l| l.split(',').map(str::to_string).collect()).collect()
}

// ---------------------------------------------------------------------------
// Item 1: an empty realization space

/// AB = 1, BC = 10, CD = 1, DA = 1 on base A–C: B needs |AC| in [9, 11], D in [0, 2].
fn cannot_close(dir: &Path) -> String {
    write(dir, "cannot-close.toml", &caymos::generate::to_toml(&caymos::generate::four_bar(1.0, 10.0, 1.0, 1.0)))
}

#[test]
fn a_scene_with_no_realization_is_explained_by_every_command() {
    let dir = scratch("empty");
    let file = cannot_close(&dir);
    let out = caymos(&["report", &file]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = stdout(&out);
    let components = text.lines().find(|l| l.starts_with("Components")).unwrap();
    assert!(components.contains("0: no realization: the base A–C would have to be at least 9"), "{components}");
    assert!(components.contains("at most 2"), "{components}");
    assert!(!text.contains("holds the drawn realization"), "no legend for an empty table: {text}");
    let json: serde_json::Value =
        serde_json::from_slice(&caymos(&["report", &file, "--format", "json"]).stdout).unwrap();
    assert_eq!(json["no_realization"]["kind"], "base_ranges_miss");
    assert!(json["no_realization"]["message"].as_str().unwrap().starts_with("no realization: the base A–C"));
    assert_eq!(json["components"].as_array().unwrap().len(), 0);
    for args in [
        vec!["trace", file.as_str()],
        vec!["svg", file.as_str()],
        vec!["path", file.as_str(), "--from", "drawn", "--to", "drawn"],
        vec!["closest", file.as_str(), "--components", "1,2"],
    ] {
        let out = caymos(&args);
        assert_eq!(out.status.code(), Some(1), "{args:?}");
        let err = stderr(&out);
        assert!(err.contains("no realization: the base A–C would have to be at least 9 long"), "{args:?}: {err}");
        assert!(!err.contains("no component"), "{args:?}: {err}");
        assert!(out.stdout.is_empty(), "{args:?}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_failed_sweep_is_not_called_an_empty_space() {
    // The crank-rocker at 1e-320: the drawn realization closes, so "no
    // realization" would be false. Such a scene (subnormal lengths) is now
    // refused when read, with the reason; a report never claims it empty.
    let dir = scratch("tiny");
    let mut scene = caymos::bundled::load("fourbar-crank-rocker").unwrap();
    for j in &mut scene.joints {
        j.pos = [j.pos[0] * 1e-320, j.pos[1] * 1e-320];
    }
    for b in &mut scene.bars {
        b.length = b.length.map(|l| l * 1e-320);
    }
    let file = write(&dir, "tiny.toml", &caymos::generate::to_toml(&scene));
    let out = caymos(&["report", &file]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("below f64's normal range"), "{}", stderr(&out));
    assert!(!stdout(&out).contains("no realization"));
    std::fs::remove_dir_all(&dir).ok();
}

// ---------------------------------------------------------------------------
// Item 7: bounded walks, steps relative to the drawing, marked jumps

/// Every row whose joints moved farther than the step from the row before
/// is marked as a jump: no silent jump.
fn assert_no_silent_jump(csv: &str, step: f64) -> usize {
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    assert_eq!(&header[..4], ["index", "lambda", "type", "jump"]);
    let rows = csv_rows(csv);
    let coords = |r: &[String]| -> Vec<f64> { r[4..].iter().map(|x| x.parse().unwrap()).collect() };
    let mut jumps = 0;
    for w in rows.windows(2) {
        let (a, b) = (coords(&w[0]), coords(&w[1]));
        let moved = a.chunks(2).zip(b.chunks(2)).map(|(p, q)| (p[0] - q[0]).hypot(p[1] - q[1])).fold(0.0, f64::max);
        let marked = w[1][3] == "1";
        assert!(marked || moved <= step * (1.0 + 1e-9), "silent jump of {moved} > {step} at row {}", w[1][0]);
        jumps += usize::from(marked);
    }
    jumps
}

#[test]
fn peaucellier_marks_its_degenerate_pass_at_lambda_2() {
    // Base O–C: at λ = 2 both B and D fold onto the line OC and coincide, so
    // P is undetermined there. A component either ends there (a dead end: it
    // is open, and its walk stops at λ = 2) or its walk marks the pass.
    let report =
        serde_json::from_slice::<serde_json::Value>(&caymos(&["report", "peaucellier", "--format", "json"]).stdout)
            .unwrap();
    let components = report["components"].as_array().unwrap().clone();
    let mut ends_or_marks_at_2 = 0;
    for (k, c) in components.iter().enumerate() {
        let out = caymos(&["trace", "peaucellier", "--component", &(k + 1).to_string(), "--step", "0.05"]);
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
        let csv = stdout(&out);
        let jumps = assert_no_silent_jump(&csv, 0.05);
        let rows = csv_rows(&csv);
        let marked: Vec<f64> = rows.iter().filter(|r| r[3] == "1").map(|r| r[1].parse::<f64>().unwrap()).collect();
        assert_eq!(marked.len(), jumps);
        let at_2 = |l: f64| (l - 2.0).abs() < 1e-9;
        let open_at_2 = c["closed"] == false
            && [rows.first(), rows.last()].iter().flatten().any(|r| at_2(r[1].parse::<f64>().unwrap()));
        if marked.iter().any(|&l| at_2(l)) || open_at_2 {
            ends_or_marks_at_2 += 1;
        }
        if jumps > 0 {
            assert!(stderr(&out).contains("jump"), "the jumps are said: {}", stderr(&out));
        }
    }
    assert!(ends_or_marks_at_2 >= 1, "the degenerate place at λ = 2 is an end or a marked pass");
}

#[test]
fn a_rhombus_walk_has_no_silent_jump() {
    // A rhombus four-bar (all sides 2) on base A–C: at λ = 0 A and C coincide.
    let dir = scratch("rhombus");
    let file = write(&dir, "rhombus.toml", &caymos::generate::to_toml(&caymos::generate::four_bar(2.0, 2.0, 2.0, 2.0)));
    let report: serde_json::Value =
        serde_json::from_slice(&caymos(&["report", &file, "--format", "json"]).stdout).unwrap();
    for k in 1..=report["components"].as_array().unwrap().len() {
        let out = caymos(&["trace", &file, "--component", &k.to_string(), "--step", "0.02"]);
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
        assert_no_silent_jump(&stdout(&out), 0.02);
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_sample_budget_stops_a_walk_and_says_so() {
    let out = caymos(&["trace", "jansen", "--max-samples", "7", "--joints", "F"]);
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(csv_rows(&stdout(&out)).len(), 7);
    assert!(stderr(&out).contains("sample budget (7 samples)"), "{}", stderr(&out));
    // Within the budget: no note.
    let out = caymos(&["trace", "jansen", "--joints", "F"]);
    assert!(!stderr(&out).contains("budget"), "{}", stderr(&out));
    // path says which of its walks were cut, and claims no shorter path then.
    let out =
        caymos(&["path", "limacon", "--from", "drawn", "--to", "-+-+@200", "--max-samples", "5", "--format", "json"]);
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for p in json["paths"].as_array().unwrap() {
        assert!(p["samples"].as_u64().unwrap() <= 5);
        assert_eq!(p["complete"], false);
        assert_eq!(p["shorter"], false);
        assert!(p["notes"][0].as_str().unwrap().contains("sample budget"));
    }
    let text = stdout(&caymos(&["path", "limacon", "--from", "drawn", "--to", "-+-+@200", "--max-samples", "5"]));
    assert!(text.contains("at least") && text.contains("sample budget"), "{text}");
    // svg: an XML comment and a note.
    let out = caymos(&["svg", "jansen", "--max-samples", "3"]);
    assert!(stdout(&out).contains("<!-- note: stopped at the sample budget"), "{}", stdout(&out));
    assert!(stderr(&out).contains("sample budget"));
    for bad in ["0", "-1", "x"] {
        let out = caymos(&["trace", "jansen", "--max-samples", bad]);
        assert_eq!(out.status.code(), Some(1), "--max-samples {bad}");
    }
}

#[test]
fn the_default_step_is_relative_to_the_drawing_not_the_longest_bar() {
    // A chain's drawing is as long as the chain; its bars stay short. With a
    // step of 1% of the longest bar this walk took 355,679 rows (4 GB).
    let dir = scratch("chain100");
    let out = caymos(&["generate", "chain", "--steps", "100"]);
    let file = write(&dir, "chain100.toml", &stdout(&out));
    let a = caymos::analysis::analyse(caymos::bundled::resolve(Some(&file)).unwrap(), None).unwrap();
    let step = caymos::commands::default_step(&a);
    let extent = caymos::commands::drawing_extent(&a);
    assert!((step - 0.01 * extent).abs() <= 1e-12 * extent && extent > 90.0, "{step} {extent}");
    let out = caymos(&["trace", &file, "--joints", "V100"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let rows = csv_rows(&stdout(&out)).len();
    assert!((2..20_000).contains(&rows), "{rows} rows");
    assert!(!stderr(&out).contains("budget"));
    std::fs::remove_dir_all(&dir).ok();
}

/// The resource test of the issue: trace, svg and path on a 300-step chain
/// and on Peaucellier with base A,B finish within the default sample budget
/// (100,000; they need under 20,000), with output proportional to the rows
/// (all joints of the chain for trace). They used to take 4 GB or more.
#[test]
fn long_and_degenerate_scenes_stay_within_the_sample_budget() {
    let dir = scratch("resources");
    let chain = write(&dir, "chain300.toml", &stdout(&caymos(&["generate", "chain", "--steps", "300"])));
    let csv = dir.join("chain300.csv");
    let out = caymos(&["trace", &chain, "--output", csv.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let bytes = std::fs::metadata(&csv).unwrap().len() as usize;
    let text = std::fs::read_to_string(&csv).unwrap();
    let rows = text.lines().count() - 1;
    let columns = text.lines().next().unwrap().split(',').count();
    // Well inside the budget: the step is 1% of the drawing (old default: 1% of a bar).
    assert!(rows < 20_000 && !stderr(&out).contains("sample budget"), "{rows} rows");
    assert!(bytes <= (rows + 1) * columns * 26, "{bytes} bytes for {rows} rows of {columns} columns");
    std::fs::remove_file(&csv).ok();
    // svg of every joint: at most SVG_MAX_POINTS points, and it says when cut.
    let out = caymos(&["svg", &chain]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let svg = stdout(&out);
    let points = svg.lines().filter(|l| l.starts_with("<polyline")).map(|l| l.matches(' ').count()).sum::<usize>();
    assert!(points <= caymos::tolerance::SVG_MAX_POINTS + 10 * 900, "{points} points");
    assert!(svg.len() <= 30 * caymos::tolerance::SVG_MAX_POINTS, "{} bytes", svg.len());
    if points > caymos::tolerance::SVG_MAX_POINTS / 2 {
        assert!(stderr(&out).contains("SVG keeps at most"), "{}", stderr(&out));
    }
    // A zero-length path and the whole cycle against it: both within the budget.
    let out = caymos(&["path", &chain, "--from", "drawn", "--to", "drawn", "--format", "json"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for p in json["paths"].as_array().unwrap() {
        let n = p["samples"].as_u64().unwrap() as usize;
        assert!(n < 20_000 && p["complete"] == true, "{n} samples");
    }
    // Peaucellier on base A,B walks through stretches where the realization
    // is not resolved in f64 (B and D coincide): bounded, jumps said.
    let report: serde_json::Value =
        serde_json::from_slice(&caymos(&["report", "peaucellier", "--base", "A,B", "--format", "json"]).stdout)
            .unwrap();
    for k in 1..=report["components"].as_array().unwrap().len() {
        let k = k.to_string();
        let out = caymos(&["trace", "peaucellier", "--base", "A,B", "--component", &k]);
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
        let rows = csv_rows(&stdout(&out)).len();
        assert!(rows < 20_000 && !stderr(&out).contains("sample budget"), "component {k}: {rows} rows");
        let jumps = csv_rows(&stdout(&out)).iter().filter(|r| r[3] == "1").count();
        assert_eq!(jumps > 0, stderr(&out).contains("jump"), "component {k}: {}", stderr(&out));
        let out = caymos(&["svg", "peaucellier", "--base", "A,B", "--component", &k]);
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
        assert!(out.stdout.len() < 2_000_000, "component {k}: {} bytes", out.stdout.len());
    }
    std::fs::remove_dir_all(&dir).ok();
}

// ---------------------------------------------------------------------------
// Item 8: lazy honesty

#[test]
fn lazy_commands_walk_requested_components_and_say_what_was_walked() {
    let dir = scratch("lazy");
    let chain = write(&dir, "chain20.toml", &stdout(&caymos(&["generate", "chain", "--steps", "20"])));
    let out = caymos(&["closest", &chain, "--components", "1,2"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(text.contains("Closest pair between components 1 and 2"), "{text}");
    assert!(text.contains("2 components walked"), "{text}");
    let out = caymos(&["trace", &chain, "--component", "2", "--joints", "V1"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(stderr(&out).contains("lazy analysis") && stderr(&out).contains("2 components walked"));
    // More than the walk finds: said as what was walked, not as what exists.
    let out = caymos(&["trace", &chain, "--component", "100000"]);
    assert_eq!(out.status.code(), Some(1));
    let err = stderr(&out);
    assert!(err.contains("walked lazily") && err.contains("--all") && !err.contains("this scene has"), "{err}");
    // --all: the full analysis, numbered as `report --all` (a small scene here).
    let out = caymos(&["closest", "jansen", "--components", "1,3", "--all"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(!stdout(&out).contains("lazy"));
    std::fs::remove_dir_all(&dir).ok();
}

// ---------------------------------------------------------------------------
// Item 10: λ in significant digits; the same point relative to the scale

#[test]
fn text_output_at_scale_1e_minus_20_keeps_its_digits() {
    let dir = scratch("small");
    let mut scene = caymos::bundled::load("fourbar-non-grashof").unwrap();
    for j in &mut scene.joints {
        j.pos = [j.pos[0] * 1e-20, j.pos[1] * 1e-20];
    }
    for b in &mut scene.bars {
        b.length = b.length.map(|l| l * 1e-20);
    }
    let file = write(&dir, "small.toml", &caymos::generate::to_toml(&scene));
    let text = stdout(&caymos(&["report", &file]));
    // THEORY.md §7: [2.5, 7] for every type, here ×1e-20.
    assert!(text.contains("Cayley space            [2.5e-20, 7e-20]"), "{text}");
    let drawn = text.lines().find(|l| l.starts_with("Drawn realization")).unwrap();
    assert!(drawn.contains("e-20") && !drawn.contains("λ = 0 "), "{drawn}");
    assert!(!text.lines().any(|l| l.contains("  0  ") && l.contains("folded")), "{text}");
    let path = stdout(&caymos(&["path", &file, "--from", "drawn", "--to", "drawn"]));
    assert!(path.contains("e-20"), "{path}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn fmt_sig_never_prints_a_nonzero_number_as_zero() {
    use caymos::report::{fmt_num, fmt_sig};
    assert_eq!(fmt_num(4.410930740183865e-20), "4.41093e-20");
    assert_eq!(fmt_num(53.79226727068166), "53.7923");
    assert_eq!(fmt_sig(53.79226727068166, 8), "53.792267");
    assert_eq!(fmt_num(2.5), "2.5");
    assert_eq!(fmt_num(-0.000125), "-0.000125");
    assert_eq!(fmt_num(3e307), "3e307");
    assert_eq!(fmt_num(4e-300), "4e-300");
    assert_eq!(fmt_num(3.99996e-320), "3.99996e-320");
    assert_eq!(fmt_num(0.0), "0");
    for x in [1e-300, 3.3e-20, 7e-5, 0.1, 1.0, 12345.678, 9.99999999e8, 1e15, 1e300] {
        let s = fmt_num(x);
        let back: f64 = s.parse().unwrap();
        assert!((back - x).abs() <= 1e-5 * x, "{x} → {s}");
    }
}

#[test]
fn two_joints_4_apart_at_1e13_are_distinct() {
    // A four-bar of sides 3 to 5 drawn near x = 1e13, and one more joint at
    // the origin with no bar: the drawing spans 1e13, the scene's scale is 5.
    // It used to be rejected ("drawn at the same point"); it is a
    // disconnected scene, and says so.
    let dir = scratch("far");
    let x = 1e13;
    let text = format!(
        "bars = [[\"A\", \"B\"], [\"B\", \"C\"], [\"C\", \"D\"], [\"D\", \"A\"]]\n[joints]\nA = [{x:?}, 0.0]\nB = [{:?}, 3.0]\nC = [{:?}, 3.0]\nD = [{:?}, 0.0]\nFar = [0.0, 0.0]\n",
        x + 1.0,
        x + 5.0,
        x + 4.0
    );
    let file = write(&dir, "far.toml", &text);
    let out = caymos(&["report", &file]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stdout(&out).contains("disconnected") && stdout(&out).contains("{Far}"), "{}", stdout(&out));
    std::fs::remove_dir_all(&dir).ok();
}

// ---------------------------------------------------------------------------
// Item 12: the small items

#[test]
fn a_bar_along_a_body_edge_is_accepted_if_it_agrees_and_named_if_not() {
    let dir = scratch("bodybar");
    let scene = |bc: &str| {
        format!(
            "bars = [\n  [\"A\", \"B\"],\n  [\"C\", \"D\"],\n  [\"D\", \"A\"],\n  [\"B\", \"C\"{bc}],\n]\nbodies = [[\"B\", \"C\", \"E\"]]\n[joints]\nA = [0.0, 0.0]\nB = [0.3, 0.9]\nC = [2.5, 1.4]\nD = [3.0, 0.0]\nE = [1.6, 2.4]\n"
        )
    };
    let agrees = write(&dir, "agrees.toml", &scene(""));
    let out = caymos(&["report", &agrees, "--format", "json"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["one_dof_tree_decomposable"], true);
    let warnings = json["warnings"].as_array().unwrap();
    let body_bar =
        |w: &&serde_json::Value| w["kind"] == "bar_in_body" && w["bar"] == 4 && w["body"] == 1 && w["line"] == 5;
    let messages: Vec<&str> = warnings.iter().filter(body_bar).map(|w| w["message"].as_str().unwrap()).collect();
    assert!(messages.iter().any(|w| w.contains("bar 4 (B–C, line 5)") && w.contains("ignored")), "{warnings:?}");
    // The same with the body's own length stated: agrees too.
    let drawn = (2.2f64 * 2.2 + 0.5 * 0.5).sqrt();
    let stated = write(&dir, "stated.toml", &scene(&format!(", {drawn:?}")));
    assert_eq!(caymos(&["report", &stated]).status.code(), Some(0));
    // A stated length the body contradicts: an error on the bar's line.
    let bad = write(&dir, "bad.toml", &scene(", 2.5"));
    let out = caymos(&["report", &bad]);
    assert_eq!(out.status.code(), Some(1));
    let err = stderr(&out);
    assert!(err.contains("bad.toml:5:") && err.contains("bar 4 (B–C)") && err.contains("body 1"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bench_says_why_it_skips_a_scene_and_counts_are_bounded() {
    let out = caymos(&["bench", "fig1c", "--repeat", "1"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stdout(&out).contains("Skipped") && stdout(&out).contains("rigid"), "{}", stdout(&out));
    assert!(!stdout(&out).contains("method"), "no empty tables: {}", stdout(&out));
    // Counts have a floor and a ceiling: every command has a bounded cost.
    for args in [
        ["bench", "jansen", "--repeat", "0"],
        ["bench", "jansen", "--repeat", "1000000000"],
        ["generate", "chain", "--steps", "100000000"],
        ["generate", "strandbeest", "--legs", "0"],
        ["trace", "jansen", "--max-samples", "4000000000"],
    ] {
        let out = caymos(&args);
        assert_eq!(out.status.code(), Some(1), "{args:?}");
        assert!(
            stderr(&out).contains("a whole number from 1 to") && stderr(&out).contains(args[2]),
            "{}",
            stderr(&out)
        );
    }
    let out = caymos(&["sweep", "fourbar-crank-rocker", "--bar", "A,B", "--from", "-1e308", "--to", "1e308"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("wider than f64"), "{}", stderr(&out));
}

#[test]
fn hard_cases_open_by_name_and_are_listed() {
    let list = stdout(&caymos(&["list"]));
    for h in caymos::generate::hard_cases() {
        assert!(list.contains(&h.name), "{list}");
        let out = caymos(&["report", &h.name, "--format", "json"]);
        assert_eq!(out.status.code(), Some(0), "{}: {}", h.name, stderr(&out));
        let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(json["scene"], h.name.as_str());
    }
    let out = caymos(&["report", "hard:nope"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("hard:sliver"), "the error lists the hard cases: {}", stderr(&out));
}

#[test]
fn trace_arc_without_from_and_to_is_an_error() {
    let out = caymos(&["trace", "jansen", "--arc", "1"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("--from"), "{}", stderr(&out));
}

#[test]
fn a_joint_named_tab_is_called_blank_not_empty() {
    let dir = scratch("tab");
    let file = write(&dir, "tab.toml", "bars = [[\"A\", \"\\t\"]]\n[joints]\nA = [0, 0]\n\"\\t\" = [1, 0]\n");
    let out = caymos(&["report", &file]);
    assert_eq!(out.status.code(), Some(1));
    let err = stderr(&out);
    assert!(err.contains("\"\\t\" is only whitespace") && !err.contains("empty"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

/// A strip of `n` triangles with one diagonal (the one from joint n/2)
/// left out: two rigid halves of about n/2 merged triangles each, hinged,
/// so one construction step. With `stated`, every bar states its drawn
/// length (to 17 digits). Joint i is drawn at (i/2, i mod 2).
fn strip(n: usize, stated: bool) -> String {
    let at = |i: usize| [i as f64 * 0.5, (i % 2) as f64];
    let bar = |a: usize, b: usize| {
        let [p, q] = [at(a), at(b)];
        let length = if stated { format!(", {:?}", (q[0] - p[0]).hypot(q[1] - p[1])) } else { String::new() };
        format!("  [\"J{a}\", \"J{b}\"{length}],\n")
    };
    let mut text = String::from("name = \"strip\"\nbars = [\n");
    for i in 0..n - 1 {
        text += &bar(i, i + 1);
    }
    for i in (0..n - 2).filter(|&i| i != n / 2) {
        text += &bar(i, i + 2);
    }
    text += "]\n[joints]\n";
    for i in 0..n {
        text += &format!("J{i} = [{}, {}]\n", at(i)[0], at(i)[1]);
    }
    text
}

/// The strip of 200 triangles with stated lengths: each half's shape is
/// placed triangle by triangle from the lengths, and the balls' enclosures
/// widen with every level of that merge, so they could not prove the
/// halves bent and `report` failed numerically (exit 3). The exact stage
/// proves them bent from the lengths as written: an answer, exit 0.
#[test]
fn a_strip_of_stated_triangles_is_answered() {
    let dir = scratch("strip");
    let path = write(&dir, "strip.toml", &strip(200, true));
    let out = caymos(&["report", &path]);
    assert_eq!(out.status.code(), Some(0), "{}", stdout(&out));
    assert!(stdout(&out).contains("Components              1"), "{}", stdout(&out));
    assert!(!stdout(&out).contains("failed numerically"), "{}", stdout(&out));
    std::fs::remove_dir_all(&dir).ok();
}

/// The same strips without stated lengths: each half is the drawing itself,
/// its shape the written coordinates (no placement through 100 triangles,
/// which lost the realization at 200 joints). The one step's lengths are
/// the drawn distances, and the Cayley space is [|a − b|, a + b].
#[test]
fn a_strip_of_drawn_triangles_keeps_its_realization() {
    let dir = scratch("drawn-strip");
    for n in [200, 400] {
        let path = write(&dir, &format!("strip{n}.toml"), &strip(n, false));
        let out = caymos(&["report", &path, "--format", "json"]);
        assert_eq!(out.status.code(), Some(0), "{n}: {}", stdout(&out));
        let doc = json(&out);
        let step = &doc["steps"][0];
        let index = |v: &serde_json::Value| v.as_str().unwrap()[1..].parse::<usize>().unwrap();
        let at = |i: usize| [i as f64 * 0.5, (i % 2) as f64];
        let length = |a: usize, b: usize| (at(b)[0] - at(a)[0]).hypot(at(b)[1] - at(a)[1]);
        let v = index(&step["vertex"]);
        let [a, b] = [length(index(&step["on"][0]), v), length(index(&step["on"][1]), v)];
        let lengths = [step["lengths"][0].as_f64().unwrap(), step["lengths"][1].as_f64().unwrap()];
        assert!((lengths[0] - a).abs() <= 1e-14 * a && (lengths[1] - b).abs() <= 1e-14 * b, "{n}: {lengths:?}");
        let span = &doc["cayley_space"][0];
        let [lo, hi] = [span[0].as_f64().unwrap(), span[1].as_f64().unwrap()];
        assert!((lo - (a - b).abs()).abs() <= 1e-13 * a && (hi - (a + b)).abs() <= 1e-13 * a, "{n}: [{lo}, {hi}]");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// A malformed `TYPE@LAMBDA` names its flag and the whole spec, and says
/// which half is wrong.
#[test]
fn a_malformed_realization_names_its_flag_and_part() {
    for (from, want) in [
        ("+-@", "--from \"+-@\": the λ after @ (\"\") is not a number"),
        ("+-@4@5", "the λ after @ (\"4@5\")"),
        ("+x@4", "--from \"+x@4\": the type before @ (\"+x\")"),
    ] {
        let out = caymos(&["path", "fourbar-crank-rocker", "--from", from, "--to", "drawn"]);
        assert_eq!(out.status.code(), Some(1));
        assert!(stderr(&out).contains(want), "{}", stderr(&out));
    }
    let out = caymos(&["trace", "fourbar-crank-rocker", "--from", "drawn", "--to", "++@x"]);
    assert!(stderr(&out).contains("--to \"++@x\""), "{}", stderr(&out));
}
