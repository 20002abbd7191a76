//! Realizations: from (λ, type) to joint positions in O(n) by ruler and
//! compass, generic over the scalar type so the same code runs in f64,
//! double-double and jets.
//!
//! Frame: base joint `a` at (0, 0), `b` at (λ, 0). Orientation of step k is `+`
//! when its vertex lies left of the directed line u_k → w_k (y up).

use std::fmt;

use crate::decompose::{Decomposition, Origin};
use crate::exact::Decimal;
use crate::linkage::Linkage;
use crate::real::{Dd, Jet, Real};
use crate::tolerance;

/// A point `[x, y]` of the generic-scalar construction. Not nalgebra's
/// [`Point2`]: that needs `T: Scalar` (and `RealField` for its geometry),
/// which the double-double, jet and ball types here do not implement, and
/// this code runs in all four of f64, [`crate::real::Dd`], [`Jet`] and
/// [`crate::real::Ball`]. Positions handed to callers in f64 are
/// [`Point2`]s ([`to_display`], [`points`]).
pub type P2<T> = [T; 2];

/// The type of the f64 joint positions handed to callers (re-exported, so
/// callers need not depend on nalgebra's version themselves).
pub use nalgebra::Point2;

/// Base-frame f64 positions (as [`Construction::realize`] gives them) as points.
pub fn points(pos: &[P2<f64>]) -> Vec<Point2<f64>> {
    pos.iter().map(|&p| Point2::from(p)).collect()
}

fn sub<T: Real>(p: P2<T>, q: P2<T>) -> P2<T> {
    [p[0] - q[0], p[1] - q[1]]
}
fn dot<T: Real>(p: P2<T>, q: P2<T>) -> T {
    p[0] * q[0] + p[1] * q[1]
}
fn cross<T: Real>(p: P2<T>, q: P2<T>) -> T {
    p[0] * q[1] - p[1] * q[0]
}
fn norm<T: Real>(p: P2<T>) -> T {
    T::hypot(p[0], p[1])
}
/// `p / |p|` (dimensionless, so dot and cross products of these never overflow).
fn unit<T: Real>(p: P2<T>) -> P2<T> {
    let n = norm(p);
    [p[0] / n, p[1] / n]
}

/// `bits` as one word, bit i for `bits[i]`; `None` past 128 bits. The
/// packed form of a type or prefix that the solver's caches key by.
pub fn bits_word(bits: &[bool]) -> Option<u128> {
    (bits.len() <= 128).then(|| bits.iter().enumerate().fold(0u128, |w, (i, &b)| w | u128::from(b) << i))
}

/// A realization type: one orientation bit per step, `true` = `+`.
#[derive(Clone, PartialEq, Eq, Hash, PartialOrd, Ord, Debug)]
pub struct RealizationType(pub Vec<bool>);

impl RealizationType {
    /// Parse a string of `+` and `-`; `None` for any other character.
    pub fn parse(text: &str) -> Option<Self> {
        text.chars()
            .map(|c| match c {
                '+' => Some(true),
                '-' => Some(false),
                _ => None,
            })
            .collect::<Option<Vec<bool>>>()
            .map(RealizationType)
    }
    /// The type with bit `i` flipped.
    pub fn flipped(&self, i: usize) -> Self {
        let mut bits = self.0.clone();
        bits[i] = !bits[i];
        RealizationType(bits)
    }

    /// The type with the bits of those `steps` chosen by `mask` flipped (bit
    /// b of the mask for `steps[b]`): the candidates at a branch point.
    pub fn flipped_by_mask(&self, steps: &[usize], mask: usize) -> Self {
        let mut bits = self.0.clone();
        for (b, &k) in steps.iter().enumerate() {
            if mask & (1 << b) != 0 {
                bits[k] = !bits[k];
            }
        }
        RealizationType(bits)
    }
}

impl fmt::Display for RealizationType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for &b in &self.0 {
            f.write_str(if b { "+" } else { "-" })?;
        }
        Ok(())
    }
}

/// Serialized as its signs, e.g. `"-+-+"`.
#[cfg(feature = "serde")]
impl serde::Serialize for RealizationType {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

#[cfg(feature = "serde")]
impl schemars::JsonSchema for RealizationType {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        "RealizationType".into()
    }
    fn json_schema(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
        schemars::json_schema!({ "type": "string", "pattern": "^[+-]*$" })
    }
}

/// A realization named by type and base length.
#[derive(Clone, Debug, PartialEq)]
pub struct Realization {
    /// Its realization type.
    pub ty: RealizationType,
    /// Its base length λ (scene units).
    pub lambda: f64,
}

impl Realization {
    /// Parse `TYPE@LAMBDA`, e.g. `-+-+@41.2`.
    pub fn parse(text: &str) -> Result<Self, String> {
        let (ty, lambda) =
            text.split_once('@').ok_or_else(|| format!("\"{text}\": expected TYPE@LAMBDA, e.g. -+-+@41.2"))?;
        let ty = RealizationType::parse(ty.trim())
            .ok_or_else(|| format!("\"{text}\": the type before @ (\"{ty}\") is a string of + and -"))?;
        let lambda: f64 =
            lambda.trim().parse().map_err(|_| format!("\"{text}\": the λ after @ (\"{lambda}\") is not a number"))?;
        if !lambda.is_finite() {
            return Err(format!("\"{text}\": the λ after @ ({lambda}) is not a finite number"));
        }
        Ok(Realization { ty, lambda })
    }
}

impl std::fmt::Display for Realization {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}@{}", self.ty, self.lambda)
    }
}

/// How a step is flat at an endpoint.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, schemars::JsonSchema))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Kind {
    /// d = r1 + r2
    Stretched,
    /// d = |r1 − r2|
    Folded,
}

impl Kind {
    /// `stretched` or `folded`.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Stretched => "stretched",
            Kind::Folded => "folded",
        }
    }

    /// The base distance at which a step with sides r1, r2 is flat this way.
    pub fn target<T: Real>(self, r1: T, r2: T) -> T {
        match self {
            Kind::Stretched => r1 + r2,
            Kind::Folded => (r1 - r2).abs(),
        }
    }

    /// The step's slack for this kind at base distance `d` (a jet, so with
    /// its slope and curvature): positive where this side of the triangle closes.
    pub fn slack<T: Real>(self, r1: T, r2: T, d: Jet<T>) -> Jet<T> {
        self.slack_value(Jet::constant(r1), Jet::constant(r2), d)
    }

    /// [`Self::slack`] in any arithmetic.
    pub fn slack_value<T: Real>(self, r1: T, r2: T, d: T) -> T {
        let t = self.target(r1, r2);
        match self {
            Kind::Stretched => t - d,
            Kind::Folded => d - t,
        }
    }
}

/// Step `step` is flat (`kind`) at an endpoint.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, schemars::JsonSchema))]
pub struct Event {
    /// The flat step (0-based; serialized from 1).
    #[cfg_attr(feature = "serde", serde(serialize_with = "crate::numbering::step_number"))]
    #[cfg_attr(feature = "serde", schemars(with = "crate::numbering::StepNo"))]
    pub step: usize,
    /// How it is flat.
    pub kind: Kind,
}

/// A cluster joint placed from a step's frame (p, q): `j = p + α(q−p) + β·perp(q−p)`.
#[derive(Debug, Clone)]
pub struct Member<T> {
    /// The joint placed.
    pub joint: usize,
    /// Its coordinate along q − p, in units of |q − p|.
    pub alpha: T,
    /// Its coordinate along perp(q − p), in units of |q − p|.
    pub beta: T,
}

