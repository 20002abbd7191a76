//! Structural decisions proven, not guessed: is a step's slack positive,
//! zero or negative at an interval end or inside a gap?
//!
//! Each question is first asked in [`Ball`] arithmetic over f64 (a
//! midpoint-radius enclosure of the exact value, from the lengths as
//! written): a ball that excludes zero proves the sign. Where it does not,
//! the same question is asked again in balls over double-double, with the
//! end's λ re-located in double-double. A ball that still holds zero is
//! answered [`Sign::Zero`]: the two events coincide (or the slack touches
//! zero) to within double-double resolution, a non-generic place that the
//! caller reports as such. The questions about the lengths alone (equal
//! sides, coinciding targets, flat clusters) are asked last of the
//! construction over the input as written, in exact arithmetic
//! ([`crate::exact`]): there a zero is proven.
//!
//! Ball radii grow with every placement far faster than the real error
//! (each adds its inputs' radii independently), so the base distances are
//! enclosed step by step, each in a frame of its own ([`Hinges`]): only a
//! scalar passes from step to step. Where balls still prove nothing, the
//! double-double value decides when it exceeds its error estimated from
//! the f64 − double-double difference (see [`Certifier::estimated`] for
//! how many decisions rested on that, with the length questions whose
//! separation bound is out of the exact stage's reach).
//!
//! An end λ* is the root of the flat step's slack. It is enclosed by a
//! bracket [λ − δ, λ + δ] whose ends have proven opposite slack signs (so
//! λ* lies inside), and the other slacks are evaluated on that whole
//! bracket with the flat steps placed exactly flat — the realization at λ*.

use std::cell::{Cell, RefCell};
use std::sync::{Arc, OnceLock};

mod exact_stage;

use crate::complexity::Complexity;
use crate::decompose::Decomposition;
use crate::exact::Expr;
use crate::hinge::Hinges;
use crate::inthash::IntMap;
use crate::linkage::Linkage;
use crate::real::{Ball, Dd, Real, Slope};
use crate::realize::{Construction, Event, Kind, P2, bits_word};
use crate::tolerance;

/// A proven sign; `Zero` when not even double-double separates the value
/// from 0; `Undefined` when an earlier step cannot close there, so the
/// question has no answer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sign {
    /// Proven below zero.
    Negative,
    /// Zero to double-double resolution (not separable from zero); proven
    /// zero where the exact stage decided it.
    Zero,
    /// Proven above zero.
    Positive,
    /// An earlier step cannot close there: the question has no answer.
    Undefined,
}

impl Sign {
    fn of(sign: Option<i8>) -> Option<Sign> {
        sign.map(|s| if s > 0 { Sign::Positive } else { Sign::Negative })
    }

    /// As ±1 or 0; `None` for [`Sign::Undefined`].
    pub fn to_i8(self) -> Option<i8> {
        match self {
            Sign::Positive => Some(1),
            Sign::Negative => Some(-1),
            Sign::Zero => Some(0),
            Sign::Undefined => None,
        }
    }
}

/// The construction in the three arithmetics a decision may need. The
/// double-double ones are built on first use: most scenes decide every
/// question in f64 balls.
#[derive(Debug, Clone)]
pub struct Certifier {
    /// The constructions, shared by [`Certifier::fork`]s (read only, but for
    /// the double-double ones' first use).
    built: Arc<Built>,
    /// Proven end brackets already searched, keyed by [`BracketKey`]
    /// (the same end is asked about once per later step).
    brackets: RefCell<IntMap<BracketKey, Option<f64>>>,
    /// Ends' λ already located in double-double ([`Certifier::refine_dd`]),
    /// keyed like the brackets (without the arithmetic): every later step
    /// and every question at the end asks for the same Newton iteration.
    refined: RefCell<IntMap<RefineKey, Dd>>,
    /// The decisions each stage took so far.
    counts: Cell<StageCounts>,
}

/// How many decisions each stage of a [`Certifier`] took: proven in f64
/// balls, in double-double balls, by the exact stage, and those that
/// rest on an estimate. A count of work (a question asked twice counts
/// twice), for `--timings` and `bench`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, schemars::JsonSchema))]
pub struct StageCounts {
    /// Proven in f64 balls.
    pub f64: usize,
    /// Proven in double-double balls.
    pub double_double: usize,
    /// Proven by the exact stage.
    pub exact: usize,
    /// Resting on an estimate ([`Certifier::estimated`]).
    pub estimated: usize,
}

/// What a [`Certifier`] decides with, built once.
#[derive(Debug)]
struct Built {
    f64_balls: Construction<Ball<f64>>,
    /// The same in slopes of balls, for mean-value enclosures ([`Hinges::enclosures`]).
    f64_slope_balls: Construction<Slope<Ball<f64>>>,
    /// Shared with the analysis (no copy).
    f64_plain: Arc<Construction<f64>>,
    /// The double-double constructions, each built on first use (`None`:
    /// a cluster's stated lengths do not close in double-double). Deciding
    /// equal sides needs only the balls.
    dd_balls: OnceLock<Option<BuiltBalls<Dd>>>,
    dd_plain: OnceLock<Option<DdPlain>>,
    /// Shared with the analysis (the double-double constructions are built
    /// from them on first use).
    linkage: Arc<Linkage>,
    dec: Arc<Decomposition>,
    /// Per step: the ways it can stop closing (see [`Certifier::kinds`]).
    kinds: Vec<&'static [Kind]>,
    /// Where each step's base distance is enclosed (`None`: in the base's frame).
    hinges: Option<Hinges>,
    /// Per step with equal sides: the two twin steps placing its base
    /// joints, if any (see [`Certifier::twins`]); empty where no step has
    /// equal sides.
    twins: Vec<Option<[usize; 2]>>,
}

/// A construction in balls and the same in slopes of balls.
type Balls<'a, T> = (&'a Construction<Ball<T>>, &'a Construction<Slope<Ball<T>>>);
/// [`Balls`], owned.
type BuiltBalls<T> = (Construction<Ball<T>>, Construction<Slope<Ball<T>>>);

/// An end's bracket depends on its λ, its first flat event, the type bits
/// before that step and the arithmetic (f64 or double-double balls).
type BracketKey = ([u64; 2], Event, u128, bool);

/// The next half-width a bracket search tries after `delta` failed, with
/// the slack's balls at its two sides (where both realized): where the
/// slack's change, estimated from the secant through their midpoints, would
/// clear their radii [`tolerance::BRACKET_SECANT_MARGIN`] times over, kept
/// between twice `delta` and [`tolerance::END_BRACKET_JUMP`] times it (a
/// secant through rounding noise may be far off); else
/// [`tolerance::END_BRACKET_GROWTH`] times it. Limacon's ends took three
/// tries (8.9e-16 of the scale, then 16 and 256 times that), now two. Only
/// how many tries a search takes: every bracket returned is proven.
fn next_half_width<T: Real>(delta: f64, sides: Option<(Ball<T>, Ball<T>)>) -> f64 {
    let grown = delta * tolerance::END_BRACKET_GROWTH;
    let Some((a, b)) = sides else { return grown };
    let slope = (b.m - a.m).to_f64().abs() / (2.0 * delta);
    let needed = tolerance::BRACKET_SECANT_MARGIN * a.r.max(b.r) / slope;
    if needed.is_finite() { needed.clamp(2.0 * delta, tolerance::END_BRACKET_JUMP * delta) } else { grown }
}

