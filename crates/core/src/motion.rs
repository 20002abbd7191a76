//! Continuous motion (THEORY.md §4): connected components as cycles of
//! oriented intervals, the two paths between two realizations, and a stepper
//! that walks them by a geometric step, landing exactly on every endpoint.

use std::collections::hash_map::Entry;

use crate::cayley_space::{CayleySpace, OrientedInterval};
use crate::inthash::{IntMap, int_map};
use crate::linkage::Linkage;
use crate::real::{Dd, Real};
use crate::realize::{Construction, Event, Point2, Realization, RealizationType, bar_residual, to_display};

/// Which end of an interval.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Side {
    /// The lower end (smaller λ).
    Lower,
    /// The upper end (larger λ).
    Upper,
}

impl Side {
    fn other(self) -> Side {
        match self {
            Side::Lower => Side::Upper,
            Side::Upper => Side::Lower,
        }
    }
}

/// A connected component of the realization space: oriented intervals in
/// traversal order, each walked upward (`forward`) or downward.
#[derive(Clone, Debug, PartialEq)]
pub struct Component {
    /// Indices of its oriented intervals, in traversal order.
    pub intervals: Vec<usize>,
    /// Per interval: walked upward in λ (`true`) or downward.
    pub forward: Vec<bool>,
    /// Whether the walk came back to its start (always, in a generic scene).
    pub closed: bool,
    /// The smallest and largest λ it reaches.
    pub lambda_range: [f64; 2],
}

/// An endpoint where the walk had a choice (several steps flat at once) or
/// none (a dead end): only in non-generic scenes.
#[derive(Clone, Debug, PartialEq)]
pub struct BranchPoint {
    /// The λ of the endpoint.
    pub lambda: f64,
    /// The steps flat there.
    pub events: Vec<Event>,
    /// The interval the walk arrived from.
    pub from: usize,
    /// Every interval it could continue into; the walk took the first.
    pub options: Vec<usize>,
    /// Intervals that go on from this end on the other side of λ: a flat
    /// step only touches zero here, and the type with its bit flipped
    /// continues beyond (the sweep splits runs at such a touch, see
    /// [`crate::cayley_space`]). The motion passes a singular place there
    /// (on Peaucellier's base A–B, where the kite O, B, C, D folds flat and
    /// D lands on B). The listing ends its component at such a place, as it
    /// does where a touch ends an interval on another base; the connected
    /// sets join both sides.
    pub through: Vec<usize>,
}

/// The connected components of a Cayley space, and where the walk had no unique way on.
#[derive(Clone, Debug, PartialEq)]
pub struct Components {
    /// The components, in order of their first interval.
    pub list: Vec<Component>,
    /// For each oriented interval, its component.
    pub of_interval: Vec<usize>,
    /// Endpoints with several ways on or none (non-generic scenes only).
    pub branch_points: Vec<BranchPoint>,
    /// Per listed component, its connected set (sets numbered in order of
    /// their first component). Components whose intervals meet at an end by
    /// the flip rule share a realization there, so they are one set. In a
    /// generic scene every component is its own set. At a branch point the
    /// listing depends on the walk; the sets join what the flip rule joins
    /// on this base, so their count is an upper bound on the connected
    /// pieces of the realization space, as the listing's is, and a tighter
    /// one. At non-generic places it can still depend on the base: a shared
    /// realization may be reached on another base only by flipping several
    /// steps at once, or through a degenerate piece or a dead end (a step's
    /// base joints coinciding, [`crate::cayley_space::Note::Degenerate`]).
    pub connected: Vec<usize>,
}

impl Components {
    /// How many connected sets the realization space has ([`Components::connected`]).
    pub fn connected_set_count(&self) -> usize {
        self.connected.iter().max().map_or(0, |m| m + 1)
    }
}

fn end(i: &OrientedInterval<f64>, side: Side) -> &crate::roots::Endpoint<f64> {
    match side {
        Side::Lower => &i.lower,
        Side::Upper => &i.upper,
    }
}

/// A realization type as a hash key: packed into an integer where every
/// type fits in 128 steps (no allocation, cheap to hash), the bits
/// themselves beyond.
trait TypeKey: Clone + Eq + std::hash::Hash {
    /// This key with bit `k` flipped.
    fn flipped(&self, k: usize) -> Self;
}

impl TypeKey for u128 {
    fn flipped(&self, k: usize) -> Self {
        self ^ (1 << k)
    }
}

impl TypeKey for Vec<bool> {
    fn flipped(&self, k: usize) -> Self {
        let mut bits = self.clone();
        bits[k] = !bits[k];
        bits
    }
}

