//! One scalar abstraction for the geometry: the same realization and endpoint
//! code runs in `f64` (fast), in [`Dd`] double-double (~106-bit reference
//! arithmetic, used to measure the f64 error) and in [`Jet`] (value plus first
//! and second derivative, for exact sign tests of a slack at its root).

use crate::realize::{Input, P2, Triangle};
use std::fmt::Debug;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// A real number type the solver can run in (a plain value: `'static`,
/// so per-thread scratch can be kept by type).
pub trait Real:
    'static
    + Copy
    + Debug
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Send
    + Sync
{
    /// Unit roundoff of the type (half the machine epsilon).
    const UNIT_ROUNDOFF: f64;
    /// A bound, with room to spare, on the relative rounding error of one
    /// operation (sum, product, quotient, square root): the rounding term
    /// of every [`Ball`] result. Four units of roundoff, where operations
    /// are correctly rounded (one unit).
    const OPERATION_ERROR: f64 = 4.0 * Self::UNIT_ROUNDOFF;
    /// An f64 in this type (exact).
    fn from_f64(x: f64) -> Self;
    /// A double-double input value (a length or coordinate as written) in
    /// this type: rounded for f64, exact for [`Dd`], with its rounding as
    /// radius for a [`Ball`].
    fn from_dd(x: Dd) -> Self;
    /// A number the construction reads from the scene: from its
    /// double-double, as every floating-point type reads it (the exact
    /// stage reads the decimals as written instead).
    fn input(x: Input) -> Self {
        match x {
            Input::Value((dd, _)) => Self::from_dd(dd),
            Input::Offset([p, q]) => Self::from_dd(p.0 - q.0),
            Input::Distance(dd, _) => Self::from_dd(dd),
        }
    }
    /// The value's sign where this type proves it: a [`Ball`] that
    /// excludes zero, an exact value decided. `None` for plain floating
    /// point (its sign may be the rounding's) and where no proof is in reach.
    fn proven_sign(self) -> Option<i8> {
        None
    }
    /// The value rounded to f64 (for a jet: its value).
    fn to_f64(self) -> f64;
    /// Square root; a negative argument gives NaN, as for f64.
    fn sqrt(self) -> Self;
    /// Zero.
    fn zero() -> Self {
        Self::from_f64(0.0)
    }
    /// |x| (NaN stays NaN).
    fn abs(self) -> Self {
        if self < Self::zero() { -self } else { self }
    }
    /// max(self, 0): a quantity that is ≥ 0 in exact arithmetic (a slack
    /// inside its interval) but may round below zero.
    fn clamp_nonneg(self) -> Self {
        if self < Self::zero() { Self::zero() } else { self }
    }
    /// max(self, 0) by value, whatever the type's own `clamp_nonneg` does.
    fn clamp_nonneg_plain(self) -> Self {
        if self < Self::zero() { Self::zero() } else { self }
    }
    /// c × self for a constant c of a construction (a member's placement
    /// coefficient: no slope, no curvature), so jets and slopes scale their
    /// parts by c's value alone; the same numbers as `c * self`.
    fn times_constant(self, c: Self) -> Self {
        c * self
    }
    /// Whether `realize::apex` divides by its base length d through one
    /// reciprocal 1/d and products, rather than by plain divisions. True
    /// where a division costs far more than a product: [`Ball`] (two ball
    /// divisions, the hot path of every certified decision) and [`Dd`]
    /// (its division is three f64 divisions and two exact products, the
    /// hot path of the double-double self-check and end refinement); the
    /// quotients differ by a few units of the type's roundoff. False for
    /// f64, and so for its jets, whose values stay exactly those of the
    /// formula as written.
    const APEX_BY_RECIPROCAL: bool = false;
    /// Where [`Self::hypot`] may square its components directly: sizes
    /// (the larger component) whose squares keep the type's precision. Set
    /// where a division costs far more than a product ([`Ball`], [`Dd`],
    /// and jets over f64); `None`: always scaled.
    const HYPOT_SQUARES: Option<[f64; 2]> = None;
    /// The apex of a step's triangle ([`crate::realize::apex_flat`], which
    /// every type but jets uses).
    fn apex(t: Triangle<Self>) -> Result<P2<Self>, Option<f64>> {
        crate::realize::apex_flat(t)
    }
    /// √(x² + y²) without squaring a length: scaled by the larger of |x|, |y|
    /// so that scenes near 1e±300 neither overflow nor underflow; squared
    /// directly within [`Self::HYPOT_SQUARES`] (two divisions fewer).
    ///
    /// A component that is exactly zero (every part of it: a ball of radius
    /// 0, a jet without slope or curvature) leaves the other's magnitude,
    /// exactly: a base distance on the base is λ itself.
    fn hypot(x: Self, y: Self) -> Self {
        generic_hypot(x, y)
    }
}