/// One step's fixed geometry.
#[derive(Debug, Clone)]
pub struct StepGeom<T> {
    /// v_k: the joint the step places.
    pub vertex: usize,
    /// u_k: the base joint on the first cluster.
    pub u: usize,
    /// w_k: the base joint on the second cluster.
    pub w: usize,
    /// |u v| inside the cluster on u.
    pub r1: T,
    /// |w v| inside the cluster on w.
    pub r2: T,
    /// r1 + r2 and r1 − r2, which the apex reads several times each (as
    /// computed there, so every realization's numbers stay the same).
    sum_diff: [T; 2],
    /// Other joints of the cluster on u, placed from (u, v); likewise for w.
    pub members_u: Vec<Member<T>>,
    /// Other joints of the cluster on w, placed from (w, v).
    pub members_w: Vec<Member<T>>,
    /// What a realization that only measures base distances must place
    /// (see [`Construction::place_step`]'s `reach`).
    first_reads: FirstReads,
}

/// The first later step that reads each placement of a step (as its u or
/// w), `usize::MAX` where none does.
#[derive(Debug, Clone, Default)]
struct FirstReads {
    /// The vertex, or any member (which are placed from it).
    apex: usize,
    /// Each member: `members_u` then `members_w`.
    members: Vec<usize>,
    /// The latest of `members` (0 without members).
    latest_member: usize,
}

/// The [`FirstReads`] of every step, from the steps' base joints (one pass
/// from the last step, keeping each joint's nearest reader so far).
fn first_reads<T>(steps: &[StepGeom<T>], n_joints: usize) -> Vec<FirstReads> {
    let mut reader = vec![usize::MAX; n_joints];
    let mut out: Vec<FirstReads> = steps
        .iter()
        .enumerate()
        .rev()
        .map(|(k, s)| {
            let members: Vec<usize> = s.members_u.iter().chain(&s.members_w).map(|m| reader[m.joint]).collect();
            let apex = members.iter().copied().fold(reader[s.vertex], usize::min);
            (reader[s.u], reader[s.w]) = (k, k);
            let latest_member = members.iter().copied().max().unwrap_or(0);
            FirstReads { apex, members, latest_member }
        })
        .collect();
    out.reverse();
    out
}

/// The construction with every length computed in `T` from the scene's numbers.
#[derive(Debug, Clone)]
pub struct Construction<T> {
    /// The number of joints.
    pub n_joints: usize,
    /// The base non-edge f = (a, b).
    pub base: [usize; 2],
    /// The construction steps, in order.
    pub steps: Vec<StepGeom<T>>,
    /// Scene scale (see [`crate::tolerance`]).
    pub scale: f64,
    /// Local shape of every cluster node (indexed like `ClusterSet::nodes`).
    pub shapes: Vec<Vec<(usize, P2<T>)>>,
}

/// Why a (λ, type) has no realization.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, schemars::JsonSchema))]
#[cfg_attr(feature = "serde", serde(tag = "reason", rename_all = "snake_case"))]
pub enum Unrealizable {
    /// Step `step`'s triangle cannot close: slack (negative) in scene units.
    Infeasible {
        /// The step (0-based; serialized from 1).
        #[cfg_attr(feature = "serde", serde(serialize_with = "crate::numbering::step_number"))]
        #[cfg_attr(feature = "serde", schemars(with = "crate::numbering::StepNo"))]
        step: usize,
        /// Its slack (negative), scene units.
        slack: f64,
    },
    /// Step `step`'s base joints coincide: its vertex is undetermined.
    Degenerate {
        /// The step (0-based; serialized from 1).
        #[cfg_attr(feature = "serde", serde(serialize_with = "crate::numbering::step_number"))]
        #[cfg_attr(feature = "serde", schemars(with = "crate::numbering::StepNo"))]
        step: usize,
    },
}

/// The stated lengths cannot form a cluster (a sketch whose numbers contradict).
#[derive(Debug, Clone, PartialEq)]
pub struct ShapeError(pub String);

/// Slack of a step: ≥ 0 iff the triangle (r1, r2, d) closes; zero when flat.
pub fn slack<T: Real>(r1: T, r2: T, d: T) -> T {
    let stretch = r1 + r2 - d;
    let fold = d - (r1 - r2).abs();
    if stretch < fold { stretch } else { fold }
}

/// Apex of the triangle on the directed base `pu → pw` with sides `r1` from
/// `pu` and `r2` from `pw`, left of the base when `plus`. The height uses the
/// cancellation-free product h² = (r1+r2+d)(r1+r2−d)(d−|r1−r2|)(d+|r1−r2|)/(4d²).
/// A slack down to `-tol` is clamped to a flat triangle; below, `Err(slack)`.
pub fn apex<T: Real>(pu: P2<T>, pw: P2<T>, r1: T, r2: T, plus: bool, tol: f64) -> Result<P2<T>, Option<f64>> {
    let e = sub(pw, pu);
    apex_flat(Triangle { pu, e, d: norm(e), sum_diff: sum_diff(r1, r2), plus, tol, flat: false })
}

/// A step's triangle as it is placed: its base from `pu` along `e = pw − pu`
/// of length `d = |e|` (computed once by the caller, which also records d
/// as the step's base distance), its sides as [r1 + r2, r1 − r2]
/// ([`sum_diff`]), left of the base when `plus`, a slack down to `-tol`
/// counted as flat, and `flat` to place it exactly flat (height zero).
#[derive(Clone, Copy, Debug)]
pub struct Triangle<T> {
    /// The base's first joint.
    pub pu: P2<T>,
    /// The base vector pw − pu.
    pub e: P2<T>,
    /// Its length.
    pub d: T,
    /// [r1 + r2, r1 − r2].
    pub sum_diff: [T; 2],
    /// Left of the base.
    pub plus: bool,
    /// Slack down to `-tol` counts as flat.
    pub tol: f64,
    /// Placed exactly flat, whatever its slack ([`flat_tolerance`]).
    pub flat: bool,
}

/// [r1 + r2, r1 − r2].
fn sum_diff<T: Real>(r1: T, r2: T) -> [T; 2] {
    [r1 + r2, r1 - r2]
}

/// [`apex`] of a [`Triangle`]. Each type computes it through [`Real::apex`]
/// (jets carry their derivatives through d alone).
pub(crate) fn apex_flat<T: Real>(t: Triangle<T>) -> Result<P2<T>, Option<f64>> {
    Ok(apex_parts(&t)?.placed(t.pu))
}

/// The apex as `pu + along·(ex, ey) + h·(−ey, ex)`, with (ex, ey) = e/d and
/// h signed by the orientation; `h2` = (h/d)² (clamped slacks count zero).
#[derive(Clone, Copy)]
struct Apex<T> {
    along: T,
    h: T,
    ex: T,
    ey: T,
    h2: T,
    /// A slack below zero was clamped to a flat triangle.
    clamped: bool,
}

impl<T: Real> Apex<T> {
    /// The apex from `pu`.
    fn placed(&self, pu: P2<T>) -> P2<T> {
        let Apex { along, h, ex, ey, .. } = *self;
        [pu[0] + along * ex - h * ey, pu[1] + along * ey + h * ex]
    }
}

