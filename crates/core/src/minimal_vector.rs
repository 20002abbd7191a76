//! The minimal complete Cayley vector (THEORY.md §5): a smallest set of
//! entries of the complete Cayley vector whose lengths still tell apart every
//! two realizations of a component that the whole vector tells apart.
//!
//! A set S of entries **separates** a component when the projection of its
//! Cayley curve onto S is one-to-one. That is proven by branch and bound on
//! the proven enclosures of [`crate::enclosure`]: the component's loop is cut
//! into **cells** (dyadic pieces of the halves of its segments), and every
//! pair of cells is settled by one of three facts about an entry e ∈ S:
//!
//! - two cells that do not touch: e's value ranges over them are disjoint,
//!   so no point of one has the projection of a point of the other;
//! - one cell: e's derivative along the cell is proven nonzero, so e is
//!   strictly monotone on it;
//! - two cells meeting at a point: e is strictly monotone along the loop
//!   over both (derivatives proven nonzero, with the same sign once each is
//!   taken in the loop's direction).
//!
//! A pair no entry settles is split (the longer cell in halves) until it is
//! settled or a budget runs out. Every pair settled is a proof that S
//! separates; a budget that runs out proves nothing, and a larger set (at
//! last the whole vector, complete by THEORY.md §5) is taken instead.
//!
//! One entry never separates a closed component (no continuous map of a
//! circle into a line is one-to-one), so a proven pair of entries is a proven
//! minimum whenever a component is closed.
//!
//! Where mirror images are realizations too, they share every length: a
//! component that holds its own mirror image is one loop walked twice over
//! by its Cayley curve, and only half of it (a loop in its own right, its
//! ends identified by the mirror) is checked.

use crate::cayley_space::CayleySpace;
use crate::cayley_vector::{Mirrors, mirror_type};
use crate::enclosure::{Half, enclose, halves};
use crate::interval::{Centred, Interval};
use crate::motion::{Component, Segment, component_segments};
use crate::realize::Construction;

/// Work limits of the search (every command has a bounded cost).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MinimalOptions {
    /// Cells enclosed at most, times the number of steps (a cell is one
    /// enclosure of the whole vector over a piece of a component, about as
    /// costly as a few realizations of every step).
    pub max_step_cells: usize,
    /// Pairs of cells compared at most, over every candidate set.
    pub max_pairs: usize,
    /// Candidate sets tried at most of each size (the most promising first).
    pub max_candidates: usize,
}

impl Default for MinimalOptions {
    fn default() -> Self {
        MinimalOptions { max_step_cells: 20_000, max_pairs: 200_000, max_candidates: 24 }
    }
}

/// How far the smallest set found is proven to be the smallest.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, schemars::JsonSchema))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Minimality {
    /// Proven to separate, and no smaller set can: a closed component has
    /// no one-to-one projection onto one entry, and every smaller set was
    /// proven to fold a component at an interval end.
    Proven,
    /// Proven to separate; a smaller set was not proven to within the budget
    /// (one may exist).
    SmallestFound,
    /// No proper subset was proven to within the budget: the whole complete
    /// Cayley vector, which separates by THEORY.md §5.
    Whole,
}

/// The minimal complete Cayley vector of the computed components.
#[derive(Clone, Debug, PartialEq)]
pub struct MinimalVector {
    /// Indices into the complete Cayley vector, ascending.
    pub entries: Vec<usize>,
    /// How far `entries` is proven smallest.
    pub minimality: Minimality,
    /// Cells enclosed.
    pub cells: usize,
    /// Pairs of cells compared.
    pub pairs: usize,
    /// A component's curve could not be enclosed with proofs (an interval
    /// end not verified, or a mirror structure not recognised): only the
    /// whole vector is claimed then.
    pub unenclosed_component: bool,
}

