//! Issue 10: no wrong answers at any size. Regression tests for the numbered
//! cases (near-coincident events, tiny intervals, high-order tangencies,
//! false warnings, extreme scales, honest accuracy) and the invariance
//! properties: the realization space does not depend on the base, the scale,
//! the pose or the analysis scope.

use crate::helpers::*;
use caymos::analysis::{Scope, Warning, analyse_with};
use caymos::bundled;
use caymos::cayley_space::{Note, OrientedInterval};
use caymos::generate::{chain, four_bar, random_linkage};
use caymos::lazy::{LazyOptions, component_through};
use caymos::real::{Ball, Dd, Jet, Real};
use caymos::realize::{Construction, Event, Kind};
use caymos::scene::{Scene, parse_scene};
use proptest::prelude::*;

/// The lazy walk from the drawn realization (as the full analysis places
/// it) finds the full analysis's component through it.
fn assert_scopes_agree(scene: &Scene) {
    let (_, full) = solve(scene.clone());
    let Some(drawn) = full.drawn_component else { return };
    let jet = full.construction.convert::<Jet<f64>>();
    let walked = component_through(
        &full.construction,
        &full.certifier,
        &jet,
        &full.drawn.ty,
        full.drawn.lambda,
        LazyOptions::default(),
    )
    .expect("the drawn realization is realizable");
    let key = |iv: &OrientedInterval<f64>| (iv.ty.to_string(), iv.lower.lambda, iv.upper.lambda);
    let mut f: Vec<_> = full.components.list[drawn].intervals.iter().map(|&i| key(&full.space.intervals[i])).collect();
    let mut l: Vec<_> = walked.intervals.iter().map(key).collect();
    f.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    l.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    assert_eq!(f.len(), l.len(), "{}: full {f:?}\nlazy {l:?}", scene.name);
    for (x, y) in f.iter().zip(&l) {
        assert_eq!(x.0, y.0);
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * full.construction.scale;
        assert!(close(x.1, y.1) && close(x.2, y.2), "{}: full {x:?} lazy {y:?}", scene.name);
    }
}

fn events(iv: &OrientedInterval<f64>) -> (Vec<Event>, Vec<Event>) {
    (iv.lower.events.to_vec(), iv.upper.events.to_vec())
}

// ---------------------------------------------------------------------------
// Numbered cases

/// Case 3: AB=1, BC=2, CD=1, DA=4 − 1e-12 whose drawing is a realization:
/// the Cayley space is [3 − 1e-12, 3], each end a different step's event.
#[test]
fn an_interval_1e_minus_12_wide_is_found_with_its_two_events() {
    assert_scopes_agree(&four_bar(1.0, 2.0, 1.0, 4.0 - 1e-12));
    for scope in [Scope::Full] {
        let (_, s) = solve_with(four_bar(1.0, 2.0, 1.0, 4.0 - 1e-12), None, scope);
        assert_eq!(s.union.len(), 1, "{scope:?}");
        let [lo, hi] = s.union[0];
        assert!((lo - (3.0 - 1e-12)).abs() <= 4e-16 && hi == 3.0, "{scope:?}: [{lo}, {hi}]");
        for iv in &s.space.intervals {
            let fold_d = Event { step: 1, kind: Kind::Folded };
            let stretch_b = Event { step: 0, kind: Kind::Stretched };
            assert_eq!(events(iv), (vec![fold_d], vec![stretch_b]), "{scope:?}");
        }
        // Both ends from different triangles: one component through all four types.
        assert_eq!(s.components.list.len(), 1);
        assert_eq!(s.components.list[0].intervals.len(), 4);
    }
}

/// Case 4: AB=1, BC=3, CD=2.5, DA=4.5(1 + δ): two fold events δ·4.5 apart
/// are distinct, so there is one component of four intervals, for every δ
/// from 1e-9 down to 1e-15 and in both analyses.
#[test]
fn fold_events_1e_minus_9_to_1e_minus_15_apart_stay_distinct() {
    for e in 9..=15 {
        let delta = 10f64.powi(-e);
        let da = 4.5 * (1.0 + delta);
        let scene = four_bar(1.0, 3.0, 2.5, da);
        assert_scopes_agree(&scene);
        for scope in [Scope::Full] {
            let (_, s) = solve_with(scene.clone(), None, scope);
            assert_eq!(s.components.list.len(), 1, "δ = 1e-{e}, {scope:?}");
            assert_eq!(s.components.list[0].intervals.len(), 4, "δ = 1e-{e}, {scope:?}");
            assert!(s.components.branch_points.is_empty(), "δ = 1e-{e}, {scope:?}: no branch point");
            for iv in &s.space.intervals {
                assert_eq!(iv.lower.lambda, da - 2.5, "δ = 1e-{e}: the lower end is D's fold");
                assert_eq!(iv.lower.events[..], [Event { step: 1, kind: Kind::Folded }], "δ = 1e-{e}, {scope:?}");
            }
        }
    }
}

/// The exact coincidence (δ = 0) is a branch point, said as such.
#[test]
fn exactly_coincident_fold_events_are_one_branch_point() {
    let (_, s) = solve(four_bar(1.0, 3.0, 2.5, 4.5));
    let both = [Event { step: 0, kind: Kind::Folded }, Event { step: 1, kind: Kind::Folded }];
    assert!(s.space.intervals.iter().all(|iv| iv.lower.events[..] == both));
    assert!(!s.components.branch_points.is_empty());
}