/// Realized prefixes of the f64 ball construction, kept across one sweep's
/// questions. A depth-first sweep asks about one place (an interval end, or
/// the midpoint of a gap in a piece that survives a step) for the type
/// prefix of bits 1..k, then for 1..k+1 with each value of bit k: each
/// question places only the steps past the longest prefix already realized
/// there. A step flat at the place is placed at height zero whichever its
/// bit, so prefixes that differ only in such bits share it (Watt 4%,
/// Peaucellier 2% fewer instructions). The positions are those a
/// realization from scratch gives (the same operations in the same order,
/// up to the sign of a zero coordinate, which no comparison tells apart),
/// so no answer changes. The same for the double-double plain values that
/// questions at exact zeros read (no ball proves a zero; non-generic scenes
/// ask many at one end).
#[derive(Debug, Default)]
pub struct Prefixes {
    balls: Kept<Ball<f64>>,
    dd: Kept<Dd>,
}

/// A place: its λ (a ball's midpoint and radius bits, or a double-double's
/// two parts) and its flat steps (bit i for step i).
type PlaceKey = (u64, u64, u128);

/// The realized prefixes of one arithmetic, by place. Every place has a
/// slot of the same size in blocks of [`SLOTS_PER_BLOCK`] slots, allocated
/// once each (no allocation per place, and no block ever moves).
#[derive(Debug)]
struct Kept<T> {
    places: IntMap<PlaceKey, Realized>,
    /// Each slot: one position per joint, those of the steps placed valid.
    /// A step reads only joints placed before it, so a question that
    /// resumes from a shorter common prefix places its later steps over
    /// the old ones in place (no copy of the positions per step).
    positions: Vec<Vec<P2<T>>>,
    /// Each slot: d_i of each step placed.
    distances: Vec<Vec<T>>,
    /// The last answer's distances (reused: no allocation per question).
    view: Vec<T>,
}

impl<T> Default for Kept<T> {
    fn default() -> Self {
        Kept { places: IntMap::default(), positions: Vec::new(), distances: Vec::new(), view: Vec::new() }
    }
}

/// Slots per block of [`Kept`].
const SLOTS_PER_BLOCK: usize = 32;

/// One place's realized prefix.
#[derive(Debug)]
struct Realized {
    /// Its slot in [`Kept`]'s blocks.
    slot: usize,
    /// The steps placed.
    placed: usize,
    /// Their orientation bits (bit i for step i).
    bits: u128,
}

/// A place's λ as two words (see [`PlaceKey`]).
trait PlaceBits {
    fn place_bits(&self) -> (u64, u64);
}

impl PlaceBits for Ball<f64> {
    fn place_bits(&self) -> (u64, u64) {
        (self.m.to_bits(), self.r.to_bits())
    }
}

impl PlaceBits for Dd {
    fn place_bits(&self) -> (u64, u64) {
        (self.hi.to_bits(), self.lo.to_bits())
    }
}

/// The base distances at `lambda` up to `upto` with the flat steps placed
/// flat: from the prefixes a sweep keeps where given (and the place fits a
/// word), else realized afresh.
fn distances_at<T: Real + PlaceBits>(
    kept: Option<&mut Kept<T>>,
    con: &Construction<T>,
    lambda: T,
    bits: &[bool],
    upto: usize,
    (mask, flat): (Option<u128>, &[usize]),
) -> Vec<T> {
    match (kept, mask) {
        (Some(kept), Some(mask)) if upto < 128 => kept.distances(con, lambda, bits, upto, mask).to_vec(),
        _ => con.base_distances_flat(lambda, bits, upto, flat),
    }
}

impl<T: Real + PlaceBits> Kept<T> {
    /// [`Construction::base_distances_flat`] at `lambda` with the steps of
    /// `flat` (bit i for step i) placed flat, from the realized prefix kept
    /// for that place, borrowed until the next question. Past
    /// [`tolerance::PREFIX_PLACES`] places the cache starts afresh (a bound
    /// on memory, not a decision).
    fn distances(&mut self, con: &Construction<T>, lambda: T, bits: &[bool], upto: usize, flat: u128) -> &[T] {
        let (hi, lo) = lambda.place_bits();
        let key = (hi, lo, flat);
        if self.places.len() >= tolerance::PREFIX_PLACES && !self.places.contains_key(&key) {
            self.places.clear();
            self.positions.clear();
            self.distances.clear();
        }
        let n = con.n_joints;
        // Room for every step the place may be asked about.
        let steps = con.steps.len().min(128);
        let next = self.places.len();
        let place = self.places.entry(key).or_insert(Realized { slot: next, placed: 0, bits: 0 });
        let (block, at) = (place.slot / SLOTS_PER_BLOCK, place.slot % SLOTS_PER_BLOCK);
        if place.slot == next {
            if block == self.positions.len() {
                self.positions.push(Vec::with_capacity(SLOTS_PER_BLOCK * n));
                self.distances.push(Vec::with_capacity(SLOTS_PER_BLOCK * steps));
            }
            let zero = T::zero();
            self.positions[block].resize((at + 1) * n, [zero, zero]);
            con.place_base(&mut self.positions[block][at * n..], lambda);
            self.distances[block].resize((at + 1) * steps, zero);
        }
        let positions = &mut self.positions[block][at * n..(at + 1) * n];
        let distances = &mut self.distances[block][at * steps..(at + 1) * steps];
        let asked = prefix_word(bits, upto).expect("upto < 128");
        let common = (((place.bits ^ asked) & !flat).trailing_zeros() as usize).min(place.placed).min(upto);
        place.placed = common;
        let tol = tolerance::FEASIBLE * con.scale;
        // Later questions at this place build on these positions: place what any step reads.
        let reach = con.steps.len();
        self.view.clear();
        while place.placed < upto {
            let k = place.placed;
            let (dk, placed) = con.place_step(positions, k, (bits[k], flat >> k & 1 == 1), tol, reach);
            if placed.is_err() {
                self.view.extend_from_slice(&distances[..k]);
                self.view.push(dk);
                return &self.view;
            }
            distances[k] = dk;
            place.bits = place.bits & !(1 << k) | u128::from(bits[k]) << k;
            place.placed += 1;
        }
        self.view.extend_from_slice(&distances[..upto]);
        self.view.push(con.base_distance(positions, upto));
        &self.view
    }
}

/// An end's λ in double-double depends on its f64 λ, its first flat event
/// and the type bits before that step.
type RefineKey = ([u64; 2], Event, u128);

/// The flat steps of `events` as one word, bit i for step i (`None` past 128 steps).
fn flat_mask(events: &[Event]) -> Option<u128> {
    events.iter().try_fold(0u128, |m, e| (e.step < 128).then(|| m | 1 << e.step))
}

/// The type bits before step `step` as one word (`None` past 128 steps).
fn prefix_word(bits: &[bool], step: usize) -> Option<u128> {
    if step <= 128 { bits_word(&bits[..step]) } else { None }
}

/// The double-double values, for the questions f64 balls leave open.
#[derive(Debug, Clone)]
struct DdPlain {
    plain: Construction<Dd>,
    /// The f64 construction with slopes, for the slope [`Certifier::refine_dd`]'s Newton iteration reads.
    f64_slopes: Construction<Slope<f64>>,
}

/// Whether a step closes at a point (see [`Certifier::closes`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Closes {
    /// Both slacks proven positive: the step closes.
    Yes,
    /// A slack proven negative: the step cannot close.
    No,
    /// Equal sides and a zero base distance: the vertex turns freely.
    Degenerate,
    /// Not decided at double-double resolution.
    Unknown,
}

/// One slack evaluated in balls.
struct Value {
    proven: Option<Sign>,
    midpoint: Option<f64>,
    radius: Option<f64>,
}

