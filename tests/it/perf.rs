//! Issue 12 (lazy walk and self-check): the walk's counters count what it
//! does, and the double-double self-check of a lazy analysis catches an f64
//! endpoint that is off its root. Never a speed.

use caymos::analysis::{Scope, lazy_reference_accuracy};
use caymos::bundled;
use caymos::generate::chain;
use caymos::lazy::{LazyOptions, WalkCounts, component_through, component_through_counted};
use caymos::real::Jet;
use caymos::scene::Scene;
use caymos::tolerance::TWO_THREADS_FROM_STEPS;

use crate::helpers::solve_with;

/// The lazy walk of the drawn component, with its counts.
fn walk(scene: Scene) -> (caymos::cayley_space::CayleySpace<f64>, WalkCounts) {
    let (_, s) = solve_with(scene, None, Scope::Lazy);
    let jet = s.construction.convert::<Jet<f64>>();
    let options = LazyOptions::default();
    let (space, counts) =
        component_through_counted(&s.construction, &s.certifier, &jet, &s.drawn.ty, s.drawn.lambda, options)
            .expect("the drawing is realizable");
    // The counted walk is the walk.
    let plain = component_through(&s.construction, &s.certifier, &jet, &s.drawn.ty, s.drawn.lambda, options).unwrap();
    assert_eq!(space.intervals, plain.intervals);
    (space, counts)
}

/// A Grashof four-bar on base (A, C): both steps are on the base, so every
/// end is an end of the base's range (λ = r1 ± r2, exact): no Newton at all.
/// The walk realizes at least: the start (once to check it, once as the first
/// probe), three searches each over a whole stretch from a start or an end
/// to the edge of the range (up and down from the start, then the flipped
/// type back across), where no gap is longer than sin(π/64) of the stretch
/// (the widest gap of 32 cosine-spaced samples), so 21 samples or more each,
/// and one probe after the flip: 66 realizations of 2 steps. The rest are
/// the samples that grow away from the ends and approach them; the exact
/// count is pinned so that a change in what the walk does shows here.
#[test]
fn four_bar_walk_counts() {
    let (space, c) = walk(bundled::load("fourbar-crank-rocker").unwrap());
    assert_eq!((c.steps, c.intervals), (2, space.intervals.len()));
    assert_eq!(c.intervals, 2);
    assert_eq!((c.roots, c.newton_evaluations), (0, 0));
    assert_eq!(c.newton_evals_per_root(), 0.0);
    assert!(c.steps_realized >= 66 * 2);
    assert_eq!(c.steps_realized, 174);
    assert_eq!(c.realizations_per_interval(), 174.0 / (2.0 * 2.0));
}

/// A chain of three four-cycles: its last step is off the base, and the
/// component's two ends (that step folded and stretched) are each located
/// by Newton at least once; every root costs at least one evaluation.
#[test]
fn chain_walk_counts() {
    let (space, c) = walk(chain(3));
    let off_base: std::collections::BTreeSet<usize> = space
        .intervals
        .iter()
        .flat_map(|iv| [&iv.lower, &iv.upper])
        .filter(|e| e.events.iter().any(|ev| ev.step == 2))
        .map(|e| e.id)
        .collect();
    assert_eq!(off_base.len(), 2);
    assert!(c.roots >= off_base.len());
    assert!(c.newton_evaluations >= c.roots);
    assert_eq!((c.steps, c.intervals, c.steps_realized, c.roots, c.newton_evaluations), (3, 2, 180, 4, 8));
}

/// The self-check refines each f64 end in double-double: on an unperturbed
/// walk it agrees to f64 rounding; an end moved by 10⁻⁹ of the scale is
/// reported as that error (and refined back); an end moved beyond any
/// refinement (10⁻³) is reported as a different structure. On a short
/// chain, and on one long enough to be walked and checked on two threads.
#[test]
fn self_check_catches_an_injected_endpoint_error() {
    for steps in [10, TWO_THREADS_FROM_STEPS] {
        injected_endpoint_error_is_caught(steps);
    }
}

fn injected_endpoint_error_is_caught(steps: usize) {
    let (a, s) = solve_with(chain(steps), None, Scope::Lazy);
    let scale = a.linkage.scale;
    let acc = s.accuracy.clone().expect("a lazy analysis of a chain checks itself");
    assert!(acc.same_structure && acc.refined && acc.max_relative_error <= 1e-11, "{steps} steps: {acc:?}");

    let mut clean = s.space.clone();
    let acc = lazy_reference_accuracy(&a.linkage, &s.dec, &mut clean).unwrap();
    assert!(acc.same_structure && acc.max_relative_error <= 1e-14, "{steps} steps: {acc:?}");

    let i = s.space.intervals.iter().position(|iv| !iv.upper.events.is_empty()).expect("an end with a flat step");
    let original = s.space.intervals[i].upper.lambda;
    let mut small = s.space.clone();
    small.intervals[i].upper.lambda += 1e-9 * scale;
    let acc = lazy_reference_accuracy(&a.linkage, &s.dec, &mut small).unwrap();
    assert!(acc.same_structure, "{acc:?}");
    assert!((0.9e-9..1.1e-9).contains(&acc.max_relative_error), "{acc:?}");
    assert!((small.intervals[i].upper.lambda - original).abs() <= 1e-14 * scale);

    let mut large = s.space.clone();
    large.intervals[i].upper.lambda += 1e-3 * scale;
    let acc = lazy_reference_accuracy(&a.linkage, &s.dec, &mut large).unwrap();
    assert!(!acc.same_structure && !acc.refined, "{acc:?}");
    assert_eq!(large.intervals[i].upper.lambda, original + 1e-3 * scale, "an unconfirmed end is left as it was");
    // ...and so is every other end: nothing is replaced unless all are confirmed.
    large.intervals[i].upper.lambda = original;
    assert_eq!(large.intervals, s.space.intervals);
}
