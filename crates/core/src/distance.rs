//! The closest pair of realizations between two components by Cayley
//! distance (THEORY.md §5), certified by branch and bound.
//!
//! Each component is cut into halves of segments, enclosed with proofs by
//! [`crate::enclosure`]. Boxes (a piece of one component × a piece of the
//! other) get proven lower bounds and are split lowest bound first; the best
//! pair found bounds the minimum from above (every pair of interval ends is a
//! candidate, then the boxes' centres, polished by Gauss–Newton steps). The
//! search stops when upper − lower ≤ gap × upper (certified), when f64 cannot
//! resolve that gap at the best pair (curves that meet), or at a budget of
//! boxes; the [`Certificate`] says which, as data.

use std::cmp::Ordering;
use std::collections::{BinaryHeap, HashMap};
use std::rc::Rc;

use crate::cayley_space::CayleySpace;
use crate::cayley_vector::{Mirrors, cayley_vector, euclid, mirror_type};
use crate::enclosure::{Half, enclose, halves};
use crate::interval::{Centred, Dual, Interval};
use crate::motion::{Component, Segment, component_segments};
use crate::realize::{Construction, Realization, RealizationType, points};
use crate::tolerance;

/// Point enclosures spent at most on polishing the best pair (a few ms on
/// a scene of up to 100 steps; each costs its steps, so deeper scenes get
/// [`POLISH_STEPS`] / steps of them).
const POLISH_BUDGET: usize = 400;

/// The polish's work budget in point enclosures × construction steps.
const POLISH_STEPS: usize = 40_000;

/// Default work budget of the closest-pair search, in boxes evaluated: about
/// 15 µs each on a scene of a few dozen steps (a bound, and at most one new
/// piece of a component enclosed), so at most a few seconds and tens of MB.
/// Deeper scenes get fewer ([`tolerance::CLOSEST_BOX_STEPS`]).
pub const DEFAULT_MAX_BOXES: usize = 100_000;

/// A component parametrized by arc length in λ, s ∈ [0, total): the Cayley
/// vector is continuous in s across interval ends, so a minimizer can move
/// from one oriented interval into the next.
pub struct Arc {
    segments: Vec<Segment>,
    starts: Vec<f64>,
    /// The component's total arc length in λ (scene units).
    pub total: f64,
}

impl Arc {
    /// Component `c` of `space` as one arc, segment after segment.
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

/// What the closest-pair search is asked for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClosestOptions {
    /// Stop once the proven bounds satisfy upper − lower ≤ gap × upper.
    pub gap: f64,
    /// Evaluate at most this many boxes (and at most
    /// [`tolerance::CLOSEST_BOX_STEPS`] boxes × construction steps).
    pub max_boxes: usize,
}

impl Default for ClosestOptions {
    fn default() -> Self {
        ClosestOptions { gap: tolerance::DEFAULT_GAP, max_boxes: DEFAULT_MAX_BOXES }
    }
}

/// Why the search stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, schemars::JsonSchema))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Outcome {
    /// The components are mirror images of each other: distance exactly 0.
    Mirror,
    /// The components meet at a branch point, where their intervals share
    /// an end by the flip rule and so a realization: distance 0, as sure as
    /// the coincidence of the steps flat there (decided to double-double
    /// resolution, a non-generic place, so not certified).
    Shared,
    /// The requested relative gap was reached (or every box was pruned).
    GapReached,
    /// f64 interval arithmetic cannot resolve the best pair's distance to the
    /// requested gap (the curves meet: distance 0 up to rounding; or the
    /// construction is too deep for its enclosures to stay narrow, even
    /// unbounded: `upper` is then infinite), or the remaining boxes cannot be
    /// split further; the search stopped at the gap it can reach.
    Resolution,
    /// The box budget ran out first.
    Budget,
}

/// The proof behind a closest pair, as data (sentences are made by the caller).
#[derive(Clone, Debug, PartialEq)]
pub struct Certificate {
    /// Proven: every pair of realizations, one in each component, is at
    /// Cayley distance ≥ `lower`.
    pub lower: f64,
    /// Proven: the exact realizations the reported pair names (to f64
    /// precision in λ) are at Cayley distance ≤ `upper`.
    pub upper: f64,
    /// (upper − lower) / upper (0 when upper is 0, 1 when it is infinite).
    pub gap: f64,
    /// The relative gap that was asked for.
    pub requested_gap: f64,
    /// Why the search stopped.
    pub outcome: Outcome,
    /// The gap was reached and every interval end was verified.
    pub certified: bool,
    /// Boxes (pairs of pieces of the two components) evaluated.
    pub boxes: usize,
    /// The box budget the search had.
    pub max_boxes: usize,
    /// Pairs of interval ends compared as candidates.
    pub end_pairs: usize,
    /// Interval ends (per oriented interval) whose exact λ could not be
    /// enclosed (several steps flat at once, or a tangency): the bounds then
    /// hold for the intervals as computed, and nothing is certified.
    pub unverified_ends: usize,
}