/// Case 2: Peaucellier on base A–B. Types +--+, +---, -++-, -+++ exist on all
/// of [3, 5] (the slack 6 − |BD| touches zero at λ = √13 to fourth order: a
/// touch, not an isolated point), and the drawn realization lies in a component.
#[test]
fn peaucellier_on_base_a_b_keeps_its_intervals_through_a_fourth_order_touch() {
    let scene = bundled::load("peaucellier").unwrap();
    let a = scene.joint_index("A").unwrap();
    let b = scene.joint_index("B").unwrap();
    for scale in [1.0, 1e3, 1e-3] {
        let mut scaled = scene.clone();
        for j in &mut scaled.joints {
            j.pos = j.pos.map(|x| x * scale);
        }
        for bar in &mut scaled.bars {
            bar.length = bar.length.map(|l| l * scale);
        }
        let (_, s) = solve_with(scaled, Some([a, b]), Scope::Full);
        for ty in ["+--+", "+---", "-++-", "-+++"] {
            let spans: Vec<[f64; 2]> = s
                .space
                .intervals
                .iter()
                .filter(|iv| iv.ty.to_string() == ty)
                .map(|iv| [iv.lower.lambda / scale, iv.upper.lambda / scale])
                .collect();
            assert_eq!(spans.len(), 1, "×{scale}: {ty} has one interval, found {spans:?}");
            assert!((spans[0][0] - 3.0).abs() < 1e-12 && (spans[0][1] - 5.0).abs() < 1e-12, "×{scale}: {ty} {spans:?}");
        }
        assert!(s.drawn_component.is_some(), "×{scale}: the drawn realization lies in a component");
        assert!(s.accuracy.as_ref().is_some_and(|acc| acc.same_structure && acc.max_relative_error < 1e-12));
    }
}

/// Case 9: a 16-step chain has no false "unresolved" or tangency warnings.
#[test]
fn a_sixteen_step_chain_has_no_false_warnings() {
    let (a, s) = solve_with(chain(16), None, Scope::Lazy);
    assert!(s.space.intervals.len() >= 2);
    let names = caymos::present::Names::new(&a.linkage, &s.dec.steps);
    for w in &a.warnings {
        use caymos::cayley_space::Note;
        assert!(!matches!(w, Warning::Note(Note::Unresolved { .. } | Note::Tangency { .. })), "false warning: {w:?}");
        let w = caymos::present::warning(w, names);
        assert!(!w.contains("unresolved") && !w.contains("tangency"), "false warning: {w}");
    }
}

/// Case 10: a four-bar scaled by 1e±160 and 1e±200 has the same two
/// components, with endpoints scaled (to rounding).
#[test]
fn extreme_scales_give_the_same_answer_scaled() {
    let (_, unit) = solve(four_bar(1.0, 4.0, 3.0, 3.5));
    for e in [-200, -160, -80, 80, 160, 200] {
        let f = 10f64.powi(e);
        let (_, s) = solve(four_bar(f, 4.0 * f, 3.0 * f, 3.5 * f));
        assert_eq!(s.components.list.len(), unit.components.list.len(), "1e{e}");
        assert_eq!(s.space.intervals.len(), unit.space.intervals.len(), "1e{e}");
        for (x, y) in s.space.intervals.iter().zip(&unit.space.intervals) {
            assert_eq!(x.ty, y.ty);
            for (p, q) in [(x.lower.lambda, y.lower.lambda), (x.upper.lambda, y.upper.lambda)] {
                assert!((p / f - q).abs() <= 1e-14 * q, "1e{e}: {p} vs {q}");
            }
        }
        assert!(
            s.drawn_positions.as_ref().is_some_and(|p| p.iter().all(|q| q.x.is_finite() && q.y.is_finite())),
            "1e{e}"
        );
    }
}

/// Case 11: an endpoint that is the difference of two ~955-long bars, in a
/// scene whose base is 1.2e-3: the reported endpoint is within 1e-15 of its
/// own value against a 60-digit computation from the written coordinates
/// (Python's decimal: |AB| − |CB| with A = (0, 0), C = (0.0012, 0),
/// B = (300.123456789, 906.6)), and the report says how far the f64 run was.
#[test]
fn accuracy_is_measured_from_the_input_as_written() {
    let text = r#"
name = "scale spread"
base = ["A", "C"]
ground = ["A", "C"]
bars = [ ["A","B"], ["B","C"], ["C","D"], ["D","A"] ]
[joints]
A = [0.0, 0.0]
C = [0.0012, 0.0]
B = [300.123456789, 906.6]
D = [0.0005, 0.0006]
"#;
    let truth = Dd::parse_decimal("0.000377123455083281737701099623659102").unwrap().to_f64();
    let (a, s) = solve_text(text, "spread.toml");
    let lower = s.union[0][0];
    assert!((lower - truth).abs() <= 1e-15 * truth, "reported {lower:e}, truth {truth:e}");
    let acc = s.accuracy.expect("reference ran");
    assert!(acc.refined && acc.same_structure);
    // f64 loses digits to the cancellation; the report must say so, not claim 1e-17.
    assert!(acc.max_error_of_value > 1e-12, "f64 error of value {:e}", acc.max_error_of_value);
    assert!(acc.max_error_of_value < 1e-8);
    assert!(a.linkage.scale > 900.0);
}

// ---------------------------------------------------------------------------
// Invariance properties

/// Every valid base of a scene gives the same number of components, and the
/// drawing lies in one of them (the realization space does not depend on the base).
fn assert_base_invariant(scene: &Scene) {
    let (a, s) = solve(scene.clone());
    for base in s.dec.other_bases(&a.linkage) {
        let (_, t) = solve_with(scene.clone(), Some(base), Scope::Full);
        assert_eq!(
            t.components.list.len(),
            s.components.list.len(),
            "{}: base {base:?} vs {:?}",
            scene.name,
            s.dec.base
        );
        assert!(t.drawn_component.is_some(), "{}: base {base:?}: the drawing lies in a component", scene.name);
    }
}

