//! Proven enclosures of the complete Cayley distance vector over pieces of a
//! component (THEORY.md §4–§5), for the certified closest pair.
//!
//! Near an interval end λ* where step k is flat, joints move like √|λ − λ*|,
//! so the Cayley vector is not Lipschitz in λ. Each segment is therefore cut
//! into two **halves**, each parametrized from its end by
//!
//! ```text
//!     λ = λ* + dir·t²,   t ∈ [0, t_max]      (dir points into the segment)
//! ```
//!
//! in which the motion is smooth through the end (the flat step's height is
//! t times a smooth positive function). Over a box of t the ruler-and-compass
//! construction is evaluated in interval arithmetic with outward rounding
//! ([`crate::interval`]), carrying the first and second derivatives in t, at
//! the box's centre and over the box, every intermediate quantity tightened
//! by its Taylor forms ([`Centred`]): every value and derivative at every
//! exact point of the box lies in the result.
//!
//! The flat step's height needs care, since √S (S its slack) has derivative
//! S'/(2√S), unbounded at the end. With S(λ*) = 0 the mean value theorem gives
//! S(λ) = S'(ξ)·dir·t² for some ξ between λ* and λ, so √S = t·√a with
//! a = S'(ξ)·dir, and d√S/dt = S'(λ)·dir/√a: both bounded once S'·dir > 0 is
//! proven over the λ range (the second derivative: `root_near_end`). This
//! needs λ* itself, which is only known as an f64: each end is **verified**
//! by finding an interval Λ with the flat step's slack proven positive at its
//! inner bound, negative at its outer one and strictly monotone over it (so
//! λ* ∈ Λ, unique). The boxes then use λ ∈ Λ + dir·t².
//!
//! The numbers of the construction (`r1`, `r2`, member coordinates, all f64)
//! are taken as exact: the proof is about the linkage they describe. The
//! oriented intervals themselves (which type exists between which ends) are
//! the analysis's; only their ends are verified here.

use crate::cayley_space::CayleySpace;
use crate::interval::{Arith, Centred, Dual, Interval, Offset};
use crate::motion::Segment;
use crate::realize::{Construction, Kind};
use crate::tolerance;

/// Half of a segment, parametrized from one of its ends by λ = λ* + dir·t².
#[derive(Clone, Debug)]
pub struct Half {
    /// Index of the segment in the component's list.
    pub segment: usize,
    /// The segment's realization type.
    pub bits: Vec<bool>,
    /// The end's λ as the analysis computed it.
    pub end: f64,
    /// +1 or −1: from the end into the segment.
    pub dir: f64,
    /// Proven enclosure of the exact end λ* (verified ends), else `[end, end]`.
    pub anchor: Interval,
    /// The end was verified (see the module doc); `flat` is then set.
    pub verified: bool,
    /// The step flat at the end and how, for the √ form of its height.
    pub flat: Option<(usize, Kind)>,
    /// The steps flat at this end (to name the end's realization exactly flat).
    pub flat_steps: Vec<usize>,
    /// t ∈ [0, t_max] covers the half up to the segment's midpoint.
    pub t_max: f64,
    /// Every t ∈ [0, t_safe] is a point of the segment (an exact realization):
    /// only those may give upper bounds.
    pub t_safe: f64,
}

impl Half {
    /// λ at `t` as an f64 (the name of the realization there).
    pub fn lambda(&self, t: f64, seg: &Segment) -> f64 {
        if t == 0.0 {
            return self.end;
        }
        let l = self.end + self.dir * t * t;
        l.clamp(seg.from.min(seg.to), seg.from.max(seg.to))
    }

    /// Enclosure of λ over the box `t`.
    fn lambda_over(&self, t: Interval) -> Interval {
        self.anchor + Interval::point(self.dir) * t.sqr()
    }
}

/// The other way of being flat.
fn other(kind: Kind) -> Kind {
    match kind {
        Kind::Stretched => Kind::Folded,
        Kind::Folded => Kind::Stretched,
    }
}

fn c<J: Arith>(x: f64) -> J {
    J::constant(Interval::point(x))
}

/// r1 + r2 and |r1 − r2| of step `k`, enclosed.
fn sides(con: &Construction<f64>, k: usize) -> (Interval, Interval) {
    let s = &con.steps[k];
    let (r1, r2) = (Interval::point(s.r1), Interval::point(s.r2));
    (r1 + r2, (r1 - r2).abs())
}