/// The closest pair of realizations between two components.
#[derive(Clone, Debug, PartialEq)]
pub struct ClosestPair {
    /// Cayley distance of the pair as computed in f64.
    pub distance: f64,
    /// The realization in the first component.
    pub a: Realization,
    /// The realization in the second component.
    pub b: Realization,
    /// The components are mirror images (distance 0, but different motions).
    pub mirror: bool,
    /// The two Cayley curves meet (distance 0 up to rounding: the best pair's
    /// own distance is not resolved even to a factor 2): different
    /// realizations with the same Cayley vector (possible when the vector is
    /// short; THEORY.md §5 only promises one-to-one within a component).
    pub crossing: bool,
    /// The proven bounds and how the search ended.
    pub certificate: Certificate,
}

/// A piece of one component (a box of t in one half) with its enclosures.
struct Side {
    half: usize,
    t: Interval,
    /// The point where the centred forms are expanded.
    tc: f64,
    /// The Cayley vector and its t-derivative at `tc`.
    at_c: Vec<[Interval; 2]>,
    /// The Cayley vector with its t-derivatives over the box.
    over: Vec<Dual>,
    /// The vector varies over the box by less than its own rounding at the
    /// centre: splitting further cannot sharpen any bound.
    saturated: bool,
}

/// The pieces of one component evaluated so far: a piece is met in many
/// boxes (paired with every piece of the other component), and evaluating it
/// is the expensive part.
struct Pieces<'a> {
    con: &'a Construction<f64>,
    ccv: &'a [[usize; 2]],
    halves: &'a [Half],
    known: HashMap<(usize, u64, u64), Rc<Side>>,
}

impl<'a> Pieces<'a> {
    fn new(con: &'a Construction<f64>, ccv: &'a [[usize; 2]], halves: &'a [Half]) -> Self {
        Pieces { con, ccv, halves, known: HashMap::new() }
    }

    /// One piece per half, over the box `box_of(half)`.
    fn all(&mut self, box_of: impl Fn(&Half) -> Interval) -> Vec<Rc<Side>> {
        (0..self.halves.len()).map(|i| self.get(i, box_of(&self.halves[i]))).collect()
    }

    fn get(&mut self, half: usize, t: Interval) -> Rc<Side> {
        let (con, ccv, h) = (self.con, self.ccv, &self.halves[half]);
        let make = || {
            let v = enclose(con, ccv, h, t);
            let width = |f: fn(&Centred) -> Interval| v.iter().map(|x| f(x).width()).sum::<f64>();
            Rc::new(Side {
                half,
                t,
                tc: t.mid(),
                at_c: v.iter().map(|x| [x.c.v, x.c.d]).collect(),
                over: v.iter().map(|x| x.b).collect(),
                saturated: width(|x| x.b.v) <= tolerance::SATURATION_FACTOR * width(|x| x.c.v),
            })
        };
        self.known.entry((half, t.lo.to_bits(), t.hi.to_bits())).or_insert_with(make).clone()
    }
}

/// Bounds over a box: `lower` on the distance (proven), the squared
/// distance at the centres, and which side to split.
struct Bounds {
    lower: f64,
    centre: Interval,
    split_a: bool,
}