/// The exact tangency with every length and coordinate multiplied by
/// 10^exponent as written (decimal exponents, so exact relations stay exact).
fn tangency_scaled(exponent: i32) -> Scene {
    scaled_as_written(caymos::generate::tangency(), exponent)
}

/// Every bundled scene and hard case, scaled by 10^±100 and 10^±150 as written, keeps
/// its types, components and connected sets on every valid base. The
/// Peaucellier inversor is the hard one, non-generic by design: on base
/// B–D steps 2, 3 and 4 are flat at once at λ = 6 (3 + 3 = 6 and
/// √(5² − 3²) = 2 + 2), and on base O–P the rhombus touches stretched at
/// λ = 4, where the lengths rounded to f64 at 1e150 put two roots √ε apart.
/// On base O–C, steps 1 and 4 are flat at once at λ = 4, where the lazy
/// walk read step 4's slack a rounding error below zero at 1e100 and ended
/// early with step 4 alone. (Scaled in f64 instead, 3 × 10^100 is written
/// 3.0000000000000002e100 and the triple point splits: a different mechanism.)
/// Both the full and the lazy analysis are checked.
#[test]
fn bundled_scenes_scaled_as_written_keep_their_structure_on_every_base() {
    let shape = |t: &caymos::analysis::Solved| {
        let types: Vec<String> = t.space.intervals.iter().map(|iv| iv.ty.to_string()).collect();
        (types, t.components.list.len(), t.components.connected_set_count())
    };
    let bundled = bundled::BUNDLED.iter().map(|b| bundled::load(b.name).unwrap());
    for scene in bundled.chain(caymos::generate::hard_cases()) {
        let name = scene.name.clone();
        // The tangency is exact in its numbers only on bases v1–v2 and p–q
        // (λ = 7 = 10 − 3 = 4 + 3; tested at 1e±150 below); on the others it
        // rests on derived lengths written to 16 digits, whose roundings to
        // f64 differ from scale to scale (at 1e100 on base a–b the point is
        // lost, and the report says the f64 and double-double runs differ).
        if name == "hard:tangency" {
            continue;
        }
        let a = analyse_with(scene.clone(), None, Scope::Full).unwrap();
        let Ok(s) = &a.outcome else { continue };
        for base in every_base(&a, s) {
            for scope in [Scope::Full, Scope::Lazy] {
                let (_, t) = solve_with(scene.clone(), Some(base), scope);
                let want = shape(&t);
                for exponent in [100, -100, 150, -150] {
                    let (_, u) = solve_with(scaled_as_written(scene.clone(), exponent), Some(base), scope);
                    assert_eq!(shape(&u), want, "{name} at 1e{exponent}: base {base:?}, {scope:?}");
                }
            }
        }
    }
}

/// The hard cases (THEORY.md §6) on every valid base. The exact tangency is
/// one isolated realization: on bases v1–v2 and p–q both steps are flat
/// there at once (p folded, q stretched at λ = 7 = 10 − 3 = 4 + 3), so the
/// point is an end of step 1's interval that step 2 touches from outside;
/// it was lost (no realization) before such an end became a point of its own.
/// (The tangency's sketch places v2 freely, so on some bases its type has no
/// realization at all and the drawing lies in no component; the report says so.)
#[test]
fn hard_cases_have_the_same_connected_sets_on_every_valid_base() {
    // Sets per hard case on its own base: the mirror pairs of the four-bars
    // with a dyad, the tangency's one point.
    let expected = [
        ("hard:sliver", 2),
        ("hard:near-coincident", 2),
        ("hard:tangency", 1),
        ("hard:scale-spread", 2),
        ("hard:near-parallelogram", 2),
    ];
    for scene in caymos::generate::hard_cases() {
        let (a, s) = solve(scene.clone());
        let sets = s.components.connected_set_count();
        let want = expected.iter().find(|(n, _)| *n == scene.name).map(|&(_, c)| c);
        assert_eq!(Some(sets), want, "{}", scene.name);
        for base in s.dec.other_bases(&a.linkage) {
            let (_, t) = solve_with(scene.clone(), Some(base), Scope::Full);
            assert_eq!(t.components.connected_set_count(), sets, "{}: base {base:?} vs {:?}", scene.name, s.dec.base);
        }
    }
    // The tangency again at 1e±150, every number scaled as written (so
    // 10 − 3 = 4 + 3 stays exact): the same point on every base.
    for exponent in [150, -150] {
        let scene = tangency_scaled(exponent);
        let (a, s) = solve(scene.clone());
        for base in every_base(&a, &s) {
            let (_, t) = solve_with(scene.clone(), Some(base), Scope::Full);
            assert_eq!(t.components.connected_set_count(), 1, "1e{exponent}: base {base:?}");
            assert_eq!(t.union.len(), 1, "1e{exponent}: base {base:?}");
            assert_eq!(t.union[0][0], t.union[0][1], "1e{exponent}: base {base:?}: one point");
        }
    }
    let scene = caymos::generate::tangency();
    let (a, _) = solve(scene.clone());
    let id = |n: &str| a.linkage.names.iter().position(|x| x == n).unwrap();
    for base in [["v1", "v2"], ["p", "q"]] {
        let (_, t) = solve_with(scene.clone(), Some([id(base[0]), id(base[1])]), Scope::Full);
        assert_eq!(t.union, vec![[7.0, 7.0]], "base {base:?}");
        // All four types are the one realization there, each a point.
        assert_eq!(t.space.intervals.len(), 4, "base {base:?}");
        for iv in &t.space.intervals {
            assert_eq!((iv.lower.lambda, iv.upper.lambda), (7.0, 7.0), "base {base:?}");
            assert_eq!(iv.lower.events.len(), 2, "base {base:?}: both steps flat");
        }
        assert_eq!(t.components.connected_set_count(), 1, "base {base:?}");
        assert!(t.drawn_component.is_some(), "base {base:?}");
        // Said as what it is: two steps flat at once, nothing unresolved.
        let coincident = t.space.notes.iter().filter(|n| matches!(n, Note::Coincident { .. })).count();
        assert_eq!(coincident, 1, "base {base:?}: {:?}", t.space.notes);
        assert!(!t.space.notes.iter().any(|n| matches!(n, Note::Unresolved { .. })), "base {base:?}");
        assert!(caymos::analysis::no_realization(&t, a.linkage.scale).is_none(), "base {base:?}");
    }
}

