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
//! Each hinge or quadrilateral has two branches (the angle ±θ); where a
//! branch fixes the side of a step's vertex, balls from the lengths as
//! written prove which, so each candidate knows some type bits of the
//! realizations with a root there ([`KnownBits`]), and a sweep asks each
//! prefix only about the candidates it admits.
//!
//! Error behaviour: every 1 ± cos is formed as a product of differences of the
//! given lengths (no cancellation), so candidates carry a few ulps of error
//! except near a double root (a tangency), where the root itself is
//! ill-conditioned; there the two branches merge into one candidate when
//! sin θ rounds to zero.

use std::cell::{Cell, OnceCell};

use crate::complexity::{Complexity, PairOrigin};
use crate::decompose::Decomposition;
use crate::real::{Ball, Real};
use crate::realize::Construction;

/// Type bits known at a candidate: every type with a root on the branches
/// the candidate stands for has, for each step in `mask`, the bit of
/// `value` (so each root of a type is at a candidate that admits it).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct KnownBits {
    /// The steps whose bit is known, bit i for step i.
    pub mask: u128,
    /// Their bits (zero outside `mask`).
    pub value: u128,
}

impl KnownBits {
    /// Whether a type whose first bits are `word` (bit i for step i) may
    /// have its root here; any type where the bits are not known as a word.
    pub fn admits(self, word: Option<u128>) -> bool {
        word.is_none_or(|w| w & self.mask == self.value)
    }

    fn with(self, step: usize, bit: bool) -> KnownBits {
        if step >= 128 {
            return self;
        }
        KnownBits { mask: self.mask | 1 << step, value: self.value | u128::from(bit) << step }
    }
}

/// A closed-form candidate λ, and the type bits its roots have.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Candidate<T> {
    /// The candidate λ.
    pub lambda: T,
    /// The bits of every type with a root here.
    pub known: KnownBits,
}

impl<T> Candidate<T> {
    /// A candidate whose roots' bits are not known.
    pub fn unknown(lambda: T) -> Self {
        Candidate { lambda, known: KnownBits::default() }
    }
}

/// The inversion's branch decisions (does a triangle close, does an angle
/// have two branches): proven where the type proves signs ([`Ball`],
/// the exact type), else taken by value and counted as unproven. After
/// the first unproven decision the rest are taken by value (the
/// candidates are no longer proven complete, and an exact sign out of
/// reach is the costliest question there is).
#[derive(Debug, Default)]
pub struct Decisions {
    unproven: Cell<usize>,
}

impl Decisions {
    /// Whether x < 0; unproven, whether x < −`tol` (values a few ulps below
    /// zero are rounding of a zero).
    fn negative<T: Real>(&self, x: T, tol: T) -> bool {
        self.proven_sign(x).map_or_else(|| self.unproven_then(x < -tol), |s| s < 0)
    }

    /// Whether x > 0.
    fn positive<T: Real>(&self, x: T) -> bool {
        self.proven_sign(x).map_or_else(|| self.unproven_then(x > T::zero()), |s| s > 0)
    }

    fn proven_sign<T: Real>(&self, x: T) -> Option<i8> {
        if self.unproven.get() > 0 { None } else { x.proven_sign() }
    }

    fn unproven_then(&self, answer: bool) -> bool {
        self.unproven.set(self.unproven.get() + 1);
        answer
    }

    /// How many decisions so far were taken by value.
    pub fn unproven(&self) -> usize {
        self.unproven.get()
    }
}

/// 1 − cos and 1 + cos of the angle opposite side `t` in a triangle with
/// sides `a`, `b`, `t`, each as a product of differences. `None` when the
/// triangle cannot close (beyond a few ulps, which are clamped to flat,
/// where the sign is not proven).
fn one_minus_plus_cos<T: Real>(a: T, b: T, t: T, decide: &Decisions) -> Option<(T, T)> {
    if !(decide.positive(a) && decide.positive(b)) {
        return None;
    }
    let m = a - b;
    let s = a + b;
    // Each a ratio of lengths times a ratio of lengths: no product of two lengths.
    let two = T::from_f64(2.0);
    let omc = (t - m) / a * ((t + m) / (two * b)); // = 1 − cos
    let opc = (s - t) / a * ((s + t) / (two * b)); // = 1 + cos
    let tol = T::from_f64(crate::tolerance::INVERT_CLAMP_ULPS * T::UNIT_ROUNDOFF);
    if decide.negative(omc, tol) || decide.negative(opc, tol) {
        return None;
    }
    // max(·, 0): f64's own clamp, and an enclosure for balls.
    Some((omc.clamp_nonneg(), opc.clamp_nonneg()))
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
    m * q.clamp_nonneg().sqrt()
}

