//! Oriented and non-oriented Cayley configuration spaces (THEORY.md §2).
//!
//! A depth-first sweep over type prefixes: the prefix of bits 1..k−1 fixes
//! d_k(λ), and so the set of λ where steps 1..k close. Refining that set by
//! step k needs the roots of d_k(λ) = r1 + r2 (stretched) and
//! d_k(λ) = |r1 − r2| (folded) inside it:
//! - **exact** (LCC): the closed-form candidates of [`crate::invert`], each
//!   checked against this prefix;
//! - **numeric** (any linkage, and the only way for non-LCC steps): a
//!   bracketing search described at `Sweep::numeric_roots`.
//!
//! Each root is classified by the sign of the step's slack on either side,
//! read from its first derivative (or second, at a tangency) computed
//! exactly by forward differentiation ([`Jet`]), not by realizing at
//! midpoints with a tolerance. A gap between roots without any root inside
//! has constant sign, so its interior value decides only when no root
//! bounds it.
//!
//! d_k reads only the bits of the steps that place its base joints (and
//! theirs): prefixes that differ elsewhere refine the same piece into the
//! same pieces, so a refinement is made once and repeated for them
//! (`Sweep::refine_once`; on the Limacon, Jansen and Peaucellier bit 1 is
//! such a bit, and half the sweep's proofs were repeats).
//!
//! Generic over the scalar type so that a double-double run is the reference.

use std::cell::{OnceCell, RefCell};

use crate::certify::{At as Place, Certifier, Closes, Prefixes, Sign};
use crate::complexity::Complexity;
use crate::decompose::Decomposition;
use crate::inthash::IntMap;
use crate::invert::{Candidate, Inverter};
use crate::real::{Jet, Real, Slope};
use crate::realize::{Construction, Event, Kind, P2, RealizationType, bits_word};
use crate::roots::{
    Endpoint, EndpointIds, Events, Extremum, base_distance_at, bisect, cmp, cosine_sample, side_signs, sign,
};
use crate::tolerance;

/// A maximal closed λ-interval on which one realization type exists
/// (`lower == upper` for an isolated point).
#[derive(Clone, Debug, PartialEq)]
pub struct OrientedInterval<T> {
    /// The realization type realizable on the interval.
    pub ty: RealizationType,
    /// The lower end (smaller λ).
    pub lower: Endpoint<T>,
    /// The upper end (larger λ; the same λ for an isolated point).
    pub upper: Endpoint<T>,
}

/// Something special found while computing: a non-generic event, or a place
/// where the method could not decide.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, schemars::JsonSchema))]
#[cfg_attr(feature = "serde", serde(tag = "kind", rename_all = "snake_case"))]
pub enum Note {
    /// Two or more steps flat at the same λ (a possible branch point).
    Coincident {
        /// Where (base length).
        lambda: f64,
        /// The steps flat there.
        events: Vec<Event>,
    },
    /// The slack of a step touches zero without changing sign: an isolated
    /// realizable point (`inside == false`) or a touch inside an interval.
    Tangency {
        /// Where (base length).
        lambda: f64,
        /// The step whose slack touches zero.
        event: Event,
        /// A touch inside an interval (`true`) or an isolated point.
        inside: bool,
    },
    /// Roots or signs that could not be separated at working precision.
    Unresolved {
        /// Where (base length).
        lambda: f64,
        /// The step concerned (serialized from 1).
        #[cfg_attr(feature = "serde", serde(serialize_with = "crate::numbering::step_number"))]
        #[cfg_attr(feature = "serde", schemars(with = "crate::numbering::StepNo"))]
        step: usize,
        /// What could not be separated.
        why: Unresolved,
    },
    /// The base length reaches zero (the base joints coincide).
    ZeroBase {
        /// The step flat at λ = 0 (serialized from 1).
        #[cfg_attr(feature = "serde", serde(serialize_with = "crate::numbering::step_number"))]
        #[cfg_attr(feature = "serde", schemars(with = "crate::numbering::StepNo"))]
        step: usize,
    },
    /// Step `step`'s base joints coincide all along a piece of λ: its vertex
    /// is free to turn (an extra degree of freedom, as in a folded rhombus).
    /// Those types have no realization there.
    Degenerate {
        /// The piece of λ, [from, to].
        lambda: [f64; 2],
        /// The degenerate step (serialized from 1).
        #[cfg_attr(feature = "serde", serde(serialize_with = "crate::numbering::step_number"))]
        #[cfg_attr(feature = "serde", schemars(with = "crate::numbering::StepNo"))]
        step: usize,
    },
}

impl Note {
    /// Two roots or none at λ for step `step`, not separable at the working precision.
    pub fn near_double_root(lambda: f64, step: usize) -> Note {
        Note::Unresolved { lambda, step, why: Unresolved::NearDoubleRoot }
    }
}

/// What could not be decided at working precision ([`Note::Unresolved`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, schemars::JsonSchema))]
#[cfg_attr(feature = "serde", serde(tag = "reason", rename_all = "snake_case"))]
pub enum Unresolved {
    /// The slack's sign on one gap disagrees between its two roots.
    GapSign,
    /// The root search could not separate the inflections of d_k.
    Inflections,
    /// A near-double root: two endpoints or none.
    NearDoubleRoot,
    /// The lazy walk stopped after this many intervals (its budget).
    WalkBudget {
        /// Intervals walked before the budget stopped it.
        intervals: usize,
    },
}

/// How endpoints were found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Method {
    /// Closed form for LCC steps (numeric only where the four-cycle test failed).
    Exact,
    /// The numeric root search for every step, with this many samples per
    /// piece; roots are bisected until their bracket is below `tol` × scale
    /// (0: to full precision).
    Numeric {
        /// Samples per piece of λ (at least 4).
        samples: usize,
        /// Bisection stops at a bracket this wide (× scale); 0: full precision.
        tol: f64,
    },
}

/// A touch inside intervals: in the types that start with `prefix`, the
/// slack of the next step (`event`) touches zero at `lambda` and comes
/// back, so that step is flat there without an interval ending. Its
/// vertex then lies on its base line: a type and the one with that step's
/// bit flipped have the same realization there, a singular place the
/// motion may pass from one into the other (one connected set).
#[derive(Clone, Debug, PartialEq)]
pub struct Touch {
    /// Where (base length).
    pub lambda: f64,
    /// The type bits before the touching step.
    pub prefix: Vec<bool>,
    /// The touching step, flat there.
    pub event: Event,
}

/// The oriented Cayley configuration space: the intervals of every type computed, and what was met on the way.
#[derive(Clone, Debug)]
pub struct CayleySpace<T> {
    /// Sorted by type, then λ.
    pub intervals: Vec<OrientedInterval<T>>,
    /// Touches inside intervals (see [`Touch`]): where a slack is zero
    /// without changing sign, as the sweep decides it (an estimate where the
    /// certifier could not prove the zero, counted among its estimates).
    pub touches: Vec<Touch>,
    /// Non-generic events and undecided places met while computing.
    pub notes: Vec<Note>,
    /// How the endpoints were found.
    pub method: Method,
    /// Steps whose endpoints came from the numeric search.
    pub numeric_steps: Vec<usize>,
}

