//! Lazy analysis: the connected component through one realization, found by
//! walking its events (THEORY.md §4) and computing only the types the walk
//! visits, never the 2^n types of the exhaustive sweep in
//! [`crate::cayley_space`](mod@crate::cayley_space).
//!
//! From a realization (τ, λ0) the interval of τ around λ0 is grown both ways
//! by `Walker::next_end`: the first λ at which some step's slack reaches
//! zero. There the flat step's bit flips (the flip rule of
//! [`crate::motion::components`]) and the new type's interval is grown the
//! other way from the shared endpoint, until the walk is back at its start.
//!
//! Finding the next end: the type is realized in [`Jet`]s (every base distance
//! with its slope and curvature, O(n)) at samples chosen from the jets: each
//! gap is as long as the slacks' quadratic Taylor models predicted the last
//! one well (their error grows as the gap cubed), a gap they do not predict
//! is halved, and no gap is longer than the widest of the numeric method's
//! cosine-spaced grid. Between two samples each step's slack is
//! certified to stay positive from its jets: a concave stretch has its
//! minimum at an end, a convex one lies above both end tangents. Only where
//! no certificate holds is the step's own minimum (Newton on the slope) or
//! inflection (bisection on the curvature) located. A sign change is a root,
//! found by safeguarded Newton to full precision; a reading at or below zero
//! within rounding of zero beside a step within rounding of flat (whose
//! vertex f64 knows only to about √ε) is the certifier's to decide
//! (`Walker::noise_below_zero`). Steps are examined in
//! construction order and every root found pulls the gap's far end in, so a
//! step is only examined where the steps before it close.
//!
//! Reuse: consecutive types differ from the flipped step on, and a walk out
//! and back meets types again but for a bit or two. Each type shares its
//! steps before the first differing bit with the types walked recently: a
//! probe at a λ one of them was probed at resumes from its kept positions
//! at that bit (samples move nearer to such λs), and a gap inside one of
//! their intervals examines only the steps not shared (the shared ones close
//! all over it). The guarantee below stands: the reuse changes only what is
//! recomputed and where the samples fall.
//!
//! Guarantee: the numeric method's (see `numeric_roots` in
//! [`crate::cayley_space`](mod@crate::cayley_space)): every end is found unless a gap between samples
//! holds two inflections of one slack; a near-double root is a tangency and is
//! noted. Cost: O(n) per sample (at least 2·samples/π of them per interval
//! visited, more where the jets ask for them), plus O(k) per Newton
//! iteration on step k; nothing is exponential in the depth.

use crate::cayley_space::{CayleySpace, Method, Note, OrientedInterval};
use crate::certify::{At, Certifier, Closes, Sign};
use crate::inthash::IntMap;
use crate::real::{Jet, Real, Slope};
use crate::realize::{Construction, Event, Kind, P2, RealizationType, Unrealizable};
use std::cell::{Cell, RefCell};
use std::collections::VecDeque;
use std::sync::mpsc;

use crate::roots::{
    Endpoint, EndpointIds, Events, Extremum, base_distance_at, between, cmp, cosine_sample, newton, newton_from,
    newton_from_end, newton_seeded, quadratic_root, side_signs,
};
use crate::tolerance;

/// How far the walk may go.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LazyOptions {
    /// No gap between samples is wider than the widest of this many
    /// cosine-spaced samples from an interval end to the edge of the base's range.
    pub samples: usize,
    /// The walk stops (and says so) after this many intervals.
    pub max_intervals: usize,
    /// A scene with at least this many construction steps is walked both
    /// ways from the start at once, on two threads (`usize::MAX`: one walk
    /// always). The same component, and the same numbers on every run, but
    /// not one walk's to the last bit: each end is located from the side
    /// its walk reached it from.
    pub both_ways_from_steps: usize,
}

impl Default for LazyOptions {
    fn default() -> Self {
        // Below it a second walk costs about what it saves: most components
        // of such scenes close within a few intervals, and the two walks
        // each compute the middle one.
        let both_ways_from_steps = tolerance::TWO_THREADS_FROM_STEPS;
        LazyOptions { samples: 32, max_intervals: 1 << 16, both_ways_from_steps }
    }
}

/// What one walk did, counted as it went (for `bench --scaling`): the
/// construction steps it realized (in jets or plain numbers; the
/// certifier's proofs at the ends are not counted) and its Newton root
/// locations.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WalkCounts {
    /// Construction steps of the scene (a full realization places this many).
    pub steps: usize,
    /// Oriented intervals of the component walked.
    pub intervals: usize,
    /// Construction steps realized (placed, or measured at the step asked
    /// about), summed over every realization the walk made.
    pub steps_realized: usize,
    /// Roots located by Newton (a slack's sign change bracketed in a gap).
    pub roots: usize,
    /// Evaluations of the slack those Newton searches made.
    pub newton_evaluations: usize,
}

impl WalkCounts {
    /// Full-length realization equivalents per interval: steps realized / (steps · intervals).
    pub fn realizations_per_interval(&self) -> f64 {
        self.steps_realized as f64 / (self.steps.max(1) * self.intervals.max(1)) as f64
    }

    /// Slack evaluations per root located (0 when no root needed Newton).
    pub fn newton_evals_per_root(&self) -> f64 {
        if self.roots == 0 { 0.0 } else { self.newton_evaluations as f64 / self.roots as f64 }
    }
}

/// The oriented intervals of the component through `(ty, lambda)`, sorted by
/// type then λ, with shared endpoint ids exactly as the exhaustive sweep gives them
/// (so [`crate::motion::components`] on the result finds this component).
/// Errors when the start itself has no realization.
pub fn component_through<T: Real>(
    con: &Construction<T>,
    cert: &Certifier,
    jet: &Construction<Jet<T>>,
    ty: &RealizationType,
    lambda: T,
    options: LazyOptions,
) -> Result<CayleySpace<T>, Unrealizable> {
    component_through_counted(con, cert, jet, ty, lambda, options).map(|(space, _)| space)
}

/// [`component_through`] with what the walk did ([`WalkCounts`]).
pub fn component_through_counted<T: Real>(
    con: &Construction<T>,
    cert: &Certifier,
    jet: &Construction<Jet<T>>,
    ty: &RealizationType,
    lambda: T,
    options: LazyOptions,
) -> Result<(CayleySpace<T>, WalkCounts), Unrealizable> {
    con.realize(lambda, ty)?;
    let mut walker = Walker::new(con, cert, jet, options);
    walker.count_steps(con.steps.len());
    // A start realized within rounding beyond an end of the base's range (a
    // drawing at that end, read at a scale where λ's last bit differs from
    // the range's) starts at the end: beyond it an on-base step has no
    // realization, and the walk would find no end there.
    let lambda = if lambda > walker.range[1] {
        walker.range[1]
    } else if lambda < walker.range[0] {
        walker.range[0]
    } else {
        lambda
    };
    let mut intervals = match walker.isolated_start(ty, lambda) {
        Some(points) => points,
        None => walker.component(ty, lambda),
    };
    // Sorted as the exhaustive sweep sorts, so that the component's traversal
    // starts (and turns) the same way: from its least type's interval, upward.
    intervals.sort_by(|a, b| a.ty.cmp(&b.ty).then(cmp(&a.lower.lambda, &b.lower.lambda)));
    let counts = WalkCounts {
        steps: con.steps.len(),
        intervals: intervals.len(),
        steps_realized: walker.steps_realized.get(),
        roots: walker.roots.get(),
        newton_evaluations: walker.newton_evaluations.get(),
    };
    let mut notes = walker.notes;
    notes.dedup();
    let space = CayleySpace {
        intervals,
        touches: Vec::new(),
        notes,
        method: Method::Numeric { samples: options.samples, tol: 0.0 },
        numeric_steps: (0..con.steps.len()).collect(),
    };
    Ok((space, counts))
}

/// One step's slack of one kind, for one type, along one direction of walk.
#[derive(Clone, Copy)]
struct Along<'b, T> {
    bits: &'b [bool],
    k: usize,
    kind: Kind,
    /// ±1: slopes are taken along the walk.
    dir: T,
}

/// Base-distance jets of every step realized at λ (up to and including the
/// first that cannot close).
#[derive(Clone)]
struct Probe<T> {
    lambda: T,
    d: Vec<Jet<T>>,
}

/// Where a search for the next end stopped.
enum End<T> {
    /// Steps flat at λ.
    Events(T, Vec<Event>),
    /// The type stops being realizable at λ without any step flat (a
    /// degenerate step: its base joints coincide).
    Stuck(T, usize),
}

/// Probes of the types walked recently and of the one being walked, with
/// their joint positions. A type shares the steps before the first bit it
/// differs in with each earlier one (with the one walked last, the steps
/// before its flipped one), so a probe of it at a λ kept for an earlier
/// type realizes only from there on (the walk prefers kept λs for its
/// samples).
struct Kept<T> {
    /// The types walked before the current one, the latest first, each with
    /// the steps it shares with the current one.
    earlier: VecDeque<(Generation<T>, usize)>,
    current: Generation<T>,
    /// Position blocks of dropped probes, for reuse.
    spare: Vec<Vec<P2<Jet<T>>>>,
}

/// The probes of one type.
struct Generation<T> {
    bits: Vec<bool>,
    probes: Vec<KeptProbe<T>>,
}

struct KeptProbe<T> {
    lambda: T,
    d: Vec<Jet<T>>,
    pos: Vec<P2<Jet<T>>>,
}

/// The walk reuses what it learned on this many intervals (types) walked
/// last: a walk out and back shares more with the outward intervals than
/// with the one before it. A bound on the work per probe and per gap.
const RECENT: usize = 16;

/// A sample is moved nearer, down to this fraction of its gap, to a λ an
/// earlier type was probed at ...
const KEPT_SNAP: f64 = 0.3;
/// ... when the types share at least 1/this of their steps.
const KEPT_WORTH: usize = 4;

/// At most this many bytes of joint positions are kept in all (a
/// 1000-step chain's walk in f64 jets keeps about 110 probes of 3000
/// joints), the oldest types' dropped first.
const KEPT_BYTES: usize = 16 << 20;

impl<T: Real> Kept<T> {
    fn new() -> Self {
        Kept {
            earlier: VecDeque::new(),
            current: Generation { bits: Vec::new(), probes: Vec::new() },
            spare: Vec::new(),
        }
    }

    /// Probes of `bits` from now on: the type being walked joins the
    /// earlier ones when `bits` is another.
    fn enter(&mut self, bits: &[bool]) {
        if self.current.bits == bits {
            return;
        }
        let fresh = Generation { bits: bits.to_vec(), probes: Vec::new() };
        let last = std::mem::replace(&mut self.current, fresh);
        self.earlier.push_front((last, 0));
        while self.earlier.len() > RECENT {
            let (oldest, _) = self.earlier.pop_back().expect("more than RECENT");
            self.spare.extend(oldest.probes.into_iter().map(|p| p.pos));
        }
        for (g, shared) in &mut self.earlier {
            *shared = shared_steps(&g.bits, bits);
        }
    }