/// The unsigned angle a hinge or quadrilateral turns through, as its
/// cosine and sine (≥ 0): two branches (±) where the sine is positive, one
/// where it is zero.
#[derive(Clone, Copy, Debug)]
struct Angle<U> {
    cos: U,
    sin: U,
}

impl<U: Real> Angle<U> {
    /// The angle whose 1 − cos and 1 + cos are given.
    fn of((omc, opc): (U, U)) -> Self {
        let one = U::from_f64(1.0);
        Angle { cos: if omc < opc { one - omc } else { opc - one }, sin: (omc * opc).sqrt() }
    }

    /// The branches' signs, `+` first.
    fn signs(self, decide: &Decisions) -> &'static [f64] {
        if decide.positive(self.sin) { &[1.0, -1.0] } else { &[1.0] }
    }
}

/// What a hinge of clusters `tu` and `tw` about `x` fixes once: with p1
/// ∈ tu and q1 ∈ tw (the pair whose distance is given) and p2 ∈ tu, q2 ∈
/// tw (the pair whose distance is sought), the sides |x p1|, |x q1|,
/// |x p2|, |x q2| and the fixed angle Δ = angle(p2 → p1) + angle(q1 → q2).
/// Given |p1 q1| = t, the hinge angle θ1 from p1 to q1 is ±acos C, and θ2
/// from p2 to q2 is θ1 + Δ.
#[derive(Clone, Copy, Debug)]
struct HingeShape<U> {
    a1: U,
    b1: U,
    a2: U,
    b2: U,
    cos_delta: U,
    sin_delta: U,
}

impl<U: Real> HingeShape<U> {
    fn new(c: &Construction<U>, [tu, tw, x]: [usize; 3], [p1, q1]: [usize; 2], [p2, q2]: [usize; 2]) -> Self {
        let (ca, sa) = if p1 == p2 { (U::from_f64(1.0), U::zero()) } else { c.cluster_angle(tu, x, p2, p1) };
        let (cb, sb) = if q1 == q2 { (U::from_f64(1.0), U::zero()) } else { c.cluster_angle(tw, x, q1, q2) };
        HingeShape {
            a1: c.cluster_distance(tu, x, p1),
            b1: c.cluster_distance(tw, x, q1),
            a2: c.cluster_distance(tu, x, p2),
            b2: c.cluster_distance(tw, x, q2),
            cos_delta: ca * cb - sa * sb,
            sin_delta: sa * cb + ca * sb,
        }
    }

    /// |θ1| where |p1 q1| = t (`None`: the hinge cannot reach t).
    fn angle(&self, t: U, decide: &Decisions) -> Option<Angle<U>> {
        one_minus_plus_cos(self.a1, self.b1, t, decide).map(Angle::of)
    }

    /// |p2 q2| on the branch θ1 = `sign`·|θ1|.
    fn side(&self, a: Angle<U>, sign: f64) -> U {
        let sin_t1 = U::from_f64(sign) * a.sin;
        // 1 − cos θ2 with θ2 = θ1 + Δ.
        let one_minus = U::from_f64(1.0) - (a.cos * self.cos_delta - sin_t1 * self.sin_delta);
        side_from_angle(self.a2, self.b2, one_minus)
    }

    /// sin θ2 on the branch θ1 = `sign`·|θ1|.
    fn sine(&self, a: Angle<U>, sign: f64) -> U {
        U::from_f64(sign) * a.sin * self.cos_delta + a.cos * self.sin_delta
    }
}

