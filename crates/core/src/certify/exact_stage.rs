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
use crate::realize::{Construction, Event, Kind};

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

/// The signs of the slacks `questions` for the type prefix `bits` at the
/// base length where the step on the base of `flat` is flat (its target),
/// realized over the input as written. Every step before
/// the deepest question must be proven to close there, each of its
/// `kinds` slack ≥ 0 (else each answer is [`Sign::Undefined`]); `None`
/// where the realization does not close in its approximations, a
/// decision is out of reach, or a cluster's shape does not close.
pub(super) fn slack_signs(
    linkage: &Linkage,
    dec: &Decomposition,
    (bits, flat): (&[bool], Event),
    kinds: &[&[Kind]],
    questions: &[(usize, Kind)],
) -> Option<Vec<Option<Sign>>> {
    let _scope = Scope::enter();
    let con = Construction::<Expr>::new(linkage, dec).ok()?;
    let lambda = flat.kind.target(con.steps[flat.step].r1, con.steps[flat.step].r2);
    let upto = kinds.len();
    let d = con.base_distances_flat(lambda, bits, upto, &[]);
    if d.len() <= upto {
        return None;
    }
    let slack = |k: usize, kind: Kind| kind.slack_value(con.steps[k].r1, con.steps[k].r2, d[k]);
    for (j, &ks) in kinds.iter().enumerate() {
        for &kind in ks {
            match sign_of(slack(j, kind).sign())? {
                Sign::Negative | Sign::Undefined => return Some(vec![Some(Sign::Undefined); questions.len()]),
                Sign::Zero | Sign::Positive => {}
            }
        }
    }
    Some(questions.iter().map(|&(k, kind)| sign_of(slack(k, kind).sign())).collect())
}
