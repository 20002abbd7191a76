//! The one entry point both the report and the terminal UI use: scene in,
//! everything the solver knows about it out.

use std::sync::Arc;
use std::time::Instant;

use crate::cayley_space::{
    CayleySpace, Method, Note, OrientedInterval, SweepPlan, cayley_space, cayley_space_planned, union,
};
use crate::cayley_vector::{Mirrors, mirror_images};
use crate::certify::{Certifier, StageCounts};
use crate::complexity::{Complexity, four_cycle_test};
use crate::decompose::{Decomposition, Outside, decompose};
use crate::invert::candidate_search_bound;
use crate::lazy::{LazyOptions, component_through};
use crate::linkage::Linkage;
use crate::minimal_vector::{MinimalOptions, MinimalVector, minimal_vector};
use crate::motion::{Components, components, locate};
use crate::real::{Dd, Jet, Real};
use crate::realize::{
    Construction, Drawn, Event, Point2, Realization, RealizationType, Unrealizable, bar_residual, drawn_realization,
    to_display,
};
use crate::scene::{Scene, SceneError};

/// Wall-clock time of each phase, in microseconds (for the report; never asserted).
#[derive(Debug, Clone, Default)]
pub struct Timings(pub Vec<(&'static str, f64)>);

impl Timings {
    /// Run `f`, recording its wall time under `phase`.
    pub fn time<R>(&mut self, phase: &'static str, f: impl FnOnce() -> R) -> R {
        let start = Instant::now();
        let out = f();
        self.0.push((phase, start.elapsed().as_secs_f64() * 1e6));
        out
    }
}

/// How far a sketch (a scene with stated lengths) was from its realization.
#[derive(Debug, Clone, PartialEq)]
pub struct SketchFit {
    /// Largest |stated − drawn| bar length.
    pub max_length_change: f64,
    /// Largest joint displacement from the drawing to the realization (display frame).
    pub max_joint_move: f64,
}

/// How the f64 endpoints compare with the double-double reference run,
/// which starts from the input as written (decimal coordinates and stated
/// lengths read into double-double), so input rounding is measured too.
#[derive(Debug, Clone, PartialEq)]
pub struct Accuracy {
    /// Largest |λ_f64 − λ_reference| over all endpoints, in scene units.
    pub max_endpoint_error: f64,
    /// The same relative to the scene scale.
    pub max_relative_error: f64,
    /// Largest |λ_f64 − λ_reference| / |λ_reference|: digits lost where an
    /// endpoint is a small difference of large lengths.
    pub max_error_of_value: f64,
    /// Whether both runs found the same intervals (same types, same count).
    pub same_structure: bool,
    /// The reported endpoints are the reference's, rounded to f64 (so within
    /// half an ulp of their own value), not the f64 run's.
    pub refined: bool,
}

/// Scenes with more types than this skip the reference run in `analyse`.
pub const REFERENCE_MAX_TYPES: usize = 1 << 12;

/// Scenes with more construction steps than this (more than 2^16 types) get
/// the lazy analysis unless the full one is asked for; so do smaller ones
/// whose full sweep is estimated above [`crate::tolerance::SWEEP_COST_MAX`].
pub const LAZY_ABOVE_STEPS: usize = 16;

/// The lazy analysis checks itself up to this many steps, by refining its
/// ends in double-double ([`lazy_reference_accuracy`]: a few realizations
/// per end, a fraction of the walk: about two fifths of it on a 1000-step
/// chain), and then shows the refined ends. It was 128 when the check was a
/// second walk in double-double; beyond the cap the f64 ends are shown.
pub const LAZY_REFERENCE_MAX_STEPS: usize = 4096;

/// How much of the realization space to compute.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scope {
    /// Every type when there are at most 2^[`LAZY_ABOVE_STEPS`] and the
    /// sweep's estimated cost is within [`crate::tolerance::SWEEP_COST_MAX`],
    /// else lazy.
    Auto,
    /// Every type's intervals and every component, however many.
    Full,
    /// Only the component through the drawn realization (more on request,
    /// see [`Solved::include`]).
    Lazy,
}

/// A scene recognised as 1-dof tree-decomposable.
#[derive(Debug, Clone)]
pub struct Solved {
    /// The base and the construction steps.
    pub dec: Arc<Decomposition>,
    /// The four-cycle test: low Cayley complexity, the complete Cayley vector, the carriers.
    pub complexity: Complexity,
    /// The construction in f64: every step's lengths and member placements
    /// (shared with the certifier).
    pub construction: Arc<Construction<f64>>,
    /// The construction in proven (ball) arithmetic, for structural decisions.
    pub certifier: Certifier,
    /// Whether mirror images of realizations are realizations too (proven).
    pub mirrors: Mirrors,
    /// The drawn realization's (λ, type) and the steps flat in the drawing.
    pub drawn: Drawn,
    /// The drawn realization in the display frame (the drawing itself unless a sketch).
    pub drawn_positions: Option<Vec<Point2<f64>>>,
    /// How far the stated lengths move the drawing (`None` when no length is stated).
    pub sketch: Option<SketchFit>,
    /// The oriented Cayley configuration space (every type, or the computed components).
    pub space: CayleySpace<f64>,
    /// The non-oriented Cayley configuration space.
    pub union: Vec<[f64; 2]>,
    /// Against the double-double reference (`None` when skipped for size,
    /// or not asked for: [`SelfCheck::Skip`]).
    pub accuracy: Option<Accuracy>,
    /// The connected components: cycles of oriented intervals of `space`.
    pub components: Components,
    /// The oriented interval and component holding the drawn realization.
    pub drawn_interval: Option<usize>,
    /// The component holding the drawn realization (`None` when it has none).
    pub drawn_component: Option<usize>,
    /// Only the components through realizations asked for were computed
    /// (`space` then holds their intervals, each component's sorted by type,
    /// and `union` is their λ range, not the whole Cayley space).
    pub lazy: bool,
    /// The full sweep's estimated cost in realization steps
    /// ([`SweepPlan::cost`]), where it was estimated (a full analysis, or
    /// `Scope::Auto` within [`LAZY_ABOVE_STEPS`]).
    pub sweep_estimate: Option<f64>,
}

impl Solved {
    /// The minimal complete Cayley vector of the components computed so far
    /// (see [`crate::minimal_vector`](mod@crate::minimal_vector)).
    pub fn minimal_vector(&self, options: MinimalOptions) -> MinimalVector {
        let (con, ccv) = (&self.construction, &self.complexity.ccv);
        minimal_vector(con, &self.space, &self.components.list, ccv, self.mirrors, options)
    }

    /// Make sure the component through `r` is known: in a lazy analysis it is
    /// walked and added (existing interval and component indices stay valid).
    /// Returns the interval holding `r`, or `None` if `r` has no realization.
    pub fn include(&mut self, r: &Realization) -> Option<usize> {
        let scale = self.construction.scale;
        if let Some(i) = locate(&self.space, r, scale) {
            return Some(i);
        }
        if !self.lazy || r.ty.0.len() != self.construction.steps.len() {
            return None;
        }
        let jet = self.construction.convert::<Jet<f64>>();
        let more =
            component_through(&self.construction, &self.certifier, &jet, &r.ty, r.lambda, LazyOptions::default())
                .ok()?;
        let offset = self.space.intervals.iter().map(|i| i.lower.id.max(i.upper.id)).max().unwrap_or(0);
        for mut iv in more.intervals {
            iv.lower.id += offset;
            iv.upper.id += offset;
            self.space.intervals.push(iv);
        }
        self.space.notes.extend(more.notes);
        self.union = union(&self.space.intervals, scale);
        self.components = components(&self.space);
        locate(&self.space, r, scale)
    }
}

/// The f64 and reference runs compared endpoint by endpoint (same order);
/// with the same structure, the f64 endpoints are replaced by the
/// reference's, rounded.
fn compare_runs<R: Real>(
    reference: &[OrientedInterval<R>],
    space: &mut [OrientedInterval<f64>],
    scale: f64,
) -> Accuracy {
    // The same types, each end with the same flat steps.
    let same_structure = reference.len() == space.len()
        && reference
            .iter()
            .zip(space.iter())
            .all(|(r, f)| r.ty == f.ty && r.lower.events == f.lower.events && r.upper.events == f.upper.events);
    let (mut worst, mut of_value): (f64, f64) = (0.0, 0.0);
    if same_structure {
        for (r, f) in reference.iter().zip(space.iter_mut()) {
            // An isolated point (a tangency at double-double resolution) stays a point.
            let point = f.lower.lambda == f.upper.lambda;
            let half = R::from_f64(0.5);
            let (lo, hi) = if point {
                let mid = (r.lower.lambda + r.upper.lambda) * half;
                (mid, mid)
            } else {
                (r.lower.lambda, r.upper.lambda)
            };
            for (x, y) in [(lo, &mut f.lower.lambda), (hi, &mut f.upper.lambda)] {
                let error = (x - R::from_f64(*y)).to_f64().abs();
                worst = worst.max(error);
                if x.to_f64() != 0.0 {
                    of_value = of_value.max(error / x.to_f64().abs());
                }
                *y = x.to_f64();
            }
        }
    }
    Accuracy {
        max_endpoint_error: worst,
        max_relative_error: worst / scale,
        max_error_of_value: of_value,
        same_structure,
        refined: same_structure,
    }
}

/// The lazy walk's f64 endpoints refined in double-double from the input as
/// written, compared with `space` (and, when every end refines, replaced by
/// the refined values rounded to f64).
///
/// Each end λ is a root of its first flat step k's slack g_k (THEORY.md §2):
/// from the f64 value, Newton steps on g_k in double-double jets (realizing
/// only steps 0..k) double the correct digits each, so one or two reach
/// double-double resolution — the cost of a few realizations per end instead
/// of a second walk. An isolated point (a tangency) is refined as the root
/// of g_k′ instead. The structure is confirmed when every end converges
/// within [`crate::tolerance::DD_NEWTON_MAX_STEP`] × scale of its f64 value
/// and every interval keeps lower ≤ upper; an f64 end off its root by more
/// (a missed or misplaced event) makes `same_structure` false. Ends with no
/// flat step (a degenerate step's end) are not refined; `refined` says
/// whether all were.
pub fn lazy_reference_accuracy(
    linkage: &Linkage,
    dec: &Decomposition,
    space: &mut CayleySpace<f64>,
) -> Option<Accuracy> {
    let jet: Construction<Jet<Dd>> = Construction::new(linkage, dec).ok()?;
    let scale = linkage.scale;
    // One refinement per endpoint id: two types meeting at a root share it.
    let mut ends: Vec<(usize, &[bool], Event, f64, bool)> = Vec::new();
    let mut seen = std::collections::HashSet::new();
    for iv in &space.intervals {
        let point = iv.lower.lambda == iv.upper.lambda;
        for end in [&iv.lower, &iv.upper] {
            if let Some(&event) = end.events.first()
                && seen.insert(end.id)
            {
                ends.push((end.id, &iv.ty.0, event, end.lambda, point));
            }
        }
    }
    let refine = |ends: &[(usize, &[bool], Event, f64, bool)]| -> Vec<(usize, Option<Dd>)> {
        ends.iter()
            .map(|&(id, bits, event, lambda, point)| (id, refine_end(&jet, bits, event, lambda, point, scale)))
            .collect()
    };
    // Each refinement stands alone: a long chain's are split over two threads.
    let by_id: std::collections::HashMap<usize, Option<Dd>> =
        if dec.steps.len() >= crate::tolerance::TWO_THREADS_FROM_STEPS && ends.len() > 1 {
            let (first, second) = ends.split_at(ends.len() / 2);
            std::thread::scope(|scope| {
                let other = scope.spawn(|| refine(second));
                let mut done = refine(first);
                done.extend(other.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic)));
                done
            })
        } else {
            refine(&ends)
        }
        .into_iter()
        .collect();
    let (mut worst, mut of_value): (f64, f64) = (0.0, 0.0);
    let (mut same_structure, mut all_refined) = (true, true);
    let mut refined: Vec<[Option<Dd>; 2]> = Vec::with_capacity(space.intervals.len());
    for iv in &space.intervals {
        let mut ends = [None, None];
        for (slot, end) in ends.iter_mut().zip([&iv.lower, &iv.upper]) {
            let Some(&x) = by_id.get(&end.id).filter(|_| !end.events.is_empty()) else {
                all_refined = false;
                continue;
            };
            same_structure &= x.is_some();
            *slot = x;
            if let Some(x) = x {
                let error = (x - Dd::new(end.lambda)).to_f64().abs();
                worst = worst.max(error);
                if x.to_f64() != 0.0 {
                    of_value = of_value.max(error / x.to_f64().abs());
                }
            }
        }
        if let [Some(lo), Some(hi)] = ends {
            same_structure &= lo <= hi;
        }
        refined.push(ends);
    }
    // The f64 run's endpoints are replaced only when every one was confirmed.
    if same_structure {
        for (iv, ends) in space.intervals.iter_mut().zip(&refined) {
            for (x, y) in ends.iter().zip([&mut iv.lower.lambda, &mut iv.upper.lambda]) {
                if let Some(x) = x {
                    *y = x.to_f64();
                }
            }
        }
    }
    Some(Accuracy {
        max_endpoint_error: worst,
        max_relative_error: worst / scale,
        max_error_of_value: of_value,
        same_structure,
        refined: same_structure && all_refined,
    })
}