/// [`Real::hypot`]'s formula, operation by operation in `T`.
fn generic_hypot<T: Real>(x: T, y: T) -> T {
    let (ax, ay) = (x.abs(), y.abs());
    if y == T::zero() {
        return ax;
    }
    if x == T::zero() {
        return ay;
    }
    let m = if ax > ay { ax } else { ay };
    if m.partial_cmp(&T::zero()) != Some(std::cmp::Ordering::Greater) {
        return m;
    }
    let big = m.to_f64();
    if T::HYPOT_SQUARES.is_some_and(|[lo, hi]| big > lo && big < hi) {
        return (x * x + y * y).sqrt();
    }
    let (u, v) = (x / m, y / m);
    m * (u * u + v * v).sqrt()
}

impl Real for f64 {
    const UNIT_ROUNDOFF: f64 = f64::EPSILON / 2.0;
    /// For the jets and slopes over f64: squares of this size neither
    /// overflow nor leave the normal range, and the direct formula spares a
    /// jet two divisions on the walk's hot path (1000-step walk 174 → 159 ms
    /// with the misfit roots hoisted; the walk's f64 ends moved within
    /// their rounding floor, smaller errors on 11 of 17 chains, larger on
    /// 4). f64 itself keeps libm's correctly rounded `hypot`: bar
    /// lengths are measured from the drawing with it (the direct formula
    /// moved some in their last bit), so a jet's value may differ from the
    /// plain realization's by a few units of roundoff.
    const HYPOT_SQUARES: Option<[f64; 2]> = Some([1e-140, 1e140]);
    fn from_f64(x: f64) -> Self {
        x
    }
    fn from_dd(x: Dd) -> Self {
        x.hi + x.lo
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
    /// The leading part: the value rounded to f64.
    pub hi: f64,
    /// The trailing part: the rounding error of `hi`.
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
    /// The double-double equal to the f64 `hi`.
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
    /// 16 units: a product rounds by at most 7 (the bound Joldes, Muller
    /// and Popescu prove for `Mul`'s algorithm, DWTimesDW1, ACM TOMS 2017;
    /// 4.38 found here, more than the four of f64), a sum by at most 3 and a
    /// fraction (their accurate sum, `Add`'s); the quotient and square
    /// root, forms without a published bound, by at most 2.3 and 2.7 over
    /// 10^5 random operands each.
    const OPERATION_ERROR: f64 = 16.0 * Self::UNIT_ROUNDOFF;
    const APEX_BY_RECIPROCAL: bool = true;
    /// Components of this size square with every part of the product (down
    /// to 2^-106 of it) a normal number.
    const HYPOT_SQUARES: Option<[f64; 2]> = Some([1e-100, 1e100]);
    fn from_f64(x: f64) -> Self {
        Dd::new(x)
    }
    fn from_dd(x: Dd) -> Self {
        x
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
    /// The value.
    pub v: T,
    /// The first derivative.
    pub d: T,
    /// The second derivative.
    pub s: T,
}

impl<T: Real> Jet<T> {
    /// The independent variable at `x`.
    pub fn variable(x: T) -> Self {
        Jet { v: x, d: T::from_f64(1.0), s: T::zero() }
    }
    /// A constant: zero derivatives.
    pub fn constant(x: T) -> Self {
        Jet { v: x, d: T::zero(), s: T::zero() }
    }
    /// Its value and slope (the curvature dropped).
    pub fn slope(self) -> Slope<T> {
        Slope { v: self.v, d: self.d }
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
        // q = a/b, q' = (a' - q b')/b, q'' = (a'' - 2 q' b' - q b'')/b. The
        // value is the plain quotient; the derivatives multiply by 1/b (two
        // divisions, not three, on the hot path of every jet realization).
        let two = T::from_f64(2.0);
        let v = self.v / o.v;
        let inv = T::from_f64(1.0) / o.v;
        let d = (self.d - v * o.d) * inv;
        let s = (self.s - two * d * o.d - v * o.s) * inv;
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
    const APEX_BY_RECIPROCAL: bool = T::APEX_BY_RECIPROCAL;
    const HYPOT_SQUARES: Option<[f64; 2]> = T::HYPOT_SQUARES;
    /// Derivatives through d alone ([`crate::realize::apex_jet`]).
    fn apex(t: Triangle<Self>) -> Result<P2<Self>, Option<f64>> {
        crate::realize::apex_jet(t)
    }
    fn times_constant(self, c: Self) -> Self {
        Jet { v: c.v * self.v, d: c.v * self.d, s: c.v * self.s }
    }
    /// Where [`Real::hypot`] squares directly, the value as it computes it
    /// and the derivatives of r = √(x² + y²) directly: r′ = (x·x′ + y·y′)/r,
    /// r″ = (x′² + x·x″ + y′² + y·y″ − r′²)/r (a jet product per square
    /// computes the same sums less directly); elsewhere that formula.
    fn hypot(x: Self, y: Self) -> Self {
        let big = x.v.abs().to_f64().max(y.v.abs().to_f64());
        let direct = x != Self::zero() && y != Self::zero();
        if !(direct && T::HYPOT_SQUARES.is_some_and(|[lo, hi]| big > lo && big < hi)) {
            return generic_hypot(x, y);
        }
        let v = (x.v * x.v + y.v * y.v).sqrt();
        let d = (x.v * x.d + y.v * y.d) / v;
        let s = (x.d * x.d + x.v * x.s + y.d * y.d + y.v * y.s - d * d) / v;
        Jet { v, d, s }
    }
    fn from_f64(x: f64) -> Self {
        Jet::constant(T::from_f64(x))
    }
    fn from_dd(x: Dd) -> Self {
        Jet::constant(T::from_dd(x))
    }
    fn to_f64(self) -> f64 {
        self.v.to_f64()
    }
    fn sqrt(self) -> Self {
        // r = √v, r' = v'/(2r), r'' = (v'' - 2 r'²)/(2r), through one 1/(2r).
        let two = T::from_f64(2.0);
        let r = self.v.sqrt();
        let inv = T::from_f64(1.0) / (two * r);
        let d = self.d * inv;
        let s = (self.s - two * d * d) * inv;
        Jet { v: r, d, s }
    }
}

/// A first-order jet `v + d·t`: a [`Jet`] without the second derivative,
/// for Newton iterations that need only the value and the slope. Its `v`
/// and `d` are computed by exactly the operations [`Jet`] uses for them (a
/// jet's value and slope never read its curvature), so they are the same
/// numbers bit for bit, at about half the cost.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slope<T> {
    /// The value.
    pub v: T,
    /// The first derivative.
    pub d: T,
}

impl<T: Real> Slope<T> {
    /// The independent variable at `x`.
    pub fn variable(x: T) -> Self {
        Slope { v: x, d: T::from_f64(1.0) }
    }
    /// A constant: zero slope.
    pub fn constant(x: T) -> Self {
        Slope { v: x, d: T::zero() }
    }
}

impl<T: Real> Add for Slope<T> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Slope { v: self.v + o.v, d: self.d + o.d }
    }
}
impl<T: Real> Sub for Slope<T> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Slope { v: self.v - o.v, d: self.d - o.d }
    }
}
impl<T: Real> Neg for Slope<T> {
    type Output = Self;
    fn neg(self) -> Self {
        Slope { v: -self.v, d: -self.d }
    }
}
impl<T: Real> Mul for Slope<T> {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        Slope { v: self.v * o.v, d: self.d * o.v + self.v * o.d }
    }
}
impl<T: Real> Div for Slope<T> {
    type Output = Self;
    fn div(self, o: Self) -> Self {
        // As in `Jet`: q = a/b, q' = (a' - q b')·(1/b).
        let v = self.v / o.v;
        Slope { v, d: (self.d - v * o.d) * (T::from_f64(1.0) / o.v) }
    }
}
impl<T: Real> PartialOrd for Slope<T> {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        self.v.partial_cmp(&other.v)
    }
}