#[derive(Clone, Debug)]
struct Piece<T> {
    lo: Endpoint<T>,
    hi: Endpoint<T>,
    /// An isolated end point where a later step touches the piece's end
    /// from outside (see `refine`); such a point may only repeat a
    /// realization another type reaches there (see `drop_repeated_touches`).
    touch: bool,
}

/// Where a root sits relative to the piece being refined.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum At {
    Lo,
    Inside,
    Hi,
}

#[derive(Clone, Copy, Debug)]
struct Root<T> {
    lambda: T,
    kind: Kind,
    at: At,
    /// Sign of the slack just left / right of the root: +1 feasible, −1 not, 0 unknown.
    left: i8,
    right: i8,
    /// The slack's value there in `T` (from the jets): far from zero, the
    /// candidate is another branch's root, not this prefix's.
    slack: T,
}

struct Sweep<'a, T: Real> {
    con: &'a Construction<T>,
    cert: &'a Certifier,
    /// `con` in jets, for a curvature (at a tangency) or the numeric
    /// search (built on first use: most exact sweeps need neither).
    jet: OnceCell<Construction<Jet<T>>>,
    /// Per step: closed-form candidates for [stretched, folded], or `None` to search numerically.
    exact: Vec<Option<[Vec<Candidate<T>>; 2]>>,
    samples: usize,
    /// Numeric roots are bisected down to a bracket this wide (scene units).
    root_tol: T,
    ids: EndpointIds,
    notes: Vec<Note>,
    out: Vec<OrientedInterval<T>>,
    /// The certifier's realized prefixes at the places this sweep asks about.
    prefixes: Prefixes,
    /// Joint positions of the last jet realization (reused).
    positions: RefCell<Vec<P2<Jet<T>>>>,
    /// `con` in slopes, for the candidates' slopes: the same numbers as
    /// `jet`'s values and slopes (built on first use: steps on the base
    /// read their jets, cheap there).
    slopes: OnceCell<Construction<Slope<T>>>,
    /// Joint positions of the last slope realization (reused).
    slope_positions: RefCell<Vec<P2<Slope<T>>>>,
    /// Indices into `out` of the isolated end points (`Piece::touch`).
    touches: Vec<usize>,
    /// Touches inside intervals ([`Touch`]).
    inside_touches: Vec<Touch>,
    /// Per step: the type bits its base distance depends on (its
    /// ancestors, [`Construction::ancestors`]) as a word; `None` past 128
    /// steps, or where no other prefix can repeat its refinements.
    depends: Vec<Option<u128>>,
    /// No step places a member (every cluster a step stands on is a bar):
    /// the mirror image of a realization (every bit flipped) has each d_k
    /// of the original, bit for bit (every operation on a coordinate is odd
    /// in the y-coordinates and even in the distances; rounding to nearest
    /// is symmetric), so a prefix's refinements are its mirror's.
    mirrored: bool,
    /// Refinements by all they depend on (see [`RefineKey`]).
    refined: IntMap<RefineKey, Refined<T>>,
}

/// What a refinement of a piece by step k depends on: k, the type bits k
/// depends on (of a prefix or, where [`Sweep::mirrored`], of its mirror
/// image: the smaller word), and the piece (its ends by id, first event and
/// flat steps, and whether it is an isolated point). Two prefixes that
/// differ only in bits step k does not read have the same d_k at every λ,
/// bit for bit, so on the same piece the same roots, proofs and pieces:
/// the second is the first's result, not a second sweep of the same
/// questions.
type RefineKey = (usize, u128, EndKey, EndKey, bool);

/// An end in a [`RefineKey`]: its id, first event (whose bracket the proofs
/// there rest on), and its flat steps by kind, bit i for step i.
type EndKey = (usize, Option<Event>, u128, u128);

/// A refinement's result, and what it added to the sweep's record.
struct Refined<T> {
    pieces: Vec<Piece<T>>,
    notes: Vec<Note>,
    /// Touches inside (λ, event): the same for every prefix it stands for.
    touches: Vec<(f64, Event)>,
    estimated: usize,
}

/// What a sweep knows before it starts: each step's closed-form candidates
/// and the type bits its base distance reads. Built first so that its
/// estimated cost ([`SweepPlan::cost`]) can decide whether to sweep at all.
#[derive(Clone, Debug)]
pub struct SweepPlan<T> {
    method: Method,
    /// Per step: closed-form candidates for [stretched, folded], or `None` to search numerically.
    exact: Vec<Option<[Vec<Candidate<T>>; 2]>>,
    numeric_steps: Vec<usize>,
    /// Per step: the bits of the steps it depends on ([`Construction::ancestors`])
    /// as a word; `None` past 128 steps.
    reads: Vec<Option<u128>>,
}

impl<T: Real> SweepPlan<T> {
    /// The plan for a sweep by `method`: closed-form candidates where the
    /// step is on the base or (exact method) has a carrier, each with the
    /// type bits its roots have where `cert`'s f64 balls prove them (the
    /// sweep asks a prefix only about the candidates it admits).
    pub fn new(
        con: &Construction<T>,
        cert: Option<&Certifier>,
        dec: &Decomposition,
        cx: &Complexity,
        method: Method,
    ) -> Self {
        let balls = cert.map(Certifier::f64_balls);
        let inverter = Inverter::new(con, dec, cx, balls);
        // The same inversion in balls proves its branch decisions; where
        // one is not proven, `T`'s candidates may miss a root (or hold a
        // false one) and the exact stage finds them instead.
        let proving = balls.map(|b| Inverter::new(b, dec, cx, None));
        let candidates = |k: usize, kind: Kind| {
            let s = &con.steps[k];
            // A step on the base is no inversion: its candidates read no balls.
            let b = balls.map(|b| &b.steps[k]).filter(|_| !con.on_base(k));
            let t_ball = b.map(|b| kind.target(b.r1, b.r2));
            let found = inverter.candidates_known(k, kind.target(s.r1, s.r2), t_ball);
            let (Some(proving), Some(t_ball), Some(cert)) = (&proving, t_ball, cert) else { return found };
            let before = proving.decisions().unproven();
            proving.found(k, t_ball);
            if proving.decisions().unproven() == before {
                return found;
            }
            match cert.exact_candidates(cx, k, kind) {
                Some(exact) => exact.into_iter().map(|x| Candidate::unknown(T::from_dd(x))).collect(),
                None => found,
            }
        };
        let mut numeric_steps = Vec::new();
        let exact = (0..con.steps.len())
            .map(|k| {
                let closed_form = con.on_base(k) || (matches!(method, Method::Exact) && cx.carriers[k].is_some());
                if !closed_form {
                    numeric_steps.push(k);
                    return None;
                }
                Some([candidates(k, Kind::Stretched), candidates(k, Kind::Folded)])
            })
            .collect();
        let reads = (0..con.steps.len())
            .map(|k| if con.steps.len() > 128 { None } else { bits_word(&con.ancestors(k)) })
            .collect();
        SweepPlan { method, exact, numeric_steps, reads }
    }