/// An end of type `bits` at `lambda` (f64), where `event` is flat, located in
/// double-double: Newton on the flat step's slack (on its slope for an
/// isolated point, a double root) from `lambda`, until a step is below
/// double-double's rounding. `None` when it does not converge within
/// [`crate::tolerance::DD_NEWTON_STEPS`] steps or strays beyond
/// [`crate::tolerance::DD_NEWTON_MAX_STEP`] × `scale` from `lambda`: then
/// `lambda` is no f64 rounding of that root.
fn refine_end(
    jet: &Construction<Jet<Dd>>,
    bits: &[bool],
    event: crate::realize::Event,
    lambda: f64,
    point: bool,
    scale: f64,
) -> Option<Dd> {
    use crate::tolerance::{DD_NEWTON_MAX_STEP, DD_NEWTON_STEPS, DD_REFINED, NEWTON_CONVERGED_ULPS};
    let s = &jet.steps[event.step];
    let start = Dd::new(lambda);
    let mut x = start;
    let mut last: Option<f64> = None;
    let mut pos = Vec::new();
    for _ in 0..DD_NEWTON_STEPS {
        let d = jet.prefix_distance_into(&mut pos, Jet::variable(x), bits, event.step).ok()?;
        let g = event.kind.slack_value(s.r1, s.r2, d);
        let (value, slope) = if point { (g.d, g.s) } else { (g.v, g.d) };
        if value == Dd::zero() {
            return Some(x);
        }
        let step = value / slope;
        if !step.to_f64().is_finite() {
            return None;
        }
        x = x - step;
        if (x - start).to_f64().abs() > DD_NEWTON_MAX_STEP * scale {
            return None;
        }
        let size = step.to_f64().abs();
        // Converged: to double-double resolution, or (deep chains amplify
        // double-double rounding) far below f64's, where the rest of the
        // error cannot change x's rounding to f64 or its distance from it;
        // or a step past f64's resolution that stops shrinking (noise).
        let magnitude = x.to_f64().abs();
        if size <= NEWTON_CONVERGED_ULPS * Dd::UNIT_ROUNDOFF * magnitude
            || size <= DD_REFINED * f64::UNIT_ROUNDOFF * magnitude
            || last.is_some_and(|l| size >= l && l <= f64::UNIT_ROUNDOFF * magnitude)
        {
            return Some(x);
        }
        last = Some(size);
    }
    None
}

