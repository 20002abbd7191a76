//! Fixed-point intervals: an enclosure [lo, hi] · 2^-p of a real number, for
//! one precision p, with every operation rounded outwards (so the interval
//! always holds the exact value). The arithmetic of the exact stage.

use num_bigint::BigInt;
use num_integer::Integer;
use num_traits::{One, Signed, Zero};

/// [lo, hi] · 2^-p, lo ≤ hi.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) struct Fixed {
    pub lo: BigInt,
    pub hi: BigInt,
}

/// ⌊x / 2^p⌋.
fn floor_shift(x: &BigInt, p: u64) -> BigInt {
    // BigInt's right shift rounds towards −∞.
    x >> p
}

/// ⌈x / 2^p⌉.
fn ceil_shift(x: &BigInt, p: u64) -> BigInt {
    -(-x >> p)
}

/// ⌈√x⌉ for x ≥ 0.
fn ceil_sqrt(x: &BigInt) -> BigInt {
    let r = x.sqrt();
    if &(&r * &r) == x { r } else { r + 1 }
}

impl Fixed {
    /// The interval of n/d (d > 0) at precision p.
    pub fn rational(n: &BigInt, d: &BigInt, p: u64) -> Fixed {
        let scaled = n << p;
        Fixed { lo: scaled.div_floor(d), hi: scaled.div_ceil(d) }
    }

    pub fn add(&self, o: &Fixed) -> Fixed {
        Fixed { lo: &self.lo + &o.lo, hi: &self.hi + &o.hi }
    }

    pub fn sub(&self, o: &Fixed) -> Fixed {
        Fixed { lo: &self.lo - &o.hi, hi: &self.hi - &o.lo }
    }

    pub fn neg(&self) -> Fixed {
        Fixed { lo: -&self.hi, hi: -&self.lo }
    }

    /// The four end products (at precision 2p), their least rounded down
    /// and their greatest rounded up.
    pub fn mul(&self, o: &Fixed, p: u64) -> Fixed {
        let products = [&self.lo * &o.lo, &self.lo * &o.hi, &self.hi * &o.lo, &self.hi * &o.hi];
        let lo = products.iter().min().expect("four");
        let hi = products.iter().max().expect("four");
        Fixed { lo: floor_shift(lo, p), hi: ceil_shift(hi, p) }
    }

    /// `None` where the divisor's interval holds zero (a finer precision may separate it).
    pub fn div(&self, o: &Fixed, p: u64) -> Option<Fixed> {
        if o.lo.sign() != o.hi.sign() || o.lo.is_zero() {
            return None;
        }
        let (a, b) = (&self.lo << p, &self.hi << p);
        let (c, d) = (&o.lo, &o.hi);
        let lo = [a.div_floor(c), a.div_floor(d), b.div_floor(c), b.div_floor(d)].into_iter().min().expect("four");
        let hi = [a.div_ceil(c), a.div_ceil(d), b.div_ceil(c), b.div_ceil(d)].into_iter().max().expect("four");
        Some(Fixed { lo, hi })
    }

    /// √ of the interval's non-negative part; `None` where it has none (the
    /// radicand is proven negative: the expression has no real value).
    pub fn sqrt(&self, p: u64) -> Option<Fixed> {
        if self.hi.is_negative() {
            return None;
        }
        let lo = if self.lo.is_positive() { (&self.lo << p).sqrt() } else { BigInt::zero() };
        Some(Fixed { lo, hi: ceil_sqrt(&(&self.hi << p)) })
    }

    pub fn abs(&self) -> Fixed {
        if !self.lo.is_negative() {
            self.clone()
        } else if !self.hi.is_positive() {
            self.neg()
        } else {
            Fixed { lo: BigInt::zero(), hi: (-&self.lo).max(self.hi.clone()) }
        }
    }

    /// max(x, 0) over the interval.
    pub fn clamp_nonneg(&self) -> Fixed {
        let zero = BigInt::zero();
        Fixed { lo: self.lo.clone().max(zero.clone()), hi: self.hi.clone().max(zero) }
    }

    /// The interval's sign where it excludes zero.
    pub fn sign(&self) -> Option<i8> {
        if self.lo.is_positive() {
            Some(1)
        } else if self.hi.is_negative() {
            Some(-1)
        } else {
            None
        }
    }

    /// Whether every value in the interval is below 2^-bits in magnitude
    /// (the interval is at precision p).
    pub fn within(&self, bits: u64, p: u64) -> bool {
        // |x| · 2^-p < 2^-bits  ⇔  |x| < 2^(p − bits).
        let Some(e) = p.checked_sub(bits) else { return self.lo.is_zero() && self.hi.is_zero() };
        let limit = BigInt::one() << e;
        self.hi < limit && -&self.lo < limit
    }
}

/// x · 2^-p as an f64 (its leading 64 bits, scaled; for approximations only).
pub(super) fn big_to_f64(x: &BigInt, p: u64) -> f64 {
    let drop = x.bits().saturating_sub(64);
    let top = i128::try_from(&(x >> drop)).expect("64 bits fit") as f64;
    let mut e = drop as i64 - p as i64;
    let mut value = top;
    // Scaled in pieces: 2^e alone may over- or underflow where the product does not.
    while e != 0 && value != 0.0 && value.is_finite() {
        let piece = e.clamp(-1000, 1000);
        value *= 2f64.powi(piece as i32);
        e -= piece;
    }
    value
}

#[cfg(test)]
mod tests {
    use super::*;

    fn int(x: i64) -> BigInt {
        BigInt::from(x)
    }

    /// Each operation's interval holds the exact result and is at most a few
    /// units of 2^-p wide for exact inputs.
    #[test]
    fn operations_round_outwards() {
        let p = 64;
        let third = Fixed::rational(&int(1), &int(3), p);
        assert_eq!(&third.hi - &third.lo, int(1));
        let minus_third = Fixed::rational(&int(-1), &int(3), p);
        assert_eq!(minus_third, third.neg());
        // 1/3 · 3 holds 1.
        let three = Fixed::rational(&int(3), &int(1), p);
        let one = third.mul(&three, p);
        assert!(one.lo <= int(1) << p && int(1) << p <= one.hi);
        // √2 at precision p: lo² ≤ 2·2^2p ≤ hi².
        let two = Fixed::rational(&int(2), &int(1), p);
        let r = two.sqrt(p).unwrap();
        let target = int(2) << (2 * p);
        assert!(&r.lo * &r.lo <= target && target <= &r.hi * &r.hi);
        assert!(&r.hi - &r.lo <= int(2));
        // Division by an interval holding zero is refused, a negative radicand too.
        let around_zero = Fixed { lo: int(-1), hi: int(1) };
        assert!(two.div(&around_zero, p).is_none());
        assert!(minus_third.sqrt(p).is_none());
        // 1 / (−3) holds −1/3.
        let q = Fixed::rational(&int(1), &int(1), p).div(&three.neg(), p).unwrap();
        assert!(q.lo <= minus_third.lo && minus_third.hi <= q.hi);
        assert_eq!(around_zero.abs(), Fixed { lo: int(0), hi: int(1) });
        assert_eq!(minus_third.clamp_nonneg(), Fixed { lo: int(0), hi: int(0) });
        assert!((big_to_f64(&third.lo, p) - 1.0 / 3.0).abs() < 1e-16);
    }
}