    /// The sweep's estimated cost in realization steps: for each step k
    /// (counting from 1), one question per closed-form candidate and one
    /// per piece (or per sample where the step is searched numerically),
    /// each realizing k steps, asked once per setting of the bits k reads
    /// (other prefixes repeat the answers). An estimate of work, known
    /// before any of it is done: it decides how much to compute, never a
    /// question about the mechanism. Saturates at `f64::INFINITY`.
    pub fn cost(&self) -> f64 {
        let samples = self.samples() as f64;
        (0..self.exact.len())
            .map(|k| {
                let read = self.reads[k].map_or(k as u32, u128::count_ones);
                let questions = match &self.exact[k] {
                    Some([a, b]) => (a.len() + b.len()) as f64 + 1.0,
                    None => samples + 1.0,
                };
                2f64.powi(read as i32) * questions * (k + 1) as f64
            })
            .sum()
    }

    /// Samples per piece of the numeric search.
    fn samples(&self) -> usize {
        match self.method {
            Method::Numeric { samples, .. } => samples.max(4),
            Method::Exact => 32,
        }
    }
}

/// Compute the oriented intervals of every type.
pub fn cayley_space<T: Real>(
    con: &Construction<T>,
    cert: &Certifier,
    dec: &Decomposition,
    cx: &Complexity,
    method: Method,
) -> CayleySpace<T> {
    cayley_space_planned(con, cert, SweepPlan::new(con, Some(cert), dec, cx, method))
}

/// [`cayley_space`] from a plan already made (for its cost).
pub fn cayley_space_planned<T: Real>(con: &Construction<T>, cert: &Certifier, plan: SweepPlan<T>) -> CayleySpace<T> {
    sweep(con, cert, plan, true)
}

/// [`cayley_space_planned`], repeating refinements for prefixes that agree
/// on the bits a step depends on (`reuse`) or refining each afresh.
fn sweep<T: Real>(con: &Construction<T>, cert: &Certifier, plan: SweepPlan<T>, reuse: bool) -> CayleySpace<T> {
    let n = con.steps.len();
    let samples = plan.samples();
    let SweepPlan { method, exact, numeric_steps, reads } = plan;
    let root_tol = match method {
        Method::Numeric { tol, .. } => T::from_f64(tol.max(0.0) * con.scale),
        Method::Exact => T::zero(),
    };
    let mirrored = con.places_no_members();
    let mut sweep = Sweep {
        con,
        cert,
        jet: OnceCell::new(),
        exact,
        samples,
        root_tol,
        ids: EndpointIds::default(),
        notes: Vec::new(),
        out: Vec::new(),
        prefixes: Prefixes::default(),
        positions: RefCell::new(Vec::new()),
        slopes: OnceCell::new(),
        slope_positions: RefCell::new(Vec::new()),
        touches: Vec::new(),
        inside_touches: Vec::new(),
        depends: reads.iter().enumerate().map(|(k, &w)| repeatable(k, w, mirrored).filter(|_| reuse)).collect(),
        mirrored,
        refined: IntMap::default(),
    };
    // Start from (0, sentinel): every root of the first step lies below the sentinel.
    let top = (0..n)
        .filter(|&k| con.on_base(k))
        .map(|k| con.steps[k].r1 + con.steps[k].r2)
        .fold(T::from_f64(f64::INFINITY), |a, b| if b < a { b } else { a });
    let top = top + top + T::from_f64(con.scale);
    let lo = sweep.ids.make(T::zero(), Events::new());
    let hi = sweep.ids.make(top, Events::new());
    let mut bits = Vec::with_capacity(n);
    sweep.descend(0, &mut bits, &[Piece { lo, hi, touch: false }]);
    let mut intervals = join_split_runs(drop_repeated_touches(sweep.out, &sweep.touches));
    // The sweep emits types in descending order (each bit `true` first),
    // each type's intervals in λ order: reversing the types leaves the sort
    // below a check over sorted input instead of moving the intervals.
    intervals.reverse();
    for run in intervals.chunk_by_mut(|a, b| a.ty == b.ty) {
        run.reverse();
    }
    intervals.sort_by(|a, b| a.ty.cmp(&b.ty).then(cmp(&a.lower.lambda, &b.lower.lambda)));
    let mut notes = sweep.notes;
    notes.dedup();
    CayleySpace { intervals, touches: sweep.inside_touches, notes, method, numeric_steps }
}

