//! The exact stage: the sign of a number built from the input as written by
//! +, −, ×, ÷ and √ (with |·| and max(·, 0)), decided, down to a proven
//! zero.
//!
//! An [`Expr`] is a node of such an expression. Its sign is found by
//! evaluating the expression in fixed-point interval arithmetic at rising
//! precision (every operation rounded outwards, so each interval holds the
//! exact value): an interval that excludes zero proves the sign. One that
//! does not, once it lies within the expression's *separation bound* of
//! zero, proves the value is zero: the BFMSS bound (Burnikel, Fleischer,
//! Mehlhorn, Schirra, Schmitt) says a nonzero value E satisfies
//! |E| ≥ 1 / (u(E)^(D−1) · l(E)), where u and l bound the conjugates of a
//! numerator and a denominator of E, built up operation by operation, and
//! D bounds its algebraic degree (2 per square root). See [`Bound`].
//!
//! The bound grows with 2^(number of square roots): a question over a few
//! radicals needs a few thousand bits, one over dozens is out of reach, and
//! [`Decided::TooHard`] says so instead of guessing.
//!
//! Expressions live in a per-thread arena, so that an [`Expr`] is a `Copy`
//! handle and the solver's generic geometry ([`Real`]) builds them as it
//! builds f64 values; a [`Scope`] frees the nodes made inside it.

mod decimal;
mod fixed;

pub use decimal::Decimal;
pub(crate) use decimal::parts as decimal_parts;

use std::cell::RefCell;
use std::cmp::Ordering;
use std::ops::{Add, Div, Mul, Neg, Sub};

use num_bigint::BigInt;
use num_integer::Integer;
use num_traits::{One, Signed, Zero};

use crate::real::{Dd, Real};
use crate::realize::{Input, Written};
use fixed::{Fixed, big_to_f64};

/// A real number as an expression over the input as written (a handle into
/// this thread's arena; valid inside the [`Scope`] that made it).
#[derive(Clone, Copy, Debug)]
pub struct Expr(u32);

#[derive(Debug)]
enum Op {
    /// n / d in lowest terms, d > 0.
    Rational(BigInt, BigInt),
    Add(u32, u32),
    Sub(u32, u32),
    Mul(u32, u32),
    Div(u32, u32),
    Neg(u32),
    Sqrt(u32),
    Abs(u32),
    /// max(x, 0).
    Max0(u32),
}

/// The separation bound's parts, as base-2 logarithms (upper bounds): u
/// and l bound the conjugates of an algebraic-integer numerator and
/// denominator of the value, D its degree. The rules for n/d, a ± b, a·b,
/// a/b and √a are BFMSS's; |a| and max(a, 0) are a, −a or 0 and keep a's.
/// Raising u or l only weakens the bound, so each log is rounded up.
#[derive(Clone, Copy, Debug)]
struct Bound {
    log_u: f64,
    log_l: f64,
    log_d: f64,
}

#[derive(Debug)]
struct Node {
    op: Op,
    /// An f64 approximation (for choosing a formula; never for a decision).
    approx: f64,
    bound: Bound,
    /// Square roots in the arena up to this node: a bound on the distinct
    /// radicals below it, so log2 D never exceeds it (a DAG's shared root
    /// counts once).
    radicals: u32,
}

thread_local! {
    static NODES: RefCell<Vec<Node>> = const { RefCell::new(Vec::new()) };
}

/// While alive, the arena keeps the nodes made since it began; on drop they
/// are freed (every [`Expr`] made inside is then invalid).
#[derive(Debug)]
pub struct Scope {
    start: usize,
}

impl Scope {
    /// A scope starting at the arena's current end.
    pub fn enter() -> Scope {
        Scope { start: NODES.with_borrow(Vec::len) }
    }
}

impl Drop for Scope {
    fn drop(&mut self) {
        NODES.with_borrow_mut(|nodes| nodes.truncate(self.start));
    }
}

/// A log2 bound rounded up past the f64 rounding of its own computation.
fn up(x: f64) -> f64 {
    x + x.abs() * 1e-12 + 1e-9
}