/// [`apex_flat`]'s numbers, before they are combined.
fn apex_parts<T: Real>(t: &Triangle<T>) -> Result<Apex<T>, Option<f64>> {
    let Triangle { e, d, sum_diff: [sum, diff], plus, tol, flat, .. } = *t;
    let [stretch, fold, gap] = closing(d, [sum, diff], flat_tolerance(flat, tol))?;
    let zero = T::zero();
    let clamped = stretch < zero || fold < zero;
    // h = d·√(dimensionless product): no product of lengths, so no overflow
    // or underflow at any scale f64 can represent.
    // 1/d keeps double-double precision only while its low part is normal.
    let magnitude = d.to_f64().abs();
    let by_reciprocal = T::APEX_BY_RECIPROCAL && magnitude > RECIPROCAL_RANGE[0] && magnitude < RECIPROCAL_RANGE[1];
    let (h2, along, ex, ey) = if by_reciprocal {
        let inv = T::from_f64(1.0) / d;
        let half_inv = inv * T::from_f64(0.5);
        let h2 = ((sum + d) * half_inv * (stretch.clamp_nonneg() * inv))
            * ((d + gap) * half_inv * (fold.clamp_nonneg() * inv));
        (h2, (d + diff * (sum * inv)) * T::from_f64(0.5), e[0] * inv, e[1] * inv)
    } else {
        let two_d = T::from_f64(2.0) * d;
        let h2 = ((sum + d) / two_d * (stretch.clamp_nonneg() / d)) * ((d + gap) / two_d * (fold.clamp_nonneg() / d));
        (h2, (d + diff * (sum / d)) / T::from_f64(2.0), e[0] / d, e[1] / d)
    };
    let h = if flat { zero } else { d * h2.sqrt() };
    let h = if plus { h } else { -h };
    // Placed flat, the vertex is r1 from u on the base line, on the side
    // `along` gives: where d is tiny the formula's along divides the
    // slack's rounding by d (a folded step on base joints 1e-6 apart put
    // its vertex 0.02 off its bar).
    let r1 = (sum + diff) * T::from_f64(0.5);
    let along = if flat && diff != zero { if along < zero { -r1 } else { r1 } } else { along };
    Ok(Apex { along, h, ex, ey, h2, clamped })
}

/// [`apex_flat`] for jets: the values are the generic formula's, operation
/// for operation (the same numbers a plain realization gives); the
/// derivatives come from writing the apex as `pu + F(d)·e + G(d)·(−e₁, e₀)`,
/// where F = along/d = ½ + σδ/2 and G = ±h/d = ±√q depend on d alone
/// (σ = (r1 + r2)/d, δ = (r1 − r2)/d, q = (σ² − 1)(1 − δ²)/4), so each is
/// one scalar chain rule instead of a jet operation per step of the
/// formula (the hot path of every jet realization: the lazy walk's probes).
/// With ρ₁ = d′/d, ρ₂ = d″/d: F′ = (dF_d)ρ₁ and F″ = (d²F_dd)ρ₁² + (dF_d)ρ₂,
/// where dF_d = −σδ, d²F_dd = 3σδ; likewise G from dq_d = σ²δ² − (σ² + δ²)/2
/// and d²q_dd = 3(σ² + δ²)/2 − 5σ²δ² through G = √q. Every quantity is
/// dimensionless (no product of lengths, and the derivatives are taken as
/// F′d and F″d², so no 1/d² either). A clamped slack has no
/// derivative (NaN, as the generic jet gives); a forced flat triangle has
/// G ≡ 0.
pub(crate) fn apex_jet<T: Real>(t: Triangle<Jet<T>>) -> Result<P2<Jet<T>>, Option<f64>> {
    let Triangle { pu, e, d, sum_diff: [sum, diff], plus, tol, flat } = t;
    let v = |p: P2<Jet<T>>| [p[0].v, p[1].v];
    let values = Triangle { pu: v(pu), e: v(e), d: d.v, sum_diff: [sum.v, diff.v], plus, tol, flat };
    let parts = apex_parts(&values)?;
    let [x, y] = parts.placed(values.pu);
    let (one, two) = (T::from_f64(1.0), T::from_f64(2.0));
    // Derivatives in units of d (ρ₁d and ρ₂d²): each factor of 1/d is
    // applied to a length last, so nothing of size 1/d² is formed (it
    // overflows below 1e-154).
    let k = d.v;
    let (rho1, rho2) = (d.d, d.s * k);
    let (sigma, delta) = (sum.v / d.v, diff.v / d.v);
    let sd = sigma * delta;
    // Placed flat with unequal sides, along = ±r1 (see `apex_parts`): F = along/d.
    let (f, f1, f2) = if flat && diff.v != T::zero() {
        let f = parts.along / d.v;
        (f, -(f * rho1), f * (two * rho1 * rho1 - rho2))
    } else {
        ((one + sd) / two, -(sd * rho1), T::from_f64(3.0) * sd * rho1 * rho1 - sd * rho2)
    };
    let (g, g1, g2) = if flat {
        (T::zero(), T::zero(), T::zero())
    } else if parts.clamped {
        let nan = T::from_f64(f64::NAN);
        (T::zero(), nan, nan)
    } else {
        let (ss, dd) = (sigma * sigma, delta * delta);
        let dq = ss * dd - (ss + dd) / two;
        let ddq = T::from_f64(1.5) * (ss + dd) - T::from_f64(5.0) * ss * dd;
        let g = parts.h2.sqrt();
        let dg = dq / (two * g);
        let ddg = (ddq - two * dg * dg) / (two * g);
        let (g1, g2) = (dg * rho1, ddg * rho1 * rho1 + dg * rho2);
        if plus { (g, g1, g2) } else { (-g, -g1, -g2) }
    };
    let [e0, e1] = e;
    // f1, g1 are F′d, G′d and f2, g2 are F″d², G″d².
    let first =
        |p: Jet<T>, a: Jet<T>, b: Jet<T>, sign: T| p.d + f1 * (a.v / k) + f * a.d + sign * (g1 * (b.v / k) + g * b.d);
    let second = |p: Jet<T>, a: Jet<T>, b: Jet<T>, sign: T| {
        p.s + (f2 * (a.v / k) + two * f1 * a.d) / k + f * a.s + sign * ((g2 * (b.v / k) + two * g1 * b.d) / k + g * b.s)
    };
    let minus = -one;
    Ok([
        Jet { v: x, d: first(pu[0], e0, e1, minus), s: second(pu[0], e0, e1, minus) },
        Jet { v: y, d: first(pu[1], e1, e0, one), s: second(pu[1], e1, e0, one) },
    ])
}

/// Whether the triangle on a base of length `d` with sides [r1 + r2, r1 − r2]
/// closes (slack down to `-tol` counts as flat): its stretched and folded
/// slacks and |r1 − r2|, else `Err(slack)`, or `Err(None)` for a base of no
/// positive length.
fn closing<T: Real>(d: T, [sum, diff]: [T; 2], tol: f64) -> Result<[T; 3], Option<f64>> {
    if d.partial_cmp(&T::zero()) != Some(std::cmp::Ordering::Greater) {
        return Err(None);
    }
    let gap = diff.abs();
    let stretch = sum - d;
    let fold = d - gap;
    let s = if stretch < fold { stretch } else { fold };
    if s.to_f64() < -tol {
        return Err(Some(s.to_f64()));
    }
    Ok([stretch, fold, gap])
}

/// The slack tolerance of a step: `tol`, or none for a step placed flat.
/// A step is placed flat at an end where it is flat (the caller's event):
/// λ is then the end's value in the arithmetic at hand, and on a deep
/// construction the step's slack there can read below any tolerance one
/// way (a 1000-step chain's, in f64, beyond 1e-10 of the scale) without
/// the step failing to close at the end itself.
fn flat_tolerance(flat: bool, tol: f64) -> f64 {
    if flat { f64::INFINITY } else { tol }
}

