//! Complete Cayley distance vectors (THEORY.md §5): the lengths of the
//! complete Cayley vector's non-edges in a realization, their Euclidean
//! distance, and when a Cayley curve stands for a mirror pair.

use crate::certify::Certifier;
use crate::decompose::Decomposition;
use crate::realize::{Point2, RealizationType};

/// The complete Cayley distance vector: the lengths of the CCV non-edges.
pub fn cayley_vector(pos: &[Point2<f64>], ccv: &[[usize; 2]]) -> Vec<f64> {
    ccv.iter().map(|&[p, q]| (pos[q][0] - pos[p][0]).hypot(pos[q][1] - pos[p][1])).collect()
}

/// Euclidean distance between two vectors of equal length (the Cayley
/// distance between two complete Cayley distance vectors).
pub fn euclid(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum::<f64>().sqrt()
}

/// Whether the mirror image of every realization is a realization too (with
/// the same Cayley vector, so each Cayley curve stands for a mirror pair).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mirrors {
    /// Some cluster a step stands on is proven not flat: no mirror pairs.
    No,
    /// Every such cluster has two joints: mirror pairs, proven.
    Yes,
    /// Every such cluster is flat to double-double resolution, some not
    /// provably (three or more joints on a line as written): mirror pairs
    /// at that resolution, a non-generic place.
    AtResolution,
}

impl Mirrors {
    /// Mirror pairs exist (proven or at double-double resolution).
    pub fn exist(self) -> bool {
        self != Mirrors::No
    }
}

/// Whether every cluster the steps stand on is achiral (all its joints on a
/// line, e.g. a bar), decided in proven arithmetic ([`Certifier::cluster_flat`]).
pub fn mirror_images(cert: &Certifier, dec: &Decomposition, scale: f64) -> Mirrors {
    let mut mirrors = Mirrors::Yes;
    for c in dec.steps.iter().flat_map(|s| [s.cluster_u, s.cluster_w]) {
        match cert.cluster_flat(c, scale) {
            Some(true) => {}
            Some(false) => return Mirrors::No,
            None => mirrors = Mirrors::AtResolution,
        }
    }
    mirrors
}

/// The mirror image's type: every orientation flipped.
pub fn mirror_type(ty: &RealizationType) -> RealizationType {
    RealizationType(ty.0.iter().map(|b| !b).collect())
}
