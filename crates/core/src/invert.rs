//! Closed-form candidate endpoints for low-Cayley-complexity linkages.
//!
//! In an LCC linkage each step's base distance d_k is carried by a valid pair
//! of clusters (Tu ∋ u_k, Tw ∋ w_k) hinged at a joint x: the two rigid
//! clusters turn about x, so any one cross distance |p q| (p ∈ Tu, q ∈ Tw)
//! fixes the hinge angle up to its sign, and with it every other cross
//! distance. Inverting d_k = t therefore gives at most two values of the
//! pair's *anchor* distance, which is either an earlier step's d_j (the pair
//! is that step's two clusters) or, for a pair made by a four-cycle, a
//! diagonal of the four-cycle's quadrilateral, which gives d_j in at most two
//! more ways. Following the chain down to a step on the base yields every λ
//! at which step k can be flat with d_k = t, as nested square roots: the
//! ruler-and-compass values of THEORY.md §2, with no sampling.
//!
//! Error behaviour: every 1 ± cos is formed as a product of differences of the
//! given lengths (no cancellation), so candidates carry a few ulps of error
//! except near a double root (a tangency), where the root itself is
//! ill-conditioned; there the two branches merge into one candidate when
//! sin θ rounds to zero.

use crate::complexity::{Complexity, PairOrigin};
use crate::decompose::Decomposition;
use crate::real::Real;
use crate::realize::Construction;

/// 1 − cos and 1 + cos of the angle opposite side `t` in a triangle with
/// sides `a`, `b`, `t`, each as a product of differences. `None` when the
/// triangle cannot close (beyond a few ulps, which are clamped to flat).
fn one_minus_plus_cos<T: Real>(a: T, b: T, t: T) -> Option<(T, T)> {
    let positive = |x: T| x.partial_cmp(&T::zero()) == Some(std::cmp::Ordering::Greater);
    if !(positive(a) && positive(b)) {
        return None;
    }
    let m = a - b;
    let s = a + b;
    // Each a ratio of lengths times a ratio of lengths: no product of two lengths.
    let two = T::from_f64(2.0);
    let omc = (t - m) / a * ((t + m) / (two * b)); // = 1 − cos
    let opc = (s - t) / a * ((s + t) / (two * b)); // = 1 + cos
    let tol = T::from_f64(crate::tolerance::INVERT_CLAMP_ULPS * T::UNIT_ROUNDOFF);
    if omc < -tol || opc < -tol {
        return None;
    }
    let clamp = |x: T| if x < T::zero() { T::zero() } else { x };
    Some((clamp(omc), clamp(opc)))
}

/// The side opposite an angle θ between sides `a` and `b`, from 1 − cos θ:
/// √((a − b)² + 2ab(1 − cos θ)), scaled by the longer side so that no
/// product of two lengths is formed.
fn side_from_angle<T: Real>(a: T, b: T, one_minus_cos: T) -> T {
    let m = if a > b { a } else { b };
    if m.partial_cmp(&T::zero()) != Some(std::cmp::Ordering::Greater) {
        return T::zero();
    }
    let (x, y) = (a / m, b / m);
    let q = (x - y) * (x - y) + T::from_f64(2.0) * x * y * one_minus_cos;
    if q < T::zero() { T::zero() } else { m * q.sqrt() }
}

/// An upper bound on the closed-form candidates' search: the branches of
/// [`Inverter::candidates`] for both targets of every step, as
/// `cayley_space::SweepPlan::new` asks them, from the carriers alone,
/// before any is computed: a step on the base has one candidate per
/// target, each hinge back towards the base at most doubles that, each
/// four-cycle quadruples it. Saturates at `f64::INFINITY`.
pub fn candidate_search_bound<T: Real>(con: &Construction<T>, cx: &Complexity) -> f64 {
    let mut bound = vec![0.0f64; con.steps.len()];
    for k in 0..con.steps.len() {
        bound[k] = if con.on_base(k) {
            1.0
        } else {
            match cx.carriers[k].map(|c| c.origin) {
                Some(PairOrigin::Step(j)) => 2.0 * bound[j],
                Some(PairOrigin::FourCycle { step: j, .. }) => 4.0 * bound[j],
                None => 0.0,
            }
        };
    }
    bound.iter().map(|b| 2.0 * b).sum()
}

/// Candidate λ values for "step k flat with d_k = t".
pub struct Inverter<'a, T: Real> {
    /// The construction whose steps are inverted.
    pub con: &'a Construction<T>,
    /// Its decomposition (the clusters of each step).
    pub dec: &'a Decomposition,
    /// The four-cycle test's carriers, which the inversion follows.
    pub cx: &'a Complexity,
}