impl<T: Real> Real for Slope<T> {
    const UNIT_ROUNDOFF: f64 = T::UNIT_ROUNDOFF;
    const APEX_BY_RECIPROCAL: bool = T::APEX_BY_RECIPROCAL;
    const HYPOT_SQUARES: Option<[f64; 2]> = T::HYPOT_SQUARES;
    fn times_constant(self, c: Self) -> Self {
        Slope { v: c.v * self.v, d: c.v * self.d }
    }
    fn from_f64(x: f64) -> Self {
        Slope::constant(T::from_f64(x))
    }
    fn from_dd(x: Dd) -> Self {
        Slope::constant(T::from_dd(x))
    }
    fn to_f64(self) -> f64 {
        self.v.to_f64()
    }
    fn sqrt(self) -> Self {
        // As in `Jet`: r = √v, r' = v'·(1/(2r)).
        let r = self.v.sqrt();
        Slope { v: r, d: self.d * (T::from_f64(1.0) / (T::from_f64(2.0) * r)) }
    }
    /// The value clamped as `T` clamps it (a ball keeps its radius, so a
    /// slack straddling zero still encloses the height above it); the
    /// slope is zero where the value is below zero (the same numbers as
    /// the default for f64 and double-double).
    fn clamp_nonneg(self) -> Self {
        Slope { v: self.v.clamp_nonneg(), d: if self.v < T::zero() { T::zero() } else { self.d } }
    }
}

