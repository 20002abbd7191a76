//! The root finder's parts, shared by the exhaustive sweep (`cayley_space`)
//! and the lazy walk (`lazy`): both look for the λ at which a step's slack
//! reaches zero (THEORY.md §2), and both need
//! - the interval ends they find, with ids shared across types ([`Endpoint`], [`EndpointIds`]);
//! - the cosine-spaced sample grid ([`cosine_sample`]);
//! - d_k(λ) with its slope and curvature for a type prefix ([`base_distance_at`]);
//! - bracketed root finding: [`bisect`] on a sign, [`newton`] safeguarded by its bracket;
//! - what the jets say at a root: the slack's sign on either side ([`side_signs`]), and
//!   whether an extremum of the slack is a touch ([`Extremum`]).
//!
//! Generic over the scalar type, so that a double-double run is the reference.

use std::cmp::Ordering;

use crate::real::Real;
use crate::realize::{Construction, Event, P2, RealizationType};
use crate::tolerance;

/// The flat steps at an interval end: one in a generic scene, two where two
/// steps are flat at once, more only at a non-generic place. Up to two are
/// held inline: an end is copied into every piece and interval that reaches
/// it, and a list on the heap per copy was a sixth of a four-bar sweep's
/// allocations. Compares, hashes and prints as the list it holds.
#[derive(Clone)]
pub struct Events(EventList);

#[derive(Clone)]
enum EventList {
    Inline(u8, [Event; 2]),
    Heap(Vec<Event>),
}

impl Events {
    /// No flat step.
    pub const fn new() -> Self {
        const UNUSED: Event = Event { step: 0, kind: crate::realize::Kind::Stretched };
        Events(EventList::Inline(0, [UNUSED; 2]))
    }

    /// One flat step.
    pub fn one(e: Event) -> Self {
        Events(EventList::Inline(1, [e, e]))
    }

    /// Add a flat step at the end.
    pub fn push(&mut self, e: Event) {
        match &mut self.0 {
            EventList::Inline(n, items) if usize::from(*n) < items.len() => {
                items[usize::from(*n)] = e;
                *n += 1;
            }
            EventList::Inline(_, items) => {
                let mut heap = items.to_vec();
                heap.push(e);
                self.0 = EventList::Heap(heap);
            }
            EventList::Heap(v) => v.push(e),
        }
    }
}

impl Default for Events {
    fn default() -> Self {
        Events::new()
    }
}

impl std::ops::Deref for Events {
    type Target = [Event];
    fn deref(&self) -> &[Event] {
        match &self.0 {
            EventList::Inline(n, items) => &items[..usize::from(*n)],
            EventList::Heap(v) => v,
        }
    }
}