/// Compute the Cayley space in double-double and compare it with `space`.
pub fn reference_accuracy(
    linkage: &Linkage,
    dec: &Decomposition,
    cx: &Complexity,
    cert: &Certifier,
    space: &mut CayleySpace<f64>,
) -> Option<Accuracy> {
    let reference = reference_space(linkage, dec, cx, cert, space.method)?;
    Some(compare_runs(&reference.intervals, &mut space.intervals, linkage.scale))
}

/// The Cayley space in double-double from the input as written: the
/// reference every accuracy figure is measured against. `None` where a
/// cluster's lengths do not close in double-double.
pub fn reference_space(
    linkage: &Linkage,
    dec: &Decomposition,
    cx: &Complexity,
    cert: &Certifier,
    method: Method,
) -> Option<CayleySpace<Dd>> {
    let con: Construction<Dd> = Construction::new(linkage, dec).ok()?;
    Some(cayley_space(&con, cert, dec, cx, method))
}

/// A realizable λ of `ty` near `lambda`, for a lazy analysis that has no
/// intervals yet: 4096 samples over the base's range, then bisection from
/// the nearest realizable one toward `lambda` (to the end of that interval).
/// A sampled search: an interval narrower than the spacing can be missed,
/// and then `None`.
fn nearest_realizable(con: &Construction<f64>, ty: &crate::realize::RealizationType, lambda: f64) -> Option<f64> {
    let (mut lo, mut hi) = (0.0f64, f64::INFINITY);
    for k in (0..con.steps.len()).filter(|&k| con.on_base(k)) {
        let s = &con.steps[k];
        lo = lo.max((s.r1 - s.r2).abs());
        hi = hi.min(s.r1 + s.r2);
    }
    if hi.partial_cmp(&lo) == Some(std::cmp::Ordering::Less) || hi.is_nan() {
        return None;
    }
    let ok = |x: f64| con.realize(x, ty).is_ok();
    const SAMPLES: usize = 4096;
    let found = (0..=SAMPLES)
        .map(|i| lo + (hi - lo) * i as f64 / SAMPLES as f64)
        .filter(|&x| ok(x))
        .min_by(|a, b| (a - lambda).abs().total_cmp(&(b - lambda).abs()))?;
    let (mut inside, mut outside) = (found, lambda);
    for _ in 0..80 {
        let mid = 0.5 * (inside + outside);
        if mid == inside || mid == outside {
            break;
        }
        if ok(mid) { inside = mid } else { outside = mid }
    }
    Some(inside)
}