impl Dd {
    /// 10^n for 0 ≤ n ≤ 300, by squaring (exact while 10^n fits 106 bits, n ≤ 45).
    fn pow10(n: u32) -> Dd {
        let (mut result, mut base, mut n) = (Dd::new(1.0), Dd::new(10.0), n);
        while n > 0 {
            if n & 1 == 1 {
                result = result * base;
            }
            base = base * base;
            n >>= 1;
        }
        result
    }

    /// A decimal number as written (`-12.5e-3`, TOML's `1_000`) in
    /// double-double: the digits are accumulated exactly (up to 31 of them),
    /// then scaled by a power of ten, so the result is within a few units of
    /// 2^-104 of the written value. `None` for anything else (hex, inf, nan).
    pub fn parse_decimal(text: &str) -> Option<Dd> {
        let (negative, digits_text, e10) = crate::exact::decimal_parts(text)?;
        let mut digits = Dd::new(0.0);
        for c in digits_text.chars() {
            digits = digits.mul_f64(10.0) + Dd::new(f64::from(c as u8 - b'0'));
        }
        let mut e10 = i32::try_from(e10).ok()?;
        // Scale in pieces so that no power of ten overflows.
        while e10 != 0 {
            let piece = e10.clamp(-300, 300);
            let p = Dd::pow10(piece.unsigned_abs());
            digits = if piece > 0 { digits * p } else { digits / p };
            e10 -= piece;
        }
        let value = if negative { -digits } else { digits };
        value.hi.is_finite().then_some(value)
    }
}

/// A midpoint-radius enclosure ("ball") of a real number: the true value
/// lies in [m − r, m + r]. Every operation widens the radius by its
/// propagated input radii and its own rounding error (bounded by a few units
/// of `T`'s roundoff times the result), so a sign read from a ball whose
/// radius is below |m| is proven. Used to decide structural questions (is
/// a slack positive, zero or negative at an event) without tolerances;
/// see the `certify` module.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ball<T> {
    /// The midpoint.
    pub m: T,
    /// The radius (an upper bound, rounded up).
    pub r: f64,
}

/// Relative slack on every radius computation (it is rounded too).
const RADIUS_ROUNDING: f64 = 1.0 + 1e-14;

/// Below this size (about 2^-797) the remainder terms of a double-double
/// quotient or square root may underflow: they scale with the dividend or
/// radicand, not with the result, so there those operations add
/// [`UNDERFLOW_LOSS`] over the divisor's (or root's) size whatever their
/// result. A sum's or product's own terms are covered by its rounding (see
/// `Ball::rounded`). Keeping absolute terms off ordinary results keeps
/// their radii normal numbers: a radius near `MIN_POSITIVE` times a
/// magnitude below 1 is subnormal, and subnormal operands and results cost
/// the processor a microcode assist on every operation (about a third of a
/// certified analysis's time, before).
const UNDERFLOW_FREE: f64 = 1e-240;

/// What the few remainder terms of one double-double division or square
/// root can lose to underflow together: each at most half the smallest
/// subnormal, and sixteen of those cover them all.
const UNDERFLOW_LOSS: f64 = 16.0 * f64::from_bits(1);