    /// The kept probe at exactly λ of the earlier type that shares the most
    /// steps with the current one, with that count.
    fn best_at(&self, lambda: T) -> Option<(&KeptProbe<T>, usize)> {
        self.earlier
            .iter()
            .filter_map(|(g, shared)| g.probes.iter().find(|p| p.lambda == lambda).map(|p| (p, *shared)))
            .max_by_key(|&(_, shared)| shared)
    }

    fn keep(&mut self, probe: KeptProbe<T>) {
        let n_joints = probe.pos.len().max(1);
        let room = KEPT_BYTES / std::mem::size_of::<P2<Jet<T>>>();
        let kept = |g: &Generation<T>| g.probes.len();
        let mut total = kept(&self.current) + self.earlier.iter().map(|(g, _)| kept(g)).sum::<usize>();
        while (total + 1) * n_joints > room {
            let Some((oldest, _)) = self.earlier.pop_back() else { break };
            total -= oldest.probes.len();
            self.spare.extend(oldest.probes.into_iter().map(|p| p.pos));
        }
        if (total + 1) * n_joints <= room {
            self.current.probes.push(probe);
        } else {
            self.spare.push(probe.pos);
        }
    }
}

/// How many steps two types share: their bits before the first that differs
/// (realizations of both agree up to there).
fn shared_steps(a: &[bool], b: &[bool]) -> usize {
    a.iter().zip(b).take_while(|(x, y)| x == y).count()
}

/// Steps `0..steps` close on the open λ range (lo, hi), and at lo (hi)
/// when `at_ends[0]` (`[1]`): no step of theirs is flat at that end.
struct Closing<T> {
    steps: usize,
    range: [T; 2],
    at_ends: [bool; 2],
}

impl<T: Real> Closing<T> {
    /// The steps of the walked interval `from` that type `bits` shares (its
    /// bits before the first that differs), with where they close.
    fn shared(from: &OrientedInterval<T>, bits: &[bool]) -> Self {
        let steps = shared_steps(&from.ty.0, bits);
        let clear = |e: &Endpoint<T>| e.events.iter().all(|ev| ev.step >= steps);
        Closing {
            steps,
            range: [from.lower.lambda, from.upper.lambda],
            at_ends: [clear(&from.lower), clear(&from.upper)],
        }
    }

    /// How many steps (from the first) close all over the gap between a and b.
    fn over(&self, a: T, b: T) -> usize {
        let (lo, hi) = if a < b { (a, b) } else { (b, a) };
        let [l, h] = self.range;
        let inside = (lo > l || (lo == l && self.at_ends[0])) && (hi < h || (hi == h && self.at_ends[1]));
        if inside { self.steps } else { 0 }
    }
}

struct Walker<'a, T: Real> {
    con: &'a Construction<T>,
    cert: &'a Certifier,
    jet: &'a Construction<Jet<T>>,
    /// `jet` without curvatures, for the Newton root location of [`Self::locate`]
    /// (value and slope only, the same numbers as `jet`'s: see [`Slope`]).
    slopes: Construction<Slope<T>>,
    options: LazyOptions,
    /// Steps on the base need |r1 − r2| ≤ λ ≤ r1 + r2: the walk never leaves this range.
    range: [T; 2],
    /// The on-base steps flat at each end of `range`.
    range_events: [Vec<Event>; 2],
    coincide: T,
    root_value: T,
    ids: EndpointIds,
    notes: Vec<Note>,
    /// [`Certifier::kinds`] of each step, asked once (each gap asks them all).
    kinds: Vec<&'static [Kind]>,
    /// The probe [`Self::scan_gap`] made at the root it returned last
    /// (the approach to that root ends there: it is not realized twice).
    root_probe: Option<Probe<T>>,
    /// An end located already, with its flat steps: the last gap of the
    /// approach to it ends there, and a sign change of those steps' slacks
    /// in that gap is that end, not a root to locate again.
    known_end: Option<(T, Vec<Event>)>,
    /// The steps the type being walked shares with each interval walked
    /// recently close all over that interval (its walk found no end of
    /// theirs inside it): gaps there examine only the later steps.
    closing: Vec<Closing<T>>,
    /// Counted for [`WalkCounts`].
    steps_realized: Cell<usize>,
    /// Positions reused by every single-slack evaluation (jets) and Newton
    /// evaluation (slopes): a fresh block each time cost a long chain's walk
    /// page faults. Probes take theirs from `kept`.
    scratch: RefCell<Vec<P2<Jet<T>>>>,
    slope_scratch: RefCell<Vec<P2<Slope<T>>>>,
    /// Probes of recent types, with their positions ([`Kept`]).
    kept: RefCell<Kept<T>>,
    roots: Cell<usize>,
    newton_evaluations: Cell<usize>,
}

/// The second walk's endpoint ids start after this (the first walk's never
/// reach it); [`join_walks`] numbers them all afresh.
const OTHER_WALK_IDS: usize = 1 << 40;

/// Where a walk stands: at interval `cur`, about to leave it by its upper
/// (or lower) end.
#[derive(Clone, Copy)]
struct Heading {
    cur: usize,
    leaving_upper: bool,
}

/// What one step of the flip rule did ([`Walker::advance`]).
enum Advance<T> {
    /// Walked one more interval.
    Walked,
    /// Back at this interval of the walk's own (its end shared): the walk
    /// closes when it is the start.
    Closed(usize),
    /// At an interval the other walk has walked.
    Met(Meeting<T>),
    /// A dead end, a degenerate type, or the budget.
    Stopped,
}

/// A walk's arrival at `others[index]` of the other walk: that interval's
/// upper (`upper`) or lower end is `end`, this walk's.
struct Meeting<T> {
    index: usize,
    upper: bool,
    end: Endpoint<T>,
}

/// Where a step of the flip rule enters: type `next` at `end`, the end the
/// walk leaves its interval by (its upper end if `leaving_upper`).
#[derive(Clone)]
struct Entry<T> {
    next: RealizationType,
    end: Endpoint<T>,
    leaving_upper: bool,
}

/// One walk's finished turn, sent to the other ([`Walker::turns`]).
enum Turn<T> {
    /// The start interval's end this walk found first.
    Start(Endpoint<T>),
    /// The interval it walked this turn (final: it did not meet the other
    /// walk there).
    Walked(OrientedInterval<T>),
    /// It stopped.
    Done,
}

/// How many turns a walk of [`Walker::both_ways`] may walk ahead of those
/// it has finished (what the other walk's pace has not yet decided).
const LEAD: usize = 4;

/// A turn walked ahead ([`Walker::turns`]): where it entered (`None`: it
/// stopped before), how many of the other's turns it was checked against,
/// the walk's state at that point, what it did, and the interval it walked.
/// A turn back at an interval of its own shares that interval's end only
/// once it is finished ([`Walker::finish`]).
struct Ahead<T> {
    entry: Option<Entry<T>>,
    checked: usize,
    rewind: Rewind,
    outcome: Advance<T>,
    walked: Option<OrientedInterval<T>>,
}

impl<T> Ahead<T> {
    /// Whether a later meeting with the other walk could still end the
    /// walk at this turn: not where it came back to its own interval (that
    /// comes first, as in lockstep) or met the other walk already.
    fn may_meet(&self) -> Option<&Entry<T>> {
        self.entry.as_ref().filter(|_| !matches!(self.outcome, Advance::Closed(_) | Advance::Met(_)))
    }
}

/// A walk's state where a turn entered, restored where it turns out to
/// meet the other walk: its intervals and notes (their lengths), its counts
/// (steps realized, roots, Newton evaluations) and its certifier's
/// estimated decisions. Caches are not restored: they hold the same
/// numbers whoever computed them.
#[derive(Default)]
struct Rewind {
    intervals: usize,
    notes: usize,
    counts: [usize; 3],
    estimated: usize,
}

/// The lower walk of [`Walker::both_ways`] when it stopped: its
/// intervals (the start first), its meeting with the upward walk, and what
/// it noted and counted.
struct Walked<T> {
    intervals: Vec<OrientedInterval<T>>,
    met: Option<Meeting<T>>,
    notes: Vec<Note>,
    /// Steps realized, roots located, Newton evaluations.
    counts: [usize; 3],
    estimated: usize,
}

/// The component from its two walks, each as its intervals and its meeting
/// with the other, if any: the upward walk's intervals (the start first),
/// then the lower walk's (after its copy of the start) but an interval both
/// walked in their last turn (they met inside it; the upward walk's copy
/// stays). Where a walk met the other, the other's interval takes its end,
/// so that the two share the endpoint as a single walk's neighbours do:
/// the upward walk's meeting first; the lower walk's too unless it is the
/// same junction seen from the other side (each met the other's last
/// interval) or it left from the interval dropped. Endpoint ids are then
/// numbered afresh, in order.
fn join_walks<T: Real>(
    (mut mine, up_met): (Vec<OrientedInterval<T>>, Option<Meeting<T>>),
    (mut theirs, down_met): (Vec<OrientedInterval<T>>, Option<Meeting<T>>),
    coincide: T,
) -> Vec<OrientedInterval<T>> {
    let near = |a: T, b: T| (a - b).abs() <= coincide;
    let same = |a: &OrientedInterval<T>, b: &OrientedInterval<T>| {
        a.ty == b.ty && near(a.lower.lambda, b.lower.lambda) && near(a.upper.lambda, b.upper.lambda)
    };
    let twice = theirs.len() > 1 && mine[1..].iter().any(|iv| same(iv, &theirs[theirs.len() - 1]));
    let set = |iv: &mut OrientedInterval<T>, upper: bool, end: Endpoint<T>| {
        if upper { iv.upper = end } else { iv.lower = end }
    };
    let one_junction = up_met.as_ref().is_some_and(|m| m.index + 2 == theirs.len())
        && down_met.as_ref().is_some_and(|m| m.index + 2 == mine.len());
    if let Some(m) = up_met {
        set(&mut theirs[m.index + 1], m.upper, m.end);
    }
    if let Some(m) = down_met.filter(|_| !one_junction && !twice) {
        set(&mut mine[m.index + 1], m.upper, m.end);
    }
    if twice {
        theirs.pop();
    }
    mine.extend(theirs.into_iter().skip(1));
    renumber(&mut mine);
    mine
}

/// Endpoint ids numbered 1, 2, … in the order they first appear.
fn renumber<T>(intervals: &mut [OrientedInterval<T>]) {
    let mut new_ids: IntMap<usize, usize> = IntMap::default();
    for iv in intervals.iter_mut() {
        for end in [&mut iv.lower, &mut iv.upper] {
            let next = new_ids.len() + 1;
            end.id = *new_ids.entry(end.id).or_insert(next);
        }
    }
}

fn finite<T: Real>(j: &Jet<T>) -> bool {
    j.v.to_f64().is_finite() && j.d.to_f64().is_finite() && j.s.to_f64().is_finite()
}