/// Link intervals by the flip rule: at an end where step k is flat the motion
/// continues, on the same side of λ, into the type with bit k flipped that
/// ends at the same root. Every interval lands in exactly one component.
pub fn components(space: &CayleySpace<f64>) -> Components {
    let packed: Option<Vec<u128>> = space.intervals.iter().map(|iv| crate::realize::bits_word(&iv.ty.0)).collect();
    match packed {
        Some(keys) => components_by(space, &keys),
        None => components_by(space, &space.intervals.iter().map(|iv| iv.ty.0.clone()).collect::<Vec<_>>()),
    }
}

/// [`components`] with each interval's type as `keys[i]`.
fn components_by<K: TypeKey>(space: &CayleySpace<f64>, keys: &[K]) -> Components {
    let ivs = &space.intervals;
    // Ends with the same (root, side, type), chained in interval order: the
    // map holds the first and last end of each chain, `next` links them (end
    // `2i` is interval i's lower, `2i + 1` its upper; no list per key). A
    // root and side are one word the same way, 2·id + side.
    let slot = |i: usize, side: Side| 2 * i + usize::from(side == Side::Upper);
    let mut chains: IntMap<(usize, K), (usize, usize)> = int_map(2 * ivs.len());
    let mut next = vec![usize::MAX; 2 * ivs.len()];
    for (i, iv) in ivs.iter().enumerate() {
        for side in [Side::Lower, Side::Upper] {
            match chains.entry((slot(end(iv, side).id, side), keys[i].clone())) {
                Entry::Occupied(mut e) => {
                    let (_, last) = e.get_mut();
                    next[*last] = slot(i, side);
                    *last = slot(i, side);
                }
                Entry::Vacant(e) => {
                    e.insert((slot(i, side), slot(i, side)));
                }
            }
        }
    }
    // Intervals with an end `entered` at the same root as end `side` of
    // interval `i`, in the types with one flat step's bit flipped (into `out`).
    let flipped_at = |i: usize, side: Side, entered: Side, out: &mut Vec<usize>| {
        out.clear();
        let e = end(&ivs[i], side);
        // Only single flips: where none continues, the end is a dead end
        // (e.g. a folded rhombus, where a later step degenerates and the
        // motion has an extra degree of freedom). Passing through by flipping
        // several bits would join components on some bases and not on
        // others; the realization space must not depend on the base.
        for ev in &e.events {
            let key = (slot(e.id, entered), keys[i].flipped(ev.step));
            let Some(&(first, _)) = chains.get(&key) else { continue };
            let mut at = first;
            while at != usize::MAX {
                // An isolated point has both ends at the root.
                if at / 2 != i && !out.contains(&(at / 2)) {
                    out.push(at / 2);
                }
                at = next[at];
            }
        }
    };
    // The walk's way on: the flipped type on the same side of λ.
    let partners = |i: usize, side: Side, out: &mut Vec<usize>| flipped_at(i, side, side, out);
    // Through a touch: the flipped type on the other side (see `BranchPoint::through`).
    let through = |i: usize, side: Side, out: &mut Vec<usize>| {
        flipped_at(i, side, side.other(), out);
        out.retain(|&j| ivs[j].lower.lambda != ivs[j].upper.lambda);
    };
    // Work lists made once (a component's own lists are copied from `seq`).
    let (mut options, mut beyond) = (Vec::with_capacity(4), Vec::with_capacity(4));
    let (mut seq, mut behind) = (Vec::new(), Vec::new());
    let mut passes_touch = false;
    let mut of_interval = vec![usize::MAX; ivs.len()];
    let mut list = Vec::with_capacity(ivs.len());
    let mut branch_points = Vec::new();
    for start in 0..ivs.len() {
        if of_interval[start] != usize::MAX {
            continue;
        }
        let c = list.len();
        of_interval[start] = c;
        seq.clear();
        seq.push((start, true));
        let mut closed = false;
        // Walk upward from the start's upper end.
        let (mut cur, mut leaving) = (start, Side::Upper);
        loop {
            partners(cur, leaving, &mut options);
            if options.len() != 1 {
                through(cur, leaving, &mut beyond);
                passes_touch |= !beyond.is_empty();
                let e = end(&ivs[cur], leaving);
                branch_points.push(BranchPoint {
                    lambda: e.lambda,
                    events: e.events.to_vec(),
                    from: cur,
                    options: options.clone(),
                    through: beyond.clone(),
                });
            }
            let Some(&next) = options.iter().find(|&&j| j == start || of_interval[j] == usize::MAX).or(options.first())
            else {
                break;
            };
            if next == start {
                closed = true;
                break;
            }
            if of_interval[next] != usize::MAX {
                break; // joins a walk already made: a branch point, reported above
            }
            of_interval[next] = c;
            // Entered at the same side we left from; leave by its other end.
            seq.push((next, leaving == Side::Lower));
            cur = next;
            leaving = leaving.other();
        }
        if !closed {
            // An open chain: collect what lies behind the start as well
            // (nearest first, then put before the rest in reverse).
            let (mut cur, mut leaving) = (start, Side::Lower);
            behind.clear();
            loop {
                partners(cur, leaving, &mut options);
                let Some(&next) = options.iter().find(|&&j| of_interval[j] == usize::MAX) else { break };
                of_interval[next] = c;
                behind.push((next, leaving == Side::Upper));
                cur = next;
                leaving = leaving.other();
            }
            if !behind.is_empty() {
                behind.reverse();
                behind.append(&mut seq);
                std::mem::swap(&mut seq, &mut behind);
            }
        }
        let lo = seq.iter().map(|&(i, _)| ivs[i].lower.lambda).fold(f64::INFINITY, f64::min);
        let hi = seq.iter().map(|&(i, _)| ivs[i].upper.lambda).fold(f64::NEG_INFINITY, f64::max);
        list.push(Component {
            intervals: seq.iter().map(|&(i, _)| i).collect(),
            forward: seq.iter().map(|&(_, f)| f).collect(),
            closed,
            lambda_range: [lo, hi],
        });
    }
    // Only an end with several flat steps can join two walks (elsewhere
    // each end has one partner, and the walk went on into it),
    // and a touch passed through (`BranchPoint::through`).
    let several = ivs.iter().any(|i| i.lower.events.len() > 1 || i.upper.events.len() > 1);
    let mut sets = UnionFind::new(list.len());
    // A touch inside intervals: each type through it meets the type with
    // the touching step's bit flipped there (see `Touch`).
    if !space.touches.is_empty() {
        let mut by_type: std::collections::HashMap<&[bool], Vec<usize>> = std::collections::HashMap::new();
        for (i, iv) in ivs.iter().enumerate() {
            by_type.entry(&iv.ty.0).or_default().push(i);
        }
        for t in &space.touches {
            let holds = |i: &usize| ivs[*i].lower.lambda <= t.lambda && t.lambda <= ivs[*i].upper.lambda;
            for (i, iv) in ivs.iter().enumerate().filter(|(i, iv)| iv.ty.0.starts_with(&t.prefix) && holds(i)) {
                let mut flipped = iv.ty.0.clone();
                flipped[t.event.step] = !flipped[t.event.step];
                for j in by_type.get(&flipped[..]).into_iter().flatten().filter(|j| holds(j)) {
                    sets.join(of_interval[i], of_interval[*j]);
                }
            }
        }
    }
    if several || passes_touch {
        for i in 0..ivs.len() {
            for side in [Side::Lower, Side::Upper] {
                partners(i, side, &mut options);
                beyond.clear();
                if passes_touch {
                    through(i, side, &mut beyond);
                }
                for &j in options.iter().chain(&beyond) {
                    sets.join(of_interval[i], of_interval[j]);
                }
            }
        }
    }
    Components { connected: sets.numbered(), list, of_interval, branch_points }
}