#[test]
fn bundled_scenes_have_the_same_components_on_every_valid_base() {
    let mut checked = 0;
    for b in bundled::BUNDLED {
        let scene = bundled::load(b.name).unwrap();
        if analyse_with(scene.clone(), None, Scope::Full).unwrap().outcome.is_ok() {
            assert_base_invariant(&scene);
            checked += 1;
        }
    }
    assert!(checked >= 8, "checked {checked} bundled scenes");
}

/// Case 5 and the non-generic families: Peaucellier (a rhombus whose fold
/// makes P turn freely) has 4 components on each of its six valid bases;
/// a parallelogram and a kite drawn with exactly equal bars keep their
/// component count on both bases.
#[test]
fn non_generic_scenes_have_the_same_components_on_every_valid_base() {
    let (a, s) = solve(bundled::load("peaucellier").unwrap());
    assert_eq!(s.components.list.len(), 4);
    assert_eq!(s.dec.other_bases(&a.linkage).len(), 5);
    let parallelogram = r#"
bars = [ ["A","B"], ["B","C"], ["C","D"], ["D","A"] ]
[joints]
A = [0.0, 0.0]
B = [0.5, 1.5]
C = [3.5, 1.5]
D = [3.0, 0.0]
"#;
    let kite = r#"
bars = [ ["A","B",1.0], ["B","C",3.0], ["C","D",3.0], ["D","A",1.0] ]
[joints]
A = [0.0, 0.0]
B = [0.5, 0.8]
C = [3.0, 0.5]
D = [0.9, -0.3]
"#;
    // |BC| + |CD| = |BP| + |PD| = 5 exactly: P's step touches stretched
    // where |BD| is largest (case 5).
    let tangent = r#"
base = ["O", "C"]
ground = ["O", "A"]
bars = [ ["O","A",2.0], ["A","C",2.0], ["O","B",5.0], ["O","D",5.0], ["C","B",3.0], ["C","D",2.0], ["B","P",2.5], ["P","D",2.5] ]
[joints]
O = [0.0, 0.0]
A = [2.0, 0.0]
C = [3.2855752193730785, 1.532088886237956]
B = [2.3859225013256795, 4.3940156824558345]
D = [4.97817393156854, 0.46667366226457063]
P = [2.9768057828522245, 1.9648477286880386]
"#;
    let (ta, t) = solve_text(tangent, "tangent");
    assert_eq!(t.dec.other_bases(&ta.linkage).len(), 5);
    for (name, text) in [("parallelogram", parallelogram), ("kite", kite), ("tangent", tangent)] {
        let scene = parse_scene(text, name, name).unwrap();
        assert_base_invariant(&scene);
    }
}

/// Rotating, translating, renaming, reordering and mirroring a scene: the
/// same Cayley space; a mirror flips every orientation bit.
fn transformed(scene: &Scene, angle: f64, shift: [f64; 2], mirror: bool, reorder: bool) -> Scene {
    let mut t = scene.clone();
    if reorder {
        reversed(&mut t);
    }
    let (c, s) = (angle.cos(), angle.sin());
    for j in &mut t.joints {
        let [x, y] = j.pos;
        let y = if mirror { -y } else { y };
        j.pos = [c * x - s * y + shift[0], s * x + c * y + shift[1]];
        j.name = format!("{}'", j.name);
    }
    t
}

/// The joints listed in reverse order, bars, bodies, base and ground renumbered.
fn reversed(t: &mut Scene) {
    let n = t.joints.len();
    let renumber = |j: usize| n - 1 - j;
    t.joints.reverse();
    for bar in &mut t.bars {
        bar.joints = bar.joints.map(renumber);
    }
    t.bars.reverse();
    t.base = t.base.map(|(b, line)| (b.map(renumber), line));
    t.ground = t.ground.iter().map(|&g| renumber(g)).collect();
    for body in &mut t.bodies {
        body.joints = body.joints.iter().map(|&j| renumber(j)).collect();
    }
}