impl<'a, T: Real> Walker<'a, T> {
    fn new(con: &'a Construction<T>, cert: &'a Certifier, jet: &'a Construction<Jet<T>>, options: LazyOptions) -> Self {
        let mut range = [T::zero(), T::from_f64(f64::INFINITY)];
        let mut limits: [Option<Event>; 2] = [None, None];
        for k in (0..con.steps.len()).filter(|&k| con.on_base(k)) {
            let s = &con.steps[k];
            let (lo, hi) = (Kind::Folded.target(s.r1, s.r2), Kind::Stretched.target(s.r1, s.r2));
            if lo > range[0] && cert.kinds(k).contains(&Kind::Folded) {
                range[0] = lo;
                limits[0] = Some(Event { step: k, kind: Kind::Folded });
            }
            if hi < range[1] {
                range[1] = hi;
                limits[1] = Some(Event { step: k, kind: Kind::Stretched });
            }
        }
        // Other on-base steps flat at the same end (proven, not by value).
        let range_events = [0, 1].map(|side| {
            let Some(first) = limits[side] else { return Vec::new() };
            let others = (0..con.steps.len())
                .filter(|&k| con.on_base(k) && k != first.step)
                .flat_map(|k| cert.kinds(k).iter().map(move |&kind| Event { step: k, kind }));
            let mut events = vec![first];
            events.extend(others.filter(|&e| cert.target_sign(e, first) == Sign::Zero));
            events.sort();
            events
        });
        let scale = T::from_f64(con.scale);
        Walker {
            con,
            cert,
            jet,
            slopes: jet.map(Jet::slope),
            options,
            range,
            range_events,
            coincide: T::from_f64(tolerance::EVENTS_COINCIDE) * scale,
            root_value: T::from_f64(tolerance::ROOT_VALUE) * scale,
            ids: EndpointIds::default(),
            notes: Vec::new(),
            kinds: (0..con.steps.len()).map(|k| cert.kinds(k)).collect(),
            root_probe: None,
            known_end: None,
            closing: Vec::new(),
            steps_realized: Cell::new(0),
            scratch: RefCell::new(Vec::new()),
            slope_scratch: RefCell::new(Vec::new()),
            kept: RefCell::new(Kept::new()),
            roots: Cell::new(0),
            newton_evaluations: Cell::new(0),
        }
    }

    /// Count `steps` construction steps realized.
    fn count_steps(&self, steps: usize) {
        self.steps_realized.set(self.steps_realized.get() + steps);
    }

    /// Every step's base-distance jet of type `bits` at λ (up to the first
    /// that cannot close), from the steps an earlier type walked shares with
    /// it when that type was probed at λ.
    fn probe(&self, bits: &[bool], lambda: T) -> Probe<T> {
        let mut kept = self.kept.borrow_mut();
        kept.enter(bits);
        let mut pos = kept.spare.pop().unwrap_or_default();
        let (d, realized) = match kept.best_at(lambda) {
            // It failed before the types differ: so does this one, there.
            Some((earlier, shared)) if earlier.d.len() <= shared => {
                pos.clone_from(&earlier.pos);
                (earlier.d.clone(), 0)
            }
            Some((earlier, shared)) => {
                pos.clone_from(&earlier.pos);
                let mut d = earlier.d[..shared].to_vec();
                self.jet.resume_distances_in(&mut pos, shared, bits, &mut d);
                let realized = d.len() - shared;
                (d, realized)
            }
            None => {
                let d = self.jet.base_distances_in(&mut pos, Jet::variable(lambda), bits);
                let realized = d.len();
                (d, realized)
            }
        };
        self.count_steps(realized);
        kept.keep(KeptProbe { lambda, d: d.clone(), pos });
        Probe { lambda, d }
    }

    /// Slack of step k for `kind` from its base distance, with the slope
    /// taken along the walk (`dir` = ±1): positive where the step closes.
    fn slack(&self, k: usize, kind: Kind, d: Jet<T>, dir: T) -> Jet<T> {
        let s = &self.con.steps[k];
        let j = kind.slack(s.r1, s.r2, d);
        Jet { v: j.v, d: j.d * dir, s: j.s }
    }