/// Lower bound over the box `a × b`: the best of three proven bounds on
/// F = |V_a − V_b|², with s = t − c the offsets from the centres:
/// - natural: the distance between the two boxes enclosing the Cayley vectors;
/// - mean value: F ∈ F(c) + ∇F(box)·s;
/// - second order: F ∈ F(c) + ∇F(c)·s + ½ sᵀ∇²F(box) s, bounded below by
///   [`quadratic_lower`]. Its error shrinks with the cube of the box, so boxes
///   near a smooth minimum (or along a valley of near-minimal pairs) are
///   pruned without the cluster effect of the cruder bounds.
fn bounds(a: &Side, b: &Side) -> Bounds {
    let two = Interval::point(2.0);
    let z = Interval::ZERO;
    let (mut natural, mut centre, mut da, mut db) = (z, z, z, z);
    let (mut ga, mut gb, mut haa, mut hab, mut hbb) = (z, z, z, z, z);
    for k in 0..a.over.len() {
        let ([ca, cda], [cb, cdb]) = (a.at_c[k], b.at_c[k]);
        let (va, vb) = (&a.over[k], &b.over[k]);
        let g = va.v - vb.v;
        let apart = if g.lo > 0.0 {
            g.lo
        } else if g.hi < 0.0 {
            -g.hi
        } else {
            0.0
        };
        natural = natural + Interval::point(apart).sqr();
        let gc = ca - cb;
        centre = centre + gc.sqr();
        da = da + g * va.d;
        db = db - g * vb.d;
        ga = ga + gc * cda;
        gb = gb - gc * cdb;
        haa = haa + va.d.sqr() + g * va.dd;
        hbb = hbb + vb.d.sqr() - g * vb.dd;
        hab = hab - va.d * vb.d;
    }
    let (da, db) = (two * da, two * db);
    let offset = |s: &Side| if s.t.lo == s.t.hi { Interval::ZERO } else { s.t - Interval::point(s.tc) };
    let (sa, sb) = (offset(a), offset(b));
    let mean_value = centre + da * sa + db * sb;
    let second = quadratic_lower([two * ga, two * gb], [two * haa, two * hab, two * hbb], [sa, sb]);
    let squared = natural.lo.max(mean_value.lo).max((centre.lo + second).next_down()).max(0.0);
    let lower = squared.sqrt().next_down().max(0.0);
    let spread = |d: Interval, s: &Side| if s.t.lo == s.t.hi { 0.0 } else { d.mag() * (s.t.hi - s.t.lo) };
    let (wa, wb) = (spread(da, a), spread(db, b));
    let split_a = if wa.is_finite() || wb.is_finite() {
        wa >= wb
    } else {
        let width = |s: &Side| s.over.iter().map(|x| x.v.width()).sum::<f64>();
        width(a) >= width(b)
    };
    Bounds { lower, centre, split_a }
}

/// A proven lower bound of q(s) = g·s + ½(h_aa s_a² + 2 h_ab s_a s_b + h_bb s_b²)
/// over s ∈ `s[0]` × `s[1]`, for every g, h in the given intervals
/// (`h` = [h_aa, h_ab, h_bb]); −∞ when something is unbounded.
///
/// The coefficients are split into f64 midpoints and radii; the radii give
/// an error term. With the midpoints: if h_aa, h_bb ≥ 0 the form is made
/// convex by moving just enough of h_ab into the error term, the box
/// minimizer s₀ is found (stationary point or an edge's minimizer) and
/// q(s) ≥ q(s₀) + ∇q(s₀)·(s − s₀) is bounded (convexity). Otherwise q is
/// concave along an axis and its minimum lies on the two edges across it.
fn quadratic_lower(g: [Interval; 2], h: [Interval; 3], s: [Interval; 2]) -> f64 {
    if g.iter().chain(&h).chain(&s).any(|x| !x.is_bounded()) {
        return f64::NEG_INFINITY;
    }
    let p = Interval::point;
    let (ga, gb) = (g[0].mid(), g[1].mid());
    let (haa, hbb) = (h[0].mid(), h[2].mid());
    let mut hab = h[1].mid();
    let convex = haa >= 0.0 && hbb >= 0.0;
    if convex {
        // |h_ab| ≤ √(h_aa h_bb)(1 − margin) keeps the determinant provably ≥ 0.
        let cap = ((p(haa) * p(hbb)).lo.sqrt() * (1.0 - tolerance::CONVEX_CAP_MARGIN)).next_down().max(0.0);
        hab = hab.clamp(-cap, cap);
    }
    let radius = |x: Interval, m: f64| (x - p(m)).mag();
    let (ma, mb) = (p(s[0].mag()), p(s[1].mag()));
    let error = p(radius(g[0], ga)) * ma
        + p(radius(g[1], gb)) * mb
        + p(0.5)
            * (p(radius(h[0], haa)) * ma.sqr()
                + p(2.0) * p(radius(h[1], hab)) * ma * mb
                + p(radius(h[2], hbb)) * mb.sqr());
    // q with the midpoint coefficients, at a point, enclosed.
    let q = |x: f64, y: f64| {
        let (x, y) = (p(x), p(y));
        p(ga) * x + p(gb) * y + p(0.5) * (p(haa) * x.sqr() + p(2.0) * p(hab) * x * y + p(hbb) * y.sqr())
    };
    let least = if convex {
        let s0 = box_minimizer([ga, gb], [haa, hab, hbb], s);
        // ∇q(s₀)·(s − s₀), each term at its worst end.
        let (x0, y0) = (p(s0[0]), p(s0[1]));
        let grad = [p(ga) + p(haa) * x0 + p(hab) * y0, p(gb) + p(hab) * x0 + p(hbb) * y0];
        let mut total = q(s0[0], s0[1]);
        for (gr, (r, c)) in grad.iter().zip(s.iter().zip([x0, y0])) {
            total = total + p((*gr * (*r - c)).lo);
        }
        total.lo
    } else {
        // Concave along a: the minimum is on an edge s_a = end; 1-D in s_b there (or the reverse).
        let (fixed, free, swap) = if haa < 0.0 { (s[0], s[1], false) } else { (s[1], s[0], true) };
        let (g_fix, g_free, h_fix, h_free) = if swap { (gb, ga, hbb, haa) } else { (ga, gb, haa, hbb) };
        [fixed.lo, fixed.hi]
            .iter()
            .map(|&x| {
                let base = p(g_fix) * p(x) + p(0.5 * h_fix) * p(x).sqr();
                quadratic_1d_lower(base, p(g_free) + p(hab) * p(x), h_free, free)
            })
            .fold(f64::INFINITY, f64::min)
    };
    (p(least) - error).lo
}