/// Disjoint sets of `0..n` (path halving, the smaller index as root).
struct UnionFind(Vec<usize>);

impl UnionFind {
    fn new(n: usize) -> Self {
        UnionFind((0..n).collect())
    }
    fn root(&mut self, mut c: usize) -> usize {
        while self.0[c] != c {
            self.0[c] = self.0[self.0[c]];
            c = self.0[c];
        }
        c
    }
    fn join(&mut self, a: usize, b: usize) {
        let (x, y) = (self.root(a), self.root(b));
        self.0[x.max(y)] = x.min(y);
    }
    /// Each element's set, numbered from 0 in order of first element.
    fn numbered(mut self) -> Vec<usize> {
        let mut number = vec![usize::MAX; self.0.len()];
        let mut sets = 0;
        (0..self.0.len())
            .map(|c| {
                let r = self.root(c);
                if number[r] == usize::MAX {
                    number[r] = sets;
                    sets += 1;
                }
                number[r]
            })
            .collect()
    }
}

/// The oriented intervals meeting at a branch point at `lambda` that
/// `interval` ends at: every branch point recorded there sharing an interval
/// with them, closed transitively (each walk records the ways it saw), in
/// index order, `interval` included. Empty when no branch point there
/// involves it (a generic end: one way on).
pub fn ways_at(components: &Components, lambda: f64, interval: usize) -> Vec<usize> {
    let here: Vec<Vec<usize>> = components
        .branch_points
        .iter()
        .filter(|b| b.lambda == lambda)
        .map(|b| std::iter::once(b.from).chain(b.options.iter().copied()).collect())
        .collect();
    let mut ways = vec![interval];
    let mut used = vec![false; here.len()];
    while let Some(k) = (0..here.len()).find(|&k| !used[k] && here[k].iter().any(|i| ways.contains(i))) {
        used[k] = true;
        ways.extend(&here[k]);
    }
    ways.sort_unstable();
    ways.dedup();
    if ways.len() > 1 { ways } else { Vec::new() }
}

