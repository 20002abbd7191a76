//! Issue 4: components, paths, stepping, traces, Cayley distance, closest pair
//! (the certified closest pair's own properties: tests/closest.rs).

use crate::helpers::*;
use caymos::analysis::{Analysis, Solved, analyse};
use caymos::bundled;
use caymos::commands;
use caymos::distance::Arc;
use caymos::generate::{four_bar, random_linkage};
use caymos::motion::{Stepper, arcs, component_segments};
use caymos::realize::{Realization, bar_residual};
use proptest::prelude::*;

/// A walk with the default sample budget.
fn walk(step: f64) -> commands::Walk {
    commands::Walk { step, max_samples: caymos::tolerance::DEFAULT_MAX_SAMPLES }
}

/// Structural invariants of the component list.
fn check_components(s: &Solved) {
    let n = s.space.intervals.len();
    let mut seen = vec![0; n];
    for (k, c) in s.components.list.iter().enumerate() {
        assert!(c.closed, "generic scenes give closed cycles");
        for &i in &c.intervals {
            seen[i] += 1;
            assert_eq!(s.components.of_interval[i], k);
        }
        // Consecutive intervals share an endpoint and differ in exactly the flat step's bit.
        let m = c.intervals.len();
        for t in 0..m {
            let (i, j) = (c.intervals[t], c.intervals[(t + 1) % m]);
            let (a, b) = (&s.space.intervals[i], &s.space.intervals[j]);
            let leave = if c.forward[t] { &a.upper } else { &a.lower };
            let enter = if c.forward[(t + 1) % m] { &b.lower } else { &b.upper };
            assert_eq!(leave.id, enter.id, "consecutive intervals must share an endpoint");
            assert_eq!(leave.lambda, enter.lambda);
            let flat = leave.events[0].step;
            let differing: Vec<usize> = (0..a.ty.0.len()).filter(|&k| a.ty.0[k] != b.ty.0[k]).collect();
            if m > 1 {
                assert_eq!(differing, vec![flat], "{} → {} at step {}", a.ty, b.ty, flat);
            }
        }
    }
    assert!(seen.iter().all(|&x| x == 1), "every oriented interval lies in exactly one component");
}

/// Walk a whole component; check the step bound, bar lengths, and the return to the start.
fn check_stepping(a: &Analysis, s: &Solved, k: usize, step: f64) -> usize {
    let segs = component_segments(&s.space, &s.components.list[k]);
    let samples: Vec<_> = Stepper::new(&s.construction, &a.linkage, segs.clone(), step).collect();
    assert!(samples.len() >= 2);
    let scale = a.linkage.scale;
    for w in samples.windows(2) {
        let moved = w[0]
            .positions
            .iter()
            .zip(&w[1].positions)
            .map(|(p, q)| (p[0] - q[0]).hypot(p[1] - q[1]))
            .fold(0.0, f64::max);
        assert!(moved <= step * (1.0 + 1e-9) + 1e-7 * scale, "moved {moved} > {step}");
    }
    for x in &samples {
        assert!(bar_residual(&a.linkage, &x.positions) <= 1e-9 * scale);
    }
    // Every segment end is hit exactly.
    for (i, seg) in segs.iter().enumerate() {
        assert!(samples.iter().any(|x| x.segment == i && x.lambda == seg.to && x.at_end), "segment {i} end missed");
    }
    let (first, last) = (&samples[0], samples.last().unwrap());
    let gap =
        first.positions.iter().zip(&last.positions).map(|(p, q)| (p[0] - q[0]).hypot(p[1] - q[1])).fold(0.0, f64::max);
    assert!(gap <= 1e-9 * scale, "a full cycle returns to its start ({gap})");
    samples.len()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Grashof (both interval ends from one triangle): 2 components of 2
    /// intervals; otherwise 1 component of 4 (THEORY.md §7).
    #[test]
    fn four_bar_components_follow_the_closed_form(ab in 0.1f64..10.0, bc in 0.1f64..10.0, cd in 0.1f64..10.0, da in 0.1f64..10.0) {
        let (lo_abc, lo_adc) = ((ab - bc).abs(), (da - cd).abs());
        let (hi_abc, hi_adc) = (ab + bc, da + cd);
        let (lo, hi) = (lo_abc.max(lo_adc), hi_abc.min(hi_adc));
        prop_assume!(hi - lo > 1e-6 * hi && (lo_abc - lo_adc).abs() > 1e-9 * hi && (hi_abc - hi_adc).abs() > 1e-9 * hi);
        let (_, s) = solve(four_bar(ab, bc, cd, da));
        let same_triangle = (lo_abc > lo_adc) == (hi_abc < hi_adc);
        let sizes: Vec<usize> = s.components.list.iter().map(|c| c.intervals.len()).collect();
        if same_triangle {
            prop_assert_eq!(sizes, vec![2, 2]);
        } else {
            prop_assert_eq!(sizes, vec![4]);
        }
        check_components(&s);
    }

    /// Components, stepping and both path arcs on random 1-dof linkages.
    #[test]
    fn motion_invariants_hold_on_random_linkages(seed in any::<u64>(), steps in 1usize..6, tri in 0.0f64..0.7, pick in any::<u64>()) {
        let (a, s) = solve(random_linkage(seed, steps, tri));
        check_components(&s);
        let k = (pick as usize) % s.components.list.len();
        check_stepping(&a, &s, k, a.linkage.scale / 40.0);
        // Two realizations in component k: both arcs start and end at them.
        let comp = &s.components.list[k];
        let arc = Arc::new(&s.space, comp);
        let (ra, rb) = (arc.at(arc.total * 0.17), arc.at(arc.total * 0.71));
        let loc = |r: &Realization| caymos::motion::locate(&s.space, r, a.linkage.scale).unwrap();
        let both = arcs(&s.space, comp, (loc(&ra), ra.lambda), (loc(&rb), rb.lambda)).unwrap();
        for segs in &both {
            let first = segs.first().unwrap();
            let last = segs.last().unwrap();
            prop_assert_eq!(&first.ty, &ra.ty);
            prop_assert_eq!(first.from, ra.lambda);
            prop_assert_eq!(&last.ty, &rb.ty);
            prop_assert_eq!(last.to, rb.lambda);
            let walk: Vec<_> = Stepper::new(&s.construction, &a.linkage, segs.clone(), a.linkage.scale / 40.0).collect();
            let end = walk.last().unwrap();
            let target = caymos::realize::to_display(&a.linkage, s.dec.base, &s.construction.realize(rb.lambda, &rb.ty).unwrap());
            let gap = end.positions.iter().zip(&target).map(|(p, q)| (p[0] - q[0]).hypot(p[1] - q[1])).fold(0.0, f64::max);
            prop_assert!(gap <= 1e-9 * a.linkage.scale);
        }
        // Together the arcs cover the cycle: their interval counts add to m + 2.
        let m = comp.intervals.len();
        if loc(&ra) != loc(&rb) {
            prop_assert_eq!(both[0].len() + both[1].len(), m + 2);
        }
    }

}