impl<'a> IntoIterator for &'a Events {
    type Item = &'a Event;
    type IntoIter = std::slice::Iter<'a, Event>;
    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

impl From<Vec<Event>> for Events {
    fn from(list: Vec<Event>) -> Self {
        let mut events = Events::new();
        for e in list {
            events.push(e);
        }
        events
    }
}

impl PartialEq for Events {
    fn eq(&self, other: &Self) -> bool {
        self[..] == other[..]
    }
}

impl Eq for Events {}

impl std::fmt::Debug for Events {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

/// An interval end: its λ, the flat steps there (one in a generic scene),
/// and an id shared by every type whose interval ends at this same root.
#[derive(Clone, Debug, PartialEq)]
pub struct Endpoint<T> {
    /// The base length λ of the end (scene units).
    pub lambda: T,
    /// The steps flat there; empty at an end that is no root (the start of a search).
    pub events: Events,
    /// Equal for the ends of two types that meet at this root.
    pub id: usize,
}

impl<T> Endpoint<T> {
    /// Whether `other`, an end of type `other_ty`, is this end of type `ty`
    /// by the flip rule: the same root, and the types one step flat here
    /// apart (the step's two orientations coincide there, so one
    /// realization). One step only: two flat steps flipped at once can be
    /// another realization (Peaucellier's fold).
    pub fn flips_to(&self, ty: &RealizationType, other: &Endpoint<T>, other_ty: &RealizationType) -> bool {
        self.id == other.id && self.events.iter().any(|e| &ty.flipped(e.step) == other_ty)
    }
}

/// Hands out endpoint ids: one per root found, counting from 1.
#[derive(Clone, Debug, Default)]
pub struct EndpointIds {
    last: usize,
}

impl EndpointIds {
    /// Ids from `last + 1` on.
    pub fn after(last: usize) -> Self {
        EndpointIds { last }
    }
    /// A new endpoint at `lambda` with the flat steps `events`, under a fresh id.
    pub fn make<T>(&mut self, lambda: T, events: Events) -> Endpoint<T> {
        self.last += 1;
        Endpoint { lambda, events, id: self.last }
    }
}

/// Sample `i` of `n` (i = 0..=n) from `from` toward `to`:
/// from + (to − from)(1 − cos(πi/n))/2, dense near both ends, where d_k
/// behaves like a square root. Sample n is computed like the others, so it
/// may differ from `to` by rounding: a caller that must land on `to` uses it.
pub fn cosine_sample<T: Real>(from: T, to: T, i: usize, n: usize) -> T {
    let c = (std::f64::consts::PI * i as f64 / n as f64).cos();
    from + (to - from) * T::from_f64(0.5) * T::from_f64(1.0 - c)
}

/// Step `k`'s base distance d_k at `lambda` for the type prefix `bits` (at
/// least `k` bits), in the construction's arithmetic (`Jet::variable(λ)`
/// gives its slope and curvature in λ, `Slope::variable(λ)` its slope),
/// realized into `pos` (the caller's block of positions, reused); `None`
/// where an earlier step cannot close or the distance is not finite.
pub fn base_distance_at<D: Real>(
    con: &Construction<D>,
    pos: &mut Vec<P2<D>>,
    bits: &[bool],
    k: usize,
    lambda: D,
) -> Option<D> {
    let d = con.prefix_distance_into(pos, lambda, bits, k).ok()?;
    d.to_f64().is_finite().then_some(d)
}

/// The sign of `x` as −1, 0 or +1 (0 for zero and NaN).
pub fn sign<T: Real>(x: T) -> i8 {
    if x > T::zero() {
        1
    } else if x < T::zero() {
        -1
    } else {
        0
    }
}

/// A total order for sorting λ values (NaN compares equal to everything).
pub fn cmp<T: Real>(a: &T, b: &T) -> Ordering {
    a.partial_cmp(b).unwrap_or(Ordering::Equal)
}

/// Whether `x` lies strictly between `a` and `b` (in either order).
pub fn between<T: Real>(x: T, a: T, b: T) -> bool {
    (x > a && x < b) || (x > b && x < a)
}

/// The root nearest zero of c0 + c1·x + c2·x², in the form without
/// cancellation (−2c0 / (c1 ± √(c1² − 4c2·c0)), the sign of c1); `None`
/// where the roots are not real.
pub fn quadratic_root<T: Real>(c0: T, c1: T, c2: T) -> Option<T> {
    let disc = c1 * c1 - T::from_f64(4.0) * c2 * c0;
    (disc >= T::zero()).then(|| {
        let root = disc.sqrt();
        -T::from_f64(2.0) * c0 / (if c1 >= T::zero() { c1 + root } else { c1 - root })
    })
}

/// Signs of a slack just left and right of a root (−1, 0 or +1), read
/// from its slope there, or at a tangency (slope below
/// [`tolerance::tangent_slope`] for `T`) from its curvature (asked for only
/// then), the same on both sides.
pub fn side_signs<T: Real>(slope: T, curvature: impl FnOnce() -> T) -> (i8, i8) {
    let slope_tol = T::from_f64(tolerance::tangent_slope(T::UNIT_ROUNDOFF));
    if slope.abs() > slope_tol {
        (-sign(slope), sign(slope))
    } else {
        let c = sign(curvature());
        (c, c)
    }
}

/// Where the value of a function at its extremum lies against zero, with
/// `touch` the root finder's resolution ([`tolerance::ROOT_VALUE`] × scale).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Extremum {
    /// Above `touch`.
    Above,
    /// Within `touch` of zero: a tangent (double) root. Unless `exact` (the
    /// value is zero), two roots and none cannot be told apart there.
    Touch {
        /// The value is exactly zero.
        exact: bool,
    },
    /// Below `-touch`, or not a number.
    Below,
}

impl Extremum {
    /// Classify the value `v` at an extremum against the resolution `touch` (≥ 0).
    pub fn of<T: Real>(v: T, touch: T) -> Extremum {
        if v > touch {
            Extremum::Above
        } else if v >= -touch {
            Extremum::Touch { exact: v == T::zero() }
        } else {
            Extremum::Below
        }
    }
}

/// Bisection on a sign function with different signs at `a` and `b`, until
/// the bracket is no wider than `stop` (zero: to full precision, at most
/// [`tolerance::ROOT_MAX_ITERATIONS`] halvings). The midpoint of the last bracket.
pub fn bisect<T: Real>(mut a: T, mut b: T, stop: T, f: impl Fn(T) -> Option<i8>) -> T {
    let sa = f(a).unwrap_or(0);
    for _ in 0..tolerance::ROOT_MAX_ITERATIONS {
        if b - a <= stop {
            break;
        }
        let m = (a + b) / T::from_f64(2.0);
        if !(m > a && m < b) {
            break;
        }
        match f(m) {
            Some(0) => return m,
            Some(s) if s == sa => a = m,
            _ => b = m,
        }
    }
    (a + b) / T::from_f64(2.0)
}

/// A root of g between a (g > 0) and b (g ≤ 0, or undefined): Newton steps
/// from g's value and derivative (`f` gives both, in λ) while they stay
/// inside the shrinking bracket, bisection otherwise; to full precision.
/// The point of least |g| seen when the iterations run out.
pub fn newton<T: Real>(a: T, b: T, f: impl Fn(T) -> Option<(T, T)>) -> T {
    newton_seeded(a, b, None, f).root
}

/// What [`newton_seeded`] found and what it cost.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewtonRun<T> {
    /// The root (or the point of least |g| seen).
    pub root: T,
    /// Calls of `f`.
    pub evaluations: usize,
}