/// Where a question is asked: a λ, and the steps flat there (empty for a
/// point inside an interval, whose λ is then taken as exact).
#[derive(Clone, Copy, Debug)]
pub struct At<'a> {
    /// The base length λ (scene units).
    pub lambda: f64,
    /// The steps flat there (empty inside an interval, where λ is exact).
    pub events: &'a [Event],
}

impl Certifier {
    /// The construction in every arithmetic a decision may need; `None` when a cluster's stated lengths do not close.
    pub fn new(linkage: &Linkage, dec: &Decomposition) -> Option<Self> {
        let f64_plain = Construction::new(linkage, dec).ok()?;
        Self::shared(Arc::new(linkage.clone()), Arc::new(dec.clone()), Arc::new(f64_plain))
    }

    /// [`Self::new`] on a linkage, decomposition and f64 construction the
    /// caller keeps too (no copy of any).
    pub fn shared(linkage: Arc<Linkage>, dec: Arc<Decomposition>, f64_plain: Arc<Construction<f64>>) -> Option<Self> {
        let f64_balls: Construction<Ball<f64>> = Construction::new(&linkage, &dec).ok()?;
        let hinges = Hinges::new(&f64_plain);
        let built = Built {
            hinges,
            f64_slope_balls: f64_balls.map(Slope::constant),
            f64_balls,
            f64_plain,
            dd_balls: OnceLock::new(),
            dd_plain: OnceLock::new(),
            linkage,
            dec,
            kinds: Vec::new(),
            twins: Vec::new(),
        };
        let mut cert = Certifier::with_built(Arc::new(built));
        // Unequal sides proven in f64 balls are unequal in double-double
        // balls too (a narrower enclosure of the same number); only sides
        // f64 cannot separate need the double-double construction.
        let proven_unequal = (0..cert.built.dec.steps.len())
            .map(|k| {
                let s = &cert.built.f64_balls.steps[k];
                Some(
                    (s.r1 - s.r2).sign().is_some() || {
                        let s = &cert.dd_balls()?.steps[k];
                        (s.r1 - s.r2).sign().is_some()
                    },
                )
            })
            .collect::<Option<Vec<bool>>>()?;
        // The sides no ball separates, decided exactly over one construction.
        let open: Vec<usize> = (0..proven_unequal.len()).filter(|&k| !proven_unequal[k]).collect();
        let mut exact =
            cert.exact_signs(open.len(), |con| open.iter().map(|&k| con.steps[k].r1 - con.steps[k].r2).collect());
        let kinds = proven_unequal
            .iter()
            .map(|&proven| {
                let unequal = proven || exact.next().expect("one per open step") != Sign::Zero;
                if unequal { &[Kind::Stretched, Kind::Folded][..] } else { &[Kind::Stretched][..] }
            })
            .collect();
        let built = Arc::get_mut(&mut cert.built).expect("not shared yet");
        built.kinds = kinds;
        let twins = cert.twins();
        Arc::get_mut(&mut cert.built).expect("not shared yet").twins = twins;
        Some(cert)
    }

    /// The construction in f64 balls from the lengths as written.
    pub fn f64_balls(&self) -> &Construction<Ball<f64>> {
        &self.built.f64_balls
    }

    /// A certifier for another thread: the same constructions (shared, the
    /// double-double ones built once for both), its own caches, and no
    /// decisions counted yet.
    pub fn fork(&self) -> Certifier {
        Certifier::with_built(self.built.clone())
    }

    /// A certifier over `built` with empty caches and no decisions counted.
    fn with_built(built: Arc<Built>) -> Certifier {
        Certifier {
            built,
            brackets: RefCell::new(IntMap::default()),
            refined: RefCell::new(IntMap::default()),
            counts: Cell::new(StageCounts::default()),
        }
    }

    /// Add to the decisions counted.
    fn count(&self, add: impl FnOnce(&mut StageCounts)) {
        let mut counts = self.counts.get();
        add(&mut counts);
        self.counts.set(counts);
    }

    /// The double-double ball construction (built on first use; `None`
    /// when a cluster's stated lengths do not close in double-double).
    fn dd_balls(&self) -> Option<&Construction<Ball<Dd>>> {
        self.dd_pair().map(|(balls, _)| balls)
    }

