//! Interval arithmetic with outward rounding, and second-order interval
//! jets ([`Dual`]): the arithmetic of proofs (the certified closest pair).
//!
//! Every operation rounds its result to nearest and then widens each bound by
//! one ulp (`f64::next_down` / `next_up`): a correctly rounded result is within
//! half an ulp of the exact one, so the exact result of the operation on any
//! points of the operands lies in the returned interval. Unbounded results
//! are `[-∞, ∞]`; no interval holds NaN.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// A closed interval `[lo, hi]` of reals (bounds may be infinite).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    /// Lower bound.
    pub lo: f64,
    /// Upper bound.
    pub hi: f64,
}

impl Interval {
    /// All reals: what an operation returns when it cannot bound its result.
    pub const ENTIRE: Interval = Interval { lo: f64::NEG_INFINITY, hi: f64::INFINITY };
    /// The point 0.
    pub const ZERO: Interval = Interval { lo: 0.0, hi: 0.0 };

    /// `[lo, hi]`; a NaN bound becomes the infinite one (nothing is known).
    pub fn new(lo: f64, hi: f64) -> Interval {
        Interval {
            lo: if lo.is_nan() { f64::NEG_INFINITY } else { lo },
            hi: if hi.is_nan() { f64::INFINITY } else { hi },
        }
    }

    /// The exact number `x` (an f64 is a real number).
    pub fn point(x: f64) -> Interval {
        Interval::new(x, x)
    }

    /// Round-to-nearest bounds widened by one ulp each: encloses the exact result.
    fn outward(lo: f64, hi: f64) -> Interval {
        Interval::new(lo.next_down(), hi.next_up())
    }

    /// The smallest interval holding both.
    pub fn hull(self, o: Interval) -> Interval {
        Interval { lo: self.lo.min(o.lo), hi: self.hi.max(o.hi) }
    }

    /// The common part of two enclosures of the same quantity (both hold it,
    /// so the intersection does; an empty one cannot happen and gives `self`).
    pub fn intersect(self, o: Interval) -> Interval {
        let (lo, hi) = (self.lo.max(o.lo), self.hi.min(o.hi));
        if lo <= hi { Interval { lo, hi } } else { self }
    }

    /// Whether 0 lies in the interval (bounds included).
    pub fn contains_zero(self) -> bool {
        self.lo <= 0.0 && self.hi >= 0.0
    }

    /// Largest |x| over the interval.
    pub fn mag(self) -> f64 {
        self.lo.abs().max(self.hi.abs())
    }

    /// 2x, exactly.
    pub fn twice(self) -> Interval {
        Interval { lo: 2.0 * self.lo, hi: 2.0 * self.hi }
    }

    /// Upper bound of the width `hi − lo`.
    pub fn width(self) -> f64 {
        (self.hi - self.lo).next_up()
    }

    /// The point nearest the middle (a member of the interval when it is bounded).
    pub fn mid(self) -> f64 {
        let m = self.lo + (self.hi - self.lo) / 2.0;
        m.clamp(self.lo, self.hi)
    }

    /// x² (tight: never negative).
    pub fn sqr(self) -> Interval {
        let (a, b) = (self.lo.abs(), self.hi.abs());
        let lo = if self.contains_zero() { 0.0 } else { (a.min(b) * a.min(b)).next_down().max(0.0) };
        Interval::new(lo, (a.max(b) * a.max(b)).next_up())
    }

    /// |x|.
    pub fn abs(self) -> Interval {
        if self.lo >= 0.0 {
            self
        } else if self.hi <= 0.0 {
            -self
        } else {
            Interval { lo: 0.0, hi: self.mag() }
        }
    }

    /// max(x, 0): the part of an enclosure that can be a length or a slack.
    pub fn clamp_nonneg(self) -> Interval {
        Interval { lo: self.lo.max(0.0), hi: self.hi.max(0.0) }
    }

    /// √max(x, 0) (square roots are taken of quantities known to be ≥ 0 at
    /// every point the enclosure stands for).
    pub fn sqrt(self) -> Interval {
        let c = self.clamp_nonneg();
        Interval::new(c.lo.sqrt().next_down().max(0.0), c.hi.sqrt().next_up())
    }

    /// Whether some operand was unbounded (or NaN slipped in).
    pub fn is_bounded(self) -> bool {
        self.lo.is_finite() && self.hi.is_finite()
    }
}

impl Add for Interval {
    type Output = Interval;
    fn add(self, o: Interval) -> Interval {
        Interval::outward(self.lo + o.lo, self.hi + o.hi)
    }
}

impl Sub for Interval {
    type Output = Interval;
    fn sub(self, o: Interval) -> Interval {
        Interval::outward(self.lo - o.hi, self.hi - o.lo)
    }
}