    /// The ways step k can stop closing. With equal sides (r1 = r2) the
    /// folded slack is d ≥ 0 itself: it never goes negative, and d = 0 is a
    /// degenerate step (its base joints coincide), not an end.
    fn kinds(&self, k: usize) -> &'static [Kind] {
        self.kinds[k]
    }

    /// Every step's every way to stop closing ([`Self::kinds`]), in step
    /// order, but for step `except`'s.
    fn questions_except(&self, except: Option<usize>) -> Vec<(usize, Kind)> {
        (0..self.con.steps.len())
            .filter(|&k| Some(k) != except)
            .flat_map(|k| self.kinds(k).iter().map(move |&kind| (k, kind)))
            .collect()
    }

    /// Step k's slack at λ alone (realizing only the steps before it).
    fn slack_at(&self, s: Along<T>, lambda: T) -> Option<Jet<T>> {
        self.count_steps(s.k + 1);
        let d = base_distance_at(self.jet, &mut self.scratch.borrow_mut(), s.bits, s.k, Jet::variable(lambda))?;
        Some(self.slack(s.k, s.kind, d, s.dir))
    }

    /// [`Self::slack_at`]'s value and slope (along the walk) alone, the same
    /// numbers, from a realization without curvatures.
    fn slack_slope_at(&self, s: Along<T>, lambda: T) -> Option<(T, T)> {
        self.count_steps(s.k + 1);
        let d =
            base_distance_at(&self.slopes, &mut self.slope_scratch.borrow_mut(), s.bits, s.k, Slope::variable(lambda))?;
        let st = &self.con.steps[s.k];
        let j = s.kind.slack_value(Slope::constant(st.r1), Slope::constant(st.r2), d);
        Some((j.v, j.d * s.dir))
    }

    /// A start at an isolated point: the steps whose slacks are zero there
    /// to double-double resolution (one at a tangency, several where steps
    /// are flat at once, as at the tangency scene's λ = 7 on base v1–v2)
    /// include, on each side, one proven not to close, as the exhaustive
    /// sweep decides it. The component is that point in every type reached
    /// by flipping flat steps' bits (one realization: a flat step's two
    /// orientations coincide, and later steps do not see its bit). `None`
    /// for any other start, and past 16 flat steps (2^16 types).
    fn isolated_start(&mut self, ty: &RealizationType, lambda: T) -> Option<Vec<OrientedInterval<T>>> {
        let questions = self.questions_except(None);
        let l = lambda.to_f64();
        let at = |x: f64| At { lambda: x, events: &[] };
        let here = self.cert.slack_signs(&ty.0, at(l), &questions);
        let mut flat: Vec<Event> = questions
            .iter()
            .zip(&here)
            .filter(|(_, s)| **s == Sign::Zero)
            .map(|(&(step, kind), _)| Event { step, kind })
            .collect();
        flat.dedup_by_key(|e| e.step);
        if flat.is_empty() || flat.len() > 16 {
            return None;
        }
        let h = tolerance::ISOLATED_SIDE_OFFSET * self.con.scale;
        let fails = |x: f64| flat.iter().any(|e| self.cert.slack_sign(&ty.0, at(x), e.step, e.kind) == Sign::Negative);
        if !(fails(l - h) && fails(l + h)) {
            return None;
        }
        self.notes.push(match flat[..] {
            [event] => Note::Tangency { lambda: l, event, inside: false },
            _ => Note::Coincident { lambda: l, events: flat.clone() },
        });
        let steps: Vec<usize> = flat.iter().map(|e| e.step).collect();
        let p = self.ids.make(lambda, Events::from(flat));
        let point =
            |mask: usize| OrientedInterval { ty: ty.flipped_by_mask(&steps, mask), lower: p.clone(), upper: p.clone() };
        Some((0..1usize << steps.len()).map(point).collect())
    }

    /// The whole component through (ty, λ): its start interval, then the
    /// walk upward from the start's upper end until it closes; an open walk
    /// (a dead end) is continued from the start's lower end as well.
    fn component(&mut self, ty: &RealizationType, lambda: T) -> Vec<OrientedInterval<T>> {
        if self.con.steps.len() >= self.options.both_ways_from_steps {
            return self.both_ways(ty, lambda);
        }
        let p0 = self.probe(&ty.0, lambda);
        let one = T::from_f64(1.0);
        let upper = self.next_end(&ty.0, &p0, one, &[]);
        let lower = self.next_end(&ty.0, &p0, -one, &[]);
        let (upper, lower) = (self.end_point(upper), self.end_point(lower));
        let mut intervals = vec![OrientedInterval { ty: ty.clone(), lower, upper }];
        if !self.walk(&mut intervals, true) {
            self.walk(&mut intervals, false);
        }
        intervals
    }

    fn end_point(&mut self, end: End<T>) -> Endpoint<T> {
        match end {
            End::Events(lambda, events) if !events.is_empty() => {
                if events.len() > 1 {
                    self.notes.push(Note::Coincident { lambda: lambda.to_f64(), events: events.clone() });
                }
                self.ids.make(lambda, Events::from(events))
            }
            End::Events(lambda, _) => self.ids.make(lambda, Events::new()),
            End::Stuck(lambda, step) => {
                let l = lambda.to_f64();
                self.notes.push(Note::Degenerate { lambda: [l, l], step });
                self.ids.make(lambda, Events::new())
            }
        }
    }

    /// Follow the flip rule from the start interval's upper (or lower) end
    /// until the walk returns to the start (`true`) or cannot go on.
    fn walk(&mut self, intervals: &mut Vec<OrientedInterval<T>>, from_upper: bool) -> bool {
        let mut heading = Heading { cur: 0, leaving_upper: from_upper };
        loop {
            match self.advance(intervals, &mut heading) {
                Advance::Walked => {}
                Advance::Closed(j) => return j == 0,
                Advance::Met(_) | Advance::Stopped => return false,
            }
        }
    }

    /// One step of the flip rule from where `heading` points: the next
    /// interval walked (pushed to `intervals`), or why the walk stops there.
    fn advance(&mut self, intervals: &mut Vec<OrientedInterval<T>>, heading: &mut Heading) -> Advance<T> {
        let turn = self.turn_ahead(intervals, heading, &[]);
        Self::finish(turn, intervals)
    }

    /// What a turn did, once it counts: a return to an interval of the
    /// walk's own shares that interval's end now.
    fn finish(turn: Ahead<T>, intervals: &mut [OrientedInterval<T>]) -> Advance<T> {
        if let (Advance::Closed(j), Some(entry)) = (&turn.outcome, turn.entry) {
            Self::share(intervals, *j, entry);
        }
        turn.outcome
    }

    /// The first part of a step of the flip rule: the type it enters
    /// next and where, or why the walk stops before (no flat step, the
    /// budget counting `others_walked` intervals of another walk, no
    /// realizable flip).
    fn enter(
        &mut self,
        intervals: &[OrientedInterval<T>],
        heading: Heading,
        others_walked: usize,
    ) -> Result<Entry<T>, Advance<T>> {
        let Heading { cur, leaving_upper } = heading;
        let e = if leaving_upper { intervals[cur].upper.clone() } else { intervals[cur].lower.clone() };
        if e.events.is_empty() {
            return Err(Advance::Stopped);
        }
        let walked = intervals.len() + others_walked;
        if walked >= self.options.max_intervals {
            self.notes.push(Note::Unresolved {
                lambda: e.lambda.to_f64(),
                step: e.events[0].step,
                why: crate::cayley_space::Unresolved::WalkBudget { intervals: walked },
            });
            return Err(Advance::Stopped);
        }
        // Into the next type on the same side of λ: walk the other way.
        let dir = T::from_f64(if leaving_upper { -1.0 } else { 1.0 });
        let Some(next) = self.flip(&intervals[cur].ty, &e, dir) else {
            return Err(Advance::Stopped);
        };
        Ok(Entry { next, end: e, leaving_upper })
    }

    /// Back at interval `j` already walked: it takes the entry's end (one
    /// endpoint shared).
    fn share(intervals: &mut [OrientedInterval<T>], j: usize, entry: Entry<T>) {
        let end = if entry.leaving_upper { &mut intervals[j].upper } else { &mut intervals[j].lower };
        *end = entry.end;
    }

    /// The first of `walked` that `entry` enters at its own end: one root
    /// computed twice (same type, side and flat steps).
    fn meets(&self, entry: &Entry<T>, walked: &[OrientedInterval<T>]) -> Option<usize> {
        let Entry { next, end: e, leaving_upper } = entry;
        walked.iter().position(|iv| {
            let end = if *leaving_upper { &iv.upper } else { &iv.lower };
            iv.ty == *next && end.events == e.events && (end.lambda - e.lambda).abs() <= self.coincide
        })
    }

    /// The rest of a step of the flip rule: the interval of `entry`'s type from its end.
    fn walk_into(
        &mut self,
        intervals: &mut Vec<OrientedInterval<T>>,
        heading: &mut Heading,
        entry: Entry<T>,
    ) -> Advance<T> {
        let Entry { next, end: e, leaving_upper } = entry;
        let dir = T::from_f64(if leaving_upper { -1.0 } else { 1.0 });
        let p = self.probe(&next.0, e.lambda);
        if let Some(k) = self.degenerate_beside(&next.0, &p, dir) {
            // A type with a step whose base joints coincide turns that
            // vertex freely: the component ends here, as in the sweep.
            let at = e.lambda.to_f64();
            self.notes.push(Note::Degenerate { lambda: [at, at], step: k });
            return Advance::Stopped;
        }
        let recent = intervals.len().saturating_sub(RECENT);
        self.closing =
            intervals[recent..].iter().map(|iv| Closing::shared(iv, &next.0)).filter(|c| c.steps > 0).collect();
        let other = self.next_end(&next.0, &p, dir, &e.events);
        self.closing.clear();
        let other = self.end_point(other);
        let iv = if leaving_upper {
            OrientedInterval { ty: next, lower: other, upper: e }
        } else {
            OrientedInterval { ty: next, lower: e, upper: other }
        };
        intervals.push(iv);
        *heading = Heading { cur: intervals.len() - 1, leaving_upper: !leaving_upper };
        Advance::Walked
    }

    /// [`Self::component`] walked both ways at once on two threads: this
    /// walker from the start's upper end, a second one (with a
    /// [`Certifier::fork`]) from its lower end, each finding that end first. Their
    /// turns count as in lockstep (each walks one interval, then each learns
    /// the other's; [`Self::turns`]), so where they meet, and so every
    /// number, is the same on every run, though neither waits for the other
    /// to walk ahead. A walk stops at an interval the other has walked, as a
    /// single walk stops at one of its own; the two lists are then joined
    /// ([`join_walks`]).
    fn both_ways(&mut self, ty: &RealizationType, lambda: T) -> Vec<OrientedInterval<T>> {
        let (con, jet, options) = (self.con, self.jet, self.options);
        let cert = self.cert.fork();
        std::thread::scope(|scope| {
            let (to_lower, from_upper) = mpsc::channel::<Turn<T>>();
            let (to_upper, from_lower) = mpsc::channel::<Turn<T>>();
            let lower_walk = scope.spawn(move || {
                let mut walker = Walker::new(con, &cert, jet, options);
                walker.ids = EndpointIds::after(OTHER_WALK_IDS);
                let lower = walker.start_end(ty, lambda, false);
                let _ = to_upper.send(Turn::Start(lower.clone()));
                // Without the upper end the other walk failed: its panic is raised at the join.
                let mut intervals = match from_upper.recv() {
                    Ok(Turn::Start(upper)) => vec![OrientedInterval { ty: ty.clone(), lower, upper }],
                    _ => Vec::new(),
                };
                let heading = Heading { cur: 0, leaving_upper: false };
                let met = if intervals.is_empty() {
                    None
                } else {
                    walker.turns(&mut intervals, heading, (&to_upper, &from_upper))
                };
                let counts = [walker.steps_realized.get(), walker.roots.get(), walker.newton_evaluations.get()];
                let estimated = cert.estimated();
                Walked { intervals, met, notes: std::mem::take(&mut walker.notes), counts, estimated }
            });
            let upper = self.start_end(ty, lambda, true);
            let _ = to_lower.send(Turn::Start(upper.clone()));
            let lower = match from_lower.recv() {
                Ok(Turn::Start(lower)) => Some(lower),
                _ => None,
            };
            let mut intervals = Vec::new();
            let mut met = None;
            if let Some(lower) = lower {
                intervals.push(OrientedInterval { ty: ty.clone(), lower, upper });
                let heading = Heading { cur: 0, leaving_upper: true };
                met = self.turns(&mut intervals, heading, (&to_lower, &from_lower));
            }
            drop(to_lower);
            let mut other = lower_walk.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic));
            let [steps, roots, evaluations] = other.counts;
            self.count_steps(steps);
            self.roots.set(self.roots.get() + roots);
            self.newton_evaluations.set(self.newton_evaluations.get() + evaluations);
            self.cert.count_estimated(other.estimated);
            self.notes.append(&mut other.notes);
            join_walks((intervals, met), (other.intervals, other.met), self.coincide)
        })
    }

    /// The start interval's upper (or lower) end, from a probe at λ.
    fn start_end(&mut self, ty: &RealizationType, lambda: T, upper: bool) -> Endpoint<T> {
        let p0 = self.probe(&ty.0, lambda);
        let end = self.next_end(&ty.0, &p0, T::from_f64(if upper { 1.0 } else { -1.0 }), &[]);
        self.end_point(end)
    }

    /// [`Self::walk`] in turns with another walk of the same component
    /// (see [`Self::both_ways`]), with the outcome of turns in lockstep:
    /// turn r meets the other walk at an interval of its turns before r,
    /// and counts them against the budget. Each turn finished so is sent on
    /// `to`; the other's come on `from`. A walk runs up to [`LEAD`] turns
    /// ahead of what it can finish: such a turn is checked against the
    /// other's earlier turns as they come, and where it meets one the walk
    /// is rewound to that meeting ([`Rewind`]), so the outcome, and every
    /// count and note, does not depend on which walk is faster.
    /// The meeting with the other walk, if the walk ends at one.
    fn turns(
        &mut self,
        intervals: &mut Vec<OrientedInterval<T>>,
        mut heading: Heading,
        (to, from): (&mpsc::Sender<Turn<T>>, &mpsc::Receiver<Turn<T>>),
    ) -> Option<Meeting<T>> {
        #[cfg(test)]
        let upward = heading.leaving_upper;
        // The other walk's finished intervals (its turn r is `others[r - 1]`), and whether it stopped.
        let (mut others, mut other_done) = (Vec::new(), false);
        let absorb = |turn: Result<Turn<T>, _>, others: &mut Vec<_>, done: &mut bool| match turn {
            Ok(Turn::Walked(iv)) if !*done => others.push(iv),
            _ => *done = true,
        };
        // Turns walked ahead, oldest first, and how many are finished.
        let mut ahead: VecDeque<Ahead<T>> = VecDeque::new();
        let mut finished = 0;
        loop {
            // Finish the oldest turn once the other's turns before it are known.
            while let Some(turn) = ahead.front() {
                let before = finished; // the other's turns before this one
                if !other_done && others.len() < before {
                    break;
                }
                let seen = others.len().min(before);
                if let Some(entry) = turn.may_meet()
                    && let Some(i) = self.meets(entry, &others[turn.checked..seen])
                {
                    let meeting =
                        Meeting { index: turn.checked + i, upper: entry.leaving_upper, end: entry.end.clone() };
                    self.rewind(&turn.rewind, intervals);
                    let _ = to.send(Turn::Done);
                    return Some(meeting);
                }
                let mut turn = ahead.pop_front().expect("a front turn");
                if let Some(walked) = turn.walked.take() {
                    let _ = to.send(Turn::Walked(walked));
                    finished += 1;
                    continue;
                }
                let _ = to.send(Turn::Done);
                return if let Advance::Met(meeting) = Self::finish(turn, intervals) { Some(meeting) } else { None };
            }
            let ended = ahead.back().is_some_and(|t| !matches!(t.outcome, Advance::Walked));
            let round = finished + ahead.len(); // the other's turns before the next
            // Near the budget, the count of the other's turns must be exact.
            let exact = other_done || others.len() >= round;
            let budget_near = intervals.len() + round >= self.options.max_intervals;
            if !ended && ahead.len() < LEAD && (exact || !budget_near) {
                #[cfg(test)]
                tests::pace(upward);
                let seen = others.len().min(round);
                let turn = self.turn_ahead(intervals, &mut heading, &others[..seen]);
                ahead.push_back(turn);
                while let Ok(turn) = from.try_recv() {
                    absorb(Ok(turn), &mut others, &mut other_done);
                }
            } else {
                absorb(from.recv().map_err(|_| ()), &mut others, &mut other_done);
            }
        }
    }

    /// One step of the flip rule, walked ahead of when it counts
    /// ([`Self::finish`]): against `others`, the other walk's turns known
    /// to come before it ([`Self::turns`]; none for a single walk), keeping
    /// what a later meeting needs.
    fn turn_ahead(
        &mut self,
        intervals: &mut Vec<OrientedInterval<T>>,
        heading: &mut Heading,
        others: &[OrientedInterval<T>],
    ) -> Ahead<T> {
        let stopped = |outcome| Ahead { entry: None, checked: 0, rewind: Rewind::default(), outcome, walked: None };
        let entry = match self.enter(intervals, *heading, others.len()) {
            Ok(entry) => entry,
            Err(stop) => return stopped(stop),
        };
        if let Some(j) = self.meets(&entry, intervals) {
            return Ahead { entry: Some(entry), ..stopped(Advance::Closed(j)) };
        }
        if let Some(index) = self.meets(&entry, others) {
            let (upper, end) = (entry.leaving_upper, entry.end);
            return stopped(Advance::Met(Meeting { index, upper, end }));
        }
        let rewind = Rewind {
            intervals: intervals.len(),
            notes: self.notes.len(),
            counts: [self.steps_realized.get(), self.roots.get(), self.newton_evaluations.get()],
            estimated: self.cert.estimated(),
        };
        let outcome = self.walk_into(intervals, heading, entry.clone());
        // The intervals of one type are disjoint: one that overlaps an
        // earlier interval of its type is that interval reached again (its
        // ends computed twice, apart by more than the rounding `meets` allows).
        if let Some((new, before)) = intervals.split_last().filter(|_| matches!(outcome, Advance::Walked)) {
            let overlaps = |iv: &OrientedInterval<T>| {
                iv.ty == new.ty && iv.lower.lambda < new.upper.lambda && new.lower.lambda < iv.upper.lambda
            };
            if let Some(j) = before.iter().position(overlaps) {
                intervals.pop();
                return Ahead { entry: Some(entry), ..stopped(Advance::Closed(j)) };
            }
        }
        let walked = matches!(outcome, Advance::Walked).then(|| intervals[intervals.len() - 1].clone());
        Ahead { entry: Some(entry), checked: others.len(), rewind, outcome, walked }
    }

    /// Back to where a turn walked ahead met the other walk.
    fn rewind(&mut self, to: &Rewind, intervals: &mut Vec<OrientedInterval<T>>) {
        #[cfg(test)]
        tests::REWINDS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        intervals.truncate(to.intervals);
        self.notes.truncate(to.notes);
        let [steps, roots, evaluations] = to.counts;
        self.steps_realized.set(steps);
        self.roots.set(roots);
        self.newton_evaluations.set(evaluations);
        self.cert.rewind_estimated(to.estimated);
    }

    /// The step of type `bits` whose base joints coincide just beside the
    /// probe `p` (in direction `dir`), proven by the certifier (d zero to
    /// double-double resolution, [`Closes::Degenerate`]) where f64 reads d
    /// within [`tolerance::touch_noise`] of zero; `None` for none. Only
    /// steps with equal sides can be degenerate and still close.
    fn degenerate_beside(&self, bits: &[bool], p: &Probe<T>, dir: T) -> Option<usize> {
        let noise = tolerance::touch_noise(T::UNIT_ROUNDOFF) * self.con.scale;
        let beside = self.beside(p.lambda, dir);
        (0..p.d.len()).find(|&k| {
            self.kinds(k).len() == 1
                && p.d[k].v.to_f64().abs() <= noise
                && self.cert.closes(None, bits, beside.to_f64(), k) == Closes::Degenerate
        })
    }

    /// A λ just beside an end at `lambda`, in direction `dir` (√FEASIBLE of
    /// the scale away): where a type entered there is tried.
    fn beside(&self, lambda: T, dir: T) -> T {
        lambda + dir * T::from_f64(tolerance::FEASIBLE.sqrt() * self.con.scale)
    }

    /// The type the motion continues into at endpoint `e` of `ty`: the flat
    /// step's bit flipped. With several steps flat at once, the first single
    /// flip whose type is realizable just beside `e` in direction `dir`.
    fn flip(&mut self, ty: &RealizationType, e: &Endpoint<T>, dir: T) -> Option<RealizationType> {
        let steps: Vec<usize> = e.events.iter().map(|ev| ev.step).collect();
        if steps.len() == 1 {
            return Some(ty.flipped(steps[0]));
        }
        let beside = self.beside(e.lambda, dir);
        let n = self.con.steps.len();
        let realizable = |t: &RealizationType| {
            self.count_steps(n);
            self.con.realize(beside, t).is_ok()
        };
        // Single flips only, as `motion::components` links them.
        (0..steps.len()).map(|b| ty.flipped(steps[b])).find(|t| realizable(t))
    }

    /// The first end of type `bits`'s interval beyond `from` in direction
    /// `dir`; `entering` are the events the walk came in through at `from`.
    fn next_end(&mut self, bits: &[bool], from: &Probe<T>, dir: T, entering: &[Event]) -> End<T> {
        let far = if dir > T::zero() { self.range[1] } else { self.range[0] };
        let length = (far - from.lambda) * dir;
        if length <= T::zero() {
            let events = self.flat_on_base(from.lambda);
            return End::Events(from.lambda, events);
        }
        let m = self.options.samples.max(4);
        let half = T::from_f64(0.5);
        let mut near = Probe { lambda: from.lambda, d: from.d.clone() };
        let mut flat_at_near = entering.to_vec();
        let finest = T::from_f64(tolerance::ROOT_STEP * self.con.scale);
        let approach = T::from_f64(tolerance::LAZY_APPROACH * self.con.scale);
        // No gap is longer than the widest of `m` cosine-spaced gaps over the
        // whole stretch (L·sin(π/2m)). The first is the first of them, or,
        // from an entered end (where later steps behave like square roots),
        // the approach ratio times the approach distance (as far out as the
        // grid's geometric approach to it began).
        let ratio = tolerance::APPROACH_RATIO;
        // Within this of an end, the later steps' jets say nothing: such a gap is not refined.
        let last_gap = approach * T::from_f64(ratio);
        let widest = length * T::from_f64((std::f64::consts::PI / (2.0 * m as f64)).sin());
        let first = (cosine_sample(from.lambda, far, 1, m) - from.lambda) * dir;
        let mut step = if entering.is_empty() { first } else { last_gap };
        // Halvings still to visit, nearest last.
        let mut pending: Vec<T> = Vec::new();
        // Probes already made at pending points (kept when a gap is halved).
        let mut made: Vec<Probe<T>> = Vec::new();
        // An end found inside a gap is accepted once the approach to it has
        // been sampled too (later steps behave like square roots next to it,
        // and their jets say nothing there): each sample at most 7/8 of the
        // way to it, down to the approach distance.
        let mut approaching: Option<(T, Vec<Event>)> = None;
        loop {
            let x = match pending.pop() {
                Some(x) => x,
                None if near.lambda == far => break,
                // The next sample is chosen from how well the jets modelled the last gap.
                None => {
                    let target = approaching.as_ref().map_or(far, |(at, _)| *at);
                    let remaining = (target - near.lambda) * dir;
                    let reach =
                        if approaching.is_some() { remaining * T::from_f64(1.0 - 1.0 / ratio) } else { remaining };
                    let advance = if step < reach { step } else { reach };
                    let x = near.lambda + dir * advance;
                    let to_end = approaching.is_some() && remaining <= last_gap;
                    if !to_end && between(x, near.lambda, target) {
                        self.kept_within(near.lambda, dir, advance * T::from_f64(KEPT_SNAP), advance).unwrap_or(x)
                    } else {
                        target
                    }
                }
            };
            if (x - near.lambda) * dir <= T::zero() && approaching.as_ref().is_none_or(|(at, _)| *at != x) {
                // Not beyond the current sample (rounding next to an end):
                // a gap of no width holds no end.
                continue;
            }
            let right = match made.last() {
                Some(p) if p.lambda == x => made.pop().expect("just seen"),
                _ => self.probe(bits, x),
            };
            let mid = (near.lambda + x) * half;
            let gap = (x - near.lambda) * dir;
            let mut ends = Vec::with_capacity(2);
            ends.extend((!entering.is_empty()).then_some(from.lambda));
            ends.extend(approaching.as_ref().map(|(at, _)| *at));
            let known = self.closing.iter().map(|c| c.over(near.lambda, x)).max().unwrap_or(0);
            let model = self.model_error(&near, &right, dir, &ends, known);
            // A gap within the approach distance of an end the walk entered
            // by or is approaching is not refined: there the later steps'
            // jets say nothing (see `tolerance::LAZY_APPROACH`).
            let at_end =
                gap <= last_gap && (approaching.as_ref().is_some_and(|(at, _)| *at == x) || !flat_at_near.is_empty());
            // Halve only while the midpoint is a new number (scenes near the
            // bottom of f64's range run out of them before `finest`).
            if !at_end && gap > finest && between(mid, near.lambda, x) && model.is_none_or(|e| e > 1.0) {
                pending.push(x);
                let quarter = gap * T::from_f64(0.25);
                pending.push(self.kept_within(near.lambda, dir, quarter, gap - quarter).unwrap_or(mid));
                made.push(right);
                continue;
            }
            // The quadratic models' error grows as the gap cubed: aim the
            // next gap at a fraction of the margin. Next to an end the slacks vary on
            // the scale of the distance t to it, so the gap also scales with
            // t (the last gap's error recurs at the same gap/t). At most the
            // approach ratio, and that much after a gap at an end.
            let distance = |l: T| ends.iter().map(|&e| (l - e).abs().to_f64()).fold(f64::INFINITY, f64::min);
            let (t0, t1) = (distance(near.lambda), distance(x));
            let relative = if t0 > 0.0 && t1.is_finite() { t1 / t0 } else { 1.0 };
            let grow = match model {
                _ if at_end => ratio,
                Some(e) => {
                    let aim = (tolerance::LAZY_MODEL_AIM / e.max(f64::MIN_POSITIVE)).cbrt();
                    (aim * relative).clamp(tolerance::LAZY_MIN_GROWTH, ratio)
                }
                None => 1.0,
            };
            let next = gap * T::from_f64(grow);
            step = if next > widest { widest } else { next };
            self.known_end = approaching.clone().filter(|(at, _)| *at == x);
            let found = self.scan_gap(bits, (&near, &right), dir, &flat_at_near, known);
            let verified = match &approaching {
                // The last gap before the end being approached: rounding may
                // leave its slack a hair positive at the end itself.
                Some((at, _)) if *at == x => found.clone().or(approaching.take()),
                _ => found.clone().filter(|(lambda, _)| (*lambda - near.lambda).abs() <= finest),
            };
            if let Some((lambda, events)) = verified {
                return End::Events(lambda, self.proven_events(bits, lambda, events));
            }
            match found {
                Some((lambda, events)) => {
                    pending.clear();
                    made.clear();
                    // The root's own probe waits at the bottom of the stack, for the last gap.
                    made.extend(self.root_probe.take().filter(|p| p.lambda == lambda));
                    approaching = Some((lambda, events));
                    continue;
                }
                None if right.d.len() < self.con.steps.len() => {
                    // The prefix fails at x with no step flat before it.
                    return End::Stuck(x, right.d.len().saturating_sub(1));
                }
                None => {}
            }
            near = right;
            flat_at_near.clear();
        }
        // Unreachable in exact arithmetic: the base range ends with a step flat.
        End::Events(far, self.flat_on_base(far))
    }

    /// The farthest λ an earlier type was probed at that lies `lo` to `hi`
    /// beyond `from` in direction `dir`, among the types that share enough
    /// steps with the one being walked for a probe there to pay for the
    /// shorter gap.
    fn kept_within(&self, from: T, dir: T, lo: T, hi: T) -> Option<T> {
        let kept = self.kept.borrow();
        let n = self.con.steps.len();
        let ahead = |p: &&KeptProbe<T>| {
            let t = (p.lambda - from) * dir;
            t >= lo && t <= hi
        };
        kept.earlier
            .iter()
            .filter(|(_, shared)| shared * KEPT_WORTH >= n)
            .flat_map(|(g, _)| g.probes.iter().filter(ahead).map(|p| p.lambda))
            .max_by(|a, b| cmp(&((*a - from) * dir), &((*b - from) * dir)))
    }

    /// How well the gap is sampled: the largest error of a slack's
    /// quadratic Taylor model from either end of the gap in predicting its
    /// value at the other, in units of [`tolerance::MODEL_MARGIN`] of the
    /// slack's size there; `None` when some slack is not certified. The
    /// gap is well sampled at 1 or less. The certificates of [`Self::search`]
    /// read the shape of a slack from its curvature at the two ends; that
    /// holds when the gap is short against the slack's variation, which this
    /// checks (a slack that dips to zero between two samples with the
    /// curvature of one sign at both ends fails it). A sign change needs no
    /// model: the root is bracketed, and steps after it are not examined.
    ///
    /// Next to an end where a step is flat (`ends`: the end the walk entered
    /// by, the end it approaches), the later steps behave like square roots
    /// of the distance t to it: there a slack may be modelled as quadratic
    /// in √t instead (a + b√t + ct, which has no inflection either), and the
    /// better of the models counts.
    fn model_error(&self, near: &Probe<T>, right: &Probe<T>, dir: T, ends: &[T], known: usize) -> Option<f64> {
        let half = T::from_f64(0.5);
        let length = (right.lambda - near.lambda) * dir;
        let coarse = T::from_f64(tolerance::WELL_SAMPLED_COARSE * self.con.scale);
        // Distances t to each end at the gap's two ends, with their square
        // roots (the same for every slack), if the gap lies on one side of it.
        let beside: Vec<[(T, T); 2]> = ends
            .iter()
            .filter(|&&e| !between(e, near.lambda, right.lambda))
            .map(|&e| ((near.lambda - e).abs(), (right.lambda - e).abs()))
            .filter(|&(t0, t1)| t0 > T::zero() && t1 > T::zero())
            .map(|(t0, t1)| [(t0, t0.sqrt()), (t1, t1.sqrt())])
            .collect();
        let n = near.d.len().min(right.d.len());
        let mut worst = 0.0f64;
        for k in known..n {
            for &kind in self.kinds(k) {
                let (s0, s1) = (self.slack(k, kind, near.d[k], dir), self.slack(k, kind, right.d[k], dir));
                if s1.v <= T::zero() {
                    return Some(worst);
                }
                if !(finite(&s0) && finite(&s1)) {
                    continue;
                }
                let margin = T::from_f64(tolerance::MODEL_MARGIN)
                    * half
                    * ((if s0.v > T::zero() { s0.v } else { T::zero() }) + s1.v);
                let mut misfit = quadratic_misfit(s0, s1, length);
                for &[end0, end1] in &beside {
                    let m = root_misfit(s0, s1, end0, end1);
                    if m < misfit {
                        misfit = m;
                    }
                }
                // (A NaN misfit is no evidence either way.)
                if misfit > margin {
                    return Some(f64::INFINITY);
                }
                worst = worst.max((misfit / margin).to_f64());
                // An uncertified slack is refined by samples of all steps at
                // once rather than by its own search, down to a short gap.
                if length > coarse && certify(s0, s1, length) != Shape::NoRoot {
                    return None;
                }
            }
        }
        Some(worst)
    }

    /// The on-base steps flat at λ when λ is an end of the base's range.
    fn flat_on_base(&self, lambda: T) -> Vec<Event> {
        (0..2).find(|&side| self.range[side] == lambda).map(|side| self.range_events[side].clone()).unwrap_or_default()
    }

    /// The steps flat at an end found at λ through `events`, proven: a
    /// step whose slack is negative there failed first (its root and the
    /// found one are closer than f64 resolves), so the end is that step's;
    /// every step whose slack is zero to double-double resolution is flat
    /// there too (a non-generic end). Steps whose ends each read the
    /// other's slack below zero (ends closer than the decisions resolve)
    /// are flat there together, once each has been tried.
    fn proven_events(&self, bits: &[bool], lambda: T, mut events: Vec<Event>) -> Vec<Event> {
        let mut tried: Vec<Event> = Vec::new();
        for _ in 0..self.con.steps.len() {
            let first = events[0];
            tried.push(first);
            // The flat step's own slacks are zero there by construction (no
            // ball proves that): not asked.
            let questions = self.questions_except(Some(first.step));
            let at = At { lambda: lambda.to_f64(), events: &[first] };
            let signs = self.cert.slack_signs(bits, at, &questions);
            let candidates = questions.iter().zip(&signs).map(|(&(step, kind), &s)| (Event { step, kind }, s));
            let failing = candidates.clone().filter(|(_, s)| *s == Sign::Negative).map(|(e, _)| e);
            if let Some(e) = failing.clone().find(|e| !tried.contains(e)) {
                events = vec![e];
                continue;
            }
            events = vec![first];
            events.extend(failing);
            events.extend(candidates.filter(|(_, s)| *s == Sign::Zero).map(|(e, _)| e));
            break;
        }
        events.sort();
        events.dedup_by_key(|e| e.step);
        events
    }

    /// The first end in the gap (near, right] between two samples, if any.
    fn scan_gap(
        &mut self,
        bits: &[bool],
        (near, right): (&Probe<T>, &Probe<T>),
        dir: T,
        flat_at_near: &[Event],
        known: usize,
    ) -> Option<(T, Vec<Event>)> {
        // Once a root is found, the gap ends there: later steps are examined up to it.
        let mut shrunk: Option<Probe<T>> = None;
        let mut events: Vec<Event> = Vec::new();
        // The plain sign change predicted first (from the slopes at the far
        // end) is located first: the other steps are then examined up to
        // it, and most never need a root of their own.
        let first = self.first_crossing(bits, near, right, dir, flat_at_near, known);
        // The step (and kind) whose root the gap ends at: steps after it behave
        // like square roots there.
        let mut ends_at: Option<(usize, usize)> = None;
        let noise = tolerance::touch_noise(T::UNIT_ROUNDOFF) * self.con.scale;
        if let Some((k, i)) = first {
            let kind = self.kinds(k)[i];
            let s1 = self.slack(k, kind, right.d[k], dir);
            let s0 = self.slack(k, kind, near.d[k], dir);
            let root = self.crossing(Along { bits, k, kind, dir }, (near.lambda, s0), (right.lambda, s1));
            events = vec![Event { step: k, kind }];
            shrunk = Some(if root == right.lambda { right.clone() } else { self.probe(bits, root) });
            ends_at = Some((k, i));
        }
        for k in known..self.con.steps.len() {
            let far = shrunk.as_ref().unwrap_or(right);
            if k >= far.d.len() || k >= near.d.len() {
                break; // the prefix fails with no step flat: the caller reports it
            }
            for (i, &kind) in self.kinds(k).iter().enumerate() {
                if first == Some((k, i)) {
                    continue;
                }
                let far = shrunk.as_ref().unwrap_or(right);
                let s0 = self.slack(k, kind, near.d[k], dir);
                let s1 = self.slack(k, kind, far.d[k], dir);
                let entering = flat_at_near.contains(&Event { step: k, kind });
                // Past a root found in this gap, later steps behave like square
                // roots at its end: only their values count here (the caller
                // samples the approach to that root).
                let s1 = if ends_at.is_some_and(|e| (k, i) > e) { Jet { d: T::from_f64(f64::NAN), ..s1 } } else { s1 };
                // A reading at or below zero that is only f64's rounding beside
                // a nearly flat earlier step, with the other end positive, is no root.
                let noisy = |p: &Probe<T>, s: &Jet<T>| s.v <= T::zero() && self.noise_below_zero(bits, p, k, kind);
                let (noisy0, noisy1) = (!entering && noisy(near, &s0), noisy(far, &s1));
                let (positive0, positive1) = (noisy0 || s0.v > T::zero(), noisy1 || s1.v > T::zero());
                if (noisy0 || noisy1) && positive0 && positive1 {
                    continue;
                }
                // At a root already found in this gap, a reading just below
                // zero may be only the rounding of the lengths to f64 (a touch
                // or an event coincident in the lengths as written): the
                // certifier decides there, at that end. (A reading of exactly
                // zero is that end's own: `first_root` keeps it coincident.)
                if let (Some(end), Some(&found)) = (&shrunk, events.first())
                    && s0.v > T::zero()
                    && s1.v < T::zero()
                    && s1.v.to_f64() >= -noise
                {
                    let at = At { lambda: end.lambda.to_f64(), events: &[found] };
                    match self.cert.slack_sign(bits, at, k, kind) {
                        Sign::Zero => {
                            events.push(Event { step: k, kind });
                            continue;
                        }
                        Sign::Positive => continue,
                        _ => {}
                    }
                }
                let along = Along { bits, k, kind, dir };
                let Some(root) = self.first_root(along, (near.lambda, s0), (far.lambda, s1), entering) else {
                    continue;
                };
                let event = Event { step: k, kind };
                if shrunk.is_some() && (root - far.lambda).abs() <= self.coincide {
                    events.push(event);
                } else {
                    events = vec![event];
                    // A root at the gap's far end has its probe there already.
                    shrunk = Some(if root == right.lambda { right.clone() } else { self.probe(bits, root) });
                    ends_at = Some((k, i));
                }
            }
        }
        let found = shrunk.as_ref().map(|p| (p.lambda, events));
        self.root_probe = shrunk;
        found
    }

    /// The step and kind (its index in [`Self::kinds`]) whose slack changes
    /// sign in the gap (near, right] first as predicted by a Newton step back
    /// from `right` (or the chord where that leaves the gap), among the
    /// plain sign changes: positive just beyond `near`, negative at `right`
    /// and not rounding at a tangency. `None` without one.
    fn first_crossing(
        &self,
        bits: &[bool],
        near: &Probe<T>,
        right: &Probe<T>,
        dir: T,
        flat_at_near: &[Event],
        known: usize,
    ) -> Option<(usize, usize)> {
        let length = (right.lambda - near.lambda) * dir;
        let n = near.d.len().min(right.d.len());
        let mut best: Option<((usize, usize), T)> = None;
        for k in known..n {
            for (i, &kind) in self.kinds(k).iter().enumerate() {
                let s1 = self.slack(k, kind, right.d[k], dir);
                if s1.v.partial_cmp(&T::zero()) != Some(std::cmp::Ordering::Less)
                    || self.rounding_at_tangency(s1)
                    || self.noise_below_zero(bits, right, k, kind)
                {
                    continue;
                }
                let s0 = self.slack(k, kind, near.d[k], dir);
                if !self.closes_beyond(s0, flat_at_near.contains(&Event { step: k, kind })) {
                    return None; // a root at `near` itself: the ordinary scan finds it
                }
                let back = length - s1.v / s1.d;
                let chord = if s0.v > T::zero() { length * s0.v / (s0.v - s1.v) } else { T::zero() };
                let at = if back > T::zero() && back < length { back } else { chord };
                if best.as_ref().is_none_or(|(_, b)| at < *b) {
                    best = Some(((k, i), at));
                }
            }
        }
        best.map(|(e, _)| e)
    }

    /// The root of a slack positive at a and negative at b: b itself when
    /// it is the end the walk approaches and this step is flat there
    /// ([`Self::known_end`]), else located by [`Self::locate`].
    fn crossing(&self, along: Along<T>, (a, s0): (T, Jet<T>), (b, s1): (T, Jet<T>)) -> T {
        let event = Event { step: along.k, kind: along.kind };
        let known = self.known_end.as_ref().is_some_and(|(at, events)| *at == b && events.contains(&event));
        if known { b } else { self.locate(along, (a, s0), (b, s1)) }
    }

    /// The first λ in (a, b] (walking in `dir`) where step k's slack for
    /// `kind` becomes negative; `s0`, `s1` are the slack jets at a and b with
    /// slopes along the walk. `entering`: the slack is zero at a by
    /// construction and grows into the gap.
    fn first_root(&mut self, along: Along<T>, (a, s0): (T, Jet<T>), (b, s1): (T, Jet<T>), entering: bool) -> Option<T> {
        let zero = T::zero();
        // Entered at a place where an earlier step is flat too, d_k behaves
        // like a square root there (no finite slope): monotone over the
        // gap, so the far end's sign is the sign just beyond a (Peaucellier
        // on base B–D, entering ---- at λ = 6, where three steps are flat).
        let monotone_from_end = entering && !finite(&s0) && s1.v > zero;
        if !monotone_from_end && !self.closes_beyond(s0, entering) {
            return Some(a);
        }
        if s1.v <= zero && self.rounding_at_tangency(s1) {
            // A touch (or rounding at one): not an end.
        } else if s1.v == zero {
            return Some(b);
        } else if s1.v < zero {
            return Some(self.crossing(along, (a, s0), (b, s1)));
        }
        let clamp = |s: Jet<T>| Jet { v: if s.v < zero { zero } else { s.v }, ..s };
        let (s0, s1) = (clamp(s0), clamp(s1));
        if !(finite(&s0) && finite(&s1)) {
            // Next to an end where an earlier step is flat, d_k behaves like
            // a square root (monotone): a sign change is all there is to find.
            return None;
        }
        self.search(along, (a, s0), (b, s1), 0)
    }

    /// A slack a few rounding errors below zero where it is nearly tangent
    /// (its quadratic model's extremum, −s′²/2s″, is within that rounding of
    /// zero) cannot be told from a touch: rounding, not a crossing. A double
    /// root is only located to about √ε, and counting such noise as two
    /// crossings would split an interval at a tangency.
    fn rounding_at_tangency(&self, s: Jet<T>) -> bool {
        let noise = T::from_f64(tolerance::TANGENCY_NOISE_ULPS * T::UNIT_ROUNDOFF * self.con.scale);
        finite(&s) && s.v >= -noise && s.d * s.d <= T::from_f64(2.0) * s.s.abs() * noise
    }

    /// Whether step k's slack for `kind` reads at or below zero at probe `p`
    /// only through rounding: a step k depends on is within
    /// [`tolerance::touch_noise`] of flat there (its vertex, and every joint
    /// built on it, is then known only to about √ε), the slack is within
    /// that of zero, and the certifier finds it positive at p. Such a
    /// reading is no end (Peaucellier on base O–P, where a rhombus touches
    /// stretched at λ = 4 and the next step's slack reads 0 beside it).
    fn noise_below_zero(&self, bits: &[bool], p: &Probe<T>, k: usize, kind: Kind) -> bool {
        let noise = tolerance::touch_noise(T::UNIT_ROUNDOFF) * self.con.scale;
        let near_zero = |j: usize, kind: Kind| {
            let s = &self.con.steps[j];
            p.d.get(j).is_some_and(|d| kind.slack_value(s.r1, s.r2, d.v).to_f64().abs() <= noise)
        };
        let nearly_flat = |j: usize| self.kinds(j).iter().any(|&kj| near_zero(j, kj));
        near_zero(k, kind)
            && (0..k).any(nearly_flat)
            && self.con.ancestors(k).iter().enumerate().any(|(j, &read)| read && nearly_flat(j))
            && self.cert.slack_sign(bits, At { lambda: p.lambda.to_f64(), events: &[] }, k, kind) == Sign::Positive
    }

    /// Whether a slack with jet `s` at a (slope along the walk) is positive
    /// just beyond a. At or just below zero (to [`tolerance::ROOT_VALUE`], or
    /// when the walk entered through this step) the slope decides, or at a
    /// tangency the curvature: an isolated point has its slack negative on
    /// both sides.
    fn closes_beyond(&self, s: Jet<T>, entering: bool) -> bool {
        let zero = T::zero();
        if s.v > zero {
            return true;
        }
        if s.v < -self.root_value && !entering {
            return false;
        }
        if self.rounding_at_tangency(s) { s.s > zero } else { side_signs(s.d, || s.s).1 > 0 }
    }

    /// Roots of a slack positive at both ends of [a, b], from its jets.
    fn search(&mut self, along: Along<T>, (a, s0): (T, Jet<T>), (b, s1): (T, Jet<T>), depth: u32) -> Option<T> {
        match certify(s0, s1, (b - a) * along.dir) {
            Shape::NoRoot => None,
            Shape::Convex => self.through_minimum(along, a, b),
            Shape::Inflection => {
                // Halve: each half is certified or halved again.
                let c = (a + b) / T::from_f64(2.0);
                let sc = self.slack_at(along, c)?;
                if depth >= tolerance::ROOT_MAX_SPLITS || !finite(&sc) || !between(c, a, b) {
                    return self.through_minimum(along, a, b);
                }
                if sc.v <= T::zero() {
                    return Some(self.locate(along, (a, s0), (c, sc)));
                }
                self.search(along, (a, s0), (c, sc), depth + 1)
                    .or_else(|| self.search(along, (c, sc), (b, s1), depth + 1))
            }
        }
    }

    /// The slack's minimum between a and b decides: above zero no root; at
    /// zero (to [`tolerance::ROOT_VALUE`]) a tangency inside the interval;
    /// below zero the first root is before the minimum.
    fn through_minimum(&mut self, along: Along<T>, a: T, b: T) -> Option<T> {
        let Along { k, kind, dir, .. } = along;
        let zero = T::zero();
        let slope = |this: &Self, x: T| this.slack_at(along, x);
        let (Some(sa), Some(sb)) = (slope(self, a), slope(self, b)) else { return None };
        if !(sa.d < zero && sb.d > zero) {
            return None;
        }
        // The slope (along the walk) goes from negative to positive: Newton on −slope.
        let m = newton(a, b, |x| slope(self, x).map(|s| (-s.d, -s.s * dir)));
        let sm = slope(self, m)?;
        // Near zero the f64 value says nothing: the certifier decides the sign there.
        // (An f64 value of exactly zero proves nothing either.)
        let extremum = match Extremum::of(sm.v, self.root_value) {
            Extremum::Touch { exact } => {
                match self.cert.slack_sign(along.bits, At { lambda: m.to_f64(), events: &[] }, k, kind) {
                    Sign::Positive => Extremum::Above,
                    Sign::Negative => {
                        self.roots.set(self.roots.get() + 1);
                        return Some(self.cert.slack_root_between(along.bits, (k, kind), [a, m]));
                    }
                    _ => Extremum::Touch { exact },
                }
            }
            other => other,
        };
        match extremum {
            Extremum::Above => None,
            Extremum::Touch { exact } => {
                let event = Event { step: k, kind };
                self.notes.push(Note::Tangency { lambda: m.to_f64(), event, inside: true });
                if !exact {
                    self.notes.push(Note::near_double_root(m.to_f64(), k));
                }
                // Beyond a touch a later step may degenerate (the vertex the
                // touching step places switches sides there): the interval
                // ends at the touch, as the sweep splits its runs there.
                // (On Peaucellier's base A–B, type ++-+ below λ = √19, where D lands on B.)
                let at = self.probe(along.bits, m);
                self.degenerate_beside(along.bits, &at, dir).map(|_| m)
            }
            Extremum::Below => Some(self.locate(along, (a, sa), (m, sm))),
        }
    }

    /// The root of step k's slack between a (jet `sa`, value > 0) and b
    /// (≤ 0), where both jets (slopes along the walk) are already known:
    /// Newton starts at the root of the quadratic model at b (about the gap
    /// cubed from the true root). Without a slope at b (b is an end where
    /// an earlier step is flat, and the slack goes as √|λ − b| there)
    /// Newton runs in u = √|λ − b| ([`newton_from_end`]) from the root of
    /// the quadratic in u through b's value and a's value and slope.
    fn locate(&self, along: Along<T>, (a, sa): (T, Jet<T>), (b, sb): (T, Jet<T>)) -> T {
        let f = |x| self.slack_slope_at(along, x).map(|(v, d)| (v, d * along.dir));
        let run = if finite(&sb) {
            // The quadratic model at b (slope in λ) puts its root about the
            // gap cubed from the true one: Newton starts there, a step
            // ahead of Newton from b.
            let step = quadratic_root(sb.v, sb.d * along.dir, T::from_f64(0.5) * sb.s);
            match step.map(|s| b + s).filter(|&x| between(x, a, b)) {
                Some(x) => newton_from(a, b, x, f),
                None => newton_seeded(a, b, Some((b, sb.v, sb.d * along.dir)), f),
            }
        } else {
            // In u = √|λ − b| the slack is smooth: h(u) = h0 + p·u + q·u²
            // through h(0) = sb.v and a's value and slope (dλ/du = 2u·sign).
            let (h0, ha) = (sb.v, sa.v);
            let (two, span) = (T::from_f64(2.0), a - b);
            let width = span.abs().sqrt();
            let sign = if span > T::zero() { T::from_f64(1.0) } else { T::from_f64(-1.0) };
            let m = sa.d * along.dir * two * sign * width;
            let q = (h0 + m * width - ha) / (width * width);
            let p = m - two * q * width;
            let quadratic = quadratic_root(h0, p, q).filter(|_| finite(&sa));
            // Else the line through the two values.
            let linear = width * h0 / (h0 - ha);
            let u = quadratic.filter(|&u| u > T::zero() && u < width).unwrap_or(linear);
            newton_from_end(a, b, b + sign * u * u, f)
        };
        self.roots.set(self.roots.get() + 1);
        self.newton_evaluations.set(self.newton_evaluations.get() + run.evaluations);
        run.root
    }
}

