//! Sweeps: how the analysis changes as one number of the scene varies (a
//! bar's length, or one coordinate of a drawn joint), and the exact values
//! where its structure changes.
//!
//! Each sample is a full [`analyse`](crate::analysis::analyse_checked) of the
//! edited scene, without the double-double self-check (it refines the ends'
//! λ within the f64 error, which changes a structure only at a non-generic
//! place), summarised as a [`Structure`]: the class, every oriented
//! interval as (type, flat steps at each end), the number of non-oriented
//! pieces, the component sizes, the branch points and (with an input bar)
//! which components turn it fully. Every part of it is decided by the
//! analysis itself (certified signs, [`crate::certify`]), so two values have
//! the same structure or not without any tolerance here. A **transition**
//! is where the structure changes between two neighbouring samples; it is
//! located by bisection on the parameter until its bracket is two adjacent
//! floats ([`locate`]). A structure found only between them (on one float,
//! such as a four-bar at s + l = p + q, where two steps are flat at once)
//! is kept with the transition rather than counted as two.
//!
//! Limits: a structure that appears and vanishes between two samples is not
//! seen (more samples find it); at most [`MAX_SPLITS`] intermediate
//! structures are followed in one sample gap.

use crate::analysis::{Scope, SelfCheck, Solved, analyse_checked, auto_scope, no_realization};
use crate::decompose::Outside;
use crate::linkage::Linkage;
use crate::motion::{Stepper, component_segments};
use crate::real::Dd;
use crate::realize::Event;
use crate::scene::Scene;

/// The most samples one sweep may ask for.
pub const MAX_STEPS: usize = 100_000;

/// Bisection steps per transition before giving up (from a sample gap to
/// adjacent floats takes at most ~64 for values of one sign).
pub const MAX_BISECTIONS: usize = 256;

/// Intermediate structures followed inside one sample gap.
pub const MAX_SPLITS: usize = 8;

/// Samples per component walk when deciding whether the input bar turns.
pub const TURN_WALK_BUDGET: usize = 20_000;

/// The number a sweep varies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Parameter {
    /// The stated length of bar `i` (scene order).
    BarLength(usize),
    /// Coordinate `axis` (0: x, 1: y) of joint `joint`'s drawn position.
    Joint {
        /// The joint (index).
        joint: usize,
        /// 0 for x, 1 for y.
        axis: usize,
    },
}

/// The scene with the parameter set to `value`. A bar's length becomes a
/// stated length (the drawing then only fixes the pose and the types, as for
/// any sketch; bars without a stated length keep their drawn length). A
/// joint coordinate moves the drawn joint: bars without a stated length and
/// bodies through it change with it.
pub fn apply(scene: &Scene, p: Parameter, value: f64) -> Scene {
    let mut s = scene.clone();
    match p {
        Parameter::BarLength(i) => {
            s.bars[i].length = Some(value);
            s.bars[i].exact_length = Some(Dd::new(value));
            s.bars[i].written_length = None;
        }
        Parameter::Joint { joint, axis } => {
            s.joints[joint].pos[axis] = value;
            s.joints[joint].exact[axis] = Dd::new(value);
            s.joints[joint].written[axis] = None;
        }
    }
    s
}

/// A bar driven as input: `pivot` is a ground joint, `tip` the other end,
/// and its angle is measured from the ground line pivot → `reference`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct InputBar {
    /// The ground joint the bar turns about.
    pub pivot: usize,
    /// Its other joint.
    pub tip: usize,
    /// Another ground joint: the ground line runs from the pivot to it.
    pub reference: usize,
}

/// Why a bar cannot drive as an input ([`InputBar::of_bar`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NotInput {
    /// Both its joints are ground joints: it is the ground link.
    GroundLink,
    /// Neither joint is a ground joint.
    NoGroundJoint,
    /// The scene has one ground joint: no ground line to measure from.
    NoGroundLine,
}

