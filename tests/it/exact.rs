//! Issue 40: questions past double-double resolution, proven by the exact
//! stage from the decimals as written (no longer taken as zero).

use caymos::analysis::Warning;
use caymos::cayley_vector::Mirrors;

use caymos::analysis::Scope;

use crate::helpers::*;

/// A dyad C on the base A–B with sides 3 and 3 + ε: its Cayley space is
/// [ε, 6 + ε], closed at ε where C folds. At ε = 1e-35 (below
/// double-double's 2^-106 of 3) the sides were taken as equal, so the
/// folded end was lost (an open end at 0, a degenerate place); as written
/// they differ, and the end is there. At ε = 0 the sides are proven equal.
#[test]
fn sides_unequal_below_double_double_keep_their_folded_end() {
    for (digit, closed) in [("1", true), ("0", false)] {
        let text = format!(
            "bars = [[\"A\", \"C\", 3], [\"B\", \"C\", 3.{digit:0>35}]]\nbase = [\"A\", \"B\"]\n[joints]\nA = [0, 0]\nB = [4, 0]\nC = [2, 2.2360679775]\n"
        );
        let (_, s) = solve_text(&text, "dyad");
        assert_eq!(s.space.intervals.len(), 2, "ε digit {digit}");
        for iv in &s.space.intervals {
            assert_eq!(!iv.lower.events.is_empty(), closed, "ε digit {digit}: {:?}", iv.lower);
        }
        assert!(s.certifier.exact_decisions() > 0, "ε digit {digit}: decided exactly");
    }
}

/// A body of three joints on one line as written in decimals that no
/// binary float holds exactly ((0, 0), (0.1, 0.3), (0.2, 0.6)): proven flat,
/// so mirror images exist (before: "at resolution"); 1e-40 off the line,
/// proven bent.
#[test]
fn a_body_on_a_line_as_written_is_proven_flat() {
    for (y, mirrors) in [("0.6", Mirrors::Yes), ("0.6000000000000000000000000000000000000001", Mirrors::No)] {
        let text = format!(
            "bars = [[\"B\", \"Q\", 2], [\"P\", \"Q\", 2], [\"A\", \"B\", 3]]\nbodies = [[\"A\", \"M\", \"P\"]]\nbase = [\"P\", \"B\"]\n[joints]\nA = [0, 0]\nM = [0.1, 0.3]\nP = [0.2, {y}]\nB = [3, 0]\nQ = [1.5, 1.5]\n"
        );
        let (a, s) = solve_text(&text, "body");
        assert_eq!(s.mirrors, mirrors, "P.y = {y}");
        assert!(!a.warnings.iter().any(|w| matches!(w, Warning::EstimatedDecisions { .. })));
    }
}

/// Issue 40's case 1 as a scene: the Peaucellier-like linkage with
/// PD = 3 + `eps` (written as a decimal, e.g. "0.000001"), base A–B.
fn near_rhombus(eps: &str) -> String {
    format!(
        "bars = [[\"O\", \"A\", 2], [\"A\", \"C\", 2], [\"O\", \"B\", 5], [\"O\", \"D\", 5], [\"C\", \"B\", 3], [\"B\", \"P\", 3], [\"P\", \"D\", 3{}], [\"D\", \"C\", 3]]\nbase = [\"A\", \"B\"]\n[joints]\nO = [0, 0]\nA = [2, 0]\nC = [3.285575219373, 1.532088886238]\nB = [2.385922501326, 4.394015682456]\nD = [4.899652718047, -0.996696163598]\nP = [4, 1.86523063262]\n",
        eps.trim_start_matches('0')
    )
}

