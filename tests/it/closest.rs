//! Issue 10, item 6: the closest pair between two components, certified by
//! branch and bound over proven interval enclosures of the Cayley vector.

use crate::helpers::*;
use caymos::analysis::{Analysis, Solved, analyse};
use caymos::bundled;
use caymos::cayley_vector::{cayley_vector, euclid};
use caymos::commands;
use caymos::distance::{ClosestOptions, ClosestPair, Outcome, closest_pair};
use caymos::enclosure::{enclose, halves};
use caymos::generate::random_linkage;
use caymos::interval::Interval;
use caymos::motion::{Component, Segment, component_segments, realization_at};
use caymos::realize::Realization;
use proptest::prelude::*;

/// The Cayley vector at λ on a segment (its ends exactly flat).
fn vector_on(a: &Analysis, s: &Solved, seg: &Segment, lambda: f64) -> Option<Vec<f64>> {
    realization_at(&s.construction, &a.linkage, seg, lambda).map(|p| cayley_vector(&p, &s.complexity.ccv))
}

/// Cayley vectors densely over a component, every interval end included:
/// each segment from both ends with equal steps in t = √|λ − end|, since
/// joints move like √|λ − end| there (where closest pairs like to sit).
fn dense(a: &Analysis, s: &Solved, c: &Component, per_half: usize) -> Vec<Vec<f64>> {
    let mut out = Vec::new();
    for seg in component_segments(&s.space, c) {
        let half = (seg.to - seg.from) / 2.0;
        for (end, towards) in [(seg.from, half), (seg.to, -half)] {
            for i in 0..=per_half {
                let u = i as f64 / per_half as f64;
                out.extend(vector_on(a, s, &seg, if i == 0 { end } else { end + towards * u * u }));
            }
        }
    }
    out
}

fn brute_force(a: &Analysis, s: &Solved, (i, j): (usize, usize), per_half: usize) -> f64 {
    let (va, vb) = (dense(a, s, &s.components.list[i], per_half), dense(a, s, &s.components.list[j], per_half));
    va.iter().flat_map(|x| vb.iter().map(move |y| euclid(x, y))).fold(f64::INFINITY, f64::min)
}

/// The segment of component `k` holding a realization.
fn segment_of(s: &Solved, k: usize, r: &Realization) -> Option<Segment> {
    component_segments(&s.space, &s.components.list[k])
        .into_iter()
        .find(|x| x.ty == r.ty && r.lambda >= x.from.min(x.to) && r.lambda <= x.from.max(x.to))
}

/// The closest pair of components `i`, `j` against a dense brute force over
/// both (ends included): its proven lower bound is never above a realized
/// pair, its distance is within its stated gap of the brute-force minimum,
/// and the pair it names lies in the two components at that distance.
fn check_pair(a: &Analysis, s: &Solved, (i, j): (usize, usize), opts: ClosestOptions) -> ClosestPair {
    let (ca, cb) = (&s.components.list[i], &s.components.list[j]);
    let c = closest_pair(&s.construction, s.mirrors, &s.space, &s.complexity.ccv, (ca, cb), opts).unwrap();
    let cert = &c.certificate;
    let name = &a.scene.name;
    let scale = s.construction.scale;
    // Rounding in the brute force's own f64 vectors.
    let slack = 1e-12 * scale;
    let brute = brute_force(a, s, (i, j), 24);
    assert!(
        cert.lower <= brute + slack,
        "{name} {i},{j}: proven lower bound {} above a realized pair at {brute}",
        cert.lower
    );
    assert!(cert.lower <= c.distance + slack && c.distance <= cert.upper + slack, "{name} {i},{j}: {c:?}");
    assert!(cert.gap >= 0.0 && cert.gap <= 1.0);
    if cert.gap < 1.0 {
        // lower ≥ (1 − gap)·upper and lower ≤ the true minimum ≤ brute.
        assert!(c.distance <= brute / (1.0 - cert.gap) + slack, "{name} {i},{j}: {} > brute {brute}", c.distance);
    }
    if cert.certified {
        assert!(cert.gap <= opts.gap && cert.unverified_ends == 0);
    }
    if c.mirror {
        assert_eq!(c.distance, 0.0);
        return c;
    }
    // The named pair: one realization in each component, at that distance.
    let (sa, sb) = (segment_of(s, i, &c.a).expect("a in component i"), segment_of(s, j, &c.b).expect("b in j"));
    let d = euclid(&vector_on(a, s, &sa, c.a.lambda).unwrap(), &vector_on(a, s, &sb, c.b.lambda).unwrap());
    assert!((d - c.distance).abs() <= 1e-9 * scale, "{name} {i},{j}: named pair at {d}, reported {}", c.distance);
    if c.crossing {
        assert!(c.distance <= 1e-9 * scale && cert.outcome == Outcome::Resolution);
    }
    c
}