/// A branch point a walk along `segments` passes: where one segment ends
/// and the next begins at a λ where several ways meet.
#[derive(Clone, Debug, PartialEq)]
pub struct BranchPassed {
    /// The λ of the branch point.
    pub lambda: f64,
    /// The steps flat there (0-based).
    pub flat: Vec<usize>,
    /// The interval the walk went on into.
    pub taken: usize,
    /// Every interval meeting there ([`ways_at`]), the one arrived from and `taken` included.
    pub ways: Vec<usize>,
}

/// The branch points passed between consecutive `segments` of a motion, in
/// order; with `closed` (a whole closed component, walked round) also the
/// one from the last segment back to the first.
pub fn branches_passed(components: &Components, segments: &[Segment], closed: bool) -> Vec<BranchPassed> {
    let wrap = segments.last().zip(segments.first()).filter(|_| closed && segments.len() > 1);
    segments
        .windows(2)
        .map(|w| (&w[0], &w[1]))
        .chain(wrap)
        .filter(|(a, b)| a.to == b.from)
        .filter_map(|(a, b)| {
            let ways = ways_at(components, a.to, a.interval);
            (!ways.is_empty()).then(|| BranchPassed { lambda: a.to, flat: a.flat_to.clone(), taken: b.interval, ways })
        })
        .collect()
}

/// The oriented interval holding a realization (its own type's interval).
pub fn locate(space: &CayleySpace<f64>, r: &Realization, scale: f64) -> Option<usize> {
    let tol = crate::tolerance::FEASIBLE * scale;
    let within = |i: &OrientedInterval<f64>, tol: f64| {
        i.ty == r.ty && r.lambda >= i.lower.lambda - tol && r.lambda <= i.upper.lambda + tol
    };
    // An interval holding λ itself first: two of one type can end within the tolerance of it.
    let intervals = &space.intervals;
    intervals.iter().position(|i| within(i, 0.0)).or_else(|| intervals.iter().position(|i| within(i, tol)))
}

/// Why a realization could not be located (see [`explain_missing`]).
#[derive(Clone, Debug, PartialEq)]
pub enum Missing {
    /// The type has `signs` signs but the scene has `steps` steps.
    WrongLength {
        /// The type asked for.
        ty: RealizationType,
        /// Its number of signs.
        signs: usize,
        /// The scene's number of construction steps.
        steps: usize,
    },
    /// The type has no interval at all.
    NoInterval {
        /// The type asked for.
        ty: RealizationType,
    },
    /// The type is realizable, but not at `lambda`: only on `spans`.
    Elsewhere {
        /// The type asked for.
        ty: RealizationType,
        /// The base length asked for.
        lambda: f64,
        /// The λ-intervals where the type is realizable.
        spans: Vec<[f64; 2]>,
    },
}

/// Why a realization could not be located.
pub fn explain_missing(space: &CayleySpace<f64>, r: &Realization, n_steps: usize) -> Missing {
    if r.ty.0.len() != n_steps {
        return Missing::WrongLength { ty: r.ty.clone(), signs: r.ty.0.len(), steps: n_steps };
    }
    let spans: Vec<[f64; 2]> =
        space.intervals.iter().filter(|i| i.ty == r.ty).map(|i| [i.lower.lambda, i.upper.lambda]).collect();
    if spans.is_empty() {
        Missing::NoInterval { ty: r.ty.clone() }
    } else {
        Missing::Elsewhere { ty: r.ty.clone(), lambda: r.lambda, spans }
    }
}

/// A stretch of motion inside one oriented interval, from λ `from` to `to`.
/// `flat_from`/`flat_to` list the steps flat there when that end is an
/// interval endpoint (empty for an end inside the interval).
#[derive(Clone, Debug, PartialEq)]
pub struct Segment {
    /// Index of the oriented interval.
    pub interval: usize,
    /// Its realization type.
    pub ty: RealizationType,
    /// λ where the stretch starts.
    pub from: f64,
    /// λ where it ends (below `from` when walked downward).
    pub to: f64,
    /// Steps flat at `from` (empty inside the interval).
    pub flat_from: Vec<usize>,
    /// Steps flat at `to` (empty inside the interval).
    pub flat_to: Vec<usize>,
}