/// Every sign the certifier proves at a point of a random linkage agrees
/// with the slack computed in double-double from the input, and at such
/// points (no slack near zero by design) none rests on an estimate, however
/// deep the construction: each base distance is enclosed in its own frame.
fn assert_signs_hold_at_points(scene: Scene, seed: u64) {
    let (a, s) = solve_with(scene, None, Scope::Lazy);
    let n = s.dec.steps.len();
    let dd: Construction<Dd> = Construction::new(&a.linkage, &s.dec).expect("closes in double-double");
    let cert = caymos::certify::Certifier::new(&a.linkage, &s.dec).expect("a certifier");
    let questions: Vec<(usize, Kind)> = (0..n).flat_map(|k| cert.kinds(k).iter().map(move |&kind| (k, kind))).collect();
    let mut rng = caymos::generate::SplitMix(seed);
    let [lo, hi] = [s.union[0][0], s.union.last().expect("a range")[1]];
    for i in 1..6 {
        let lambda = lo + (hi - lo) * f64::from(i) / 6.0;
        let mut bits = s.drawn.ty.0.clone();
        for b in bits.iter_mut() {
            *b ^= rng.below(4) == 0;
        }
        let signs = cert.slack_signs(&bits, caymos::certify::At { lambda, events: &[] }, &questions);
        let d = dd.base_distances(Dd::new(lambda), &bits);
        for (&(k, kind), sign) in questions.iter().zip(&signs) {
            let Some(&dk) = d.get(k) else { continue };
            let st = &dd.steps[k];
            let v = kind.slack_value(st.r1, st.r2, dk).to_f64();
            let want = if v > 0.0 { caymos::certify::Sign::Positive } else { caymos::certify::Sign::Negative };
            if d.len() > k + 1 || v.abs() > 1e-20 * s.construction.scale {
                assert_eq!(*sign, want, "step {k} {kind:?} at λ = {lambda}: double-double slack {v}");
            }
        }
    }
    assert_eq!(cert.estimated(), 0, "estimated decisions on a random {n}-step linkage");
}

#[test]
fn proven_signs_hold_on_a_deep_chain() {
    assert_signs_hold_at_points(chain(200), 7);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    #[test]
    fn proven_signs_hold_on_random_linkages(seed in any::<u64>(), steps in 2usize..60) {
        assert_signs_hold_at_points(random_linkage(seed, steps, 0.3), seed);
    }

    #[test]
    fn random_scenes_have_the_same_components_on_every_valid_base(seed in any::<u64>(), steps in 1usize..5) {
        assert_base_invariant(&random_linkage(seed, steps, 0.3));
    }

    #[test]
    fn scaling_and_moving_change_nothing_but_what_they_must(
        seed in any::<u64>(), steps in 1usize..5, e in prop::sample::select(vec![-150i32, -9, -3, 3, 9, 150]),
        angle in 0.0f64..std::f64::consts::TAU, mirror in any::<bool>(), reorder in any::<bool>()
    ) {
        let scene = random_linkage(seed, steps, 0.3);
        let (_, s) = solve(scene.clone());
        let f = 10f64.powi(e);
        let mut scaled = scene.clone();
        for j in &mut scaled.joints {
            j.pos = j.pos.map(|x| x * f);
        }
        let (_, t) = solve(transformed(&scaled, angle, [0.3 * f, -1.7 * f], mirror, reorder));
        prop_assert_eq!(t.components.list.len(), s.components.list.len());
        prop_assert_eq!(t.space.intervals.len(), s.space.intervals.len());
        // Reordering the joints may reorder the construction steps, so types
        // are compared only when the order is kept; a mirror flips every bit.
        let flip = |ty: &str| -> String {
            if reorder {
                String::new()
            } else if mirror {
                ty.chars().map(|c| if c == '+' { '-' } else { '+' }).collect()
            } else {
                ty.to_string()
            }
        };
        let mut want: Vec<(String, f64, f64)> = s.space.intervals.iter().map(|iv| (flip(&iv.ty.to_string()), iv.lower.lambda, iv.upper.lambda)).collect();
        want.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)).then(a.2.total_cmp(&b.2)));
        let mut got: Vec<(String, f64, f64)> = t.space.intervals.iter().map(|iv| (if reorder { String::new() } else { iv.ty.to_string() }, iv.lower.lambda / f, iv.upper.lambda / f)).collect();
        got.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)).then(a.2.total_cmp(&b.2)));
        for (g, w) in got.iter().zip(&want) {
            prop_assert_eq!(&g.0, &w.0);
            prop_assert!((g.1 - w.1).abs() <= 1e-9 * s.construction.scale, "{} vs {}", g.1, w.1);
            prop_assert!((g.2 - w.2).abs() <= 1e-9 * s.construction.scale, "{} vs {}", g.2, w.2);
        }
    }

    /// `--all` and `--lazy` agree on four-bar families: near-coincident
    /// events, tiny intervals, parallelograms, kites and rhombi.
    #[test]
    fn full_and_lazy_agree_on_hard_four_bar_families(
        e in 9i32..=15, family in 0usize..8, a in 0.5f64..2.0, b in 2.5f64..4.0
    ) {
        let delta = 10f64.powi(-e);
        let (ab, bc, cd, da) = match family {
            0 => (a, b, b - a + 0.5, 1.0 + 0.5 + b - a + delta),   // near-coincident folds
            1 => (a, b, a, b + delta),                              // near-parallelogram
            2 => (a, a * (1.0 + delta), b, b),                      // near-kite
            3 => (1.0, 2.0, 1.0, 4.0 - delta * 4.0),                // tiny interval
            4 => (a, b, a, b),                                      // parallelogram
            5 => (a, a, b, b),                                      // kite
            6 => (a, a, a, a),                                      // rhombus
            _ => (b - a, b, a, 2.0 * b - a),                        // both folds at exactly |BC| − |AB|
        };
        let scene = four_bar(ab, bc, cd, da);
        assert_scopes_agree(&scene);
    }
}