impl InputBar {
    /// Bar number `bar` (an index into `scene.bars`) as an input: its one
    /// ground joint is the pivot, and the angle is measured from the line to
    /// the first other ground joint.
    pub fn of_bar(scene: &Scene, bar: usize) -> Result<InputBar, NotInput> {
        let [p, q] = scene.bars[bar].joints;
        let ground = |j: usize| scene.ground.contains(&j);
        let (pivot, tip) = match (ground(p), ground(q)) {
            (true, false) => (p, q),
            (false, true) => (q, p),
            (true, true) => return Err(NotInput::GroundLink),
            (false, false) => return Err(NotInput::NoGroundJoint),
        };
        let reference = scene.ground.iter().copied().find(|&g| g != pivot).ok_or(NotInput::NoGroundLine)?;
        Ok(InputBar { pivot, tip, reference })
    }

    /// The bar's angle from the ground line in radians, in (−π, π],
    /// counter-clockwise with y up: the direction pivot → tip less the
    /// direction pivot → reference (two `atan2`, no product of lengths, so
    /// any scale). The same in every frame a realization is drawn in.
    pub fn angle(&self, pos: &[crate::realize::Point2<f64>]) -> f64 {
        let direction = |j: usize| (pos[j][1] - pos[self.pivot][1]).atan2(pos[j][0] - pos[self.pivot][0]);
        wrap_angle(direction(self.tip) - direction(self.reference))
    }
}

/// What a sweep holds fixed: the scene, the parameter, the base, the input bar.
#[derive(Clone, Debug)]
pub struct Setup {
    /// The scene as given (the parameter's own value in it is ignored).
    pub scene: Scene,
    /// What varies.
    pub parameter: Parameter,
    /// The base non-edge, if one was asked for (else the analysis chooses, per sample).
    pub base: Option<[usize; 2]>,
    /// The bar whose full turns are counted, if any.
    pub input: Option<InputBar>,
    /// The analysis every sample gets, `Full` or `Lazy` as `Scope::Auto`
    /// gives the scene as given ([`auto_scope`]): samples compare only
    /// when all are analysed alike, and `Auto`'s choice can vary with the
    /// lengths (through the sweep's estimate).
    pub scope: Scope,
}

impl Setup {
    /// The setup of a sweep of `parameter` over `scene`, its scope decided once.
    pub fn new(scene: Scene, parameter: Parameter, base: Option<[usize; 2]>, input: Option<InputBar>) -> Self {
        let scope = auto_scope(&scene, base);
        Setup { scene, parameter, base, input, scope }
    }
}

/// The class of a sample, as data.
#[derive(Clone, Debug, PartialEq)]
pub enum Class {
    /// 1-dof tree-decomposable, with at least one realization.
    Solved,
    /// In the class, but no realization at all.
    NoRealization,
    /// Outside the handled class.
    Outside(Outside),
    /// The edited scene cannot be analysed (e.g. a zero length); the reason as the analysis gave it.
    Invalid(String),
}

/// [`Class`] without its detail: what structures compare.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, schemars::JsonSchema))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum ClassKind {
    /// 1-dof tree-decomposable with a realization.
    Solved,
    /// In the class, no realization.
    NoRealization,
    /// Outside the handled class.
    Outside,
    /// Not analysable.
    Invalid,
}

impl Class {
    /// The kind, without detail.
    pub fn kind(&self) -> ClassKind {
        match self {
            Class::Solved => ClassKind::Solved,
            Class::NoRealization => ClassKind::NoRealization,
            Class::Outside(_) => ClassKind::Outside,
            Class::Invalid(_) => ClassKind::Invalid,
        }
    }
}

/// Whether the input bar turns fully along a component.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, schemars::JsonSchema))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Turn {
    /// Its angle winds round (a crank): once around the component it turns
    /// a nonzero number of times.
    Full,
    /// It rocks: once around the component its angle comes back without a turn.
    Rocks,
    /// Not decided: the component is open, or its walk jumped or ran out of budget.
    Unknown,
}

/// One oriented interval as the structure sees it: type and flat steps at its ends.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct IntervalShape {
    /// The type's bits.
    pub ty: Vec<bool>,
    /// Steps flat at the lower end.
    pub lower: Vec<Event>,
    /// Steps flat at the upper end.
    pub upper: Vec<Event>,
    /// Whether it is a single point.
    pub point: bool,
}

