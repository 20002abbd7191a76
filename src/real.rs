//! One scalar abstraction for the geometry: the same realization and endpoint
//! code runs in `f64` (fast), in [`Dd`] double-double (~106-bit reference
//! arithmetic, used to measure the f64 error) and in [`Jet`] (value plus first
//! and second derivative, for exact sign tests of a slack at its root).

use std::fmt::Debug;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// A real number type the solver can run in.
pub trait Real:
    Copy
    + Debug
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// Unit roundoff of the type (half the machine epsilon).
    const UNIT_ROUNDOFF: f64;
    fn from_f64(x: f64) -> Self;
    /// The value rounded to f64 (for a jet: its value).
    fn to_f64(self) -> f64;
    /// Square root; a negative argument gives NaN, as for f64.
    fn sqrt(self) -> Self;
    fn zero() -> Self {
        Self::from_f64(0.0)
    }
    fn abs(self) -> Self {
        if self < Self::zero() { -self } else { self }
    }
    fn hypot(x: Self, y: Self) -> Self {
        (x * x + y * y).sqrt()
    }
}

impl Real for f64 {
    const UNIT_ROUNDOFF: f64 = f64::EPSILON / 2.0;
    fn from_f64(x: f64) -> Self {
        x
    }
    fn to_f64(self) -> f64 {
        self
    }
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    fn hypot(x: Self, y: Self) -> Self {
        f64::hypot(x, y)
    }
}

/// Double-double number: the unevaluated sum `hi + lo` with `|lo| <= ulp(hi)/2`,
/// about 106 bits of significand. Arithmetic follows the classic error-free
/// transformations (Knuth's two-sum, fused-multiply-add two-product); relative
/// error of each operation is a small multiple of 2^-104.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Dd {
    pub hi: f64,
    pub lo: f64,
}

#[inline]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

#[inline]
fn quick_two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    (s, b - (s - a))
}

#[inline]
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

impl Dd {
    pub const fn new(hi: f64) -> Self {
        Dd { hi, lo: 0.0 }
    }
    fn mul_f64(self, b: f64) -> Dd {
        let (p, e) = two_prod(self.hi, b);
        let (hi, lo) = quick_two_sum(p, e + self.lo * b);
        Dd { hi, lo }
    }
}

impl Add for Dd {
    type Output = Dd;
    fn add(self, y: Dd) -> Dd {
        let (s, e) = two_sum(self.hi, y.hi);
        let (t, f) = two_sum(self.lo, y.lo);
        let (s, e) = quick_two_sum(s, e + t);
        let (hi, lo) = quick_two_sum(s, e + f);
        Dd { hi, lo }
    }
}

impl Neg for Dd {
    type Output = Dd;
    fn neg(self) -> Dd {
        Dd { hi: -self.hi, lo: -self.lo }
    }
}

impl Sub for Dd {
    type Output = Dd;
    fn sub(self, y: Dd) -> Dd {
        self + (-y)
    }
}

impl Mul for Dd {
    type Output = Dd;
    fn mul(self, y: Dd) -> Dd {
        let (p, e) = two_prod(self.hi, y.hi);
        let (hi, lo) = quick_two_sum(p, e + (self.hi * y.lo + self.lo * y.hi));
        Dd { hi, lo }
    }
}

impl Div for Dd {
    type Output = Dd;
    fn div(self, y: Dd) -> Dd {
        let q1 = self.hi / y.hi;
        let r = self - y.mul_f64(q1);
        let q2 = r.hi / y.hi;
        let r = r - y.mul_f64(q2);
        let q3 = r.hi / y.hi;
        let (hi, lo) = quick_two_sum(q1, q2);
        Dd { hi, lo } + Dd::new(q3)
    }
}

impl PartialOrd for Dd {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        match self.hi.partial_cmp(&other.hi) {
            Some(std::cmp::Ordering::Equal) => self.lo.partial_cmp(&other.lo),
            ord => ord,
        }
    }
}

impl Real for Dd {
    const UNIT_ROUNDOFF: f64 = 1.232_595_164_407_831e-32; // 2^-106
    fn from_f64(x: f64) -> Self {
        Dd::new(x)
    }
    fn to_f64(self) -> f64 {
        self.hi + self.lo
    }
    fn sqrt(self) -> Self {
        if self.hi <= 0.0 {
            return Dd::new(if self.hi == 0.0 { 0.0 } else { f64::NAN });
        }
        // One Newton step from the f64 root doubles the correct bits.
        let q = self.hi.sqrt();
        let (p, e) = two_prod(q, q);
        let r = (self - Dd { hi: p, lo: e }).hi;
        let (hi, lo) = quick_two_sum(q, r / (2.0 * q));
        Dd { hi, lo }
    }
}