impl Neg for Interval {
    type Output = Interval;
    fn neg(self) -> Interval {
        Interval { lo: -self.hi, hi: -self.lo }
    }
}

impl Mul for Interval {
    type Output = Interval;
    fn mul(self, o: Interval) -> Interval {
        if self == Interval::ZERO || o == Interval::ZERO {
            return Interval::ZERO;
        }
        // A NaN product is 0 × ∞ (an infinite bound stands for an unknown
        // finite value): min/max skip it, and the same zero bound times the
        // other factor's finite bound (or an infinite one) covers it.
        let (a, b, c, d) = (self.lo * o.lo, self.lo * o.hi, self.hi * o.lo, self.hi * o.hi);
        Interval::outward(a.min(b).min(c.min(d)), a.max(b).max(c.max(d)))
    }
}

impl Div for Interval {
    type Output = Interval;
    /// Unbounded when the divisor may be zero.
    fn div(self, o: Interval) -> Interval {
        if o.contains_zero() {
            return Interval::ENTIRE;
        }
        let c = [self.lo / o.lo, self.lo / o.hi, self.hi / o.lo, self.hi / o.hi];
        if c.iter().any(|x| x.is_nan()) {
            return Interval::ENTIRE;
        }
        let lo = c.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = c.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        Interval::outward(lo, hi)
    }
}

/// A quantity with its first and second derivatives along one parameter, all
/// three enclosed over a box of that parameter: `v` holds every value, `d`
/// every first and `dd` every second derivative at the box's points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dual {
    /// Every value over the box.
    pub v: Interval,
    /// Every first derivative over the box.
    pub d: Interval,
    /// Every second derivative over the box.
    pub dd: Interval,
}

impl Dual {
    /// A constant (derivatives zero).
    pub fn constant(x: Interval) -> Dual {
        Dual { v: x, d: Interval::ZERO, dd: Interval::ZERO }
    }

    /// Whether both derivatives are exactly zero.
    pub fn is_constant(self) -> bool {
        self.d == Interval::ZERO && self.dd == Interval::ZERO
    }

    /// The parameter itself over `x`.
    pub fn variable(x: Interval) -> Dual {
        Dual { v: x, d: Interval::point(1.0), dd: Interval::ZERO }
    }

    /// The same quantity differentiated along another parameter `s`, given
    /// enclosures of dp/ds and d²p/ds² of this parameter p (chain rule:
    /// x_s = x_p·p_s, x_ss = x_pp·p_s² + x_p·p_ss).
    pub fn chain(self, p_s: Interval, p_ss: Interval) -> Dual {
        Dual { v: self.v, d: self.d * p_s, dd: self.dd * p_s.sqr() + self.d * p_ss }
    }

    /// The square, with its derivatives by the chain rule.
    pub fn sqr(self) -> Dual {
        Dual { v: self.v.sqr(), d: (self.v * self.d).twice(), dd: (self.d.sqr() + self.v * self.dd).twice() }
    }

    /// √x; the derivatives (r' = x'/2r, r'' = (x'' − 2r'²)/2r) are unbounded
    /// where x may vanish.
    pub fn sqrt(self) -> Dual {
        let v = self.v.sqrt();
        let two_v = v.twice();
        let d = self.d / two_v;
        Dual { v, d, dd: (self.dd - d.sqr().twice()) / two_v }
    }

    /// max(x, 0) for a quantity that is ≥ 0 at every point it stands for:
    /// the value is clamped, the derivatives are the quantity's own.
    pub fn clamp_nonneg(self) -> Dual {
        Dual { v: self.v.clamp_nonneg(), ..self }
    }

    /// Componentwise intersection of two enclosures of the same quantity.
    pub fn intersect(self, o: Dual) -> Dual {
        Dual { v: self.v.intersect(o.v), d: self.d.intersect(o.d), dd: self.dd.intersect(o.dd) }
    }

    /// √(x² + y²).
    pub fn hypot(x: Dual, y: Dual) -> Dual {
        (x.sqr() + y.sqr()).sqrt()
    }
}

impl Add for Dual {
    type Output = Dual;
    fn add(self, o: Dual) -> Dual {
        Dual { v: self.v + o.v, d: self.d + o.d, dd: self.dd + o.dd }
    }
}

impl Sub for Dual {
    type Output = Dual;
    fn sub(self, o: Dual) -> Dual {
        Dual { v: self.v - o.v, d: self.d - o.d, dd: self.dd - o.dd }
    }
}

impl Neg for Dual {
    type Output = Dual;
    fn neg(self) -> Dual {
        Dual { v: -self.v, d: -self.d, dd: -self.dd }
    }
}