/// Whether every step on the base has equal sides (decided exactly), so
/// that each can fold to d = 0: at λ = 0 the base joints may meet, and the
/// vertices there turn freely, a motion no λ follows.
fn base_joints_may_meet(con: &Construction<f64>, cert: &Certifier) -> bool {
    (0..con.steps.len()).filter(|&k| con.on_base(k)).all(|k| cert.kinds(k).len() == 1)
}

/// Other valid bases tried for one whose joints never meet.
const MAX_BASES_TRIED: usize = 8;

/// The λ of `ty` nearest to `lambda` (itself if realizable), from the type's intervals.
pub fn nearest_attainable(space: &CayleySpace<f64>, ty: &crate::realize::RealizationType, lambda: f64) -> Option<f64> {
    space
        .intervals
        .iter()
        .filter(|i| &i.ty == ty)
        .map(|i| lambda.clamp(i.lower.lambda, i.upper.lambda))
        .min_by(|a, b| (a - lambda).abs().total_cmp(&(b - lambda).abs()))
}

/// Something the analysis found that a reader should know, as data (the
/// presentation layer says it in words). Serialized as `{"kind": …, data}`,
/// steps, bars and bodies numbered from 1.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, schemars::JsonSchema))]
#[cfg_attr(feature = "serde", serde(tag = "kind", rename_all = "snake_case"))]
pub enum Warning {
    /// A bar joins two joints of a body that already holds them at that
    /// length: recognition ignores it (`line`: its line in the scene file).
    BarInBody {
        /// The bar (0-based; serialized from 1).
        #[cfg_attr(feature = "serde", serde(serialize_with = "crate::numbering::item_number"))]
        #[cfg_attr(feature = "serde", schemars(with = "crate::numbering::ItemNo"))]
        bar: usize,
        /// The body holding both its joints (0-based; serialized from 1).
        #[cfg_attr(feature = "serde", serde(serialize_with = "crate::numbering::item_number"))]
        #[cfg_attr(feature = "serde", schemars(with = "crate::numbering::ItemNo"))]
        body: usize,
        /// The bar's line in the scene file, if known.
        line: Option<usize>,
    },
    /// Step `step` is flat in the drawing; its orientation is taken as +.
    FlatInDrawing {
        /// The flat step (0-based; serialized from 1).
        #[cfg_attr(feature = "serde", serde(serialize_with = "crate::numbering::step_number"))]
        #[cfg_attr(feature = "serde", schemars(with = "crate::numbering::StepNo"))]
        step: usize,
    },
    /// The f64 and double-double runs found different intervals.
    RunsDiffer,
    /// The lazy walk's ends were not confirmed in double-double; the full
    /// sweep's component through the drawn realization is given instead.
    WalkUnconfirmed,
    /// A sketch's base length is not attainable in its type: it is realized
    /// at the nearest attainable λ instead.
    SketchRelocated {
        /// The sketch's realization type.
        #[cfg_attr(feature = "serde", serde(rename = "type"))]
        ty: RealizationType,
        /// The base length as drawn.
        drawn_lambda: f64,
        /// The nearest attainable base length, where it is realized.
        lambda: f64,
    },
    /// The drawn (λ, type) has no realization.
    DrawnUnrealizable {
        /// The drawn type.
        #[cfg_attr(feature = "serde", serde(rename = "type"))]
        ty: RealizationType,
        /// The drawn base length.
        lambda: f64,
        /// Which step fails, and how.
        why: Unrealizable,
    },
    /// The drawn realization misses a bar length by `residual` (scene units).
    BarResidual {
        /// The largest bar-length miss, scene units.
        residual: f64,
    },
    /// `count` decisions rest on a double-double error estimate, not a
    /// proof (neither balls nor the exact stage decided them).
    EstimatedDecisions {
        /// How many decisions.
        count: usize,
    },
    /// Every cluster a step stands on is flat to double-double resolution,
    /// some not provably (three or more joints on a line as written): mirror
    /// pairs are taken to exist, a non-generic place ([`Mirrors::AtResolution`]).
    MirrorsAtResolution,
    /// A branch point (`ways` > 0 ways on) or a dead end (`ways` == 0) at λ;
    /// with `through` > 0 a singular place the motion passes, where the
    /// listing ends a component ([`crate::motion::BranchPoint::through`]).
    BranchPoint {
        /// Where (base length).
        lambda: f64,
        /// The steps flat there.
        events: Vec<Event>,
        /// How many ways on (0: a dead end).
        ways: usize,
        /// How many types go on through a touch on the other side of λ.
        through: usize,
    },
    /// The two ground joints are in no rigid part together (no bar, body or
    /// rigid cluster holds both): their distance changes in the motion, so
    /// the display holds the first in place and the second on its drawn
    /// direction from the first, not both.
    GroundMoves {
        /// The two ground joints, by name.
        joints: [String; 2],
    },
    /// A special event met while computing the Cayley space.
    #[cfg_attr(feature = "serde", serde(untagged))]
    Note(Note),
}