impl<T: Real> Sweep<'_, T> {
    fn descend(&mut self, k: usize, bits: &mut Vec<bool>, pieces: &[Piece<T>]) {
        if k == self.con.steps.len() {
            for p in pieces {
                if p.touch {
                    self.touches.push(self.out.len());
                }
                let ty = RealizationType(bits.clone());
                self.out.push(OrientedInterval { ty, lower: p.lo.clone(), upper: p.hi.clone() });
            }
            return;
        }
        let mut refined: Vec<Piece<T>> = Vec::new();
        for p in pieces {
            self.refine_once(k, bits, p, &mut refined);
        }
        if refined.is_empty() {
            return;
        }
        for b in [true, false] {
            bits.push(b);
            self.descend(k + 1, bits, &refined);
            bits.pop();
        }
    }

    /// [`Self::refine`] appended to `out`, or its result for an earlier
    /// prefix that agrees on every bit step k depends on (see
    /// [`RefineKey`]), with the notes and estimated decisions it recorded
    /// (so the record is the one a second refinement would make).
    fn refine_once(&mut self, k: usize, bits: &[bool], piece: &Piece<T>, out: &mut Vec<Piece<T>>) {
        let Some(depends) = self.depends[k] else { return out.extend(self.refine(k, bits, piece)) };
        let end = |e: &Endpoint<T>| {
            let mask = |kind: Kind| e.events.iter().filter(|ev| ev.kind == kind).fold(0u128, |m, ev| m | 1 << ev.step);
            (e.id, e.events.first().copied(), mask(Kind::Stretched), mask(Kind::Folded))
        };
        let word = bits_word(&bits[..k]).expect("at most 128 steps where repeats are kept");
        let read = if self.mirrored { (word & depends).min(!word & depends) } else { word & depends };
        let key = (k, read, end(&piece.lo), end(&piece.hi), piece.touch);
        if let Some(done) = self.refined.get(&key) {
            self.notes.extend_from_slice(&done.notes);
            let touched =
                done.touches.iter().map(|&(lambda, event)| Touch { lambda, prefix: bits[..k].to_vec(), event });
            self.inside_touches.extend(touched);
            self.cert.count_estimated(done.estimated);
            return out.extend_from_slice(&done.pieces);
        }
        let (notes, touches, estimated) = (self.notes.len(), self.inside_touches.len(), self.cert.estimated());
        let pieces = self.refine(k, bits, piece);
        out.extend_from_slice(&pieces);
        let touches = self.inside_touches[touches..].iter().map(|t| (t.lambda, t.event)).collect();
        if self.refined.len() >= tolerance::REFINEMENTS_KEPT {
            self.refined.clear();
        }
        let (notes, estimated) = (self.notes[notes..].to_vec(), self.cert.estimated() - estimated);
        let done = Refined { pieces, notes, touches, estimated };
        self.refined.insert(key, done);
    }

    /// d_k at λ for the prefix `bits`, with its first and second derivative
    /// (realized into the sweep's one block of positions). A step on the
    /// base has d_k = λ: nothing to realize (the sweep asks only where the
    /// steps before k close).
    fn distance(&self, k: usize, bits: &[bool], lambda: T) -> Option<Jet<T>> {
        if self.con.on_base(k) {
            return Some(Jet::variable(lambda));
        }
        let jet = self.jet.get_or_init(|| self.con.map(Jet::constant));
        base_distance_at(jet, &mut self.positions.borrow_mut(), bits, k, Jet::variable(lambda))
    }

    /// [`Self::distance`]'s value and slope alone (the same numbers).
    fn slope_distance(&self, k: usize, bits: &[bool], lambda: T) -> Option<Slope<T>> {
        if self.con.on_base(k) {
            return self.distance(k, bits, lambda).map(Jet::slope);
        }
        let slopes = self.slopes.get_or_init(|| self.con.map(Slope::constant));
        base_distance_at(slopes, &mut self.slope_positions.borrow_mut(), bits, k, Slope::variable(lambda))
    }

    /// Slack of step k as a jet (value, slope, curvature).
    fn slack(&self, k: usize, kind: Kind, d: Jet<T>) -> Jet<T> {
        let s = &self.con.steps[k];
        kind.slack(s.r1, s.r2, d)
    }

    fn target(&self, k: usize, kind: Kind) -> T {
        let s = &self.con.steps[k];
        kind.target(s.r1, s.r2)
    }

    /// Proven signs of step k's slacks ([stretched, folded]) at a piece end.
    fn end_signs(&mut self, k: usize, bits: &[bool], end: &Endpoint<T>) -> [Sign; 2] {
        let at = Place { lambda: end.lambda.to_f64(), events: &end.events };
        self.cert.slack_signs_kept(&mut self.prefixes, bits, at, [(k, Kind::Stretched), (k, Kind::Folded)])
    }

    /// The roots of d_k = target strictly inside `piece`, and at its ends
    /// where step k's slack is proven zero there (`ends`: [lo, hi] signs).
    fn roots(&mut self, k: usize, bits: &[bool], piece: &Piece<T>, ends: [[Sign; 2]; 2]) -> Vec<Root<T>> {
        let (lo, hi) = (piece.lo.lambda, piece.hi.lambda);
        let mut roots = Vec::new();
        let word = bits_word(bits);
        for (ki, &kind) in self.cert.kinds(k).iter().enumerate() {
            let numeric: Vec<Candidate<T>>;
            let candidates: &[Candidate<T>] = match &self.exact[k] {
                Some(c) => &c[ki],
                None => {
                    let roots = self.numeric_roots((k, kind), bits, piece);
                    numeric = roots.into_iter().map(Candidate::unknown).collect();
                    &numeric
                }
            };
            // The candidates this prefix admits: the others are no roots of its slack.
            let candidates = candidates.iter().filter(|c| c.known.admits(word)).map(|c| c.lambda);
            let at_ends = [(lo, At::Lo, ends[0][ki]), (hi, At::Hi, ends[1][ki])];
            // Where step k is proven flat at an end, a candidate a few ulps
            // inside is that same root computed another way, not a new one.
            let ulps = |x: T| T::from_f64(tolerance::SAME_ROOT_ULPS * T::UNIT_ROUNDOFF) * x.abs();
            let beside_flat_end =
                |x: T| at_ends.iter().any(|&(e, _, sign)| sign == Sign::Zero && (x - e).abs() <= ulps(e));
            let inside = candidates.filter(|&x| x > lo && x < hi && !beside_flat_end(x));
            let flat_ends = at_ends.into_iter().filter(|e| e.2 == Sign::Zero).map(|(x, at, _)| (x, at));
            for (lambda, at) in inside.map(|x| (x, At::Inside)).chain(flat_ends) {
                // Value and slope (the jet's, bit for bit); the curvature
                // only at a tangency.
                let Some(d) = self.slope_distance(k, bits, lambda) else { continue };
                // Every closed-form candidate is kept as a boundary, even one of
                // another type's: the proven signs on the gaps beside it decide
                // (a boundary with the same sign on both sides and a nonzero
                // slack is dropped in `refine`). Testing candidates by value
                // would reject true roots next to an end, where d_k′ is huge.
                if !(d.d.to_f64().is_finite() || at != At::Inside) {
                    continue;
                }
                let st = &self.con.steps[k];
                let slack = kind.slack_value(Slope::constant(st.r1), Slope::constant(st.r2), d);
                let curvature = || self.distance(k, bits, lambda).map_or(T::zero(), |d| self.slack(k, kind, d).s);
                let (left, right) = side_signs(slack.d, curvature);
                roots.push(Root { lambda, kind, at, left, right, slack: slack.v });
            }
        }
        roots.sort_by(|a, b| cmp(&a.lambda, &b.lambda));
        roots.dedup_by(|a, b| a.lambda == b.lambda && a.kind == b.kind);
        roots
    }

    /// Split `piece` by the slack of step k into the parts where it closes.
    ///
    /// Whether step k is also flat at an end of the piece (two events at one
    /// λ) is the proven sign of its slack there ([`Certifier`]), and whether
    /// it closes on a gap between roots is the proven sign at a point inside
    /// the gap; the slopes at the roots only decide gaps too narrow to hold
    /// a point of their own.
    fn refine(&mut self, k: usize, bits: &[bool], piece: &Piece<T>) -> Vec<Piece<T>> {
        let ends = [self.end_signs(k, bits, &piece.lo), self.end_signs(k, bits, &piece.hi)];
        let roots = self.roots(k, bits, piece, ends);
        if piece.lo.lambda == piece.hi.lambda {
            return self.refine_point(k, piece, &roots, ends[0]);
        }
        let event = |r: &Root<T>| Event { step: k, kind: r.kind };
        // The roots in λ order: those at lo, those inside, those at hi (the
        // list itself becomes the inside ones; roots at the ends are rare).
        let (lo_end, hi_start) = (roots.partition_point(|r| r.at == At::Lo), roots.partition_point(|r| r.at != At::Hi));
        debug_assert!(roots[lo_end..hi_start].iter().all(|r| r.at == At::Inside));
        let mut inside = roots;
        let at_hi = inside.split_off(hi_start);
        let at_lo: Vec<Root<T>> = inside.drain(..lo_end).collect();
        // Step k's proven slacks at each candidate that is far from being
        // this prefix's root (see `off_root_signs`).
        let mut off_root: Vec<Option<[Sign; 2]>> = inside.iter().map(|r| self.off_root_signs(k, bits, r)).collect();
        // Boundaries and the feasibility of each gap between them.
        let mut feasible: Vec<bool> = Vec::with_capacity(inside.len() + 1);
        let n_gaps = inside.len() + 1;
        for g in 0..n_gaps {
            let a = if g == 0 { piece.lo.lambda } else { inside[g - 1].lambda };
            let b = if g == n_gaps - 1 { piece.hi.lambda } else { inside[g].lambda };
            // Between two places proven to be no root of step k (the piece's
            // ends, or candidates proven off-root) each slack keeps its sign
            // (a change would be a root): where the proofs at both agree that
            // it closes, or that it does not, they decide and no midpoint is
            // needed. A gap beside a root keeps its midpoint: deciding it from
            // one side alone disagreed with the midpoint at Peaucellier's
            // fourth-order touch on base A–B (a sign change that the
            // candidates did not bound).
            let point = |i: usize| off_root[i].and_then(end_closes);
            let left = if g == 0 { end_closes(ends[0]) } else { point(g - 1) };
            let right = if g == n_gaps - 1 { end_closes(ends[1]) } else { point(g) };
            let from_sides = left.filter(|_| left == right);
            let proven = from_sides.or_else(|| self.gap_closes(k, bits, a, b));
            let proven = proven.or_else(|| {
                let between = (g > 0 && g < n_gaps - 1).then(|| [inside[g - 1], inside[g]])?;
                self.gap_between_non_roots(k, bits, between)
            });
            let slot = proven.unwrap_or_else(|| {
                // The slopes at the roots beside the gap decide: not a proof.
                self.cert.count_estimated(1);
                let from_left = if g == 0 { at_lo.first().map(|r| r.right) } else { Some(inside[g - 1].right) };
                let from_right = if g == n_gaps - 1 { at_hi.first().map(|r| r.left) } else { Some(inside[g].left) };
                match (from_left.filter(|&s| s != 0), from_right.filter(|&s| s != 0)) {
                    (Some(x), Some(y)) if x == y => x > 0,
                    (Some(x), None) | (None, Some(x)) => x > 0,
                    (l, r) => {
                        if l.is_some() && r.is_some() {
                            self.notes.push(Note::Unresolved { lambda: a.to_f64(), step: k, why: Unresolved::GapSign });
                        }
                        self.gap_sign(k, bits, a, b) > 0
                    }
                }
            });
            feasible.push(slot);
        }
        // A root with the same feasibility on both sides is a touch only if
        // the slack is proven zero there; otherwise it is no root of this
        // prefix (a candidate of another branch, or one root found twice).
        let mut g = 0;
        while g < inside.len() {
            let r = inside[g];
            let same = feasible[g] == feasible[g + 1];
            let at = Place { lambda: r.lambda.to_f64(), events: &[] };
            let mut proven_zero = || match off_root[g] {
                Some(signs) => signs[usize::from(r.kind == Kind::Folded)] == Sign::Zero,
                None => self.cert.slack_signs_kept(&mut self.prefixes, bits, at, [(k, r.kind)])[0] == Sign::Zero,
            };
            if same && !proven_zero() {
                inside.remove(g);
                off_root.remove(g);
                feasible.remove(g + 1);
            } else {
                g += 1;
            }
        }
        let n_gaps = inside.len() + 1;
        // Walk the gaps, emitting maximal feasible runs and isolated roots.
        // An end where step k's slack is zero (to double-double resolution)
        // and the step closes, beside a gap where it does not, is an isolated
        // point of its own: two steps flat at one λ (a non-generic place,
        // noted as such by `with_coincident`).
        let isolated_end = |flat: &[Root<T>], signs: [Sign; 2], gap: bool| !gap && !flat.is_empty() && closes_at(signs);
        let mut out = Vec::new();
        if isolated_end(&at_lo, ends[0], feasible[0]) {
            let p = self.with_coincident(piece.lo.clone(), &at_lo, k);
            out.push(Piece { lo: p.clone(), hi: p, touch: true });
        }
        // A feasible run reaching an end where step k is proven not to close
        // (and no root of k lies inside, in `T`): k's root lies between the
        // run and the end, closer to the end than `T` resolves (two base
        // steps whose targets round to one f64, 9 and 9 + 1e-15), so the end
        // is k's: the earlier step is not flat there.
        let failing = |signs: [Sign; 2]| {
            [Kind::Stretched, Kind::Folded]
                .into_iter()
                .zip(signs)
                .find(|&(_, s)| s == Sign::Negative)
                .map(|(kind, _)| kind)
        };
        let end_of = |this: &mut Self, end: &Endpoint<T>, flat: &[Root<T>], signs: [Sign; 2]| match failing(signs) {
            Some(kind) => this.ids.make(end.lambda, Events::one(Event { step: k, kind })),
            None => this.with_coincident(end.clone(), flat, k),
        };
        let mut start: Option<Endpoint<T>> = None;
        for g in 0..n_gaps {
            if feasible[g] && start.is_none() {
                start = Some(if g == 0 {
                    end_of(self, &piece.lo, &at_lo, ends[0])
                } else {
                    let r = inside[g - 1];
                    self.ids.make(r.lambda, Events::one(event(&r)))
                });
            }
            if g == n_gaps - 1 {
                if let Some(lo) = start.take() {
                    let hi = end_of(self, &piece.hi, &at_hi, ends[1]);
                    out.push(Piece { lo, hi, touch: false });
                } else if isolated_end(&at_hi, ends[1], feasible[g]) {
                    let p = self.with_coincident(piece.hi.clone(), &at_hi, k);
                    out.push(Piece { lo: p.clone(), hi: p, touch: true });
                }
                break;
            }
            let r = inside[g];
            match (feasible[g], feasible[g + 1]) {
                (true, true) => {
                    self.notes.push(Note::Tangency { lambda: r.lambda.to_f64(), event: event(&r), inside: true });
                    let touch = Touch { lambda: r.lambda.to_f64(), prefix: bits[..k].to_vec(), event: event(&r) };
                    self.inside_touches.push(touch);
                    // A later step need not be analytic through this touch:
                    // the vertex placed here can switch sides of its base
                    // line (on Peaucellier's base A–B, D lies on B below
                    // λ = √19 in type ++-+, and on B's mirror image above,
                    // where step 3 touches folded). The run is split there,
                    // so each side is refined by the later steps on its own,
                    // and joined again at the leaves where both survive.
                    if k + 1 < self.con.steps.len() {
                        let at = self.ids.make(r.lambda, Events::one(event(&r)));
                        out.push(Piece { lo: start.take().expect("open run"), hi: at.clone(), touch: false });
                        start = Some(at);
                    }
                }
                (true, false) => {
                    let hi = self.ids.make(r.lambda, Events::one(event(&r)));
                    out.push(Piece { lo: start.take().expect("open run"), hi, touch: false });
                }
                (false, false) => {
                    self.notes.push(Note::Tangency { lambda: r.lambda.to_f64(), event: event(&r), inside: false });
                    let p = self.ids.make(r.lambda, Events::one(event(&r)));
                    out.push(Piece { lo: p.clone(), hi: p, touch: false });
                }
                (false, true) => {}
            }
        }
        out
    }

    /// Step k's slacks ([stretched, folded]) at a candidate whose slack in
    /// `T` is far from zero ([`tolerance::OFF_ROOT`] of the scale, so most
    /// likely a root of another branch), where f64 balls prove both: the
    /// step closes on both sides of it, or on neither, as at the point
    /// itself, so the gaps beside it need no point of their own. `None`
    /// otherwise (near zero: a root to place, not to prove; or not proven in
    /// f64, so the gaps are asked as before). Which candidates are asked is
    /// a matter of cost only: every answer used is proven.
    fn off_root_signs(&mut self, k: usize, bits: &[bool], r: &Root<T>) -> Option<[Sign; 2]> {
        let off = r.slack.to_f64().abs();
        if off.is_nan() || off <= tolerance::OFF_ROOT * self.con.scale {
            return None;
        }
        let at = Place { lambda: r.lambda.to_f64(), events: &[] };
        let questions = [(k, Kind::Stretched), (k, Kind::Folded)];
        self.cert.slack_signs_in_f64(&mut self.prefixes, bits, at, questions)
    }

    /// Whether step k closes on the open gap (a, b) between two roots, from
    /// the proven sign at its midpoint; `None` when the gap holds no point
    /// of its own or the sign is not proven (the caller then reads the
    /// slopes at its roots).
    fn gap_closes(&mut self, k: usize, bits: &[bool], a: T, b: T) -> Option<bool> {
        let mid = ((a + b) / T::from_f64(2.0)).to_f64();
        let inside = T::from_f64(mid) > a && T::from_f64(mid) < b;
        match inside.then(|| self.cert.closes(Some(&mut self.prefixes), bits, mid, k))? {
            Closes::Yes => Some(true),
            Closes::No => Some(false),
            Closes::Degenerate => {
                self.notes.push(Note::Degenerate { lambda: [a.to_f64(), b.to_f64()], step: k });
                Some(false)
            }
            Closes::Unknown => None,
        }
    }

    /// A gap between two candidates whose midpoint the certifier cannot
    /// decide (the slack there is zero to double-double resolution) where
    /// step k is proven to close at both candidates, so neither is a root of
    /// the scene as written: the gap is feasible, and the slack's zero inside
    /// it is a touch from above (noted as a tangency, a non-generic place).
    /// This is where an exact touch in the lengths as written splits into two
    /// f64 roots about √ε apart once the lengths are rounded to f64
    /// (Peaucellier on base O–P written at 1e150). A touch from below is an
    /// isolated point, found by the slopes at the roots as before (`None`).
    fn gap_between_non_roots(&mut self, k: usize, bits: &[bool], [r1, r2]: [Root<T>; 2]) -> Option<bool> {
        let closes = |s: &mut Self, r: Root<T>| s.cert.closes(Some(&mut s.prefixes), bits, r.lambda.to_f64(), k);
        if r1.kind != r2.kind || closes(self, r1) != Closes::Yes || closes(self, r2) != Closes::Yes {
            return None;
        }
        let lambda = ((r1.lambda + r2.lambda) / T::from_f64(2.0)).to_f64();
        let event = Event { step: k, kind: r1.kind };
        self.notes.push(Note::Tangency { lambda, event, inside: true });
        self.inside_touches.push(Touch { lambda, prefix: bits[..k].to_vec(), event });
        Some(true)
    }

    /// An isolated point from earlier steps survives step k if k closes
    /// there (proven signs of both slacks, `signs`); where k is flat too,
    /// the point gains its event.
    fn refine_point(&mut self, k: usize, piece: &Piece<T>, roots: &[Root<T>], signs: [Sign; 2]) -> Vec<Piece<T>> {
        if !closes_at(signs) {
            return Vec::new();
        }
        let flat: Vec<Root<T>> = roots.iter().copied().filter(|r| r.at != At::Inside).collect();
        if !flat.is_empty() {
            let lo = self.with_coincident(piece.lo.clone(), &flat, k);
            return vec![Piece { lo: lo.clone(), hi: lo, touch: piece.touch }];
        }
        vec![piece.clone()]
    }

    /// Add step k's flat events at an inherited endpoint (two steps flat at once).
    fn with_coincident(&mut self, mut end: Endpoint<T>, roots: &[Root<T>], k: usize) -> Endpoint<T> {
        for r in roots {
            let e = Event { step: k, kind: r.kind };
            if !end.events.contains(&e) {
                end.events.push(e);
            }
        }
        if end.events.len() > 1 {
            self.notes.push(Note::Coincident { lambda: end.lambda.to_f64(), events: end.events.to_vec() });
        }
        if end.lambda == T::zero() && !end.events.is_empty() {
            self.notes.push(Note::ZeroBase { step: k });
        }
        end
    }

    /// Sign of step k's slack inside a gap known to hold no root.
    fn gap_sign(&mut self, k: usize, bits: &[bool], a: T, b: T) -> i8 {
        let mid = (a + b) / T::from_f64(2.0);
        match self.distance(k, bits, mid) {
            Some(d) if d.v > T::zero() => {
                let s = &self.con.steps[k];
                sign(crate::realize::slack(s.r1, s.r2, d.v))
            }
            _ => {
                self.notes.push(Note::Degenerate { lambda: [a.to_f64(), b.to_f64()], step: k });
                -1
            }
        }
    }

    /// Numeric roots of g(λ) = d_k(λ) − t on a piece.
    ///
    /// Samples at λ = lo + (hi − lo)(1 − cos θ)/2 for equally spaced θ (dense
    /// near the piece ends, where d_k behaves like a square root). A gap whose
    /// ends have g″ of opposite sign is split at the inflection (bisection on
    /// g″), so every gap examined has g″ of one sign at both ends. There a
    /// sign change of g is a root (bisection to full precision), and a sign
    /// change of g′ is an extremum (bisection on g′) whose value decides
    /// between no root, a tangent (double) root, and two roots.
    /// Guarantee: every root is found provided no gap between samples holds
    /// two inflections of d_k with g″ of equal sign at its ends (g″ would
    /// change sign twice within 1/N of the piece); a near-double root whose
    /// extremum value is within [`tolerance::ROOT_VALUE`] of zero is decided
    /// by the certifier's sign there (two roots, placed by bisection on its
    /// signs, or none); where it cannot decide, reported as one tangent root
    /// and flagged [`Note::Unresolved`].
    fn numeric_roots(&mut self, (k, kind): (usize, Kind), bits: &[bool], piece: &Piece<T>) -> Vec<T> {
        let (lo, hi) = (piece.lo.lambda, piece.hi.lambda);
        let t = self.target(k, kind);
        let eval = |this: &Self, x: T| this.distance(k, bits, x).map(|d| d - Jet::constant(t));
        let n = self.samples;
        let xs: Vec<T> = (0..=n).map(|i| cosine_sample(lo, hi, i, n)).collect();
        let mut roots = Vec::new();
        for w in xs.windows(2) {
            self.numeric_gap((k, kind, bits), w[0], w[1], &eval, 0, &mut roots);
        }
        roots
    }

    /// The certifier's sign of g = d_k − t at `x` (the slack's for folded,
    /// its opposite for stretched); `None` where g has no value.
    fn proven_g_sign(&self, (k, kind, bits): (usize, Kind, &[bool]), x: T) -> Option<i8> {
        let s = self.cert.slack_sign(bits, Place { lambda: x.to_f64(), events: &[] }, k, kind).to_i8()?;
        Some(if kind == Kind::Stretched { -s } else { s })
    }

    fn numeric_gap(
        &mut self,
        question: (usize, Kind, &[bool]),
        a: T,
        b: T,
        eval: &dyn Fn(&Self, T) -> Option<Jet<T>>,
        depth: u32,
        roots: &mut Vec<T>,
    ) {
        let k = question.0;
        let (Some(ga), Some(gb)) = (eval(self, a), eval(self, b)) else { return };
        let finite = |g: &Jet<T>| g.d.to_f64().is_finite() && g.s.to_f64().is_finite();
        let value_change = sign(ga.v) * sign(gb.v) < 0;
        if ga.v == T::zero() {
            roots.push(a);
        }
        if !(finite(&ga) && finite(&gb)) {
            // Next to a piece end d_k behaves like a square root: monotone, so
            // a sign change of g is all there is to find.
            if value_change {
                roots.push(bisect(a, b, self.root_tol, |x| eval(self, x).map(|g| sign(g.v))));
            }
            return;
        }
        if sign(ga.s) * sign(gb.s) < 0 {
            // An inflection inside: split there, so each half has at most one extremum.
            let c = bisect(a, b, T::zero(), |x| eval(self, x).map(|g| sign(g.s)));
            // An inflection at an end (where a previous split put it) is that end's.
            let margin = (b - a) * T::from_f64(tolerance::INFLECTION_AT_END);
            if c - a > margin && b - c > margin {
                if depth < tolerance::ROOT_MAX_SPLITS {
                    self.numeric_gap(question, a, c, eval, depth + 1, roots);
                    self.numeric_gap(question, c, b, eval, depth + 1, roots);
                } else {
                    self.notes.push(Note::Unresolved { lambda: a.to_f64(), step: k, why: Unresolved::Inflections });
                }
                return;
            }
        }
        if value_change {
            roots.push(bisect(a, b, self.root_tol, |x| eval(self, x).map(|g| sign(g.v))));
            return;
        }
        if sign(ga.d) * sign(gb.d) < 0 {
            let e = bisect(a, b, T::zero(), |x| eval(self, x).map(|g| sign(g.d)));
            let Some(ge) = eval(self, e) else { return };
            let touch = T::from_f64(tolerance::ROOT_VALUE * self.con.scale);
            match Extremum::of(ge.v, touch) {
                // Near zero the f64 value says nothing (nor does an f64
                // value of exactly zero): the certifier decides.
                Extremum::Touch { exact } => match self.proven_g_sign(question, e) {
                    Some(s) if s != 0 && s != sign(ga.v) => {
                        // Two roots, one either side of the extremum.
                        let (kind, bits) = (question.1, question.2);
                        for ends in [[a, e], [e, b]] {
                            roots.push(self.cert.slack_root_between(bits, (k, kind), ends));
                        }
                    }
                    Some(s) if s != 0 => {}
                    _ => {
                        roots.push(e);
                        if !exact {
                            self.notes.push(Note::near_double_root(e.to_f64(), k));
                        }
                    }
                },
                _ if sign(ge.v) * sign(ga.v) < 0 => {
                    roots.push(bisect(a, e, self.root_tol, |x| eval(self, x).map(|g| sign(g.v))));
                    roots.push(bisect(e, b, self.root_tol, |x| eval(self, x).map(|g| sign(g.v))));
                }
                _ => {}
            }
        }
    }
}

