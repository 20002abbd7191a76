//! Issue 6: the lazy component walk equals the exhaustive sweep's component.

use caymos::analysis::{Solved, analyse};
use caymos::bundled;
use caymos::cayley_space::CayleySpace;
use caymos::generate::{hard_cases, random_linkage};
use caymos::lazy::{LazyOptions, component_through};
use caymos::motion::{Component, components};
use caymos::real::Jet;
use caymos::scene::Scene;
use proptest::prelude::*;

/// A component as (type, λ of the end walked from, λ of the end walked to) in traversal order.
fn walk(space: &CayleySpace<f64>, c: &Component) -> Vec<(String, f64, f64)> {
    c.intervals
        .iter()
        .zip(&c.forward)
        .map(|(&i, &fwd)| {
            let iv = &space.intervals[i];
            let (a, b) = if fwd { (iv.lower.lambda, iv.upper.lambda) } else { (iv.upper.lambda, iv.lower.lambda) };
            (iv.ty.to_string(), a, b)
        })
        .collect()
}

/// Equal as cycles: same length, and some rotation matches type by type with
/// endpoints within `tol`.
fn same_cycle(lazy: &[(String, f64, f64)], full: &[(String, f64, f64)], tol: f64) -> Result<(), String> {
    if lazy.len() != full.len() {
        return Err(format!("lazy has {} intervals, exhaustive {}:\n{lazy:?}\n{full:?}", lazy.len(), full.len()));
    }
    let m = full.len();
    let close = |x: f64, y: f64| (x - y).abs() <= tol;
    let matches = |r: usize| {
        (0..m).all(|t| {
            let (a, b) = (&lazy[t], &full[(t + r) % m]);
            a.0 == b.0 && close(a.1, b.1) && close(a.2, b.2)
        })
    };
    if (0..m).any(matches) { Ok(()) } else { Err(format!("no rotation matches:\nlazy {lazy:?}\nfull {full:?}")) }
}

/// For every component of the exhaustive analysis, start the lazy walk
/// inside its first interval and compare.
fn check_scene(scene: Scene) -> Result<usize, String> {
    let name = scene.name.clone();
    let a = analyse(scene, None).map_err(|e| e.to_string())?;
    let s: Solved = a.outcome.map_err(|_| format!("{name}: outside the class"))?;
    let jet = s.construction.convert::<Jet<f64>>();
    let tol = 1e-9 * a.linkage.scale;
    for (k, c) in s.components.list.iter().enumerate() {
        let first = &s.space.intervals[c.intervals[0]];
        let start = 0.5 * (first.lower.lambda + first.upper.lambda);
        let lazy = component_through(&s.construction, &jet, &first.ty, start, LazyOptions::default())
            .map_err(|e| format!("{name}: component {k}: start not realizable: {e:?}"))?;
        let lazy_components = components(&lazy);
        if lazy_components.list.len() != 1 {
            return Err(format!("{name}: component {k}: lazy space splits into {}", lazy_components.list.len()));
        }
        let lc = &lazy_components.list[0];
        if lc.closed != c.closed {
            return Err(format!("{name}: component {k}: closed {} vs {}", lc.closed, c.closed));
        }
        same_cycle(&walk(&lazy, lc), &walk(&s.space, c), tol).map_err(|e| format!("{name}: component {k}: {e}"))?;
    }
    Ok(s.components.list.len())
}

#[test]
fn lazy_equals_exhaustive_on_every_bundled_scene() {
    let mut checked = 0;
    for b in bundled::BUNDLED {
        let scene = bundled::load(b.name).unwrap();
        let a = analyse(scene.clone(), None).unwrap();
        if a.outcome.is_err() {
            continue; // not 1-dof tree-decomposable: nothing to walk
        }
        checked += check_scene(scene).unwrap_or_else(|e| panic!("{e}"));
    }
    assert!(checked >= 20, "expected components in the bundled scenes, walked {checked}");
}

#[test]
fn lazy_equals_exhaustive_on_hard_cases() {
    for scene in hard_cases() {
        check_scene(scene).unwrap_or_else(|e| panic!("{e}"));
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn lazy_equals_exhaustive_on_random_scenes(seed in any::<u64>(), steps in 1usize..7, tri in 0.0f64..0.6) {
        let scene = random_linkage(seed, steps, tri);
        check_scene(scene).map_err(TestCaseError::fail)?;
    }
}