/// Why a solved scene has no component at all, as data.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, schemars::JsonSchema))]
#[cfg_attr(feature = "serde", serde(tag = "kind", rename_all = "snake_case"))]
pub enum NoRealization {
    /// Each step on the base allows the base length only in [|r1 − r2|, r1 + r2]:
    /// step `lower_step` needs at least `lower`, step `upper_step` at most `upper` < `lower`.
    BaseRangesMiss {
        /// The largest lower bound |r1 − r2| over the steps on the base.
        lower: f64,
        /// The step giving it (0-based; serialized from 1).
        #[cfg_attr(feature = "serde", serde(serialize_with = "crate::numbering::step_number"))]
        #[cfg_attr(feature = "serde", schemars(with = "crate::numbering::StepNo"))]
        lower_step: usize,
        /// The smallest upper bound r1 + r2 over the steps on the base.
        upper: f64,
        /// The step giving it (0-based; serialized from 1).
        #[cfg_attr(feature = "serde", serde(serialize_with = "crate::numbering::step_number"))]
        #[cfg_attr(feature = "serde", schemars(with = "crate::numbering::StepNo"))]
        upper_step: usize,
    },
    /// Nothing was found, yet the drawn realization closes every step
    /// (`drawn_closes`) or every step stands on the base with overlapping
    /// ranges: the analysis failed numerically.
    NumericFailure {
        /// Whether the drawn realization closes every step.
        drawn_closes: bool,
        /// The drawn type.
        #[cfg_attr(feature = "serde", serde(rename = "type"))]
        ty: RealizationType,
        /// The drawn base length.
        lambda: f64,
        /// The scene's scale.
        scale: f64,
    },
    /// A lazy analysis starts from the drawn realization, and its type has
    /// none at the drawn λ.
    LazyDrawnType {
        /// The drawn type.
        #[cfg_attr(feature = "serde", serde(rename = "type"))]
        ty: RealizationType,
        /// The drawn base length.
        lambda: f64,
    },
    /// No orientation type closes every step (for any base length in
    /// `range`, the range the steps on the base allow).
    NoTypeCloses {
        /// The base lengths the steps on the base allow, if any step is on the base.
        range: Option<[f64; 2]>,
        /// Decisions that rested on a double-double error estimate, not a
        /// proof (0: the answer is proven; otherwise it is not).
        estimated: usize,
    },
}

/// Why `s` has no component (`None` when it has one).
pub fn no_realization(s: &Solved, scale: f64) -> Option<NoRealization> {
    if !s.components.list.is_empty() {
        return None;
    }
    let con = &s.construction;
    let on_base: Vec<(usize, f64, f64)> = (0..con.steps.len())
        .filter(|&k| con.on_base(k))
        .map(|k| (k, (con.steps[k].r1 - con.steps[k].r2).abs(), con.steps[k].r1 + con.steps[k].r2))
        .collect();
    let lowest_upper = on_base.iter().min_by(|x, y| x.2.total_cmp(&y.2));
    let highest_lower = on_base.iter().max_by(|x, y| x.1.total_cmp(&y.1));
    if let (Some(&(kl, lo, _)), Some(&(ku, _, hi))) = (highest_lower, lowest_upper)
        && lo > hi
    {
        return Some(NoRealization::BaseRangesMiss { lower: lo, lower_step: kl, upper: hi, upper_step: ku });
    }
    // A realization the sweep should have found: the drawn one, or (every
    // step on the base, their ranges overlapping) any type inside the overlap.
    let drawn_closes = con.realize(s.drawn.lambda, &s.drawn.ty).is_ok();
    let all_on_base = on_base.len() == con.steps.len();
    if drawn_closes || (all_on_base && !on_base.is_empty()) {
        return Some(NoRealization::NumericFailure {
            drawn_closes,
            ty: s.drawn.ty.clone(),
            lambda: s.drawn.lambda,
            scale,
        });
    }
    if s.lazy {
        return Some(NoRealization::LazyDrawnType { ty: s.drawn.ty.clone(), lambda: s.drawn.lambda });
    }
    let range = match (highest_lower, lowest_upper) {
        (Some(&(_, lo, _)), Some(&(_, _, hi))) => Some([lo, hi]),
        _ => None,
    };
    Some(NoRealization::NoTypeCloses { range, estimated: s.certifier.estimated() })
}

/// A scene analysed: its linkage and either the solved analysis or why it is outside the class.
#[derive(Debug, Clone)]
pub struct Analysis {
    /// The scene as parsed.
    pub scene: Scene,
    /// The linkage the scene states.
    pub linkage: Arc<Linkage>,
    /// The analysis, or why the linkage is outside the handled class.
    pub outcome: Result<Solved, Outside>,
    /// Things the user should know about the input, as data.
    pub warnings: Vec<Warning>,
    /// Time spent per phase.
    pub timings: Timings,
}