impl Mul for Dual {
    type Output = Dual;
    fn mul(self, o: Dual) -> Dual {
        if o.is_constant() {
            return Dual { v: self.v * o.v, d: self.d * o.v, dd: self.dd * o.v };
        }
        if self.is_constant() {
            return Dual { v: self.v * o.v, d: self.v * o.d, dd: self.v * o.dd };
        }
        Dual {
            v: self.v * o.v,
            d: self.d * o.v + self.v * o.d,
            dd: self.dd * o.v + (self.d * o.d).twice() + self.v * o.dd,
        }
    }
}

impl Div for Dual {
    type Output = Dual;
    /// q = a/b: q' = (a' − q b')/b, q'' = (a'' − 2q'b' − q b'')/b.
    fn div(self, o: Dual) -> Dual {
        if o.is_constant() {
            return Dual { v: self.v / o.v, d: self.d / o.v, dd: self.dd / o.v };
        }
        let q = self.v / o.v;
        let d = (self.d - q * o.d) / o.v;
        Dual { v: q, d, dd: (self.dd - (d * o.d).twice() - q * o.dd) / o.v }
    }
}

/// What the construction needs of a number type: the field operations,
/// squares and square roots, and the enclosure of its value.
pub trait Arith:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self> + Neg<Output = Self>
{
    /// A constant known to lie in `x`.
    fn constant(x: Interval) -> Self;
    /// The square.
    fn sqr(self) -> Self;
    /// The square root (of the part ≥ 0 for an interval reaching below 0).
    fn sqrt(self) -> Self;
    /// max(x, 0) for a quantity that is ≥ 0 at every point it stands for.
    fn clamp_nonneg(self) -> Self;
    /// Every value the quantity takes.
    fn value(self) -> Interval;
    /// √(x² + y²).
    fn hypot(x: Self, y: Self) -> Self {
        (x.sqr() + y.sqr()).sqrt()
    }
}

impl Arith for Dual {
    fn constant(x: Interval) -> Self {
        Dual::constant(x)
    }
    fn sqr(self) -> Self {
        Dual::sqr(self)
    }
    fn sqrt(self) -> Self {
        Dual::sqrt(self)
    }
    fn clamp_nonneg(self) -> Self {
        Dual::clamp_nonneg(self)
    }
    fn value(self) -> Interval {
        self.v
    }
}

/// A jet over a box of the parameter, kept centred: `c` holds the jet at the
/// box's centre, `b` over the whole box, and `s` encloses the parameter's
/// offset from the centre. After every operation the box jet is tightened
/// by the Taylor forms
///
/// ```text
///     x'(box) ⊆ x'(c) + x''(box)·s
///     x(box)  ⊆ x(c) + x'(box)·s  and  x(c) + x'(c)·s + x''(box)·s²/2,
/// ```
///
/// so the dependencies between intermediate quantities (which plain
/// interval arithmetic forgets, overestimating by orders of magnitude over a
/// chain of constructions) are kept to second order. `s` is zero for
/// constants.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Centred {
    /// The quantity at the box's centre (its derivatives there too).
    pub c: Dual,
    /// The quantity over the whole box.
    pub b: Dual,
    /// The parameter's offset from the centre (zero for constants).
    pub s: Offset,
}

/// The parameter's offset from the box's centre, and half its square.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Offset {
    /// The offset s = t − centre over the box.
    pub s: Interval,
    half_s2: Interval,
}

impl Offset {
    /// No offset: a constant.
    pub const NONE: Offset = Offset { s: Interval::ZERO, half_s2: Interval::ZERO };

    /// The offset `s` with its half square.
    pub fn new(s: Interval) -> Offset {
        Offset { s, half_s2: Interval::point(0.5) * s.sqr() }
    }
}

impl Centred {
    /// From the jet at the centre and over the box, tightened.
    pub fn new(c: Dual, b: Dual, o: Offset) -> Centred {
        if o.s == Interval::ZERO {
            return Centred { c, b: b.intersect(c), s: o };
        }
        let d = b.d.intersect(c.d + b.dd * o.s);
        let v = b.v.intersect(c.v + d * o.s).intersect(c.v + c.d * o.s + b.dd * o.half_s2);
        Centred { c, b: Dual { v, d, dd: b.dd }, s: o }
    }

    /// The offset shared by two operands (a constant has none).
    fn offset(self, o: Centred) -> Offset {
        if self.s.s == Interval::ZERO { o.s } else { self.s }
    }

    /// Componentwise intersection of two enclosures of the same quantity.
    pub fn intersect(self, o: Centred) -> Centred {
        Centred::new(self.c.intersect(o.c), self.b.intersect(o.b), self.offset(o))
    }
}

macro_rules! centred_op {
    ($trait:ident, $f:ident) => {
        impl $trait for Centred {
            type Output = Centred;
            fn $f(self, o: Centred) -> Centred {
                // With a constant operand the centred forms gain nothing over
                // the other operand's own (already tightened) enclosure.
                if self.s == Offset::NONE || o.s == Offset::NONE {
                    return Centred { c: self.c.$f(o.c), b: self.b.$f(o.b), s: self.offset(o) };
                }
                Centred::new(self.c.$f(o.c), self.b.$f(o.b), self.offset(o))
            }
        }
    };
}
centred_op!(Add, add);
centred_op!(Sub, sub);
centred_op!(Mul, mul);
centred_op!(Div, div);

