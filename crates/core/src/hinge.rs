//! Base distances step by step, each measured in a frame of its own.
//!
//! A realization in the base's frame carries every joint's position from
//! step to step. In ball arithmetic each placement widens its inputs'
//! radii by its own factor (3 to 20 per step on a chain of four-cycles)
//! whatever the real sensitivity, because the balls forget that the
//! errors of a step's joints are mostly one rigid motion: the wrapping
//! effect. A 1000-step chain's balls overflowed within 14 steps, and every
//! decision past them rested on an estimate.
//!
//! Step k's base joints u_k, w_k usually both lie in the frame of one
//! earlier step j (each is u_j, w_j, v_j or a member placed from them), or
//! are placed from that frame by a few more steps (a hinge closed through
//! a four-cycle). Then d_k = |u_k w_k| depends on d_j, and the bits of j
//! and of those steps, alone: place step j with u_j at the origin and w_j
//! at (d_j, 0), then the few steps, by the construction's one
//! [`Construction::place_step`], and measure. A rotation and translation
//! map that frame onto the base's, so the distance is the same number.
//! Only the scalar d_j passes from frame to frame: a ball widens by d_k's
//! real sensitivity to d_j and a few placements' rounding. Where no later
//! frame holds them, the base's does (λ, and the steps from there): the
//! realization in the base's frame is the worst case, not a separate path.

use std::any::Any;
use std::cell::RefCell;

use crate::real::{Ball, Real, Slope};
use crate::realize::{Construction, Kind, P2};
use crate::tolerance;

/// For each step, the frame its base distance is measured in and the steps
/// placed in that frame first.
#[derive(Debug, Clone)]
pub struct Hinges {
    /// Per frame (the base's, then each step's), the steps measured in it,
    /// `measured[starts[f]..starts[f + 1]]`.
    measured: Vec<usize>,
    starts: Vec<usize>,
    /// Per step, the steps placed in its frame before it is measured,
    /// `chain[chain_starts[k]..chain_starts[k + 1]]`, in step order.
    chain: Vec<usize>,
    chain_starts: Vec<usize>,
}

/// The joints step `j` pivots on or places: u_j, w_j, v_j and its members.
fn frame_joints<T>(con: &Construction<T>, j: usize) -> impl Iterator<Item = usize> + '_ {
    let s = &con.steps[j];
    [s.u, s.w, s.vertex].into_iter().chain(s.members_u.iter().chain(&s.members_w).map(|m| m.joint))
}

/// Per joint, the step that places it (`usize::MAX` for a base joint).
fn placers<T>(con: &Construction<T>) -> Vec<usize> {
    let mut placer = vec![usize::MAX; con.n_joints];
    for (j, s) in con.steps.iter().enumerate() {
        placer[s.vertex] = j;
        for m in s.members_u.iter().chain(&s.members_w) {
            placer[m.joint] = j;
        }
    }
    placer
}

/// Blocks of positions in balls and in slopes of balls.
type Blocks<'a, T> = (&'a mut Vec<P2<Ball<T>>>, &'a mut Vec<P2<Slope<Ball<T>>>>);

/// `f` on this thread's block of positions in `U`, reused: a frame
/// touches a few joints but its block spans them all, and a fresh block per
/// question cost a 1000-step chain a quarter of its time zeroing pages. A
/// nested call takes a block of its own.
fn with_scratch<U: Real, R>(f: impl FnOnce(&mut Vec<P2<U>>) -> R) -> R {
    thread_local! {
        static BLOCKS: RefCell<Vec<Box<dyn Any>>> = const { RefCell::new(Vec::new()) };
    }
    let taken = BLOCKS.with(|blocks| {
        let mut blocks = blocks.borrow_mut();
        let at = blocks.iter().position(|b| b.is::<Vec<P2<U>>>())?;
        blocks.swap_remove(at).downcast::<Vec<P2<U>>>().ok()
    });
    let mut block = taken.map_or_else(Vec::new, |b| *b);
    let out = f(&mut block);
    BLOCKS.with(|blocks| blocks.borrow_mut().push(Box::new(block)));
    out
}

