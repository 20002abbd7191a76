//! Every tolerance of the solver, in one place. All are relative to the scene's
//! scale (`Linkage::scale`: its longest bar or rigid-body span),
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

/// Base joints closer than this (× scale, about √ε) make a step's vertex
/// direction ill-conditioned in f64: a shown realization is then computed
/// in double-double (a choice of precision for display, not a decision).
pub const NEAR_JOINTS: f64 = 1e-8;

/// A computed root whose slack slope |d slack/dλ| (dimensionless) is below
/// this is a tangency (double root) and is classified by its curvature. For
/// f64 this is 1e-10; for a finer type it shrinks with √(unit roundoff):
/// near a double root, roots are only located to about √u.
pub fn tangent_slope(unit_roundoff: f64) -> f64 {
    1e-10 * (unit_roundoff / (f64::EPSILON / 2.0)).sqrt()
}

/// Within this (× scale) of flat, a step's vertex is known only to about
/// √(unit roundoff) of the scale (its height is a square root of a slack
/// at rounding level), and so is every later slack built on it: a later
/// slack within this of zero beside it is not read as a sign by the lazy
/// walk, which asks the certifier instead. For f64 about 1.7e-7.
pub fn touch_noise(unit_roundoff: f64) -> f64 {
    16.0 * unit_roundoff.sqrt()
}

/// The lazy walk halves a gap between its samples down to this width
/// (× scale), and accepts an end once it lies within this of the sample
/// before it: far below any feature a user draws, far above f64 resolution.
pub const ROOT_STEP: f64 = 1e-9;

/// An extremum of a slack (or of g = d_k − t) within this (× scale) of zero
/// is a touch: a tangent (double) root, noted as such (`roots::Extremum`); two
/// roots that close together are not separated at f64 precision.
pub const ROOT_VALUE: f64 = 1e-12;

/// The lazy walk recognises an interval end it computed before (same type,
/// side and flat steps) within this (× scale): its own root found twice, not
/// a question about the mechanism. Whether two different events coincide is
/// never decided by a tolerance: see the `certify` module.
pub const EVENTS_COINCIDE: f64 = 1e-11;

/// Intervals of the non-oriented Cayley space closer than this (× scale) are joined.
pub const UNION_GAP: f64 = 1e-12;

/// The lazy walk samples toward every interval end it finds (and away from
/// the end it enters by) down to this distance (× scale): there the later
/// steps behave like square roots and their derivatives say nothing. The
/// gap that touches the end is at most [`APPROACH_RATIO`] times this and is
/// not refined: a dip of a later step's slack inside it that does not
/// change the slack's sign at its ends is not looked for.
pub const LAZY_APPROACH: f64 = 1e-7;

// ---------------------------------------------------------------------------
// Resource budgets and default steps (not tolerances on values: they bound
// how much work a command does, never decide a question of structure).
// Steps are fractions of the drawing's extent (its bounding-box diagonal),
// so a long chain gets steps as long as its drawing, not as its longest bar.

/// Scenes with at least this many construction steps spread the lazy walk
/// and its self-check over two threads (see `lazy::LazyOptions`); below,
/// starting a thread costs about what it saves.
pub const TWO_THREADS_FROM_STEPS: usize = 256;

/// Default geometric step of `trace`, `svg` and `path` (× the drawing's diagonal).
pub const DEFAULT_STEP_FRACTION: f64 = 0.01;

/// Default step of the terminal UI's arrow keys (× the drawing's diagonal).
pub const TUI_STEP_FRACTION: f64 = 1.0 / 60.0;

/// The terminal UI's arrow-key step is never halved below this (× the drawing's diagonal).
pub const TUI_MIN_STEP_FRACTION: f64 = 1e-6;

/// The terminal UI's edit mode moves a joint or changes a bar's length by
/// the power of ten at or below this (× the drawing's diagonal) per fine
/// step, so edited numbers stay short decimals …
pub const TUI_EDIT_FINE_FRACTION: f64 = 0.01;

/// … and by the power of ten at or below this per coarse step.
pub const TUI_EDIT_COARSE_FRACTION: f64 = 0.1;

/// Default step of the terminal UI's angle drive, degrees of the input bar.
pub const TUI_ANGLE_STEP_DEGREES: f64 = 10.0;

/// The angle drive scans the motion in samples between which the input bar
/// turns at most about this (radians: its tip moves at most this × its
/// length), so the angle unwraps unambiguously (well under a half turn).
pub const TUI_ANGLE_SCAN_TURN: f64 = 0.05;

/// The terminal UI's "go to λ" accepts a λ this far (× scale) outside a
/// segment of the current motion as on it (a λ typed from a printed end).
pub const TUI_GOTO_MARGIN: f64 = 1e-12;