    /// [`Self::dd_balls`] with its slopes of balls.
    fn dd_pair(&self) -> Option<Balls<'_, Dd>> {
        let built = self.built.dd_balls.get_or_init(|| {
            let balls: Construction<Ball<Dd>> = Construction::new(&self.built.linkage, &self.built.dec).ok()?;
            let slopes = balls.map(Slope::constant);
            Some((balls, slopes))
        });
        built.as_ref().map(|(b, s)| (b, s))
    }

    /// The f64 ball construction with its slopes of balls.
    fn f64_pair(&self) -> Balls<'_, f64> {
        (&self.built.f64_balls, &self.built.f64_slope_balls)
    }

    /// The double-double plain construction, with the f64 slopes (built on
    /// first use, like [`Self::dd_balls`]).
    fn dd_plain(&self) -> Option<&DdPlain> {
        self.built
            .dd_plain
            .get_or_init(|| {
                let plain = Construction::new(&self.built.linkage, &self.built.dec).ok()?;
                // Slope arithmetic on values is f64's own, operation for operation:
                // the plain construction's numbers as constants are the ones
                // `Construction::<Slope<f64>>::new` computes.
                Some(DdPlain { plain, f64_slopes: self.built.f64_plain.map(Slope::constant) })
            })
            .as_ref()
    }

    /// The ways step k can stop closing. With equal sides (r1 = r2, proven
    /// in double-double) the folded slack is d ≥ 0 itself: it never goes
    /// negative, and d = 0 is a degenerate step (its base joints coincide,
    /// as in a rhombus), not an interval end.
    pub fn kinds(&self, k: usize) -> &'static [Kind] {
        self.built.kinds[k]
    }

    /// Whether cluster `c`'s joints lie on one line: `Some(true)` for two
    /// joints, `Some(false)` when a joint is proven off the line of the first
    /// two (f64 or double-double balls, then exactly, from the lengths and
    /// coordinates as written), `Some(true)` when every joint is proven on
    /// it (exactly), `None` where that is out of the exact stage's reach.
    /// The balls take differences in units of `scale`, so no product of two
    /// lengths over- or underflows.
    pub fn cluster_flat(&self, c: usize, scale: f64) -> Option<bool> {
        /// The proven sign of each joint's cross product with the first edge.
        fn crosses<T: Real>(shape: &[(usize, [Ball<T>; 2])], scale: f64) -> impl Iterator<Item = Option<i8>> + '_ {
            let unit = Ball::exact(T::from_f64(scale));
            let (p, q) = (shape[0].1, shape[1].1);
            let (ux, uy) = ((q[0] - p[0]) / unit, (q[1] - p[1]) / unit);
            shape[2..].iter().map(move |&(_, r)| {
                let (vx, vy) = ((r[0] - p[0]) / unit, (r[1] - p[1]) / unit);
                (ux * vy - uy * vx).sign()
            })
        }
        if self.built.f64_balls.shapes[c].len() <= 2 {
            return Some(true);
        }
        // f64 balls first (they prove most shapes bent), then double-double.
        if crosses(&self.built.f64_balls.shapes[c], scale).any(|s| s.is_some()) {
            return Some(false);
        }
        let balls = self.dd_balls()?;
        if crosses(&balls.shapes[c], scale).any(|s| s.is_some()) {
            return Some(false);
        }
        let signs = exact_stage::decide(&self.built.linkage, &self.built.dec, |con| {
            let shape = &con.shapes[c];
            let (p, q) = (shape[0].1, shape[1].1);
            let cross = |r: [Expr; 2]| (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
            shape[2..].iter().map(|&(_, r)| cross(r)).collect()
        })?;
        // One joint proven off the line proves the answer; all on it too.
        let answer = if signs.iter().any(|s| matches!(s, Some(Sign::Positive | Sign::Negative))) {
            Some(false)
        } else if signs.iter().all(|s| *s == Some(Sign::Zero)) {
            Some(true)
        } else {
            None
        };
        self.count_exact(answer.is_some());
        answer
    }

    /// Whether two steps are flat at the same base length: the proven sign
    /// of `a`'s flat distance minus `b`'s (for steps on the base, whose
    /// flat distances are the λ of their events).
    pub fn target_sign(&self, a: Event, b: Event) -> Sign {
        fn diff<T: Real>(con: &Construction<Ball<T>>, a: Event, b: Event) -> Option<i8> {
            let (sa, sb) = (&con.steps[a.step], &con.steps[b.step]);
            (a.kind.target(sa.r1, sa.r2) - b.kind.target(sb.r1, sb.r2)).sign()
        }
        let fast = diff(&self.built.f64_balls, a, b);
        self.count(|c| c.f64 += usize::from(fast.is_some()));
        let fine = || {
            let sign = self.dd_balls().and_then(|balls| diff(balls, a, b));
            self.count(|c| c.double_double += usize::from(sign.is_some()));
            sign
        };
        Sign::of(fast.or_else(fine)).unwrap_or_else(|| {
            self.exact_sign(|con| {
                let (sa, sb) = (&con.steps[a.step], &con.steps[b.step]);
                a.kind.target(sa.r1, sa.r2) - b.kind.target(sb.r1, sb.r2)
            })
        })
    }

    /// The sign of one number over the construction in exact arithmetic
    /// ([`Self::exact_signs`]).
    fn exact_sign(&self, number: impl FnOnce(&Construction<Expr>) -> Expr) -> Sign {
        self.exact_signs(1, |con| vec![number(con)]).next().expect("one number")
    }

    /// The signs of the `n` numbers `numbers` builds over one construction
    /// in exact arithmetic ([`exact_stage::decide`]); where one is out of
    /// reach (or no exact construction closes), [`Sign::Zero`], counted in
    /// [`Self::estimated`].
    fn exact_signs(
        &self,
        n: usize,
        numbers: impl FnOnce(&Construction<Expr>) -> Vec<Expr>,
    ) -> std::vec::IntoIter<Sign> {
        let decided = exact_stage::decide(&self.built.linkage, &self.built.dec, numbers);
        let decided = decided.unwrap_or_else(|| vec![None; n]);
        let signs: Vec<Sign> = decided
            .into_iter()
            .map(|d| {
                self.count_exact(d.is_some());
                d.unwrap_or(Sign::Zero)
            })
            .collect();
        signs.into_iter()
    }

    /// Step k's closed-form candidates for `kind` with every branch of the
    /// inversion decided exactly, to double-double precision; `None` where
    /// the exact stage cannot decide one (counted as an estimate: the
    /// caller keeps its own candidates).
    pub fn exact_candidates(&self, cx: &Complexity, k: usize, kind: Kind) -> Option<Vec<Dd>> {
        let found = exact_stage::candidates(&self.built.linkage, &self.built.dec, cx, k, kind);
        self.count_exact(found.is_some());
        found
    }

    /// Count one decision of the exact stage: proven, or out of its reach
    /// (then the caller's answer is an estimate).
    fn count_exact(&self, proven: bool) {
        self.count(|c| if proven { c.exact += 1 } else { c.estimated += 1 });
    }

    /// How many decisions so far the exact stage proved (the balls could not).
    pub fn exact_decisions(&self) -> usize {
        self.counts.get().exact
    }

    /// How many decisions so far each stage took.
    pub fn stage_counts(&self) -> StageCounts {
        self.counts.get()
    }

    /// The proven sign of step `k`'s slack for `kind` at `at`, for the type
    /// prefix `bits` (at least `k` bits).
    pub fn slack_sign(&self, bits: &[bool], at: At, k: usize, kind: Kind) -> Sign {
        self.slack_signs(bits, at, &[(k, kind)])[0]
    }

    /// [`Self::slack_sign`] for several (step, kind) questions at one place,
    /// sharing the realizations.
    pub fn slack_signs(&self, bits: &[bool], at: At, questions: &[(usize, Kind)]) -> Vec<Sign> {
        self.slack_signs_in(None, bits, at, questions)
    }

    /// [`Self::slack_signs_in`] for a sweep's fixed few questions, asked
    /// where the steps before them close. Most are proven by the f64 balls
    /// of the prefix kept for the place (at any depth: even a first step's
    /// question then allocates nothing), and a folded rhombus by its twin
    /// steps ([`Self::twin_zero`]); the rest take the general path.
    pub fn slack_signs_kept<const N: usize>(
        &self,
        prefixes: &mut Prefixes,
        bits: &[bool],
        at: At,
        questions: [(usize, Kind); N],
    ) -> [Sign; N] {
        let fast = self.signs_in_f64(prefixes, bits, at, questions);
        let signs = std::array::from_fn(|i| fast[i].or_else(|| self.twin_zero(bits, at, questions[i])));
        if signs.iter().all(Option::is_some) {
            return signs.map(|s| s.expect("all proven"));
        }
        let signs = self.slack_signs_in(Some(prefixes), bits, at, &questions);
        std::array::from_fn(|i| signs[i])
    }

    /// The steps whose base joints are placed by two twin steps: steps on
    /// the same base joints (in the same order) whose clusters are single
    /// bars of the same lengths as written (equal double-doubles), so the
    /// same formula from the same inputs. Twins with the same orientation,
    /// or flat (then both are, at the same λ), place their vertices at one
    /// point, exactly: the step on them has base distance 0 there (the
    /// folded rhombus of Peaucellier's inversor). Only steps with equal
    /// sides are looked at (with unequal ones a zero base distance is a
    /// negative folded slack, which balls prove).
    fn twins(&self) -> Vec<Option<[usize; 2]>> {
        let steps = &self.built.dec.steps;
        if self.built.kinds.iter().all(|k| k.len() == 2) {
            return Vec::new();
        }
        // The step placing each joint as its vertex (one pass, not a search per step).
        let mut placed_by = vec![None; self.built.linkage.n_joints()];
        for (k, s) in steps.iter().enumerate() {
            placed_by[s.vertex] = Some(k);
        }
        let placing = |joint: usize| placed_by[joint];
        (0..steps.len())
            .map(|k| {
                if self.built.kinds[k].len() != 1 {
                    return None;
                }
                let (a, b) = (placing(steps[k].u)?, placing(steps[k].w)?);
                let (sa, sb) = (&steps[a], &steps[b]);
                let sides = self.bar_sides(a).zip(self.bar_sides(b));
                let twins = a != b && (sa.u, sa.w) == (sb.u, sb.w) && sides.is_some_and(|(x, y)| x == y);
                twins.then_some([a, b])
            })
            .collect()
    }

    /// Step k's sides |u v| and |w v| as written (each bit of their
    /// double-doubles), where both its clusters are single bars.
    fn bar_sides(&self, k: usize) -> Option<[[u64; 2]; 2]> {
        let step = &self.built.dec.steps[k];
        let length = |c: usize| match self.built.dec.clusters.nodes[c].origin {
            crate::decompose::Origin::Bar(i) => Some(self.built.linkage.bars[i].exact),
            _ => None,
        };
        let bits = |x: Dd| [x.hi.to_bits(), x.lo.to_bits()];
        Some([bits(length(step.cluster_u)?), bits(length(step.cluster_w)?)])
    }

    /// Whether steps a and b have the same targets r1 + r2 and |r1 − r2|,
    /// exactly: their sides are the same bars' lengths as written (in
    /// either order), so each is flat the same way at the same λ.
    fn same_target(&self, a: usize, b: usize) -> bool {
        let (Some(x), Some(y)) = (self.bar_sides(a), self.bar_sides(b)) else { return false };
        x == y || x == [y[1], y[0]]
    }

    /// [`Sign::Zero`] for the folded slack of an equal-sided step on twin
    /// steps' vertices (see [`Self::twins`]) where they coincide: the same
    /// orientation bits, or one of them flat at `at`. Asked only at places
    /// where the steps before it close (every place the sweep asks about).
    fn twin_zero(&self, bits: &[bool], at: At, (k, kind): (usize, Kind)) -> Option<Sign> {
        let [a, b] = self.built.twins.get(k).copied().flatten()?;
        let flat = at.events.iter().any(|e| e.step == a || e.step == b);
        (kind == Kind::Folded && (bits[a] == bits[b] || flat)).then_some(Sign::Zero)
    }

    /// [`Self::slack_signs_kept`] where f64 balls (or a step on the base)
    /// prove every answer; `None` where one would need double-double. A
    /// question asked here to save others costs no more than f64 balls and
    /// never an estimate.
    pub fn slack_signs_in_f64<const N: usize>(
        &self,
        prefixes: &mut Prefixes,
        bits: &[bool],
        at: At,
        questions: [(usize, Kind); N],
    ) -> Option<[Sign; N]> {
        let signs = self.signs_in_f64(prefixes, bits, at, questions);
        signs.iter().all(Option::is_some).then(|| signs.map(|s| s.expect("all proven")))
    }

    /// Each of [`Self::slack_signs_in_f64`]'s answers that f64 balls (or a
    /// step on the base) prove.
    fn signs_in_f64<const N: usize>(
        &self,
        prefixes: &mut Prefixes,
        bits: &[bool],
        at: At,
        questions: [(usize, Kind); N],
    ) -> [Option<Sign>; N] {
        if let Some(signs) = self.on_base_signs(at, &questions) {
            self.count(|c| c.f64 += N);
            return signs.map(Some);
        }
        let upto = questions.iter().map(|&(k, _)| k).max().unwrap_or(0);
        let Some(mask) = flat_mask(at.events).filter(|_| upto < 128) else { return [None; N] };
        let Some(l) = self.bracket(self.f64_pair(), bits, at, Dd::new(at.lambda)) else { return [None; N] };
        let d = prefixes.balls.distances(&self.built.f64_balls, l, bits, upto, mask);
        let steps = &self.built.f64_balls.steps;
        let proven = |(k, kind): (usize, Kind)| {
            let d = *d.get(k)?;
            Sign::of(kind.slack_value(steps[k].r1, steps[k].r2, d).sign())
        };
        let signs = questions.map(proven);
        self.count(|c| c.f64 += signs.iter().filter(|s| s.is_some()).count());
        signs
    }

    /// The signs of questions about steps standing on the base, proven
    /// without a realization: there d = λ, so a slack is λ against the
    /// step's target. λ is exact inside an interval; at an end whose first
    /// flat step stands on the base, it is that step's target exactly (its
    /// ball from the lengths as written). `None` where a question is about
    /// another step, about a step flat at `at`, or is not proven so (the
    /// general path decides it).
    fn on_base_signs<const N: usize>(&self, at: At, questions: &[(usize, Kind); N]) -> Option<[Sign; N]> {
        let con = &self.built.f64_balls;
        if at.events.first().is_some_and(|e| !con.on_base(e.step)) {
            return None;
        }
        // λ exact, or the flat step's target: `bracket` reads no type bits for either.
        let lambda = self.bracket(self.f64_pair(), &[], at, Dd::new(at.lambda))?;
        let flat_here = |k: usize, kind: Kind| at.events.iter().any(|e| e.step == k && e.kind == kind);
        let mut signs = [Sign::Zero; N];
        for (sign, &(k, kind)) in signs.iter_mut().zip(questions) {
            if !con.on_base(k) || flat_here(k, kind) {
                return None;
            }
            let s = &con.steps[k];
            let slack = kind.slack_value(s.r1, s.r2, lambda);
            // With equal sides the folded slack is d = λ itself: at an exact
            // λ = 0 (the base's end) it is exactly zero, proven. At an end
            // where another step on the base is flat the same way with the
            // same sides as written, λ is this step's target too, exactly.
            let exact_zero = kind == Kind::Folded && self.kinds(k).len() == 1 && lambda == Ball::exact(0.0);
            let twin_end = || at.events.first().is_some_and(|e| e.kind == kind && self.same_target(e.step, k));
            *sign = match Sign::of(slack.sign()) {
                Some(s) if !exact_zero => s,
                _ if exact_zero || twin_end() => Sign::Zero,
                _ => return None,
            };
        }
        Some(signs)
    }

    /// [`Self::slack_signs`], realizing in f64 balls from the prefixes kept
    /// in `prefixes` (a sweep's; see [`Prefixes`]) where given.
    pub fn slack_signs_in(
        &self,
        prefixes: Option<&mut Prefixes>,
        bits: &[bool],
        at: At,
        questions: &[(usize, Kind)],
    ) -> Vec<Sign> {
        let upto = questions.iter().map(|&(k, _)| k).max().unwrap_or(0);
        let lambda = Dd::new(at.lambda);
        let flat: Vec<usize> = at.events.iter().map(|e| e.step).filter(|&s| s < upto).collect();
        let mask = flat_mask(at.events);
        let mut prefixes = prefixes;
        let mut enclose = |l: Ball<f64>| match &self.built.hinges {
            Some(_) => self.enclosed(self.f64_pair(), (l, bits), (upto, &flat)),
            None => distances_at(
                prefixes.as_deref_mut().map(|p| &mut p.balls),
                &self.built.f64_balls,
                l,
                bits,
                upto,
                (mask, &flat),
            ),
        };
        let mut realize = |l: f64| self.built.f64_plain.base_distances_flat(l, bits, upto, &flat);
        let fast = self.evaluate(
            self.f64_pair(),
            &self.built.f64_plain,
            bits,
            at,
            lambda,
            questions,
            Some(&mut enclose),
            &mut realize,
        );
        self.count(|c| c.f64 += fast.iter().filter(|v| v.proven.is_some()).count());
        if fast.iter().all(|v| v.proven.is_some()) {
            return fast.into_iter().map(|v| v.proven.expect("all proven")).collect();
        }
        // Double-double balls are about 2^-53 of the f64 ones wide: skip them
        // where even that would not exclude zero.
        let shrink = Dd::UNIT_ROUNDOFF / f64::UNIT_ROUNDOFF * tolerance::DD_BALL_SHRINK_MARGIN;
        let hopeless = |v: &Value| v.radius.zip(v.midpoint).is_some_and(|(r, m)| r * shrink > m.abs());
        let balls = !fast.iter().filter(|v| v.proven.is_none()).all(hopeless);
        // Only the questions f64 left open, with their f64 values.
        let open: Vec<(usize, Kind)> =
            questions.iter().zip(&fast).filter(|(_, f)| f.proven.is_none()).map(|(&q, _)| q).collect();
        let refined = self.refine_dd(bits, at, lambda);
        // A sketch whose shapes close in f64 but not in double-double (a
        // triangle at the feasibility tolerance): nothing more to prove with.
        let (Some(dd_balls), Some(dd)) = (self.dd_pair(), self.dd_plain()) else {
            return fast.iter().map(|f| f.proven.unwrap_or(Sign::Zero)).collect();
        };
        // The open questions, realized only as deep as they reach.
        let upto = open.iter().map(|&(k, _)| k).max().unwrap_or(0);
        let flat: Vec<usize> = flat.into_iter().filter(|&s| s < upto).collect();
        let mut enclose = |l: Ball<Dd>| self.enclosed(dd_balls, (l, bits), (upto, &flat));
        let enclose: Option<&mut dyn FnMut(Ball<Dd>) -> Vec<Ball<Dd>>> = if balls { Some(&mut enclose) } else { None };
        let mut realize =
            |l: Dd| distances_at(prefixes.as_deref_mut().map(|p| &mut p.dd), &dd.plain, l, bits, upto, (mask, &flat));
        let fine = self.evaluate(dd_balls, &dd.plain, bits, at, refined, &open, enclose, &mut realize);
        self.count(|c| c.double_double += fine.iter().filter(|v| v.proven.is_some()).count());
        // What double-double left open, exactly where λ is known exactly.
        let still: Vec<(usize, Kind)> =
            open.iter().zip(&fine).filter(|(_, v)| v.proven.is_none()).map(|(&q, _)| q).collect();
        let mut exact = self.exact_slack_signs(bits, at, &still).into_iter();
        let mut fine = fine.into_iter();
        fast.iter()
            .map(|f| {
                f.proven.unwrap_or_else(|| {
                    let d = fine.next().expect("one answer per open question");
                    d.proven.or_else(|| exact.next().flatten()).unwrap_or_else(|| self.estimate(f, &d))
                })
            })
            .collect()
    }

    /// The signs of `questions` at `at` in exact arithmetic over the input
    /// as written, where λ is exact: an end whose first flat step stands on
    /// the base (λ is its target). There every step reads its exact slack,
    /// so one flat at λ is flat exactly, with no placement forced. Each
    /// answer is proven and counted as exact; `None` where out of reach (an
    /// end λ* that only a root defines; a λ given as an f64 without events,
    /// which callers also use for a rounded candidate, where a touch's zero
    /// is not; a construction deeper than
    /// [`tolerance::EXACT_SLACK_STEPS`], a bound past the exact stage's),
    /// and [`Sign::Undefined`] where an earlier step is proven not to close.
    fn exact_slack_signs(&self, bits: &[bool], at: At, questions: &[(usize, Kind)]) -> Vec<Option<Sign>> {
        let upto = questions.iter().map(|&(k, _)| k).max().unwrap_or(0);
        let lambda = match at.events.first() {
            Some(&e) if self.built.f64_plain.on_base(e.step) => Some(e),
            _ => None,
        };
        let Some(lambda) = lambda.filter(|_| !questions.is_empty() && upto < tolerance::EXACT_SLACK_STEPS) else {
            return vec![None; questions.len()];
        };
        let kinds: Vec<&[Kind]> = (0..upto).map(|j| self.kinds(j)).collect();
        let signs = exact_stage::slack_signs(&self.built.linkage, &self.built.dec, (bits, lambda), &kinds, questions);
        let signs = signs.unwrap_or_else(|| vec![None; questions.len()]);
        self.count(|c| c.exact += signs.iter().filter(|s| s.is_some()).count());
        signs
    }

    /// A sign the balls could not prove: ball radii grow with every level of
    /// a deep construction far faster than the real error, so past them the
    /// double-double value decides when it exceeds its error estimated as
    /// the f64 error (f64 − double-double) scaled to double-double precision
    /// with a margin of 2^10 ([`Self::estimated_error`]); otherwise the
    /// value is taken as zero. Counted in [`Self::estimated`].
    ///
    /// Past a step f64 failed to close by more than its tolerance
    /// ([`tolerance::FEASIBLE`]) while double-double closes it, f64 has no
    /// value: its error there is at least that tolerance, and is taken as
    /// that (the step is not taken for flat for want of an f64 value).
    fn estimate(&self, f: &Value, d: &Value) -> Sign {
        let Some(y) = d.midpoint else {
            return if f.midpoint.is_none() { Sign::Undefined } else { Sign::Zero };
        };
        self.count(|c| c.estimated += 1);
        let scale = self.built.f64_balls.scale;
        let error = self.estimated_error(f.midpoint.map_or(tolerance::FEASIBLE * scale, |x| (x - y).abs()));
        if y.abs() > error { if y > 0.0 { Sign::Positive } else { Sign::Negative } } else { Sign::Zero }
    }

    /// The error [`Self::estimate`] gives a double-double value whose f64
    /// value is `f64_error` off it.
    fn estimated_error(&self, f64_error: f64) -> f64 {
        f64_error * (Dd::UNIT_ROUNDOFF / f64::UNIT_ROUNDOFF) * tolerance::ESTIMATE_MARGIN
            + tolerance::ESTIMATE_FLOOR_ULPS * Dd::UNIT_ROUNDOFF * self.built.f64_balls.scale
    }

    /// Count `n` decisions again that rested on an estimate: the sweep's
    /// refinements repeated for another type (each type's decision counts).
    pub fn count_estimated(&self, n: usize) {
        self.count(|c| c.estimated += n);
    }

    /// Set the decisions counted back to `counts`: those since were
    /// discarded (a lazy walk that the sweep answers instead).
    pub(crate) fn rewind_counts(&self, counts: StageCounts) {
        self.counts.set(counts);
    }

    /// Set the count of [`Self::estimated`] back to `n`: a lazy walk's turn
    /// walked ahead and undone.
    pub(crate) fn rewind_estimated(&self, n: usize) {
        self.count(|c| c.estimated = n);
    }

    /// How many decisions so far rested on an estimate (see `estimate`) rather than a proof.
    pub fn estimated(&self) -> usize {
        self.counts.get().estimated
    }

    /// The root of step `k`'s slack for `kind` between `a` and `b` (in
    /// either order), where its proven signs differ: bisection on this
    /// certifier's signs to full precision. Where two roots lie closer
    /// than f64 resolves the slack near them, Newton on f64 values cannot
    /// place either. The signs it cannot prove lie within its resolution of
    /// the root and only place it, so they are not counted as estimates.
    pub fn slack_root_between<T: Real>(&self, bits: &[bool], (k, kind): (usize, Kind), [a, b]: [T; 2]) -> T {
        let estimated = self.estimated();
        let sign = |x: T| self.slack_sign(bits, At { lambda: x.to_f64(), events: &[] }, k, kind).to_i8();
        let (lo, hi) = if a < b { (a, b) } else { (b, a) };
        let root = crate::roots::bisect(lo, hi, T::zero(), sign);
        self.rewind_estimated(estimated);
        root
    }

    /// Whether step `k` closes at a λ inside an interval (taken as exact):
    /// both slacks proven positive, one proven negative, or — with equal
    /// sides, where the folded slack is the base distance d itself — d zero
    /// to double-double resolution: a degenerate step whose base joints
    /// coincide (its vertex turns freely, as in a folded rhombus).
    /// `prefixes` as in [`Self::slack_signs_in`].
    pub fn closes(&self, prefixes: Option<&mut Prefixes>, bits: &[bool], lambda: f64, k: usize) -> Closes {
        let at = At { lambda, events: &[] };
        let questions = [(k, Kind::Stretched), (k, Kind::Folded)];
        let signs = match prefixes {
            Some(p) => self.slack_signs_kept(p, bits, at, questions),
            None => self.slack_signs(bits, at, &questions).try_into().expect("two answers"),
        };
        let equal_sides = self.kinds(k).len() == 1;
        if signs.contains(&Sign::Negative) {
            Closes::No
        } else if equal_sides && signs[1] == Sign::Zero {
            Closes::Degenerate
        } else if signs.iter().all(|&s| s == Sign::Positive) {
            Closes::Yes
        } else {
            Closes::Unknown
        }
    }

    /// Each question's slack at `at` in `con`'s balls: its proven sign, and
    /// its midpoint (the plain value in `T`). Without a proven bracket of
    /// the end, nothing is proven and the midpoints are taken at `lambda`.
    /// `enclose` computes the base distances at the bracket (`None`: no
    /// bracket is sought, the balls prove nothing; the caller passes `None`
    /// where even double-double balls would not exclude zero), `realize`
    /// the plain ones at λ (both as deep as the questions reach, the flat
    /// steps placed flat).
    #[allow(clippy::too_many_arguments)]
    fn evaluate<T: Real>(
        &self,
        balls: Balls<T>,
        plain: &Construction<T>,
        bits: &[bool],
        at: At,
        lambda: Dd,
        questions: &[(usize, Kind)],
        enclose: Option<&mut dyn FnMut(Ball<T>) -> Vec<Ball<T>>>,
        realize: &mut dyn FnMut(T) -> Vec<T>,
    ) -> Vec<Value> {
        let bracket = if enclose.is_some() { self.bracket(balls, bits, at, lambda) } else { None };
        let con = balls.0;
        let enclosures = bracket.zip(enclose).map(|(l, f)| f(l)).unwrap_or_default();
        // The plain values are only needed where a ball proves nothing.
        // Where the balls were computed their midpoints serve: each ball
        // operation computes its midpoint as `T` does, from the bracket's
        // centre λ (f64 balls square hypot's components where f64 calls
        // libm, a last-bit difference: either is an evaluation in `T`, all
        // that `estimate` and the hopeless test read). A plain realization
        // only where no ball was.
        let all_proven = questions.iter().all(|&(k, kind)| {
            enclosures.get(k).is_some_and(|&d| kind.slack_value(con.steps[k].r1, con.steps[k].r2, d).sign().is_some())
        });
        let values = if all_proven {
            Vec::new()
        } else if !enclosures.is_empty() {
            enclosures.iter().map(|d| d.m).collect()
        } else {
            realize(T::from_dd(lambda))
        };
        questions
            .iter()
            .map(|&(k, kind)| {
                let ball = enclosures.get(k).map(|&d| kind.slack_value(con.steps[k].r1, con.steps[k].r2, d));
                let s = &plain.steps[k];
                let proven = match (ball, values.get(k)) {
                    (Some(b), _) => Sign::of(b.sign()),
                    // Steps after the first that cannot close have no distance.
                    (None, None) => bracket.map(|_| Sign::Undefined),
                    (None, Some(_)) => None,
                };
                let midpoint =
                    values.get(k).map(|&d| kind.slack_value(s.r1, s.r2, d).to_f64()).filter(|m| m.is_finite());
                Value { proven, midpoint, radius: ball.map(|b| b.r) }
            })
            .collect()
    }

    /// An enclosure of the end λ* near `lambda`: for an end with a flat step,
    /// the smallest tried bracket whose ends have proven opposite signs of
    /// that step's slack; inside an interval, λ itself (exact).
    fn bracket<T: Real>(&self, balls: Balls<T>, bits: &[bool], at: At, lambda: Dd) -> Option<Ball<T>> {
        let con = balls.0;
        let Some(&event) = at.events.first() else { return Some(Ball::exact(T::from_dd(lambda))) };
        // A step on the base is flat where λ is its target: the ball of that
        // target from the lengths as written encloses the end (no search).
        if con.on_base(event.step) {
            let s = &con.steps[event.step];
            return Some(event.kind.target(s.r1, s.r2));
        }
        // The search depends only on the bits before the flat step: cache it
        // (every later step asks about the same end).
        let key = prefix_word(bits, event.step).map(|prefix| {
            let dd = T::UNIT_ROUNDOFF < f64::UNIT_ROUNDOFF;
            ([lambda.hi.to_bits(), lambda.lo.to_bits()], event, prefix, dd)
        });
        if let Some(radius) = key.as_ref().and_then(|k| self.brackets.borrow().get(k).copied()) {
            return radius.map(|r| Ball { m: T::from_dd(lambda), r });
        }
        let found = self.search_bracket(balls, bits, event, lambda);
        if let Some(k) = key {
            self.brackets.borrow_mut().insert(k, found.map(|b| b.r));
        }
        found
    }

    /// The bracket search of [`Self::bracket`] for an end where `event` is flat.
    fn search_bracket<T: Real>(&self, balls: Balls<T>, bits: &[bool], event: Event, lambda: Dd) -> Option<Ball<T>> {
        // One block of positions for every realization of the search.
        let pos = RefCell::new(Vec::new());
        let con = balls.0;
        let ancestors = con.ancestors(event.step);
        let slack_ball = |x: T| self.flat_slack_ball(balls, &mut pos.borrow_mut(), &ancestors, bits, event, x);
        let centre = T::from_dd(lambda);
        let scale = con.scale;
        // A slack whose ball at the centre is already wider than the widest
        // bracket tried cannot prove a sign change there: skip the search.
        let width = slack_ball(centre)?.r;
        if width.is_nan() || width >= tolerance::BALL_TOO_WIDE * scale {
            return None;
        }
        // At least the smallest subnormal, so that the search grows even for
        // scenes at the bottom of f64's range.
        let mut delta = (tolerance::LAMBDA_RESOLUTION_ULPS * T::UNIT_ROUNDOFF * lambda.to_f64().abs().max(scale))
            .max(f64::from_bits(1));
        while delta < tolerance::END_BRACKET_MAX * scale {
            let (lo, hi) = (centre - T::from_f64(delta), centre + T::from_f64(delta));
            let (a, b) = (slack_ball(lo), slack_ball(hi));
            if let (Some(x), Some(y)) = (a.and_then(|a| a.sign()), b.and_then(|b| b.sign()))
                && x != y
            {
                return Some(Ball { m: centre, r: delta * (1.0 + tolerance::BRACKET_RADIUS_MARGIN) });
            }
            delta = next_half_width(delta, a.zip(b));
        }
        None
    }

    /// The ball of the slack of `event`'s step at exactly `x`, or `None`
    /// where its prefix fails or a ball it depends on overflowed (that
    /// proves nothing downstream: the realization stops there).
    /// `ancestors` are the flat step's ([`Construction::ancestors`]).
    fn flat_slack_ball<T: Real>(
        &self,
        balls: Balls<T>,
        pos: &mut Vec<P2<Ball<T>>>,
        ancestors: &[bool],
        bits: &[bool],
        event: Event,
        x: T,
    ) -> Option<Ball<T>> {
        let (k, lambda, con) = (event.step, Ball::exact(x), balls.0);
        let overflowed = |j: usize, d: &Ball<T>| ancestors[j] && !d.r.is_finite();
        let d = match &self.built.hinges {
            Some(h) => *h.enclosures(balls, (lambda, bits), (k, &[]), overflowed)?.get(k)?,
            None => con.prefix_distance_unless(pos, lambda, bits, k, overflowed).ok()??,
        };
        let s = &con.steps[k];
        Some(event.kind.slack_value(s.r1, s.r2, d))
    }

    /// The base distances d_0, …, d_upto in balls at `lambda`, as
    /// [`Construction::base_distances_flat`] gives them, each enclosed in
    /// its frame ([`Hinges`]) where the construction has them.
    fn enclosed<T: Real>(
        &self,
        balls: Balls<T>,
        (lambda, bits): (Ball<T>, &[bool]),
        (upto, flat): (usize, &[usize]),
    ) -> Vec<Ball<T>> {
        match &self.built.hinges {
            Some(h) => h.enclosures(balls, (lambda, bits), (upto, flat), |_, _| false).unwrap_or_default(),
            None => balls.0.base_distances_flat(lambda, bits, upto, flat),
        }
    }

    /// The end's λ located in double-double: Newton on the flat step's
    /// slack from the f64 value (a few steps double the digits each). It
    /// stops at the rounding floor: a step no smaller than the one before is
    /// rounding noise and is not taken; and once Newton's next step,
    /// predicted from the last two (s_{k+1} ≈ s_k³ / s_{k-1}², quadratic
    /// convergence), is below the resolution, it is not computed (a noisy
    /// s_k only overstates it, so the stop is never early).
    /// Each end is located once per type prefix (cached, see `refined`).
    fn refine_dd(&self, bits: &[bool], at: At, lambda: Dd) -> Dd {
        let Some(&event) = at.events.first() else { return lambda };
        // A step on the base is flat at its target (in double-double).
        if self.built.f64_plain.on_base(event.step)
            && let Some(dd) = self.dd_plain()
        {
            let s = &dd.plain.steps[event.step];
            return event.kind.target(s.r1, s.r2);
        }
        let key = prefix_word(bits, event.step).map(|p| ([lambda.hi.to_bits(), lambda.lo.to_bits()], event, p));
        if let Some(x) = key.as_ref().and_then(|k| self.refined.borrow().get(k).copied()) {
            return x;
        }
        let x = self.newton_dd(bits, event, lambda);
        if let Some(k) = key {
            self.refined.borrow_mut().insert(k, x);
        }
        x
    }

    /// The Newton iteration of [`Self::refine_dd`] for an end where `event`
    /// is flat: the slack's values in double-double, its slope once, in f64
    /// at the f64 end (a chord iteration: the slope's relative error, about
    /// the f64 end's, turns the quadratic convergence into a linear one at
    /// that rate, so from an f64 end it takes the same two iterations, each
    /// a plain double-double realization instead of one with slopes, 40%
    /// cheaper). Without a finite nonzero slope (a square-root end) λ stays.
    fn newton_dd(&self, bits: &[bool], event: Event, lambda: Dd) -> Dd {
        let Some(dd) = self.dd_plain() else { return lambda };
        let mut pos = Vec::new();
        let at = Slope::variable(lambda.to_f64());
        let Ok(d) = dd.f64_slopes.prefix_distance_into(&mut pos, at, bits, event.step) else { return lambda };
        let s = &dd.f64_slopes.steps[event.step];
        let slope = event.kind.slack_value(s.r1, s.r2, d).d;
        if !(slope.is_finite() && slope != 0.0) {
            return lambda;
        }
        let con = &dd.plain;
        let s = &con.steps[event.step];
        let mut x = lambda;
        let mut last = f64::INFINITY;
        let mut pos = Vec::new();
        for _ in 0..tolerance::DD_NEWTON_STEPS {
            let Ok(d) = con.prefix_distance_into(&mut pos, x, bits, event.step) else { break };
            let step = event.kind.slack_value(s.r1, s.r2, d) / Dd::new(slope);
            let size = step.to_f64().abs();
            if !size.is_finite() || size > tolerance::DD_NEWTON_MAX_STEP * con.scale || size >= last {
                break;
            }
            x = x - step;
            let resolution = tolerance::NEWTON_CONVERGED_ULPS * Dd::UNIT_ROUNDOFF * x.to_f64().abs();
            if size <= resolution || (last.is_finite() && size * (size / last).powi(2) <= resolution) {
                break;
            }
            last = size;
        }
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cayley_space::tests::{PEAUCELLIER, every_base};
    use crate::cayley_space::{Method, cayley_space};

    /// A bracket search's next half-width: where a linear slack's secant
    /// says its change clears the radii twice over, kept within 2 and 256
    /// times the last; 16 times it without a secant (a side that did not
    /// realize) or with a flat one.
    #[test]
    fn next_half_width_follows_the_secant_within_bounds() {
        let ball = |m: f64, r: f64| Ball { m, r };
        let sides = |slope: f64, delta: f64, r: f64| Some((ball(-slope * delta, r), ball(slope * delta, r)));
        let next = next_half_width(1e-13, sides(0.25, 1e-13, 3e-12));
        assert!((next - 2.0 * 3e-12 / 0.25).abs() <= 1e-12 * next, "{next}");
        assert!(0.25 * next >= 2.0 * 3e-12 * (1.0 - 1e-12));
        assert_eq!(next_half_width(1e-13, sides(1e3, 1e-13, 1e-12)), 2e-13);
        assert_eq!(next_half_width(1e-13, sides(1e-9, 1e-13, 1e-12)), 256.0 * 1e-13);
        assert_eq!(next_half_width(1e-13, sides(0.0, 1e-13, 1e-12)), 16.0 * 1e-13);
        assert_eq!(next_half_width::<f64>(1e-13, None), 16.0 * 1e-13);
    }

    /// Kept prefixes give the distances a fresh realization gives, at every
    /// interval end of Peaucellier's inversor on every base, for every type
    /// asked in two orders: each question cuts or extends the kept prefix,
    /// across the bits of the steps flat there (shared) and of the others.
    #[test]
    fn kept_distances_are_the_fresh_ones() {
        let mut flat_before_last = 0;
        for (base, dec, cx, con, cert) in every_base(PEAUCELLIER, "peaucellier") {
            let space = cayley_space(&con, &cert, &dec, &cx, Method::Exact);
            let balls = &cert.built.f64_balls;
            let n = con.steps.len();
            let mut kept = Kept::default();
            for end in space.intervals.iter().flat_map(|iv| [&iv.lower, &iv.upper]) {
                let mask = flat_mask(&end.events).expect("few steps");
                let flat: Vec<usize> = end.events.iter().map(|e| e.step).collect();
                flat_before_last += usize::from(flat.iter().any(|&s| s + 1 < n));
                let lambda = Ball::exact(end.lambda);
                // Every type in two orders, each asked to the last step and
                // to a shallower one (a shorter question after a longer one
                // resumes below positions the longer one placed).
                for code in (0..1usize << n).chain((0..1usize << n).rev()) {
                    let bits: Vec<bool> = (0..n).map(|i| code >> i & 1 == 1).collect();
                    for upto in [n - 1, 1 + code % (n - 1)] {
                        let flat: Vec<usize> = flat.iter().copied().filter(|&s| s < upto).collect();
                        let fresh = balls.base_distances_flat(lambda, &bits, upto, &flat);
                        let got = kept.distances(balls, lambda, &bits, upto, mask);
                        let parts = |d: &[Ball<f64>]| d.iter().map(|b| (b.m, b.r)).collect::<Vec<_>>();
                        assert_eq!(
                            parts(got),
                            parts(&fresh),
                            "base {base:?} at {} type {bits:?} to {upto}",
                            end.lambda
                        );
                    }
                }
            }
        }
        assert!(flat_before_last > 0, "some end has a flat step that a later step builds on");
    }
}