/// What a transition is a change of: equal structures are the same behaviour.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Structure {
    /// The class.
    pub class: ClassKind,
    /// Every oriented interval, sorted.
    pub intervals: Vec<IntervalShape>,
    /// Pieces of the non-oriented Cayley space.
    pub union_parts: usize,
    /// Oriented intervals per component, largest first.
    pub component_sizes: Vec<usize>,
    /// Endpoints with several ways on or none.
    pub branch_points: usize,
    /// The input bar's turn per component, sorted (empty without an input bar).
    pub turns: Vec<Turn>,
}

/// One component of a sample.
#[derive(Clone, Debug, PartialEq)]
pub struct ComponentSize {
    /// How many oriented intervals it has.
    pub intervals: usize,
    /// Total λ travelled once around it (sum of its intervals' widths).
    pub lambda_length: f64,
    /// The smallest and largest λ it reaches.
    pub lambda_range: [f64; 2],
    /// Whether the input bar turns fully along it (`None` without an input bar).
    pub turn: Option<Turn>,
}

/// The analysis at one value of the parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepSample {
    /// The parameter's value.
    pub value: f64,
    /// The class, with detail.
    pub class: Class,
    /// The non-oriented Cayley space. Its ends (and the components' λ
    /// below) are the f64 analysis's, not refined by the self-check: within
    /// that analysis's error of the double-double ends that `report` shows.
    pub union: Vec<[f64; 2]>,
    /// How many oriented intervals.
    pub oriented_intervals: usize,
    /// The components, in the analysis's order.
    pub components: Vec<ComponentSize>,
    /// Whether only the drawn component was computed (a scene above 2^16 types).
    pub lazy: bool,
    /// Decisions of the analysis that rest on a double-double estimate, not a proof.
    pub estimated: usize,
    /// The structure transitions compare.
    pub structure: Structure,
}

/// One change between two structures, as data.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, schemars::JsonSchema))]
#[cfg_attr(feature = "serde", serde(tag = "kind", rename_all = "snake_case"))]
pub enum Change {
    /// The class changes (e.g. the linkage stops closing).
    Class {
        /// Before.
        from: ClassKind,
        /// After.
        to: ClassKind,
    },
    /// The number of components changes.
    Components {
        /// Before.
        from: usize,
        /// After.
        to: usize,
    },
    /// Same number of components, different sizes (oriented intervals each).
    ComponentSizes {
        /// Before, largest first.
        from: Vec<usize>,
        /// After, largest first.
        to: Vec<usize>,
    },
    /// The number of oriented intervals changes (intervals born or dying).
    Intervals {
        /// Before.
        from: usize,
        /// After.
        to: usize,
    },
    /// The number of pieces of the non-oriented space changes.
    UnionParts {
        /// Before.
        from: usize,
        /// After.
        to: usize,
    },
    /// Interval ends are set by other flat steps than before: events meet.
    /// `events` are the flat steps at the ends that changed (before and after).
    EventsMeet {
        /// The events involved.
        events: Vec<Event>,
    },
    /// The number of branch points (or dead ends) changes.
    BranchPoints {
        /// Before.
        from: usize,
        /// After.
        to: usize,
    },
    /// The number of components along which the input bar turns fully changes.
    FullTurns {
        /// Before.
        from: usize,
        /// After.
        to: usize,
    },
    /// The input bar's turning is undecided on one side.
    TurnsUndecided,
}

/// Everything that differs from `a` to `b`, coarsest first (empty when equal).
pub fn changes(a: &Structure, b: &Structure) -> Vec<Change> {
    let mut out = Vec::new();
    if a.class != b.class {
        out.push(Change::Class { from: a.class, to: b.class });
    }
    let (ca, cb) = (a.component_sizes.len(), b.component_sizes.len());
    if ca != cb {
        out.push(Change::Components { from: ca, to: cb });
    } else if a.component_sizes != b.component_sizes {
        out.push(Change::ComponentSizes { from: a.component_sizes.clone(), to: b.component_sizes.clone() });
    }
    if a.intervals.len() != b.intervals.len() {
        out.push(Change::Intervals { from: a.intervals.len(), to: b.intervals.len() });
    }
    if a.union_parts != b.union_parts {
        out.push(Change::UnionParts { from: a.union_parts, to: b.union_parts });
    }
    // Intervals of a type on both sides whose ends are set by other flat steps.
    let mut events: Vec<Event> = Vec::new();
    for x in a.intervals.iter().filter(|x| !b.intervals.contains(x)) {
        for y in b.intervals.iter().filter(|y| y.ty == x.ty && !a.intervals.contains(y)) {
            if x.lower != y.lower {
                events.extend(x.lower.iter().chain(&y.lower));
            }
            if x.upper != y.upper {
                events.extend(x.upper.iter().chain(&y.upper));
            }
        }
    }
    events.sort();
    events.dedup();
    if !events.is_empty() {
        out.push(Change::EventsMeet { events });
    }
    if a.branch_points != b.branch_points {
        out.push(Change::BranchPoints { from: a.branch_points, to: b.branch_points });
    }
    let full = |s: &Structure| s.turns.iter().filter(|&&t| t == Turn::Full).count();
    if full(a) != full(b) {
        out.push(Change::FullTurns { from: full(a), to: full(b) });
    }
    let unknown = |s: &Structure| s.turns.contains(&Turn::Unknown);
    if unknown(a) != unknown(b) {
        out.push(Change::TurnsUndecided);
    }
    out
}