/// `bench` matches a method's interval to the reference's when they overlap
/// to within this (× scale): far wider than any error it then reports.
pub const BENCH_MATCH_SLACK: f64 = 1e-6;

/// The fixed absolute tolerance of the classic baseline `bench` measures
/// (CayMos's approach, THEORY.md §6): deliberately not scaled, as the
/// baseline does it; never used by the analysis itself.
pub const CLASSIC_ABSOLUTE_TOL: f64 = 1e-4;

/// Step of the terminal UI's traces and Cayley curve (× the drawing's diagonal).
pub const TUI_TRACE_STEP_FRACTION: f64 = 1.0 / 150.0;

/// Step of the coarse walk that frames the terminal UI's view (× the drawing's diagonal).
pub const TUI_BOUNDS_STEP_FRACTION: f64 = 1.0 / 20.0;

/// Samples of the coarse walk that picks the terminal UI's default traced joint.
pub const TUI_MOVER_SAMPLES: usize = 200;

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
/// See [`TUI_MAX_NUMBERS`]: the terminal UI's sample cap per motion.
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
/// See [`LAZY_SEED_PROBES`]: at most this many components walked per request.
pub const LAZY_MAX_NEW_COMPONENTS: usize = 256;

/// Bisection and Newton iterations of the root finder stop after this many
/// steps: a bracket halves each time, so 200 exhaust any f64 or
/// double-double range; a bound on work, never reached in practice.
pub const ROOT_MAX_ITERATIONS: usize = 200;

/// A Newton step at x of at most this many units of the scalar type's
/// roundoff × |x| has converged: the step is rounding noise (root finder,
/// and the double-double re-location of an end in `certify`).
pub const NEWTON_CONVERGED_ULPS: f64 = 4.0;

/// Newton has reached the rounding floor when a step is no shorter than the
/// one before and both are below this fraction of the bracket's magnitude:
/// quadratic convergence shrinks every step far more until rounding noise
/// (which on deep chains is many ulps) decides the steps. Precision, not
/// structure: the end's flat steps are proven afterwards (`certify`).
pub const NEWTON_FLOOR: f64 = 1e-9;

/// The numeric root search splits a gap at an inflection (or halves it) at
/// most this many times: below 2^-40 of a gap the sample spacing holds no
/// more structure than f64 resolves. A bound on work.
pub const ROOT_MAX_SPLITS: u32 = 40;

/// An inflection of d_k found within this fraction of a gap's width from
/// its end belongs to that end (a previous split put it there): the gap is
/// not split again there.
pub const INFLECTION_AT_END: f64 = 1e-6;

/// A closed-form candidate whose slack (in f64, for the prefix being
/// refined) is farther than this × scale from zero is asked about with f64
/// balls before the gaps beside it: likely another branch's root, whose
/// proven slacks then decide both gaps. A matter of cost only (nearer
/// candidates are placed as roots and their gaps asked at midpoints, as
/// before); every decision still rests on a proof.
pub const OFF_ROOT: f64 = 1e-8;

/// Where step k is proven flat at a piece end, a root candidate within this
/// many units of roundoff × |λ| of that end is the same root computed
/// another way (the closed form and the end's own λ differ by rounding).
pub const SAME_ROOT_ULPS: f64 = 8.0;

/// Two closed-form candidates within this many units of roundoff × |λ| of
/// each other are one candidate reached along two branches of the inversion.
pub const SAME_CANDIDATE_ULPS: f64 = 4.0;

/// The closed-form inversion clamps 1 ∓ cos down to −this many units of
/// roundoff to 0 (dimensionless: a ratio of lengths): rounding at an
/// exactly flat triangle, not an infeasible one.
pub const INVERT_CLAMP_ULPS: f64 = 64.0;

/// λ is resolved in f64 to this many units of roundoff of max(|λ|, scale):
/// the smallest λ step a walk takes, and the first half-width tried for a
/// proven bracket around an interval end (`certify`, `enclosure`).
pub const LAMBDA_RESOLUTION_ULPS: f64 = 8.0;

/// An interval end is searched for a proven bracket up to this half-width
/// (× scale), growing by [`END_BRACKET_GROWTH`] from
/// [`LAMBDA_RESOLUTION_ULPS`]: a bound on work, not a decision. An end
/// placed worse than this stays unproven (and is said so).
pub const END_BRACKET_MAX: f64 = 1e-6;

/// Factor by which the bracket half-width grows between tries in `certify`
/// where no secant through the last try's slacks says how far to go.
pub const END_BRACKET_GROWTH: f64 = 16.0;

/// The most a bracket half-width grows between two tries in `certify` on
/// the secant's estimate: a bound on work (and on how much wider than
/// needed a bracket can come out), not a decision.
pub const END_BRACKET_JUMP: f64 = 256.0;