/// The smallest set of complete-Cayley-vector entries (`ccv`) proven to
/// separate the realizations of every component in `components` (module
/// doc). A vector of at most one entry is its own minimum; with no
/// component, or a budget too small for one cell per half segment, the
/// whole vector is returned unreduced.
pub fn minimal_vector(
    con: &Construction<f64>,
    space: &CayleySpace<f64>,
    components: &[Component],
    ccv: &[[usize; 2]],
    mirrors: Mirrors,
    options: MinimalOptions,
) -> MinimalVector {
    // Enclosures multiply lengths (squares, products of slacks), which at
    // 1e±150 overflow or underflow: they are made in units of the scene's
    // scale, a power of two, so every number scales exactly and the proofs
    // are the same at every scale.
    let unit = 2f64.powi((-con.scale.log2().round()).clamp(-1000.0, 1000.0) as i32);
    let (con, space) = (&con.scaled(unit), &scaled_space(space, unit));
    let whole: Vec<usize> = (0..ccv.len()).collect();
    let max_cells = options.max_step_cells / con.steps.len().max(1);
    let mut budget = Budget { cells: 0, pairs: 0, max_cells, max_pairs: options.max_pairs };
    let mut loops = Vec::new();
    let mut unenclosed = false;
    // Every loop starts with its ends verified and one cell per half: with
    // less than that in the budget nothing can be proven, and nothing is tried.
    let segments: usize = components.iter().map(|c| c.intervals.len()).sum();
    let components = if 2 * segments * (1 + END_COST_CELLS) > max_cells { &[][..] } else { components };
    for c in components {
        match Loop::new(con, space, c, ccv, mirrors, &mut budget) {
            Some(l) => loops.push(l),
            None => {
                // The whole vector it will be: spend nothing more.
                unenclosed = true;
                break;
            }
        }
    }
    let result = |entries, minimality, budget: &Budget| MinimalVector {
        entries,
        minimality,
        cells: budget.cells,
        pairs: budget.pairs,
        unenclosed_component: unenclosed,
    };
    if ccv.len() <= 1 {
        return result(whole, Minimality::Proven, &budget);
    }
    if loops.is_empty() {
        return result(whole, Minimality::Whole, &budget);
    }
    if unenclosed {
        return result(whole, Minimality::Whole, &budget);
    }
    // One entry never separates a closed loop; below `size`, every set was
    // refuted as long as `refuted_below` holds.
    let first_size = if loops.iter().any(|l| l.closed) { 2 } else { 1 };
    let mut refuted_below = true;
    let order = promising_entries(&loops, ccv.len());
    for size in first_size..ccv.len() {
        let sets = candidates(&order, size, options.max_candidates);
        let mut refuted = sets.len() == binomial(ccv.len(), size);
        for set in sets {
            if loops.iter().any(|l| l.folds(&set)) {
                continue;
            }
            refuted = false;
            if size == 2 && loops.iter().any(|l| crosses(&l.samples, [set[0], set[1]], l.closed)) {
                continue;
            }
            let mut proven = true;
            for l in &mut loops {
                match l.separates(con, ccv, &set, &mut budget) {
                    Some(true) => {}
                    Some(false) => {
                        proven = false;
                        break;
                    }
                    None => return result(whole, Minimality::Whole, &budget),
                }
            }
            if proven {
                let minimality = if refuted_below { Minimality::Proven } else { Minimality::SmallestFound };
                let mut set = set;
                set.sort_unstable();
                return result(set, minimality, &budget);
            }
        }
        refuted_below &= refuted;
    }
    let minimality = if refuted_below { Minimality::Proven } else { Minimality::Whole };
    result(whole, minimality, &budget)
}

/// n choose k (saturating).
fn binomial(n: usize, k: usize) -> usize {
    (0..k).fold(1usize, |acc, i| acc.saturating_mul(n - i) / (i + 1))
}

/// The space with every λ multiplied by `f`.
fn scaled_space(space: &CayleySpace<f64>, f: f64) -> CayleySpace<f64> {
    let mut space = space.clone();
    for iv in &mut space.intervals {
        iv.lower.lambda *= f;
        iv.upper.lambda *= f;
    }
    space
}

struct Budget {
    cells: usize,
    pairs: usize,
    max_cells: usize,
    max_pairs: usize,
}

impl Budget {
    fn exhausted(&self) -> bool {
        self.cells >= self.max_cells || self.pairs >= self.max_pairs
    }
}

/// What verifying one interval end costs, in cells (a bracket search of a
/// few dozen enclosures of the flat step's slack), for the budget.
const END_COST_CELLS: usize = 16;

/// Depth of dyadic splitting a cell may reach: a pair still unsettled that
/// deep is where the projection meets itself (or nearly so), and the set is
/// given up.
const MAX_DEPTH: u32 = 40;

/// A dyadic piece of a half: t ∈ t_max·[index, index + 1]/2^depth.
struct Cell {
    half: usize,
    depth: u32,
    index: u64,
    /// The whole vector over the cell, with derivatives in t.
    values: Vec<Centred>,
    children: Option<[usize; 2]>,
}

/// One component's loop of halves, with the cells enclosed so far.
struct Loop {
    halves: Vec<Half>,
    closed: bool,
    cells: Vec<Cell>,
    /// The whole vector at sample points in loop order (for [`crosses`]).
    samples: Vec<Vec<f64>>,
    /// Per end between two segments: which entries differ on its two sides
    /// at one λ (see [`end_folds`]).
    differs_at_ends: Vec<Vec<bool>>,
}