impl Segment {
    /// The same stretch walked the other way.
    pub fn reversed(&self) -> Segment {
        Segment {
            from: self.to,
            to: self.from,
            flat_from: self.flat_to.clone(),
            flat_to: self.flat_from.clone(),
            ..self.clone()
        }
    }
}

/// The whole component as segments, starting at its first interval's start.
pub fn component_segments(space: &CayleySpace<f64>, c: &Component) -> Vec<Segment> {
    c.intervals
        .iter()
        .zip(&c.forward)
        .map(|(&i, &fwd)| {
            let iv = &space.intervals[i];
            let (a, b) = if fwd { (&iv.lower, &iv.upper) } else { (&iv.upper, &iv.lower) };
            let steps = |e: &crate::roots::Endpoint<f64>| e.events.iter().map(|ev| ev.step).collect();
            Segment {
                interval: i,
                ty: iv.ty.clone(),
                from: a.lambda,
                to: b.lambda,
                flat_from: steps(a),
                flat_to: steps(b),
            }
        })
        .collect()
}

/// The two arcs of a closed component between realizations in intervals
/// `ia` (at `la`) and `ib` (at `lb`): first following the component's
/// direction, then against it. An open component (a chain between dead
/// ends) has one path only: the arc that would pass its ends is empty.
/// `None` when either interval is not in the component.
pub fn arcs(
    space: &CayleySpace<f64>,
    c: &Component,
    (ia, la): (usize, f64),
    (ib, lb): (usize, f64),
) -> Option<[Vec<Segment>; 2]> {
    let segs = component_segments(space, c);
    let m = segs.len();
    let pos = |i: usize| c.intervals.iter().position(|&j| j == i);
    let (pa, pb) = (pos(ia)?, pos(ib)?);
    let ahead = |s: &Segment, x: f64, y: f64| if s.to >= s.from { y >= x } else { y <= x };
    // Forward: from (pa, la) along the traversal to (pb, lb).
    let mut fwd = Vec::new();
    let start = |s: Segment| Segment { from: la, flat_from: Vec::new(), ..s };
    let finish = |s: Segment| Segment { to: lb, flat_to: Vec::new(), ..s };
    if pa == pb && ahead(&segs[pa], la, lb) {
        fwd.push(finish(start(segs[pa].clone())));
    } else {
        fwd.push(start(segs[pa].clone()));
        let mut k = (pa + 1) % m;
        while k != pb {
            fwd.push(segs[k].clone());
            k = (k + 1) % m;
        }
        fwd.push(finish(segs[pb].clone()));
    }
    // Backward: against the traversal.
    let rev = Segment::reversed;
    let mut back = Vec::new();
    if pa == pb && !ahead(&segs[pa], la, lb) {
        back.push(finish(start(segs[pa].clone())));
    } else {
        back.push(start(rev(&segs[pa])));
        let mut k = (pa + m - 1) % m;
        while k != pb {
            back.push(rev(&segs[k]));
            k = (k + m - 1) % m;
        }
        back.push(finish(rev(&segs[pb])));
    }
    if !c.closed {
        // The chain runs in list order: forward is a path only if it does not wrap.
        let forward = pa < pb || (pa == pb && ahead(&segs[pa], la, lb));
        if forward { back.clear() } else { fwd.clear() }
    }
    Some([fwd, back])
}

/// One realization along a walk.
#[derive(Clone, Debug, PartialEq)]
pub struct Sample {
    /// The base length λ.
    pub lambda: f64,
    /// The realization type.
    pub ty: RealizationType,
    /// Joint positions in the display frame.
    pub positions: Vec<Point2<f64>>,
    /// Index of the segment this sample belongs to.
    pub segment: usize,
    /// Set when the sample is a segment's end (an interval endpoint, except at the walk's end).
    pub at_end: bool,
    /// Set when some joint moved farther than the step from the previous
    /// sample although λ could not be resolved any finer: the motion is
    /// discontinuous here (a degenerate pass, e.g. a rhombus folding flat), or
    /// an unresolved stretch was skipped (see [`WalkSummary::unresolved`]).
    /// No continuous motion joins this sample to the previous one.
    pub jump: bool,
}