/// Lower bound of c₀ + α·x + ½β·x² over x ∈ `x` (β exact).
fn quadratic_1d_lower(c0: Interval, alpha: Interval, beta: f64, x: Interval) -> f64 {
    let p = Interval::point;
    let at = |y: f64| (c0 + alpha * p(y) + p(0.5 * beta) * p(y).sqr()).lo;
    let mut least = at(x.lo).min(at(x.hi));
    if beta > 0.0 {
        let stationary = -alpha / p(beta);
        if stationary.hi >= x.lo && stationary.lo <= x.hi {
            least = least.min((c0 - alpha.sqr() / p(2.0 * beta)).lo);
        }
    }
    least
}

/// The minimizer of the convex g·s + ½ sᵀHs over the box (f64, approximate:
/// only the quality of the bound depends on it): the stationary point if
/// inside, else the best of the four edges' 1-D minimizers.
fn box_minimizer(g: [f64; 2], [haa, hab, hbb]: [f64; 3], s: [Interval; 2]) -> [f64; 2] {
    let q = |x: f64, y: f64| g[0] * x + g[1] * y + 0.5 * (haa * x * x + 2.0 * hab * x * y + hbb * y * y);
    let det = haa * hbb - hab * hab;
    let inside = |x: f64, y: f64| x >= s[0].lo && x <= s[0].hi && y >= s[1].lo && y <= s[1].hi;
    if det > 0.0 {
        let (x, y) = ((-hbb * g[0] + hab * g[1]) / det, (hab * g[0] - haa * g[1]) / det);
        if inside(x, y) {
            return [x, y];
        }
    }
    let clamp1 = |num: f64, den: f64, r: Interval| if den > 0.0 { (-num / den).clamp(r.lo, r.hi) } else { r.lo };
    let mut candidates = Vec::with_capacity(8);
    for x in [s[0].lo, s[0].hi] {
        candidates.push([x, clamp1(g[1] + hab * x, hbb, s[1])]);
    }
    for y in [s[1].lo, s[1].hi] {
        candidates.push([clamp1(g[0] + hab * y, haa, s[0]), y]);
    }
    candidates.into_iter().min_by(|u, v| q(u[0], u[1]).total_cmp(&q(v[0], v[1]))).unwrap_or([0.0, 0.0])
}

/// A box waiting in the queue, lowest bound first.
struct Node {
    lower: f64,
    split_a: bool,
    a: Rc<Side>,
    b: Rc<Side>,
}

impl PartialEq for Node {
    fn eq(&self, o: &Self) -> bool {
        self.lower == o.lower
    }
}
impl Eq for Node {}
impl PartialOrd for Node {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Node {
    fn cmp(&self, o: &Self) -> Ordering {
        o.lower.total_cmp(&self.lower)
    }
}

/// The best proven pair so far.
struct Best {
    upper: f64,
    /// Proven lower bound of the same pair's distance: how well f64 resolves it.
    point_lower: f64,
    at: Option<(usize, f64, usize, f64)>,
}

impl Best {
    /// Offer the centres of a box: an upper bound when both are exact realizations.
    fn offer(&mut self, (ha, hb): (&[Half], &[Half]), a: &Side, b: &Side, centre: Interval) {
        if a.tc > ha[a.half].t_safe || b.tc > hb[b.half].t_safe {
            return;
        }
        let upper = centre.hi.sqrt().next_up();
        if upper < self.upper || self.at.is_none() {
            let point_lower = centre.lo.max(0.0).sqrt().next_down().max(0.0);
            *self = Best { upper, point_lower, at: Some((a.half, a.tc, b.half, b.tc)) };
        }
    }