fn push(op: Op, approx: f64, bound: Bound) -> Expr {
    NODES.with_borrow_mut(|nodes| {
        let before = nodes.last().map_or(0, |n| n.radicals);
        let radicals = before + u32::from(matches!(op, Op::Sqrt(_)));
        let bound = Bound { log_d: bound.log_d.min(f64::from(radicals)), ..bound };
        let id = u32::try_from(nodes.len()).expect("fewer than 2^32 nodes");
        nodes.push(Node { op, approx, bound, radicals });
        Expr(id)
    })
}

fn with_node<R>(e: Expr, f: impl FnOnce(&Node) -> R) -> R {
    NODES.with_borrow(|nodes| f(&nodes[e.0 as usize]))
}

/// n / d (d ≠ 0) exactly, as a leaf in lowest terms.
fn rational(n: BigInt, d: BigInt) -> Expr {
    assert!(!d.is_zero(), "a rational with a zero denominator");
    let g = n.gcd(&d);
    let (mut n, mut d) = if g.is_zero() { (n, d) } else { (n / &g, d / &g) };
    if d.is_negative() {
        (n, d) = (-n, -d);
    }
    let approx = ratio_to_f64(&n, &d);
    let bound = Bound { log_u: n.bits() as f64, log_l: d.bits() as f64, log_d: 0.0 };
    push(Op::Rational(n, d), approx, bound)
}

/// n / d to about f64 precision, without over- or underflowing in between.
fn ratio_to_f64(n: &BigInt, d: &BigInt) -> f64 {
    let p = (64 + d.bits() as i64 - n.bits() as i64).max(0) as u64;
    big_to_f64(&(n << p).div_floor(d), p)
}

/// The leaf's rational, if `e` is one.
fn leaf(e: Expr) -> Option<(BigInt, BigInt)> {
    with_node(e, |n| match &n.op {
        Op::Rational(a, b) => Some((a.clone(), b.clone())),
        _ => None,
    })
}

fn approx(e: Expr) -> f64 {
    with_node(e, |n| n.approx)
}

fn bound(e: Expr) -> Bound {
    with_node(e, |n| n.bound)
}

impl Expr {
    /// A decimal as written, exactly.
    pub fn decimal(x: &Decimal) -> Expr {
        let (n, d) = x.rational();
        rational(n, d)
    }

    /// An f64, exactly (a dyadic rational).
    pub fn f64(x: f64) -> Expr {
        assert!(x.is_finite(), "an exact value must be finite");
        let (n, d) = dyadic(x);
        rational(n, d)
    }

    /// The rational value, where `self` is a leaf.
    pub fn as_rational(self) -> Option<(BigInt, BigInt)> {
        leaf(self)
    }

    fn unary(self, op: fn(u32) -> Op, approx: f64, bound: Bound) -> Expr {
        push(op(self.0), approx, bound)
    }

    /// The value's sign, decided: see [`sign`].
    pub fn sign(self) -> Decided {
        sign(self).0
    }
}

/// An f64 as n / 2^k.
fn dyadic(x: f64) -> (BigInt, BigInt) {
    if x == 0.0 {
        return (BigInt::zero(), BigInt::one());
    }
    let bits = x.to_bits();
    let exponent = ((bits >> 52) & 0x7ff) as i64;
    let fraction = bits & ((1 << 52) - 1);
    let (mantissa, e) = if exponent == 0 { (fraction, -1074) } else { (fraction | 1 << 52, exponent - 1075) };
    let n = BigInt::from(mantissa) * if x < 0.0 { -1 } else { 1 };
    if e >= 0 { (n << e as u64, BigInt::one()) } else { (n, BigInt::one() << (-e) as u64) }
}

fn binary(a: Expr, b: Expr, op: fn(u32, u32) -> Op, approx: f64, bound: Bound) -> Expr {
    push(op(a.0, b.0), approx, bound)
}