/// What a walk met, for the commands to say: how many samples, whether the
/// budget stopped it, where it jumped, what it skipped, where it failed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WalkSummary {
    /// Samples made.
    pub samples: usize,
    /// Stopped at the sample budget before the end of the walk.
    pub truncated: bool,
    /// λ of every sample reached by a jump.
    pub jumps: Vec<f64>,
    /// Stretches `[from, to]` of λ skipped as one jump: more than
    /// [`crate::tolerance::STEPPER_MAX_JUMPS_PER_SEGMENT`] jumps in one segment
    /// mean the realization is not resolved in f64 there.
    pub unresolved: Vec<[f64; 2]>,
    /// λ at which no realization could be computed: the walk ended there.
    pub stopped_at: Option<f64>,
}

impl WalkSummary {
    /// Whether the walk covered all of its segments.
    pub fn complete(&self) -> bool {
        !self.truncated && self.stopped_at.is_none()
    }
}

/// The diagonal of the points' bounding box: the drawing's extent, the unit
/// of default steps. Computed on halved coordinates so that drawings near
/// ±f64::MAX do not overflow; 0 for fewer than two distinct points.
pub fn bounding_diagonal(points: &[Point2<f64>]) -> f64 {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in points {
        for axis in 0..2 {
            lo[axis] = lo[axis].min(p[axis] / 2.0);
            hi[axis] = hi[axis].max(p[axis] / 2.0);
        }
    }
    if points.is_empty() {
        return 0.0;
    }
    ((hi[0] - lo[0]).hypot(hi[1] - lo[1]) * 2.0).min(f64::MAX)
}

/// Walks segments by a geometric step: consecutive samples differ by at most
/// `step` in every joint's position (display frame), except where λ cannot be
/// resolved finer (adjacent floats): such a sample is marked as a
/// [jump](Sample::jump). Every segment end is hit exactly. At most `budget`
/// samples are made (default [`crate::tolerance::DEFAULT_MAX_SAMPLES`]);
/// [`Stepper::summary`] says whether the walk was cut there.
pub struct Stepper<'a> {
    con: &'a Construction<f64>,
    linkage: &'a Linkage,
    segments: Vec<Segment>,
    step: f64,
    seg: usize,
    lambda: f64,
    last: Option<Vec<Point2<f64>>>,
    delta: f64,
    done: bool,
    budget: usize,
    /// Jumps met in the current segment.
    jumps_here: usize,
    summary: WalkSummary,
}

impl<'a> Stepper<'a> {
    /// A walk over `segments` with joints moving at most `step` (scene units) per sample.
    pub fn new(con: &'a Construction<f64>, linkage: &'a Linkage, segments: Vec<Segment>, step: f64) -> Self {
        let lambda = segments.first().map_or(0.0, |s| s.from);
        let delta = step.max(f64::MIN_POSITIVE);
        Stepper {
            con,
            linkage,
            done: segments.is_empty(),
            segments,
            step,
            seg: 0,
            lambda,
            last: None,
            delta,
            budget: crate::tolerance::DEFAULT_MAX_SAMPLES,
            jumps_here: 0,
            summary: WalkSummary::default(),
        }
    }

    /// The same walk with a sample budget of `max_samples`.
    pub fn with_budget(mut self, max_samples: usize) -> Self {
        self.budget = max_samples;
        self
    }

    /// What the walk has met so far (complete once the iterator is exhausted).
    pub fn summary(&self) -> &WalkSummary {
        &self.summary
    }

    fn positions(&self, lambda: f64, ty: &RealizationType) -> Option<Vec<Point2<f64>>> {
        let s = &self.segments[self.seg];
        realization_at(self.con, self.linkage, &Segment { ty: ty.clone(), ..s.clone() }, lambda)
    }

    /// Whether nothing is left to walk: at the end of the last segment of positive length.
    fn at_walk_end(&self) -> bool {
        self.last.is_some()
            && self.lambda == self.segments[self.seg].to
            && self.segments[self.seg + 1..].iter().all(|s| s.from == s.to)
    }

