//! A number as a scene writes it, kept exactly.

use num_bigint::BigInt;
use num_traits::{One, Zero};

use crate::real::Dd;

/// A decimal number as written in a scene (`-12.5e-3`, TOML's `1_000`):
/// the exact rational the text means, which the exact stage starts from
/// (the solver's floating-point arithmetics start from its double-double).
#[derive(Clone, Debug, PartialEq)]
pub struct Decimal {
    /// The digits as one integer, with its sign.
    mantissa: BigInt,
    /// The power of ten the digits are scaled by.
    exp10: i64,
    /// The text's double-double, as the scene parser reads it.
    dd: Option<Dd>,
}

/// A decimal text (`-12.5e-3`, TOML's `1_000`) as its sign, its digits
/// and the power of ten they are scaled by; `None` for anything else.
pub(crate) fn parts(text: &str) -> Option<(bool, String, i64)> {
    let text: String = text.trim().chars().filter(|&c| c != '_').collect();
    let (negative, body) = match text.as_bytes().first()? {
        b'-' => (true, &text[1..]),
        b'+' => (false, &text[1..]),
        _ => (false, &text[..]),
    };
    let (mantissa, exponent) = match body.find(['e', 'E']) {
        Some(i) => (&body[..i], body[i + 1..].parse::<i64>().ok()?),
        None => (body, 0),
    };
    let (int, frac) = mantissa.split_once('.').unwrap_or((mantissa, ""));
    let digits: String = int.chars().chain(frac.chars()).collect();
    if digits.is_empty() || !digits.chars().all(|c| c.is_ascii_digit()) {
        return None;
    }
    Some((negative, digits, exponent.checked_sub(i64::try_from(frac.len()).ok()?)?))
}

impl Decimal {
    /// The decimal a text writes; `None` for anything else (hex, inf, nan).
    pub fn parse(text: &str) -> Option<Decimal> {
        let (negative, digits, exp10) = parts(text)?;
        let magnitude: BigInt = digits.parse().ok()?;
        Some(Decimal { mantissa: if negative { -magnitude } else { magnitude }, exp10, dd: Dd::parse_decimal(text) })
    }

    /// An integer, exactly.
    pub fn integer(n: i64) -> Decimal {
        Decimal { mantissa: BigInt::from(n), exp10: 0, dd: Dd::parse_decimal(&n.to_string()) }
    }

    /// The value as numerator and positive denominator (not reduced).
    pub fn rational(&self) -> (BigInt, BigInt) {
        let ten = BigInt::from(10);
        let power = ten.pow(u32::try_from(self.exp10.unsigned_abs()).unwrap_or(u32::MAX));
        if self.exp10 >= 0 { (&self.mantissa * power, BigInt::one()) } else { (self.mantissa.clone(), power) }
    }

    /// Whether the value is zero.
    pub fn is_zero(&self) -> bool {
        self.mantissa.is_zero()
    }

    /// The text's double-double, as the scene parser reads it.
    pub fn dd(&self) -> Option<Dd> {
        self.dd
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decimals_are_their_exact_rationals() {
        let d = Decimal::parse("-12.5e-3").unwrap();
        assert_eq!(d.rational(), (BigInt::from(-125), BigInt::from(10_000)));
        assert_eq!(Decimal::parse("1_000").unwrap().rational(), (BigInt::from(1000), BigInt::one()));
        assert_eq!(Decimal::parse("2.5E2").unwrap().rational(), (BigInt::from(25) * 10, BigInt::from(1)));
        assert_eq!(Decimal::parse("+.5").unwrap().rational(), (BigInt::from(5), BigInt::from(10)));
        for bad in ["", "-", "inf", "nan", "0x10", "1e", "1.2.3"] {
            assert_eq!(Decimal::parse(bad), None, "{bad}");
        }
        assert_eq!(Decimal::parse("0.1").unwrap().dd(), Dd::parse_decimal("0.1"));
        assert!(Decimal::parse("-0.0").unwrap().is_zero());
    }
}