    /// The relative gap f64 resolves at the best pair itself (infinite when
    /// no pair could be enclosed at all).
    fn resolution(&self) -> f64 {
        if !self.upper.is_finite() {
            f64::INFINITY
        } else if self.upper > 0.0 {
            (self.upper - self.point_lower) / self.upper
        } else {
            0.0
        }
    }
}

/// Local Gauss–Newton steps on F = |V_a − V_b|² from the best pair, inside
/// its two halves, each costing two point enclosures: a near-optimal pair
/// early lets the search stop as soon as the bounds allow (where the curves
/// meet, at once). Only the bounds prove anything; this only finds pairs.
/// Returns the point enclosures spent (at most `budget`).
fn polish(best: &mut Best, pieces: &mut (Pieces, Pieces), budget: usize) -> usize {
    let mut spent = 0;
    let mut damping = 1.0;
    while spent + 2 <= budget {
        let Some((ha, ta, hb, tb)) = best.at else { break };
        let (a, b) = (pieces.0.get(ha, Interval::point(ta)), pieces.1.get(hb, Interval::point(tb)));
        let (mut jaa, mut jab, mut jbb, mut ga, mut gb) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for ([va, da], [vb, db]) in a.at_c.iter().zip(&b.at_c) {
            let (g, ja, jb) = (va.mid() - vb.mid(), da.mid(), -db.mid());
            (jaa, jab, jbb, ga, gb) = (jaa + ja * ja, jab + ja * jb, jbb + jb * jb, ga + ja * g, gb + jb * g);
        }
        let mu = tolerance::POLISH_DAMPING * (jaa + jbb) + f64::MIN_POSITIVE;
        let det = (jaa + mu) * (jbb + mu) - jab * jab;
        if det.is_nan() || det <= 0.0 {
            break;
        }
        let step = [damping * ((jbb + mu) * ga - jab * gb) / det, damping * ((jaa + mu) * gb - jab * ga) / det];
        let clamp = |t: f64, s: f64, h: &Half| (t - s).clamp(0.0, h.t_safe);
        let (na, nb) = (clamp(ta, step[0], &pieces.0.halves[ha]), clamp(tb, step[1], &pieces.1.halves[hb]));
        if na == ta && nb == tb {
            break;
        }
        let (a, b) = (pieces.0.get(ha, Interval::point(na)), pieces.1.get(hb, Interval::point(nb)));
        spent += 2;
        let before = best.upper;
        best.offer((pieces.0.halves, pieces.1.halves), &a, &b, bounds(&a, &b).centre);
        if best.upper < before {
            damping = 1.0;
        } else if damping > tolerance::POLISH_MIN_STEP {
            damping /= tolerance::POLISH_SHRINK;
        } else {
            break;
        }
    }
    spent
}

/// The branch and bound: boxes (a piece of A × a piece of B) waiting lowest
/// bound first, the best proven pair, and the work done.
struct Search<'a> {
    pieces: (Pieces<'a>, Pieces<'a>),
    heap: BinaryHeap<Node>,
    best: Best,
    boxes: usize,
    /// Lowest bound of the boxes set aside: pruned, or too small (or too
    /// blurred by rounding) to split.
    floor: f64,
    polish_left: usize,
    opts: ClosestOptions,
}