/// The four-cycle of step j: `pivot` (u_j if `on_u`, else w_j) with
/// clusters (step j's own, `other`), `far` = other ∩ opposite, and step
/// j's other base joint `opp` in `opposite`: the sides |v_j pivot|,
/// |v_j opp|, |pivot far|, |opp far|. Given the diagonal e = |v_j far|,
/// the unsigned angles α1 (pivot, far) and α2 (opp, far) at v_j are fixed;
/// the `+` branch has pivot and opp on one side of v_j → far (α1 − α2
/// between them), the `−` branch one on each (α1 + α2).
#[derive(Clone, Copy, Debug)]
struct QuadShape<U> {
    r_piv: U,
    r_opp: U,
    p: U,
    q: U,
}

impl<U: Real> QuadShape<U> {
    fn new(c: &Construction<U>, j: usize, on_u: bool, [other, opposite, far]: [usize; 3]) -> Self {
        let s = &c.steps[j];
        let (pivot, opp, r_piv, r_opp) = if on_u { (s.u, s.w, s.r1, s.r2) } else { (s.w, s.u, s.r2, s.r1) };
        QuadShape { r_piv, r_opp, p: c.cluster_distance(other, pivot, far), q: c.cluster_distance(opposite, opp, far) }
    }

    /// α1 and α2 where |v_j far| = e, and the branches' signs (two where
    /// both sines are positive).
    fn angles(&self, e: U, decide: &Decisions) -> Option<([Angle<U>; 2], &'static [f64])> {
        let a1 = Angle::of(one_minus_plus_cos(self.r_piv, e, self.p, decide)?);
        let a2 = Angle::of(one_minus_plus_cos(self.r_opp, e, self.q, decide)?);
        let signs: &[f64] = if decide.positive(a1.sin * a2.sin) { &[1.0, -1.0] } else { &[1.0] };
        Some(([a1, a2], signs))
    }

    /// d_j = |u_j w_j| on the branch `sign`: cos(α1 ∓ α2) = c1 c2 ± s1 s2.
    fn side(&self, [a1, a2]: [Angle<U>; 2], sign: f64) -> U {
        let cos_sum = a1.cos * a2.cos + U::from_f64(sign) * a1.sin * a2.sin;
        side_from_angle(self.r_piv, self.r_opp, U::from_f64(1.0) - cos_sum)
    }

    /// sin(±α2 − α1) = ±s2 c1 − c2 s1 on the branch `sign`: the sine of the
    /// angle at v_j from pivot to opp, times the orientation o of
    /// (v_j, far, pivot) (the signed angles from far are o·α1 and ±o·α2).
    fn sine(&self, [a1, a2]: [Angle<U>; 2], sign: f64) -> U {
        U::from_f64(sign) * a2.sin * a1.cos - a2.cos * a1.sin
    }
}

/// How step k's base distance is inverted: through its carrier's hinge
/// to the anchor step j's d_j, directly or through j's four-cycle.
#[derive(Clone, Copy, Debug)]
enum Inversion<U> {
    Step(HingeShape<U>),
    FourCycle(HingeShape<U>, QuadShape<U>),
}

impl<U: Real> Inversion<U> {
    fn new(c: &Construction<U>, dec: &Decomposition, cx: &Complexity, k: usize) -> Option<Self> {
        let step = &dec.steps[k];
        let carrier = cx.carriers[k]?;
        let (tu, tw, x) = (carrier.tu, carrier.tw, carrier.x);
        let pair = [step.u, step.w];
        Some(match carrier.origin {
            PairOrigin::Step(j) => {
                let sj = &dec.steps[j];
                let p2 = if tu == sj.cluster_u { sj.u } else { sj.w };
                let q2 = if tw == sj.cluster_w { sj.w } else { sj.u };
                Inversion::Step(HingeShape::new(c, [tu, tw, x], pair, [p2, q2]))
            }
            PairOrigin::FourCycle { step: j, on_u, other, opposite, far } => {
                let sj = &dec.steps[j];
                let step_cluster = if on_u { sj.cluster_u } else { sj.cluster_w };
                let anchors = if tu == step_cluster { [sj.vertex, far] } else { [far, sj.vertex] };
                Inversion::FourCycle(
                    HingeShape::new(c, [tu, tw, x], pair, anchors),
                    QuadShape::new(c, j, on_u, [other, opposite, far]),
                )
            }
        })
    }
}