#[test]
fn jansen_has_six_components_and_the_crank_turns_fully() {
    let (a, s) = solve(bundled::load("jansen").unwrap());
    assert_eq!(s.components.list.len(), 6);
    check_components(&s);
    let k = s.drawn_component.expect("drawn realization located");
    let c = &s.components.list[k];
    let op = (38.0f64 * 38.0 + 7.8 * 7.8).sqrt();
    assert!((c.lambda_range[0] - (op - 15.0)).abs() < 1e-12 * a.linkage.scale);
    assert!((c.lambda_range[1] - (op + 15.0)).abs() < 1e-12 * a.linkage.scale);
    // A full crank turn: the type changes exactly twice, at the two crank ends.
    let samples: Vec<_> = Stepper::new(&s.construction, &a.linkage, component_segments(&s.space, c), 0.5).collect();
    let changes = samples.windows(2).filter(|w| w[0].ty != w[1].ty).count();
    assert_eq!(changes, 2 - 1, "one change inside the walk, one where it closes");
    assert_ne!(samples.first().unwrap().ty, samples[samples.len() / 2 + 1].ty);
    assert_eq!(c.intervals.len(), 2);
    check_stepping(&a, &s, k, 0.5);
}

#[test]
fn limacon_has_three_components_and_paths_of_four_and_six_intervals() {
    let (a, s) = solve(bundled::load("limacon").unwrap());
    let mut sizes: Vec<usize> = s.components.list.iter().map(|c| c.intervals.len()).collect();
    sizes.sort();
    assert_eq!(sizes, vec![4, 4, 8]);
    check_components(&s);
    let k = s.components.list.iter().position(|c| c.intervals.len() == 8).unwrap();
    let comp = &s.components.list[k];
    let holding = |l: f64| -> Vec<usize> {
        comp.intervals
            .iter()
            .copied()
            .filter(|&i| s.space.intervals[i].lower.lambda <= l && l <= s.space.intervals[i].upper.lambda)
            .collect()
    };
    let mut found = false;
    for ia in holding(227.96) {
        for ib in holding(246.96) {
            let both = arcs(&s.space, comp, (ia, 227.96), (ib, 246.96)).unwrap();
            let mut counts = [both[0].len(), both[1].len()];
            counts.sort();
            if counts == [4, 6] {
                found = true;
                // The same through the command, with JSON-ready output.
                let from = format!("{}@227.96", s.space.intervals[ia].ty);
                let to = format!("{}@246.96", s.space.intervals[ib].ty);
                let p = commands::path(&a.linkage, &s, &from, &to, walk(a.linkage.scale / 50.0)).unwrap();
                assert!(p.same_component && !p.same_type_path);
                let mut n: Vec<usize> = p.paths.iter().map(|x| x.n_intervals).collect();
                n.sort();
                assert_eq!(n, vec![4, 6]);
                assert!(p.paths.iter().all(|x| x.cayley_length > 0.0 && x.max_joint_travel > 0.0));
            }
        }
    }
    assert!(found, "no pair of realizations at 227.96 and 246.96 with arcs of 4 and 6 intervals");
    for k in 0..3 {
        check_stepping(&a, &s, k, 2.0);
    }
}