/// Where a requested base came from, for the error message.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BaseSource {
    /// Named in the scene file (`base = [...]`).
    Scene,
    /// Given on the command line (`--base`).
    CommandLine,
}

/// Analyse a scene. Errors are for input that cannot be analysed at all
/// (an invalid base, contradictory stated lengths); a valid scene outside the
/// handled class is an `Ok` whose `outcome` says why.
pub fn analyse(scene: Scene, base_override: Option<[usize; 2]>) -> Result<Analysis, SceneError> {
    analyse_with(scene, base_override, Scope::Auto)
}

/// Why the full analysis of a scene with `steps` steps is refused: `what`
/// would cost about `cost` (a bounded cost for every command).
fn full_refused(steps: usize, what: &str, cost: f64) -> String {
    format!(
        "the full analysis (every one of 2^{steps} types, --all) is beyond its budget: {what} is estimated at {cost:.1e} (budgets: tolerance::FULL_SEARCH_MAX, FULL_COST_MAX); without --all the lazy analysis walks the drawn component"
    )
}

/// The sweep `scope` calls for (`None`: the lazy walk), and the full
/// sweep's estimated cost where it was estimated; `Err` with the reason
/// where the full analysis is beyond its budget. `Auto` sweeps within
/// [`LAZY_ABOVE_STEPS`] and [`crate::tolerance::SWEEP_COST_MAX`]; `Lazy`
/// sweeps only a small sketch whose drawn λ its type cannot reach (the
/// walk has no start there).
fn plan_for(
    scope: Scope,
    (con, cert, dec, cx): (&Construction<f64>, Option<&Certifier>, &Decomposition, &Complexity),
    unreachable_sketch: bool,
) -> Result<(Option<SweepPlan<f64>>, Option<f64>), String> {
    let small = dec.steps.len() <= LAZY_ABOVE_STEPS;
    if scope == Scope::Full {
        let bound = candidate_search_bound(con, cx);
        if bound > crate::tolerance::FULL_SEARCH_MAX {
            return Err(full_refused(dec.steps.len(), "its closed-form candidates' search", bound));
        }
    }
    let wanted = match scope {
        Scope::Auto => small,
        Scope::Full => true,
        Scope::Lazy => unreachable_sketch && small,
    };
    let Some(plan) = wanted.then(|| SweepPlan::new(con, cert, dec, cx, Method::Exact)) else { return Ok((None, None)) };
    let cost = plan.cost();
    if scope == Scope::Full && cost > crate::tolerance::FULL_COST_MAX {
        return Err(full_refused(dec.steps.len(), "its sweep", cost));
    }
    let sweep = scope == Scope::Full || cost <= crate::tolerance::SWEEP_COST_MAX;
    Ok((sweep.then_some(plan), Some(cost)))
}

/// What `Scope::Auto` comes to for `scene` (on `base_override`, else its
/// own base or the chosen one): `Full` or `Lazy`, from the recognition and
/// the sweep's estimate alone (`plan_for`). `Auto` where the scene cannot
/// be recognised (the analysis says why). For callers that give many
/// variants of one scene the same analysis, so that their results compare
/// (a sweep's samples: their candidates, so their estimates, vary with the
/// lengths).
pub fn auto_scope(scene: &Scene, base_override: Option<[usize; 2]>) -> Scope {
    let linkage = Linkage::from_scene(scene);
    let Ok(Ok(dec)) = decompose(&linkage, base_override.or(scene.base.map(|b| b.0))) else { return Scope::Auto };
    let Ok(con) = Construction::<f64>::new(&linkage, &dec) else { return Scope::Auto };
    match plan_for(Scope::Auto, (&con, None, &dec, &four_cycle_test(&dec)), false) {
        Ok((Some(_), _)) => Scope::Full,
        _ => Scope::Lazy,
    }
}

/// Whether an analysis checks itself against the double-double reference.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SelfCheck {
    /// Check, and show the reference's ends where the structures agree (every report).
    Run,
    /// Skip it: for callers that read only the structure (a sweep's
    /// samples). The check moves ends within the f64 error, so it changes a
    /// structure only at a non-generic place; it costs two fifths of a
    /// 1000-step chain's walk, and many times a small scene's analysis (a
    /// second analysis in double-double).
    Skip,
}

/// [`analyse`] with the extent of the realization space chosen explicitly.
pub fn analyse_with(scene: Scene, base_override: Option<[usize; 2]>, scope: Scope) -> Result<Analysis, SceneError> {
    analyse_checked(scene, base_override, scope, SelfCheck::Run)
}