/// Analyse the scene at `value`: the whole analysis, summarised.
pub fn sample(setup: &Setup, value: f64) -> SweepSample {
    let scene = apply(&setup.scene, setup.parameter, value);
    let empty = |class: Class| {
        let structure = Structure {
            class: class.kind(),
            intervals: Vec::new(),
            union_parts: 0,
            component_sizes: Vec::new(),
            branch_points: 0,
            turns: Vec::new(),
        };
        SweepSample {
            value,
            class,
            union: Vec::new(),
            oriented_intervals: 0,
            components: Vec::new(),
            lazy: false,
            estimated: 0,
            structure,
        }
    };
    let analysis = match analyse_checked(scene, setup.base, setup.scope, SelfCheck::Skip) {
        Err(e) => return empty(Class::Invalid(e.message)),
        Ok(a) => a,
    };
    let s = match analysis.outcome {
        Err(o) => return empty(Class::Outside(o)),
        Ok(s) => s,
    };
    let class = if no_realization(&s, analysis.linkage.scale).is_some() { Class::NoRealization } else { Class::Solved };
    summarise(value, class, &analysis.linkage, &s, setup.input)
}

/// The sample of a solved analysis.
fn summarise(value: f64, class: Class, linkage: &Linkage, s: &Solved, input: Option<InputBar>) -> SweepSample {
    let mut intervals: Vec<IntervalShape> = s
        .space
        .intervals
        .iter()
        .map(|iv| IntervalShape {
            ty: iv.ty.0.clone(),
            lower: iv.lower.events.to_vec(),
            upper: iv.upper.events.to_vec(),
            point: iv.lower.lambda == iv.upper.lambda,
        })
        .collect();
    intervals.sort();
    let components: Vec<ComponentSize> = s
        .components
        .list
        .iter()
        .map(|c| ComponentSize {
            intervals: c.intervals.len(),
            lambda_length: c
                .intervals
                .iter()
                .map(|&i| s.space.intervals[i].upper.lambda - s.space.intervals[i].lower.lambda)
                .sum(),
            lambda_range: c.lambda_range,
            turn: input.map(|bar| turn(linkage, s, c, bar)),
        })
        .collect();
    let mut component_sizes: Vec<usize> = components.iter().map(|c| c.intervals).collect();
    component_sizes.sort_unstable_by(|a, b| b.cmp(a));
    let mut turns: Vec<Turn> = components.iter().filter_map(|c| c.turn).collect();
    turns.sort();
    let structure = Structure {
        class: class.kind(),
        intervals,
        union_parts: s.union.len(),
        component_sizes,
        branch_points: s.components.branch_points.len(),
        turns,
    };
    SweepSample {
        value,
        class,
        union: s.union.clone(),
        oriented_intervals: s.space.intervals.len(),
        components,
        lazy: s.lazy,
        estimated: s.certifier.estimated(),
        structure,
    }
}

