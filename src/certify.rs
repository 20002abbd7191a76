//! Structural decisions proven, not guessed: is a step's slack positive,
//! zero or negative at an interval end or inside a gap?
//!
//! Each question is first asked in [`Ball`] arithmetic over f64 (a
//! midpoint-radius enclosure of the exact value, from the lengths as
//! written): a ball that excludes zero proves the sign. Where it does not,
//! the same question is asked again in balls over double-double, with the
//! end's λ re-located in double-double. A ball that still holds zero is
//! answered [`Sign::Zero`]: the two events coincide (or the slack touches
//! zero) to within double-double resolution, a non-generic place that the
//! caller reports as such.
//!
//! An end λ* is the root of the flat step's slack. It is enclosed by a
//! bracket [λ − δ, λ + δ] whose ends have proven opposite slack signs (so
//! λ* lies inside), and the other slacks are evaluated on that whole
//! bracket with the flat steps placed exactly flat — the realization at λ*.

use crate::cayley_space::{Event, Kind};
use crate::decompose::Decomposition;
use crate::linkage::Linkage;
use crate::real::{Ball, Dd, Jet, Real};
use crate::realize::Construction;

/// A proven sign; `Zero` when not even double-double separates the value from 0.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sign {
    Negative,
    Zero,
    Positive,
}

impl Sign {
    fn of(sign: Option<i8>) -> Option<Sign> {
        sign.map(|s| if s > 0 { Sign::Positive } else { Sign::Negative })
    }
}

/// The construction in the three arithmetics a decision may need.
#[derive(Debug, Clone)]
pub struct Certifier {
    f64_balls: Construction<Ball<f64>>,
    dd_balls: Construction<Ball<Dd>>,
    dd_jets: Construction<Jet<Dd>>,
}

/// Where a question is asked: a λ, and the steps flat there (empty for a
/// point inside an interval, whose λ is then taken as exact).
#[derive(Clone, Copy, Debug)]
pub struct At<'a> {
    pub lambda: f64,
    pub events: &'a [Event],
}

impl Certifier {
    pub fn new(linkage: &Linkage, dec: &Decomposition) -> Option<Self> {
        Some(Certifier {
            f64_balls: Construction::new(linkage, dec).ok()?,
            dd_balls: Construction::new(linkage, dec).ok()?,
            dd_jets: Construction::new(linkage, dec).ok()?,
        })
    }

    /// The proven sign of step `k`'s slack for `kind` at `at`, for the type
    /// prefix `bits` (at least `k` bits).
    pub fn slack_sign(&self, bits: &[bool], at: At, k: usize, kind: Kind) -> Sign {
        self.slack_signs(bits, at, &[(k, kind)])[0]
    }

    /// [`Self::slack_sign`] for several (step, kind) questions at one place,
    /// sharing the realizations.
    pub fn slack_signs(&self, bits: &[bool], at: At, questions: &[(usize, Kind)]) -> Vec<Sign> {
        let upto = questions.iter().map(|&(k, _)| k).max().unwrap_or(0);
        let mut out: Vec<Option<Sign>> = vec![None; questions.len()];
        let lambda = Dd::new(at.lambda);
        if let Some(l) = self.bracket(&self.f64_balls, bits, at, lambda) {
            self.decide(&self.f64_balls, bits, at.events, l, upto, questions, &mut out);
        }
        if out.iter().any(Option::is_none) {
            let refined = self.refine_dd(bits, at, lambda);
            if let Some(l) = self.bracket(&self.dd_balls, bits, at, refined) {
                self.decide(&self.dd_balls, bits, at.events, l, upto, questions, &mut out);
            }
        }
        out.into_iter().map(|s| s.unwrap_or(Sign::Zero)).collect()
    }

    /// The proven sign of step `k`'s slack (both kinds: positive where the
    /// triangle closes) at a λ inside an interval (taken as exact).
    pub fn closes_sign(&self, bits: &[bool], lambda: f64, k: usize) -> Sign {
        let at = At { lambda, events: &[] };
        let signs = self.slack_signs(bits, at, &[(k, Kind::Stretched), (k, Kind::Folded)]);
        match (signs[0], signs[1]) {
            (Sign::Negative, _) | (_, Sign::Negative) => Sign::Negative,
            (Sign::Positive, Sign::Positive) => Sign::Positive,
            _ => Sign::Zero,
        }
    }

    /// Answer what `con`'s balls can prove on the λ enclosure `l`.
    #[allow(clippy::too_many_arguments)]
    fn decide<T: Real>(
        &self,
        con: &Construction<Ball<T>>,
        bits: &[bool],
        events: &[Event],
        l: Ball<T>,
        upto: usize,
        questions: &[(usize, Kind)],
        out: &mut [Option<Sign>],
    ) {
        let flat: Vec<usize> = events.iter().map(|e| e.step).filter(|&s| s < upto).collect();
        let Ok(pos) = con.realize_flat(l, bits, upto, &flat) else { return };
        for (slot, &(k, kind)) in out.iter_mut().zip(questions) {
            if slot.is_none() {
                let s = &con.steps[k];
                let d = con.base_distance(&pos, k);
                *slot = Sign::of(kind.slack_value(s.r1, s.r2, d).sign());
            }
        }
    }

    /// An enclosure of the end λ* near `lambda`: for an end with a flat step,
    /// the smallest tried bracket whose ends have proven opposite signs of
    /// that step's slack; inside an interval, λ itself (exact).
    fn bracket<T: Real>(&self, con: &Construction<Ball<T>>, bits: &[bool], at: At, lambda: Dd) -> Option<Ball<T>> {
        let Some(event) = at.events.first() else { return Some(Ball::exact(T::from_dd(lambda))) };
        let s = &con.steps[event.step];
        let slack = |x: T| -> Option<i8> {
            let pos = con.realize_prefix(Ball::exact(x), bits, event.step).ok()?;
            let d = con.base_distance(&pos, event.step);
            event.kind.slack_value(s.r1, s.r2, d).sign()
        };
        let centre = T::from_dd(lambda);
        let scale = con.scale;
        let mut delta = 8.0 * T::UNIT_ROUNDOFF * lambda.to_f64().abs().max(scale);
        while delta < 1e-6 * scale {
            let (lo, hi) = (centre - T::from_f64(delta), centre + T::from_f64(delta));
            if let (Some(a), Some(b)) = (slack(lo), slack(hi))
                && a != b
            {
                return Some(Ball { m: centre, r: delta * (1.0 + 1e-12) });
            }
            delta *= 16.0;
        }
        None
    }

    /// The end's λ located in double-double: Newton on the flat step's
    /// slack from the f64 value (a few steps double the digits each).
    fn refine_dd(&self, bits: &[bool], at: At, lambda: Dd) -> Dd {
        let Some(event) = at.events.first() else { return lambda };
        let con = &self.dd_jets;
        let s = &con.steps[event.step];
        let mut x = lambda;
        for _ in 0..6 {
            let Ok(pos) = con.realize_prefix(Jet::variable(x), bits, event.step) else { break };
            let g = event.kind.slack_value(s.r1, s.r2, con.base_distance(&pos, event.step));
            let step = g.v / g.d;
            if !step.to_f64().is_finite() || step.to_f64().abs() > 1e-6 * con.scale {
                break;
            }
            x = x - step;
        }
        x
    }
}