/// Issue 40, case 1: a Peaucellier-like linkage (OA = AC = 2, OB = OD = 5,
/// CB = BP = DC = 3) with PD = 3 + ε. Where D folds, B and D meet, and P
/// (which needs |BD| ≥ ε) folds just before: 2 closed components, as a
/// 60-digit computation gives. On base A–B the P-fold lies ~ε/5 from
/// √19, where the f64 inversion (|OC| = 2 + O(ε²) near its minimum) lost
/// both candidates and the D-fold was taken for the end; the candidates
/// are now those of the exact inversion wherever balls leave a branch
/// undecided. Every valid base, full and lazy: from ε = 1e-10 the walk's
/// ends next to √19 on A–B are not confirmed in double-double, and the
/// sweep's component answers instead (said in a warning).
#[test]
fn a_near_rhombus_has_two_closed_components_on_every_base() {
    for eps in ["0.00001", "0.000001", "0.0000000001", "0.000000000001", "0.00000000000001"] {
        let text = near_rhombus(eps);
        let (a, s) = solve_text(&text, "near-rhombus");
        for base in every_base(&a, &s) {
            let scene = || caymos::scene::parse_scene(&text, "near-rhombus", "near-rhombus").unwrap();
            let (_, t) = solve_with(scene(), Some(base), Scope::Full);
            let c = &t.components;
            assert_eq!(c.connected_set_count(), 2, "ε = {eps}, base {base:?}");
            assert_eq!(c.list.len(), 2, "ε = {eps}, base {base:?}");
            assert!(c.list.iter().all(|k| k.closed), "ε = {eps}, base {base:?}: closed");
            let (l, lazy) = solve_with(scene(), Some(base), Scope::Lazy);
            assert_lazy_is_a_full_component(&lazy, &t, &format!("ε = {eps}, base {base:?}"));
            let escalated = l.warnings.contains(&Warning::WalkUnconfirmed);
            assert!(!l.warnings.contains(&Warning::RunsDiffer), "ε = {eps}, base {base:?}: unconfirmed, not escalated");
            let mut names = base.map(|j| l.linkage.names[j].as_str());
            names.sort();
            let small = eps.len() >= "0.0000000001".len();
            assert!(escalated || !small || names != ["A", "B"], "ε = {eps}: A–B escalates to the sweep");
        }
        // On A–B the ends next to √19 are P's folds (step 4), not D's touch.
        let p_folds = s
            .space
            .intervals
            .iter()
            .flat_map(|iv| [&iv.lower, &iv.upper])
            .filter(|e| e.events.iter().any(|ev| ev.step == 3 && ev.kind == caymos::realize::Kind::Folded));
        assert_eq!(p_folds.count(), 8, "ε = {eps}: four types end where P folds, either side of √19");
    }
}

/// Issue 40, case 2: an exact tangency in dyadic lengths. The rhombus-like
/// linkage has |BP| + |PD| = 3.25 + 2.25 = |BC| + |CD| = 3 + 2.5, so on
/// base O–P, where |BD| is greatest (B, P, D in line) C is exactly
/// stretched: its slack touches zero inside intervals, and the types with
/// C's bit flipped meet there. That base gave 6 connected sets, every
/// other base 2: the touch split the runs for the later steps and joined
/// them again, so the components never saw it. Now the sweep keeps each
/// touch inside intervals for the connected sets.
#[test]
fn an_exact_tangency_joins_the_same_sets_on_every_base() {
    let text = "bars = [[\"O\",\"A\",2],[\"A\",\"C\",2],[\"O\",\"B\",5],[\"O\",\"D\",4.5],[\"C\",\"B\",3],[\"B\",\"P\",3.25],[\"P\",\"D\",2.25],[\"D\",\"C\",2.5]]\nbase = [\"O\",\"P\"]\n[joints]\nO = [0, 0]\nA = [1.232462, 1.575131]\nB = [5, 0]\nC = [3.090909, 2.314168]\nD = [1.5, 4.242641]\nP = [2.931818, 2.507015]\n";
    let (a, s) = solve_text(text, "tangency-dyadic");
    assert!(!s.space.touches.is_empty(), "a touch inside intervals on O–P");
    for base in every_base(&a, &s) {
        let scene = || caymos::scene::parse_scene(text, "tangency-dyadic", "tangency-dyadic").unwrap();
        let (_, t) = solve_with(scene(), Some(base), Scope::Full);
        assert_eq!(t.components.connected_set_count(), 2, "base {base:?}");
        let (_, lazy) = solve_with(scene(), Some(base), Scope::Lazy);
        assert_lazy_is_a_full_component(&lazy, &t, &format!("base {base:?}"));
    }
}