impl<T: Real> Ball<T> {
    /// The ball of radius 0 around `m` (an exactly known value).
    pub fn exact(m: T) -> Self {
        Ball { m, r: 0.0 }
    }
    fn mag(x: T) -> f64 {
        x.to_f64().abs()
    }
    /// A result `m` whose propagated radius is `r`: add `m`'s own rounding,
    /// [`Real::OPERATION_ERROR`] relative plus [`f64::MIN_POSITIVE`], which
    /// is at least the larger of the two. Where the relative term is the
    /// larger (|m| from 2^-971 in f64, 2^-920 in double-double), its margin
    /// over the rounding itself is more than half of 2^-1022: that covers
    /// what the error terms and the radius terms lost to underflow (each at
    /// most 2^-1075). Below, `MIN_POSITIVE` covers the rounding and those
    /// losses together. From a relative term of 2^-968 (|m| from 2^-917 in
    /// f64, 2^-866 in double-double) the sum is that term exactly. One
    /// addition where a comparison and a choice were (Limacon 0.7%, Jansen
    /// 0.6% fewer instructions); a NaN stays NaN.
    fn rounded(m: T, r: f64) -> Self {
        let own = T::OPERATION_ERROR * Self::mag(m) + f64::MIN_POSITIVE;
        Ball { m, r: (r + own) * RADIUS_ROUNDING }
    }
    /// The exact zero, for an operation whose result is exactly zero.
    fn exact_zero(self) -> bool {
        self.r == 0.0 && self.m == T::zero()
    }
    /// The sign of the enclosed value: `Some(±1)` when proven, `None` when
    /// the ball holds zero.
    pub fn sign(self) -> Option<i8> {
        let m = self.m.to_f64();
        if !(self.r.is_finite() && m.is_finite()) || m.abs() <= self.r {
            None
        } else {
            Some(if m > 0.0 { 1 } else { -1 })
        }
    }
}

impl<T: Real> Add for Ball<T> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Ball::rounded(self.m + o.m, self.r + o.r)
    }
}
impl<T: Real> Sub for Ball<T> {
    type Output = Self;
    /// x − x of an exact x is an exact zero, not a tiny radius (a base
    /// along an axis has such a difference).
    fn sub(self, o: Self) -> Self {
        if self.r == 0.0 && o.r == 0.0 && self.m == o.m {
            return Ball::exact(T::zero());
        }
        Ball::rounded(self.m - o.m, self.r + o.r)
    }
}
impl<T: Real> Neg for Ball<T> {
    type Output = Self;
    fn neg(self) -> Self {
        Ball { m: -self.m, r: self.r }
    }
}
impl<T: Real> Mul for Ball<T> {
    type Output = Self;
    /// A product with an exact zero is an exact zero.
    fn mul(self, o: Self) -> Self {
        if self.exact_zero() || o.exact_zero() {
            return Ball::exact(T::zero());
        }
        let (a, b) = (Self::mag(self.m), Self::mag(o.m));
        // a·r' + b·r + r·r', with r·r' folded into the first product (one
        // product fewer, and no product of two tiny radii).
        Ball::rounded(self.m * o.m, (a + self.r) * o.r + b * self.r)
    }
}
impl<T: Real> Div for Ball<T> {
    type Output = Self;
    fn div(self, o: Self) -> Self {
        let m = self.m / o.m;
        let below = Self::mag(o.m) - o.r;
        if below.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return Ball { m, r: f64::INFINITY };
        }
        // A tiny dividend's remainder terms may underflow (see UNDERFLOW_FREE).
        let tiny = if Self::mag(self.m) < UNDERFLOW_FREE { UNDERFLOW_LOSS } else { 0.0 };
        Ball::rounded(m, (self.r + Self::mag(m) * o.r + tiny) / below)
    }
}
impl<T: Real> PartialOrd for Ball<T> {
    /// By midpoint: only for choosing a formula, never for a decision (use [`Ball::sign`]).
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        self.m.partial_cmp(&other.m)
    }
}