    /// The next sample, or `None` at the end of the walk or where no realization exists.
    fn advance(&mut self) -> Option<Sample> {
        if self.last.is_none() {
            let s = self.segments[0].clone();
            let Some(pos) = self.positions(s.from, &s.ty) else {
                self.summary.stopped_at = Some(s.from);
                return None;
            };
            self.last = Some(pos.clone());
            let at_end = s.from == s.to;
            return Some(Sample { lambda: s.from, ty: s.ty, positions: pos, segment: 0, at_end, jump: false });
        }
        // Past a segment's end: continue in the next one (same λ there).
        while self.lambda == self.segments[self.seg].to {
            if self.seg + 1 == self.segments.len() {
                return None;
            }
            self.seg += 1;
            self.jumps_here = 0;
            self.lambda = self.segments[self.seg].from;
        }
        let s = self.segments[self.seg].clone();
        if self.jumps_here > crate::tolerance::STEPPER_MAX_JUMPS_PER_SEGMENT {
            // Not resolved in f64 here: one marked jump to the segment's end
            // instead of a crawl float by float.
            let Some(pos) = self.positions(s.to, &s.ty) else {
                self.summary.stopped_at = Some(s.to);
                return None;
            };
            self.summary.unresolved.push([self.lambda, s.to]);
            self.lambda = s.to;
            self.last = Some(pos.clone());
            return Some(Sample {
                lambda: s.to,
                ty: s.ty,
                positions: pos,
                segment: self.seg,
                at_end: true,
                jump: true,
            });
        }
        let remaining = s.to - self.lambda;
        let first_try = (self.delta * 2.0).min(remaining.abs());
        let (delta, target, found) = self.search(&s, first_try);
        let Some((pos, moved)) = found else {
            self.summary.stopped_at = Some(target);
            return None;
        };
        let jump = moved > self.step;
        if jump {
            self.jumps_here += 1;
        }
        // After a jump the motion beyond is as smooth as before it: resume the step that was tried.
        self.delta = if jump { first_try / 2.0 } else { delta }.max(f64::MIN_POSITIVE);
        self.lambda = target;
        self.last = Some(pos.clone());
        let at_end = target == s.to;
        Some(Sample { lambda: target, ty: s.ty, positions: pos, segment: self.seg, at_end, jump })
    }

    /// Halve the λ step from `delta` until no joint moves more than the step,
    /// or λ cannot be resolved finer. Returns the λ step, the target λ and the
    /// realization there with its largest joint move (`None`: no realization
    /// at the finest resolution).
    #[allow(clippy::type_complexity)]
    fn search(&self, s: &Segment, mut delta: f64) -> (f64, f64, Option<(Vec<Point2<f64>>, f64)>) {
        let remaining = s.to - self.lambda;
        let last = self.last.as_deref().unwrap_or_default();
        loop {
            let target = if delta >= remaining.abs() { s.to } else { self.lambda + delta * remaining.signum() };
            let pos = self.positions(target, &s.ty);
            // Below a few ulps of λ the step cannot shrink: accept, as a jump if it moved too far.
            let resolution = crate::tolerance::LAMBDA_RESOLUTION_ULPS * (f64::EPSILON / 2.0);
            let small = delta <= resolution * self.lambda.abs().max(self.con.scale);
            match pos {
                Some(pos) => {
                    let moved = max_move(&pos, last);
                    if small || moved <= self.step {
                        return (delta, target, Some((pos, moved)));
                    }
                }
                None if small => return (delta, target, None),
                None => {}
            }
            delta /= 2.0;
        }
    }
}

/// Joint positions (display frame) at λ on a segment. At the segment's ends
/// the steps flat there are placed exactly flat; where a step degenerates
/// exactly at λ (its base joints coincide, as in a folded rhombus) the limit
/// is taken by nudging λ toward the segment's interior. `None` when no
/// realization can be computed there (or it is not finite).
pub fn realization_at(
    con: &Construction<f64>,
    linkage: &Linkage,
    s: &Segment,
    lambda: f64,
) -> Option<Vec<Point2<f64>>> {
    let inward = if lambda == s.to { s.from - s.to } else { s.to - s.from }.signum();
    let flat: &[usize] = if lambda == s.to {
        &s.flat_to
    } else if lambda == s.from {
        &s.flat_from
    } else {
        &[]
    };
    let n = con.steps.len();
    let pos = con.realize_flat(lambda, &s.ty.0, n, flat).ok().or_else(|| {
        crate::tolerance::DEGENERATE_NUDGES
            .iter()
            .find_map(|e| con.realize(lambda + inward * e * con.scale, &s.ty).ok())
    })?;
    let shown = to_display(linkage, con.base, &pos);
    let finite = |p: &[Point2<f64>]| p.iter().all(|p| p[0].is_finite() && p[1].is_finite());
    let miss = bar_residual(linkage, &shown);
    // A step whose base joints nearly meet places its vertex along e/|e|,
    // carrying the rounding divided by |e|: where they are closer than
    // √ε of the scale, f64 may meet every bar and still be far from the
    // realization at this λ (the next λ then jumps back).
    let near = (0..n).any(|k| con.base_distance(&pos, k) < crate::tolerance::NEAR_JOINTS * con.scale);
    let meets = crate::tolerance::BAR_RESIDUAL * con.scale;
    if finite(&shown) && miss <= meets && !near {
        return Some(shown);
    }
    // There f64 misses bars, or may: realize in double-double, and keep
    // whichever meets the bars better.
    let dd = con.map(Dd::new);
    let finer = dd.realize_flat(Dd::new(lambda), &s.ty.0, n, flat).ok().map(|p| {
        let p: Vec<[f64; 2]> = p.iter().map(|q| [q[0].to_f64(), q[1].to_f64()]).collect();
        to_display(linkage, con.base, &p)
    });
    match finer {
        // (An f64 result with no finite miss is never better.)
        Some(f) if finite(&f) && (miss.is_nan() || bar_residual(linkage, &f) <= miss.max(meets)) => Some(f),
        _ => finite(&shown).then_some(shown),
    }
}