#[test]
fn grashof_four_bar_components_are_mirror_images_at_distance_zero() {
    let (a, s) = solve(bundled::load("fourbar-crank-rocker").unwrap());
    assert_eq!(s.components.list.len(), 2);
    let c = commands::closest(&a.linkage, &s, 0, 1).unwrap();
    assert_eq!(c.distance, 0.0);
    assert!(c.mirror_images);
}

#[test]
fn paths_between_components_give_the_closest_pair() {
    let (a, s) = solve(bundled::load("jansen").unwrap());
    let p = commands::path(&a.linkage, &s, "----@40", "-+--@40", walk(0.5)).unwrap();
    assert!(!p.same_component && !p.same_connected_set && p.paths.is_empty());
    let c = p.closest_pair.expect("closest pair given");
    assert!(c.distance > 0.0 && c.lower_bound <= c.distance && c.certified);
    assert!(!c.mirror_images, "Jansen's triangles are chiral");
}

/// Components of one connected set (Peaucellier on base A–B: ---- and --+-
/// meet where the kite folds flat, at λ = √19) have no path along one
/// component, and the path says they are in one set; Jansen's components
/// are sets of their own, and the path says so.
#[test]
fn a_path_between_components_of_one_connected_set_says_so() {
    let scene = bundled::load("peaucellier").unwrap();
    let a = caymos::analysis::analyse(scene.clone(), None).unwrap();
    let id = |n: &str| a.linkage.names.iter().position(|x| x == n).unwrap();
    let (a, s) = solve_with(scene, Some([id("A"), id("B")]), caymos::analysis::Scope::Full);
    let p = commands::path(&a.linkage, &s, "----@3.2", "--+-@4.8", walk(0.5)).unwrap();
    assert!(!p.same_component && p.same_connected_set && p.paths.is_empty());
    assert!(p.to_text().contains("different components of one connected set"), "{}", p.to_text());
    // ---- and ---+ are joined through the singular place at √13 (P on C)
    // by way of -++- and -+++: one set, but no component holds both.
    let q = commands::path(&a.linkage, &s, "----@3.2", "---+@4", walk(0.5)).unwrap();
    assert!(!q.same_component && q.same_connected_set);
    let (a, s) = solved("jansen");
    let q = commands::path(&a.linkage, &s, "----@40", "-+--@40", walk(0.5)).unwrap();
    assert!(!q.same_component && !q.same_connected_set);
    assert!(q.to_text().contains("No path: the realizations lie in different components."));
}

#[test]
fn unrealizable_specs_are_rejected_with_a_reason() {
    let (a, s) = solve(bundled::load("jansen").unwrap());
    let err = commands::path(&a.linkage, &s, "--+-@24", "drawn", walk(1.0)).unwrap_err();
    assert!(err.contains("not realizable") && err.contains("26.24"), "{err}");
    assert!(commands::path(&a.linkage, &s, "-+@30", "drawn", walk(1.0)).unwrap_err().contains("4 steps"));
    assert!(commands::path(&a.linkage, &s, "x", "drawn", walk(1.0)).unwrap_err().contains("TYPE@LAMBDA"));
}