/// Issue 40, case 3: a four-bar a–c–b–d whose |cd| is greatest (exactly 5,
/// at λ = √10) inside its range, and a dyad e ◁ (c, d) that folds at
/// |cd| = 5 − 1e-13: every type lives on a window ~1e-6 wide. The lazy
/// walk found the window's ends again a little apart, took them for new
/// ends and listed each interval up to three times, in open "components".
/// On every base the lazy component through the drawing is now closed,
/// without a repeated type, and is the full analysis's component there.
#[test]
fn a_narrow_window_is_walked_once_on_every_base() {
    let text = "bars = [[\"a\",\"c\",3],[\"c\",\"b\",4],[\"a\",\"d\",2],[\"d\",\"b\",4],[\"c\",\"e\",1],[\"e\",\"d\",5.9999999999999]]\nbase = [\"a\",\"b\"]\n[joints]\na = [0, 0]\nb = [3.16227766, 0]\nc = [0.474341649, 2.962262649]\nd = [-0.316227766, -1.974841766]\ne = [0.632455581, 3.949683524]\n";
    let scene = || caymos::scene::parse_scene(text, "window", "window").unwrap();
    let (a, s) = solve(scene());
    for base in every_base(&a, &s) {
        let (_, full) = solve_with(scene(), Some(base), Scope::Full);
        let (_, lazy) = solve_with(scene(), Some(base), Scope::Lazy);
        assert_lazy_is_a_full_component(&lazy, &full, &format!("base {base:?}"));
    }
}

/// Every component of the lazy analysis is closed and has the intervals'
/// types (with their multiplicities) of a component of the full analysis.
fn assert_lazy_is_a_full_component(lazy: &caymos::analysis::Solved, full: &caymos::analysis::Solved, what: &str) {
    let types = |t: &caymos::analysis::Solved, c: &caymos::motion::Component| {
        let mut v: Vec<String> = c.intervals.iter().map(|&i| t.space.intervals[i].ty.to_string()).collect();
        v.sort();
        v
    };
    assert!(!lazy.components.list.is_empty(), "{what}");
    for walked in &lazy.components.list {
        assert!(walked.closed, "{what}: closed");
        let walked = types(lazy, walked);
        assert!(
            full.components.list.iter().any(|c| types(full, c) == walked),
            "{what}: {walked:?} is a full component"
        );
    }
}

/// `report --timings` says how many decisions each stage took: Jansen's
/// are all proven in f64 balls; the exact Peaucellier needs the exact
/// stage (its touch candidates) and still rests some on estimates, and
/// says so in the text too.
#[test]
fn timings_count_the_decisions_of_each_stage() {
    let doc = json(&caymos(&["report", "jansen", "--timings", "--format", "json"]));
    let d = &doc["decisions"];
    assert!(d["f64"].as_u64().unwrap() > 0, "{d}");
    assert_eq!(
        (d["double_double"].as_u64(), d["exact"].as_u64(), d["estimated"].as_u64()),
        (Some(0), Some(0), Some(0))
    );
    let doc = json(&caymos(&["report", "peaucellier", "--timings", "--format", "json"]));
    assert!(doc["decisions"]["exact"].as_u64().unwrap() > 0, "{}", doc["decisions"]);
    let warned = doc["warnings"].as_array().unwrap().iter().find(|w| w["kind"] == "estimated_decisions");
    assert_eq!(warned.and_then(|w| w["count"].as_u64()), doc["decisions"]["estimated"].as_u64());
    let text = stdout(&caymos(&["report", "peaucellier", "--timings"]));
    assert!(text.lines().any(|l| l.starts_with("Decisions") && l.contains(" exact, ")), "{text}");
    assert!(json(&caymos(&["report", "jansen", "--format", "json"]))["decisions"].is_null());
}

