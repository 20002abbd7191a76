//! Issue 40, item 6: every scale f64 can hold gives the answer of scale 1.
//! Each bundled scene is scaled by 10^k as written (a decimal exponent
//! appended, nothing rounded) for k across −300…300, the thresholds where a
//! product of two lengths (1e±154) or a double-double's low part (1e-292)
//! would leave the normal range included, and analysed in full and lazily.

use crate::helpers::*;
use caymos::analysis::{Scope, Solved, analyse_with};
use caymos::bundled;

const EXPONENTS: [i32; 24] = [
    -300, -299, -292, -250, -200, -160, -156, -155, -154, -150, -100, -7, 7, 100, 150, 154, 155, 156, 160, 200, 250,
    292, 299, 300,
];

/// What must not change with the scale.
#[derive(Debug, PartialEq)]
struct Structure {
    /// Each interval's type and the flat steps at its ends.
    intervals: Vec<String>,
    /// Each component as its types in order, and the connected sets.
    components: (Vec<Vec<String>>, usize),
    /// The drawn realization's component.
    drawn: Option<usize>,
    /// The kinds of notes met, sorted.
    notes: Vec<String>,
    /// Whether the double-double run found the same structure.
    same_structure: Option<bool>,
    /// Decisions resting on estimates.
    estimated: usize,
}

fn structure(s: &Solved) -> Structure {
    let ty = |i: usize| s.space.intervals[i].ty.to_string();
    let intervals =
        s.space.intervals.iter().map(|iv| format!("{} {:?} {:?}", iv.ty, iv.lower.events, iv.upper.events)).collect();
    let components = s.components.list.iter().map(|c| c.intervals.iter().map(|&i| ty(i)).collect()).collect();
    let mut notes: Vec<String> = s
        .space
        .notes
        .iter()
        .map(|n| format!("{n:?}").split([' ', '{', '(']).next().unwrap_or_default().to_string())
        .collect();
    notes.sort();
    Structure {
        intervals,
        components: (components, s.components.connected_set_count()),
        drawn: s.drawn_component,
        notes,
        same_structure: s.accuracy.as_ref().map(|a| a.same_structure),
        estimated: s.certifier.estimated(),
    }
}

/// Every generic bundled scene, at every exponent, in full and lazily: the
/// same structure with nothing more estimated, and endpoints scaled to
/// rounding. Below 1e-292 a double-double's low part is subnormal and a
/// ball's absolute radius term (2^-1022) is 1e-8 of the values: the lazy
/// Limacon's walk then rests 12 decisions on estimates (the same answer).
/// Peaucellier is non-generic by design: its exact touches rest on
/// estimates at scale 1 already, and its decimals rounded to f64 at each
/// scale put them at a different rounding error from zero; only its
/// components are compared, to 1e±292.
#[test]
fn bundled_scenes_scaled_by_any_power_of_ten_give_the_scaled_analysis() {
    let mut checked = 0;
    for b in bundled::BUNDLED {
        let scene = bundled::load(b.name).unwrap();
        for scope in [Scope::Full, Scope::Lazy] {
            let a = analyse_with(scene.clone(), None, scope).unwrap();
            let Ok(unit) = &a.outcome else { continue };
            let want = structure(unit);
            for k in EXPONENTS {
                let (_, s) = solve_with(scaled_as_written(scene.clone(), k), None, scope);
                let at = format!("{} at 1e{k}, {scope:?}", b.name);
                let got = structure(&s);
                if b.name == "peaucellier" {
                    if k.abs() <= 292 {
                        assert_eq!(got.components, want.components, "{at}");
                    }
                } else if k < -292 {
                    assert_eq!(
                        (&got.intervals, &got.components, got.drawn),
                        (&want.intervals, &want.components, want.drawn),
                        "{at}"
                    );
                } else {
                    assert_eq!(got, want, "{at}");
                }
                let f = 10f64.powi(k);
                for (x, y) in s.space.intervals.iter().zip(&unit.space.intervals) {
                    for (p, q) in [(x.lower.lambda, y.lower.lambda), (x.upper.lambda, y.upper.lambda)] {
                        assert!((p / f - q).abs() <= 1e-13 * unit.construction.scale, "{at}: {p:e} vs {q}");
                    }
                }
                checked += 1;
            }
        }
    }
    assert!(checked >= 9 * 2 * EXPONENTS.len(), "checked {checked}");
}
