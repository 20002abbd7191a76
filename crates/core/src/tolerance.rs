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

// ---------------------------------------------------------------------------
// Resource budgets and default steps (not tolerances on values: they bound
// how much work a command does, never decide a question of structure).
// Steps are fractions of the drawing's extent (its bounding-box diagonal),
// so a long chain gets steps as long as its drawing, not as its longest bar.

/// Default geometric step of `trace`, `svg` and `path` (× the drawing's diagonal).
pub const DEFAULT_STEP_FRACTION: f64 = 0.01;

/// Default step of the terminal UI's arrow keys (× the drawing's diagonal).
pub const TUI_STEP_FRACTION: f64 = 1.0 / 60.0;

/// Step of the terminal UI's traces and Cayley curve (× the drawing's diagonal).
pub const TUI_TRACE_STEP_FRACTION: f64 = 1.0 / 150.0;

/// Step of the coarse walk that frames the terminal UI's view (× the drawing's diagonal).
pub const TUI_BOUNDS_STEP_FRACTION: f64 = 1.0 / 20.0;

/// Default sample budget of one walk (`trace`, `svg`, each path of `path`,
/// `bench`'s stepping rows): realizations computed. `--max-samples` changes it.
pub const DEFAULT_MAX_SAMPLES: usize = 100_000;

/// `svg` keeps at most this many trace points (about 64 MB in memory),
/// whatever the sample budget; its traces end there, and it says so.
pub const SVG_MAX_POINTS: usize = 4_000_000;

/// `svg` leaves out a trace point closer than this (× the drawing's diagonal)
/// to the last one drawn: under half a pixel at the SVG's 800-pixel width.
pub const SVG_POINT_GAP_FRACTION: f64 = 5e-4;

/// The terminal UI keeps at most this many numbers (positions and Cayley
/// vectors) of the current motion, and at most [`TUI_MAX_SAMPLES`] samples.
pub const TUI_MAX_NUMBERS: usize = 4_000_000;
pub const TUI_MAX_SAMPLES: usize = 20_000;

/// A walk that meets more than this many jumps in one segment (joints moving
/// farther than the step between adjacent resolvable λ) is in a stretch where
/// the realization is not resolved in f64: the rest of the segment is
/// skipped as one marked jump instead of being crawled through float by float.
pub const STEPPER_MAX_JUMPS_PER_SEGMENT: usize = 32;

/// Two drawn points closer than this many units in the last place of their
/// coordinates cannot be told apart by the drawing: the same point, however
/// small the scene's scale (a resolution limit of f64, not a tolerance).
pub const DRAWN_RESOLUTION_ULPS: f64 = 8.0;

/// A lazy analysis walks further components on demand (`--component K`,
/// `closest`, the UI's `n`) through the realizations at the drawn λ: at most
/// this many prefixes of types are tried, and at most
/// [`LAZY_MAX_NEW_COMPONENTS`] components walked, per request.
pub const LAZY_SEED_PROBES: usize = 1 << 16;
pub const LAZY_MAX_NEW_COMPONENTS: usize = 256;