/// Issue 40, case 1 traced: on base O–C the component's ends are where P
/// folds with B and D 1e-6 apart. Placed "flat" by the triangle formula,
/// P's distance along BD divided the slack's rounding by |BD| and the end
/// rows missed |BP| = 3 by 0.019; placed r1 from its base joint, every
/// continuous row meets every bar to the f64 resolution of that end. On
/// base A–B with ε = 1e-10 and 1e-12 the rows next to √19 have B and D
/// about ε apart, where f64 placed P up to 3 off its bars: such rows are
/// realized again in double-double.
#[test]
fn a_trace_through_a_near_rhombus_meets_every_bar() {
    for (eps, base) in [("0.000001", "O,C"), ("0.0000000001", "A,B"), ("0.000000000001", "A,B")] {
        let text = near_rhombus(eps);
        let file = scratch("near-rhombus-trace").join(format!("near-rhombus-{eps}.toml"));
        std::fs::write(&file, text).unwrap();
        let pd: f64 = format!("3{}", eps.trim_start_matches('0')).parse().unwrap();
        let bars = [
            ("O", "A", 2.0),
            ("A", "C", 2.0),
            ("O", "B", 5.0),
            ("O", "D", 5.0),
            ("C", "B", 3.0),
            ("B", "P", 3.0),
            ("P", "D", pd),
            ("D", "C", 3.0),
        ];
        for component in ["1", "2"] {
            let out = caymos(&["trace", file.to_str().unwrap(), "--base", base, "--all", "--component", component]);
            assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
            let csv = stdout(&out);
            let mut lines = csv.lines();
            let head: Vec<&str> = lines.next().unwrap().split(',').collect();
            let col = |name: &str| head.iter().position(|h| *h == name).unwrap();
            let mut rows = 0;
            for line in lines {
                let f: Vec<&str> = line.split(',').collect();
                if f[col("jump")] != "0" {
                    continue;
                }
                let at = |j: &str, axis: &str| f[col(&format!("{j}.{axis}"))].parse::<f64>().unwrap();
                for (a, b, length) in bars {
                    let d = (at(a, "x") - at(b, "x")).hypot(at(a, "y") - at(b, "y"));
                    assert!((d - length).abs() < 1e-7, "ε {eps} component {component}: |{a}{b}| = {d} in {line}");
                }
                rows += 1;
            }
            assert!(rows > 100, "ε {eps} component {component}: {rows} continuous rows");
        }
    }
}

/// A near-parallelogram (AB = CD = 5, BC = 1, DA = 1 + 1e-15) with a dyad
/// E ◁ (B, D) (6.5, 4.5) on base A–E, whose step C dips 1e-15 below flat.
fn dip() -> String {
    four_bar_with_dyad_text(Some(["A", "E"]), ["5", "1", "5", "1.000000000000001"], ["6.5", "4.5"])
}

/// A near-parallelogram (AB = CD = 5, BC = 1, DA = 1 + 1e-15) with a dyad
/// E ◁ (B, D), base A–E. Step C ◁ (B, D) dips 1e-15 below flat where |BD|
/// peaks at 6 + 1e-15 (and likewise folded at 4 − 1e-15): two roots
/// 8e-8 apart, at the rounding level of the f64 slack. The lazy walk took
/// each for a touch ("two endpoints or none") and walked one interval
/// [3.5, 5.5] where the full analysis, and a 60-digit computation, end at
/// the first root. The certifier now decides the sign at the dip and
/// bisection on its signs places the root.
#[test]
fn a_dip_below_zero_at_the_rounding_level_is_a_pair_of_roots_lazily_too() {
    let (a, full) = solve_text(&dip(), "dip.toml");
    let (_, lazy) = solve_with(a.scene.clone(), None, Scope::Lazy);
    assert_lazy_is_a_full_component(&lazy, &full, "dip");
    // The roots from mpmath at 60 digits (4.34932940943845234…, 4.44409715873697102…), rounded.
    let truth = [4.349329409438452, 4.444097158736971];
    let uppers: Vec<f64> = lazy.space.intervals.iter().map(|iv| iv.upper.lambda).collect();
    for t in truth {
        assert!(uppers.iter().any(|&u| (u - t).abs() <= 1e-15 * t), "{t} among {uppers:?}");
    }
    assert_eq!(lazy.certifier.estimated(), 0);
    assert!(!lazy.space.notes.iter().any(|n| matches!(n, caymos::cayley_space::Note::Tangency { .. })));
}