impl Loop {
    /// The component's halves (only a fundamental half of a loop that holds
    /// its own mirror image); `None` when an end cannot be verified.
    fn new(
        con: &Construction<f64>,
        space: &CayleySpace<f64>,
        c: &Component,
        ccv: &[[usize; 2]],
        mirrors: Mirrors,
        budget: &mut Budget,
    ) -> Option<Loop> {
        let mut segments = component_segments(space, c);
        if mirrors.exist() && segments.iter().any(|s| segments.iter().any(|o| o.ty == mirror_type(&s.ty))) {
            segments = mirror_fundamental_half(segments, c.closed)?;
        }
        let halves = halves(con, space, &segments);
        let unverified = |h: &Half| !h.flat_steps.is_empty() && !h.verified;
        if halves.iter().any(unverified) {
            return None;
        }
        let samples = loop_samples(con, ccv, &halves, &segments);
        let differs_at_ends = differs_at_ends(con, ccv, &halves, &segments, c.closed);
        let mut l = Loop { halves, closed: c.closed, cells: Vec::new(), samples, differs_at_ends };
        for h in 0..l.halves.len() {
            l.push_cell(con, ccv, h, 0, 0, budget);
        }
        Some(l)
    }

    fn push_cell(
        &mut self,
        con: &Construction<f64>,
        ccv: &[[usize; 2]],
        half: usize,
        depth: u32,
        index: u64,
        budget: &mut Budget,
    ) -> usize {
        budget.cells += 1;
        let t = self.t_range(half, depth, index);
        let values = enclose(con, ccv, &self.halves[half], t);
        self.cells.push(Cell { half, depth, index, values, children: None });
        self.cells.len() - 1
    }

    fn t_range(&self, half: usize, depth: u32, index: u64) -> Interval {
        let t_max = self.halves[half].t_max;
        let at = |i: u64| t_max * (i as f64 / (1u64 << depth) as f64);
        Interval::new(at(index), at(index + 1))
    }

    /// The cell's two ends as positions along the loop, in units of
    /// 2^-MAX_DEPTH of a half: half h covers [h, h + 1]; even halves run
    /// from their segment's start (t grows along the loop), odd ones from
    /// its end (t grows against it).
    fn span(&self, cell: &Cell) -> [u128; 2] {
        let unit = 1u128 << MAX_DEPTH;
        let width = unit >> cell.depth;
        let from_t0 = u128::from(cell.index) * width;
        let h = cell.half as u128 * unit;
        if cell.half.is_multiple_of(2) {
            [h + from_t0, h + from_t0 + width]
        } else {
            [h + unit - from_t0 - width, h + unit - from_t0]
        }
    }

    /// +1 when t grows along the loop in this cell's half, −1 against it.
    fn along(&self, cell: &Cell) -> f64 {
        if cell.half.is_multiple_of(2) { 1.0 } else { -1.0 }
    }

    fn touch(&self, a: &Cell, b: &Cell) -> bool {
        let ([a0, a1], [b0, b1]) = (self.span(a), self.span(b));
        let total = self.halves.len() as u128 * (1u128 << MAX_DEPTH);
        a1 == b0 || b1 == a0 || (self.closed && ((a0 == 0 && b1 == total) || (b0 == 0 && a1 == total)))
    }

    fn children(&mut self, con: &Construction<f64>, ccv: &[[usize; 2]], id: usize, budget: &mut Budget) -> [usize; 2] {
        if let Some(c) = self.cells[id].children {
            return c;
        }
        let (half, depth, index) = (self.cells[id].half, self.cells[id].depth + 1, self.cells[id].index * 2);
        let c = [
            self.push_cell(con, ccv, half, depth, index, budget),
            self.push_cell(con, ccv, half, depth, index + 1, budget),
        ];
        self.cells[id].children = Some(c);
        c
    }