fn max_move(a: &[Point2<f64>], b: &[Point2<f64>]) -> f64 {
    a.iter().zip(b).map(|(p, q)| (p[0] - q[0]).hypot(p[1] - q[1])).fold(0.0, f64::max)
}

impl Iterator for Stepper<'_> {
    type Item = Sample;

    fn next(&mut self) -> Option<Sample> {
        if self.done {
            return None;
        }
        if self.summary.samples >= self.budget {
            self.done = true;
            self.summary.truncated = !self.at_walk_end();
            return None;
        }
        let sample = self.advance();
        match &sample {
            Some(s) => {
                self.summary.samples += 1;
                if s.jump {
                    self.summary.jumps.push(s.lambda);
                }
            }
            None => self.done = true,
        }
        sample
    }
}

/// Measures of a walked path.
#[derive(Clone, Debug, PartialEq)]
pub struct PathMeasure {
    /// Length of the polyline of complete Cayley distance vectors (jumps not counted).
    pub cayley_length: f64,
    /// The longest distance any one joint travels (jumps not counted).
    pub max_joint_travel: f64,
    /// What the walk met.
    pub walk: WalkSummary,
}

/// Walk `segments` within `budget` samples and measure them (`ccv` pairs
/// give the Cayley vector). A jump is no motion: it adds nothing to either length.
pub fn measure(
    con: &Construction<f64>,
    linkage: &Linkage,
    segments: Vec<Segment>,
    step: f64,
    ccv: &[[usize; 2]],
    budget: usize,
) -> PathMeasure {
    let mut travel = vec![0.0; linkage.n_joints()];
    let mut cayley_length = 0.0;
    let mut prev: Option<(Vec<Point2<f64>>, Vec<f64>)> = None;
    let mut walk = Stepper::new(con, linkage, segments, step).with_budget(budget);
    for s in walk.by_ref() {
        let v = crate::cayley_vector::cayley_vector(&s.positions, ccv);
        if let (Some((p, w)), false) = (&prev, s.jump) {
            for (t, (a, b)) in travel.iter_mut().zip(p.iter().zip(&s.positions)) {
                *t += (a[0] - b[0]).hypot(a[1] - b[1]);
            }
            cayley_length += crate::cayley_vector::euclid(w, &v);
        }
        prev = Some((s.positions, v));
    }
    PathMeasure {
        cayley_length,
        max_joint_travel: travel.into_iter().fold(0.0, f64::max),
        walk: walk.summary().clone(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cayley_space::Method;
    use crate::realize::Kind;
    use crate::roots::Endpoint;

    /// Three types end at one λ where steps 0 and 1 are flat; the fourth
    /// (010) has no interval. 000 and 100 meet by flipping step 0, 100 and
    /// 110 by flipping step 1: one realization there, so one connected set,
    /// however the walk lists them.
    #[test]
    fn components_meeting_at_an_end_with_several_flat_steps_are_one_set() {
        let flat = vec![Event { step: 0, kind: Kind::Stretched }, Event { step: 1, kind: Kind::Stretched }];
        let top = Endpoint { lambda: 2.0, events: flat.into(), id: 1 };
        let bottom =
            |id: usize| Endpoint { lambda: 1.0, events: vec![Event { step: 2, kind: Kind::Folded }].into(), id };
        let ty = |bits: [bool; 3]| RealizationType(bits.to_vec());
        let interval = |bits, id| OrientedInterval { ty: ty(bits), lower: bottom(id), upper: top.clone() };
        let space = CayleySpace {
            intervals: vec![
                interval([false, false, false], 2),
                interval([true, false, false], 3),
                interval([true, true, false], 4),
            ],
            touches: Vec::new(),
            notes: Vec::new(),
            method: Method::Exact,
            numeric_steps: Vec::new(),
        };
        let c = components(&space);
        // The walk lists {000, 100} and {110}: the one recorded branch point
        // does not join them, the flip at the shared end does.
        assert_eq!(c.list.len(), 2, "{c:#?}");
        assert_eq!(c.connected, vec![0, 0], "{c:#?}");
    }
}