/// A truncated Taylor expansion `v + d·t + (s/2)·t²` in one variable: carries
/// the value, first and second derivative through every operation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Jet<T> {
    pub v: T,
    pub d: T,
    pub s: T,
}

impl<T: Real> Jet<T> {
    /// The independent variable at `x`.
    pub fn variable(x: T) -> Self {
        Jet { v: x, d: T::from_f64(1.0), s: T::zero() }
    }
    pub fn constant(x: T) -> Self {
        Jet { v: x, d: T::zero(), s: T::zero() }
    }
}

impl<T: Real> Add for Jet<T> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Jet { v: self.v + o.v, d: self.d + o.d, s: self.s + o.s }
    }
}
impl<T: Real> Sub for Jet<T> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Jet { v: self.v - o.v, d: self.d - o.d, s: self.s - o.s }
    }
}
impl<T: Real> Neg for Jet<T> {
    type Output = Self;
    fn neg(self) -> Self {
        Jet { v: -self.v, d: -self.d, s: -self.s }
    }
}
impl<T: Real> Mul for Jet<T> {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        let two = T::from_f64(2.0);
        Jet { v: self.v * o.v, d: self.d * o.v + self.v * o.d, s: self.s * o.v + two * self.d * o.d + self.v * o.s }
    }
}
impl<T: Real> Div for Jet<T> {
    type Output = Self;
    fn div(self, o: Self) -> Self {
        // q = a/b, q' = (a' - q b')/b, q'' = (a'' - 2 q' b' - q b'')/b
        let two = T::from_f64(2.0);
        let v = self.v / o.v;
        let d = (self.d - v * o.d) / o.v;
        let s = (self.s - two * d * o.d - v * o.s) / o.v;
        Jet { v, d, s }
    }
}
impl<T: Real> PartialOrd for Jet<T> {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        self.v.partial_cmp(&other.v)
    }
}

impl<T: Real> Real for Jet<T> {
    const UNIT_ROUNDOFF: f64 = T::UNIT_ROUNDOFF;
    fn from_f64(x: f64) -> Self {
        Jet::constant(T::from_f64(x))
    }
    fn to_f64(self) -> f64 {
        self.v.to_f64()
    }
    fn sqrt(self) -> Self {
        // r = √v, r' = v'/(2r), r'' = (v'' - 2 r'²)/(2r)
        let two = T::from_f64(2.0);
        let r = self.v.sqrt();
        let d = self.d / (two * r);
        let s = (self.s - two * d * d) / (two * r);
        Jet { v: r, d, s }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn double_double_is_much_finer_than_f64() {
        let third = Dd::new(1.0) / Dd::new(3.0);
        let back = third * Dd::new(3.0) - Dd::new(1.0);
        assert!(back.to_f64().abs() < 1e-31);
        let r2 = Dd::new(2.0).sqrt();
        assert!((r2 * r2 - Dd::new(2.0)).to_f64().abs() < 1e-31);
        // 1 + 2^-80 survives in dd, not in f64.
        let tiny = Dd::new(1.0) + Dd::new(2f64.powi(-80));
        assert_eq!((tiny - Dd::new(1.0)).to_f64(), 2f64.powi(-80));
    }

    #[test]
    fn jets_carry_first_and_second_derivatives() {
        // f(x) = sqrt(x^3) / (1 + x) at x = 2
        let x = Jet::variable(2.0f64);
        let one = Jet::<f64>::from_f64(1.0);
        let f = (x * x * x).sqrt() / (one + x);
        let g = |x: f64| (x * x * x).sqrt() / (1.0 + x);
        let h = 1e-4;
        let d_num = (g(2.0 + h) - g(2.0 - h)) / (2.0 * h);
        let s_num = (g(2.0 + h) - 2.0 * g(2.0) + g(2.0 - h)) / (h * h);
        assert!((f.v - g(2.0)).abs() < 1e-15);
        assert!((f.d - d_num).abs() < 1e-7);
        assert!((f.s - s_num).abs() < 1e-5);
    }
}