    /// Whether the projection onto `set` is proven one-to-one on this loop:
    /// `Some(false)` when a pair could not be settled to [`MAX_DEPTH`],
    /// `None` when the budget ran out.
    fn separates(
        &mut self,
        con: &Construction<f64>,
        ccv: &[[usize; 2]],
        set: &[usize],
        budget: &mut Budget,
    ) -> Option<bool> {
        let roots: Vec<usize> = (0..self.halves.len()).collect();
        let mut work: Vec<(usize, usize)> = Vec::new();
        for (i, &a) in roots.iter().enumerate() {
            for &b in &roots[i..] {
                work.push((a, b));
            }
        }
        while let Some((a, b)) = work.pop() {
            if budget.exhausted() {
                return None;
            }
            budget.pairs += 1;
            if self.settled(a, b, set) {
                continue;
            }
            if a == b {
                if self.cells[a].depth >= MAX_DEPTH {
                    return Some(false);
                }
                let [x, y] = self.children(con, ccv, a, budget);
                work.extend([(x, x), (y, y), (x, y)]);
                continue;
            }
            let (split, keep) = if self.cells[a].depth <= self.cells[b].depth { (a, b) } else { (b, a) };
            if self.cells[split].depth >= MAX_DEPTH {
                return Some(false);
            }
            let [x, y] = self.children(con, ccv, split, budget);
            work.extend([(x, keep), (y, keep)]);
        }
        Some(true)
    }

    /// Whether the projection onto `set` is proven not one-to-one: at an end
    /// where the loop passes from one type to the next, every entry of
    /// `set` is computed from joints the flat step does not move, so the
    /// two sides (distinct realizations at the same λ) project alike.
    fn folds(&self, set: &[usize]) -> bool {
        self.differs_at_ends.iter().any(|d| set.iter().all(|&e| !d[e]))
    }

    /// One of the module doc's three facts, for some entry of `set`.
    fn settled(&self, a: usize, b: usize, set: &[usize]) -> bool {
        let (ca, cb) = (&self.cells[a], &self.cells[b]);
        if a == b {
            return set.iter().any(|&e| !ca.values[e].b.d.contains_zero());
        }
        let disjoint = |e: usize| {
            let (x, y) = (ca.values[e].b.v, cb.values[e].b.v);
            x.hi < y.lo || y.hi < x.lo
        };
        if set.iter().any(|&e| disjoint(e)) {
            return true;
        }
        if !self.touch(ca, cb) {
            return false;
        }
        let (sa, sb) = (Interval::point(self.along(ca)), Interval::point(self.along(cb)));
        set.iter().any(|&e| {
            let (da, db) = (ca.values[e].b.d * sa, cb.values[e].b.d * sb);
            (da.lo > 0.0 && db.lo > 0.0) || (da.hi < 0.0 && db.hi < 0.0)
        })
    }
}

/// The first half of a loop that holds its own mirror image: segments
/// s₀…s₂ₘ₋₁ with s_{j+m} the mirror of s_j (a free involution of a circle
/// turns it by half a turn). `None` when the segments do not have that form.
fn mirror_fundamental_half(mut segments: Vec<Segment>, closed: bool) -> Option<Vec<Segment>> {
    let n = segments.len();
    if !closed || !n.is_multiple_of(2) {
        return None;
    }
    let m = n / 2;
    let mirrored = (0..m).all(|j| {
        let (a, b) = (&segments[j], &segments[j + m]);
        b.ty == mirror_type(&a.ty) && b.from == a.from && b.to == a.to
    });
    if !mirrored {
        return None;
    }
    segments.truncate(m);
    Some(segments)
}

/// Per end between consecutive segments (and the loop's own end when
/// closed): which entries differ between the realizations on its two sides
/// at one λ. An entry that does not depend on the step flat there is
/// computed by the very same operations on both sides, so it is equal bit
/// for bit, and exactly: a set of such entries folds the loop there.
fn differs_at_ends(
    con: &Construction<f64>,
    ccv: &[[usize; 2]],
    halves: &[Half],
    segments: &[Segment],
    closed: bool,
) -> Vec<Vec<bool>> {
    let n = halves.len();
    let ends = if closed { n / 2 } else { (n / 2).saturating_sub(1) };
    (0..ends)
        .map(|s| {
            let (a, b) = (&halves[2 * s + 1], &halves[(2 * s + 2) % n]);
            let t = 0.5 * a.t_max.min(b.t_max);
            let at = |h: &Half| {
                let pos = con.realize_flat(h.lambda(t, &segments[h.segment]), &h.bits, con.steps.len(), &[]).ok()?;
                Some(crate::cayley_vector::cayley_vector(&crate::realize::points(&pos), ccv))
            };
            match (at(a), at(b)) {
                (Some(va), Some(vb)) if a.lambda(t, &segments[a.segment]) == b.lambda(t, &segments[b.segment]) => {
                    va.iter().zip(&vb).map(|(x, y)| x != y).collect()
                }
                _ => vec![true; ccv.len()],
            }
        })
        .collect()
}

/// Sample points per half for the crossing pre-screen.
const SAMPLES_PER_HALF: usize = 12;

