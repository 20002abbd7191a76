//! The minimal complete Cayley vector: a subset of the complete vector, no
//! larger, and on dense samples it tells apart every two realizations of a
//! component that the whole vector tells apart.

use caymos::analysis::Solved;
use caymos::cayley_vector::{cayley_vector, euclid};
use caymos::generate::random_linkage;
use caymos::minimal_vector::{MinimalOptions, Minimality};
use caymos::motion::component_segments;
use caymos::realize::points;
use proptest::prelude::*;

use crate::helpers::{solve, solved};

/// The whole vector at `per_segment` λ values of every segment of every
/// component (the same λ grid on every segment, so the two sides of an
/// interval end are sampled at equal λ), per component.
fn dense_samples(s: &Solved, per_segment: usize) -> Vec<Vec<Vec<f64>>> {
    let ccv = &s.complexity.ccv;
    s.components
        .list
        .iter()
        .map(|c| {
            let mut out = Vec::new();
            for seg in component_segments(&s.space, c) {
                let (lo, hi) = (seg.from.min(seg.to), seg.from.max(seg.to));
                for k in 1..per_segment {
                    let lambda = lo + (hi - lo) * k as f64 / per_segment as f64;
                    if let Ok(pos) = s.construction.realize(lambda, &seg.ty) {
                        out.push(cayley_vector(&points(&pos), ccv));
                    }
                }
            }
            out
        })
        .collect()
}

/// The first two samples of one component that the whole vector tells apart
/// and `set` does not (projections equal bit for bit), if any.
fn collision(samples: &[Vec<Vec<f64>>], set: &[usize], scale: f64) -> Option<(Vec<f64>, Vec<f64>)> {
    for comp in samples {
        for (i, a) in comp.iter().enumerate() {
            for b in &comp[i + 1..] {
                if euclid(a, b) > 1e-9 * scale && set.iter().all(|&e| a[e] == b[e]) {
                    return Some((a.clone(), b.clone()));
                }
            }
        }
    }
    None
}

/// Every subset of `0..n` with `k` entries.
fn subsets(n: usize, k: usize) -> Vec<Vec<usize>> {
    (0u32..1 << n)
        .filter(|m| m.count_ones() as usize == k)
        .map(|m| (0..n).filter(|&e| m >> e & 1 == 1).collect())
        .collect()
}

fn check(s: &Solved, name: &str) {
    let m = s.minimal_vector(MinimalOptions::default());
    let n = s.complexity.ccv.len();
    assert!(!m.entries.is_empty() && m.entries.len() <= n, "{name}: {:?}", m.entries);
    assert!(m.entries.windows(2).all(|w| w[0] < w[1]) && m.entries.iter().all(|&e| e < n), "{name}: {:?}", m.entries);
    if m.minimality == Minimality::Whole {
        assert_eq!(m.entries.len(), n, "{name}");
    }
    let samples = dense_samples(s, 60);
    let scale = s.construction.scale;
    assert_eq!(collision(&samples, &m.entries, scale), None, "{name}: {:?} does not separate", m.entries);
    if m.minimality == Minimality::Proven && m.entries.len() > 2 {
        // Proven smallest: every smaller set folds some component, which
        // the equal-λ samples on the two sides of an end show.
        for set in subsets(n, m.entries.len() - 1) {
            assert!(
                collision(&samples, &set, scale).is_some(),
                "{name}: {set:?} separates, so {:?} is not minimal",
                m.entries
            );
        }
    }
}

#[test]
fn every_bundled_scene_has_a_separating_minimal_vector() {
    for b in caymos::bundled::BUNDLED {
        let a = caymos::analysis::analyse(caymos::bundled::load(b.name).unwrap(), None).unwrap();
        // fig1c is rigid: outside the class, no Cayley vector.
        if let Ok(s) = &a.outcome {
            check(s, b.name);
        }
    }
}

#[test]
fn known_minimal_vectors_are_found_and_proven() {
    // Watt I: the two later entries separate; λ with either one folds a
    // component where the other's step is flat.
    let (a, s) = solved("watt");
    let m = s.minimal_vector(MinimalOptions::default());
    let names: Vec<String> =
        m.entries.iter().map(|&e| s.complexity.ccv[e].map(|j| a.linkage.names[j].clone()).join("–")).collect();
    assert_eq!(m.minimality, Minimality::Proven);
    assert_eq!(m.entries.len(), 2, "{names:?}");
    assert!(m.cells > 0 && m.pairs > 0);
    // The sampled check can fail: on Jansen, λ with O–Y folds the component
    // where W's step is flat (neither length moves with W).
    let (_, j) = solved("jansen");
    assert!(collision(&dense_samples(&j, 60), &[0, 1], j.construction.scale).is_some());
    // A four-bar's vector has two entries: it is its own minimum.
    let m = solved("fourbar-crank-rocker").1.minimal_vector(MinimalOptions::default());
    assert_eq!((m.entries, m.minimality), (vec![0, 1], Minimality::Proven));
}

#[test]
fn a_budget_too_small_leaves_the_whole_vector() {
    let (_, s) = solved("jansen");
    let m = s.minimal_vector(MinimalOptions { max_step_cells: 4, ..MinimalOptions::default() });
    assert_eq!(m.entries, (0..s.complexity.ccv.len()).collect::<Vec<_>>());
    assert_eq!(m.minimality, Minimality::Whole);
    assert_eq!(m.cells, 0);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 16, ..ProptestConfig::default() })]

    #[test]
    fn random_scenes_have_a_separating_minimal_vector(seed in any::<u64>(), steps in 1usize..5) {
        let (_, s) = solve(random_linkage(seed, steps, 0.3));
        check(&s, &format!("seed {seed}, {steps} steps"));
    }
}

/// Scaling the scene changes nothing: the enclosures are made in units of the
/// scene's scale (at 1e±150 their products of lengths would overflow or
/// underflow, and only the whole vector could be claimed).
#[test]
fn the_minimal_vector_does_not_depend_on_the_scale() {
    let scene = caymos::bundled::load("watt").unwrap();
    let want = solve(scene.clone()).1.minimal_vector(MinimalOptions::default());
    assert_eq!(want.minimality, Minimality::Proven);
    for f in [1e150, 1e-150, 1e-300] {
        let mut scaled = scene.clone();
        for j in &mut scaled.joints {
            j.pos = j.pos.map(|x| x * f);
        }
        let got = solve(scaled).1.minimal_vector(MinimalOptions::default());
        assert_eq!((got.entries, got.minimality), (want.entries.clone(), want.minimality), "scale {f:e}");
    }
}
