//! `caymos sweep`: transitions against the closed-form Grashof equalities,
//! the crank-rocker's one transition, shards, bad input, the text at 80 columns.

use proptest::prelude::*;
use serde_json::Value;

use caymos::commands::{Shard, sweep};
use caymos::sweep::{Change, InputBar, Parameter, Setup, Turn};

use crate::helpers::*;

/// The four-bar A-B-C-D (base A–C) closes for some λ iff the ranges of its
/// two triangles meet: max(|AB−BC|, |CD−DA|) ≤ min(AB+BC, CD+DA).
fn closes([ab, bc, cd, da]: [f64; 4]) -> bool {
    (ab - bc).abs().max((cd - da).abs()) <= (ab + bc).min(cd + da)
}

/// Where the structure of a four-bar with AB = x, BC = b, CD = c, DA = d
/// can change (closed form): s + l = p + q for each way of pairing the four
/// lengths (x + b = c + d, x + c = b + d, x + d = b + c) and the limits
/// where one length is the sum of the other three.
fn grashof_values(b: f64, c: f64, d: f64) -> Vec<f64> {
    vec![c + d - b, b + d - c, b + c - d, b + c + d, b - c - d, c - b - d, d - b - c]
}

#[test]
fn crank_rocker_has_one_transition_at_s_plus_l_equals_p_plus_q() {
    // First what the analysis itself says either side of AB = 2.5 (THEORY.md
    // §7: both ends from one triangle → 2 components, else 1).
    for (ab, expected) in [(2.4, 2), (2.6, 1)] {
        let (_, s) = solve(caymos::generate::four_bar(ab, 4.0, 3.0, 3.5));
        assert_eq!(s.components.list.len(), expected, "AB = {ab}");
    }
    let out = caymos(&[
        "sweep",
        "fourbar-crank-rocker",
        "--bar",
        "A,B",
        "--from",
        "0.5",
        "--to",
        "3",
        "--input-bar",
        "A,B",
        "--format",
        "json",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let doc = json(&out);
    assert_eq!(doc["samples"].as_array().unwrap().len(), 64, "64 samples by default");
    let transitions = doc["transitions"].as_array().unwrap();
    assert_eq!(transitions.len(), 1, "{transitions:#?}");
    let t = &transitions[0];
    let value = t["value"].as_f64().unwrap();
    assert!((value - 2.5).abs() <= 1e-12, "transition at {value}");
    let (before, after) = (t["before"].as_f64().unwrap(), t["after"].as_f64().unwrap());
    assert!(before < 2.5 && 2.5 < after && after - before < 1e-14, "bracket [{before}, {after}]");
    let changes = t["changes"].as_array().unwrap();
    assert!(changes.iter().any(|c| c["kind"] == "components" && c["from"] == 2 && c["to"] == 1), "{changes:#?}");
    // The crank turns fully in both mirror components below, in none above.
    assert!(changes.iter().any(|c| c["kind"] == "full_turns" && c["from"] == 2 && c["to"] == 0), "{changes:#?}");
    let samples = doc["samples"].as_array().unwrap();
    for s in samples {
        let v = s["value"].as_f64().unwrap();
        let comps = s["components"].as_array().unwrap();
        assert_eq!(comps.len(), if v < 2.5 { 2 } else { 1 }, "AB = {v}");
        // The Cayley space is [|AB − BC| or |DA − CD|, min(AB + BC, DA + CD)] (THEORY.md §7).
        let space = &s["cayley_space"][0];
        assert!((space[0].as_f64().unwrap() - (4.0 - v).max(0.5)).abs() < 1e-12, "{s:#}");
        assert!((space[1].as_f64().unwrap() - (v + 4.0).min(6.5)).abs() < 1e-12, "{s:#}");
        let turn = if v < 2.5 { "full" } else { "rocks" };
        assert!(comps.iter().all(|c| c["input_turn"] == turn), "AB = {v}: {s:#}");
    }
}

#[test]
fn shards_split_the_samples_and_keep_the_transitions() {
    let run = |shard: &str| {
        let args = ["sweep", "fourbar-crank-rocker", "--bar", "A,B", "--from", "0.5", "--to", "3", "--steps", "10"];
        json(&caymos(&[&args[..], &["--shard", shard, "--format", "json"]].concat()))
    };
    let whole = run("1/1");
    let indices = |d: &Value| -> Vec<u64> {
        d["samples"].as_array().unwrap().iter().map(|s| s["index"].as_u64().unwrap()).collect()
    };
    let (a, b, c) = (run("1/3"), run("2/3"), run("3/3"));
    assert_eq!(indices(&a), vec![0, 3, 6, 9]);
    assert_eq!(indices(&b), vec![1, 4, 7]);
    assert_eq!(indices(&c), vec![2, 5, 8]);
    let count = |d: &Value| d["transitions"].as_array().unwrap().len();
    assert_eq!(count(&a) + count(&b) + count(&c), count(&whole));
    assert_eq!(count(&whole), 1);
    // Gap 7 (samples 7 and 8, AB from 2.44 to 2.72) holds it: shard 2's.
    assert_eq!(count(&b), 1);
    assert_eq!(b["transitions"][0]["gap"], 7);
}

#[test]
fn a_joint_coordinate_sweep_changes_drawn_lengths() {
    // The non-Grashof four-bar states its lengths; a scene with drawn lengths
    // changes them when a joint moves: here D along x changes |CD| and |DA|.
    let dir = scratch("sweep-joint");
    let file = write(
        &dir,
        "drawn.toml",
        "base = [\"A\", \"C\"]\nground = [\"D\", \"A\"]\nbars = [[\"A\", \"B\"], [\"B\", \"C\"], [\"C\", \"D\"], [\"D\", \"A\"]]\n[joints]\nA = [0, 0]\nB = [0, 1]\nC = [3, 2]\nD = [3.5, 0]\n",
    );
    let out =
        caymos(&["sweep", &file, "--joint", "D.x", "--from", "1", "--to", "8", "--steps", "16", "--format", "json"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let doc = json(&out);
    assert_eq!(doc["parameter"], "D.x");
    assert_eq!(doc["parameter_kind"], "joint_x");
    assert!(!doc["transitions"].as_array().unwrap().is_empty());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_input_is_a_clear_error() {
    let base = ["sweep", "fourbar-crank-rocker"];
    for (args, needle) in [
        (vec!["--bar", "A,C", "--from", "1", "--to", "2"], "no bar joins A and C"),
        (vec!["--bar", "A,Q", "--from", "1", "--to", "2"], "no joint named \"Q\""),
        (vec!["--bar", "A,B", "--from", "2", "--to", "2"], "must be below --to"),
        (vec!["--bar", "A,B", "--from", "3", "--to", "1"], "must be below --to"),
        (vec!["--bar", "A,B", "--from", "-1", "--to", "1"], "must be positive"),
        (vec!["--bar", "A,B", "--from", "1", "--to", "2", "--shard", "0/2"], "--shard 0/2"),
        (vec!["--bar", "A,B", "--from", "1", "--to", "2", "--shard", "3/2"], "--shard 3/2"),
        (vec!["--bar", "A,B", "--from", "1", "--to", "2", "--shard", "x"], "--shard x"),
        (vec!["--bar", "A,B", "--from", "1", "--to", "2", "--steps", "1"], "--steps 1"),
        (vec!["--bar", "A,B", "--from", "1", "--to", "2", "--steps", "100001"], "100000"),
        (vec!["--bar", "A,B", "--from", "1", "--to", "2", "--input-bar", "B,C"], "neither joint is a ground joint"),
        (vec!["--bar", "A,B", "--from", "1", "--to", "2", "--input-bar", "D,A"], "ground link"),
        (vec!["--joint", "C.z", "--from", "1", "--to", "2"], "no coordinate \"z\""),
        (vec!["--from", "1", "--to", "2"], "--bar"),
    ] {
        let out = caymos(&[&base[..], &args[..]].concat());
        assert_eq!(out.status.code(), Some(1), "{args:?}");
        assert!(out.stdout.is_empty(), "{args:?}");
        assert!(stderr(&out).contains(needle), "{args:?}: {}", stderr(&out));
    }
}

#[test]
fn text_sweep_at_80_columns() {
    let out = caymos(&[
        "sweep",
        "fourbar-crank-rocker",
        "--bar",
        "A,B",
        "--from",
        "0.5",
        "--to",
        "3",
        "--steps",
        "12",
        "--input-bar",
        "A,B",
    ]);
    assert_eq!(out.status.code(), Some(0));
    let text = stdout(&out);
    for line in text.lines() {
        assert!(line.chars().count() <= 80, "wider than 80 columns: {line}");
    }
    insta::assert_snapshot!("sweep_crank_rocker_80", text);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, failure_persistence: None, ..ProptestConfig::default() })]

    /// Random four-bars, AB swept: every transition found is a closed-form
    /// Grashof equality or closing limit, and every such value where the
    /// four-bar closes on at least one side is found.
    #[test]
    fn four_bar_transitions_are_the_grashof_equalities(b in 1.0f64..5.0, c in 1.0f64..5.0, d in 1.0f64..5.0) {
        let (from, to, steps) = (0.2, 14.0, 48);
        let spacing = (to - from) / (steps - 1) as f64;
        let near = 1e-3;
        let mut expected: Vec<f64> = grashof_values(b, c, d)
            .into_iter()
            .filter(|&x| x > from + spacing && x < to - spacing)
            .filter(|&x| closes([x - near, b, c, d]) || closes([x + near, b, c, d]))
            .collect();
        expected.sort_by(f64::total_cmp);
        // Two changes within one sample gap may cancel; keep the cases where they cannot.
        prop_assume!(expected.windows(2).all(|w| w[1] - w[0] > 2.0 * spacing));
        let setup = Setup::new(
            caymos::generate::four_bar(1.0, b, c, d),
            Parameter::BarLength(0),
            None,
            Some(InputBar { pivot: 0, tip: 1, reference: 3 }),
        );
        let (samples, transitions) = sweep(&setup, from, to, steps, Shard::ALL);
        prop_assert_eq!(samples.len(), steps);
        let found: Vec<f64> = transitions.iter().filter(|t| !t.changes.is_empty()).map(|t| t.value).collect();
        for &x in &expected {
            prop_assert!(found.iter().any(|&y| (y - x).abs() <= 1e-12 * x.max(1.0)), "missed {} in {:?}", x, found);
        }
        let all = grashof_values(b, c, d);
        for &y in &found {
            prop_assert!(all.iter().any(|&x| (y - x).abs() <= 1e-12 * x.max(1.0)), "{} is no Grashof value: {:?}", y, all);
        }
        // Every change of component count is one of them, and the count
        // matches the closed form: 2 when both ends of the Cayley interval
        // come from one triangle (Grashof), 1 when not, 0 when it cannot close.
        for s in &samples {
            let x = s.value;
            let n = if !closes([x, b, c, d]) {
                0
            } else {
                let lower_abc = (x - b).abs() > (c - d).abs();
                let upper_abc = x + b < c + d;
                if lower_abc == upper_abc { 2 } else { 1 }
            };
            prop_assert_eq!(s.components.len(), n, "AB = {}", x);
            // AB turns fully exactly in the Grashof cases where it or the
            // ground DA is the shortest link (crank-rocker, double crank).
            let shortest = x.min(d) < b.min(c);
            let turns = s.components.iter().filter(|k| k.turn == Some(Turn::Full)).count();
            prop_assert_eq!(turns, if n == 2 && shortest { 2 } else { 0 }, "AB = {}", x);
        }
        for t in &transitions {
            prop_assert!(t.resolved);
            prop_assert!(t.after > t.before);
            prop_assert!(!t.changes.iter().any(|c| matches!(c, Change::TurnsUndecided)));
        }
    }
}

/// The crank-rocker with bar A–B's length swept.
fn crank_rocker_ab() -> Setup {
    Setup::new(caymos::bundled::load("fourbar-crank-rocker").unwrap(), Parameter::BarLength(0), None, None)
}

#[test]
fn a_sample_on_the_transition_still_gives_one_transition() {
    // 6 samples from 0.5 to 3: sample 4 is AB = 2.5 itself, where two steps are
    // flat at once; the brackets either side of it are one transition.
    let setup = crank_rocker_ab();
    let (samples, transitions) = sweep(&setup, 0.5, 3.0, 6, Shard::ALL);
    assert_eq!(samples[4].value, 2.5);
    assert_eq!(samples[4].structure.branch_points, 2, "non-generic at 2.5: {:?}", samples[4].structure);
    assert_eq!(transitions.len(), 1, "{transitions:#?}");
    let t = &transitions[0];
    assert_eq!(t.value, 2.5);
    assert!(t.between.iter().any(|p| p.value == 2.5), "{t:#?}");
    assert!(t.changes.contains(&Change::Components { from: 2, to: 1 }), "{:?}", t.changes);
}

/// The chart's ▲ stands under the column of the value now, whether its
/// words fit right of it, left of it or only on a line of their own.
#[test]
fn the_marker_of_the_value_now_is_under_its_column() {
    let setup = crank_rocker_ab();
    let r = caymos::commands::sweep_report(&setup, 0.2, 2.0, 2, Shard::ALL);
    for width in [23, 30, 50, 80] {
        let cols = (width - 7).min(16);
        for v in [0.2, 0.5, 1.0, 1.4, 1.9, 2.0] {
            let chart = r.chart(width, Some(v));
            let line = chart.iter().find(|l| l.contains('▲')).unwrap_or_else(|| panic!("{chart:#?}"));
            let at = line.chars().position(|c| c == '▲').unwrap();
            let want = 7 + ((v - 0.2) / 1.8 * (cols - 1) as f64).round() as usize;
            assert_eq!(at, want, "width {width}, value {v}: {chart:#?}");
            assert!(chart.iter().any(|l| l.contains("now A–B = ")), "the value is said: {chart:#?}");
            // Every line but the heading (which the TUI wraps) fits.
            assert!(chart.iter().skip(1).all(|l| l.chars().count() <= width), "{chart:#?}");
        }
    }
}

/// A sweep's samples skip the double-double self-check: it refines the ends'
/// λ within the f64 error, which could change a structure only at a
/// non-generic place. On every bundled scene and hard case (full analyses)
/// and on a 30-step chain (the lazy walk): the same oriented intervals with
/// the same events and point intervals, components and non-oriented pieces.
#[test]
fn the_self_check_keeps_the_structure_of_every_bundled_scene() {
    use caymos::analysis::{Scope, SelfCheck, analyse_checked};
    let mut scenes: Vec<_> = caymos::bundled::BUNDLED.iter().map(|b| caymos::bundled::load(b.name).unwrap()).collect();
    scenes.extend(caymos::generate::hard_cases());
    scenes.push(caymos::generate::chain(30));
    let mut checked_some = 0;
    for scene in scenes {
        let name = scene.name.clone();
        let run = |check| analyse_checked(scene.clone(), None, Scope::Auto, check).unwrap();
        let (with, without) = (run(SelfCheck::Run), run(SelfCheck::Skip));
        let scale = with.linkage.scale;
        let (Ok(with), Ok(without)) = (with.outcome, without.outcome) else { continue };
        assert!(without.accuracy.is_none(), "{name}");
        checked_some += usize::from(with.accuracy.is_some());
        let shape = |s: &caymos::analysis::Solved| {
            let ivs: Vec<_> = s
                .space
                .intervals
                .iter()
                .map(|iv| {
                    let point = iv.lower.lambda == iv.upper.lambda;
                    (iv.ty.clone(), iv.lower.events.clone(), iv.upper.events.clone(), point)
                })
                .collect();
            let comps: Vec<_> = s.components.list.iter().map(|c| c.intervals.clone()).collect();
            (ivs, comps, s.union.len(), s.components.branch_points.len())
        };
        assert_eq!(shape(&with), shape(&without), "{name}");
        // The ends agree to a few ulps of the scene's scale.
        for (a, b) in with.space.intervals.iter().zip(&without.space.intervals) {
            for (x, y) in [(a.lower.lambda, b.lower.lambda), (a.upper.lambda, b.upper.lambda)] {
                assert!((x - y).abs() <= 64.0 * f64::EPSILON * scale, "{name}: {x} vs {y}");
            }
        }
    }
    assert!(checked_some >= 10, "the self-check ran on {checked_some} scenes");
}

/// Every sample of a sweep gets the analysis `Auto` gives the scene as given
/// (here lazy: more than 2^16 types), and the text and chart say that the
/// component counts are the drawn component's only; a four-bar's are full.
#[test]
fn a_lazy_sweep_is_lazy_throughout_and_says_so() {
    let chain = caymos::generate::chain(caymos::analysis::LAZY_ABOVE_STEPS + 1);
    let setup = Setup::new(chain, Parameter::BarLength(0), None, None);
    assert_eq!(setup.scope, caymos::analysis::Scope::Lazy);
    let r = caymos::commands::sweep_report(&setup, 0.95, 1.05, 2, Shard::ALL);
    assert!(r.samples.iter().all(|s| s.lazy && s.components.len() == 1), "{:#?}", r.samples);
    assert!(r.to_text().contains("Lazy analysis of every sample"));
    assert!(r.chart(80, None)[0].contains("lazy: the drawn one's only"));
    let full = crank_rocker_ab();
    assert_eq!(full.scope, caymos::analysis::Scope::Full);
    let r = caymos::commands::sweep_report(&full, 0.2, 2.0, 2, Shard::ALL);
    assert!(r.samples.iter().all(|s| !s.lazy));
    assert!(!r.to_text().contains("lazy"));
}