/// The whole vector along the loop at [`SAMPLES_PER_HALF`] points of every
/// half (λ = end + dir·t², t evenly spaced), in loop order; points that do not
/// realize in f64 are left out.
fn loop_samples(con: &Construction<f64>, ccv: &[[usize; 2]], halves: &[Half], segments: &[Segment]) -> Vec<Vec<f64>> {
    let mut out = Vec::with_capacity(halves.len() * SAMPLES_PER_HALF);
    for (h, half) in halves.iter().enumerate() {
        let seg = &segments[half.segment];
        let mut ts: Vec<f64> = (0..SAMPLES_PER_HALF).map(|k| half.t_max * k as f64 / SAMPLES_PER_HALF as f64).collect();
        // Even halves run along the loop from t = 0, odd ones towards t = 0.
        if !h.is_multiple_of(2) {
            ts.reverse();
        }
        for t in ts {
            let lambda = half.lambda(t, seg);
            let flat: &[usize] = if t == 0.0 { &half.flat_steps } else { &[] };
            if let Ok(pos) = con.realize_flat(lambda, &half.bits, con.steps.len(), flat) {
                out.push(crate::cayley_vector::cayley_vector(&crate::realize::points(&pos), ccv));
            }
        }
    }
    out
}

/// Whether the sampled polyline, projected on entries `e`, crosses itself
/// (two segments that share no sample meet properly): then the projection
/// is very likely not one-to-one, and the pair is not worth a proof. This
/// only chooses what to try; it decides nothing.
fn crosses(samples: &[Vec<f64>], e: [usize; 2], closed: bool) -> bool {
    let p: Vec<[f64; 2]> = samples.iter().map(|v| [v[e[0]], v[e[1]]]).collect();
    let n = p.len();
    let edges = if closed { n } else { n.saturating_sub(1) };
    // −1, 0 or +1 (not `signum`, which gives ±1 for a zero).
    let orient = |a: [f64; 2], b: [f64; 2], c: [f64; 2]| {
        let x = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        f64::from(i8::from(x > 0.0) - i8::from(x < 0.0))
    };
    for i in 0..edges {
        let (a, b) = (p[i], p[(i + 1) % n]);
        for j in i + 2..edges {
            if closed && (j + 1) % n == i {
                continue;
            }
            let (c, d) = (p[j], p[(j + 1) % n]);
            let (o1, o2) = (orient(a, b, c), orient(a, b, d));
            let (o3, o4) = (orient(c, d, a), orient(c, d, b));
            if o1 * o2 < 0.0 && o3 * o4 < 0.0 {
                return true;
            }
        }
    }
    false
}

/// Entries by how far their value moves over the loops' root cells (the
/// widest first): those most likely to tell points apart are tried first.
/// Only the order of trying depends on this; every answer is proven.
fn promising_entries(loops: &[Loop], n: usize) -> Vec<usize> {
    let mut spread = vec![0.0f64; n];
    for l in loops {
        for (e, spread) in spread.iter_mut().enumerate() {
            let (lo, hi) =
                l.cells.iter().take(l.halves.len()).fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), c| {
                    let v = c.values[e].c.v.mid();
                    (lo.min(v), hi.max(v))
                });
            if hi >= lo {
                *spread = spread.max(hi - lo);
            }
        }
    }
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| spread[b].total_cmp(&spread[a]).then(a.cmp(&b)));
    order
}

/// Up to `max` sets of `size` entries, in lexicographic order of their
/// positions in `order`.
fn candidates(order: &[usize], size: usize, max: usize) -> Vec<Vec<usize>> {
    let mut out = Vec::new();
    let mut pick: Vec<usize> = (0..size).collect();
    loop {
        if out.len() >= max {
            return out;
        }
        out.push(pick.iter().map(|&i| order[i]).collect());
        // Advance the rightmost position that can move.
        let n = order.len();
        let Some(k) = (0..size).rev().find(|&k| pick[k] < n - size + k) else {
            return out;
        };
        pick[k] += 1;
        for j in k + 1..size {
            pick[j] = pick[j - 1] + 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn candidates_are_every_subset_in_order() {
        let sets = candidates(&[5, 6, 7, 8], 2, 100);
        assert_eq!(sets, vec![vec![5, 6], vec![5, 7], vec![5, 8], vec![6, 7], vec![6, 8], vec![7, 8]]);
        assert_eq!(candidates(&[1, 2, 3], 3, 100), vec![vec![1, 2, 3]]);
        assert_eq!(candidates(&[1, 2, 3, 4], 2, 2).len(), 2);
    }
}