/// The bound of a ± b.
fn sum_bound(a: Bound, b: Bound) -> Bound {
    Bound {
        log_u: up((a.log_u + b.log_l).max(a.log_l + b.log_u) + 1.0),
        log_l: up(a.log_l + b.log_l),
        log_d: a.log_d + b.log_d,
    }
}

impl Add for Expr {
    type Output = Expr;
    fn add(self, o: Expr) -> Expr {
        if let (Some((a, b)), Some((c, d))) = (leaf(self), leaf(o)) {
            return rational(a * &d + c * &b, b * d);
        }
        binary(self, o, Op::Add, approx(self) + approx(o), sum_bound(bound(self), bound(o)))
    }
}

impl Sub for Expr {
    type Output = Expr;
    fn sub(self, o: Expr) -> Expr {
        if self.0 == o.0 {
            return rational(BigInt::zero(), BigInt::one());
        }
        if let (Some((a, b)), Some((c, d))) = (leaf(self), leaf(o)) {
            return rational(a * &d - c * &b, b * d);
        }
        binary(self, o, Op::Sub, approx(self) - approx(o), sum_bound(bound(self), bound(o)))
    }
}

impl Mul for Expr {
    type Output = Expr;
    fn mul(self, o: Expr) -> Expr {
        if let (Some((a, b)), Some((c, d))) = (leaf(self), leaf(o)) {
            return rational(a * c, b * d);
        }
        let (x, y) = (bound(self), bound(o));
        let bound = Bound { log_u: up(x.log_u + y.log_u), log_l: up(x.log_l + y.log_l), log_d: x.log_d + y.log_d };
        binary(self, o, Op::Mul, approx(self) * approx(o), bound)
    }
}

impl Div for Expr {
    type Output = Expr;
    fn div(self, o: Expr) -> Expr {
        if let (Some((a, b)), Some((c, d))) = (leaf(self), leaf(o))
            && !c.is_zero()
        {
            return rational(a * d, b * c);
        }
        let (x, y) = (bound(self), bound(o));
        let bound = Bound { log_u: up(x.log_u + y.log_l), log_l: up(x.log_l + y.log_u), log_d: x.log_d + y.log_d };
        binary(self, o, Op::Div, approx(self) / approx(o), bound)
    }
}

impl Neg for Expr {
    type Output = Expr;
    fn neg(self) -> Expr {
        if let Some((a, b)) = leaf(self) {
            return rational(-a, b);
        }
        self.unary(Op::Neg, -approx(self), bound(self))
    }
}

impl PartialEq for Expr {
    /// The same node, or two leaves of the same rational: equal for sure.
    /// Anything else compares unequal here (only an exact zero component
    /// is asked about, in [`Real::hypot`]); decide equality with [`sign`].
    fn eq(&self, o: &Expr) -> bool {
        self.0 == o.0 || leaf(*self).is_some_and(|x| leaf(*o) == Some(x))
    }
}

impl PartialOrd for Expr {
    /// By approximation: only for choosing among formulas that are equal in
    /// exact arithmetic, never for a decision.
    fn partial_cmp(&self, o: &Expr) -> Option<Ordering> {
        approx(*self).partial_cmp(&approx(*o))
    }
}

