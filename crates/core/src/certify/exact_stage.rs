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
/// realized over the input as written. A question about step k is
/// answered from its own slack where every step before it is proven to
/// close there (each of its `kinds` slacks ≥ 0), [`Sign::Undefined`]
/// where one is proven not to, and `None` where one is out of reach; all
/// `None` where the realization does not close in its approximations or
/// a cluster's shape does not close.
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
    // Per step before the deepest question: proven to close (Some(true)), not to (Some(false)), or out of reach.
    let closes: Vec<Option<bool>> = kinds
        .iter()
        .enumerate()
        .map(|(j, &ks)| {
            let signs: Option<Vec<Sign>> = ks.iter().map(|&kind| sign_of(slack(j, kind).sign())).collect();
            signs.map(|s| !s.iter().any(|&s| matches!(s, Sign::Negative | Sign::Undefined)))
        })
        .collect();
    let answer = |(k, kind): (usize, Kind)| {
        let before = &closes[..k.min(closes.len())];
        if before.contains(&Some(false)) {
            return Some(Sign::Undefined);
        }
        if before.contains(&None) {
            return None;
        }
        sign_of(slack(k, kind).sign())
    };
    Some(questions.iter().map(|&q| answer(q)).collect())
}