/// For step k's carrier, the sign `plus` of a branch's sine where the
/// anchor step j's bit is `+` (`None`: the inversion reads no bit).
/// Through j's two clusters hinged at v_j, the sine is the hinge's sin θ2,
/// θ2 running from p2 to q2 at v_j, from u_j to w_j or back: bit j is `+`
/// exactly where the angle from u_j to w_j has a positive sine (v_j left
/// of u_j → w_j). Through j's four-cycle hinged at its pivot, the sine is
/// the hinge's sign times the quadrilateral's: the hinge's θ2 runs from
/// v_j to far or back, so its sign is the orientation o of (pivot, v_j,
/// far), and the quadrilateral's o·sin is the angle from pivot to opp's.
fn bit_from(dec: &Decomposition, cx: &Complexity, k: usize) -> Option<i8> {
    let carrier = cx.carriers[k]?;
    let (tu, tw, x) = (carrier.tu, carrier.tw, carrier.x);
    match carrier.origin {
        PairOrigin::Step(j) => {
            let sj = &dec.steps[j];
            let forward = tu == sj.cluster_u && tw == sj.cluster_w;
            let backward = tu == sj.cluster_w && tw == sj.cluster_u;
            (x == sj.vertex && (forward || backward)).then_some(if forward { 1 } else { -1 })
        }
        PairOrigin::FourCycle { step: j, on_u, .. } => {
            let sj = &dec.steps[j];
            let (pivot, step_cluster) = if on_u { (sj.u, sj.cluster_u) } else { (sj.w, sj.cluster_w) };
            // The hinge's θ2 runs from v_j to far where tu is step j's own cluster.
            let from_vertex = if tu == step_cluster { 1 } else { -1 };
            let from_u = if on_u { 1 } else { -1 };
            (x == pivot).then_some(from_vertex * from_u)
        }
    }
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

/// The branches a candidate was found on, from step k down to the base:
/// two bits per hinge or quadrilateral (whether it had two branches, and
/// which), the first at the top, so that the paths below a branch are
/// one run when sorted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Path {
    code: u64,
    levels: u32,
}

impl Path {
    const MAX_LEVELS: u32 = 32;

    /// This path, then branch `i` of `count`; `None` past [`Self::MAX_LEVELS`].
    fn then(self, count: usize, i: usize) -> Option<Path> {
        (self.levels < Self::MAX_LEVELS).then(|| {
            let bits = u64::from(count == 2) << 1 | i as u64;
            Path { code: self.code | bits << (2 * (Self::MAX_LEVELS - 1 - self.levels)), levels: self.levels + 1 }
        })
    }

    /// The run of `sorted` (by code) below this path.
    fn range_in(self, sorted: &[(Path, usize)]) -> std::ops::Range<usize> {
        let low_bits = 2 * (Self::MAX_LEVELS - self.levels);
        let mask = if low_bits == 64 { 0 } else { u64::MAX << low_bits };
        let key = |p: &Path| p.code & mask;
        sorted.partition_point(|(p, _)| key(p) < self.code)..sorted.partition_point(|(p, _)| key(p) <= self.code)
    }
}

/// How one step's base distance is inverted.
#[derive(Clone, Copy, Debug)]
struct Shape<T> {
    /// The carrier's anchor step.
    anchor: usize,
    inversion: Inversion<T>,
    /// The sign of a branch's sine where the anchor's bit is `+` (see
    /// [`bit_from`]; `None`: the inversion reads no bit).
    plus: Option<i8>,
    /// Whether this inversion or one below it reads a bit (else balls are not worth following).
    learns: bool,
}