impl Real for Expr {
    /// The resolution of the approximations that choose formulas.
    const UNIT_ROUNDOFF: f64 = f64::EPSILON / 2.0;
    fn from_f64(x: f64) -> Self {
        Expr::f64(x)
    }
    /// The double-double's own value, exactly.
    fn from_dd(x: Dd) -> Self {
        Expr::f64(x.hi) + Expr::f64(x.lo)
    }
    /// The decimals as written (a value's own double-double where none is known).
    fn input(x: Input) -> Self {
        let value = |(dd, written): Written| written.map_or_else(|| Expr::from_dd(dd), Expr::decimal);
        match x {
            Input::Value(v) => value(v),
            Input::Offset([p, q]) => value(p) - value(q),
            Input::Distance(_, [p, q]) => Expr::hypot(value(p[0]) - value(q[0]), value(p[1]) - value(q[1])),
        }
    }
    /// Evaluated to at most [`BRANCH_BITS`]: a branch decision out of that
    /// reach is cheaper said than chased (its caller then has no proof
    /// either way).
    fn proven_sign(self) -> Option<i8> {
        match sign_within(self, BRANCH_BITS).0 {
            Decided::Sign(s) => Some(s),
            Decided::Undefined | Decided::TooHard => None,
        }
    }
    fn to_f64(self) -> f64 {
        approx(self)
    }
    fn sqrt(self) -> Self {
        let b = bound(self);
        let half = up((b.log_u + b.log_l) / 2.0);
        let bound = if b.log_u >= b.log_l {
            Bound { log_u: half, log_l: b.log_l, log_d: b.log_d + 1.0 }
        } else {
            Bound { log_u: b.log_u, log_l: half, log_d: b.log_d + 1.0 }
        };
        self.unary(Op::Sqrt, approx(self).max(0.0).sqrt(), bound)
    }
    fn abs(self) -> Self {
        if let Some((a, b)) = leaf(self) {
            return rational(a.abs(), b);
        }
        self.unary(Op::Abs, approx(self).abs(), bound(self))
    }
    fn clamp_nonneg(self) -> Self {
        if let Some((a, b)) = leaf(self) {
            return rational(a.max(BigInt::zero()), b);
        }
        self.unary(Op::Max0, approx(self).max(0.0), bound(self))
    }
    fn clamp_nonneg_plain(self) -> Self {
        self.clamp_nonneg()
    }
    /// √(x² + y²) as written (no scaling: nothing over- or underflows).
    fn hypot(x: Self, y: Self) -> Self {
        let zero = Expr::f64(0.0);
        if y == zero {
            x.abs()
        } else if x == zero {
            y.abs()
        } else {
            // The approximation as f64 computes a hypot: the squares' own
            // approximations may under- or overflow.
            let h = (x * x + y * y).sqrt();
            let approx = approx(x).hypot(approx(y));
            NODES.with_borrow_mut(|nodes| nodes[h.0 as usize].approx = approx);
            h
        }
    }
}

/// A decided sign.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Decided {
    /// Proven negative, zero or positive (−1, 0, 1).
    Sign(i8),
    /// The expression has no real value: a square root of a proven negative.
    Undefined,
    /// Not decided: the separation bound is past [`MAX_BITS`] (or the
    /// evaluation needed more than four times the bound).
    TooHard,
}

/// The largest separation bound (in bits) the exact stage evaluates to:
/// 2^16 bits keep one evaluation of a few hundred nodes within tens of
/// milliseconds. A bound past it says the question is out of reach, not
/// what its answer is.
pub const MAX_BITS: u64 = 1 << 16;

/// Where the bound is out of reach, the precision evaluated to before
/// saying so (values this far from zero are still decided).
pub const UNBOUNDED_BITS: u64 = 4096;

/// The most precision a branch decision ([`Real::proven_sign`]) is
/// evaluated to before saying it is out of reach.
pub const BRANCH_BITS: u64 = 4096;

/// The precision the exact stage starts at (bits after the binary point).
const START_BITS: u64 = 128;

/// What deciding a sign took: the last precision evaluated and the
/// separation bound in bits (`None` where it is past [`MAX_BITS`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Effort {
    /// Bits after the binary point of the last evaluation.
    pub precision: u64,
    /// −log2 of the separation bound, where within reach.
    pub bound_bits: Option<u64>,
}

/// The sign of `e`, decided: evaluations at 128, 256, 512, … bits until
/// the interval excludes zero (the sign) or lies within the separation
/// bound (zero); [`Decided::TooHard`] where that bound is past [`MAX_BITS`]
/// and [`UNBOUNDED_BITS`] did not separate the value from zero.
pub fn sign(e: Expr) -> (Decided, Effort) {
    sign_within(e, u64::MAX)
}