/// [`analyse_with`], with or without the double-double self-check.
pub fn analyse_checked(
    scene: Scene,
    base_override: Option<[usize; 2]>,
    scope: Scope,
    check: SelfCheck,
) -> Result<Analysis, SceneError> {
    let mut timings = Timings::default();
    let linkage = Arc::new(timings.time("linkage", || Linkage::from_scene(&scene)));
    let (requested, source) = match (base_override, scene.base) {
        (Some(b), _) => (Some(b), BaseSource::CommandLine),
        (None, Some((b, _))) => (Some(b), BaseSource::Scene),
        (None, None) => (None, BaseSource::Scene),
    };
    let mut warnings: Vec<Warning> = crate::decompose::bars_within_bodies(&linkage)
        .into_iter()
        .filter(|b| b.agrees)
        .map(|b| Warning::BarInBody {
            bar: b.bar,
            body: b.body,
            line: scene.bars.get(b.bar).map(|bar| bar.line).filter(|&l| l > 0),
        })
        .collect();
    let dec = match timings.time("decompose", || decompose(&linkage, requested)) {
        Err(outside) => return Ok(Analysis { scene, linkage, outcome: Err(outside), warnings, timings }),
        Ok(Err(base_error)) => {
            let line = if source == BaseSource::Scene { scene.base.map(|b| b.1) } else { None };
            let mut err = scene.error_at(line, base_error.message);
            if source == BaseSource::CommandLine {
                err.message = format!("--base: {}", err.message);
            }
            return Err(err);
        }
        Ok(Ok(dec)) => Arc::new(dec),
    };
    if let [a, b] = linkage.ground[..]
        && !dec.clusters.clustered(a, b)
    {
        warnings.push(Warning::GroundMoves { joints: [a, b].map(|j| linkage.names[j].clone()) });
    }
    let built = |dec: Arc<Decomposition>, timings: &mut Timings| {
        let construction = timings
            .time("construction", || Construction::<f64>::new(&linkage, &dec))
            .map(Arc::new)
            .map_err(|e| scene.error_at(None, e.0))?;
        let certifier = Certifier::shared(linkage.clone(), dec.clone(), construction.clone())
            .expect("the f64 construction succeeded, so the ball ones do");
        Ok::<_, SceneError>((dec, construction, certifier))
    };
    let (mut dec, mut construction, mut certifier) = built(dec, &mut timings)?;
    if dec.base_chosen && base_joints_may_meet(&construction, &certifier) {
        // Another valid base, if one keeps its joints apart, sees the whole motion.
        for f in dec.other_bases(&linkage).into_iter().take(MAX_BASES_TRIED) {
            let Ok(Ok(other)) = decompose(&linkage, Some(f)) else { continue };
            let other = Decomposition { base_chosen: true, ..other };
            let (d, con, cert) = built(Arc::new(other), &mut timings)?;
            if !base_joints_may_meet(&con, &cert) {
                (dec, construction, certifier) = (d, con, cert);
                break;
            }
        }
    }
    let complexity = timings.time("four_cycle", || four_cycle_test(&dec));
    let drawn = drawn_realization(&linkage, &dec);
    warnings.extend(drawn.flat_steps.iter().map(|&step| Warning::FlatInDrawing { step }));
    // A sketch whose drawn λ its type cannot reach has no start for the walk:
    // small ones get the full analysis where it is affordable (it relocates
    // the drawing from its intervals), others a sampled search for a start.
    let unreachable_sketch = scene.is_sketch() && construction.realize(drawn.lambda, &drawn.ty).is_err();
    let (plan, sweep_estimate) =
        plan_for(scope, (&construction, Some(&certifier), &dec, &complexity), unreachable_sketch)
            .map_err(|why| scene.error_at(None, why))?;
    let lazy = plan.is_none();
    let before_walk = certifier.stage_counts();
    let mut space = if lazy {
        timings.time("lazy_component", || {
            let jet = construction.convert::<Jet<f64>>();
            // A sketch whose drawn λ its type cannot reach starts from the
            // nearest λ it can (the full analysis does the same from its intervals).
            let start = if unreachable_sketch {
                nearest_realizable(&construction, &drawn.ty, drawn.lambda).unwrap_or(drawn.lambda)
            } else {
                drawn.lambda
            };
            component_through(&construction, &certifier, &jet, &drawn.ty, start, LazyOptions::default()).unwrap_or_else(
                |_| CayleySpace {
                    intervals: Vec::new(),
                    touches: Vec::new(),
                    notes: Vec::new(),
                    method: Method::Numeric { samples: LazyOptions::default().samples, tol: 0.0 },
                    numeric_steps: Vec::new(),
                },
            )
        })
    } else {
        timings.time("cayley_space", || {
            let plan = plan.expect("a full analysis has its plan");
            cayley_space_planned(&construction, &certifier, plan)
        })
    };
    let mut accuracy = if check == SelfCheck::Skip {
        None
    } else if lazy {
        (dec.steps.len() <= LAZY_REFERENCE_MAX_STEPS && !space.intervals.is_empty())
            .then(|| timings.time("reference", || lazy_reference_accuracy(&linkage, &dec, &mut space)))
            .flatten()
    } else if space.intervals.len() <= REFERENCE_MAX_TYPES {
        timings.time("reference", || reference_accuracy(&linkage, &dec, &complexity, &certifier, &mut space))
    } else {
        None
    };
    // A walk whose ends double-double did not confirm escalates to the
    // sweep, which decides close events from closed-form candidates.
    if lazy
        && accuracy.as_ref().is_some_and(|a| !a.same_structure)
        && let Some((swept, swept_accuracy)) = timings.time("swept_component", || {
            swept_component(&linkage, (&dec, &complexity), (&construction, &certifier), &drawn, before_walk)
        })
    {
        warnings.push(Warning::WalkUnconfirmed);
        (space, accuracy) = (swept, swept_accuracy);
    }
    let union = union(&space.intervals, linkage.scale);
    if accuracy.as_ref().is_some_and(|a| !a.same_structure) {
        warnings.push(Warning::RunsDiffer);
    }
    let mut drawn = drawn;
    let realized = timings.time("realize", || construction.realize(drawn.lambda, &drawn.ty));
    let drawn_positions = match realized {
        Ok(pos) => Some(to_display(&linkage, dec.base, &pos)),
        Err(why) => {
            let attainable = nearest_attainable(&space, &drawn.ty, drawn.lambda);
            let retry = attainable.and_then(|l| construction.realize(l, &drawn.ty).ok().map(|p| (l, p)));
            match retry {
                Some((l, pos)) if scene.is_sketch() => {
                    warnings.push(Warning::SketchRelocated {
                        ty: drawn.ty.clone(),
                        drawn_lambda: drawn.lambda,
                        lambda: l,
                    });
                    drawn.lambda = l;
                    Some(to_display(&linkage, dec.base, &pos))
                }
                _ => {
                    warnings.push(Warning::DrawnUnrealizable { ty: drawn.ty.clone(), lambda: drawn.lambda, why });
                    None
                }
            }
        }
    };
    let sketch = if scene.is_sketch() {
        let max_length_change = linkage.bars.iter().map(|b| b.sketch_error.abs()).fold(0.0, f64::max);
        let max_joint_move = drawn_positions.as_ref().map_or(f64::NAN, |pos| {
            pos.iter().zip(&linkage.drawn).map(|(p, d)| (p[0] - d[0]).hypot(p[1] - d[1])).fold(0.0, f64::max)
        });
        Some(SketchFit { max_length_change, max_joint_move })
    } else {
        if let Some(pos) = &drawn_positions {
            let r = bar_residual(&linkage, pos);
            if r > crate::tolerance::BAR_RESIDUAL * linkage.scale {
                warnings.push(Warning::BarResidual { residual: r });
            }
        }
        None
    };
    for note in &space.notes {
        push_new(&mut warnings, Warning::Note(note.clone()));
    }
    if certifier.estimated() > 0 {
        warnings.push(Warning::EstimatedDecisions { count: certifier.estimated() });
    }
    let components = timings.time("components", || components(&space));
    for b in &components.branch_points {
        push_new(
            &mut warnings,
            Warning::BranchPoint {
                lambda: b.lambda,
                events: b.events.clone(),
                ways: b.options.len(),
                through: b.through.len(),
            },
        );
    }
    let drawn_interval = drawn_positions
        .as_ref()
        .and_then(|_| locate(&space, &Realization { ty: drawn.ty.clone(), lambda: drawn.lambda }, linkage.scale));
    let drawn_component = drawn_interval.map(|i| components.of_interval[i]);
    let mirrors = mirror_images(&certifier, &dec, linkage.scale);
    if mirrors == Mirrors::AtResolution {
        warnings.push(Warning::MirrorsAtResolution);
    }
    let solved = Solved {
        dec,
        complexity,
        construction,
        certifier,
        mirrors,
        drawn,
        drawn_positions,
        sketch,
        space,
        union,
        accuracy,
        components,
        drawn_interval,
        drawn_component,
        lazy,
        sweep_estimate,
    };
    Ok(Analysis { scene, linkage, outcome: Ok(solved), warnings, timings })
}