impl Search<'_> {
    /// The proven lower bound over everything not yet resolved.
    fn lower(&self) -> f64 {
        self.heap.peek().map_or(f64::INFINITY, |n| n.lower).min(self.floor)
    }

    /// The gap aimed at: the requested one, unless the best pair's own
    /// distance is not resolved that finely (no bound can then do better
    /// than about that resolution).
    fn reach(&self) -> f64 {
        self.opts.gap.max(2.0 * self.best.resolution())
    }

    /// Bound a box, offer its centres, and keep it unless it is resolved.
    fn push(&mut self, a: Rc<Side>, b: Rc<Side>) {
        let bd = bounds(&a, &b);
        self.boxes += 1;
        self.best.offer((self.pieces.0.halves, self.pieces.1.halves), &a, &b, bd.centre);
        if bd.lower >= (1.0 - self.reach()) * self.best.upper {
            self.floor = self.floor.min(bd.lower);
        } else {
            self.heap.push(Node { lower: bd.lower, split_a: bd.split_a, a, b });
        }
    }

    fn polish(&mut self) {
        self.polish_left -= polish(&mut self.best, &mut self.pieces, self.polish_left);
    }

    /// Split the lowest box in two; `Some` when the search is over.
    fn step(&mut self) -> Option<Outcome> {
        let reach = self.reach();
        if reach.is_infinite() || self.best.upper - self.lower() <= reach * self.best.upper {
            return Some(if reach > self.opts.gap { Outcome::Resolution } else { Outcome::GapReached });
        }
        let Some(node) = self.heap.pop() else { return Some(Outcome::Resolution) };
        if self.boxes >= self.opts.max_boxes {
            self.heap.push(node);
            return Some(Outcome::Budget);
        }
        let splittable = |s: &Side| {
            let m = s.t.mid();
            m > s.t.lo && m < s.t.hi && !s.saturated
        };
        let split_a = match (splittable(&node.a), splittable(&node.b)) {
            (false, false) => {
                self.floor = self.floor.min(node.lower);
                return None;
            }
            (true, true) => node.split_a,
            (a, _) => a,
        };
        let piece = if split_a { &node.a } else { &node.b };
        let m = piece.t.mid();
        let before = self.best.upper;
        for t in [Interval::new(piece.t.lo, m), Interval::new(m, piece.t.hi)] {
            let cache = if split_a { &mut self.pieces.0 } else { &mut self.pieces.1 };
            let child = cache.get(piece.half, t);
            let (a, b) = if split_a { (child, node.b.clone()) } else { (node.a.clone(), child) };
            self.push(a, b);
        }
        if self.best.upper < before {
            self.polish();
        }
        None
    }
}

/// Closest pair by Cayley distance, certified by branch and bound.
///
/// Each component is cut into halves of segments parametrized from their ends
/// ([`crate::enclosure`]); every pair of interval ends is a candidate, then
/// boxes (a piece of A × a piece of B) are taken lowest proven bound first,
/// each split in the piece that widens its bound most, until the best pair
/// found is within `opts.gap` (relative) of the lowest bound of any box left,
/// or the budget of boxes was spent (`opts.max_boxes`, fewer on a scene of
/// more than 100 steps: [`tolerance::CLOSEST_BOX_STEPS`]). `None` when a component has no
/// segment.
pub fn closest_pair(
    con: &Construction<f64>,
    mirrors: Mirrors,
    space: &CayleySpace<f64>,
    ccv: &[[usize; 2]],
    (ca, cb): (&Component, &Component),
    opts: ClosestOptions,
) -> Option<ClosestPair> {
    let (seg_a, seg_b) = (component_segments(space, ca), component_segments(space, cb));
    if seg_a.is_empty() || seg_b.is_empty() {
        return None;
    }
    // A proof first (mirror images), then a branch point's shared realization.
    if let Some(pair) = mirror_pair(mirrors, space, (ca, cb), &seg_a, opts) {
        return Some(pair);
    }
    if let Some(pair) = shared_pair(space, (ca, cb), opts) {
        return Some(pair);
    }
    // Budgets of work (so many × steps) as counts on this scene.
    let per_step = |work: usize| work / con.steps.len().max(1);
    let opts = ClosestOptions { max_boxes: opts.max_boxes.min(per_step(tolerance::CLOSEST_BOX_STEPS)), ..opts };
    let (ha, hb) = (halves(con, space, &seg_a), halves(con, space, &seg_b));
    let unverified_ends = ha.iter().chain(&hb).filter(|h| !h.verified).count();
    let mut search = Search {
        pieces: (Pieces::new(con, ccv, &ha), Pieces::new(con, ccv, &hb)),
        heap: BinaryHeap::new(),
        best: Best { upper: f64::INFINITY, point_lower: 0.0, at: None },
        boxes: 0,
        floor: f64::INFINITY,
        polish_left: POLISH_BUDGET.min(per_step(POLISH_STEPS)),
        opts,
    };
    // Every pair of interval ends is a candidate; then every pair of halves is a box.
    let (ends_a, ends_b) = (search.pieces.0.all(|_| Interval::ZERO), search.pieces.1.all(|_| Interval::ZERO));
    for a in &ends_a {
        for b in &ends_b {
            search.best.offer((&ha, &hb), a, b, bounds(a, b).centre);
        }
    }
    let end_pairs = ends_a.len() * ends_b.len();
    let whole = |h: &Half| Interval::new(0.0, h.t_max);
    let (all_a, all_b) = (search.pieces.0.all(whole), search.pieces.1.all(whole));
    for a in &all_a {
        for b in &all_b {
            search.push(a.clone(), b.clone());
        }
    }
    search.polish();
    let outcome = loop {
        if let Some(outcome) = search.step() {
            break outcome;
        }
    };
    let (best, lower, boxes) = (&search.best, search.lower().min(search.best.upper), search.boxes);
    let (h_a, t_a, h_b, t_b) = best.at?;
    let (a, va) = named(con, ccv, (&ha, &seg_a), h_a, t_a);
    let (b, vb) = named(con, ccv, (&hb, &seg_b), h_b, t_b);
    let distance = va.zip(vb).map_or(best.upper, |(x, y)| euclid(&x, &y));
    let upper = best.upper;
    let gap = if upper.is_finite() && upper > 0.0 { (upper - lower) / upper } else { f64::from(upper > 0.0) };
    let certificate = Certificate {
        lower,
        upper,
        gap,
        requested_gap: opts.gap,
        outcome,
        certified: outcome == Outcome::GapReached && unverified_ends == 0,
        boxes,
        max_boxes: opts.max_boxes,
        end_pairs,
        unverified_ends,
    };
    // The curves meet: the best pair's distance is not resolved even to a factor 2.
    let crossing = best.point_lower <= 0.5 * best.upper;
    Some(ClosestPair { distance, a, b, mirror: false, crossing, certificate })
}

