//! Numbers for people: significant digits, never a fixed number of decimals,
//! so no scale prints as 0. Used by error messages here and by every
//! presentation layer.

/// A number with 6 significant digits, without trailing zeros.
pub fn fmt_num(x: f64) -> String {
    fmt_sig(x, 6)
}

/// An interval `[a, b]` with the significant digits that tell its ends
/// apart: six, or more for a narrow one (two past the digits of its
/// relative width), up to 17 (a width of a few ulps).
pub fn fmt_span([a, b]: [f64; 2]) -> String {
    let size = a.abs().max(b.abs());
    let width = (b - a).abs();
    let needed = if width > 0.0 && size > 0.0 { (size / width).log10().ceil() + 2.0 } else { 6.0 };
    let digits = if needed.is_finite() { (needed as usize).clamp(6, 17) } else { 17 };
    format!("[{}, {}]", fmt_sig(a, digits), fmt_sig(b, digits))
}

/// A number with `digits` significant digits (1 to 17), trailing zeros
/// dropped: positional between 1e-4 and 1e9, else scientific (`4.41093e-20`).
/// Never a fixed number of decimals, so no scale prints as 0.
pub fn fmt_sig(x: f64, digits: usize) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let digits = digits.clamp(1, 17);
    let exp = x.abs().log10().floor() as i32;
    let trim = |s: &str| -> String {
        if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_string() } else { s.to_string() }
    };
    if (-4..9).contains(&exp) {
        let decimals = (digits as i32 - 1 - exp).max(0) as usize;
        trim(&format!("{x:.decimals$}"))
    } else {
        let s = format!("{x:.prec$e}", prec = digits - 1);
        match s.split_once('e') {
            Some((mantissa, e)) => format!("{}e{e}", trim(mantissa)),
            None => s,
        }
    }
}

/// A small number in scientific notation (errors, residuals).
pub fn fmt_sci(x: f64) -> String {
    if x == 0.0 { "0".to_string() } else { format!("{x:.1e}") }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spans_keep_the_digits_that_tell_their_ends_apart() {
        assert_eq!(fmt_span([23.792308, 53.792308]), "[23.7923, 53.7923]");
        assert_eq!(fmt_span([1.0, 1.0 + 1e-9]), "[1, 1.000000001]");
        let (a, b) = (2.5, 2.5f64.next_up());
        assert_eq!(fmt_span([a, b]), format!("[{}, {}]", fmt_sig(a, 17), fmt_sig(b, 17)));
        assert_ne!(fmt_sig(a, 17), fmt_sig(b, 17));
        assert_eq!(fmt_span([0.0, 0.0]), "[0, 0]");
    }
}