/// `reads`, the bits before step k that d_k depends on, where another
/// prefix can repeat a refinement (see [`Sweep::depends`]): where it leaves
/// some bit out, or, with mirror images sharing refinements (`mirrored`),
/// past the first step (whose prefix is empty and has no mirror).
fn repeatable(k: usize, reads: Option<u128>, mirrored: bool) -> Option<u128> {
    let every = if k == 0 { 0 } else { u128::MAX >> (128 - k) };
    reads.filter(|&w| w != every || (mirrored && k > 0))
}

/// The intervals without the isolated end points (`touches`) that repeat a
/// realization another interval reaches at that end: where an interval of
/// positive length ends at the point's root in a type one flat step away
/// ([`Endpoint::flips_to`], the flip rule), the point adds nothing. Kept:
/// points that are the only realization there, as the exact tangency on
/// base v1–v2, where all four types are points.
fn drop_repeated_touches<T: Real>(intervals: Vec<OrientedInterval<T>>, touches: &[usize]) -> Vec<OrientedInterval<T>> {
    if touches.is_empty() {
        return intervals;
    }
    let repeated = |p: &OrientedInterval<T>| {
        intervals
            .iter()
            .filter(|i| i.lower.lambda != i.upper.lambda)
            .any(|i| p.lower.flips_to(&p.ty, &i.lower, &i.ty) || p.lower.flips_to(&p.ty, &i.upper, &i.ty))
    };
    let drop: Vec<bool> = (0..intervals.len()).map(|i| touches.contains(&i) && repeated(&intervals[i])).collect();
    intervals.into_iter().zip(drop).filter(|(_, d)| !d).map(|(i, _)| i).collect()
}