/// Candidate λ values for "step k flat with d_k = t".
pub struct Inverter<'a, T: Real> {
    con: &'a Construction<T>,
    dec: &'a Decomposition,
    cx: &'a Complexity,
    /// The same construction in f64 balls from the lengths as written,
    /// where given: they prove which type bits each candidate's roots have.
    balls: Option<&'a Construction<Ball<f64>>>,
    /// Per step, on first use: how its base distance is inverted (`None`:
    /// on the base, or no carrier).
    shapes: Vec<OnceCell<Option<Shape<T>>>>,
    /// Per step, on first use: the hinge's sides |x u_k|, |x w_k|, which
    /// decide whether it reaches a target at all (before the rest of its
    /// shape is worth computing).
    reaches: Vec<OnceCell<Option<[T; 2]>>>,
    /// The λ where every step on the base closes: a candidate outside is
    /// inside no piece a sweep refines by all of them, so its bits are not
    /// worth proving.
    closing: [T; 2],
    /// Per step, on first use: the inversion in balls (empty without balls).
    ball_shapes: Vec<OnceCell<Option<Inversion<Ball<f64>>>>>,
    decide: Decisions,
}

impl<'a, T: Real> Inverter<'a, T> {
    /// The inversions of `con`'s steps along `cx`'s carriers, with `balls`
    /// (the same construction in f64 balls) where the type bits of each
    /// candidate's roots are wanted.
    pub fn new(
        con: &'a Construction<T>,
        dec: &'a Decomposition,
        cx: &'a Complexity,
        balls: Option<&'a Construction<Ball<f64>>>,
    ) -> Self {
        // No room where no step is inverted (every step on the base, or without a carrier).
        let n =
            if (0..con.steps.len()).any(|k| !con.on_base(k) && cx.carriers[k].is_some()) { con.steps.len() } else { 0 };
        let ball_shapes = if balls.is_some() { (0..n).map(|_| OnceCell::new()).collect() } else { Vec::new() };
        let (shapes, reaches) = ((0..n).map(|_| OnceCell::new()).collect(), (0..n).map(|_| OnceCell::new()).collect());
        let on_base = con.steps.iter().enumerate().filter(|&(k, _)| con.on_base(k)).map(|(_, s)| s);
        let closing = on_base
            .fold(None, |range: Option<[T; 2]>, s| {
                let (below, above) = ((s.r1 - s.r2).abs(), s.r1 + s.r2);
                Some(range.map_or([below, above], |[lo, hi]| {
                    [if below > lo { below } else { lo }, if above < hi { above } else { hi }]
                }))
            })
            .unwrap_or([T::zero(), T::zero()]);
        Inverter { con, dec, cx, balls, shapes, reaches, closing, ball_shapes, decide: Decisions::default() }
    }

    fn shape(&self, k: usize) -> Option<Shape<T>> {
        if self.con.on_base(k) {
            return None;
        }
        *self.shapes.get(k)?.get_or_init(|| {
            let anchor = match self.cx.carriers[k]?.origin {
                PairOrigin::Step(j) | PairOrigin::FourCycle { step: j, .. } => j,
            };
            let inversion = Inversion::new(self.con, self.dec, self.cx, k)?;
            let plus = bit_from(self.dec, self.cx, k);
            let learns = plus.is_some() || self.shape(anchor).is_some_and(|s| s.learns);
            Some(Shape { anchor, inversion, plus, learns })
        })
    }

    /// Whether step k's hinge can reach d_k = t (see [`HingeShape::angle`]).
    fn reaches(&self, k: usize, t: T) -> bool {
        let sides = self.reaches.get(k).and_then(|cell| {
            *cell.get_or_init(|| {
                let (c, step) = (self.cx.carriers[k]?, &self.dec.steps[k]);
                Some([self.con.cluster_distance(c.tu, c.x, step.u), self.con.cluster_distance(c.tw, c.x, step.w)])
            })
        });
        sides.is_some_and(|[a1, b1]| one_minus_plus_cos(a1, b1, t, &self.decide).is_some())
    }

    fn ball_shape(&self, k: usize) -> Option<Inversion<Ball<f64>>> {
        *self.ball_shapes.get(k)?.get_or_init(|| Inversion::new(self.balls?, self.dec, self.cx, k))
    }

    /// Every λ > 0 at which some realization has d_k = t (a superset: the
    /// caller checks each against the prefix it cares about). Sorted, exact
    /// duplicates removed.
    pub fn candidates(&self, k: usize, t: T) -> Vec<T> {
        self.candidates_known(k, t, None).into_iter().map(|c| c.lambda).collect()
    }