impl<T: Real> Real for Ball<T> {
    const UNIT_ROUNDOFF: f64 = T::UNIT_ROUNDOFF;
    /// n·(1/d) encloses n/d: the ball of 1/d encloses 1/δ for every δ in d's
    /// ball (its division gives radius ∞ when that ball reaches 0), and a
    /// ball product encloses the product of every pair of enclosed values.
    /// The midpoints differ from `T`'s own quotients in the last bits, which
    /// the radii cover (each product adds its own rounding, an underflowing
    /// one is covered by the radius's absolute term).
    const APEX_BY_RECIPROCAL: bool = true;
    /// Components of this size square without overflow, and their squares
    /// stay normal (the sum then carries their rounding in its radius; an
    /// underflowing smaller square is covered by the radius's absolute
    /// term): the hot path of every certified decision.
    const HYPOT_SQUARES: Option<[f64; 2]> = Some([1e-140, 1e140]);
    fn from_f64(x: f64) -> Self {
        Ball::exact(T::from_f64(x))
    }
    fn from_dd(x: Dd) -> Self {
        // The rounding to T, and the decimal → double-double conversion.
        let size = x.to_f64().abs();
        Ball { m: T::from_dd(x), r: size * (4.0 * T::UNIT_ROUNDOFF + 1e-30) }
    }
    fn proven_sign(self) -> Option<i8> {
        self.sign()
    }
    fn to_f64(self) -> f64 {
        self.m.to_f64()
    }
    /// The midpoint stays the plain square root (so a ball's midpoint is
    /// always what `T` alone computes); the radius covers √ of the enclosure,
    /// clamped at zero where it reaches below.
    fn sqrt(self) -> Self {
        let m = self.m.to_f64();
        let root = self.m.clamp_nonneg_plain().sqrt();
        let centre = Self::mag(root);
        if m - self.r <= 0.0 {
            let top = (m + self.r).max(0.0).sqrt();
            return Ball { m: root, r: (top.max(centre) * RADIUS_ROUNDING).max(centre) };
        }
        // |√x − √m| ≤ r / (√m + √(m − r)), and √(m − r) ≥ √m·(1 − r/m)
        // (√(1 − t) ≥ 1 − t on [0, 1]): no second square root, and a bound
        // looser only by the relative r/(2m).
        // A tiny radicand's Newton correction may underflow (see UNDERFLOW_FREE).
        let tiny = if m < UNDERFLOW_FREE { UNDERFLOW_LOSS / centre } else { 0.0 };
        Ball::rounded(root, self.r / (centre * (2.0 - self.r / m)) + tiny)
    }
    fn clamp_nonneg(self) -> Self {
        // max(·, 0) is 1-Lipschitz: the radius carries over.
        Ball { m: self.m.clamp_nonneg_plain(), r: self.r }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Jets' direct hypot against the generic formula in jet arithmetic:
    /// the same value, the same derivatives to rounding; an exactly zero
    /// component still leaves the other's magnitude.
    #[test]
    fn jet_hypot_matches_the_generic_formula() {
        for scale in [1e-120, 1.0, 3e5, 1e120] {
            for (x, y) in [(0.3, 0.4), (-2.0, 1e-3), (1.0, -1.0), (5e-9, 7.0)] {
                let x = Jet { v: x * scale, d: 0.7, s: -0.2 / scale };
                let y = Jet { v: y * scale, d: -0.1, s: 0.9 / scale };
                let (fast, slow) = (Jet::hypot(x, y), generic_hypot(x, y));
                assert_eq!(fast.v, slow.v);
                assert!((fast.d - slow.d).abs() <= 1e-12 * slow.d.abs().max(1.0));
                assert!((fast.s - slow.s).abs() <= 1e-9 * slow.s.abs().max(1.0 / scale));
            }
        }
        let x = Jet { v: -3.0, d: 1.0, s: 0.5 };
        assert_eq!(Jet::hypot(x, Jet::constant(0.0)), -x);
    }

    /// Scaling by a construction's constant is the product with it, part
    /// for part, for jets and slopes alike.
    #[test]
    fn times_constant_is_the_product_with_a_constant() {
        let x = Jet { v: 1.5, d: -0.25, s: 3.0 };
        let c = Jet::constant(-0.7);
        assert_eq!(x.times_constant(c), c * x);
        let y = Slope { v: 2.0, d: 0.125 };
        assert_eq!(y.times_constant(Slope::constant(3.0)), Slope::constant(3.0) * y);
    }

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
    fn decimals_parse_to_double_double() {
        let tenth = Dd::parse_decimal("0.1").unwrap();
        // 0.1 is not an f64; its double-double is 10^-32 close.
        assert!(((tenth * Dd::new(10.0)) - Dd::new(1.0)).to_f64().abs() < 1e-31);
        assert_eq!(tenth.to_f64(), 0.1);
        let x = Dd::parse_decimal("-3.999999999999e-3").unwrap();
        assert_eq!(x.to_f64(), -3.999999999999e-3);
        assert_eq!(Dd::parse_decimal("1_000").unwrap().to_f64(), 1000.0);
        assert_eq!(Dd::parse_decimal("2.5E+2").unwrap().to_f64(), 250.0);
        assert!(Dd::parse_decimal("1e-320").is_some_and(|v| v.to_f64() == 1e-320));
        assert!(Dd::parse_decimal("inf").is_none() && Dd::parse_decimal("0x10").is_none());
    }

    #[test]
    fn balls_enclose_and_prove_signs() {
        // (1/3)·3 − 1 is zero in exact arithmetic: the ball must hold 0.
        let third = Ball::<f64>::from_f64(1.0) / Ball::from_f64(3.0);
        let zero = third * Ball::from_f64(3.0) - Ball::from_f64(1.0);
        assert_eq!(zero.sign(), None);
        // 0.1 as written: its f64 is off by 5.5e-18, which the radius covers.
        let tenth = Ball::<f64>::from_dd(Dd::parse_decimal("0.1").unwrap());
        assert!(tenth.r >= 5.5e-18);
        let d = Ball::<f64>::from_f64(1e-12) - Ball::from_f64(0.0);
        assert_eq!(d.sign(), Some(1));
        // √ of an enclosure reaching below zero stays an enclosure of √[0, hi].
        let s = Ball::<f64> { m: 1e-20, r: 1e-18 }.sqrt();
        assert!(s.m - s.r <= 0.0 && s.m + s.r >= (1.01e-18f64).sqrt());
        // Away from zero it encloses √ of both ends, and is nearly tight.
        let b = Ball::<f64> { m: 2.0, r: 0.5 }.sqrt();
        assert!(b.m - b.r <= 1.5f64.sqrt() && b.m + b.r >= 2.5f64.sqrt() && b.r < 0.21);
        // Double-double balls decide what f64 ones cannot.
        let a = Ball::<Dd>::from_dd(Dd::new(1.0) + Dd::new(1e-20));
        assert_eq!((a - Ball::from_f64(1.0)).sign(), Some(1));
    }

    #[test]
    fn ball_radii_stay_normal_yet_cover_underflow() {
        let exact = Ball::<f64>::from_f64;
        // Exact zeros stay exact: no radius for a product to make subnormal.
        let dy = exact(0.0) - exact(0.0);
        assert_eq!((dy, exact(2.5) * dy, dy * exact(0.3)), (exact(0.0), exact(0.0), exact(0.0)));
        // An ordinary computation's radii are relative, never near MIN_POSITIVE:
        // their products with magnitudes below 1 stay normal.
        let x = exact(1.0) / exact(3.0);
        let y = (x * x - exact(0.1)) * exact(1e-9);
        assert!(x.r.is_normal() && y.r.is_normal() && y.r < 1e-24 && (y.r * 1e-20).is_normal());
        // A product that underflows to zero (1e-200² ≈ 1e-400) still encloses
        // the true positive value.
        let t = exact(1e-200) * exact(1e-200);
        assert!(t.m == 0.0 && t.r >= f64::MIN_POSITIVE);
        // A quotient near the underflow threshold keeps an absolute cover.
        let q = exact(1e-300) / exact(3e10);
        assert!(q.r >= f64::MIN_POSITIVE && (q.m - 1e-300 / 3e10).abs() <= q.r);
        // A result's own rounding is its relative term where that is at
        // least 2^-968, and MIN_POSITIVE more below; a NaN keeps a NaN radius.
        let big = exact(1e-270) + exact(1e-280);
        assert_eq!(big.r, <f64 as Real>::OPERATION_ERROR * big.m * RADIUS_ROUNDING);
        let small = exact(1e-300) + exact(0.0);
        assert!(small.r >= f64::MIN_POSITIVE && small.r <= 1.01 * f64::MIN_POSITIVE);
        let nan = Ball { m: f64::NAN, r: 0.0 } + exact(1.0);
        assert!(nan.m.is_nan() && nan.r.is_nan() && nan.sign().is_none());
        // Double-double quotients and roots of tiny operands (normal
        // results, but remainder terms that underflow, up to 1e-23 of the
        // value) are still enclosed. The operands are full-width numbers
        // times 2^-1000: the same operation on them unscaled is the reference.
        let tiny = 2f64.powi(-1000);
        let (x, y) = (0.737_512_345_678_901, 2.918_273_645_546_372);
        let dd = |v: f64| Ball::<Dd>::exact(Dd::new(v * tiny));
        let q = dd(x) / dd(y);
        assert!((q.m - Dd::new(x) / Dd::new(y)).to_f64().abs() <= q.r && q.r < 1e-20);
        let root = dd(y).sqrt();
        let want = Dd::new(y).sqrt() * Dd::new(2f64.powi(-500));
        assert!((root.m - want).to_f64().abs() <= root.r && root.r < 1e-20 * want.to_f64());
    }

    /// A product of two exact double-double balls encloses the exact
    /// product: at a pair whose double-double product rounds by 4.38 units
    /// of 2^-106 (more than four, so [`Real::OPERATION_ERROR`] is more for
    /// `Dd`), and at pseudo-random pairs of full double-doubles. The exact
    /// error is summed error-free (Shewchuk's expansion) from the four
    /// partial products, each exact as a two-product.
    #[test]
    fn double_double_ball_products_enclose_the_exact_product() {
        fn error_in_units(x: Dd, y: Dd) -> (f64, Ball<Dd>) {
            let z = Ball::exact(x) * Ball::exact(y);
            let mut terms = vec![z.m.hi, z.m.lo];
            for (a, b) in [(x.hi, y.hi), (x.hi, y.lo), (x.lo, y.hi), (x.lo, y.lo)] {
                let (p, e) = two_prod(a, b);
                terms.extend([-p, -e]);
            }
            let mut expansion: Vec<f64> = Vec::new();
            for t in terms {
                let mut q = t;
                for c in expansion.iter_mut() {
                    (q, *c) = two_sum(q, *c);
                }
                expansion.push(q);
            }
            let error: f64 = expansion.iter().sum();
            (error.abs() / (z.m.to_f64().abs() * Dd::UNIT_ROUNDOFF), z)
        }
        let dd = |hi: f64, lo: f64| {
            let (hi, lo) = quick_two_sum(hi, lo);
            Dd { hi, lo }
        };
        let (x, y) = (dd(1.011675796753424, 1.1021356130614272e-16), dd(1.0804087891012337, 1.1092162017823667e-16));
        let (units, z) = error_in_units(x, y);
        assert!(units > 4.3 && units * Dd::UNIT_ROUNDOFF * z.m.to_f64() <= z.r, "{units} units, radius {}", z.r);
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut uniform = || {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..20_000 {
            let mut full = || {
                let hi = 1.0 + uniform();
                dd(hi, (uniform() - 0.5) * 2f64.powi(-52))
            };
            let (x, y) = (full(), full());
            let (units, z) = error_in_units(x, y);
            assert!(units * Dd::UNIT_ROUNDOFF * z.m.to_f64() <= z.r, "{x:?} × {y:?}: {units} units");
        }
    }

    #[test]
    fn slopes_are_the_jets_value_and_slope_bit_for_bit() {
        // f(x) = hypot(x², 1 − x) · √x / (3 − x) − x at a few x, in double-double.
        fn f<T: Real>(x: T) -> T {
            let one = T::from_f64(1.0);
            T::hypot(x * x, one - x) * x.sqrt() / (T::from_f64(3.0) - x) - x
        }
        for x in [0.25, 0.7, 1.9, 2.5] {
            let x = Dd::new(x) / Dd::new(3.0);
            let (j, s) = (f(Jet::variable(x)), f(Slope::variable(x)));
            assert_eq!((j.v, j.d), (s.v, s.d));
            assert!(s.d.to_f64() != 0.0);
        }
    }

    /// An exactly zero component leaves the other's magnitude, exactly;
    /// a zero that is only a midpoint (radius > 0) or a value (with a
    /// slope) is squared in as before.
    #[test]
    fn hypot_with_an_exact_zero_is_the_magnitude() {
        let x = Ball::<f64> { m: -3.0, r: 1e-15 };
        assert_eq!(Real::hypot(x, Ball::exact(0.0)), Ball { m: 3.0, r: 1e-15 });
        assert_eq!(Real::hypot(Ball::exact(0.0), x), Ball { m: 3.0, r: 1e-15 });
        let near = Real::hypot(x, Ball { m: 0.0, r: 1e-15 });
        assert!(near.r > 1e-15 && near.m == 3.0, "{near:?}");
        let lambda = Jet::variable(2.5f64);
        assert_eq!(Real::hypot(-lambda, Jet::constant(0.0)), Jet { v: 2.5, d: 1.0, s: 0.0 });
        let moving = Real::hypot(lambda, Jet::variable(0.0));
        assert!(moving.s > 0.0, "a zero with a slope curves the distance: {moving:?}");
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