/// The intervals with each run that `Sweep::refine` split at a touch (for
/// the later steps) and that survived on both sides joined again. A type's
/// intervals are emitted together in λ order, so the two halves are
/// neighbours sharing the touch's endpoint. Joined after the repeated touch
/// points are dropped: the split end is what such a point flips to.
fn join_split_runs<T: Real>(intervals: Vec<OrientedInterval<T>>) -> Vec<OrientedInterval<T>> {
    let mut out: Vec<OrientedInterval<T>> = Vec::with_capacity(intervals.len());
    for iv in intervals {
        match out.last_mut() {
            Some(last) if last.ty == iv.ty && last.upper.id == iv.lower.id => last.upper = iv.upper,
            _ => out.push(iv),
        }
    }
    out
}

/// Whether a step closes at a point, from its slacks' signs there
/// ([stretched, folded]): none negative, and both defined (an undefined
/// sign says an earlier step cannot close there).
fn closes_at(signs: [Sign; 2]) -> bool {
    !signs.contains(&Sign::Negative) && !signs.contains(&Sign::Undefined)
}

/// Whether a step closes next to a piece end, from its slacks' proven signs
/// there ([stretched, folded]): `Some(true)` when both are positive,
/// `Some(false)` when one is negative, `None` otherwise (a slack zero there,
/// or undefined).
fn end_closes(signs: [Sign; 2]) -> Option<bool> {
    if signs.contains(&Sign::Negative) {
        Some(false)
    } else if signs.iter().all(|&s| s == Sign::Positive) {
        Some(true)
    } else {
        None
    }
}