fn check_all_pairs(name: &str) -> usize {
    let (a, s) = solve(bundled::load(name).unwrap());
    let n = s.components.list.len();
    let mut certified = 0;
    for i in 0..n {
        for j in i + 1..n {
            certified += check_pair(&a, &s, (i, j), ClosestOptions::default()).certificate.certified as usize;
        }
    }
    certified
}

#[test]
fn limacon_closest_pair_is_the_shared_upper_end_certified() {
    let (a, s) = solve(bundled::load("limacon").unwrap());
    let comp = |ty: &str| {
        let i = s.space.intervals.iter().position(|x| x.ty.to_string() == ty).unwrap();
        (s.components.of_interval[i], s.space.intervals[i].upper.lambda)
    };
    let ((i, end), (j, end_b)) = (comp("----"), comp("+---"));
    assert_eq!(end, end_b, "the two components share their upper end");
    assert!((end - 271.83599).abs() < 1e-5);
    // The pair at the shared end (each exactly flat there): 143.8733 apart.
    let at = |k: usize, ty: &str| {
        let r = Realization { ty: caymos::realize::RealizationType::parse(ty).unwrap(), lambda: end };
        vector_on(&a, &s, &segment_of(&s, k, &r).unwrap(), end).unwrap()
    };
    let d_end = euclid(&at(i, "----"), &at(j, "+---"));
    assert!((d_end - 143.8733).abs() < 1e-4, "{d_end}");
    let c = commands::closest(&a.linkage, &s, i, j).unwrap();
    // Sampling missed it (144.0571); now the minimum is found and proven.
    assert!(c.distance <= d_end + 1e-12 * a.linkage.scale, "{} > {d_end}", c.distance);
    assert!(c.lower_bound <= d_end && d_end <= c.distance + 1e-12 * a.linkage.scale);
    assert!(c.certified && c.relative_gap <= 1e-9 && c.unverified_ends == 0);
    assert!(c.certificate.starts_with("certified to 1e-9"), "{}", c.certificate);
    assert!((c.a.lambda - end).abs() < 1e-6 && (c.b.lambda - end).abs() < 1e-6, "{:?} {:?}", c.a, c.b);
}

#[test]
fn a_search_stopped_by_its_budget_says_so_and_stays_sound() {
    let (a, s) = solve(bundled::load("limacon").unwrap());
    let opts = ClosestOptions { max_boxes: 80, ..Default::default() };
    let c = commands::closest_with(&a.linkage, &s, 0, 2, opts).unwrap();
    assert_eq!(c.outcome, Outcome::Budget);
    assert!(!c.certified && c.relative_gap > 1e-9);
    assert!(c.certificate.starts_with("not certified to 1e-9: the budget of 80 boxes ran out"), "{}", c.certificate);
    // Still proven: the true minimum (143.8733…) lies between the bounds.
    assert!(c.lower_bound <= 143.8734 && c.upper_bound >= 143.8733 && c.lower_bound <= c.distance);
    // A looser gap is reached with the default budget, and said so.
    let c = commands::closest_with(&a.linkage, &s, 0, 2, ClosestOptions { gap: 1e-6, ..Default::default() }).unwrap();
    assert!(c.certified && c.certificate.starts_with("certified to 1e-6"), "{}", c.certificate);
    assert!(commands::closest_with(&a.linkage, &s, 0, 2, ClosestOptions { gap: 0.0, ..Default::default() }).is_err());
}

#[test]
fn jansen_component_pairs_are_within_their_gap_of_a_dense_brute_force() {
    // 15 pairs; those whose curves do not meet are certified to 1e-9.
    assert!(check_all_pairs("jansen") >= 10);
}

#[test]
fn limacon_component_pairs_are_within_their_gap_of_a_dense_brute_force() {
    assert!(check_all_pairs("limacon") >= 1);
}

#[test]
fn fig1a_component_pairs_are_within_their_gap_of_a_dense_brute_force() {
    // 28 pairs: the Cayley curves of some meet; the others are certified.
    assert!(check_all_pairs("fig1a") >= 10);
}

