//! Complete Cayley distance vectors (THEORY.md §5): the lengths of the
//! complete Cayley vector's non-edges in a realization, their Euclidean
//! distance, and when a Cayley curve stands for a mirror pair.

use crate::decompose::Decomposition;
use crate::realize::{Construction, Point2, RealizationType};

/// The complete Cayley distance vector: the lengths of the CCV non-edges.
pub fn cayley_vector(pos: &[Point2<f64>], ccv: &[[usize; 2]]) -> Vec<f64> {
    ccv.iter().map(|&[p, q]| (pos[q][0] - pos[p][0]).hypot(pos[q][1] - pos[p][1])).collect()
}

/// Euclidean distance between two vectors of equal length (the Cayley
/// distance between two complete Cayley distance vectors).
pub fn euclid(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum::<f64>().sqrt()
}

/// Whether every cluster is achiral (all its joints on a line, e.g. a bar):
/// then the mirror image of a realization is one too, with the same Cayley
/// vector, and the Cayley curve stands for a mirror pair.
pub fn mirror_images_exist(con: &Construction<f64>, dec: &Decomposition) -> bool {
    dec.steps.iter().flat_map(|s| [s.cluster_u, s.cluster_w]).all(|c| {
        let shape = &con.shapes[c];
        let (p, q) = (shape[0].1, shape[1].1);
        let len = (q[0] - p[0]).hypot(q[1] - p[1]);
        shape.iter().all(|&(_, r)| {
            ((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])).abs()
                <= crate::tolerance::COLLINEAR * len * len
        })
    })
}

/// The mirror image's type: every orientation flipped.
pub fn mirror_type(ty: &RealizationType) -> RealizationType {
    RealizationType(ty.0.iter().map(|b| !b).collect())
}
