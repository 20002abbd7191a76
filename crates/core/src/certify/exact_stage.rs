//! The certifier's last stage: a question about the lengths that the balls
//! left open, asked of the construction built over the input as written
//! ([`Expr`]). Every answer is proven; one out of reach
//! ([`Decided::TooHard`]) is `None`.

use crate::decompose::Decomposition;
use crate::exact::{Decided, Expr, Scope};
use crate::linkage::Linkage;
use crate::realize::Construction;

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