/// Whether `bar` turns fully once around component `c`: the winding number
/// of its angle from the ground line, summed over a walk whose joints move at most half the
/// bar's length per sample (so its angle changes by less than 30° between
/// samples, and each increment is read without ambiguity). Unknown for an
/// open component, a walk with a jump, or one cut by [`TURN_WALK_BUDGET`].
fn turn(linkage: &Linkage, s: &Solved, c: &crate::motion::Component, bar: InputBar) -> Turn {
    if !c.closed {
        return Turn::Unknown;
    }
    let length = linkage.bar_between(bar.pivot, bar.tip).map_or(0.0, |b| b.length);
    if length <= 0.0 || !length.is_finite() {
        return Turn::Unknown;
    }
    let segments = component_segments(&s.space, c);
    let mut walk = Stepper::new(&s.construction, linkage, segments, 0.5 * length).with_budget(TURN_WALK_BUDGET);
    let (mut first, mut last, mut total) = (None, None, 0.0f64);
    for sample in walk.by_ref() {
        if sample.jump {
            return Turn::Unknown;
        }
        let a = bar.angle(&sample.positions);
        if let Some(prev) = last {
            total += wrap_angle(a - prev);
        }
        first.get_or_insert(a);
        last = Some(a);
    }
    if !walk.summary().complete() {
        return Turn::Unknown;
    }
    // Back at the start: close the loop (the last sample is the first realization).
    if let (Some(f), Some(l)) = (first, last) {
        total += wrap_angle(f - l);
    }
    let winding = (total / std::f64::consts::TAU).round();
    if winding != 0.0 { Turn::Full } else { Turn::Rocks }
}

/// An angle difference brought into (−π, π].
pub fn wrap_angle(d: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    let d = d.rem_euclid(TAU);
    if d > PI { d - TAU } else { d }
}

/// The `i`-th of `n` sample values from `from` to `to` (both included; `n` ≥ 2).
pub fn sample_value(from: f64, to: f64, i: usize, n: usize) -> f64 {
    if i + 1 == n {
        return to;
    }
    from + (to - from) * (i as f64 / (n - 1) as f64)
}

/// A structure met only inside a transition's bracket, on one float.
#[derive(Clone, Debug, PartialEq)]
pub struct PointStructure {
    /// The value where it holds.
    pub value: f64,
    /// How it differs from the structure before the transition.
    pub changes: Vec<Change>,
    /// Its sample there (class, intervals, components).
    pub sample: Box<SweepSample>,
}

/// A value where the structure changes, to float resolution.
#[derive(Clone, Debug, PartialEq)]
pub struct Transition {
    /// The sample gap it lies in: between samples `gap` and `gap + 1`.
    pub gap: usize,
    /// The last value with the structure before.
    pub before: f64,
    /// The first value with the structure after.
    pub after: f64,
    /// The transition value: the first float whose structure differs from
    /// the one before (`after`, or the first of `between`).
    pub value: f64,
    /// What changes from before to after (empty when the structure after
    /// is the one before: a special structure on isolated floats only).
    pub changes: Vec<Change>,
    /// Structures met on single floats strictly between `before` and `after`
    /// (each float's neighbours on both sides differ from it), in order:
    /// non-generic places such as two steps flat at once.
    pub between: Vec<PointStructure>,
    /// Whether every bracket reached adjacent floats (else the bisection budget ran out).
    pub resolved: bool,
    /// Whether a sample at or inside the bracket rests on decisions the
    /// analysis could only estimate, not prove ([`crate::certify`]).
    pub estimated: bool,
    /// The sample at `before`.
    pub before_sample: Box<SweepSample>,
    /// The sample at `after` (its class, components, …).
    pub after_sample: Box<SweepSample>,
}

/// One bracket bisected to the end: `from` holds at `lo`, `to` at `hi`.
struct Raw {
    lo: f64,
    hi: f64,
    from: SweepSample,
    to: SweepSample,
    resolved: bool,
}

/// The transitions between neighbouring samples `a` (index `gap`) and `b`,
/// located by bisection on the parameter (none when their structures are equal).
pub fn locate(setup: &Setup, gap: usize, a: &SweepSample, b: &SweepSample) -> Vec<Transition> {
    if a.structure == b.structure {
        return Vec::new();
    }
    let mut raws = Vec::new();
    let mut splits = MAX_SPLITS;
    bisect(setup, a.clone(), b.clone(), &mut raws, &mut splits);
    merge(gap, raws)
}

