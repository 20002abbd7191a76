//! Issue 3: exact Cayley configuration spaces, checked against closed forms,
//! the worked examples of THEORY.md §7, and a double-double reference.

use crate::helpers::*;
use caymos::analysis::{Analysis, Scope, Solved, analyse, reference_accuracy};
use caymos::bundled;
use caymos::cayley_space::{CayleySpace, Method, Note, SweepPlan, cayley_space, cayley_space_planned};
use caymos::generate::{bd_distance, four_bar, four_bar_with_dyad, random_linkage, tangency};
use caymos::invert::Inverter;
use caymos::linkage::Linkage;
use caymos::real::Jet;
use caymos::realize::{Construction, Kind, slack};
use caymos::roots::Endpoint;
use proptest::prelude::*;

/// The type bits a closed-form candidate knows hold for every type with a
/// root there: realized forward in f64 at the candidate, every prefix whose
/// step k is flat there (slack within 1e-9 of the scale) is one the
/// candidate admits. And the sweep that asks each prefix only about the
/// candidates it admits finds the intervals of the one that asks about
/// all, λ bit for bit.
fn assert_known_bits_hold(l: &Linkage, s: &Solved) {
    let con = &s.construction;
    let balls = s.certifier.f64_balls();
    let inverter = Inverter::new(con, &s.dec, &s.complexity, Some(balls));
    for k in (0..con.steps.len()).filter(|&k| !con.on_base(k)) {
        let (st, b) = (&con.steps[k], &balls.steps[k]);
        for kind in [Kind::Stretched, Kind::Folded] {
            let t = kind.target(st.r1, st.r2);
            for c in inverter.candidates_known(k, t, Some(kind.target(b.r1, b.r2))) {
                for word in 0..1u128 << k {
                    let bits: Vec<bool> = (0..con.steps.len()).map(|i| word >> i & 1 == 1).collect();
                    let d = con.base_distances(c.lambda, &bits);
                    let Some(&dk) = d.get(k) else { continue };
                    if kind.slack_value(st.r1, st.r2, dk).abs() <= 1e-9 * l.scale {
                        let at = c.lambda;
                        assert!(
                            c.known.admits(Some(word)),
                            "step {k} {kind:?} at {at}: bits {word:b} flat, {:?}",
                            c.known
                        );
                    }
                }
            }
        }
    }
    let plan = |cert| SweepPlan::new(con, cert, &s.dec, &s.complexity, Method::Exact);
    let with_bits = cayley_space_planned(con, &s.certifier.fork(), plan(Some(&s.certifier)));
    let without = cayley_space_planned(con, &s.certifier.fork(), plan(None));
    let view = |space: &CayleySpace<f64>| {
        let end = |e: &Endpoint<f64>| (e.lambda.to_bits(), e.events.clone());
        space.intervals.iter().map(|i| (i.ty.clone(), end(&i.lower), end(&i.upper))).collect::<Vec<_>>()
    };
    assert_eq!(view(&with_bits), view(&without));
}

/// f64 endpoints within 1e-12 × scale of the double-double reference, same structure.
fn assert_matches_reference(l: &Linkage, s: &Solved) {
    let acc = reference_accuracy(l, &s.dec, &s.complexity, &s.certifier, &mut s.space.clone()).expect("reference runs");
    assert!(acc.same_structure, "f64 and double-double disagree on the intervals");
    assert!(acc.max_relative_error <= 1e-12, "endpoint error {:e} relative", acc.max_relative_error);
}

