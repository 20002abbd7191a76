//! Every tolerance of the solver, in one place. All are relative to the scene's
//! [scale](crate::linkage::Linkage::scale) (its longest bar or rigid-body span),
//! so a scene scaled by 1e3 or 1e-3 gives the same answers scaled.

/// Two drawn points closer than this (× scale) are the same point.
pub const COINCIDENT: f64 = 1e-12;

/// A step whose slack is above `-FEASIBLE × scale` is treated as flat rather
/// than infeasible when realizing: rounding in earlier steps may push an exact
/// endpoint a few ulps outside. Far below any geometric feature a user draws.
pub const FEASIBLE: f64 = 1e-10;

/// A drawn step whose triangle height is below this (× scale) is called flat in
/// the drawing (its orientation bit is then a choice, reported as a warning).
pub const DRAWN_FLAT: f64 = 1e-9;

/// A realization meets its bars when every bar length is within this (× scale).
pub const BAR_RESIDUAL: f64 = 1e-9;

/// A computed root whose slack slope |d slack/dλ| (dimensionless) is below
/// this is a tangency (double root) and is classified by its curvature. For
/// f64 this is 1e-10; for a finer type it shrinks with √(unit roundoff):
/// near a double root, roots are only located to about √u.
pub fn tangent_slope(unit_roundoff: f64) -> f64 {
    1e-10 * (unit_roundoff / (f64::EPSILON / 2.0)).sqrt()
}

/// A candidate λ is accepted as a root of `d_k(λ) = t` when the Newton
/// correction |g/g'| is below this (× scale), or |g| itself is below
/// [`ROOT_VALUE`] (× scale), which covers tangent roots where g' vanishes.
pub const ROOT_STEP: f64 = 1e-9;
pub const ROOT_VALUE: f64 = 1e-12;

/// The lazy walk recognises an interval end it computed before (same type,
/// side and flat steps) within this (× scale): its own root found twice, not
/// a question about the mechanism. Whether two different events coincide is
/// never decided by a tolerance: see [`crate::certify`].
pub const EVENTS_COINCIDE: f64 = 1e-11;

/// Intervals of the non-oriented Cayley space closer than this (× scale) are joined.
pub const UNION_GAP: f64 = 1e-12;

/// The lazy walk samples geometrically toward every interval end it finds
/// (and away from the end it enters by), down to this distance (× scale):
/// there the later steps behave like square roots and their derivatives
/// say nothing. A dip of a later step's slack closer than this to an end is
/// not looked for.
pub const LAZY_APPROACH: f64 = 1e-7;
