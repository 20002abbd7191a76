//! Cayley vectors and distances (THEORY.md §5), and the closest pair of
//! realizations between two components.

use crate::cayley_space::CayleySpace;
use crate::decompose::Decomposition;
use crate::motion::{Component, Realization, Segment, component_segments};
use crate::realize::{Construction, P2, RealizationType};

/// The complete Cayley distance vector: the lengths of the CCV non-edges.
pub fn cayley_vector(pos: &[P2<f64>], ccv: &[[usize; 2]]) -> Vec<f64> {
    ccv.iter().map(|&[p, q]| (pos[q][0] - pos[p][0]).hypot(pos[q][1] - pos[p][1])).collect()
}

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
        shape
            .iter()
            .all(|&(_, r)| ((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])).abs() <= 1e-12 * len * len)
    })
}

/// The mirror image's type: every orientation flipped.
pub fn mirror_type(ty: &RealizationType) -> RealizationType {
    RealizationType(ty.0.iter().map(|b| !b).collect())
}

/// A component parametrized by arc length in λ, s ∈ [0, total): the Cayley
/// vector is continuous in s across interval ends, so a minimizer can move
/// from one oriented interval into the next.
pub struct Arc {
    segments: Vec<Segment>,
    starts: Vec<f64>,
    pub total: f64,
}

impl Arc {
    pub fn new(space: &CayleySpace<f64>, c: &Component) -> Arc {
        let segments = component_segments(space, c);
        let mut starts = Vec::with_capacity(segments.len());
        let mut total = 0.0;
        for s in &segments {
            starts.push(total);
            total += (s.to - s.from).abs();
        }
        Arc { segments, starts, total }
    }

    /// The realization at arc parameter `s` (taken modulo the total).
    pub fn at(&self, s: f64) -> Realization {
        let s = if self.total > 0.0 { s.rem_euclid(self.total) } else { 0.0 };
        let k = self.starts.partition_point(|&x| x <= s).saturating_sub(1);
        let seg = &self.segments[k];
        let t = (s - self.starts[k]).min((seg.to - seg.from).abs());
        let lambda = seg.from + t * (seg.to - seg.from).signum();
        Realization { ty: seg.ty.clone(), lambda }
    }
}

/// The closest pair of realizations between two components.
#[derive(Clone, Debug, PartialEq)]
pub struct ClosestPair {
    pub distance: f64,
    pub a: Realization,
    pub b: Realization,
    /// The best distance among the sampled pairs (the refined one is ≤ it).
    pub best_sampled: f64,
    pub samples: usize,
    /// The components are mirror images (distance 0, but different motions).
    pub mirror: bool,
    /// The two Cayley curves cross: different realizations with the same
    /// Cayley vector (possible when the vector is short; THEORY.md §5 only
    /// promises one-to-one within a component).
    pub crossing: bool,
    pub certificate: String,
}

