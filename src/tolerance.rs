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