/// Step lists by key, as one flat list and offsets.
fn grouped(keys: &[usize], groups: usize) -> (Vec<usize>, Vec<usize>) {
    let mut starts = vec![0usize; groups + 1];
    for &g in keys {
        starts[g + 1] += 1;
    }
    for g in 0..groups {
        starts[g + 1] += starts[g];
    }
    let mut list = vec![0; keys.len()];
    let mut next = starts.clone();
    for (k, &g) in keys.iter().enumerate() {
        list[next[g]] = k;
        next[g] += 1;
    }
    (list, starts)
}

impl Hinges {
    /// Each step's frame and the steps placed in it first. From the step's
    /// base joints, the latest step placing a joint still needed either
    /// holds them all in its frame (the frame found) or is placed in the
    /// frame too (its base joints needed instead); the base's frame holds
    /// the base joints. About linear in the construction's size where
    /// frames are near (every bundled scene); `None` where the steps placed
    /// in frames would pass 8 per step (a construction of high Cayley
    /// complexity, whose distances the caller realizes in the base's frame).
    pub fn new<T: Real>(con: &Construction<T>) -> Option<Hinges> {
        let placer = placers(con);
        let mut frame = Vec::with_capacity(con.steps.len());
        let (mut chain, mut chain_starts) = (Vec::new(), vec![0]);
        let mut need: Vec<usize> = Vec::new();
        let mut placed: Vec<usize> = Vec::new();
        for s in &con.steps {
            need.clear();
            need.extend([s.u, s.w]);
            placed.clear();
            let found = loop {
                let latest = need.iter().map(|&q| placer[q]).filter(|&j| j != usize::MAX).max();
                let Some(j) = latest else { break 0 };
                if need.iter().all(|&q| frame_joints(con, j).any(|p| p == q)) {
                    break j + 1;
                }
                placed.push(j);
                let t = &con.steps[j];
                need.retain(|&q| placer[q] != j);
                for q in [t.u, t.w] {
                    if !need.contains(&q) {
                        need.push(q);
                    }
                }
            };
            frame.push(found);
            chain.extend(placed.iter().rev());
            chain_starts.push(chain.len());
            if chain.len() > 8 * con.steps.len().max(1) {
                return None;
            }
        }
        let (measured, starts) = grouped(&frame, con.steps.len() + 1);
        Some(Hinges { measured, starts, chain, chain_starts })
    }

    /// The base distances d_0, …, d_upto of the type prefix `bits` at λ
    /// (the steps in `flat` placed exactly flat), as
    /// [`Construction::base_distances_flat`] gives them: up to and including
    /// the first step before `upto` that cannot close, else through `upto`
    /// (`upto` < the number of steps); empty where a step on the way to
    /// one cannot be placed in that step's frame though it is in its own.
    #[cfg(test)]
    pub fn distances<T: Real>(
        &self,
        con: &Construction<T>,
        (lambda, bits): (T, &[bool]),
        (upto, flat): (usize, &[usize]),
    ) -> Vec<T> {
        let mut scratch = Vec::new();
        let run = self.run(
            upto,
            lambda,
            |_, _| false,
            |f, base, d| self.frame(con, &mut scratch, (f, base), (bits, flat, upto), d, |_, _| true, &mut Vec::new()),
        );
        run.unwrap_or_default()
    }