#[test]
fn other_bundled_component_pairs_are_within_their_gap_of_a_dense_brute_force() {
    let mut scenes = 0;
    for b in bundled::BUNDLED {
        if ["jansen", "limacon", "fig1a"].contains(&b.name) {
            continue;
        }
        let a = analyse(bundled::load(b.name).unwrap(), None).unwrap();
        if a.outcome.is_ok() {
            check_all_pairs(b.name);
            scenes += 1;
        }
    }
    assert!(scenes >= 5);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]

    /// The same on random 1-dof linkages (bars and triangles: chiral or not).
    #[test]
    fn random_linkages_are_within_their_gap_of_a_dense_brute_force(
        seed in any::<u64>(), steps in 2usize..6, tri in 0.0f64..0.7
    ) {
        let (a, s) = solve(random_linkage(seed, steps, tri));
        prop_assume!(s.components.list.len() >= 2);
        let n = s.components.list.len();
        check_pair(&a, &s, (0, 1), ClosestOptions::default());
        check_pair(&a, &s, (n - 2, n - 1), ClosestOptions::default());
    }
}

/// Every enclosure holds the realizations it stands for: sampled points of
/// each box against the f64 construction (values, and first and second
/// derivatives in t by finite differences), at the ends included.
#[test]
fn enclosures_hold_the_realizations() {
    let mut scenes = vec![bundled::load("limacon").unwrap(), bundled::load("jansen").unwrap()];
    scenes.extend((0..3).map(|seed| random_linkage(seed, 3, 0.5)));
    for scene in scenes {
        let (a, s) = solve(scene);
        let (con, ccv) = (&s.construction, &s.complexity.ccv);
        let scale = con.scale;
        let c = &s.components.list[0];
        let segs = component_segments(&s.space, c);
        for h in halves(con, &s.space, &segs) {
            let seg = &segs[h.segment];
            let at = |t: f64| vector_on(&a, &s, seg, h.lambda(t, seg)).unwrap();
            let tm = h.t_max;
            let boxes =
                [(0.0, tm), (0.0, 1e-3 * tm), (2e-3 * tm, 1e-2 * tm), (0.3 * tm, 0.5 * tm), (0.9 * tm, tm), (0.0, 0.0)];
            for (lo, hi) in boxes {
                let encl = enclose(con, ccv, &h, Interval::new(lo, hi));
                // The centre, the end itself (exactly flat), and inner points
                // where the end's uncertainty (~1e-11) is negligible against t².
                let mut samples = vec![(lo + hi) / 2.0];
                if lo == 0.0 {
                    samples.push(0.0);
                }
                samples.extend((0..=8).map(|k| lo + (hi - lo) * k as f64 / 8.0).filter(|&t| t >= 1e-3 * tm));
                for t in samples {
                    let v = at(t);
                    let (h1, h2) = (1e-4 * t, 5e-2 * t);
                    // λ = end ± t² is rounded to its ulp: |dV/dλ| ≈ |dV/dt|/2t times that.
                    let ulp = 4.0 * f64::EPSILON * h.end.abs().max(scale) / (2.0 * t);
                    let (p1, m1, p2, m2) = (at(t + h1), at(t - h1), at(t + h2), at(t - h2));
                    let inside = |i: Interval, y: f64, tol: f64| i.lo - tol <= y && y <= i.hi + tol;
                    for k in 0..v.len() {
                        let x = &encl[k];
                        let what =
                            format!("{} half {:?} box [{lo}, {hi}] t={t} entry {k}", a.scene.name, (h.segment, h.end));
                        assert!(inside(x.b.v, v[k], 1e-9 * scale), "{what}: {} ∉ {:?}", v[k], x.b.v);
                        if t == (lo + hi) / 2.0 {
                            assert!(inside(x.c.v, v[k], 1e-9 * scale), "{what}: {} ∉ centre {:?}", v[k], x.c.v);
                        }
                        if t == 0.0 {
                            continue;
                        }
                        let d1 = (p1[k] - m1[k]) / (2.0 * h1);
                        let d2 = (p2[k] - 2.0 * v[k] + m2[k]) / (h2 * h2);
                        let tol1 = 1e-6 * (d1.abs() + 1.0) + (1e-13 * scale + ulp * (d1.abs() + 1.0)) / h1;
                        let tol2 =
                            1e-3 * (d2.abs() + d1.abs() + 1.0) + (1e-13 * scale + ulp * (d1.abs() + 1.0)) / (h2 * h2);
                        assert!(inside(x.b.d, d1, tol1), "{what}: d/dt {d1} ∉ {:?}", x.b.d);
                        assert!(inside(x.b.dd, d2, tol2), "{what}: d²/dt² {d2} ∉ {:?}", x.b.dd);
                    }
                }
            }
        }
    }
}