/// Slack of a step for `kind` at base distance `d`: positive where that side closes.
fn slack<J: Arith>(kind: Kind, (sum, diff): (Interval, Interval), d: J) -> J {
    match kind {
        Kind::Stretched => J::constant(sum) - d,
        Kind::Folded => d - J::constant(diff),
    }
}

/// Base vector u→w of step `k` and its length.
fn frame<J: Arith>(con: &Construction<f64>, k: usize, pos: &[[J; 2]]) -> ([J; 2], J) {
    let s = &con.steps[k];
    let e = [pos[s.w][0] - pos[s.u][0], pos[s.w][1] - pos[s.u][1]];
    (e, J::hypot(e[0], e[1]))
}

/// Place step `k`'s vertex at height `h` (≥ 0) on the side `plus`, then the
/// other joints of both clusters, exactly as `Construction::realize` does.
fn place<J: Arith>(con: &Construction<f64>, k: usize, pos: &mut [[J; 2]], plus: bool, (e, d): ([J; 2], J), h: J) {
    let s = &con.steps[k];
    let (r1, r2) = (c::<J>(s.r1), c::<J>(s.r2));
    let along = (d + (r1 - r2) * (r1 + r2) / d) * c(0.5);
    let (ex, ey) = (e[0] / d, e[1] / d);
    let h = if plus { h } else { -h };
    let pu = pos[s.u];
    let v = [pu[0] + along * ex - h * ey, pu[1] + along * ey + h * ex];
    pos[s.vertex] = v;
    for (pivot, list) in [(s.u, &s.members_u), (s.w, &s.members_w)] {
        let p = pos[pivot];
        let e = [v[0] - p[0], v[1] - p[1]];
        for m in list {
            let (a, b) = (c::<J>(m.alpha), c::<J>(m.beta));
            pos[m.joint] = [p[0] + a * e[0] - b * e[1], p[1] + a * e[1] + b * e[0]];
        }
    }
}

/// Steps in `range` placed the ordinary way (height √h², the cancellation-free
/// product of THEORY.md §1). Returns whether every one of them is proven
/// strictly feasible (no slack clamped, base distance positive).
fn ordinary_steps<J: Arith>(
    con: &Construction<f64>,
    bits: &[bool],
    pos: &mut [[J; 2]],
    range: std::ops::Range<usize>,
) -> bool {
    let mut strict = true;
    for k in range {
        let (e, d) = frame(con, k, pos);
        let (sum, diff) = sides(con, k);
        let (stretch, fold) = (slack(Kind::Stretched, (sum, diff), d), slack(Kind::Folded, (sum, diff), d));
        strict &= stretch.value().lo > 0.0 && fold.value().lo > 0.0 && d.value().lo > 0.0;
        let h2 = (J::constant(sum) + d) * stretch.clamp_nonneg() * fold.clamp_nonneg() * (d + J::constant(diff))
            / (c::<J>(4.0) * d.sqr());
        place(con, k, pos, bits[k], (e, d), h2.sqrt());
    }
    strict
}

/// Positions with base length `lam` through the first `upto` steps.
fn prefix<J: Arith>(con: &Construction<f64>, bits: &[bool], lam: J, upto: usize) -> (Vec<[J; 2]>, bool) {
    let zero = c::<J>(0.0);
    let mut pos = vec![[zero, zero]; con.n_joints];
    pos[con.base[1]] = [lam, zero];
    let strict = ordinary_steps(con, bits, &mut pos, 0..upto);
    (pos, strict)
}

/// Slack of step `k` (as `kind`) over λ ∈ `lam`, with its λ-derivatives, and
/// whether every earlier step is proven strictly feasible there.
fn slack_over(con: &Construction<f64>, bits: &[bool], (k, kind): (usize, Kind), lam: Interval) -> (Dual, bool) {
    let (pos, strict) = prefix(con, bits, Dual::variable(lam), k);
    let (_, d) = frame(con, k, &pos);
    (slack(kind, sides(con, k), d), strict && d.v.lo > 0.0)
}