/// The non-oriented Cayley space: the union of all oriented intervals.
pub fn union<T: Real>(intervals: &[OrientedInterval<T>], scale: f64) -> Vec<[f64; 2]> {
    let mut spans: Vec<[f64; 2]> =
        intervals.iter().map(|i| [i.lower.lambda.to_f64(), i.upper.lambda.to_f64()]).collect();
    spans.sort_by(|a, b| a[0].total_cmp(&b[0]));
    let mut out: Vec<[f64; 2]> = Vec::new();
    for s in spans {
        match out.last_mut() {
            Some(last) if s[0] <= last[1] + tolerance::UNION_GAP * scale => last[1] = last[1].max(s[1]),
            _ => out.push(s),
        }
    }
    out
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::complexity::four_cycle_test;
    use crate::decompose::decompose;
    use crate::linkage::Linkage;

    /// The Peaucellier inversor: step 4 reads steps 2 and 3 only, so the
    /// types differing in bit 1 repeat its refinements; a rhombus, so they
    /// include coincident ends, degenerate gaps and a touch.
    pub(crate) const PEAUCELLIER: &str = r#"
base = ["O", "C"]
bars = [["O", "A", 2.0], ["A", "C", 2.0], ["O", "B", 5.0], ["O", "D", 5.0],
        ["C", "B", 3.0], ["B", "P", 3.0], ["P", "D", 3.0], ["D", "C", 3.0]]
[joints]
O = [0.0, 0.0]
A = [2.0, 0.0]
C = [3.285575219373, 1.532088886238]
B = [2.385922501326, 4.394015682456]
D = [4.899652718047, -0.996696163598]
P = [4.0, 1.86523063262]
"#;

    /// One base of a scene: the base, its decomposition, the four-cycle
    /// test, the f64 construction and a certifier.
    pub(crate) type OnBase = ([usize; 2], Decomposition, Complexity, Construction<f64>, Certifier);

    /// Each valid base of a scene (its own first).
    pub(crate) fn every_base(text: &str, name: &str) -> Vec<OnBase> {
        let scene = crate::scene::parse_scene(text, "test", name).expect("parses");
        let linkage = Linkage::from_scene(&scene);
        let first = decompose(&linkage, scene.base.map(|b| b.0)).expect("in the class").expect("a base");
        std::iter::once(first.base)
            .chain(first.other_bases(&linkage))
            .map(|base| {
                let dec = decompose(&linkage, Some(base)).expect("in the class").expect("valid base");
                let cx = four_cycle_test(&dec);
                let con = Construction::<f64>::new(&linkage, &dec).expect("closes");
                let cert = Certifier::new(&linkage, &dec).expect("closes");
                (base, dec, cx, con, cert)
            })
            .collect()
    }

    /// The intervals of a space as data: types, λ bit for bit, flat steps.
    type View = Vec<(RealizationType, u64, Vec<Event>, u64, Vec<Event>)>;

    fn view(s: &CayleySpace<f64>) -> View {
        let end = |e: &Endpoint<f64>| (e.lambda.to_bits(), e.events.to_vec());
        s.intervals
            .iter()
            .map(|i| {
                let ((lo, lo_events), (hi, hi_events)) = (end(&i.lower), end(&i.upper));
                (i.ty.clone(), lo, lo_events, hi, hi_events)
            })
            .collect()
    }

    /// On every base of the bundled scenes whose steps are inverted
    /// through hinges and four-cycles: the sweep that asks each prefix only
    /// about the candidates whose known bits admit it finds the intervals
    /// (λ bit for bit), notes and components of the one that asks every
    /// prefix about every candidate; and on Limacon's own base, seven of its
    /// last step's eight candidates know both bits that step reads, so that
    /// each prefix admits at most two of those seven. (Not Peaucellier: its
    /// exact touches take their candidates from the exact stage, which a
    /// plan without a certifier does not reach.)
    #[test]
    fn known_bits_leave_the_intervals_unchanged() {
        let scenes = [
            (include_str!("../../../linkages/limacon.toml"), "limacon"),
            (include_str!("../../../linkages/jansen.toml"), "jansen"),
            (include_str!("../../../linkages/fig1a.toml"), "fig1a"),
            (include_str!("../../../linkages/watt.toml"), "watt"),
        ];
        let mut known = 0;
        for (text, name) in scenes {
            for (base, dec, cx, con, cert) in every_base(text, name) {
                let with_bits = SweepPlan::new(&con, Some(&cert), &dec, &cx, Method::Exact);
                let without = SweepPlan::new(&con, None, &dec, &cx, Method::Exact);
                let lambdas = |p: &SweepPlan<f64>| {
                    p.exact.iter().flatten().flatten().flatten().map(|c| c.lambda.to_bits()).collect::<Vec<_>>()
                };
                assert_eq!(lambdas(&with_bits), lambdas(&without), "{name} base {base:?}: the same candidates");
                known += with_bits.exact.iter().flatten().flatten().flatten().filter(|c| c.known.mask != 0).count();
                let (a, b) = (
                    cayley_space_planned(&con, &cert.fork(), with_bits),
                    cayley_space_planned(&con, &cert.fork(), without),
                );
                assert!(!a.intervals.is_empty(), "{name} base {base:?}");
                assert_eq!(view(&a), view(&b), "{name} base {base:?}");
                assert_eq!(a.notes, b.notes, "{name} base {base:?}");
                let (ca, cb) = (crate::motion::components(&a), crate::motion::components(&b));
                assert_eq!((ca.list, ca.connected), (cb.list, cb.connected), "{name} base {base:?}");
            }
        }
        assert!(known > 0, "some candidate has known bits");
        // Limacon on its own base: its last step's eight candidates, of which the seven
        // where both steps on the base close know the two bits it reads, two per setting.
        let (_, dec, cx, con, cert) = every_base(scenes[0].0, "limacon").swap_remove(0);
        let plan = SweepPlan::new(&con, Some(&cert), &dec, &cx, Method::Exact);
        let last = plan.exact.last().cloned().flatten().expect("closed form");
        let candidates: Vec<_> = last.iter().flatten().collect();
        assert_eq!(candidates.len(), 8);
        let knowing: Vec<_> = candidates.iter().filter(|c| c.known.mask == 0b110).collect();
        assert_eq!(knowing.len(), 7);
        for word in 0..4u128 {
            let admitted = knowing.iter().filter(|c| c.known.admits(Some(word << 1))).count();
            assert_eq!(admitted, if word == 0b11 { 1 } else { 2 }, "bits {word:b}");
        }
    }

    /// On every base of Peaucellier's inversor (bars only: mirror images
    /// share refinements) and the Watt six-bar (triangles, whose members
    /// later steps read: they do not): the sweep that repeats refinements
    /// gives the intervals (types, λ bit for bit, flat steps), notes and
    /// components of the one that refines every prefix afresh, and on some
    /// base it repeats, and on some only through mirror images.
    #[test]
    fn repeated_refinements_are_the_fresh_ones() {
        let (mut repeating, mut mirrored) = (0, 0);
        for (text, name) in [(PEAUCELLIER, "peaucellier"), (include_str!("../../../linkages/watt.toml"), "watt")] {
            for (base, dec, cx, con, cert) in every_base(text, name) {
                let plan = SweepPlan::new(&con, Some(&cert), &dec, &cx, Method::Exact);
                let run = |reuse| sweep(&con, &cert, plan.clone(), reuse);
                let (fresh, reused) = (run(false), run(true));
                assert!(!fresh.intervals.is_empty(), "{name} base {base:?}");
                assert_eq!(view(&fresh), view(&reused), "{name} base {base:?}");
                assert_eq!(fresh.notes, reused.notes, "{name} base {base:?}");
                // Shared refinements share endpoint ids: the components are the same.
                let (a, b) = (crate::motion::components(&fresh), crate::motion::components(&reused));
                assert_eq!((a.list, a.connected), (b.list, b.connected), "{name} base {base:?}");
                let reads = plan.reads.iter().enumerate();
                repeating += usize::from(reads.clone().any(|(k, &w)| repeatable(k, w, false).is_some()));
                // A step reading every earlier bit, repeated only by the mirror image.
                let only_mirror = |(k, &w): (usize, &Option<u128>)| repeatable(k, w, false).is_none() && w.is_some();
                mirrored += usize::from(con.places_no_members() && reads.filter(|&(k, _)| k > 0).any(only_mirror));
            }
        }
        assert!(repeating > 0, "some base has a step that does not read every earlier bit");
        assert!(mirrored > 0, "some base has a step repeated only through mirror images");
    }
}