impl<T: Real> Inverter<'_, T> {
    /// Every λ > 0 at which some realization has d_k = t (a superset: the
    /// caller checks each against the prefix it cares about). Sorted, exact
    /// duplicates removed.
    pub fn candidates(&self, k: usize, t: T) -> Vec<T> {
        let mut out = Vec::new();
        self.descend(k, t, &mut out);
        out.retain(|x| *x > T::zero());
        out.sort_by(|a, b| a.partial_cmp(b).unwrap_or(std::cmp::Ordering::Equal));
        out.dedup_by(|a, b| {
            (*a - *b).abs() <= T::from_f64(crate::tolerance::SAME_CANDIDATE_ULPS * T::UNIT_ROUNDOFF) * b.abs()
        });
        out
    }

    fn descend(&self, k: usize, t: T, out: &mut Vec<T>) {
        if self.con.on_base(k) {
            out.push(t);
            return;
        }
        let step = &self.dec.steps[k];
        let Some(carrier) = self.cx.carriers[k] else { return };
        let (tu, tw, x) = (carrier.tu, carrier.tw, carrier.x);
        match carrier.origin {
            PairOrigin::Step(j) => {
                let sj = &self.dec.steps[j];
                let p2 = if tu == sj.cluster_u { sj.u } else { sj.w };
                let q2 = if tw == sj.cluster_w { sj.w } else { sj.u };
                for dj in self.hinge(tu, tw, x, [step.u, step.w], t, [p2, q2]) {
                    if self.step_can_close(j, dj) {
                        self.descend(j, dj, out);
                    }
                }
            }
            PairOrigin::FourCycle { step: j, on_u, other, opposite, far } => {
                let vj = self.dec.steps[j].vertex;
                let step_cluster = if on_u { self.dec.steps[j].cluster_u } else { self.dec.steps[j].cluster_w };
                let anchors = if tu == step_cluster { [vj, far] } else { [far, vj] };
                for e in self.hinge(tu, tw, x, [step.u, step.w], t, anchors) {
                    for dj in self.quadrilateral(j, on_u, other, opposite, far, e) {
                        if self.step_can_close(j, dj) {
                            self.descend(j, dj, out);
                        }
                    }
                }
            }
        }
    }

    fn step_can_close(&self, j: usize, d: T) -> bool {
        let s = &self.con.steps[j];
        let tol = T::from_f64(crate::tolerance::FEASIBLE * self.con.scale);
        d >= (s.r1 - s.r2).abs() - tol && d <= s.r1 + s.r2 + tol
    }

    /// Clusters `tu` and `tw` turn about `x`. Given |p1 q1| = t (p1 ∈ tu,
    /// q1 ∈ tw), the possible values of |p2 q2|: the hinge angle θ1 = ±acos C,
    /// shifted by the fixed angle Δ between the two pairs.
    fn hinge(&self, tu: usize, tw: usize, x: usize, [p1, q1]: [usize; 2], t: T, [p2, q2]: [usize; 2]) -> Vec<T> {
        let c = self.con;
        let (a1, b1) = (c.cluster_distance(tu, x, p1), c.cluster_distance(tw, x, q1));
        let Some((omc, opc)) = one_minus_plus_cos(a1, b1, t) else { return Vec::new() };
        let cos1 = if omc < opc { T::from_f64(1.0) - omc } else { opc - T::from_f64(1.0) };
        let sin1 = (omc * opc).sqrt();
        // Δ = angle(p2 → p1) in tu + angle(q1 → q2) in tw.
        let (ca, sa) = if p1 == p2 { (T::from_f64(1.0), T::zero()) } else { c.cluster_angle(tu, x, p2, p1) };
        let (cb, sb) = if q1 == q2 { (T::from_f64(1.0), T::zero()) } else { c.cluster_angle(tw, x, q1, q2) };
        let (cd, sd) = (ca * cb - sa * sb, sa * cb + ca * sb);
        let (a2, b2) = (c.cluster_distance(tu, x, p2), c.cluster_distance(tw, x, q2));
        let signs: &[f64] = if sin1 > T::zero() { &[1.0, -1.0] } else { &[1.0] };
        signs
            .iter()
            .map(|&sg| {
                let sin_t1 = T::from_f64(sg) * sin1;
                // 1 − cos θ2 with θ2 = θ1 + Δ.
                let one_minus = T::from_f64(1.0) - (cos1 * cd - sin_t1 * sd);
                side_from_angle(a2, b2, one_minus)
            })
            .collect()
    }

    /// The four-cycle of step j: `pivot` (u_j if `on_u`, else w_j) with
    /// clusters (step j's own, `other`), `far` = other ∩ opposite, and step
    /// j's other base joint in `opposite`. Given the diagonal e = |v_j far|,
    /// the two values of the other diagonal d_j = |u_j w_j|.
    fn quadrilateral(&self, j: usize, on_u: bool, other: usize, opposite: usize, far: usize, e: T) -> Vec<T> {
        let c = self.con;
        let s = &c.steps[j];
        let (pivot, opp, r_piv, r_opp) = if on_u { (s.u, s.w, s.r1, s.r2) } else { (s.w, s.u, s.r2, s.r1) };
        let p = c.cluster_distance(other, pivot, far);
        let q = c.cluster_distance(opposite, opp, far);
        // Angles at v_j: α1 between pivot and far, α2 between opp and far.
        let Some((omc1, opc1)) = one_minus_plus_cos(r_piv, e, p) else { return Vec::new() };
        let Some((omc2, opc2)) = one_minus_plus_cos(r_opp, e, q) else { return Vec::new() };
        let one = T::from_f64(1.0);
        let (c1, s1) = (if omc1 < opc1 { one - omc1 } else { opc1 - one }, (omc1 * opc1).sqrt());
        let (c2, s2) = (if omc2 < opc2 { one - omc2 } else { opc2 - one }, (omc2 * opc2).sqrt());
        let signs: &[f64] = if s1 * s2 > T::zero() { &[1.0, -1.0] } else { &[1.0] };
        signs
            .iter()
            .map(|&sg| {
                // cos(α1 ∓ α2) = c1 c2 ± s1 s2
                let cos_sum = c1 * c2 + T::from_f64(sg) * s1 * s2;
                side_from_angle(r_piv, r_opp, one - cos_sum)
            })
            .collect()
    }
}