/// [`newton`] with a known evaluation `seed` = (x, g(x), g′(x)) inside or at
/// an end of the bracket (typically its far end, already evaluated as a
/// sample or a root of another step): the first step is taken from it at no
/// cost instead of from the midpoint.
///
/// Stops when a step is rounding noise: within
/// [`tolerance::NEWTON_CONVERGED_ULPS`] of x, or predicted to leave the
/// next one that close (quadratic convergence: the next step is about
/// step³/last², once a step is under a quarter of the last), or — at the rounding floor,
/// where g's value is its rounding error and Newton steps stop shrinking —
/// when a Newton step is no shorter than the one before and both are below
/// [`tolerance::NEWTON_FLOOR`] of the bracket's magnitude. At the floor every
/// point is as good a root as f64 resolves: the secant root between the
/// bracket's evaluated ends is tried (one more evaluation), and the point of
/// least |g| seen is returned.
pub fn newton_seeded<T: Real>(a: T, b: T, seed: Option<(T, T, T)>, f: impl Fn(T) -> Option<(T, T)>) -> NewtonRun<T> {
    newton_run(a, b, seed, None, Chart::Line, f)
}

/// [`newton`] with its first evaluation at `start` (strictly inside the
/// bracket; else at the midpoint): a guess from what is known of g without
/// its derivative.
pub fn newton_from<T: Real>(a: T, b: T, start: T, f: impl Fn(T) -> Option<(T, T)>) -> NewtonRun<T> {
    newton_run(a, b, None, Some(start).filter(|&s| between(s, a, b)), Chart::Line, f)
}

/// [`newton_from`] where g goes as √|λ − b| next to b (b is where an earlier
/// step is flat, and its vertex rises as that square root): there Newton in
/// λ crawls, so it runs in u = √|λ − b|, where g is smooth, and stops as
/// [`newton_seeded`] does, by the step's length in λ.
pub fn newton_from_end<T: Real>(a: T, b: T, start: T, f: impl Fn(T) -> Option<(T, T)>) -> NewtonRun<T> {
    let sign = if a > b { T::from_f64(1.0) } else { T::from_f64(-1.0) };
    let (width, u) = ((a - b).abs().sqrt(), (start - b).abs().sqrt());
    let start = Some(u).filter(|&u| between(u, width, T::zero()));
    newton_run(width, T::zero(), None, start, Chart::Root { end: b, sign }, f)
}