/// The full sweep's component through the drawn realization, with its
/// accuracy, where the sweep is within the automatic budget
/// ([`crate::tolerance::SWEEP_COST_MAX`]): what answers a lazy walk whose
/// ends double-double did not confirm. Its intervals are sorted as the
/// walk sorts them, with the notes and touches met where they are. The
/// certifier's counts go back to `counts` (before the walk) first, and
/// to the walk's where the sweep does not answer. The accuracy is the
/// sweep's over every type (a `runs_differ` may come from another
/// component).
fn swept_component(
    linkage: &Linkage,
    (dec, cx): (&Decomposition, &Complexity),
    (con, cert): (&Construction<f64>, &Certifier),
    drawn: &Drawn,
    counts: StageCounts,
) -> Option<(CayleySpace<f64>, Option<Accuracy>)> {
    let walked = cert.stage_counts();
    cert.rewind_counts(counts);
    let plan = SweepPlan::new(con, Some(cert), dec, cx, Method::Exact);
    if plan.cost() > crate::tolerance::SWEEP_COST_MAX {
        cert.rewind_counts(walked);
        return None;
    }
    let mut full = cayley_space_planned(con, cert, plan);
    let accuracy = if full.intervals.len() <= REFERENCE_MAX_TYPES {
        reference_accuracy(linkage, dec, cx, cert, &mut full)
    } else {
        None
    };
    let all = components(&full);
    let Some(at) = locate(&full, &Realization { ty: drawn.ty.clone(), lambda: drawn.lambda }, linkage.scale) else {
        cert.rewind_counts(walked);
        return None;
    };
    let ours = all.of_interval[at];
    let mut intervals: Vec<_> =
        full.intervals.iter().zip(&all.of_interval).filter(|&(_, &c)| c == ours).map(|(iv, _)| iv.clone()).collect();
    intervals.sort_by(|a, b| a.ty.cmp(&b.ty).then(a.lower.lambda.total_cmp(&b.lower.lambda)));
    // What was met on the way, only where the component is.
    let meets = |lo: f64, hi: f64| intervals.iter().any(|iv| lo <= iv.upper.lambda && hi >= iv.lower.lambda);
    let notes = full
        .notes
        .iter()
        .filter(|n| match n {
            Note::Coincident { lambda, .. } | Note::Tangency { lambda, .. } | Note::Unresolved { lambda, .. } => {
                meets(*lambda, *lambda)
            }
            Note::ZeroBase { .. } => meets(0.0, 0.0),
            Note::Degenerate { lambda: [a, b], .. } => meets(*a, *b),
        })
        .cloned()
        .collect();
    let touches = full
        .touches
        .iter()
        .filter(|t| {
            intervals
                .iter()
                .any(|iv| iv.ty.0.starts_with(&t.prefix) && iv.lower.lambda <= t.lambda && t.lambda <= iv.upper.lambda)
        })
        .cloned()
        .collect();
    Some((CayleySpace { intervals, notes, touches, ..full }, accuracy))
}

/// Add `w` unless it is already there (one warning per distinct event).
fn push_new(warnings: &mut Vec<Warning>, w: Warning) {
    if !warnings.contains(&w) {
        warnings.push(w);
    }
}