/// Base lengths whose reciprocal (and its double-double low part) stays a
/// normal number: outside, the apex divides as written.
const RECIPROCAL_RANGE: [f64; 2] = [1e-140, 1e140];

/// Maps `x` rigidly (rotation + translation, never a reflection) so that the
/// local points `p0`, `p1` go to `q0`, `q1` (assumed at the same distance).
fn rigid_map<T: Real>(p0: P2<T>, p1: P2<T>, q0: P2<T>, q1: P2<T>) -> impl Fn(P2<T>) -> P2<T> {
    let (a, b) = (unit(sub(p1, p0)), unit(sub(q1, q0)));
    let (c, s) = (dot(a, b), cross(a, b));
    move |x: P2<T>| {
        let r = sub(x, p0);
        [q0[0] + c * r[0] - s * r[1], q0[1] + s * r[0] + c * r[1]]
    }
}

type Shape<T> = Vec<(usize, P2<T>)>;

/// A number of the scene as read: its double-double and, where known, the
/// decimal it was written as.
pub type Written<'a> = (Dd, Option<&'a Decimal>);

/// A number the construction reads from the scene ([`Real::input`]).
#[derive(Clone, Copy, Debug)]
pub enum Input<'a> {
    /// A stated length, or a coordinate.
    Value(Written<'a>),
    /// The difference p − q of two coordinates.
    Offset([Written<'a>; 2]),
    /// A bar's drawn length (its double-double) between two joints (their
    /// coordinates, x then y).
    Distance(Dd, [[Written<'a>; 2]; 2]),
}

fn shape_pos<T: Real>(shape: &Shape<T>, joint: usize) -> P2<T> {
    shape.iter().find(|(j, _)| *j == joint).map(|&(_, p)| p).expect("joint in cluster shape")
}

/// Converts one construction's numbers into another scalar type.
impl Construction<f64> {
    /// The same construction with its numbers rounded to `U`.
    pub fn convert<U: Real>(&self) -> Construction<U> {
        self.map(U::from_f64)
    }
}

impl<T: Real> Construction<T> {
    /// The same construction with every number mapped by `c` (joints, steps and shapes unchanged).
    pub fn map<U: Real>(&self, c: impl Fn(T) -> U) -> Construction<U> {
        let members = |list: &Vec<Member<T>>| {
            list.iter().map(|m| Member { joint: m.joint, alpha: c(m.alpha), beta: c(m.beta) }).collect()
        };
        Construction {
            n_joints: self.n_joints,
            base: self.base,
            scale: self.scale,
            steps: self
                .steps
                .iter()
                .map(|s| StepGeom {
                    vertex: s.vertex,
                    u: s.u,
                    w: s.w,
                    r1: c(s.r1),
                    r2: c(s.r2),
                    sum_diff: sum_diff(c(s.r1), c(s.r2)),
                    members_u: members(&s.members_u),
                    members_w: members(&s.members_w),
                    first_reads: s.first_reads.clone(),
                })
                .collect(),
            shapes: self.shapes.iter().map(|sh| sh.iter().map(|&(j, p)| (j, [c(p[0]), c(p[1])])).collect()).collect(),
        }
    }
}

impl Construction<f64> {
    /// The same construction with every length multiplied by `f` (bar
    /// lengths, cluster shapes, the scale; members are in units of their
    /// frame and stay). With `f` a power of two every number scales exactly.
    pub fn scaled(&self, f: f64) -> Construction<f64> {
        let mut c = self.clone();
        c.scale *= f;
        for s in &mut c.steps {
            s.r1 *= f;
            s.r2 *= f;
            s.sum_diff = sum_diff(s.r1, s.r2);
        }
        for p in c.shapes.iter_mut().flatten() {
            p.1 = [p.1[0] * f, p.1[1] * f];
        }
        c
    }
}

/// Local coordinates of the clusters the steps stand on, computed up the
/// merge tree from bar lengths and body shapes; each triangle of clusters
/// takes its orientation from the drawing. A cluster made only of bars
/// without a stated length (and bodies) is the drawing itself, exactly: its
/// shape is the written coordinates, not a placement through every
/// triangle below it (whose rounding, and whose balls' radii, grow with the
/// depth of the merge tree: a strip of 100 triangles lost its realization).
/// Clusters no needed shape is built from are left empty.
fn cluster_shapes<T: Real>(linkage: &Linkage, dec: &Decomposition) -> Result<Vec<Shape<T>>, ShapeError> {
    let clusters = &dec.clusters;
    let n = clusters.nodes.len();
    // Per node: taken from the drawing, and needed (one block for both).
    const DRAWN: u8 = 1;
    const NEEDED: u8 = 2;
    let mut flags = vec![0u8; n];
    for (i, node) in clusters.nodes.iter().enumerate() {
        let drawn = match &node.origin {
            Origin::Bar(b) => !linkage.bars[*b].stated,
            Origin::Body(_) => true,
            Origin::Base | Origin::Overlap { .. } => false,
            Origin::Triangle { parts, .. } => parts.iter().all(|&c| flags[c] & DRAWN != 0),
        };
        flags[i] = if drawn { DRAWN } else { 0 };
    }
    // Needed: the steps' clusters, and what a needed merge not taken from
    // the drawing is built from (parts precede the merges they form).
    for s in &dec.steps {
        flags[s.cluster_u] |= NEEDED;
        flags[s.cluster_w] |= NEEDED;
    }
    for i in (0..n).rev() {
        if flags[i] == NEEDED {
            let parts = match &clusters.nodes[i].origin {
                Origin::Triangle { parts, .. } => &parts[..],
                Origin::Overlap { parts } => &parts[..],
                _ => &[],
            };
            parts.iter().for_each(|&c| flags[c] |= NEEDED);
        }
    }
    let mut shapes: Vec<Shape<T>> = Vec::with_capacity(n);
    for (i, node) in clusters.nodes.iter().enumerate() {
        if flags[i] & NEEDED == 0 {
            shapes.push(Vec::new());
            continue;
        }
        if flags[i] & DRAWN != 0 && node.joints.len() > 2 {
            // Relative to the first joint in double-double (exact for
            // coordinates of like size), then rounded to `T`.
            let origin = node.joints[0];
            let at = |j: usize| {
                let offset = |axis: usize| {
                    T::input(Input::Offset([linkage.coordinate(j, axis), linkage.coordinate(origin, axis)]))
                };
                [offset(0), offset(1)]
            };
            shapes.push(node.joints.iter().map(|&j| (j, at(j))).collect());
            continue;
        }
        let shape = match &node.origin {
            Origin::Bar(i) => {
                let bar = &linkage.bars[*i];
                let l = T::input(if bar.stated {
                    Input::Value((bar.exact, bar.written.as_ref()))
                } else {
                    let [p, q] = bar.joints;
                    let point = |j: usize| [linkage.coordinate(j, 0), linkage.coordinate(j, 1)];
                    Input::Distance(bar.exact, [point(p), point(q)])
                });
                vec![(bar.joints[0], [T::zero(), T::zero()]), (bar.joints[1], [l, T::zero()])]
            }
            Origin::Body(i) => {
                let point = |j: usize| [0, 1].map(|axis| T::input(Input::Value(linkage.coordinate(j, axis))));
                linkage.bodies[*i].iter().map(|&j| (j, point(j))).collect()
            }
            Origin::Base => Vec::new(),
            Origin::Triangle { parts, shared: [p, q, r] } => {
                // parts[0] ∋ r, p; parts[1] ∋ p, q; parts[2] ∋ q, r.
                let side = |c: usize, x: usize, y: usize| norm(sub(shape_pos(&shapes[c], x), shape_pos(&shapes[c], y)));
                let (pq, qr, rp) = (side(parts[1], *p, *q), side(parts[2], *q, *r), side(parts[0], *r, *p));
                let dr = |j: usize| linkage.drawn[j];
                // Through the unit vector: a product of two lengths underflows at 1e-160.
                let drawn_cross = cross(unit(sub(dr(*q), dr(*p))), sub(dr(*r), dr(*p)));
                let tp = [T::zero(), T::zero()];
                let tq = [pq, T::zero()];
                let tr =
                    apex(tp, tq, rp, qr, drawn_cross >= 0.0, tolerance::FEASIBLE * linkage.scale).map_err(|_| {
                        let n = &linkage.names;
                        ShapeError(format!(
                            "the stated lengths cannot close the triangle {}, {}, {} ({:.6}, {:.6}, {:.6})",
                            n[*p],
                            n[*q],
                            n[*r],
                            pq.to_f64(),
                            qr.to_f64(),
                            rp.to_f64()
                        ))
                    })?;
                let mut out: Shape<T> = Vec::new();
                for (c, x, y, tx, ty) in
                    [(parts[0], *r, *p, tr, tp), (parts[1], *p, *q, tp, tq), (parts[2], *q, *r, tq, tr)]
                {
                    let map = rigid_map(shape_pos(&shapes[c], x), shape_pos(&shapes[c], y), tx, ty);
                    for &(j, pos) in &shapes[c] {
                        if !out.iter().any(|(k, _)| *k == j) {
                            out.push((j, map(pos)));
                        }
                    }
                }
                out
            }
            Origin::Overlap { .. } => {
                return Err(ShapeError("over-constrained clusters have no consistent shape".into()));
            }
        };
        shapes.push(shape);
    }
    Ok(shapes)
}

impl<T: Real> Construction<T> {
    /// Fix every step's lengths and member placements.
    pub fn new(linkage: &Linkage, dec: &Decomposition) -> Result<Self, ShapeError> {
        let shapes = cluster_shapes::<T>(linkage, dec)?;
        let members = |c: usize, pivot: usize, apex_joint: usize| -> (T, Vec<Member<T>>) {
            let (p, q) = (shape_pos(&shapes[c], pivot), shape_pos(&shapes[c], apex_joint));
            let e = sub(q, p);
            let length = norm(e);
            // A two-joint cluster (a bar) has no members: no unit vector to divide out.
            if shapes[c].len() <= 2 {
                return (length, Vec::new());
            }
            // unit(e), from the norm just taken (one hypot, not two).
            let eh = [e[0] / length, e[1] / length];
            let list = shapes[c]
                .iter()
                .filter(|(j, _)| *j != pivot && *j != apex_joint)
                .map(|&(joint, pos)| {
                    let r = sub(pos, p);
                    let r = [r[0] / length, r[1] / length];
                    Member { joint, alpha: dot(r, eh), beta: cross(eh, r) }
                })
                .collect();
            (length, list)
        };
        let mut steps: Vec<StepGeom<T>> = dec
            .steps
            .iter()
            .map(|s| {
                let (r1, members_u) = members(s.cluster_u, s.u, s.vertex);
                let (r2, members_w) = members(s.cluster_w, s.w, s.vertex);
                let (vertex, u, w, sum_diff) = (s.vertex, s.u, s.w, sum_diff(r1, r2));
                let first_reads = FirstReads::default();
                StepGeom { vertex, u, w, r1, r2, sum_diff, members_u, members_w, first_reads }
            })
            .collect();
        let reads = first_reads(&steps, linkage.n_joints());
        for (s, r) in steps.iter_mut().zip(reads) {
            s.first_reads = r;
        }
        Ok(Construction { n_joints: linkage.n_joints(), base: dec.base, steps, scale: linkage.scale, shapes })
    }

    /// Position of `joint` in the local shape of cluster `cluster`.
    pub fn local(&self, cluster: usize, joint: usize) -> P2<T> {
        shape_pos(&self.shapes[cluster], joint)
    }

    /// Distance between two joints of one cluster.
    pub fn cluster_distance(&self, cluster: usize, p: usize, q: usize) -> T {
        norm(sub(self.local(cluster, q), self.local(cluster, p)))
    }

    /// (cos, sin) of the signed angle at `x` from `p − x` to `q − x` in a cluster's shape.
    pub fn cluster_angle(&self, cluster: usize, x: usize, p: usize, q: usize) -> (T, T) {
        let (a, b) =
            (sub(self.local(cluster, p), self.local(cluster, x)), sub(self.local(cluster, q), self.local(cluster, x)));
        let (a, b) = (unit(a), unit(b));
        (dot(a, b), cross(a, b))
    }

    /// Whether no step places a member (every cluster a step stands on is a
    /// bar): flipping every bit of a type then mirrors every placed joint.
    pub fn places_no_members(&self) -> bool {
        self.steps.iter().all(|s| s.members_u.is_empty() && s.members_w.is_empty())
    }

    /// Whether step `k` stands directly on the base (its base distance is λ).
    pub fn on_base(&self, k: usize) -> bool {
        let s = &self.steps[k];
        (s.u == self.base[0] && s.w == self.base[1]) || (s.u == self.base[1] && s.w == self.base[0])
    }

    /// All joint positions at base length `lambda` in type `ty`, in the base
    /// frame. Slack down to −[`tolerance::FEASIBLE`]·scale counts as flat.
    pub fn realize(&self, lambda: T, ty: &RealizationType) -> Result<Vec<P2<T>>, Unrealizable> {
        self.realize_prefix(lambda, &ty.0, self.steps.len())
    }

    /// Like [`Self::realize`] but only the first `upto` steps (`bits` needs at
    /// least that many); joints of later steps are left at the origin.
    pub fn realize_prefix(&self, lambda: T, bits: &[bool], upto: usize) -> Result<Vec<P2<T>>, Unrealizable> {
        self.realize_flat(lambda, bits, upto, &[])
    }

    /// Step `k`'s base distance d_k for the type prefix `bits` (at least `k`
    /// bits), realizing in `pos` (its allocation reused, see
    /// [`Self::base_distances_in`]) only the joints steps up to k read
    /// ([`Self::place_step`]); why not where an earlier step cannot close.
    pub fn prefix_distance_into(
        &self,
        pos: &mut Vec<P2<T>>,
        lambda: T,
        bits: &[bool],
        k: usize,
    ) -> Result<T, Unrealizable> {
        self.prefix_distance_unless(pos, lambda, bits, k, |_, _| false).map(|d| d.expect("never stopped"))
    }

    /// [`Self::prefix_distance_into`], stopped with `Ok(None)` at the first
    /// step j for which `stop(j, d_j)` holds. The certifier stops at a ball
    /// that overflowed on a step k depends on ([`Self::ancestors`]): the
    /// joints placed from it, and so d_k, would overflow too (an overflowed
    /// radius stays so through every later operation), and a long chain's
    /// balls overflow within a few dozen steps of a prefix of hundreds.
    pub fn prefix_distance_unless(
        &self,
        pos: &mut Vec<P2<T>>,
        lambda: T,
        bits: &[bool],
        k: usize,
        stop: impl Fn(usize, &T) -> bool,
    ) -> Result<Option<T>, Unrealizable> {
        let tol = tolerance::FEASIBLE * self.scale;
        self.start_into(pos, lambda);
        for (j, &plus) in bits.iter().enumerate().take(k) {
            let (dj, placed) = self.place_step(pos, j, (plus, false), tol, k);
            if stop(j, &dj) {
                return Ok(None);
            }
            placed?;
        }
        Ok(Some(self.base_distance(pos, k)))
    }

    /// The steps before step k that it depends on: those placing a joint
    /// (vertex or member) that k, or a step it depends on, reads as its u or w.
    pub fn ancestors(&self, k: usize) -> Vec<bool> {
        let mut read = vec![false; self.n_joints];
        let mut ancestors = vec![false; k];
        read[self.steps[k].u] = true;
        read[self.steps[k].w] = true;
        for j in (0..k).rev() {
            let s = &self.steps[j];
            let mut placed = std::iter::once(s.vertex).chain(s.members_u.iter().chain(&s.members_w).map(|m| m.joint));
            if placed.any(|q| read[q]) {
                ancestors[j] = true;
                read[s.u] = true;
                read[s.w] = true;
            }
        }
        ancestors
    }

    /// Realize with the steps in `flat` placed exactly flat (height zero):
    /// at an interval endpoint the flat step's height is otherwise √(rounding),
    /// and the two types meeting there would differ by that much.
    pub fn realize_flat(
        &self,
        lambda: T,
        bits: &[bool],
        upto: usize,
        flat: &[usize],
    ) -> Result<Vec<P2<T>>, Unrealizable> {
        self.realize_steps(lambda, bits, upto, flat, tolerance::FEASIBLE * self.scale, None)
    }

    /// The base distances d_0, d_1, … of type `bits` at λ, in step order, up
    /// to and including the first step that cannot close (or every step).
    /// Slack down to −[`tolerance::FEASIBLE`]·scale counts as flat, as in
    /// [`Self::realize`], so the distances continue through an exact endpoint.
    pub fn base_distances(&self, lambda: T, bits: &[bool]) -> Vec<T> {
        self.base_distances_in(&mut Vec::new(), lambda, bits)
    }

    /// [`Self::base_distances`], realizing in `scratch` (its allocation
    /// reused: a walk along a long chain realizes thousands of times, and a
    /// fresh block of positions each time cost it page faults).
    pub fn base_distances_in(&self, scratch: &mut Vec<P2<T>>, lambda: T, bits: &[bool]) -> Vec<T> {
        let mut d = Vec::with_capacity(self.steps.len());
        let tol = tolerance::FEASIBLE * self.scale;
        let n = self.steps.len();
        let _ = self.realize_steps_into(scratch, lambda, bits, (n, n), &[], tol, Some(&mut d));
        d
    }

    /// [`Self::base_distances_in`] resumed at step `from`: `pos` holds a
    /// realization at the same λ of a type whose bits before `from` are
    /// `bits`' (steps after it place their joints before later steps read
    /// them, so its later joints need not be this type's), and `d` its first
    /// `from` distances, to which the rest are pushed.
    pub fn resume_distances_in(&self, pos: &mut [P2<T>], from: usize, bits: &[bool], d: &mut Vec<T>) {
        let tol = tolerance::FEASIBLE * self.scale;
        let n = self.steps.len();
        let _ = self.steps_into(pos, from, bits, (n, n), &[], tol, Some(d));
    }

    /// [`Self::base_distances`] with the steps in `flat` placed exactly flat,
    /// up to step `upto` (included when every step before it closes; `bits`
    /// needs `upto` of them).
    pub fn base_distances_flat(&self, lambda: T, bits: &[bool], upto: usize, flat: &[usize]) -> Vec<T> {
        let mut d = Vec::with_capacity(upto + 1);
        let tol = tolerance::FEASIBLE * self.scale;
        let mut pos = Vec::new();
        if self.realize_steps_into(&mut pos, lambda, bits, (upto, upto), flat, tol, Some(&mut d)).is_ok() {
            d.push(self.base_distance(&pos, upto));
        }
        d
    }

    /// Realize with an absolute slack tolerance `tol` instead of the scaled
    /// one (for the classic fixed-tolerance baseline in `bench`).
    pub fn realize_with_tolerance(&self, lambda: T, bits: &[bool], tol: f64) -> Result<Vec<P2<T>>, Unrealizable> {
        self.realize_steps(lambda, bits, self.steps.len(), &[], tol, None)
    }

    /// The first `upto` steps, clamping slack down to `-tol` to flat; each
    /// step's base distance is pushed to `distances` before it is placed.
    fn realize_steps(
        &self,
        lambda: T,
        bits: &[bool],
        upto: usize,
        flat: &[usize],
        tol: f64,
        distances: Option<&mut Vec<T>>,
    ) -> Result<Vec<P2<T>>, Unrealizable> {
        let mut pos = Vec::new();
        self.realize_steps_into(&mut pos, lambda, bits, (upto, usize::MAX), flat, tol, distances).map(|()| pos)
    }

    /// [`Self::realize_steps`] into `pos`, which it clears first, placing
    /// only the joints steps up to `reach` read ([`Self::place_step`]).
    #[allow(clippy::too_many_arguments)]
    fn realize_steps_into(
        &self,
        pos: &mut Vec<P2<T>>,
        lambda: T,
        bits: &[bool],
        (upto, reach): (usize, usize),
        flat: &[usize],
        tol: f64,
        distances: Option<&mut Vec<T>>,
    ) -> Result<(), Unrealizable> {
        self.start_into(pos, lambda);
        self.steps_into(pos, 0, bits, (upto, reach), flat, tol, distances)
    }

    /// Steps `from` up to `upto` of [`Self::realize_steps_into`] on
    /// positions where the steps before `from` are placed.
    #[allow(clippy::too_many_arguments)]
    fn steps_into(
        &self,
        pos: &mut [P2<T>],
        from: usize,
        bits: &[bool],
        (upto, reach): (usize, usize),
        flat: &[usize],
        tol: f64,
        mut distances: Option<&mut Vec<T>>,
    ) -> Result<(), Unrealizable> {
        for (k, &plus) in bits.iter().enumerate().take(upto.min(self.steps.len())).skip(from) {
            let (dk, placed) = self.place_step(pos, k, (plus, flat.contains(&k)), tol, reach);
            if let Some(d) = distances.as_deref_mut() {
                d.push(dk);
            }
            placed?;
        }
        Ok(())
    }

    /// The joint positions before any step: base joint b at (λ, 0), every
    /// other joint at the origin.
    pub fn start(&self, lambda: T) -> Vec<P2<T>> {
        let mut pos = Vec::new();
        self.start_into(&mut pos, lambda);
        pos
    }

    /// [`Self::start`] in `pos`, its allocation reused. A block of the right
    /// size is not cleared: every joint a step reads is placed before it is
    /// read, so only the base joints are written (the others keep whatever
    /// an earlier realization left, unread).
    fn start_into(&self, pos: &mut Vec<P2<T>>, lambda: T) {
        if pos.len() != self.n_joints {
            let zero = T::zero();
            pos.clear();
            pos.resize(self.n_joints, [zero, zero]);
        }
        self.place_base(pos, lambda);
    }

    /// Base joint a at the origin and b at (λ, 0).
    pub(crate) fn place_base(&self, pos: &mut [P2<T>], lambda: T) {
        pos[self.base[0]] = [T::zero(), T::zero()];
        pos[self.base[1]] = [lambda, T::zero()];
    }

    /// Step `k` on positions where the steps before it are placed: its base
    /// distance d_k, and its vertex and members placed in `pos` (`plus` its
    /// orientation, `flat` placed exactly flat whatever its slack, other
    /// slack down to `-tol` clamped to flat), or why it cannot be (then
    /// `pos` is unchanged).
    ///
    /// Only the joints some step up to `reach` reads (as its u or w) are
    /// placed: a realization that measures base distances up to step `reach`
    /// skips the apex (a division and a square root) of a step whose joints
    /// no later step reads, and the members no later step reads; such a step
    /// is still checked to close. `usize::MAX` places every joint.
    pub fn place_step(
        &self,
        pos: &mut [P2<T>],
        k: usize,
        (plus, flat): (bool, bool),
        tol: f64,
        reach: usize,
    ) -> (T, Result<(), Unrealizable>) {
        let s = &self.steps[k];
        // One base vector and length per step: recorded, then built on.
        let e = sub(pos[s.w], pos[s.u]);
        let dk = norm(e);
        let why = |e: Option<f64>| match e {
            Some(slack) => Unrealizable::Infeasible { step: k, slack },
            None => Unrealizable::Degenerate { step: k },
        };
        if s.first_reads.apex > reach {
            return (dk, closing(dk, s.sum_diff, flat_tolerance(flat, tol)).map(|_| ()).map_err(why));
        }
        let v = match T::apex(Triangle { pu: pos[s.u], e, d: dk, sum_diff: s.sum_diff, plus, tol, flat }) {
            Ok(v) => v,
            Err(e) => return (dk, Err(why(e))),
        };
        pos[s.vertex] = v;
        // Every member read by then (the usual case): no test per member.
        let every = s.first_reads.latest_member <= reach;
        let mut reads = s.first_reads.members.iter();
        for (pivot, list) in [(s.u, &s.members_u), (s.w, &s.members_w)] {
            let p = pos[pivot];
            let e = sub(v, p);
            for m in list {
                if every || reads.next().is_none_or(|&read| read <= reach) {
                    let (a, b) = (m.alpha, m.beta);
                    let (ae, be) = (e.map(|x| x.times_constant(a)), e.map(|x| x.times_constant(b)));
                    pos[m.joint] = [p[0] + ae[0] - be[1], p[1] + ae[1] + be[0]];
                }
            }
        }
        (dk, Ok(()))
    }

    /// Base distance d_k = |u_k w_k| of step `k` in a realization (prefix).
    pub fn base_distance(&self, pos: &[P2<T>], k: usize) -> T {
        let s = &self.steps[k];
        norm(sub(pos[s.w], pos[s.u]))
    }
}

/// The drawn realization's (λ, type), and the steps that are flat in the drawing.
#[derive(Debug, Clone, PartialEq)]
pub struct Drawn {
    /// The drawn base length λ.
    pub lambda: f64,
    /// The drawn realization type.
    pub ty: RealizationType,
    /// Steps whose triangle is flat in the drawing (their bit is then a choice).
    pub flat_steps: Vec<usize>,
}

/// The drawn realization's (λ, type), read from the drawing.
pub fn drawn_realization(linkage: &Linkage, dec: &Decomposition) -> Drawn {
    let p = &linkage.drawn;
    let lambda = crate::linkage::dist(p[dec.base[0]], p[dec.base[1]]);
    let mut flat_steps = Vec::new();
    let bits = dec
        .steps
        .iter()
        .enumerate()
        .map(|(k, s)| {
            let base = sub(p[s.w], p[s.u]);
            let height = if norm(base) > 0.0 { cross(unit(base), sub(p[s.vertex], p[s.u])) } else { 0.0 };
            if height.abs() <= tolerance::DRAWN_FLAT * linkage.scale {
                flat_steps.push(k);
            }
            height >= 0.0
        })
        .collect();
    Drawn { lambda, ty: RealizationType(bits), flat_steps }
}

/// The display frame: a rigid motion that keeps the ground joints where the
/// scene drew them (one ground joint: it stays put and the base keeps its
/// drawn direction).
pub fn to_display(linkage: &Linkage, base: [usize; 2], pos: &[P2<f64>]) -> Vec<Point2<f64>> {
    let g = &linkage.ground;
    let (r0, r1, d0, d1) = if g.len() >= 2 {
        (pos[g[0]], pos[g[1]], linkage.drawn[g[0]], linkage.drawn[g[1]])
    } else {
        let anchor = g.first().copied().unwrap_or(base[0]);
        let shift = |q: P2<f64>, o: P2<f64>, d: P2<f64>| [q[0] - o[0] + d[0], q[1] - o[1] + d[1]];
        let (ra, rb) = (pos[base[0]], pos[base[1]]);
        let (da, db) = (linkage.drawn[base[0]], linkage.drawn[base[1]]);
        (pos[anchor], shift(rb, ra, pos[anchor]), linkage.drawn[anchor], shift(db, da, linkage.drawn[anchor]))
    };
    let (a, b) = (sub(r1, r0), sub(d1, d0));
    let (c, s) = if norm(a) > 0.0 && norm(b) > 0.0 {
        let (a, b) = (unit(a), unit(b));
        (dot(a, b), cross(a, b))
    } else {
        (1.0, 0.0)
    };
    pos.iter()
        .map(|&x| {
            let r = sub(x, r0);
            Point2::new(d0[0] + c * r[0] - s * r[1], d0[1] + s * r[0] + c * r[1])
        })
        .collect()
}

/// Largest |length − bar length| over all bars, and over all body edges
/// against their drawn shape, in scene units.
pub fn bar_residual(linkage: &Linkage, pos: &[Point2<f64>]) -> f64 {
    let at = |j: usize| -> P2<f64> { pos[j].into() };
    let mut worst: f64 = 0.0;
    for bar in &linkage.bars {
        let l = norm(sub(at(bar.joints[1]), at(bar.joints[0])));
        worst = worst.max((l - bar.length).abs());
    }
    for body in &linkage.bodies {
        for (i, &p) in body.iter().enumerate() {
            for &q in &body[i + 1..] {
                let drawn = norm(sub(linkage.drawn[q], linkage.drawn[p]));
                worst = worst.max((norm(sub(at(q), at(p))) - drawn).abs());
            }
        }
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A triangle placed flat at its end is placed whatever its slack: at a
    /// λ where that slack reads beyond the feasibility tolerance, the
    /// triangle fails to close unless it is the one placed flat, which goes
    /// on with height zero (in f64, balls, jets and double-double alike).
    #[test]
    fn a_step_placed_flat_closes_whatever_its_slack() {
        fn check<T: Real>(scale: f64) {
            let tol = tolerance::FEASIBLE * scale;
            let (r1, r2) = (T::from_f64(3.0 * scale), T::from_f64(4.0 * scale));
            let pu = [T::zero(), T::zero()];
            // Stretched beyond its slack tolerance: r1 + r2 = 7, the base 7 + 3·tol.
            let d = T::from_f64(7.0 * scale + 3.0 * tol);
            let e = [d, T::zero()];
            let triangle = |flat| Triangle { pu, e, d, sum_diff: sum_diff(r1, r2), plus: true, tol, flat };
            assert!(T::apex(triangle(false)).is_err(), "beyond the tolerance, scale {scale}");
            let v = T::apex(triangle(true)).expect("placed flat");
            assert_eq!(v[1].to_f64(), 0.0, "on the base line, scale {scale}");
            assert!((v[0].to_f64() - 3.0 * scale).abs() <= 1e-6 * scale, "r1 along the base, scale {scale}");
        }
        for scale in [1e-150, 1.0, 1e150] {
            check::<f64>(scale);
            check::<crate::real::Ball<f64>>(scale);
            check::<Jet<f64>>(scale);
            check::<crate::real::Dd>(scale);
        }
    }

    /// Frames enclose a step's distance over a ball of λ where an earlier
    /// step nears flat with its slack's ball straddling zero (a review's
    /// counterexample: the slope of a clamped slack dropped its radius, so
    /// the height √slack above zero was lost and the exact d_1 lay 2.5e-5
    /// outside a ball of radius 1.8e-9). Base a, b; step 0 stretched at
    /// λ = 7 (sides 3 and 4) carries c; step 1 stands on (c, b).
    #[test]
    fn frames_enclose_where_a_step_nears_flat() {
        let step = |vertex, u, w, r1: f64, r2: f64, members_u| StepGeom {
            vertex,
            u,
            w,
            r1,
            r2,
            sum_diff: sum_diff(r1, r2),
            members_u,
            members_w: Vec::new(),
            first_reads: FirstReads::default(),
        };
        let con = Construction {
            n_joints: 5,
            base: [0, 1],
            steps: vec![
                step(2, 0, 1, 3.0, 4.0, vec![Member { joint: 3, alpha: 0.5, beta: 0.5 }]),
                step(4, 3, 1, 10.0, 10.0, vec![]),
            ],
            scale: 7.0,
            shapes: vec![],
        };
        let hinges = crate::hinge::Hinges::new(&con).expect("hinged");
        let balls: Construction<crate::real::Ball<f64>> = con.map(crate::real::Ball::exact);
        let slopes = balls.map(crate::real::Slope::constant);
        let dd: Construction<crate::real::Dd> = con.map(crate::real::Dd::new);
        let bits = [true, true];
        let mut checked = 0;
        for (m, r) in [(7.0 + 1e-14, 1e-9), (7.0 + 1e-12, 1e-7), (7.0, 1e-9), (7.0 - 1e-14, 1e-9)] {
            let l = crate::real::Ball { m, r };
            let d = hinges.enclosures((&balls, &slopes), (l, &bits), (1, &[]), |_, _| false).expect("never stopped");
            for t in [-0.999, -0.5, -1e-3, 0.0, 0.5, 0.999] {
                let x = m + t * r;
                let exact = dd.base_distances_flat(crate::real::Dd::new(x), &bits, 1, &[]);
                if x > 7.0 || exact.len() < 2 {
                    continue; // step 0 does not close there
                }
                let off = (exact[1] - crate::real::Dd::new(d[1].m)).to_f64().abs();
                assert!(off <= d[1].r, "λ = {x}: d_1 = {} is {off:e} off a ball of {:e}", exact[1].to_f64(), d[1].r);
                checked += 1;
            }
        }
        assert!(checked >= 10, "{checked} points checked");
    }

    /// The jet apex's shortcut (derivatives through d alone) against the
    /// generic formula carried through jet arithmetic step by step: the same
    /// values, bit for bit, and the same derivatives to rounding, over
    /// triangles near and far from flat, both orientations, every scale.
    #[test]
    fn jet_apex_matches_the_generic_jet_formula() {
        let close = |a: f64, b: f64, size: f64| (a - b).abs() <= 1e-9 * size;
        let mut checked = 0;
        for scale in [1e-150, 1e-3, 1.0, 7.0e4, 1e150] {
            for (r1, r2) in [(1.0, 1.3), (2.0, 0.7), (1.0, 1.0), (0.45, 0.6)] {
                for t in [0.001, 0.3, 0.5, 0.77, 0.999_999] {
                    let (lo, hi) = (f64::abs(r1 - r2), r1 + r2);
                    let d = lo + (hi - lo) * t;
                    if d <= 0.0 {
                        continue;
                    }
                    // A moving base: pu and pw with slopes and curvatures.
                    let j = |v: f64, d: f64, s: f64| Jet { v: v * scale, d, s: s / scale };
                    let pu = [j(0.3, 0.2, -0.1), j(-0.4, 0.05, 0.3)];
                    let (a, b) = (0.6f64, 0.8f64);
                    let pw = [pu[0] + j(d * a, 0.7, 0.2), pu[1] + j(d * b, -0.3, 0.1)];
                    let e = sub(pw, pu);
                    let dk = norm(e);
                    let sd = sum_diff(Jet::constant(r1 * scale), Jet::constant(r2 * scale));
                    // The same base in f64 at λ-offset t (the jets' Taylor polynomials).
                    let at = |p: P2<Jet<f64>>, t: f64| p.map(|c| c.v + c.d * t + c.s * t * t / 2.0);
                    for plus in [true, false] {
                        let fast = apex_jet(Triangle { pu, e, d: dk, sum_diff: sd, plus, tol: 0.0, flat: false })
                            .expect("closes");
                        // Independent: central differences of the f64 apex (away
                        // from flat, where a step of h keeps the triangle closed).
                        let h = 1e-4 * scale;
                        let away = t > 0.1 && t < 0.9;
                        let f64_apex =
                            |t: f64| apex(at(pu, t), at(pw, t), r1 * scale, r2 * scale, plus, 0.0).expect("closes");
                        let differences = away.then(|| (f64_apex(-h), f64_apex(0.0), f64_apex(h)));
                        for (i, (a, m, b)) in (0..2).flat_map(|i| differences.map(|abc| (i, abc))) {
                            let (slope, curvature) = ((b[i] - a[i]) / (2.0 * h), (b[i] - 2.0 * m[i] + a[i]) / (h * h));
                            let size = fast[i].d.abs().max(1.0);
                            assert!(
                                (fast[i].d - slope).abs() <= 1e-4 * size,
                                "slope {} vs {slope} (scale {scale}, t {t})",
                                fast[i].d
                            );
                            let size = fast[i].s.abs().max(1.0 / scale);
                            let off = (fast[i].s - curvature).abs();
                            assert!(
                                off <= 1e-3 * size,
                                "curvature {} vs {curvature} (scale {scale}, t {t})",
                                fast[i].s
                            );
                        }
                        let slow = apex_flat(Triangle { pu, e, d: dk, sum_diff: sd, plus, tol: 0.0, flat: false })
                            .expect("closes");
                        for (f, s) in fast.iter().zip(&slow) {
                            assert_eq!(f.v, s.v, "value at scale {scale}, t {t}");
                            // The generic formula overflows in its curvature at
                            // 1e-150 (products of 1/length terms); the shortcut,
                            // dimensionless, does not: compare where it is finite.
                            if !(s.d.is_finite() && s.s.is_finite()) {
                                assert!(scale < 1e-100, "the generic jet overflowed at scale {scale}");
                                continue;
                            }
                            let (sd1, ss) = (s.d.abs().max(1.0), s.s.abs().max(1.0 / scale));
                            assert!(close(f.d, s.d, sd1), "slope {} vs {} (scale {scale}, t {t})", f.d, s.d);
                            assert!(close(f.s, s.s, ss), "curvature {} vs {} (scale {scale}, t {t})", f.s, s.s);
                            checked += 1;
                        }
                    }
                    // Forced flat: no height, and so no height derivatives.
                    let fast = apex_jet(Triangle { pu, e, d: dk, sum_diff: sd, plus: true, tol: 0.0, flat: true })
                        .expect("closes");
                    let slow = apex_flat(Triangle { pu, e, d: dk, sum_diff: sd, plus: true, tol: 0.0, flat: true })
                        .expect("closes");
                    assert!(fast.iter().zip(&slow).all(|(f, s)| f.v == s.v && close(f.d, s.d, s.d.abs().max(1.0))));
                }
            }
        }
        assert!(checked > 300, "{checked} values compared");
    }
}