/// The closed-form and numeric methods find the same intervals (two independent computations).
fn assert_methods_agree(l: &Linkage, s: &Solved) {
    let numeric =
        cayley_space(&s.construction, &s.certifier, &s.dec, &s.complexity, Method::Numeric { samples: 24, tol: 0.0 });
    assert_eq!(numeric.intervals.len(), s.space.intervals.len(), "interval counts differ");
    for (n, e) in numeric.intervals.iter().zip(&s.space.intervals) {
        assert_eq!(n.ty, e.ty);
        assert!((n.lower.lambda - e.lower.lambda).abs() <= 1e-11 * l.scale, "{} vs {}", n.lower.lambda, e.lower.lambda);
        assert!((n.upper.lambda - e.upper.lambda).abs() <= 1e-11 * l.scale, "{} vs {}", n.upper.lambda, e.upper.lambda);
        assert_eq!(n.lower.events, e.lower.events);
        assert_eq!(n.upper.events, e.upper.events);
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Every type of a four-bar has the single interval
    /// [max(|AB−BC|, |DA−CD|), min(AB+BC, DA+CD)] (THEORY.md §7).
    #[test]
    fn four_bars_match_the_closed_form(ab in 0.1f64..10.0, bc in 0.1f64..10.0, cd in 0.1f64..10.0, da in 0.1f64..10.0) {
        let lo = (ab - bc).abs().max((da - cd).abs());
        let hi = (ab + bc).min(da + cd);
        prop_assume!(hi - lo > 1e-6 * hi);
        // The drawn pose must itself be realizable for the sketch; any λ inside works.
        let (Analysis { linkage: l, .. }, s) = solve(four_bar(ab, bc, cd, da));
        prop_assert_eq!(s.space.intervals.len(), 4);
        for i in &s.space.intervals {
            prop_assert!((i.lower.lambda - lo).abs() <= 1e-13 * hi, "{} vs {lo}", i.lower.lambda);
            prop_assert!((i.upper.lambda - hi).abs() <= 1e-13 * hi, "{} vs {hi}", i.upper.lambda);
        }
        prop_assert_eq!(s.union.len(), 1);
        assert_matches_reference(&l, &s);
    }

    /// A realization that only measures base distances (skipping the joints
    /// no later step reads) gives every d_k bit for bit as the full
    /// realization does, and fails at the same step.
    #[test]
    fn distance_only_realizations_measure_as_full_ones(seed in any::<u64>(), steps in 1usize..8, tri in 0.0f64..0.6, at in 0.0f64..1.0, type_seed in any::<u64>()) {
        let (_, s) = solve(random_linkage(seed, steps, tri));
        let con = &s.construction;
        let Some(&[lo, hi]) = s.union.first() else { return Ok(()) };
        let lambda = lo + (hi - lo) * at;
        let bits: Vec<bool> = (0..con.steps.len()).map(|k| type_seed >> (k % 64) & 1 == 1).collect();
        let mut scratch = Vec::new();
        for k in 0..con.steps.len() {
            let full = con.realize_prefix(lambda, &bits, k).map(|pos| con.base_distance(&pos, k));
            let only = con.prefix_distance_into(&mut scratch, lambda, &bits, k);
            prop_assert_eq!(full.map(f64::to_bits), only.map(f64::to_bits), "step {}", k);
        }
        let full: Vec<f64> = (0..con.steps.len())
            .map_while(|k| {
                let pos = con.realize_prefix(lambda, &bits, k).ok()?;
                Some(con.base_distance(&pos, k))
            })
            .collect();
        let only = con.base_distances(lambda, &bits);
        prop_assert_eq!(&only[..full.len()], &full[..]);
    }

    /// A realization resumed at step m on the positions of another type
    /// that shares its first m bits (as the lazy walk's probes resume on
    /// the last type's) measures every d_k bit for bit as a fresh one, and
    /// fails at the same step; one that failed before m is the other's too.
    #[test]
    fn resumed_realizations_measure_as_fresh_ones(seed in any::<u64>(), steps in 1usize..8, tri in 0.0f64..0.6, at in 0.0f64..1.0, type_seed in any::<u64>(), flip in any::<usize>()) {
        let (_, s) = solve(random_linkage(seed, steps, tri));
        let con = &s.construction;
        let Some(&[lo, hi]) = s.union.first() else { return Ok(()) };
        let lambda = lo + (hi - lo) * at;
        let n = con.steps.len();
        let last: Vec<bool> = (0..n).map(|k| type_seed >> (k % 64) & 1 == 1).collect();
        let m = flip % n;
        let mut bits = last.clone();
        bits[m] = !bits[m];
        // Later bits may differ too: the resumed steps read none of the last type's.
        for b in bits.iter_mut().skip(m + 1) {
            *b = flip >> 8 & 1 == 1;
        }
        let mut pos = Vec::new();
        let last_d = con.base_distances_in(&mut pos, lambda, &last);
        let fresh = con.base_distances(lambda, &bits);
        if last_d.len() <= m {
            prop_assert_eq!(&fresh, &last_d);
            return Ok(());
        }
        let mut resumed = last_d[..m].to_vec();
        con.resume_distances_in(&mut pos, m, &bits, &mut resumed);
        let as_bits = |d: &[f64]| d.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        prop_assert_eq!(as_bits(&resumed), as_bits(&fresh));
    }

    /// [`assert_known_bits_hold`] on every valid base of random linkages.
    #[test]
    fn known_bits_hold_at_every_root(seed in any::<u64>(), steps in 2usize..7, tri in 0.0f64..0.8) {
        let scene = random_linkage(seed, steps, tri);
        let (Analysis { linkage: l, .. }, s) = solve(scene.clone());
        assert_known_bits_hold(&l, &s);
        for base in s.dec.other_bases(&l).into_iter().take(6) {
            let (Analysis { linkage: l, .. }, s) = solve_with(scene.clone(), Some(base), Scope::Full);
            assert_known_bits_hold(&l, &s);
        }
    }

    /// Scaling a scene scales its intervals and keeps their counts.
    #[test]
    fn intervals_scale_with_the_scene(seed in any::<u64>(), steps in 2usize..6, factor in prop::sample::select(vec![1e-3, 1e3])) {
        let scene = random_linkage(seed, steps, 0.4);
        let mut scaled = scene.clone();
        for j in &mut scaled.joints {
            j.pos = [j.pos[0] * factor, j.pos[1] * factor];
        }
        let (Analysis { linkage: l, .. }, s) = solve(scene);
        let (_, t) = solve(scaled);
        prop_assert_eq!(s.space.intervals.len(), t.space.intervals.len());
        for (x, y) in s.space.intervals.iter().zip(&t.space.intervals) {
            prop_assert_eq!(&x.ty, &y.ty);
            prop_assert!((x.lower.lambda * factor - y.lower.lambda).abs() <= 1e-12 * l.scale * factor);
            prop_assert!((x.upper.lambda * factor - y.upper.lambda).abs() <= 1e-12 * l.scale * factor);
        }
    }

    /// At every endpoint exactly the named step is flat; all steps close just
    /// inside the interval and the named step does not just outside.
    #[test]
    fn endpoints_have_exactly_the_named_step_flat(seed in any::<u64>(), steps in 1usize..7, tri in 0.0f64..0.6) {
        let (Analysis { linkage: l, .. }, s) = solve(random_linkage(seed, steps, tri));
        let con = &s.construction;
        let h = 1e-7 * l.scale;
        for i in &s.space.intervals {
            let width = i.upper.lambda - i.lower.lambda;
            for (end, inward) in [(&i.lower, 1.0), (&i.upper, -1.0)] {
                let [event] = end.events[..] else { panic!("generic scene, one event per end") };
                let pos = con.realize(end.lambda, &i.ty).unwrap();
                let st = &con.steps[event.step];
                let d = con.base_distance(&pos, event.step);
                let target = match event.kind { Kind::Stretched => st.r1 + st.r2, Kind::Folded => (st.r1 - st.r2).abs() };
                prop_assert!((d - target).abs() <= 1e-9 * l.scale, "step {} not flat: {d} vs {target}", event.step);
                // Just inside: every step closes strictly.
                let inside = end.lambda + inward * (h.min(width / 2.0));
                if width > 0.0 {
                    let pos = con.realize(inside, &i.ty).unwrap();
                    for (k, st) in con.steps.iter().enumerate() {
                        prop_assert!(slack(st.r1, st.r2, con.base_distance(&pos, k)) > 0.0, "step {k} flat inside");
                    }
                }
                // Just outside: the named step cannot close.
                let outside = end.lambda - inward * h;
                if let Ok(pos) = con.realize_prefix(outside, &i.ty.0, event.step) {
                    let d = con.base_distance(&pos, event.step);
                    prop_assert!(slack(st.r1, st.r2, d) < 0.0, "step {} still closes outside", event.step);
                }
            }
        }
    }
}

#[test]
fn jansen_leg_has_sixteen_intervals_over_the_crank_range() {
    let (Analysis { linkage: l, .. }, s) = solve(bundled::load("jansen").unwrap());
    assert_eq!(s.space.intervals.len(), 16);
    let op = (38.0f64 * 38.0 + 7.8 * 7.8).sqrt();
    assert_eq!(s.union.len(), 1);
    assert!((s.union[0][0] - (op - 15.0)).abs() < 1e-12 * l.scale);
    assert!((s.union[0][1] - (op + 15.0)).abs() < 1e-12 * l.scale);
    assert!((s.union[0][0] - 23.7923).abs() < 1e-4 && (s.union[0][1] - 53.7923).abs() < 1e-4);
    // The near-coincident endpoints of THEORY.md §6 are told apart.
    assert!(s.space.intervals.iter().any(|i| (i.lower.lambda - 23.8238).abs() < 1e-3));
    assert_matches_reference(&l, &s);
    assert_methods_agree(&l, &s);
}

#[test]
fn limacon_matches_the_published_intervals() {
    let (Analysis { linkage: l, .. }, s) = solve(bundled::load("limacon").unwrap());
    assert_eq!(s.union.len(), 1);
    assert!((s.union[0][0] - 70.03).abs() < 0.01 && (s.union[0][1] - 321.98).abs() < 0.01);
    let mut spans: Vec<(f64, f64)> = s.space.intervals.iter().map(|i| (i.lower.lambda, i.upper.lambda)).collect();
    spans.sort_by(|a, b| a.partial_cmp(b).unwrap());
    let published = [(70.03, 261.40), (70.03, 271.84), (132.60, 247.10), (132.60, 321.98)];
    assert_eq!(spans.len(), 16);
    for (chunk, p) in spans.chunks(4).zip(published) {
        for span in chunk {
            assert!((span.0 - p.0).abs() < 0.01 && (span.1 - p.1).abs() < 0.01, "{span:?} vs {p:?}");
        }
    }
    assert_matches_reference(&l, &s);
    assert_methods_agree(&l, &s);
}

// ---- The hard-case suite -------------------------------------------------

#[test]
fn hard_case_interval_narrower_than_1e_minus_7() {
    // B ◁ (A, C) closes for λ ∈ [1, 7], D for λ ∈ [1.5, 5.5]. With B and D on
    // opposite sides, |BD| falls steeply as λ → 5.5; E closes where
    // |BD| ≤ BE + DE, set to |BD| at 5.5 − 2e-8: a sliver [5.5 − 2e-8, 5.5].
    let lengths = [3.0, 4.0, 3.5, 2.0];
    let t = bd_distance(lengths, 5.5 - 2e-8, true, false);
    let (Analysis { linkage: l, .. }, s) = solve(four_bar_with_dyad(lengths, t / 2.0 + 0.25, t / 2.0 - 0.25));
    let sliver: Vec<_> =
        s.space.intervals.iter().filter(|i| i.upper.lambda - i.lower.lambda < 1e-7 * i.upper.lambda).collect();
    assert!(!sliver.is_empty(), "no sliver found");
    for i in sliver {
        assert!(i.upper.lambda > i.lower.lambda, "a sliver, not a point");
        assert!((i.upper.lambda - 5.5).abs() < 1e-12 * l.scale);
        assert!((i.lower.lambda - (5.5 - 2e-8)).abs() < 1e-9, "{}", i.lower.lambda);
    }
    assert_matches_reference(&l, &s);
    assert_methods_agree(&l, &s);
}

#[test]
fn hard_case_endpoints_of_different_steps_closer_than_1e_minus_6() {
    // E's stretched limit at |BD| of 5.5 − 3e-7 with B, D on opposite sides:
    // those types start at 5.5 − 3e-7 (step E); the types with B, D on one
    // side (|BD| smaller) run to 5.5 (step D). Two events of different steps
    // 3e-7 apart, in different intervals.
    let lengths = [3.0, 4.0, 3.5, 2.0];
    let t = bd_distance(lengths, 5.5 - 3e-7, true, false);
    let (Analysis { linkage: l, .. }, s) = solve(four_bar_with_dyad(lengths, t / 2.0 + 0.25, t / 2.0 - 0.25));
    let ends: Vec<(f64, usize)> =
        s.space.intervals.iter().flat_map(|i| [&i.lower, &i.upper]).map(|e| (e.lambda, e.events[0].step)).collect();
    let close =
        ends.iter().any(|&(x, kx)| ends.iter().any(|&(y, ky)| kx != ky && x != y && (x - y).abs() < 1e-6 * l.scale));
    assert!(close, "no pair of near-coincident endpoints from different steps: {ends:?}");
    assert_matches_reference(&l, &s);
    assert_methods_agree(&l, &s);
}

#[test]
fn hard_case_isolated_point_from_a_tangency() {
    // See `generate::tangency`: |pq| ≤ 7 with equality at one λ, where the
    // hinge angle a-v1-b is 180° − 30° − 60°, so λ = 10 sin 45°.
    let expected = 10.0 * ((std::f64::consts::PI - 30f64.to_radians() - 60f64.to_radians()) / 2.0).sin();
    let (Analysis { linkage: l, .. }, s) = solve(tangency());
    assert!(!s.space.intervals.is_empty(), "the isolated point must be kept");
    for i in &s.space.intervals {
        assert_eq!(i.lower.lambda, i.upper.lambda, "an isolated point has zero width");
        assert!((i.lower.lambda - expected).abs() < 1e-12 * l.scale, "{} vs {expected}", i.lower.lambda);
        assert_eq!(i.lower.events[0].kind, Kind::Folded);
    }
    assert!(s.space.notes.iter().any(|n| matches!(n, Note::Tangency { inside: false, .. })));
    assert_matches_reference(&l, &s);
}

#[test]
fn hard_case_bars_from_1e_minus_3_to_1e3() {
    // A Grashof four-bar with a 1e-3 crank and 1e3 coupler, plus a dyad whose
    // reach (0.55 + 0.4505) cuts the motion where |BD| ∈ [0.999, 1.001] passes 1.0005.
    let lengths = [1e-3, 1e3, 999.9995, 1.0];
    let (Analysis { linkage: l, .. }, s) = solve(four_bar_with_dyad(lengths, 0.55, 0.4505));
    assert!(s.space.intervals.iter().flat_map(|i| [&i.lower, &i.upper]).any(|e| e.events[0].step == 2));
    let (lo, hi) = (999.999, 1000.001);
    assert!(!s.space.intervals.is_empty());
    for i in &s.space.intervals {
        assert!(i.lower.lambda >= lo - 1e-12 * l.scale && i.upper.lambda <= hi + 1e-12 * l.scale);
    }
    assert!((s.union[0][0] - lo).abs() < 1e-12 * l.scale && (s.union[0][1] - hi).abs() < 1e-12 * l.scale);
    assert_matches_reference(&l, &s);
}

#[test]
fn hard_case_near_parallelogram() {
    // Opposite bars equal but for 1e-6 relative: AB = 2, CD = 2(1 + 1e-6), BC = DA = 3.
    let (ab, bc, cd, da) = (2.0, 3.0, 2.0 * (1.0 + 1e-6), 3.0);
    let (Analysis { linkage: l, .. }, s) = solve(four_bar(ab, bc, cd, da));
    let lo = (ab - bc).abs().max((da - cd).abs());
    let hi = (ab + bc).min(da + cd);
    assert_eq!(s.space.intervals.len(), 4);
    for i in &s.space.intervals {
        assert!((i.lower.lambda - lo).abs() <= 1e-13 * hi && (i.upper.lambda - hi).abs() <= 1e-13 * hi);
    }
    assert_matches_reference(&l, &s);
}

#[test]
fn hard_case_non_lcc_scenes_use_the_numeric_search_and_match_the_reference() {
    for name in ["stephenson", "fig1b"] {
        let (Analysis { linkage: l, .. }, s) = solve(bundled::load(name).unwrap());
        assert!(!s.complexity.low);
        assert!(!s.space.numeric_steps.is_empty());
        assert!(!s.space.intervals.is_empty());
        assert!(!s.space.notes.iter().any(|n| matches!(n, Note::Unresolved { .. })), "{name}: {:?}", s.space.notes);
        assert_matches_reference(&l, &s);
    }
}

#[test]
fn hard_case_peaucellier_is_non_generic_and_reported() {
    let (Analysis { linkage: l, .. }, s) = solve(bundled::load("peaucellier").unwrap());
    // λ = |OC| ∈ [2, 4]: B, D need |OC| ≥ 5 − 3, A needs |OC| ≤ 2 + 2.
    assert_eq!(s.union, vec![[2.0, 4.0]]);
    let coincident = |x: f64| {
        s.space.notes.iter().any(
            |n| matches!(n, Note::Coincident { lambda, events } if (lambda - x).abs() < 1e-12 && events.len() >= 2),
        )
    };
    assert!(coincident(2.0) && coincident(4.0), "{:?}", s.space.notes);
    // Types with B and D on one side fold the rhombus flat: P turns freely.
    assert!(s.space.notes.iter().any(|n| matches!(n, Note::Degenerate { step: 3, .. })));
    assert_eq!(s.space.intervals.len(), 8);
    assert_matches_reference(&l, &s);
}

#[test]
fn every_bundled_scene_meets_the_accuracy_target() {
    for b in bundled::BUNDLED {
        let a = analyse(bundled::load(b.name).unwrap(), None).unwrap();
        if let Ok(s) = &a.outcome {
            let acc = s.accuracy.as_ref().expect("reference computed for small scenes");
            assert!(acc.same_structure && acc.max_relative_error <= 1e-12, "{}: {acc:?}", b.name);
            assert!(!s.space.intervals.is_empty(), "{}", b.name);
        }
    }
}

#[test]
fn a_construction_converts_between_scalar_types_exactly() {
    let (_, s) = solve(bundled::load("limacon").unwrap());
    let jet: Construction<Jet<f64>> = s.construction.convert();
    assert_eq!(jet.steps.len(), s.construction.steps.len());
    assert_eq!(jet.steps[2].r1.v, s.construction.steps[2].r1);
}

/// A sweep's kept prefixes (`certify::Prefixes`) answer every question as a
/// fresh certifier realizing from scratch does, asked in an order that both
/// extends and cuts kept prefixes (each type's steps in turn, then the next
/// type). At every end its own flat step's slack is exactly zero: no f64
/// ball can prove a sign there, so each scene also exercises the fallback to
/// double-double, which answers zero from the kept double-double prefixes.
#[test]
fn kept_prefixes_answer_as_fresh_realizations() {
    use caymos::certify::{At, Certifier, Prefixes, Sign};
    for name in ["peaucellier", "jansen", "limacon", "hard:near-coincident", "hard:tangency", "hard:scale-spread"] {
        let (a, s) = solve(bundled::resolve(Some(name)).unwrap());
        let fresh = Certifier::new(&a.linkage, &s.dec).expect("the analysis built one");
        let mut prefixes = Prefixes::default();
        let mut zeros = 0;
        for iv in &s.space.intervals {
            let bits = &iv.ty.0;
            for end in [&iv.lower, &iv.upper] {
                for k in 0..bits.len() {
                    let at = At { lambda: end.lambda, events: &end.events };
                    let questions = [(k, Kind::Stretched), (k, Kind::Folded)];
                    let kept = s.certifier.slack_signs_in(Some(&mut prefixes), bits, at, &questions);
                    assert_eq!(
                        kept,
                        fresh.slack_signs(bits, at, &questions),
                        "{name} {} step {k} at {}",
                        iv.ty,
                        end.lambda
                    );
                    let own = end.events.iter().any(|e| e.step == k);
                    zeros += usize::from(own && kept.contains(&Sign::Zero));
                }
            }
        }
        assert!(zeros > 0, "{name}: no end's own flat step was asked in double-double");
    }
}

/// A four-bar's two steps stand on the base and no step reads their
/// vertices: measuring d_1 places no joint at all.
#[test]
fn distance_only_realizations_skip_unread_joints() {
    let (_, s) = solve(four_bar(3.0, 4.0, 2.5, 5.0));
    let con = &s.construction;
    let mut pos = Vec::new();
    let d = con.prefix_distance_into(&mut pos, 4.0, &[true, true], 1).unwrap();
    assert_eq!(d, 4.0);
    let at_origin = pos.iter().filter(|p| p[0] == 0.0 && p[1] == 0.0).count();
    // All but the base joint at (λ, 0).
    assert_eq!(at_origin, pos.len() - 1);
    let full = con.realize_prefix(4.0, &[true, true], 1).unwrap();
    assert!(full.iter().filter(|p| p[0] == 0.0 && p[1] == 0.0).count() < at_origin);
}