#[test]
fn closest_through_the_binary_reports_its_certificate() {
    let run = |args: &[&str]| std::process::Command::new(env!("CARGO_BIN_EXE_caymos")).args(args).output().unwrap();
    let out = run(&["closest", "limacon", "--components", "1,3", "--gap", "1e-6", "--format", "json"]);
    assert_eq!(out.status.code(), Some(0));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["certified"], true);
    assert_eq!(json["requested_gap"], 1e-6);
    assert_eq!(json["outcome"], "gap_reached");
    assert!(json["lower_bound"].as_f64().unwrap() <= json["distance"].as_f64().unwrap());
    assert!(json["boxes"].as_u64().unwrap() > 0 && json["end_pairs"].as_u64().unwrap() == 64);
    let out = run(&["closest", "limacon", "--components", "1,3"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("Cayley distance 143.87") && text.contains("certified to 1e-9"), "{text}");
    assert_eq!(run(&["closest", "limacon", "--components", "1,3", "--gap", "2"]).status.code(), Some(1));
}

/// Mirror pairs are decided in proven arithmetic: bars only is proven, a
/// rigid triangle proven not, three joints on a line as written proven
/// flat (exactly, from the decimals), so proven too.
#[test]
fn mirror_pairs_are_proven_or_said_to_be_at_resolution() {
    use caymos::analysis::Warning;
    use caymos::cayley_vector::Mirrors;
    let (_, s) = solved("fourbar-non-grashof");
    assert_eq!(s.mirrors, Mirrors::Yes);
    let (_, s) = solved("jansen");
    assert_eq!(s.mirrors, Mirrors::No);
    let straight_coupler = r#"
ground = ["A", "D"]
bars = [["A", "B"], ["C", "D"], ["D", "A"]]
bodies = [["B", "E", "C"]]
[joints]
A = [0, 0]
B = [0, 1]
E = [1.5, 1.5]
C = [3, 2]
D = [3.5, 0]
"#;
    let (a, s) = solve_text(straight_coupler, "straight.toml");
    assert_eq!(s.mirrors, Mirrors::Yes);
    assert!(!a.warnings.contains(&Warning::MirrorsAtResolution), "{:?}", a.warnings);
    // A Grashof crank-rocker (1 + 3.5 < √10 + √4.25): two components, mirror images.
    assert_eq!(s.components.list.len(), 2);
    let (ca, cb) = (&s.components.list[0], &s.components.list[1]);
    let c = closest_pair(&s.construction, s.mirrors, &s.space, &s.complexity.ccv, (ca, cb), ClosestOptions::default())
        .unwrap();
    assert_eq!(c.certificate.outcome, Outcome::Mirror);
    assert!(c.certificate.certified, "flat proven exactly: the mirror pair is a proof");
}

/// The budget is work, not boxes alone: each box encloses pieces through
/// every step, so a deep scene (50 Jansen legs, 151 steps) gets
/// CLOSEST_BOX_STEPS / 151 boxes (about the same time as 100 000 boxes on a
/// scene of 100 steps); a shallow one keeps the default count.
#[test]
fn a_deep_scene_gets_fewer_boxes_for_the_same_work() {
    let mut a = analyse(caymos::generate::strandbeest(50), None).unwrap();
    let s = a.outcome.as_mut().unwrap();
    assert_eq!(s.construction.steps.len(), 151);
    commands::walk_components(s, 2);
    // A loose gap is reached at once: only the budget it had is read here.
    let opts = ClosestOptions { gap: 0.5, ..Default::default() };
    let c = commands::closest_with(&a.linkage, s, 0, 1, opts).unwrap();
    assert_eq!(c.max_boxes, caymos::tolerance::CLOSEST_BOX_STEPS / 151);
    assert!(c.max_boxes < caymos::distance::DEFAULT_MAX_BOXES && c.boxes <= c.max_boxes);
    let (a, s) = solve(bundled::load("limacon").unwrap());
    let c = commands::closest_with(&a.linkage, &s, 0, 2, opts).unwrap();
    assert_eq!(c.max_boxes, caymos::distance::DEFAULT_MAX_BOXES);
}