/// Bisect `[a, b]` (different structures) until adjacent floats; a third
/// structure met on the way splits the bracket in two (at most `splits` times).
fn bisect(setup: &Setup, mut a: SweepSample, mut b: SweepSample, out: &mut Vec<Raw>, splits: &mut usize) {
    for _ in 0..MAX_BISECTIONS {
        let mut mid = a.value + (b.value - a.value) / 2.0;
        if !mid.is_finite() {
            mid = a.value / 2.0 + b.value / 2.0; // the difference overflowed
        }
        if mid <= a.value.min(b.value) || mid >= a.value.max(b.value) {
            out.push(Raw { lo: a.value, hi: b.value, from: a, to: b, resolved: true });
            return;
        }
        let m = sample(setup, mid);
        if m.structure == a.structure {
            a = m;
        } else if m.structure == b.structure {
            b = m;
        } else if *splits > 0 {
            *splits -= 1;
            bisect(setup, a, m.clone(), out, splits);
            bisect(setup, m, b, out, splits);
            return;
        } else {
            b = m; // out of splits: report the first change met
        }
    }
    out.push(Raw { lo: a.value, hi: b.value, from: a, to: b, resolved: false });
}

/// Raw brackets in order → transitions, [joined](join) where they touch.
fn merge(gap: usize, raws: Vec<Raw>) -> Vec<Transition> {
    let single = raws
        .into_iter()
        .map(|r| Transition {
            gap,
            before: r.lo,
            after: r.hi,
            value: r.hi,
            changes: changes(&r.from.structure, &r.to.structure),
            between: Vec::new(),
            resolved: r.resolved,
            estimated: r.from.estimated > 0 || r.to.estimated > 0,
            before_sample: Box::new(r.from),
            after_sample: Box::new(r.to),
        })
        .collect();
    join(single)
}

/// Transitions in order of value, with those that touch (one's `after` is
/// the next one's `before`, both resolved) joined into one: the floats where
/// they touch carry structures of their own ([`Transition::between`]). This
/// also joins across sample gaps, where a sample falls on a transition.
pub fn join(transitions: Vec<Transition>) -> Vec<Transition> {
    let mut out: Vec<Transition> = Vec::new();
    for t in transitions {
        let Some(prev) = out.last_mut().filter(|p| p.resolved && t.resolved && p.after == t.before) else {
            out.push(t);
            continue;
        };
        let from = &prev.before_sample.structure;
        let mut between = std::mem::take(&mut prev.between);
        between.push(PointStructure {
            value: prev.after,
            changes: changes(from, &prev.after_sample.structure),
            sample: prev.after_sample.clone(),
        });
        between
            .extend(t.between.into_iter().map(|p| PointStructure { changes: changes(from, &p.sample.structure), ..p }));
        prev.after = t.after;
        prev.changes = changes(from, &t.after_sample.structure);
        prev.between = between;
        prev.estimated |= t.estimated;
        prev.after_sample = t.after_sample;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_brings_differences_into_a_half_turn() {
        use std::f64::consts::PI;
        assert_eq!(wrap_angle(0.25), 0.25);
        assert!((wrap_angle(2.0 * PI - 0.25) + 0.25).abs() < 1e-15);
        assert!((wrap_angle(-2.0 * PI + 0.25) - 0.25).abs() < 1e-15);
    }

    #[test]
    fn samples_span_the_range_and_land_on_both_ends() {
        assert_eq!(sample_value(0.1, 0.7, 0, 4), 0.1);
        assert_eq!(sample_value(0.1, 0.7, 3, 4), 0.7);
        assert!((sample_value(0.1, 0.7, 1, 4) - 0.3).abs() < 1e-16);
    }

    #[test]
    fn a_bar_length_becomes_a_stated_length() {
        let text = "bars = [[\"A\", \"B\"], [\"B\", \"C\"]]\n[joints]\nA = [0, 0]\nB = [1, 0]\nC = [1, 1]\n";
        let scene = crate::scene::parse_scene(text, "t", "t").unwrap();
        let edited = apply(&scene, Parameter::BarLength(1), 2.5);
        assert_eq!(Linkage::from_scene(&edited).bars[1].length, 2.5);
        assert_eq!(Linkage::from_scene(&edited).bars[0].length, 1.0);
        let moved = apply(&scene, Parameter::Joint { joint: 2, axis: 1 }, 3.0);
        assert_eq!(Linkage::from_scene(&moved).bars[1].length, 3.0);
    }
}