impl Neg for Centred {
    type Output = Centred;
    fn neg(self) -> Centred {
        Centred { c: -self.c, b: -self.b, s: self.s }
    }
}

impl Arith for Centred {
    fn constant(x: Interval) -> Self {
        Centred { c: Dual::constant(x), b: Dual::constant(x), s: Offset::NONE }
    }
    fn sqr(self) -> Self {
        Centred::new(self.c.sqr(), self.b.sqr(), self.s)
    }
    fn sqrt(self) -> Self {
        Centred::new(self.c.sqrt(), self.b.sqrt(), self.s)
    }
    fn clamp_nonneg(self) -> Self {
        Centred { c: self.c.clamp_nonneg(), b: self.b.clamp_nonneg(), s: self.s }
    }
    fn value(self) -> Interval {
        self.b.v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn holds(i: Interval, x: f64) -> bool {
        i.lo <= x && x <= i.hi
    }

    #[test]
    fn operations_enclose_the_exact_result() {
        // 0.1 + 0.2 is not 0.3 in f64; the enclosure holds the exact sum of the two doubles.
        let s = Interval::point(0.1) + Interval::point(0.2);
        assert!(s.lo < s.hi && holds(s, 0.30000000000000004) && s.width() < 1e-15);
        let p = Interval::new(-2.0, 3.0) * Interval::new(-5.0, 1.0);
        assert!(p.lo <= -15.0 && p.hi >= 10.0 && p.lo > -15.0001 && p.hi < 10.0001);
        assert_eq!(Interval::new(1.0, 2.0) / Interval::new(-1.0, 1.0), Interval::ENTIRE);
        let q = Interval::point(1.0) / Interval::point(3.0);
        assert!(holds(q, 1.0 / 3.0) && q.lo < 1.0 / 3.0 && q.hi > 1.0 / 3.0);
        assert_eq!(Interval::new(-3.0, 2.0).sqr().lo, 0.0);
        assert!(holds(Interval::new(-3.0, 2.0).sqr(), 9.0));
        // The negative part of a square root's argument is dropped.
        assert_eq!(Interval::new(-1.0, 4.0).sqrt().lo, 0.0);
        assert!(holds(Interval::new(-1.0, 4.0).sqrt(), 2.0));
        // 0 × unbounded is 0 (an unbounded bound is an unknown finite value).
        assert_eq!(Interval::ZERO * Interval::ENTIRE, Interval::ZERO);
        let z = Interval::new(0.0, 2.0) * Interval::new(1.0, f64::INFINITY);
        assert!(z.lo <= 0.0 && z.hi == f64::INFINITY);
    }

    #[test]
    fn duals_enclose_derivatives() {
        // f(x) = x·√(x² + 1) on [1, 2]: f' = (2x² + 1)/√(x² + 1), f'' = x(2x² + 3)/(x² + 1)^{3/2}.
        let x = Dual::variable(Interval::new(1.0, 2.0));
        let f = (x.sqr() + Dual::constant(Interval::point(1.0))).sqrt() * x;
        let g = x * x / (x.sqr() + Dual::constant(Interval::point(1.0))).sqrt(); // x²/√(x²+1)
        for k in 0..=10 {
            let t = 1.0 + k as f64 / 10.0;
            let w = (t * t + 1.0).sqrt();
            assert!(holds(f.v, t * w));
            assert!(holds(f.d, (2.0 * t * t + 1.0) / w));
            assert!(holds(f.dd, t * (2.0 * t * t + 3.0) / (w * w * w)));
            // (x²/√(x²+1))' = x(x² + 2)/(x² + 1)^{3/2}
            assert!(holds(g.d, t * (t * t + 2.0) / (w * w * w)));
            // chain: f(p(s)) with p = s², s ∈ [1, √2]: d/ds = f'(p)·2s, d²/ds² = f''(p)·4s² + f'(p)·2
            let s = t.sqrt();
            let c = f.chain(Interval::new(2.0, 2.0 * 2f64.sqrt()), Interval::point(2.0));
            assert!(holds(c.d, (2.0 * t * t + 1.0) / w * 2.0 * s));
            assert!(holds(c.dd, t * (2.0 * t * t + 3.0) / (w * w * w) * 4.0 * t + (2.0 * t * t + 1.0) / w * 2.0));
        }
        // √x over [0, 1]: the derivative is unbounded.
        assert!(!Dual::variable(Interval::new(0.0, 1.0)).sqrt().d.is_bounded());
    }
}