/// Closest pair by Cayley distance: `samples` realizations on each component,
/// all pairs compared, then the best few pairs refined by a pattern search
/// over both arc parameters down to λ resolution.
pub fn closest_pair(
    con: &Construction<f64>,
    dec: &Decomposition,
    space: &CayleySpace<f64>,
    ccv: &[[usize; 2]],
    (ca, cb): (&Component, &Component),
    samples: usize,
) -> Option<ClosestPair> {
    let (arc_a, arc_b) = (Arc::new(space, ca), Arc::new(space, cb));
    let vector = |arc: &Arc, s: f64| -> Option<Vec<f64>> {
        let r = arc.at(s);
        con.realize(r.lambda, &r.ty).ok().map(|p| cayley_vector(&p, ccv))
    };
    if mirror_images_exist(con, dec) {
        let mirrored = |iv: usize| mirror_type(&space.intervals[iv].ty);
        let in_b = |ty: &RealizationType| cb.intervals.iter().any(|&j| &space.intervals[j].ty == ty);
        if ca.intervals.iter().all(|&i| in_b(&mirrored(i))) {
            let a = arc_a.at(0.0);
            let b = Realization { ty: mirror_type(&a.ty), lambda: a.lambda };
            return Some(ClosestPair {
                distance: 0.0,
                a,
                b,
                best_sampled: 0.0,
                samples: 0,
                mirror: true,
                crossing: false,
                certificate: "the components are mirror images: every realization's mirror lies in the other, with the same Cayley vector".into(),
            });
        }
    }
    let n = samples.max(8);
    let grid = |arc: &Arc| -> Vec<(f64, Vec<f64>)> {
        (0..n)
            .filter_map(|i| {
                let s = arc.total * i as f64 / n as f64;
                vector(arc, s).map(|v| (s, v))
            })
            .collect()
    };
    let (ga, gb) = (grid(&arc_a), grid(&arc_b));
    let mut pairs: Vec<(f64, f64, f64)> = Vec::with_capacity(ga.len() * gb.len());
    for (sa, va) in &ga {
        for (sb, vb) in &gb {
            pairs.push((euclid(va, vb), *sa, *sb));
        }
    }
    pairs.sort_by(|x, y| x.0.total_cmp(&y.0));
    let best_sampled = pairs.first()?.0;
    let f = |sa: f64, sb: f64| match (vector(&arc_a, sa), vector(&arc_b, sb)) {
        (Some(a), Some(b)) => euclid(&a, &b),
        _ => f64::INFINITY,
    };
    let mut best = (best_sampled, pairs[0].1, pairs[0].2);
    const STARTS: usize = 6;
    const MAX_MOVES: usize = 2000;
    for &(d0, sa0, sb0) in pairs.iter().take(STARTS) {
        let (mut sa, mut sb, mut d) = (sa0, sb0, d0);
        // Adaptive pattern search: a successful move doubles the step (so the
        // search can run along a narrow valley), a failed one halves it.
        let (ha0, hb0) = (arc_a.total / n as f64, arc_b.total / n as f64);
        let (mut ha, mut hb) = (ha0, hb0);
        let floor = 1e-15 * (arc_a.total + arc_b.total);
        for _ in 0..MAX_MOVES {
            if ha + hb <= floor {
                break;
            }
            let moves = [(ha, 0.0), (-ha, 0.0), (0.0, hb), (0.0, -hb), (ha, hb), (-ha, -hb), (ha, -hb), (-ha, hb)];
            match moves.iter().map(|&(da, db)| (f(sa + da, sb + db), da, db)).min_by(|x, y| x.0.total_cmp(&y.0)) {
                Some((dn, da, db)) if dn < d => {
                    d = dn;
                    sa += da;
                    sb += db;
                    ha = (ha * 2.0).min(ha0);
                    hb = (hb * 2.0).min(hb0);
                }
                _ => {
                    ha /= 2.0;
                    hb /= 2.0;
                }
            }
        }
        if d < best.0 {
            best = (d, sa, sb);
        }
    }
    let (distance, sa, sb) = best;
    let (a, b) = (arc_a.at(sa), arc_b.at(sb));
    // A zero distance between different realizations: the curves cross.
    let crossing = distance <= 1e-9 * con.scale
        && match (con.realize(a.lambda, &a.ty), con.realize(b.lambda, &b.ty)) {
            (Ok(p), Ok(q)) => p.iter().zip(&q).any(|(x, y)| (x[0] - y[0]).hypot(x[1] - y[1]) > 1e-6 * con.scale),
            _ => false,
        };
    let mut certificate = format!(
        "refined minimum {distance:.12e} ≤ best of {n}×{n} sampled pairs {best_sampled:.12e}; the {STARTS} best sampled pairs refined by an adaptive pattern search over both components (at most {MAX_MOVES} moves each)"
    );
    if crossing {
        certificate.push_str("; the Cayley curves cross here: two different realizations share one Cayley vector");
    }
    Some(ClosestPair { distance, a, b, best_sampled, samples: n, mirror: false, crossing, certificate })
}