/// The realization half `h` names at `t` (its λ as an f64), with its Cayley
/// vector in f64. A name at the end's λ (t = 0, or t² below its ulp) is the
/// end's realization: its flat steps are placed exactly flat (computed, they
/// would stand √rounding high, 1e-8 of the scale).
fn named(
    con: &Construction<f64>,
    ccv: &[[usize; 2]],
    (hs, segs): (&[Half], &[Segment]),
    h: usize,
    t: f64,
) -> (Realization, Option<Vec<f64>>) {
    let seg = &segs[hs[h].segment];
    let r = Realization { ty: seg.ty.clone(), lambda: hs[h].lambda(t, seg) };
    let flat: &[usize] = if r.lambda == hs[h].end { &hs[h].flat_steps } else { &[] };
    let v = con.realize_flat(r.lambda, &r.ty.0, con.steps.len(), flat).ok().map(|p| cayley_vector(&points(&p), ccv));
    (r, v)
}

/// Two components that meet at a branch point: an end of an interval of A
/// and one of B on the same side that are one end by the flip rule
/// ([`crate::roots::Endpoint::flips_to`]): one realization, distance 0.
fn shared_pair(
    space: &CayleySpace<f64>,
    (ca, cb): (&Component, &Component),
    opts: ClosestOptions,
) -> Option<ClosestPair> {
    let ends = |i: usize| {
        let iv = &space.intervals[i];
        [(&iv.lower, false), (&iv.upper, true)].map(|(e, upper)| (e, upper, &iv.ty))
    };
    let (a, b) = ca.intervals.iter().flat_map(|&i| ends(i)).find_map(|(ea, upper_a, ta)| {
        let (eb, _, tb) = cb
            .intervals
            .iter()
            .flat_map(|&j| ends(j))
            .find(|&(eb, upper_b, tb)| upper_b == upper_a && ea.flips_to(ta, eb, tb))?;
        Some((Realization { ty: ta.clone(), lambda: ea.lambda }, Realization { ty: tb.clone(), lambda: eb.lambda }))
    })?;
    let certificate = Certificate {
        lower: 0.0,
        upper: 0.0,
        gap: 0.0,
        requested_gap: opts.gap,
        outcome: Outcome::Shared,
        certified: false,
        boxes: 0,
        max_boxes: opts.max_boxes,
        end_pairs: 0,
        unverified_ends: 0,
    };
    Some(ClosestPair { distance: 0.0, a, b, mirror: false, crossing: false, certificate })
}

