//! Continuous motion (THEORY.md §4): connected components as cycles of
//! oriented intervals, the two paths between two realizations, and a stepper
//! that walks them by a geometric step, landing exactly on every endpoint.

use std::collections::HashMap;

use crate::cayley_space::{CayleySpace, Event, OrientedInterval};
use crate::linkage::Linkage;
use crate::realize::{Construction, P2, RealizationType, to_display};

/// Which end of an interval.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Side {
    Lower,
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
    pub intervals: Vec<usize>,
    pub forward: Vec<bool>,
    /// Whether the walk came back to its start (always, in a generic scene).
    pub closed: bool,
    pub lambda_range: [f64; 2],
}

/// An endpoint where the walk had a choice (several steps flat at once) or
/// none (a dead end): only in non-generic scenes.
#[derive(Clone, Debug, PartialEq)]
pub struct BranchPoint {
    pub lambda: f64,
    pub events: Vec<Event>,
    /// The interval the walk arrived from.
    pub from: usize,
    /// Every interval it could continue into; the walk took the first.
    pub options: Vec<usize>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Components {
    pub list: Vec<Component>,
    /// For each oriented interval, its component.
    pub of_interval: Vec<usize>,
    pub branch_points: Vec<BranchPoint>,
}

fn end(i: &OrientedInterval<f64>, side: Side) -> &crate::cayley_space::Endpoint<f64> {
    match side {
        Side::Lower => &i.lower,
        Side::Upper => &i.upper,
    }
}

/// Link intervals by the flip rule: at an end where step k is flat the motion
/// continues, on the same side of λ, into the type with bit k flipped that
/// ends at the same root. Every interval lands in exactly one component.
pub fn components(space: &CayleySpace<f64>) -> Components {
    let ivs = &space.intervals;
    let mut by_end: HashMap<(usize, Side, &RealizationType), Vec<usize>> = HashMap::new();
    for (i, iv) in ivs.iter().enumerate() {
        for side in [Side::Lower, Side::Upper] {
            by_end.entry((end(iv, side).id, side, &iv.ty)).or_default().push(i);
        }
    }
    // Intervals reachable from end `side` of interval `i`: flip each flat
    // step's bit (or, failing that, any set of them).
    let partners = |i: usize, side: Side| -> Vec<usize> {
        let e = end(&ivs[i], side);
        let steps: Vec<usize> = e.events.iter().map(|ev| ev.step).collect();
        let lookup = |mask: usize| -> Vec<usize> {
            let ty = ivs[i].ty.flipped_by_mask(&steps, mask);
            by_end.get(&(e.id, side, &ty)).cloned().unwrap_or_default()
        };
        // Only single flips: where none continues, the end is a dead end
        // (e.g. a folded rhombus, where a later step degenerates and the
        // motion has an extra degree of freedom). Passing through by flipping
        // several bits would join components on some bases and not on
        // others; the realization space must not depend on the base.
        (0..steps.len()).flat_map(|b| lookup(1 << b)).filter(|&j| j != i).collect()
    };
    let mut of_interval = vec![usize::MAX; ivs.len()];
    let mut list = Vec::new();
    let mut branch_points = Vec::new();
    for start in 0..ivs.len() {
        if of_interval[start] != usize::MAX {
            continue;
        }
        let c = list.len();
        of_interval[start] = c;
        let mut seq = vec![(start, true)];
        let mut closed = false;
        // Walk upward from the start's upper end.
        let (mut cur, mut leaving) = (start, Side::Upper);
        loop {
            let options = partners(cur, leaving);
            if options.len() != 1 {
                let e = end(&ivs[cur], leaving);
                branch_points.push(BranchPoint {
                    lambda: e.lambda,
                    events: e.events.clone(),
                    from: cur,
                    options: options.clone(),
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
            // An open chain: collect what lies behind the start as well.
            let (mut cur, mut leaving) = (start, Side::Lower);
            loop {
                let options = partners(cur, leaving);
                let Some(&next) = options.iter().find(|&&j| of_interval[j] == usize::MAX) else { break };
                of_interval[next] = c;
                seq.insert(0, (next, leaving == Side::Upper));
                cur = next;
                leaving = leaving.other();
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
    Components { list, of_interval, branch_points }
}

/// A realization named by type and base length.
#[derive(Clone, Debug, PartialEq)]
pub struct Realization {
    pub ty: RealizationType,
    pub lambda: f64,
}

impl Realization {
    /// Parse `TYPE@LAMBDA`, e.g. `-+-+@41.2`.
    pub fn parse(text: &str) -> Result<Self, String> {
        let (ty, lambda) =
            text.split_once('@').ok_or_else(|| format!("\"{text}\": expected TYPE@LAMBDA, e.g. -+-+@41.2"))?;
        let ty = RealizationType::parse(ty.trim()).ok_or_else(|| format!("\"{ty}\": a type is a string of + and -"))?;
        let lambda: f64 = lambda.trim().parse().map_err(|_| format!("\"{lambda}\": not a number"))?;
        if !lambda.is_finite() {
            return Err(format!("\"{lambda}\": not a finite number"));
        }
        Ok(Realization { ty, lambda })
    }
}

impl std::fmt::Display for Realization {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}@{}", self.ty, self.lambda)
    }
}

/// The oriented interval holding a realization (its own type's interval).
pub fn locate(space: &CayleySpace<f64>, r: &Realization, scale: f64) -> Option<usize> {
    let tol = crate::tolerance::FEASIBLE * scale;
    space
        .intervals
        .iter()
        .position(|i| i.ty == r.ty && r.lambda >= i.lower.lambda - tol && r.lambda <= i.upper.lambda + tol)
}

/// Why a realization could not be located, as a sentence.
pub fn explain_missing(space: &CayleySpace<f64>, r: &Realization, n_steps: usize) -> String {
    if r.ty.0.len() != n_steps {
        return format!("type {} has {} signs; this scene has {n_steps} steps", r.ty, r.ty.0.len());
    }
    let spans: Vec<String> = space
        .intervals
        .iter()
        .filter(|i| i.ty == r.ty)
        .map(|i| format!("[{}, {}]", i.lower.lambda, i.upper.lambda))
        .collect();
    if spans.is_empty() {
        format!("type {} has no realization at any λ", r.ty)
    } else {
        format!("type {} is not realizable at λ = {}; it is at λ in {}", r.ty, r.lambda, spans.join(" ∪ "))
    }
}

/// A stretch of motion inside one oriented interval, from λ `from` to `to`.
/// `flat_from`/`flat_to` list the steps flat there when that end is an
/// interval endpoint (empty for an end inside the interval).
#[derive(Clone, Debug, PartialEq)]
pub struct Segment {
    pub interval: usize,
    pub ty: RealizationType,
    pub from: f64,
    pub to: f64,
    pub flat_from: Vec<usize>,
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
            let steps = |e: &crate::cayley_space::Endpoint<f64>| e.events.iter().map(|ev| ev.step).collect();
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
    pub lambda: f64,
    pub ty: RealizationType,
    /// Joint positions in the display frame.
    pub positions: Vec<P2<f64>>,
    /// Index of the segment this sample belongs to.
    pub segment: usize,
    /// Set when the sample is a segment's end (an interval endpoint, except at the walk's end).
    pub at_end: bool,
}

/// Walks segments by a geometric step: consecutive samples differ by at most
/// `step` in every joint's position (display frame), except where λ cannot be
/// resolved finer (adjacent floats); every segment end is hit exactly.
pub struct Stepper<'a> {
    con: &'a Construction<f64>,
    linkage: &'a Linkage,
    segments: Vec<Segment>,
    step: f64,
    seg: usize,
    lambda: f64,
    last: Option<Vec<P2<f64>>>,
    delta: f64,
    done: bool,
}

impl<'a> Stepper<'a> {
    pub fn new(con: &'a Construction<f64>, linkage: &'a Linkage, segments: Vec<Segment>, step: f64) -> Self {
        let lambda = segments.first().map_or(0.0, |s| s.from);
        let delta = step.max(f64::MIN_POSITIVE);
        Stepper { con, linkage, done: segments.is_empty(), segments, step, seg: 0, lambda, last: None, delta }
    }

    fn positions(&self, lambda: f64, ty: &RealizationType) -> Option<Vec<P2<f64>>> {
        let s = &self.segments[self.seg];
        realization_at(self.con, self.linkage, &Segment { ty: ty.clone(), ..s.clone() }, lambda)
    }
}

/// Joint positions (display frame) at λ on a segment. At the segment's ends
/// the steps flat there are placed exactly flat; where a step degenerates
/// exactly at λ (its base joints coincide, as in a folded rhombus) the limit
/// is taken by nudging λ toward the segment's interior.
pub fn realization_at(con: &Construction<f64>, linkage: &Linkage, s: &Segment, lambda: f64) -> Option<Vec<P2<f64>>> {
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
        [1e-12, 1e-10, 1e-8].iter().find_map(|e| con.realize(lambda + inward * e * con.scale, &s.ty).ok())
    })?;
    Some(to_display(linkage, con.base, &pos))
}

fn max_move(a: &[P2<f64>], b: &[P2<f64>]) -> f64 {
    a.iter().zip(b).map(|(p, q)| (p[0] - q[0]).hypot(p[1] - q[1])).fold(0.0, f64::max)
}

impl Iterator for Stepper<'_> {
    type Item = Sample;

    fn next(&mut self) -> Option<Sample> {
        if self.done {
            return None;
        }
        let Some(last) = self.last.clone() else {
            let s = &self.segments[0];
            let pos = self.positions(s.from, &s.ty)?;
            self.last = Some(pos.clone());
            let at_end = s.from == s.to;
            return Some(Sample { lambda: s.from, ty: s.ty.clone(), positions: pos, segment: 0, at_end });
        };
        // Past a segment's end: continue in the next one (same realization there).
        while self.lambda == self.segments[self.seg].to {
            if self.seg + 1 == self.segments.len() {
                self.done = true;
                return None;
            }
            self.seg += 1;
            self.lambda = self.segments[self.seg].from;
        }
        let s = self.segments[self.seg].clone();
        let remaining = s.to - self.lambda;
        let mut delta = (self.delta * 2.0).min(remaining.abs());
        loop {
            let target = if delta >= remaining.abs() { s.to } else { self.lambda + delta * remaining.signum() };
            let pos = self.positions(target, &s.ty);
            let small = delta <= 4.0 * f64::EPSILON * self.lambda.abs().max(self.con.scale);
            match pos {
                Some(pos) if small || max_move(&pos, &last) <= self.step => {
                    self.delta = delta.max(f64::MIN_POSITIVE);
                    self.lambda = target;
                    self.last = Some(pos.clone());
                    let at_end = target == s.to;
                    return Some(Sample { lambda: target, ty: s.ty, positions: pos, segment: self.seg, at_end });
                }
                None if small => {
                    self.done = true;
                    return None;
                }
                _ => delta /= 2.0,
            }
        }
    }
}

/// Measures of a walked path.
#[derive(Clone, Debug, PartialEq)]
pub struct PathMeasure {
    /// Length of the polyline of complete Cayley distance vectors.
    pub cayley_length: f64,
    /// The longest distance any one joint travels.
    pub max_joint_travel: f64,
    pub samples: usize,
}

/// Walk `segments` and measure them (`ccv` pairs give the Cayley vector).
pub fn measure(
    con: &Construction<f64>,
    linkage: &Linkage,
    segments: Vec<Segment>,
    step: f64,
    ccv: &[[usize; 2]],
) -> PathMeasure {
    let mut travel = vec![0.0; linkage.n_joints()];
    let mut cayley_length = 0.0;
    let mut prev: Option<(Vec<P2<f64>>, Vec<f64>)> = None;
    let mut samples = 0;
    for s in Stepper::new(con, linkage, segments, step) {
        let v = crate::distance::cayley_vector(&s.positions, ccv);
        if let Some((p, w)) = &prev {
            for (t, (a, b)) in travel.iter_mut().zip(p.iter().zip(&s.positions)) {
                *t += (a[0] - b[0]).hypot(a[1] - b[1]);
            }
            cayley_length += crate::distance::euclid(w, &v);
        }
        prev = Some((s.positions, v));
        samples += 1;
    }
    PathMeasure { cayley_length, max_joint_travel: travel.into_iter().fold(0.0, f64::max), samples }
}