/// How many times over the slack's estimated change across a bracket
/// should clear its balls' radii (`certify`'s next try): a margin for the
/// secant's error, not a decision.
pub const BRACKET_SECANT_MARGIN: f64 = 2.0;

/// Factor by which the bracket half-width grows between tries in
/// `enclosure` (interval arithmetic, cheaper per try than `certify`'s balls).
pub const ENCLOSURE_BRACKET_GROWTH: f64 = 4.0;

/// A proven bracket's radius is widened by this relative margin, so that
/// rounding of λ ± δ keeps both tried ends inside the ball.
pub const BRACKET_RADIUS_MARGIN: f64 = 1e-12;

/// The deepest step whose slack is asked of the exact stage at an exact λ
/// (an expression over that many placements): a bound on work. Deeper,
/// the separation bound is far past the exact stage's reach anyway.
pub const EXACT_SLACK_STEPS: usize = 24;

/// A slack whose ball at an end's centre is already this wide (× scale)
/// cannot prove a sign change within any bracket tried: the search is
/// skipped (a bound on work). Deep in a chain a slack's ball is wide and
/// its slope steep alike (1e-7 and 1e9 at step 996 of 1000), so a
/// bracket of 1e-16 still proves the change: not 1e-8, which sent such
/// ends to double-double balls.
pub const BALL_TOO_WIDE: f64 = 1e-2;

/// Newton steps that re-locate an end in double-double from its f64 value
/// (each doubles the correct digits: 6 go far beyond double-double's 32).
pub const DD_NEWTON_STEPS: usize = 6;

/// A double-double Newton step below this × f64's unit roundoff × |λ| has
/// refined an f64 end: the error left (quadratically smaller than the
/// step) changes neither its rounding to f64 nor the measured f64 error.
pub const DD_REFINED: f64 = 1e-8;

/// A double-double Newton step longer than this (× scale) is not a
/// refinement of an end located in f64: the re-location stops there.
pub const DD_NEWTON_MAX_STEP: f64 = 1e-6;

/// Double-double balls are about u_dd/u_f64 of the f64 ones wide; they are
/// skipped where even this many times that would not exclude zero.
pub const DD_BALL_SHRINK_MARGIN: f64 = 16.0;

/// A sign the balls could not prove is decided by the double-double value
/// when it exceeds its error, estimated as the f64 − double-double
/// difference scaled to double-double precision times this margin (2^10) …
pub const ESTIMATE_MARGIN: f64 = 1024.0;

/// … plus this many units of double-double roundoff × scale (a floor for a
/// difference that happens to vanish).
pub const ESTIMATE_FLOOR_ULPS: f64 = 64.0;

/// A start that may be an isolated point is tested on both sides at this
/// offset (× scale): far above double-double resolution, far below any
/// feature a user draws.
pub const ISOLATED_SIDE_OFFSET: f64 = 1e-9;

/// The lazy walk refines a gap whose slack it cannot certify by sampling all
/// steps at once down to this width (× scale), then by that slack's own search.
pub const WELL_SAMPLED_COARSE: f64 = 1e-7;

/// A gap is well sampled when each slack's quadratic Taylor model from one
/// end predicts its value at the other to within this fraction of the slack's
/// mean size there.
pub const MODEL_MARGIN: f64 = 0.25;

/// A slack within this many units of roundoff × scale below zero at a near
/// tangency is rounding, not a crossing (lazy walk).
pub const TANGENCY_NOISE_ULPS: f64 = 64.0;

/// The lazy walk's next gap aims the jets' model error at this fraction of
/// the margin that still certified the last gap (the error grows as the gap
/// cubed, so the gap scales by the cube root). A step-size choice only: every
/// gap is certified or refined whatever its length.
pub const LAZY_MODEL_AIM: f64 = 0.5;

/// The lazy walk's next gap is at least this fraction of the last one (a
/// gap the model predicted badly shrinks, but not to nothing).
pub const LAZY_MIN_GROWTH: f64 = 0.25;

/// The lazy walk's samples next to an end: each at least this factor closer
/// to an end it approaches than the one before, and no gap more than this
/// factor longer than the one before.
pub const APPROACH_RATIO: f64 = 8.0;

/// Where a step degenerates exactly at λ (its base joints coincide), the
/// realization's limit is taken at λ nudged toward the segment's interior by
/// the first of these (× scale) that realizes.
pub const DEGENERATE_NUDGES: [f64; 3] = [1e-12, 1e-10, 1e-8];

/// The relative gap the closest pair is certified to by default
/// (`closest --gap`): upper − lower ≤ gap × upper.
pub const DEFAULT_GAP: f64 = 1e-9;