/// The coordinate Newton runs in.
#[derive(Clone, Copy, Debug)]
enum Chart<T> {
    /// λ itself.
    Line,
    /// u ≥ 0 with λ = end + sign·u².
    Root { end: T, sign: T },
}

impl<T: Real> Chart<T> {
    fn lambda(self, x: T) -> T {
        match self {
            Chart::Line => x,
            Chart::Root { end, sign } => end + sign * x * x,
        }
    }
    /// dλ/dx.
    fn slope(self, x: T) -> T {
        match self {
            Chart::Line => T::from_f64(1.0),
            Chart::Root { sign, .. } => T::from_f64(2.0) * sign * x,
        }
    }
}

fn newton_run<T: Real>(
    a: T,
    b: T,
    seed: Option<(T, T, T)>,
    start: Option<T>,
    chart: Chart<T>,
    f: impl Fn(T) -> Option<(T, T)>,
) -> NewtonRun<T> {
    // g and dg/dx at x (f gives them in λ).
    let f = |x: T| f(chart.lambda(x)).map(|(g, dg)| (g, dg * chart.slope(x)));
    let done = |root: T, evaluations: usize| NewtonRun { root: chart.lambda(root), evaluations };
    let (mut pos, mut neg) = (a, b);
    let two = T::from_f64(2.0);
    let mut x = start.unwrap_or((a + b) / two);
    let mut best = (x, T::from_f64(f64::INFINITY));
    let mut evaluations = 0;
    let converged = T::from_f64(tolerance::NEWTON_CONVERGED_ULPS * T::UNIT_ROUNDOFF);
    let (la, lb) = (chart.lambda(a).abs(), chart.lambda(b).abs());
    let floor = T::from_f64(tolerance::NEWTON_FLOOR) * (if la > lb { la } else { lb });
    // Steps and their lengths are measured in λ.
    let mut last_step: Option<T> = None;
    // g at the bracket's ends, once evaluated there.
    let (mut g_pos, mut g_neg): (Option<T>, Option<T>) = (None, None);
    let mut known = seed.filter(|&(s, _, _)| s == a || s == b || between(s, a, b));
    for _ in 0..tolerance::ROOT_MAX_ITERATIONS {
        let evaluated = match known.take() {
            Some((s, g, dg)) => {
                x = s;
                Some((g, dg))
            }
            None => {
                evaluations += 1;
                f(x)
            }
        };
        let Some((g, dg)) = evaluated else {
            neg = x;
            x = (pos + neg) / two;
            last_step = None;
            if !between(x, pos, neg) {
                break;
            }
            continue;
        };
        if g.abs() < best.1 {
            best = (x, g.abs());
        }
        if g == T::zero() {
            return done(x, evaluations);
        }
        if g > T::zero() {
            pos = x;
            g_pos = Some(g);
        } else {
            neg = x;
            g_neg = Some(g);
        }
        let step = g / dg;
        let next = x - step;
        let length = step.abs() * chart.slope(x).abs();
        // A NaN step is no shorter either.
        let shrinks = |l: T| length.partial_cmp(&l) == Some(std::cmp::Ordering::Less);
        if last_step.is_some_and(|l: T| !shrinks(l) && l <= floor) {
            let secant = g_pos.zip(g_neg).map(|(gp, gn)| pos - gp * (neg - pos) / (gn - gp));
            if let Some(s) = secant.filter(|&s| between(s, pos, neg)) {
                evaluations += 1;
                if let Some((g, _)) = f(s)
                    && g.abs() <= best.1
                {
                    return done(s, evaluations);
                }
            }
            return done(best.0, evaluations);
        }
        if between(next, pos, neg) && step.to_f64().is_finite() {
            let here = chart.lambda(next).abs();
            if length <= converged * chart.lambda(x).abs() {
                return done(next, evaluations);
            }
            // Converging quadratically (this step under a quarter of the
            // last), the next would be about step³/last²: below rounding, so
            // this step lands as close as f64 resolves, with no evaluation.
            let quarter = T::from_f64(0.25);
            if let Some(l) = last_step
                && length <= quarter * l
                && length * (length / l) * (length / l) <= converged * here
            {
                return done(next, evaluations);
            }
            last_step = Some(length);
            x = next;
        } else {
            last_step = None;
            let mid = (pos + neg) / two;
            if !between(mid, pos, neg) {
                break;
            }
            x = mid;
        }
    }
    done(best.0, evaluations)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Inline or on the heap, a list of flat steps reads, compares and
    /// prints as the same list, in the order pushed.
    #[test]
    fn events_are_the_list_pushed() {
        use crate::realize::Kind;
        let e = |step: usize| Event { step, kind: if step.is_multiple_of(2) { Kind::Stretched } else { Kind::Folded } };
        let mut grown = Events::new();
        assert!(grown.is_empty());
        for n in 1..=5 {
            grown.push(e(n));
            let expected: Vec<Event> = (1..=n).map(e).collect();
            assert_eq!(grown[..], expected[..]);
            assert_eq!(grown, Events::from(expected.clone()));
            assert_eq!(format!("{grown:?}"), format!("{expected:?}"));
        }
        assert_eq!(Events::one(e(3))[..], [e(3)]);
        assert_ne!(Events::one(e(3)), Events::one(e(4)));
        assert_ne!(Events::one(e(3)), Events::from(vec![e(3), e(3)]));
    }

    /// g(x) = 2 − x² on [1, 2]: positive at 1, negative at 2, root √2.
    fn g(x: f64) -> Option<(f64, f64)> {
        Some((2.0 - x * x, -2.0 * x))
    }

    #[test]
    fn newton_finds_the_root_and_counts_its_evaluations() {
        let run = newton_seeded(1.0, 2.0, None, g);
        assert!((run.root - 2f64.sqrt()).abs() <= 4.0 * f64::EPSILON);
        // From the midpoint 1.5: quadratic convergence, a handful of steps.
        assert!((3..=6).contains(&run.evaluations), "{run:?}");
        assert_eq!(newton(1.0, 2.0, g), run.root);
    }

    /// g(λ) = u − 1/20 + 3u²/10 with u = √(1 − λ): a square root at the
    /// end λ = 1, as a later step's slack next to an earlier step's flat
    /// point, with its root near that end (u ≈ 0.049 of the bracket's 1).
    #[test]
    fn newton_runs_in_the_square_root_next_to_an_end() {
        let g = |x: f64| {
            let u = (1.0 - x).sqrt();
            Some((u - 0.05 + 0.3 * u * u, -0.5 / u - 0.3))
        };
        let u = ((1.0f64 + 0.06).sqrt() - 1.0) / 0.6;
        let root = 1.0 - u * u;
        // From the root of the line through the ends' values in u.
        let start = 1.0 - (0.05f64 / 1.3).powi(2);
        let in_u = newton_from_end(0.0, 1.0, start, g);
        let in_lambda = newton_from(0.0, 1.0, start, g);
        for run in [in_u, in_lambda] {
            assert!((run.root - root).abs() <= 4.0 * f64::EPSILON, "{run:?} vs {root}");
        }
        assert!(in_u.evaluations < in_lambda.evaluations, "{in_u:?} vs {in_lambda:?}");
        assert!(in_u.evaluations <= 3, "{in_u:?}");
    }

    #[test]
    fn a_seed_at_a_known_root_costs_nothing() {
        let r = 2f64.sqrt();
        let (v, d) = g(r).unwrap();
        let run = newton_seeded(1.0, 2.0, Some((r, 0.0, d)), g);
        assert_eq!((run.root, run.evaluations), (r, 0));
        // Seeded next to the root, far fewer evaluations than from the midpoint.
        let near = r + 1e-9;
        let (vn, dn) = g(near).unwrap();
        let seeded = newton_seeded(1.0, near, Some((near, vn, dn)), g);
        assert!((seeded.root - r).abs() <= 4.0 * f64::EPSILON && seeded.evaluations <= 2, "{seeded:?} {v}");
    }

    #[test]
    fn newton_stops_at_the_rounding_floor() {
        // A root whose value is only known to ~1e-12 (noise far above f64's
        // ulp): Newton must stop once its steps stop shrinking, not chase it.
        let noisy = |x: f64| Some((2.0 - x * x + 1e-12 * (x * 1e9).sin(), -2.0 * x));
        let run = newton_seeded(1.0, 2.0, None, noisy);
        assert!((run.root - 2f64.sqrt()).abs() <= 1e-11, "{run:?}");
        assert!(run.evaluations <= 12, "{run:?}");
    }
}