/// A proven enclosure of the exact root of step `k`'s slack near `end`
/// (see the module doc), narrowed by bisection; `None` when none is found
/// within [`tolerance::END_BRACKET_MAX`] × scale (an end placed worse, or
/// where several steps are flat at once, stays unverified, and the closest
/// pair is then not certified).
fn verify_end(con: &Construction<f64>, bits: &[bool], flat: (usize, Kind), end: f64, dir: f64) -> Option<Interval> {
    let s_at = |l: f64| slack_over(con, bits, flat, Interval::point(l)).0.v;
    // At least the smallest subnormal: at scales near 1e-320 the product
    // underflows to 0, and a zero margin would never grow.
    let mut m =
        (tolerance::LAMBDA_RESOLUTION_ULPS * (f64::EPSILON / 2.0) * end.abs().max(con.scale)).max(f64::from_bits(1));
    while m <= tolerance::END_BRACKET_MAX * con.scale {
        let (mut inner, mut outer) = (end + dir * m, end - dir * m);
        let (s, strict) = slack_over(con, bits, flat, Interval::new(inner.min(outer), inner.max(outer)));
        if strict && (s.d * Interval::point(dir)).lo > 0.0 && s_at(inner).lo > 0.0 && s_at(outer).hi < 0.0 {
            // Monotone with a sign change: exactly one root in between. Narrow it.
            for _ in 0..64 {
                let mid = inner + (outer - inner) / 2.0;
                if mid == inner || mid == outer {
                    break;
                }
                let sm = s_at(mid);
                if sm.lo > 0.0 {
                    inner = mid;
                } else if sm.hi < 0.0 {
                    outer = mid;
                } else {
                    break;
                }
            }
            return Some(Interval::new(inner.min(outer), inner.max(outer)));
        }
        m *= tolerance::ENCLOSURE_BRACKET_GROWTH;
    }
    None
}

/// The two halves of every segment of a component.
pub fn halves(con: &Construction<f64>, space: &CayleySpace<f64>, segments: &[Segment]) -> Vec<Half> {
    let mut out = Vec::with_capacity(2 * segments.len());
    for (i, seg) in segments.iter().enumerate() {
        let iv = &space.intervals[seg.interval];
        let mid = seg.from + (seg.to - seg.from) / 2.0;
        for (end, other_end, flat_steps) in [(seg.from, seg.to, &seg.flat_from), (seg.to, seg.from, &seg.flat_to)] {
            let dir = if other_end >= end { 1.0 } else { -1.0 };
            let events = if end == iv.lower.lambda { &iv.lower.events } else { &iv.upper.events };
            let flat = match (flat_steps.as_slice(), &events[..]) {
                ([k], [e]) if e.step == *k => Some((*k, e.kind)),
                _ => None,
            };
            let verified = flat.and_then(|f| verify_end(con, &seg.ty.0, f, end, dir));
            let anchor = verified.unwrap_or(Interval::point(end));
            let span = (Interval::point(mid) - anchor) * Interval::point(dir);
            let t_max = span.hi.max(0.0).sqrt().next_up();
            let t_safe = if span.lo > 0.0 { span.lo.sqrt().next_down() } else { 0.0 };
            out.push(Half {
                segment: i,
                bits: seg.ty.0.clone(),
                end,
                dir,
                anchor,
                verified: verified.is_some(),
                flat: if verified.is_some() { flat } else { None },
                flat_steps: flat_steps.clone(),
                t_max,
                t_safe: t_safe.min(t_max),
            });
        }
    }
    out
}

/// The complete Cayley distance vector over the box `t` of a half (t ⊆
/// [0, t_max]): values and first and second derivatives in t, at the box's
/// centre `t.mid()` and over the box ([`Centred`]), enclosed at every exact point.
pub fn enclose(con: &Construction<f64>, ccv: &[[usize; 2]], half: &Half, t: Interval) -> Vec<Centred> {
    let tc = Interval::point(t.mid());
    let dir = Interval::point(half.dir);
    let two = Interval::point(2.0);
    let n = con.steps.len();
    // λ = λ* + dir·t²: dλ/dt = 2·dir·t, d²λ/dt² = 2·dir; λ − λ(centre) = dir·(t − c)(t + c).
    let lambda = Centred {
        c: Dual::variable(half.lambda_over(tc)),
        b: Dual::variable(half.lambda_over(t)),
        s: Offset::new(dir * (t - tc) * (t + tc)),
    };
    let offset = Offset::new(t - tc);
    let to_t = |pos: &mut Vec<[Centred; 2]>| {
        for p in pos.iter_mut().flatten() {
            let c = p.c.chain(two * dir * tc, two * dir);
            *p = Centred::new(c, p.b.chain(two * dir * t, two * dir), offset);
        }
    };
    let (mut pos, from) = match half.flat {
        None => {
            let (mut pos, _) = prefix(con, &half.bits, lambda, n);
            to_t(&mut pos);
            (pos, n)
        }
        Some((k, kind)) => {
            let (mut pos, _) = prefix(con, &half.bits, lambda, k);
            let sides = sides(con, k);
            let s_l = slack(kind, sides, frame(con, k, &pos).1); // S with its λ-derivatives
            to_t(&mut pos);
            let (e, d) = frame(con, k, &pos);
            let mut root = slack(kind, sides, d).clamp_nonneg().sqrt(); // √S the direct way
            // Near the end the direct way is loose: its derivatives blow up, and
            // S is small against the width of its own enclosure (which the
            // anchor's width dominates). Either way is sound; this only saves
            // work away from the end.
            if t.lo < tolerance::NEAR_END_FRACTION * t.hi || root.c.v.width() > tolerance::LOOSE_ENCLOSURE * root.c.v.lo
            {
                let hull = if t.lo == 0.0 {
                    s_l.b
                } else {
                    slack_over(con, &half.bits, (k, kind), half.lambda_over(Interval::new(0.0, t.hi))).0
                };
                let near =
                    Centred::new(root_near_end(half, tc, s_l.c, hull), root_near_end(half, t, s_l.b, hull), root.s);
                root = root.intersect(near);
            }
            let rest = slack(other(kind), sides, d).clamp_nonneg();
            let p = (Centred::constant(sides.0) + d) * rest * (d + Centred::constant(sides.1))
                / (c::<Centred>(4.0) * d.sqr());
            place(con, k, &mut pos, half.bits[k], (e, d), p.sqrt() * root);
            (pos, k + 1)
        }
    };
    ordinary_steps(con, &half.bits, &mut pos, from..n);
    ccv.iter().map(|&[p, q]| Centred::hypot(pos[q][0] - pos[p][0], pos[q][1] - pos[p][1])).collect()
}