/// [`sign`], evaluating to at most `ceiling` bits.
fn sign_within(e: Expr, ceiling: u64) -> (Decided, Effort) {
    if let Some((n, _)) = leaf(e) {
        return (Decided::Sign(n.signum().try_into().expect("a sign")), Effort { precision: 0, bound_bits: Some(0) });
    }
    let b = bound(e);
    let bits = (b.log_d < 40.0)
        .then(|| (2f64.powf(b.log_d) - 1.0) * b.log_u + b.log_l)
        .filter(|&x| x < MAX_BITS as f64)
        .map(|x| up(x).ceil() as u64);
    let mut p = START_BITS;
    // The evaluation's own losses grow with depth: go some way past the bound.
    let last = bits.map_or(UNBOUNDED_BITS, |bits| (4 * bits + START_BITS).clamp(UNBOUNDED_BITS, 4 * MAX_BITS));
    let last = last.min(ceiling);
    loop {
        match evaluate(e, p) {
            Err(Undefined) => return (Decided::Undefined, Effort { precision: p, bound_bits: bits }),
            Ok(Some(x)) => {
                if let Some(s) = x.sign() {
                    return (Decided::Sign(s), Effort { precision: p, bound_bits: bits });
                }
                if bits.is_some_and(|bits| x.within(bits, p)) {
                    return (Decided::Sign(0), Effort { precision: p, bound_bits: bits });
                }
            }
            Ok(None) => {}
        }
        if p >= last {
            return (Decided::TooHard, Effort { precision: p, bound_bits: bits });
        }
        p = (2 * p).min(last);
    }
}

/// `e`'s value to double-double precision (relative 2^-104 or better),
/// from evaluations at rising precision; exactly 0 where the value is
/// proven zero. `None` where it has no value or its sign is out of reach.
pub fn approximate(e: Expr) -> Option<Dd> {
    match sign(e).0 {
        Decided::Sign(0) => return Some(Dd::new(0.0)),
        Decided::Sign(_) => {}
        Decided::Undefined | Decided::TooHard => return None,
    }
    let mut p = START_BITS;
    loop {
        if let Ok(Some(x)) = evaluate(e, p)
            && x.sign().is_some()
        {
            let magnitude = x.lo.abs().min(x.hi.abs());
            if (&x.hi - &x.lo) << 110u32 <= magnitude {
                let mid = (&x.lo + &x.hi) >> 1u32;
                let hi = big_to_f64(&mid, p);
                let (n, d) = dyadic(hi);
                let rest = &mid - Fixed::rational(&n, &d, p).lo;
                return Some(Dd::new(hi) + Dd::new(big_to_f64(&rest, p)));
            }
        }
        if p >= 4 * MAX_BITS {
            return None;
        }
        p *= 2;
    }
}

/// A square root of a proven negative number met while evaluating.
struct Undefined;