/// The text report counts the listed components and, where some meet at a
/// branch point, the connected sets they form (JSON: `connected_set`).
#[test]
fn the_report_says_how_many_connected_sets_the_components_form() {
    let out = caymos(&["report", "hard:tangency", "--base", "v1,v2"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = String::from_utf8_lossy(&out.stdout);
    let line = text.lines().find(|l| l.starts_with("Components")).expect("a Components line");
    assert!(
        line.contains("2 in 1 connected set (components that meet at a branch point share a realization"),
        "{line}"
    );
    let doc = json(&caymos(&["report", "hard:tangency", "--base", "v1,v2", "--format", "json"]));
    let sets: Vec<u64> =
        doc["components"].as_array().unwrap().iter().map(|c| c["connected_set"].as_u64().unwrap()).collect();
    assert_eq!(sets, vec![1, 1]);
    // Their closest pair is the shared realization, said as such, not certified.
    let doc =
        json(&caymos(&["closest", "hard:tangency", "--base", "v1,v2", "--components", "1,2", "--format", "json"]));
    assert_eq!(doc["outcome"], "shared", "{doc:#}");
    assert_eq!((doc["distance"].as_f64(), doc["certified"].as_bool()), (Some(0.0), Some(false)));
    assert_eq!((doc["a"]["lambda"].as_f64(), doc["b"]["lambda"].as_f64()), (Some(7.0), Some(7.0)));
    // A generic scene: each component its own set, and the line says nothing more.
    let out = caymos(&["report", "jansen"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.lines().any(|l| l.starts_with("Components") && l.trim_end().ends_with(" 6")), "{text}");
}

/// At 1e-300 double-double's low parts underflow and the tangency is missed
/// on every base; where the report then says no type closes, it says too
/// that this rests on estimates, not a proof.
#[test]
fn a_no_realization_that_rests_on_estimates_says_it_is_not_proven() {
    let scene = tangency_scaled(-300);
    let (a, s) = solve(scene.clone());
    let mut seen = 0;
    for base in every_base(&a, &s) {
        let (_, t) = solve_with(scene.clone(), Some(base), Scope::Full);
        if let Some(caymos::analysis::NoRealization::NoTypeCloses { estimated, .. }) =
            caymos::analysis::no_realization(&t, a.linkage.scale)
        {
            assert!(estimated > 0, "base {base:?}: a claim of no realization at 1e-300 cannot be proven");
            seen += 1;
        }
    }
    assert!(seen > 0, "the 1e-300 tangency says no type closes on some base");
}

/// Integer lengths make steps touch the ends of earlier steps' intervals
/// from outside. A four-bar with a dyad (AB = BC = CD = 1, DA = 2, BE = 1,
/// DE = 3) found no realization on two of its four bases before such an end
/// became a point of its own; and where the touching step's point only
/// repeats a realization another type reaches there (AB, BC, CD, DA = 1, 3,
/// 4, 2 with BE = DE = 1: at λ = 4 steps B and E are flat), no extra
/// interval is listed.
#[test]
fn touching_ends_are_found_on_every_base_and_not_listed_twice() {
    let scene = caymos::generate::four_bar_with_dyad([1.0, 1.0, 1.0, 2.0], 1.0, 3.0);
    let (a, s) = solve(scene.clone());
    for base in every_base(&a, &s) {
        let (_, t) = solve_with(scene.clone(), Some(base), Scope::Full);
        assert!(!t.space.intervals.is_empty(), "base {base:?}: no realization");
        assert!(caymos::analysis::no_realization(&t, a.linkage.scale).is_none(), "base {base:?}");
    }
    let (_, s) = solve(caymos::generate::four_bar_with_dyad([1.0, 3.0, 4.0, 2.0], 1.0, 1.0));
    assert_eq!(s.space.intervals.len(), 8, "{:#?}", s.space.intervals);
    assert!(s.space.intervals.iter().all(|i| i.lower.lambda < i.upper.lambda), "no point intervals");
    assert_eq!(s.components.list.len(), 2);
    assert_eq!(s.components.connected_set_count(), 1, "both steps B and D folded at λ = 2: all types meet");
}

/// The certifier's double-double Newton construction is the plain
/// double-double one with zero slopes (built once, mapped): its numbers are
/// exactly those that building it in slope arithmetic gives, on every
/// bundled scene, every hard case and a chain.
#[test]
fn the_slope_construction_mapped_from_the_plain_one_is_the_one_built_in_slopes() {
    use caymos::real::Slope;
    use caymos::realize::Construction;
    let scenes = bundled::BUNDLED.iter().filter_map(|s| bundled::resolve(Some(s.name)).ok());
    let mut checked = 0;
    for scene in scenes.chain(caymos::generate::hard_cases()).chain([chain(40)]) {
        let linkage = caymos::linkage::Linkage::from_scene(&scene);
        let Some(Ok(dec)) = caymos::decompose::decompose(&linkage, scene.base.map(|b| b.0)).ok() else { continue };
        let (Ok(built), Ok(plain)) =
            (Construction::<Slope<Dd>>::new(&linkage, &dec), Construction::<Dd>::new(&linkage, &dec))
        else {
            continue;
        };
        // Equal numbers; a zero slope's sign may differ (|x| of a negative
        // constant negates its zero slope), and −0 = 0.
        let unsigned = |text: String| text.replace("-0.0,", "0.0,").replace("-0.0 ", "0.0 ");
        assert_eq!(
            unsigned(format!("{built:?}")),
            unsigned(format!("{:?}", plain.map(Slope::constant))),
            "{}",
            scene.name
        );
        checked += 1;
    }
    assert!(checked >= 12, "only {checked} scenes built");
}

/// The lazy walk asks the certifier nothing it cannot prove where the
/// exhaustive sweep can: a bundled scene whose full analysis rests on no
/// estimate says the same lazily (it used to count the flat step's own
/// slack at each end, zero by construction, as 3 estimated decisions).
#[test]
fn a_lazy_report_warns_of_estimates_only_where_the_full_one_does() {
    let estimated = |a: &caymos::analysis::Analysis| {
        a.warnings.iter().find_map(|w| match w {
            Warning::EstimatedDecisions { count } => Some(*count),
            _ => None,
        })
    };
    let mut compared = 0;
    for b in bundled::BUNDLED {
        let scene = bundled::resolve(Some(b.name)).expect("bundled");
        let Ok(full) = analyse_with(scene.clone(), None, Scope::Full) else { continue };
        if full.outcome.is_err() {
            continue;
        }
        let lazy = analyse_with(scene, None, Scope::Lazy).expect("a valid scene");
        if estimated(&full).is_none() {
            assert_eq!(estimated(&lazy), None, "{}", b.name);
            compared += 1;
        }
    }
    assert!(compared >= 8, "only {compared} scenes compared");
}

/// A prefix stopped where a ball the measured step depends on overflowed
/// (the certifier's bracket search at a deep end of a long chain) loses
/// nothing: where it stops, the whole prefix's ball has overflowed too (or
/// an earlier step fails); where it does not, it is the same ball, bit for
/// bit, or the same failure.
#[test]
fn prefixes_stopped_at_an_overflowed_ball_lose_nothing() {
    let (a, s) = solve_with(chain(40), None, Scope::Lazy);
    let con: Construction<Ball<f64>> = Construction::new(&a.linkage, &s.dec).unwrap();
    let bits = &s.drawn.ty.0;
    let lambda = Ball::exact(s.drawn.lambda);
    let (mut pos, mut whole_pos, mut stopped) = (Vec::new(), Vec::new(), 0);
    for k in 0..con.steps.len() {
        let ancestors = con.ancestors(k);
        let overflowed = |j: usize, d: &Ball<f64>| ancestors[j] && !d.r.is_finite();
        let early = con.prefix_distance_unless(&mut pos, lambda, bits, k, overflowed);
        let whole = con.prefix_distance_into(&mut whole_pos, lambda, bits, k);
        let same = |d: Ball<f64>| (d.m.to_bits(), d.r.to_bits());
        match early {
            Ok(Some(d)) => assert_eq!(Ok(same(d)), whole.map(same), "step {k}"),
            Ok(None) => {
                stopped += 1;
                assert!(whole.is_err() || !whole.unwrap().r.is_finite(), "step {k}: {whole:?}");
            }
            Err(e) => assert_eq!(Err(e), whole.map(same), "step {k}"),
        }
    }
    // The chain's balls overflow within its first steps: the stop is taken.
    assert!(stopped > 0 && stopped < con.steps.len(), "stopped at {stopped} steps");
}

/// A step's ancestors are all it depends on: flipping the orientation of
/// any other earlier step leaves its base distance unchanged, bit for bit
/// (two Jansen legs on one crank: each leg's steps depend on the crank, not
/// on the other leg).
#[test]
fn a_step_depends_on_its_ancestors_only() {
    let (_, s) = solve(caymos::generate::strandbeest(2));
    let con = &s.construction;
    let bits = &s.drawn.ty.0;
    let mut independent = 0;
    for k in 0..con.steps.len() {
        let ancestors = con.ancestors(k);
        let d = con.realize_prefix(s.drawn.lambda, bits, k).map(|p| con.base_distance(&p, k).to_bits());
        for j in (0..k).filter(|&j| !ancestors[j]) {
            independent += 1;
            let mut flipped = bits.clone();
            flipped[j] = !flipped[j];
            let e = con.realize_prefix(s.drawn.lambda, &flipped, k).map(|p| con.base_distance(&p, k).to_bits());
            if let (Ok(d), Ok(e)) = (d, e) {
                assert_eq!(d, e, "step {k} moved with step {j}");
            }
        }
    }
    assert!(independent > 0, "two legs have independent steps");
}

/// A kite grounded on its diagonal B–D (A and C each equidistant from B and
/// D): both steps stand on the base with equal sides, so at λ = 0 both base
/// joints coincide and each vertex turns freely. That end is proven (the
/// folded slack of an equal-sided step on the base is λ itself, exactly 0
/// there), not estimated, and said to be a degenerate place, not a dead end
/// with an empty list of flat steps.
#[test]
fn a_kite_on_its_diagonal_ends_at_a_proven_degenerate_place() {
    let text = "name = \"kite\"\nbase = [\"B\", \"D\"]\nbars = [[\"A\", \"B\"], [\"A\", \"D\"], [\"C\", \"B\"], [\"C\", \"D\"]]\n[joints]\nA = [0.0, 1.0]\nB = [-1.0, 0.0]\nD = [1.0, 0.0]\nC = [0.0, -2.0]\n";
    let (a, s) = solve_text(text, "kite");
    assert_eq!(s.space.intervals.len(), 4);
    assert!(s.space.intervals.iter().all(|iv| iv.lower.lambda == 0.0 && iv.lower.events.is_empty()));
    assert!(!a.warnings.iter().any(|w| matches!(w, Warning::EstimatedDecisions { .. })), "{:?}", a.warnings);
    let text = caymos::report::Report::new(&a).to_text();
    assert!(text.contains("an end at λ = 0 where no step is flat (a degenerate place"), "{text}");
    assert!(!text.contains("a dead end at λ = 0 ()"), "{text}");
}

/// Issue 12: the sweep asks about a closed-form candidate far from being its
/// prefix's root in f64 balls alone (`Certifier::slack_signs_in_f64`, which
/// never escalates). Where those balls prove the signs they are the general
/// path's answers; at an exact tangency, where only double-double can say
/// zero, they claim nothing.
#[test]
fn f64_only_signs_are_the_general_answers_or_none() {
    use caymos::certify::{At, Prefixes, Sign};
    let (_, s) = solved("limacon");
    let inv = caymos::invert::Inverter::new(&s.construction, &s.dec, &s.complexity, None);
    let k = 3;
    let step = &s.construction.steps[k];
    let questions = [(k, Kind::Stretched), (k, Kind::Folded)];
    let mut prefixes = Prefixes::default();
    let (mut proven, mut asked) = (0, 0);
    for target in [step.r1 + step.r2, (step.r1 - step.r2).abs()] {
        for lambda in inv.candidates(k, target) {
            for code in 0..8u32 {
                let bits: Vec<bool> = (0..k).map(|i| code >> i & 1 == 1).collect();
                let at = At { lambda, events: &[] };
                let general = s.certifier.slack_signs(&bits, at, &questions);
                asked += 1;
                if let Some(f64_only) = s.certifier.slack_signs_in_f64(&mut prefixes, &bits, at, questions) {
                    assert_eq!(f64_only.to_vec(), general, "λ = {lambda}, bits {bits:?}");
                    proven += 1;
                }
            }
        }
    }
    assert!(proven > asked / 2, "{proven} of {asked} proven in f64 balls");
    // The tangency's isolated point: step 2 touches folded there.
    let (_, s) = solve(caymos::generate::tangency());
    let end = &s.space.intervals[0].lower;
    let bits = &s.space.intervals[0].ty.0;
    let at = At { lambda: end.lambda, events: &end.events };
    let touch = [(1, Kind::Folded)];
    assert_eq!(s.certifier.slack_signs_in_f64(&mut Prefixes::default(), bits, at, touch), None);
    assert_eq!(s.certifier.slack_signs(bits, at, &touch), [Sign::Zero]);
}

/// Peaucellier's rhombus folded: B ◁ (O, C) and D ◁ (O, C) are twins (the
/// same base joints, bars of the same lengths as written), so with the same
/// orientation they are one point and P ◁ (B, D), with equal sides, has base
/// distance exactly 0 (its vertex turns freely). The sweep's questions there
/// are proven from that structure, with no double-double estimate; with
/// opposite orientations B and D are apart and the folded slack is positive.
#[test]
fn twin_steps_prove_a_folded_rhombus_exactly() {
    use caymos::certify::{At, Prefixes, Sign};
    let (_, s) = solved("peaucellier");
    let cert = &s.certifier;
    let questions = [(3, Kind::Stretched), (3, Kind::Folded)];
    let at = At { lambda: 3.0, events: &[] };
    let before = cert.estimated();
    let same = cert.slack_signs_kept(&mut Prefixes::default(), &[true, true, true], at, questions);
    assert_eq!(same, [Sign::Positive, Sign::Zero]);
    assert_eq!(cert.estimated(), before, "proven, not estimated");
    let apart = cert.slack_signs_kept(&mut Prefixes::default(), &[true, true, false], at, questions);
    assert_eq!(apart, [Sign::Positive, Sign::Positive]);
    // The general path (which does not know twins) agrees where it decides.
    assert_eq!(cert.slack_signs(&[true, true, false], at, &questions), apart.to_vec());
    assert_eq!(cert.slack_signs(&[true, true, true], at, &questions), same.to_vec());
}

/// A rhombus on either diagonal: its two steps stand on the base with the
/// same sides as written, so both are flat at one λ, exactly (where one
/// folds, the other does, and where one stretches the other does). Those
/// coincidences are proven from the lengths as written, none estimated.
#[test]
fn a_rhombus_on_a_diagonal_proves_its_coincident_ends() {
    let text = "name = \"rhombus\"\nbase = [\"A\", \"C\"]\nbars = [[\"A\", \"B\", 3], [\"B\", \"C\", 3], [\"C\", \"D\", 3], [\"D\", \"A\", 3]]\n[joints]\nA = [0, 0]\nB = [1.5, 2.598076211353316]\nC = [4.5, 2.598076211353316]\nD = [3, 0]\n";
    let scene = parse_scene(text, "rhombus", "rhombus").unwrap();
    for base in [["A", "C"], ["B", "D"]] {
        let ids = base.map(|n| scene.joints.iter().position(|j| j.name == n).unwrap());
        let (a, s) = solve_with(scene.clone(), Some(ids), Scope::Full);
        assert!(s.space.notes.iter().any(|n| matches!(n, Note::Coincident { .. })), "{base:?}: the folds coincide");
        assert!(
            !a.warnings.iter().any(|w| matches!(w, Warning::EstimatedDecisions { .. })),
            "{base:?}: {:?}",
            a.warnings
        );
    }
}

/// The bundled Limacon scaled as written by 1e-160: the double-double
/// reference run loses step 3's folded end there (the f64 run and every
/// other method agree on it), and the report used to show the reference's
/// endpoints anyway, 3.5 times off, because the two runs listed the same
/// types. Runs whose ends differ in their flat steps differ in structure:
/// the f64 endpoints stay, and the report says the runs differ.
#[test]
fn a_reference_run_with_other_events_does_not_replace_the_endpoints() {
    let scene = scaled_as_written(bundled::load("limacon").unwrap(), -160);
    let (a, s) = solve(scene);
    let lower = s.union[0][0];
    assert!((lower / 7.003190304277537e-159 - 1.0).abs() < 1e-12, "lower end {lower:e}");
    let differ = a.warnings.iter().any(|w| matches!(w, Warning::RunsDiffer));
    let same = s.accuracy.as_ref().is_some_and(|acc| acc.same_structure);
    assert_eq!(differ, !same, "the warning says what the comparison found");
}