/// The closest-pair search's work budget in boxes × construction steps:
/// each box encloses pieces of both components through every step (about
/// 0.3 µs per box and step), so a deep scene gets fewer boxes and the same
/// bound on time, about 3 s (a bound on work, not a decision: a search that
/// reaches it says so and certifies nothing).
pub const CLOSEST_BOX_STEPS: usize = 10_000_000;

/// A closest-pair piece is saturated (splitting it cannot sharpen a bound)
/// when its vector's spread over the piece is at most this × its own rounding
/// width at the centre.
pub const SATURATION_FACTOR: f64 = 4.0;

/// The second-order bound caps |h_ab| at √(h_aa h_bb)(1 − this): a relative
/// margin that keeps the determinant provably ≥ 0 after rounding.
pub const CONVEX_CAP_MARGIN: f64 = 1e-9;

/// Gauss–Newton polishing of the best pair is damped by this × the trace of
/// JᵀJ (Levenberg), enough to keep a singular step finite.
pub const POLISH_DAMPING: f64 = 1e-12;

/// Gauss–Newton polishing shortens a step that did not improve the best
/// pair by this factor …
pub const POLISH_SHRINK: f64 = 4.0;

/// … and stops once the step is below this fraction of a full one.
pub const POLISH_MIN_STEP: f64 = 0.01;

/// The enclosure near an end switches from the direct √S to the anchored
/// form when t is within this fraction of the box's far end …
pub const NEAR_END_FRACTION: f64 = 0.25;

/// … or when √S's enclosure is wider than this × its lower bound (loose
/// next to the end). Either form is sound: this only saves work.
pub const LOOSE_ENCLOSURE: f64 = 1e-6;

/// Whether two drawn points are the same point: exactly equal, within
/// [`COINCIDENT`] × the scene's scale, or closer than the drawing can resolve
/// ([`DRAWN_RESOLUTION_ULPS`] units in the last place of their coordinates).
/// All three arguments are halved (so that drawings near ±f64::MAX stay
/// finite): the points' distance, their largest |coordinate|, the scale.
pub fn same_drawn_point(half_distance: f64, half_magnitude: f64, half_scale: f64) -> bool {
    half_distance <= same_drawn_point_reach(half_magnitude, half_scale)
}

/// The largest half-distance [`same_drawn_point`] takes for the same point,
/// for points whose largest |coordinate| is at most 2 × `half_magnitude`.
pub fn same_drawn_point_reach(half_magnitude: f64, half_scale: f64) -> f64 {
    (COINCIDENT * half_scale).max(DRAWN_RESOLUTION_ULPS * f64::EPSILON * half_magnitude)
}

/// A sweep keeps at most this many refinements to repeat for prefixes that
/// agree on the bits a step reads (`cayley_space::RefineKey`), then starts
/// afresh: a bound on memory, not a decision (repeats come from the types
/// just visited).
pub const REFINEMENTS_KEPT: usize = 4096;

/// `Scope::Auto` sweeps every type only where the sweep's estimated cost
/// (`cayley_space::SweepPlan::cost`, in realization steps) is at most this,
/// about a second on this project's machine (a generated 10-step chain
/// is 3.9e5, an 11-step one 1.8e6, a four-legged Strandbeest 1.9e3); above it the lazy walk.
/// A budget on work, not a decision about the mechanism.
pub const SWEEP_COST_MAX: f64 = 5e5;

/// The largest `--max-samples` a walking command takes: a budget the user
/// may raise, but not past a bounded cost (realizations of the whole scene).
pub const MAX_SAMPLES_LIMIT: usize = 10_000_000;

/// The largest `bench --repeat` (timed repetitions of every method).
pub const MAX_REPEAT: usize = 1000;

/// The largest generated families (`generate chain --steps`,
/// `generate strandbeest --legs`): files of a few MB, analysed lazily.
pub const MAX_GENERATED_STEPS: usize = 100_000;
/// See [`MAX_GENERATED_STEPS`].
pub const MAX_GENERATED_LEGS: usize = 10_000;

/// The full analysis (`Scope::Full`, `--all`) is refused where its
/// closed-form candidates' search could exceed this many branches
/// (`cayley_space::candidate_search_bound`, before any is computed) …
pub const FULL_SEARCH_MAX: f64 = 1e8;
/// … or where its sweep is estimated above this many realization steps
/// (`cayley_space::SweepPlan::cost`; about a quarter of an hour on this
/// project's machine: a generated 16-step chain is 9.2e7 and takes 78 s,
/// an 18-step one 9.3e10).
pub const FULL_COST_MAX: f64 = 1e9;

/// A sweep keeps the realized prefixes of at most this many places
/// (`certify::Prefixes`), then starts afresh: a bound on memory, not a decision.
pub const PREFIX_PLACES: usize = 4096;