    /// [`Self::distances`] in balls, each distance by the mean-value form
    /// where it is narrower: a frame's distances are functions f of its
    /// base D = m ± r, so f(D) ⊂ f(m) + f′(D)·[−r, r], with f(m) in balls at
    /// the point m (radius: rounding) and f′(D) in slopes of balls over D.
    /// That holds where f is smooth on D: every step placed on the way
    /// closes on all of D with both slacks proven positive, or is placed
    /// flat. `slopes` is `balls` in slopes of balls (constants). `stop(j,
    /// d_j)` ends the distances before step j is placed (an overflowed ball
    /// proves nothing downstream), with `None`; so does a step on the way
    /// to one that cannot be placed in that step's frame though it is in
    /// its own (its base joints meet to rounding).
    pub fn enclosures<T: Real>(
        &self,
        (balls, slopes): (&Construction<Ball<T>>, &Construction<Slope<Ball<T>>>),
        (lambda, bits): (Ball<T>, &[bool]),
        (upto, flat): (usize, &[usize]),
        stop: impl Fn(usize, &Ball<T>) -> bool,
    ) -> Option<Vec<Ball<T>>> {
        with_scratch(|at_point| {
            with_scratch(|over| self.enclosed_in((at_point, over), (balls, slopes), (lambda, bits), (upto, flat), stop))
        })
    }

    /// [`Self::enclosures`] in the blocks of positions given.
    fn enclosed_in<T: Real>(
        &self,
        (at_point, over): Blocks<T>,
        (balls, slopes): (&Construction<Ball<T>>, &Construction<Slope<Ball<T>>>),
        (lambda, bits): (Ball<T>, &[bool]),
        (upto, flat): (usize, &[usize]),
        stop: impl Fn(usize, &Ball<T>) -> bool,
    ) -> Option<Vec<Ball<T>>> {
        let mut slope_d: Vec<Option<Slope<Ball<T>>>> = vec![None; upto + 1];
        let mut rough = Vec::new();
        let smooth = |i: usize, d: Slope<Ball<T>>| {
            let s = &balls.steps[i];
            flat.contains(&i)
                || [Kind::Stretched, Kind::Folded].iter().all(|k| k.slack_value(s.r1, s.r2, d.v).sign() == Some(1))
        };
        self.run(upto, lambda, stop, |f, base, d| {
            let closed =
                self.frame(balls, at_point, (f, Ball::exact(base.m)), (bits, flat, upto), d, |_, _| true, &mut rough);
            if !closed || base.r == 0.0 {
                return closed;
            }
            rough.clear();
            let variable = Slope::variable(base);
            let swept = self.frame(slopes, over, (f, variable), (bits, flat, upto), &mut slope_d, smooth, &mut rough);
            let measured = self.measured(f, upto);
            if !swept || measured.iter().any(|&k| d[k].is_some() && slope_d[k].is_none()) {
                // No slopes over D where the point had values: plain balls over D enclose them.
                return self.frame(balls, at_point, (f, base), (bits, flat, upto), d, |_, _| true, &mut rough);
            }
            let spread = Ball { m: T::zero(), r: base.r };
            for &k in measured {
                let (Some(point), Some(s)) = (d[k], slope_d[k]) else { continue };
                let mean_value = point + s.d * spread;
                let narrower = mean_value.r.partial_cmp(&s.v.r) == Some(std::cmp::Ordering::Less);
                d[k] = Some(if narrower && !rough.contains(&k) { mean_value } else { s.v });
            }
            true
        })
    }

    /// The steps measured in frame `f` (0: the base's, j + 1: step j's) up to `upto`.
    fn measured(&self, f: usize, upto: usize) -> &[usize] {
        let all = &self.measured[self.starts[f]..self.starts[f + 1]];
        &all[..all.partition_point(|&k| k <= upto)]
    }