/// σ = √S of the flat step over `t` by the √ form (module doc), with
/// b = S/t² = dir·S'(ξ) ∈ B := dir·S'(hull of λ* and the box):
///
/// ```text
///     σ   = t·√b
///     σ'  = dir·S'(λ)/√b
///     σ'' = 2t·S''(λ)/√b − dir·S'(λ)·θ·t·S''(η)/b^{3/2},   θ ∈ [0, 1], η in the hull
/// ```
///
/// (from b' = 2(dir·S'(λ) − b)/t = 2θt·S''(η)). `s_l` is S with its
/// λ-derivatives over `t`, `hull` the same over [0, t.hi]. Unbounded when B
/// is not proven positive.
fn root_near_end(half: &Half, t: Interval, s_l: Dual, hull: Dual) -> Dual {
    let dir = Interval::point(half.dir);
    let b = hull.d * dir;
    if b.lo <= 0.0 {
        return Dual { v: Interval::ENTIRE, d: Interval::ENTIRE, dd: Interval::ENTIRE };
    }
    let rb = b.sqrt();
    let theta = Interval::new(0.0, 1.0);
    let dd = Interval::point(2.0) * t * s_l.dd / rb - dir * s_l.d * theta * t * hull.dd / (b * rb);
    Dual { v: t * rb, d: s_l.d * dir / rb, dd }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The √ form against a closed form: S(λ) = λ + λ² with λ* = 0, λ = t²
    /// gives σ = t√(1 + t²), σ' = (1 + 2t²)/√(1 + t²), σ'' = (2t³ + 3t)/(1 + t²)^{3/2}.
    #[test]
    fn root_near_end_encloses_the_closed_form() {
        let half = Half {
            segment: 0,
            bits: vec![],
            end: 0.0,
            dir: 1.0,
            anchor: Interval::ZERO,
            verified: true,
            flat: None,
            flat_steps: vec![],
            t_max: 2.0,
            t_safe: 2.0,
        };
        let s_over = |t: Interval| {
            let l = Dual::variable(t.sqr());
            l + l.sqr()
        };
        for (lo, hi) in [(0.0, 0.1), (0.0, 1.0), (0.2, 1.0), (0.5, 0.6), (1.5, 2.0), (0.3, 0.3)] {
            let t = Interval::new(lo, hi);
            let r = root_near_end(&half, t, s_over(t), s_over(Interval::new(0.0, hi)));
            for k in 0..=10 {
                let x = lo + (hi - lo) * k as f64 / 10.0;
                let w = (1.0 + x * x).sqrt();
                let holds = |i: Interval, y: f64| i.lo <= y && y <= i.hi;
                assert!(holds(r.v, x * w), "σ at {x}: {:?}", r.v);
                assert!(holds(r.d, (1.0 + 2.0 * x * x) / w), "σ' at {x}: {:?}", r.d);
                assert!(holds(r.dd, (2.0 * x * x * x + 3.0 * x) / (w * w * w)), "σ'' at {x}: {:?}", r.dd);
            }
        }
    }
}