/// The interval of `e` at precision `p`: `Ok(None)` where a divisor's
/// interval held zero (a finer precision may separate it).
fn evaluate(e: Expr, p: u64) -> Result<Option<Fixed>, Undefined> {
    NODES.with_borrow(|nodes| {
        let top = e.0 as usize;
        // The nodes `e` reads (children precede parents in the arena).
        let mut needed = vec![false; top + 1];
        needed[top] = true;
        let mut first = top;
        for i in (0..=top).rev() {
            if !needed[i] {
                continue;
            }
            first = i;
            let mut mark = |c: u32| needed[c as usize] = true;
            match nodes[i].op {
                Op::Rational(..) => {}
                Op::Add(a, b) | Op::Sub(a, b) | Op::Mul(a, b) | Op::Div(a, b) => {
                    mark(a);
                    mark(b);
                }
                Op::Neg(a) | Op::Sqrt(a) | Op::Abs(a) | Op::Max0(a) => mark(a),
            }
        }
        let mut values: Vec<Option<Fixed>> = vec![None; top + 1 - first];
        for i in first..=top {
            if !needed[i] {
                continue;
            }
            let v = |c: u32| values[c as usize - first].as_ref().expect("children first");
            let x = match &nodes[i].op {
                Op::Rational(n, d) => Fixed::rational(n, d, p),
                Op::Add(a, b) => v(*a).add(v(*b)),
                Op::Sub(a, b) => v(*a).sub(v(*b)),
                Op::Mul(a, b) => v(*a).mul(v(*b), p),
                Op::Div(a, b) => match v(*a).div(v(*b), p) {
                    Some(x) => x,
                    None => return Ok(None),
                },
                Op::Neg(a) => v(*a).neg(),
                Op::Sqrt(a) => v(*a).sqrt(p).ok_or(Undefined)?,
                Op::Abs(a) => v(*a).abs(),
                Op::Max0(a) => v(*a).clamp_nonneg(),
            };
            values[i - first] = Some(x);
        }
        Ok(values.pop().flatten())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn int(n: i64) -> Expr {
        Expr::decimal(&Decimal::integer(n))
    }

    fn dec(text: &str) -> Expr {
        Expr::decimal(&Decimal::parse(text).unwrap())
    }

    /// Expressions known to be zero decide zero; ones 1e-40 (and 1e-300)
    /// from zero decide their sign, either side.
    #[test]
    fn zero_bound_decides_zero_and_near_zero() {
        let _scope = Scope::enter();
        // √2·√3 − √6.
        let e = int(2).sqrt() * int(3).sqrt() - int(6).sqrt();
        assert_eq!(e.sign(), Decided::Sign(0));
        // φ² − φ − 1 with φ = (1 + √5)/2.
        let phi = (int(1) + int(5).sqrt()) / int(2);
        assert_eq!((phi * phi - phi - int(1)).sign(), Decided::Sign(0));
        // The same, 1e-40 off either way.
        for (off, s) in [("1e-40", 1), ("-1e-40", -1), ("1e-300", 1)] {
            let e = int(2).sqrt() * int(3).sqrt() - int(6).sqrt() + dec(off);
            assert_eq!(e.sign(), Decided::Sign(s), "{off}");
            let e = phi * phi - phi - int(1) - dec(off);
            assert_eq!(e.sign(), Decided::Sign(-s), "{off}");
        }
        // Decimals as written: 0.1 + 0.2 − 0.3 is zero (in f64 it is not).
        assert_eq!((dec("0.1") + dec("0.2") - dec("0.3")).sign(), Decided::Sign(0));
        assert_eq!((Expr::f64(0.1) + Expr::f64(0.2) - Expr::f64(0.3)).sign(), Decided::Sign(1));
        // Nested radicals: √(3 + 2√2) = 1 + √2, and a hypot through Real.
        let nested = (int(3) + int(2) * int(2).sqrt()).sqrt() - int(1) - int(2).sqrt();
        assert_eq!(nested.sign(), Decided::Sign(0));
        let h = <Expr as Real>::hypot(dec("0.3"), dec("0.4")) - dec("0.5");
        assert_eq!(h.sign(), Decided::Sign(0));
        assert_eq!(<Expr as Real>::hypot(dec("-2.5"), int(0)).as_rational(), dec("2.5").as_rational());
    }

    /// Random identities (√a + √b)² = a + b + 2√(ab) over decimals as
    /// written decide zero; the same shifted by ±2^-k (k up to 400) decide
    /// the shift's sign. A deterministic generator: no test dependency.
    #[test]
    fn random_identities_and_their_shifts() {
        let _scope = Scope::enter();
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = |m: u64| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state % m
        };
        for _ in 0..200 {
            let a = dec(&format!("{}.{:03}", next(1000), next(1000)));
            let b = dec(&format!("{}.{:03}", 1 + next(1000), next(1000)));
            let lhs = (a.sqrt() + b.sqrt()) * (a.sqrt() + b.sqrt());
            let zero = lhs - (a + b + int(2) * (a * b).sqrt());
            assert_eq!(zero.sign(), Decided::Sign(0));
            let k = 1 + next(400) as i32;
            let s = if next(2) == 0 { 1 } else { -1 };
            let shifted = zero + Expr::f64(f64::from(s) * 2f64.powi(-k));
            assert_eq!(shifted.sign(), Decided::Sign(s as i8), "2^-{k}");
        }
    }

    /// A square root of a proven negative has no value; |·| and max(·, 0)
    /// of a zero expression stay zero.
    #[test]
    fn undefined_and_clamped() {
        let _scope = Scope::enter();
        let zero = int(2).sqrt() * int(2).sqrt() - int(2);
        assert_eq!(zero.sign(), Decided::Sign(0));
        assert_eq!((zero - int(1)).sqrt().sign(), Decided::Undefined);
        assert_eq!(zero.abs().sign(), Decided::Sign(0));
        assert_eq!((zero - dec("1e-30")).clamp_nonneg().sign(), Decided::Sign(0));
        assert_eq!((zero - dec("1e-30")).abs().sign(), Decided::Sign(1));
    }

    /// A bound past the budget says so rather than guessing: y − y·1 over
    /// 41 nested square roots is zero, but no bound within reach proves it;
    /// the same 2^-3000 off is decided by evaluation alone.
    #[test]
    fn out_of_reach_is_said() {
        let _scope = Scope::enter();
        let mut x = int(2);
        for _ in 0..41 {
            x = x.sqrt() + int(1);
        }
        let y = x * x - x;
        let (decided, effort) = sign(y - y * int(1));
        assert_eq!(decided, Decided::TooHard);
        assert_eq!((effort.bound_bits, effort.precision), (None, UNBOUNDED_BITS));
        let tiny = Expr::f64(2f64.powi(-1000)) * Expr::f64(2f64.powi(-1000)) * Expr::f64(2f64.powi(-1000));
        assert_eq!((y - y * int(1) + tiny).sign(), Decided::Sign(1));
    }

    /// Values to double-double precision, at any scale; a proven zero is 0.
    #[test]
    fn approximations_reach_double_double() {
        let _scope = Scope::enter();
        let root2 = Dd::new(std::f64::consts::SQRT_2) + Dd::new(-9.667293313452913e-17);
        for text in ["1", "1e-200", "1e200", "0.1"] {
            let x = approximate(int(2).sqrt() * dec(text)).expect("a value");
            let want = root2 * approximate(dec(text)).expect("a decimal");
            assert!(((x - want) / want).to_f64().abs() < 1e-30, "{text}: {x:?}");
        }
        // Past double-double's range its low part underflows; the high part stays right.
        let tiny = approximate(int(2).sqrt() * dec("1e-300")).expect("a value");
        assert!((tiny.hi / (std::f64::consts::SQRT_2 * 1e-300) - 1.0).abs() < 1e-15);
        let zero = int(2).sqrt() * int(3).sqrt() - int(6).sqrt();
        assert_eq!(approximate(zero), Some(Dd::new(0.0)));
        assert_eq!(approximate((zero - int(1)).sqrt()), None);
    }

    /// A scope frees its nodes; handles made before it stay valid.
    #[test]
    fn scopes_free_their_nodes() {
        let outer = Scope::enter();
        let kept = int(7).sqrt();
        let before = NODES.with_borrow(Vec::len);
        {
            let _inner = Scope::enter();
            let _ = int(3).sqrt() + kept;
            assert!(NODES.with_borrow(Vec::len) > before);
        }
        assert_eq!(NODES.with_borrow(Vec::len), before);
        assert_eq!((kept * kept - int(7)).sign(), Decided::Sign(0));
        drop(outer);
    }

    /// Exact values of f64s and double-doubles; approximations are f64-close.
    #[test]
    fn leaves_and_approximations() {
        let _scope = Scope::enter();
        assert_eq!(Expr::f64(0.75).as_rational(), Some((BigInt::from(3), BigInt::from(4))));
        assert_eq!(Expr::f64(-3.0 * 2f64.powi(-1074)).as_rational(), Some((BigInt::from(-3), BigInt::one() << 1074)));
        let x = dec("1e-300") * dec("3");
        assert!((x.to_f64() - 3e-300).abs() < 1e-315);
        assert!((int(2).sqrt().to_f64() - std::f64::consts::SQRT_2).abs() < 1e-15);
        assert!((dec("1e300") * dec("1e10")).to_f64().is_infinite());
    }
}