#[test]
fn motion_commands_run_on_every_bundled_scene() {
    for b in bundled::BUNDLED {
        let a = analyse(bundled::load(b.name).unwrap(), None).unwrap();
        let Ok(s) = a.outcome.clone() else { continue };
        let step = walk(commands::default_step(&a));
        let p = commands::path(&a.linkage, &s, "drawn", "drawn", step).unwrap();
        assert!(p.same_component && p.same_type_path, "{}", b.name);
        assert!(p.paths.iter().all(|p| p.complete && p.samples >= 1), "{}", b.name);
        let segs = commands::trace_segments(&a.linkage, &s, None, None).unwrap();
        let mut out = Vec::new();
        let cols = commands::TraceColumns { joints: vec![0, 1], angle: None, cayley: true };
        let summary = commands::trace_csv(&a.linkage, &s, segs.clone(), &cols, step, &mut out).unwrap();
        let csv = String::from_utf8(out).unwrap();
        let header = csv.lines().next().unwrap();
        assert!(header.starts_with("index,lambda,type,jump,") && header.contains(".y,"), "{header}");
        assert_eq!(header.split(',').count(), 4 + 4 + s.complexity.ccv.len());
        assert!(csv.lines().count() > 3, "{}", b.name);
        assert_eq!(csv.lines().count(), summary.samples + 1, "{}", b.name);
        assert!(summary.complete(), "{}", b.name);
        let svg = commands::svg(&a.scene.name, &a.linkage, &s, segs, &[0], step);
        assert!(svg.text.starts_with("<svg") && svg.text.contains("polyline") && !svg.points_cut);
        if s.components.list.len() >= 2 {
            let c = commands::closest(&a.linkage, &s, 0, 1).unwrap();
            assert!(c.lower_bound >= 0.0 && c.lower_bound <= c.distance, "{}", b.name);
        }
    }
}

/// `trace --angle A,B`: the crank's angle from the ground line A→D, checked
/// against the traced positions, turns a full 360° around the crank-rocker's
/// component; a bar without a ground joint is refused.
#[test]
fn trace_angle_column_is_the_crank_angle_from_the_ground_line() {
    let out = caymos(&["trace", "fourbar-crank-rocker", "--joints", "A,B,D", "--angle", "A,B"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let csv = stdout(&out);
    let mut lines = csv.lines();
    assert_eq!(lines.next().unwrap(), "index,lambda,type,jump,A.x,A.y,B.x,B.y,D.x,D.y,A-B.angle");
    let (mut total, mut last, mut rows) = (0.0f64, None::<f64>, 0);
    for line in lines {
        let v: Vec<f64> = line.split(',').skip(4).map(|x| x.parse().unwrap()).collect();
        let (a, b, d, angle) = ([v[0], v[1]], [v[2], v[3]], [v[4], v[5]], v[6]);
        let dir = |p: [f64; 2]| (p[1] - a[1]).atan2(p[0] - a[0]).to_degrees();
        let want = (dir(b) - dir(d) + 540.0).rem_euclid(360.0) - 180.0;
        let diff = (angle - want + 540.0).rem_euclid(360.0) - 180.0;
        assert!(diff.abs() < 1e-9, "{angle} vs {want}");
        assert!(angle > -180.0 && angle <= 180.0);
        if let Some(prev) = last {
            total += (angle - prev + 540.0f64).rem_euclid(360.0) - 180.0;
        }
        last = Some(angle);
        rows += 1;
    }
    assert!(rows > 20);
    // The walk returns to its start: one full turn of the crank.
    assert!((total.abs() - 360.0).abs() < 10.0, "the crank turned {total}°");
    let bad = caymos(&["trace", "fourbar-crank-rocker", "--angle", "B,C"]);
    assert_eq!(bad.status.code(), Some(1));
    assert!(stderr(&bad).contains("--angle B,C: neither joint is a ground joint"), "{}", stderr(&bad));
}

/// The crank-rocker with AB = 2.5 (AB + BC = CD + DA): at λ = 6.5 both steps
/// are stretched and all four types meet; paths and traces through it say
/// which way they went on.
#[test]
fn paths_and_traces_say_which_way_they_took_at_a_branch_point() {
    let text = bundled::find("fourbar-crank-rocker").unwrap().text.replace(r#"["A", "B", 1.0]"#, r#"["A", "B", 2.5]"#);
    let (a, s) = solve_text(&text, "cr25");
    let p = commands::path(&a.linkage, &s, "--@2", "+-@3", walk(0.05)).unwrap();
    let along = p.paths.iter().find(|x| x.intervals.iter().any(|i| i.to == 6.5)).expect("one path passes λ = 6.5");
    assert_eq!(along.branch_points.len(), 1, "{:?}", along.branch_points);
    let b = &along.branch_points[0];
    assert_eq!((b.lambda, b.steps.clone(), b.took.as_str()), (6.5, vec![1, 2], "+-"));
    assert_eq!(b.ways, ["--", "-+", "+-", "++"]);
    assert!(along.notes.iter().any(|n| n.contains("went on into type +-")), "{:?}", along.notes);
    // The other path passes no branch point and says none.
    let other = p.paths.iter().find(|x| !x.intervals.iter().any(|i| i.to == 6.5)).unwrap();
    assert!(other.branch_points.is_empty() && !other.notes.iter().any(|n| n.contains("branch")));
    // The trace of the component says it on stderr.
    let dir = scratch("branch-trace");
    let file = write(&dir, "cr25.toml", &text);
    let o = caymos(&["trace", &file, "--component", "1"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("a branch point (steps 1, 2 flat; 4 ways meet"), "{}", stderr(&o));
}