/// What the jets at the two ends of a gap say about a slack positive at both.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Shape {
    /// It stays positive: concave (its minimum is at an end), monotone, or
    /// above its end tangents.
    NoRoot,
    /// Convex with an inside minimum that the tangents cannot place above zero.
    Convex,
    /// Its curvature changes sign and the bounds do not decide.
    Inflection,
}

/// How far a slack's quadratic Taylor models from each end of a gap of
/// `length` miss its value at the other end (jets `s0`, `s1`, slopes along
/// the gap): the larger miss.
fn quadratic_misfit<T: Real>(s0: Jet<T>, s1: Jet<T>, length: T) -> T {
    let half = T::from_f64(0.5);
    let ahead = s0.v + s0.d * length + half * s0.s * length * length;
    let back = s1.v - s1.d * length + half * s1.s * length * length;
    let (e1, e0) = ((ahead - s1.v).abs(), (back - s0.v).abs());
    if e1 > e0 || e0.to_f64().is_nan() { e1 } else { e0 }
}

/// [`quadratic_misfit`] of the models in u = √t, t the distance to an end
/// (t0, t1 > 0 at the gap's ends, on one side of it, each given with its
/// u = √t): with t′ = ±1 along the gap, s_u = 2u·s_t and s_uu = 4t·s_tt + 2s_t.
fn root_misfit<T: Real>(s0: Jet<T>, s1: Jet<T>, (t0, u0): (T, T), (t1, u1): (T, T)) -> T {
    let (two, four) = (T::from_f64(2.0), T::from_f64(4.0));
    // Slopes in t: along the gap when it leads away from the end.
    let away = if t1 > t0 { T::from_f64(1.0) } else { T::from_f64(-1.0) };
    let in_u = |s: Jet<T>, t: T, u: T| {
        let st = s.d * away;
        Jet { v: s.v, d: two * u * st, s: four * t * s.s + two * st }
    };
    quadratic_misfit(in_u(s0, t0, u0), in_u(s1, t1, u1), u1 - u0)
}

