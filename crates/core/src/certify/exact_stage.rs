//! The certifier's last stage: a question about the lengths that the balls
//! left open, asked of the construction built over the input as written
//! ([`Expr`]). Every answer is proven; one out of reach
//! ([`Decided::TooHard`]) is `None`.

use crate::complexity::Complexity;
use crate::decompose::Decomposition;
use crate::exact::{Decided, Expr, Scope, approximate};
use crate::invert::Inverter;
use crate::linkage::Linkage;
use crate::real::Dd;
use crate::realize::{Construction, Kind};

use super::Sign;

/// The sign an exact decision proves; `None` where it is out of reach.
fn sign_of(d: Decided) -> Option<Sign> {
    match d {
        Decided::Sign(s) if s > 0 => Some(Sign::Positive),
        Decided::Sign(s) if s < 0 => Some(Sign::Negative),
        Decided::Sign(_) => Some(Sign::Zero),
        Decided::Undefined => Some(Sign::Undefined),
        Decided::TooHard => None,
    }
}

/// The signs of the numbers `question` builds over the construction in
/// exact arithmetic (built afresh in its own arena scope, freed on
/// return). `None` where a cluster's shape does not close.
pub(super) fn decide(
    linkage: &Linkage,
    dec: &Decomposition,
    question: impl FnOnce(&Construction<Expr>) -> Vec<Expr>,
) -> Option<Vec<Option<Sign>>> {
    let _scope = Scope::enter();
    let con = Construction::<Expr>::new(linkage, dec).ok()?;
    Some(question(&con).into_iter().map(|e| sign_of(e.sign())).collect())
}

/// Step k's closed-form candidates for `kind` ([`Inverter::candidates`]),
/// every branch decided exactly, each value to double-double precision;
/// sorted, those that double-double cannot tell apart given once. `None`
/// where a decision or a value is out of reach.
pub(super) fn candidates(
    linkage: &Linkage,
    dec: &Decomposition,
    cx: &Complexity,
    k: usize,
    kind: Kind,
) -> Option<Vec<Dd>> {
    let _scope = Scope::enter();
    let con = Construction::<Expr>::new(linkage, dec).ok()?;
    let inverter = Inverter::new(&con, dec, cx, None);
    let s = &con.steps[k];
    let found = inverter.found(k, kind.target(s.r1, s.r2));
    if inverter.decisions().unproven() > 0 {
        return None;
    }
    let mut values = found.into_iter().map(approximate).collect::<Option<Vec<Dd>>>()?;
    values.sort_by(|a, b| a.partial_cmp(b).unwrap_or(std::cmp::Ordering::Equal));
    values.dedup_by(|a, b| *a == *b);
    Some(values)
}