    /// [`Self::candidates`], each with the type bits its roots have, where
    /// the balls prove them from `t_ball` (an enclosure of `t`).
    ///
    /// Each hinge and quadrilateral back towards the base has up to two
    /// branches; at a root, every realization follows one branch at each,
    /// and the balls along that path enclose its values. Where a branch
    /// fixes the side of an anchor step's vertex (see [`bit_from`]) with a
    /// sine whose ball excludes zero, every realization with a root on that
    /// path has that bit. Where the sine's ball holds zero (the step near
    /// flat) nothing is known there; where the branches in balls and in `T`
    /// differ in number, nothing below. A candidate that stands for several
    /// (within [`crate::tolerance::SAME_CANDIDATE_ULPS`]) is left without
    /// bits: its paths would have to agree (they seldom do, and following
    /// them costs as much as the bits save).
    pub fn candidates_known(&self, k: usize, t: T, t_ball: Option<Ball<f64>>) -> Vec<Candidate<T>> {
        if self.con.on_base(k) {
            return if t > T::zero() { vec![Candidate::unknown(t)] } else { Vec::new() };
        }
        let mut found = self.found_on_paths(k, t);
        found.sort_by(|a, b| a.0.partial_cmp(&b.0).unwrap_or(std::cmp::Ordering::Equal));
        let same = T::from_f64(crate::tolerance::SAME_CANDIDATE_ULPS * T::UNIT_ROUNDOFF);
        // The candidates, and each one found on one path alone with that path.
        let mut out: Vec<Candidate<T>> = Vec::with_capacity(found.len());
        let mut alone: Vec<(Path, usize)> = Vec::new();
        for (lambda, path) in found {
            match out.last() {
                Some(c) if (lambda - c.lambda).abs() <= same * c.lambda.abs() => {
                    if alone.last().is_some_and(|&(_, i)| i + 1 == out.len()) {
                        alone.pop();
                    }
                }
                _ => {
                    let [lo, hi] = self.closing;
                    alone.extend(path.filter(|_| lambda >= lo && lambda <= hi).map(|p| (p, out.len())));
                    out.push(Candidate::unknown(lambda));
                }
            }
        }
        if let Some(t_ball) = t_ball.filter(|_| self.balls.is_some() && !alone.is_empty()) {
            alone.sort_by_key(|(p, _)| p.code);
            self.learn(k, Some(t_ball), Path::default(), KnownBits::default(), &alone, &mut out);
        }
        out
    }

    /// Every λ > 0 the inversion of d_k = t reaches, unsorted, one per
    /// path (a candidate reached on two paths is there twice).
    pub fn found(&self, k: usize, t: T) -> Vec<T> {
        if self.con.on_base(k) {
            return if self.decide.positive(t) { vec![t] } else { Vec::new() };
        }
        self.found_on_paths(k, t).into_iter().map(|(lambda, _)| lambda).collect()
    }

    fn found_on_paths(&self, k: usize, t: T) -> Vec<(T, Option<Path>)> {
        let mut found = Vec::new();
        self.descend(k, t, Some(Path::default()), &mut found);
        found.retain(|(lambda, _)| self.decide.positive(*lambda));
        found
    }

    /// The candidates for d_k = t below step k, each with its path (`None`
    /// past [`Path::MAX_LEVELS`]).
    fn descend(&self, k: usize, t: T, path: Option<Path>, out: &mut Vec<(T, Option<Path>)>) {
        if self.con.on_base(k) {
            out.push((t, path));
            return;
        }
        if !self.reaches(k, t) {
            return;
        }
        let Some(Shape { anchor: j, inversion, .. }) = self.shape(k) else { return };
        let next = |path: Option<Path>, signs: &[f64], i: usize| path.and_then(|p| p.then(signs.len(), i));
        match inversion {
            Inversion::Step(hinge) => {
                let Some(angle) = hinge.angle(t, &self.decide) else { return };
                for (i, &sign) in angle.signs(&self.decide).iter().enumerate() {
                    let dj = hinge.side(angle, sign);
                    if self.step_can_close(j, dj) {
                        self.descend(j, dj, next(path, angle.signs(&self.decide), i), out);
                    }
                }
            }
            Inversion::FourCycle(hinge, quad) => {
                let Some(angle) = hinge.angle(t, &self.decide) else { return };
                for (i, &sign) in angle.signs(&self.decide).iter().enumerate() {
                    let Some((angles, signs)) = quad.angles(hinge.side(angle, sign), &self.decide) else { continue };
                    let path = next(path, angle.signs(&self.decide), i);
                    for (qi, &quad_sign) in signs.iter().enumerate() {
                        let dj = quad.side(angles, quad_sign);
                        if self.step_can_close(j, dj) {
                            self.descend(j, dj, next(path, signs, qi), out);
                        }
                    }
                }
            }
        }
    }

