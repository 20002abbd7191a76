//! Issue 6 (part): `caymos bench` output is correct (never its timings), and
//! the generated families are what they claim.

use std::process::Command;

use caymos::analysis::analyse;
use caymos::bench::compare;
use caymos::generate::{chain, strandbeest, to_toml};
use caymos::realize::RealizationType;
use caymos::scene::parse_scene;

use crate::helpers::{caymos, scratch, stderr, stdout, write};

#[test]
fn bench_runs_on_every_bundled_scene_and_hard_case() {
    let out = Command::new(env!("CARGO_BIN_EXE_caymos"))
        .args(["bench", "--repeat", "1", "--format", "json"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let rows = json["methods"].as_array().unwrap();
    let in_class = caymos::bundled::BUNDLED
        .iter()
        .filter(|b| analyse(caymos::bundled::load(b.name).unwrap(), None).unwrap().outcome.is_ok())
        .count();
    let scenes: std::collections::BTreeSet<&str> = rows.iter().map(|r| r["scene"].as_str().unwrap()).collect();
    assert_eq!(scenes.len(), in_class + caymos::generate::hard_cases().len());
    for r in rows {
        let method = &r["method"];
        let (kind, tol) = (method["kind"].as_str().unwrap(), method["tol"].as_f64());
        let err = r["max_endpoint_error"].as_f64().unwrap();
        assert!(r["median_us"].as_f64().unwrap() >= 0.0);
        if kind == "exact" || (kind == "numeric" && tol == Some(0.0)) || kind == "lazy" {
            assert!(err <= 1e-12, "{}: {method}: {err}", r["scene"]);
            assert_eq!((r["missed"].as_u64(), r["spurious"].as_u64()), (Some(0), Some(0)), "{}: {method}", r["scene"]);
        }
        if kind == "numeric" && tol == Some(1e-8) {
            assert!(err <= 1e-7, "{}: {method}: {err}", r["scene"]);
        }
    }
    let steps = json["stepping"].as_array().unwrap();
    assert!(!steps.is_empty());
    for r in steps {
        assert!(r["max_bar_residual"].as_f64().unwrap() <= 1e-12);
        // The chord error of a geometric step is bounded by the step itself.
        assert!(r["max_chord_error"].as_f64().unwrap() <= r["step"].as_f64().unwrap());
    }
    let text = Command::new(env!("CARGO_BIN_EXE_caymos"))
        .args(["bench", "fourbar-crank-rocker", "--repeat", "1"])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&text.stdout);
    assert!(
        text.contains("classic (midpoints, abs tol 1e-4)") && text.contains("time µs") && text.contains("error (log)")
    );
}

#[test]
fn compare_counts_missed_and_spurious_intervals() {
    let t = |s: &str| RealizationType::parse(s).unwrap();
    let reference = vec![(t("+-"), 1.0, 2.0), (t("--"), 3.0, 4.0)];
    let method = vec![(t("+-"), 1.0 + 1e-3, 2.0), (t("++"), 3.0, 4.0)];
    let (err, missed, spurious) = compare(&method, &reference, 10.0);
    assert!((err - 1e-4).abs() < 1e-12);
    assert_eq!((missed, spurious), (1, 1));
}

#[test]
fn generated_chains_and_strandbeests_are_low_complexity_with_the_right_step_counts() {
    for n in [1, 4, 7] {
        let a = analyse(chain(n), None).unwrap();
        let s = a.outcome.unwrap_or_else(|o| panic!("chain {n}: {o:?}"));
        assert_eq!(s.dec.steps.len(), n);
        assert!(s.complexity.low);
        assert!(!s.space.intervals.is_empty() && s.drawn_positions.is_some());
    }
    for legs in [1, 2] {
        let a = analyse(strandbeest(legs), None).unwrap();
        let s = a.outcome.unwrap_or_else(|o| panic!("strandbeest {legs}: {o:?}"));
        assert_eq!(s.dec.steps.len(), 1 + 3 * legs);
        assert!(s.complexity.low);
        let bar_check = caymos::realize::bar_residual(&a.linkage, s.drawn_positions.as_ref().unwrap());
        assert!(bar_check < 1e-9 * a.linkage.scale);
    }
}

#[test]
fn generated_scenes_round_trip_through_toml() {
    for scene in [chain(5), strandbeest(3)] {
        let text = to_toml(&scene);
        let back = parse_scene(&text, "generated.toml", "generated").unwrap();
        assert_eq!(back.joints.len(), scene.joints.len());
        assert_eq!(back.bars.len(), scene.bars.len());
        assert_eq!(back.bodies.len(), scene.bodies.len());
        assert_eq!(back.base.map(|b| b.0), scene.base.map(|b| b.0));
        for (x, y) in back.joints.iter().zip(&scene.joints) {
            assert_eq!((x.name.as_str(), x.pos), (y.name.as_str(), y.pos));
        }
    }
}

/// Issue 12: the like-for-like rows. The timed pipeline is the analysis
/// itself (same components as `analyse` without its self-check), and each
/// row names its scene, both medians and every phase (values never asserted
/// beyond being measured).
#[test]
fn analysis_rows_time_the_same_analysis_by_phase() {
    for name in ["fourbar-crank-rocker", "jansen", "limacon", "peaucellier"] {
        let scene = caymos::bundled::load(name).unwrap();
        let solved = analyse(scene.clone(), None).unwrap().outcome.unwrap();
        let (components, timings) = caymos::bench::full_analysis_phases(&scene, None);
        assert_eq!(components, solved.components.list.len(), "{name}");
        assert_eq!(caymos::bench::full_analysis(&scene, None), components, "{name}: the untimed run");
        let phases: Vec<&str> = timings.0.iter().map(|(p, _)| *p).collect();
        assert_eq!(phases, ["linkage", "decompose", "four_cycle", "construction", "cayley_space", "components"]);
    }
    let out = Command::new(env!("CARGO_BIN_EXE_caymos"))
        .args(["bench", "jansen", "limacon", "--repeat", "3", "--format", "json"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let rows = json["analysis"].as_array().unwrap();
    let scenes: Vec<&str> = rows.iter().map(|r| r["scene"].as_str().unwrap()).collect();
    assert_eq!(scenes, ["Jansen leg", "Limacon"]);
    for r in rows {
        for key in ["full_analysis_us", "realization_us"] {
            assert!(r[key].as_f64().is_some_and(|t| t.is_finite() && t >= 0.0), "{key}: {r}");
        }
        let phases = r["phases_us"].as_object().unwrap();
        assert_eq!(phases.len(), 6, "{r}");
    }
    let text = Command::new(env!("CARGO_BIN_EXE_caymos")).args(["bench", "jansen", "--repeat", "1"]).output().unwrap();
    let text = String::from_utf8_lossy(&text.stdout);
    assert!(text.contains("analysis µs") && text.contains("realizations") && text.contains("cayley_space"), "{text}");
}

/// A cluster of many joints (a Strandbeest's crank body holds every leg's
/// crank tip) is shown by its first joints and its size, so the step table
/// stays as wide as for a few legs: written out, 5000 legs made 434 MB of
/// text. Each row still names both clusters.
#[test]
fn a_big_cluster_is_shown_by_its_first_joints_and_its_size() {
    let dir = scratch("big-cluster");
    let path = write(&dir, "beest.toml", &to_toml(&strandbeest(40)));
    let out = caymos(&["report", &path]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    let table: Vec<&str> =
        text.lines().skip_while(|l| !l.starts_with("Construction steps")).skip(2).take(121).collect();
    assert_eq!(table.len(), 121);
    assert!(table[0].contains("{O,X0,X1,X2,X3,X4,X5,X6,X7,X8,X9,X10,… 41 joints}"), "{}", table[0]);
    let widest = table.iter().map(|l| l.chars().count()).max().unwrap();
    assert!(widest < 140, "{widest} characters: {}", table[0]);
    assert!(table.iter().all(|l| l.matches('{').count() == 2), "both clusters on every row");
}