/// When every cluster is achiral and B holds the mirror image of every
/// interval of A, the components are mirror images: distance exactly 0
/// (certified only when the clusters are proven flat, see [`Mirrors`]).
fn mirror_pair(
    mirrors: Mirrors,
    space: &CayleySpace<f64>,
    (ca, cb): (&Component, &Component),
    seg_a: &[Segment],
    opts: ClosestOptions,
) -> Option<ClosestPair> {
    if !mirrors.exist() {
        return None;
    }
    let in_b = |ty: &RealizationType| cb.intervals.iter().any(|&j| &space.intervals[j].ty == ty);
    if !ca.intervals.iter().all(|&i| in_b(&mirror_type(&space.intervals[i].ty))) {
        return None;
    }
    let a = Realization { ty: seg_a[0].ty.clone(), lambda: seg_a[0].from };
    let b = Realization { ty: mirror_type(&a.ty), lambda: a.lambda };
    let certificate = Certificate {
        lower: 0.0,
        upper: 0.0,
        gap: 0.0,
        requested_gap: opts.gap,
        outcome: Outcome::Mirror,
        certified: mirrors == Mirrors::Yes,
        boxes: 0,
        max_boxes: opts.max_boxes,
        end_pairs: 0,
        unverified_ends: 0,
    };
    Some(ClosestPair { distance: 0.0, a, b, mirror: true, crossing: false, certificate })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// No pair enclosed at all (a construction too deep for f64 intervals):
    /// the search stops at once, and never calls that a reached gap.
    #[test]
    fn an_unbounded_best_pair_is_never_a_reached_gap() {
        let ccv = [[0, 1]];
        let con = Construction::<f64> { n_joints: 2, base: [0, 1], steps: vec![], scale: 1.0, shapes: vec![] };
        let mut search = Search {
            pieces: (Pieces::new(&con, &ccv, &[]), Pieces::new(&con, &ccv, &[])),
            heap: BinaryHeap::new(),
            best: Best { upper: f64::INFINITY, point_lower: 0.0, at: None },
            boxes: 0,
            floor: 0.0,
            polish_left: 0,
            opts: ClosestOptions::default(),
        };
        assert_eq!(search.step(), Some(Outcome::Resolution));
        // With a finite pair and every box resolved, the gap is reached.
        search.best = Best { upper: 1.0, point_lower: 1.0 - 1e-15, at: None };
        search.floor = 1.0 - 1e-12;
        assert_eq!(search.step(), Some(Outcome::GapReached));
        search.floor = 0.5;
        assert_eq!(search.step(), Some(Outcome::Resolution), "nothing left to split, the gap not reached");
    }

    #[test]
    fn quadratic_lower_bounds_hold_on_a_grid() {
        let cases = [
            ([1.0, -2.0], [2.0, -1.9, 2.0]), // a valley: nearly singular, convex
            ([0.5, 0.3], [-1.0, 0.2, 3.0]),  // concave along a
            ([0.0, 0.0], [1.0, 0.0, -2.0]),  // concave along b
            ([-3.0, 1.0], [4.0, 1.0, 1.0]),  // stationary point inside
            ([0.2, -0.1], [1.0, 2.0, 1.0]),  // a saddle with a positive diagonal
        ];
        for (g, h) in cases {
            let widen = |x: f64| Interval::new(x - 1e-3, x + 1e-3);
            let s = [Interval::new(-0.7, 0.4), Interval::new(-0.3, 0.9)];
            let lower = quadratic_lower([widen(g[0]), widen(g[1])], [widen(h[0]), widen(h[1]), widen(h[2])], s);
            for i in 0..=40 {
                for j in 0..=40 {
                    let (x, y) = (-0.7 + 1.1 * i as f64 / 40.0, -0.3 + 1.2 * j as f64 / 40.0);
                    for (dg, dh) in [(1e-3, -1e-3), (-1e-3, 1e-3), (0.0, 0.0)] {
                        let (ga, gb) = (g[0] + dg, g[1] - dg);
                        let (haa, hab, hbb) = (h[0] + dh, h[1] - dh, h[2] + dh);
                        let q = ga * x + gb * y + 0.5 * (haa * x * x + 2.0 * hab * x * y + hbb * y * y);
                        assert!(lower <= q + 1e-12, "g {g:?} h {h:?}: {lower} > q({x}, {y}) = {q}");
                    }
                }
            }
            if h[0] * h[2] < h[1] * h[1] {
                continue; // a saddle: sound, but not sharp
            }
            // And it is sharp: within the coefficients' uncertainty of the true minimum.
            let min = (0..=400)
                .flat_map(|i| (0..=400).map(move |j| (-0.7 + 1.1 * i as f64 / 400.0, -0.3 + 1.2 * j as f64 / 400.0)))
                .map(|(x, y)| g[0] * x + g[1] * y + 0.5 * (h[0] * x * x + 2.0 * h[1] * x * y + h[2] * y * y))
                .fold(f64::INFINITY, f64::min);
            assert!(lower >= min - 1e-2, "g {g:?} h {h:?}: {lower} far below {min}");
        }
    }
}