/// The same dip in the full sweep's numeric search (the method for steps
/// no closed form carries, and `bench`'s numeric rows): its extremum read
/// within `ROOT_VALUE` of zero was one "tangent root", so 8 of the 16
/// intervals were missing. The certifier now decides the sign there, and
/// the numeric sweep gives the closed form's intervals.
#[test]
fn the_numeric_sweep_finds_both_roots_of_a_dip() {
    use caymos::cayley_space::{Method, cayley_space};
    let (_, s) = solve_text(&dip(), "dip.toml");
    let numeric = Method::Numeric { samples: 32, tol: 0.0 };
    let n = cayley_space(&*s.construction, &s.certifier, &s.dec, &s.complexity, numeric);
    assert_eq!(n.intervals.len(), s.space.intervals.len());
    for (x, y) in n.intervals.iter().zip(&s.space.intervals) {
        assert_eq!((&x.ty, &x.lower.events, &x.upper.events), (&y.ty, &y.lower.events, &y.upper.events));
        for (p, q) in [(x.lower.lambda, y.lower.lambda), (x.upper.lambda, y.upper.lambda)] {
            assert!((p - q).abs() <= 1e-14 * q, "{p} vs {q}");
        }
    }
}

/// A near-kite (AB = BC = 3, CD = 4, DA = 4 + 1e-15) with a dyad, base
/// A–E: step C ◁ (B, D) with 3 and 4 dips 1e-15 below stretched where A
/// lies between B and D. There the f64 slack at the minimum is exactly 0,
/// which the walk took as a proven tangency: `--lazy` walked 2 intervals
/// where the full analysis's component has 6. An f64 zero proves nothing;
/// the certifier decides it as any other value near zero.
#[test]
fn an_f64_zero_at_a_dip_is_no_tangency() {
    let text = four_bar_with_dyad_text(Some(["A", "E"]), ["3", "3", "4", "4.000000000000001"], ["5.5", "4.5"]);
    let (a, full) = solve_text(&text, "kite-dip.toml");
    let (_, lazy) = solve_with(a.scene.clone(), None, Scope::Lazy);
    assert_lazy_is_a_full_component(&lazy, &full, "kite dip");
    assert_eq!(lazy.space.intervals.len(), 6);
}

/// Two steps on the base whose stretched targets round to one f64: on a
/// near-kite (AB = BC = 4, CD = 5, DA = 5 + 1e-15) with base B–D, A is
/// stretched at 9 + 1e-15 and C at 9, and 4 + 5.000000000000001 rounds to
/// 9.0. The sweep ended every type at 9 "where A is stretched", with C
/// proven not to close there, and flipped A's bit to join the components;
/// the double-double run (and the lazy walk) end at C. The end is now the
/// step proven to fail there.
#[test]
fn an_end_belongs_to_the_step_proven_to_fail_there() {
    let text = four_bar_with_dyad_text(Some(["B", "D"]), ["4", "4", "5", "5.000000000000001"], ["7.5", "5.5"]);
    let (a, full) = solve_text(&text, "near-kite.toml");
    let c = a.linkage.names.iter().position(|n| n == "C").unwrap();
    let c_step = full.dec.steps.iter().position(|s| s.vertex == c).unwrap();
    for iv in &full.space.intervals {
        assert_eq!(iv.upper.lambda, 9.0);
        assert_eq!(
            &iv.upper.events[..],
            [caymos::realize::Event { step: c_step, kind: caymos::realize::Kind::Stretched }]
        );
    }
    assert!(full.accuracy.as_ref().is_some_and(|x| x.same_structure));
    let (_, lazy) = solve_with(a.scene.clone(), None, Scope::Lazy);
    assert_lazy_is_a_full_component(&lazy, &full, "near-kite");
}