/// Certify a slack over a gap of `length` from its jets `s0`, `s1` at the
/// ends (slopes along the gap), assuming at most one inflection inside:
/// a convex stretch lies above its tangents, a concave one above its chord.
fn certify<T: Real>(s0: Jet<T>, s1: Jet<T>, length: T) -> Shape {
    let zero = T::zero();
    let (convex0, convex1) = (s0.s >= zero, s1.s >= zero);
    if !convex0 && !convex1 {
        return Shape::NoRoot;
    }
    if convex0 && convex1 {
        if s0.d >= zero || s1.d <= zero {
            return Shape::NoRoot; // monotone toward the higher end
        }
        // Both tangents lie below a convex function; they cross at t.
        let t = (s1.v - s1.d * length - s0.v) / (s0.d - s1.d);
        return if s0.v + s0.d * t > zero { Shape::NoRoot } else { Shape::Convex };
    }
    // One inflection: the convex part lies above the tangent at its end,
    // the concave part above its end values.
    // A tangent that rises away from its end (s0 may be zero at an end the
    // walk entered by) keeps the convex part positive beyond that end.
    let positive =
        if convex0 { s0.d > zero || s0.v + s0.d * length > zero } else { s1.d < zero || s1.v - s1.d * length > zero };
    if positive { Shape::NoRoot } else { Shape::Inflection }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicU8, AtomicUsize, Ordering};

    /// Which walk of [`Walker::both_ways`] a test slows down (1: the upward
    /// one, 2: the lower), so that the other runs ahead of it.
    static SLOW_WALK: AtomicU8 = AtomicU8::new(0);
    /// Turns walked ahead that met the other walk and were undone.
    pub(super) static REWINDS: AtomicUsize = AtomicUsize::new(0);

    /// Before each turn of a walk: a pause when the test slows that walk.
    pub(super) fn pace(upward: bool) {
        if SLOW_WALK.load(Ordering::Relaxed) == if upward { 1 } else { 2 } {
            std::thread::sleep(std::time::Duration::from_millis(3));
        }
    }

    /// A chain of `steps` four-cycles, each carried by the one before (as
    /// `caymos generate chain`, which lives in the binary's crate).
    fn chain(steps: usize) -> crate::scene::Scene {
        let wobble = |k: usize, s: f64| 0.07 * ((k as f64) * s).sin();
        let mut joints = vec![("P0".to_string(), [0.0, 0.0]), ("Q0".to_string(), [wobble(0, 1.3), 1.0])];
        let mut bars = Vec::new();
        let (mut p, mut q) = ("P0".to_string(), "Q0".to_string());
        for k in 1..=steps {
            let x = k as f64;
            let v = format!("V{k}");
            joints.push((v.clone(), [x - 0.5 + wobble(k, 2.1), 0.42 + wobble(k, 0.7)]));
            bars.extend([(p.clone(), v.clone()), (q.clone(), v.clone())]);
            if k < steps {
                let (p2, q2) = (format!("P{k}"), format!("Q{k}"));
                joints.push((p2.clone(), [x + wobble(k, 1.7), wobble(k, 3.1)]));
                joints.push((q2.clone(), [x + wobble(k, 0.9), 1.0 + wobble(k, 2.3)]));
                bars.extend([
                    (p.clone(), p2.clone()),
                    (v.clone(), p2.clone()),
                    (q.clone(), q2.clone()),
                    (v, q2.clone()),
                ]);
                (p, q) = (p2, q2);
            }
        }
        let bars: Vec<String> = bars.iter().map(|(a, b)| format!("[\"{a}\", \"{b}\"]")).collect();
        let joints: Vec<String> = joints.iter().map(|(n, [x, y])| format!("\"{n}\" = [{x:?}, {y:?}]")).collect();
        let text = format!(
            "name = \"chain\"\nbase = [\"P0\", \"Q0\"]\nground = [\"P0\", \"V1\"]\nbars = [{}]\n[joints]\n{}\n",
            bars.join(", "),
            joints.join("\n")
        );
        crate::scene::parse_scene(&text, "chain", "chain").expect("a chain scene")
    }

    /// What a walk of a scene starts from.
    struct Built {
        linkage: crate::linkage::Linkage,
        dec: crate::decompose::Decomposition,
        con: Construction<f64>,
        jet: Construction<Jet<f64>>,
        drawn: crate::realize::Drawn,
    }

    fn built(scene: crate::scene::Scene) -> Built {
        let linkage = crate::linkage::Linkage::from_scene(&scene);
        let dec = crate::decompose::decompose(&linkage, scene.base.map(|b| b.0)).expect("in class").expect("a base");
        let con = Construction::<f64>::new(&linkage, &dec).expect("a construction");
        let jet = con.convert::<Jet<f64>>();
        let drawn = crate::realize::drawn_realization(&linkage, &dec);
        Built { linkage, dec, con, jet, drawn }
    }

    /// A long chain's component is decided with no estimate: every base
    /// distance is enclosed in its own frame (`hinge`), so the balls stay
    /// about as narrow as the values' real error. Every interval end is
    /// also a proven sign change of its flat step (one both ways of it).
    #[test]
    fn a_long_chain_is_decided_without_estimates() {
        let Built { linkage, dec, con, jet, drawn } = built(chain(300));
        let cert = Certifier::new(&linkage, &dec).expect("a certifier");
        let options = LazyOptions { both_ways_from_steps: usize::MAX, ..LazyOptions::default() };
        let space = component_through(&con, &cert, &jet, &drawn.ty, drawn.lambda, options).expect("realizable");
        assert!(space.intervals.len() >= 4, "{} intervals", space.intervals.len());
        assert_eq!(cert.estimated(), 0, "estimated decisions on a 300-step chain");
        let counts = cert.stage_counts();
        assert!(counts.f64 + counts.double_double > 1000, "{counts:?}");
    }

    /// The two walks of a long component give the same intervals, notes and
    /// counts whichever of them is faster, with or without the budget
    /// stopping them: a walk running ahead and meeting the other is undone
    /// to where lockstep would have stopped it.
    #[test]
    fn both_ways_is_the_same_whichever_walk_is_faster() {
        let Built { linkage, dec, con, jet, drawn } = built(chain(30));
        let rewinds = REWINDS.load(Ordering::Relaxed);
        for max_intervals in [usize::MAX, 5] {
            let options = LazyOptions { both_ways_from_steps: 0, max_intervals, ..LazyOptions::default() };
            let run = |slow: u8| {
                let cert = Certifier::new(&linkage, &dec).expect("a certifier");
                SLOW_WALK.store(slow, Ordering::Relaxed);
                let walked = component_through_counted(&con, &cert, &jet, &drawn.ty, drawn.lambda, options);
                SLOW_WALK.store(0, Ordering::Relaxed);
                let (space, counts) = walked.expect("the drawing realizes");
                (format!("{:?} {:?}", space.intervals, space.notes), counts, cert.estimated())
            };
            let even = run(0);
            assert!(even.1.intervals >= 8 || max_intervals == 5, "a long component: {:?}", even.1);
            assert_eq!(run(1), even, "the upward walk slowed, budget {max_intervals}");
            assert_eq!(run(2), even, "the lower walk slowed, budget {max_intervals}");
        }
        assert!(REWINDS.load(Ordering::Relaxed) > rewinds, "a walk ran ahead and was undone");
    }

    fn end(lambda: f64, step: usize, id: usize) -> Endpoint<f64> {
        Endpoint { lambda, events: Events::one(Event { step, kind: Kind::Stretched }), id }
    }

    fn interval(ty: &str, lower: &Endpoint<f64>, upper: &Endpoint<f64>) -> OrientedInterval<f64> {
        let ty = RealizationType::parse(ty).expect("a type");
        OrientedInterval { ty, lower: lower.clone(), upper: upper.clone() }
    }

    /// The ids of each interval's ends, in order.
    fn ids(intervals: &[OrientedInterval<f64>]) -> Vec<[usize; 2]> {
        intervals.iter().map(|iv| [iv.lower.id, iv.upper.id]).collect()
    }

    /// A loop of four intervals walked both ways: each walk computes the
    /// middle one (its far end from its own side), and each meets the
    /// other's first interval. The lower walk's copy of the middle goes,
    /// with its meeting; the upward walk's far end becomes the lower walk's
    /// interval's end, so every junction has one id.
    #[test]
    fn two_walks_that_both_computed_the_middle_join_into_one_loop() {
        let (l, u) = (end(1.0, 0, 1), end(3.0, 1, 2));
        let start = interval("++", &l, &u);
        let (x, y) = (end(2.0, 0, 3), end(4.0, 1, 4));
        let (a1, middle) = (interval("-+", &x, &u), interval("--", &x, &y));
        let (y_other, x_other) = (end(4.0 + 1e-15, 1, 1 << 40 | 1), end(2.0, 0, 1 << 40 | 2));
        let (b1, middle_other) = (interval("+-", &l, &y_other), interval("--", &x_other, &y_other));
        let up = (vec![start.clone(), a1, middle], Some(Meeting { index: 0, upper: true, end: y.clone() }));
        let down = (vec![start, b1, middle_other], Some(Meeting { index: 0, upper: false, end: x_other }));
        let joined = join_walks(up, down, 1e-9);
        let types: Vec<String> = joined.iter().map(|iv| iv.ty.to_string()).collect();
        assert_eq!(types, ["++", "-+", "--", "+-"]);
        assert_eq!(ids(&joined), [[1, 2], [3, 2], [3, 4], [1, 4]]);
        assert_eq!(joined[3].upper.lambda, 4.0, "the upward walk's end is the shared one");
    }

    /// Two walks whose last intervals meet at one junction, each seeing the
    /// other's: one end there, the upward walk's.
    #[test]
    fn two_walks_meeting_at_one_junction_share_the_upward_walks_end() {
        let (l, u) = (end(1.0, 0, 1), end(3.0, 1, 2));
        let start = interval("++", &l, &u);
        let x = end(2.0, 2, 3);
        let x_other = end(2.0 + 1e-15, 2, 1 << 40 | 1);
        let a1 = interval("-+", &x, &u);
        let b1 = interval("+-", &l, &x_other);
        let up = (vec![start.clone(), a1], Some(Meeting { index: 0, upper: true, end: x.clone() }));
        let down = (vec![start, b1], Some(Meeting { index: 0, upper: false, end: x_other }));
        let joined = join_walks(up, down, 1e-9);
        assert_eq!(ids(&joined), [[1, 2], [3, 2], [1, 3]]);
        assert_eq!(joined[2].upper.lambda, 2.0);
    }
}