    /// The distances through `upto`, frame by frame: `frame(f, base, d)`
    /// places frame `f` on its base distance, writes the distances of the
    /// steps measured in it into `d`, and says whether its step closes.
    fn run<U: Real>(
        &self,
        upto: usize,
        lambda: U,
        stop: impl Fn(usize, &U) -> bool,
        mut frame: impl FnMut(usize, U, &mut [Option<U>]) -> bool,
    ) -> Option<Vec<U>> {
        let mut d: Vec<Option<U>> = vec![None; upto + 1];
        frame(0, lambda, &mut d);
        let mut out = Vec::with_capacity(upto + 1);
        for j in 0..=upto {
            // A step on the way that its own frame placed but this one
            // could not (its base joints meet to rounding here): nothing is
            // said, rather than that step j has no realization.
            let dj = d[j]?;
            out.push(dj);
            if j == upto {
                break;
            }
            if stop(j, &dj) {
                return None;
            }
            if !frame(j + 1, dj, &mut d) {
                return Some(out);
            }
        }
        Some(out)
    }

    /// Frame `f` placed with its two joints `base` apart in `scratch`: step
    /// j's frame places step j (false where it cannot close), then for each
    /// step k measured there the steps on the way, and d_k. `check(i, d_i)`
    /// is asked of every step placed; k goes to `rough` where one fails.
    #[allow(clippy::too_many_arguments)]
    fn frame<U: Real>(
        &self,
        con: &Construction<U>,
        scratch: &mut Vec<P2<U>>,
        (f, base): (usize, U),
        (bits, flat, upto): (&[bool], &[usize], usize),
        d: &mut [Option<U>],
        check: impl Fn(usize, U) -> bool,
        rough: &mut Vec<usize>,
    ) -> bool {
        let zero = U::zero();
        if scratch.len() != con.n_joints {
            scratch.clear();
            scratch.resize(con.n_joints, [zero, zero]);
        }
        let [a, b] = if f == 0 { con.base } else { [con.steps[f - 1].u, con.steps[f - 1].w] };
        let place = |scratch: &mut Vec<P2<U>>, i: usize, tol: f64| {
            let (di, placed) = con.place_step(scratch, i, (bits[i], flat.contains(&i)), tol, usize::MAX);
            (placed.is_ok(), check(i, di))
        };
        scratch[a] = [zero, zero];
        scratch[b] = [base, zero];
        let mut all_smooth = true;
        if f > 0 {
            let (closed, smooth) = place(scratch, f - 1, tolerance::FEASIBLE * con.scale);
            if !closed {
                return false;
            }
            all_smooth = smooth;
        }
        for &k in self.measured(f, upto) {
            let t = &con.steps[k];
            let chain = &self.chain[self.chain_starts[k]..self.chain_starts[k + 1]];
            if chain.is_empty() && [t.u, t.w] == [a, b] {
                d[k] = Some(base);
                continue;
            }
            // Whether a step on the way closes is its own question, asked in its own frame.
            let mut smooth = all_smooth;
            let mut closed = true;
            for &i in chain {
                let (c, s) = place(scratch, i, f64::INFINITY);
                closed &= c;
                smooth &= s;
            }
            if !smooth {
                rough.push(k);
            }
            if closed {
                d[k] = Some(con.base_distance(scratch, k));
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::analyse;
    use crate::real::{Ball, Dd};
    use crate::scene::load_scene;

    /// The bundled scenes in the class: each construction with its drawn
    /// type and the λ range of its space.
    type Bundled = (String, Construction<f64>, Vec<bool>, [f64; 2]);

    fn hinged_scenes() -> Vec<Bundled> {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../linkages");
        let mut paths: Vec<_> = std::fs::read_dir(dir).expect("linkages").map(|e| e.expect("entry").path()).collect();
        paths.sort();
        let mut out = Vec::new();
        for path in paths {
            let scene = load_scene(&path).expect("bundled scene");
            let analysis = analyse(scene, None).expect("analysed");
            let Ok(solved) = analysis.outcome.as_ref() else { continue };
            let con = (*solved.construction).clone();
            let range = [solved.union[0][0], solved.union.last().expect("a range")[1]];
            out.push((path.display().to_string(), con, solved.drawn.ty.0.clone(), range));
        }
        out
    }

    /// A few types per scene: the drawn one and its prefixes flipped.
    fn types(drawn: &[bool]) -> Vec<Vec<bool>> {
        let mut out = vec![drawn.to_vec()];
        for k in 0..drawn.len() {
            let mut t = drawn.to_vec();
            for b in &mut t[k..] {
                *b = !*b;
            }
            out.push(t);
        }
        out
    }

    /// Every bundled scene measures each step in a frame at most two
    /// placements from it (none in the base's but the steps on the base).
    #[test]
    fn bundled_frames_are_near() {
        let scenes = hinged_scenes();
        assert_eq!(scenes.len(), 9);
        for (name, con, ..) in scenes {
            let h = Hinges::new(&con).expect("hinged");
            let longest = (0..con.steps.len()).map(|k| h.chain_starts[k + 1] - h.chain_starts[k]).max();
            assert!(longest <= Some(2), "{name}: {longest:?}");
            for k in h.measured[h.starts[0]..h.starts[1]].iter() {
                assert!(con.on_base(*k), "{name}: step {k} in the base's frame");
            }
        }
    }

    /// In f64 the frames give the base-frame distances to rounding, and
    /// fail where the base frame fails.
    #[test]
    fn distances_in_frames_are_the_base_frame_ones() {
        for (name, con, drawn, [lo, hi]) in hinged_scenes() {
            let hinges = Hinges::new(&con).expect("hinged");
            let n = con.steps.len();
            for bits in types(&drawn) {
                for i in 0..=40 {
                    let lambda = lo + (hi - lo) * f64::from(i) / 40.0;
                    for flat in [vec![], vec![0]] {
                        let global = con.base_distances_flat(lambda, &bits, n - 1, &flat);
                        let local = hinges.distances(&con, (lambda, &bits), (n - 1, &flat));
                        assert_eq!(global.len(), local.len(), "{name} {bits:?} λ {lambda} flat {flat:?}");
                        for (k, (g, l)) in global.iter().zip(&local).enumerate() {
                            assert!((g - l).abs() <= 1e-9 * con.scale, "{name} step {k} λ {lambda}: {g} vs {l}");
                        }
                    }
                }
            }
        }
    }

    /// Balls in frames hold the double-double values: at a point, and over
    /// a ball of λ (the mean-value form) at its ends and centre.
    #[test]
    fn balls_in_frames_hold_the_values() {
        for (name, con, drawn, [lo, hi]) in hinged_scenes() {
            let hinges = Hinges::new(&con).expect("hinged");
            let dd: Construction<Dd> = con.map(Dd::new);
            let balls: Construction<Ball<f64>> = con.map(Ball::exact);
            let slopes = balls.map(Slope::constant);
            let n = con.steps.len();
            for bits in types(&drawn) {
                for i in 1..40 {
                    let lambda = lo + (hi - lo) * f64::from(i) / 40.0;
                    for r in [0.0, 1e-12 * con.scale, 1e-6 * con.scale] {
                        let l = Ball { m: lambda, r };
                        let Some(enclosed) =
                            hinges.enclosures((&balls, &slopes), (l, &bits), (n - 1, &[]), |_, _| false)
                        else {
                            panic!("never stopped")
                        };
                        for x in [lambda - 0.999 * r, lambda, lambda + 0.999 * r] {
                            let exact = dd.base_distances_flat(Dd::new(x), &bits, n - 1, &[]);
                            if exact.len() < enclosed.len() {
                                continue; // the type does not close at x
                            }
                            for (k, (x, b)) in exact.iter().zip(&enclosed).enumerate() {
                                let off = (*x - Dd::new(b.m)).to_f64().abs();
                                assert!(
                                    off <= b.r,
                                    "{name} step {k} λ {lambda} ± {r}: {} off by {off} > {}",
                                    x.to_f64(),
                                    b.r
                                );
                            }
                        }
                    }
                }
            }
        }
    }
}