    /// [`Self::descend`] again in balls, only along the paths of `alone`
    /// (sorted, each with its place in `out`; all below `path`): the bits
    /// each path's sines prove, set on its candidate.
    fn learn(
        &self,
        k: usize,
        t: Option<Ball<f64>>,
        path: Path,
        known: KnownBits,
        alone: &[(Path, usize)],
        out: &mut [Candidate<T>],
    ) {
        if self.con.on_base(k) {
            for &(_, i) in alone.iter().filter(|(p, _)| *p == path) {
                out[i].known = known;
            }
            return;
        }
        let (Some(Shape { anchor: j, plus, learns, .. }), Some(t)) = (self.shape(k), t) else { return };
        let Some(inversion) = self.ball_shape(k).filter(|_| learns) else { return };
        // The paths through branch i of `signs` below `path` (none where the
        // balls have another number of branches than `T` had).
        let through = |path: Path, signs: &[f64], i: usize| {
            let p = path.then(signs.len(), i)?;
            let range = p.range_in(alone);
            (!range.is_empty()).then(|| (p, &alone[range]))
        };
        // Below a step on the base no distance is inverted: its ball is not needed.
        let deeper = !self.con.on_base(j);
        let learned = |known: KnownBits, sign: Option<i8>, plus: Option<i8>| match (sign, plus) {
            (Some(s), Some(plus)) => known.with(j, s == plus),
            _ => known,
        };
        match inversion {
            Inversion::Step(hinge) => {
                let Some(angle) = hinge.angle(t, &self.decide) else { return };
                for (i, &sign) in angle.signs(&self.decide).iter().enumerate() {
                    let Some((p, below)) = through(path, angle.signs(&self.decide), i) else { continue };
                    let known = learned(known, hinge.sine(angle, sign).sign(), plus);
                    let dj = deeper.then(|| hinge.side(angle, sign));
                    self.learn(j, dj, p, known, below, out);
                }
            }
            Inversion::FourCycle(hinge, quad) => {
                let Some(angle) = hinge.angle(t, &self.decide) else { return };
                for (i, &sign) in angle.signs(&self.decide).iter().enumerate() {
                    let Some((p, _)) = through(path, angle.signs(&self.decide), i) else { continue };
                    let Some((angles, signs)) = quad.angles(hinge.side(angle, sign), &self.decide) else { continue };
                    // The hinge's sine: the orientation o of (pivot, v_j, far), or its opposite.
                    let orientation = hinge.sine(angle, sign).sign();
                    for (qi, &quad_sign) in signs.iter().enumerate() {
                        let Some((p, below)) = through(p, signs, qi) else { continue };
                        let sine = orientation.zip(quad.sine(angles, quad_sign).sign()).map(|(o, s)| o * s);
                        let dj = deeper.then(|| quad.side(angles, quad_sign));
                        self.learn(j, dj, p, learned(known, sine, plus), below, out);
                    }
                }
            }
        }
    }

    fn step_can_close(&self, j: usize, d: T) -> bool {
        let s = &self.con.steps[j];
        let tol = T::from_f64(crate::tolerance::FEASIBLE * self.con.scale);
        !self.decide.negative(d - (s.r1 - s.r2).abs(), tol) && !self.decide.negative(s.r1 + s.r2 - d, tol)
    }

    /// The branch decisions so far (see [`Decisions`]).
    pub fn decisions(&self) -> &Decisions {
        &self.decide
    }
}
