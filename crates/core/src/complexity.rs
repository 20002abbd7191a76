//! Low Cayley complexity by the four-cycle test, and the complete Cayley
//! vector (THEORY.md §3). About linear in the number of steps where every
//! joint is in a few clusters: the built clusters holding a joint are kept
//! per joint, and a cluster's build position is stored, not searched. At a
//! hub (a Strandbeest's pivot, held by every leg) each step reads the
//! clusters built there, once, not once per cluster on its other base joint.
//!
//! Determinism: when several valid pairs of built clusters carry a step, the
//! pair built earliest is used (smallest index of its later-built cluster,
//! then of its earlier one).

use crate::decompose::{ClusterSet, Decomposition, JointMarks};
use crate::inthash::{IntMap, int_map};

/// Why a pair of clusters is valid (adjacent in a four-cycle of clusters).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PairOrigin {
    /// The two clusters of step `j`, hinged at its vertex.
    Step(usize),
    /// Step `j`'s cluster on side `u` (or `w`) and a built cluster `other`,
    /// hinged at step j's `u` (or `w`), closed into a four-cycle through
    /// `opposite` (holding step j's other base joint), which shares joint
    /// `far` with `other`.
    FourCycle {
        /// Step j.
        step: usize,
        /// Its cluster on `u` (`true`) or on `w`.
        on_u: bool,
        /// The built cluster hinged to it.
        other: usize,
        /// The cluster closing the four-cycle.
        opposite: usize,
        /// The joint `opposite` shares with `other`.
        far: usize,
    },
}

/// The valid pair that carries a step: clusters `tu ∋ u`, `tw ∋ w`, hinged at `x`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Carrier {
    /// The built cluster containing u.
    pub tu: usize,
    /// The built cluster containing w.
    pub tw: usize,
    /// The joint shared by `tu` and `tw`: the Cayley vector gains (x, v_k).
    pub x: usize,
    /// How the pair became valid.
    pub origin: PairOrigin,
}

/// A step where the four-cycle test fails: no valid pair of built clusters
/// (adjacent in a four-cycle) holds both of its base joints.
#[derive(Debug, Clone, PartialEq)]
pub struct LccFailure {
    /// The failing step (0-based).
    pub step: usize,
    /// Pairs of built clusters holding the step's `u` and `w` that share no
    /// joint (opposite in a four-cycle), each as its sorted joints; empty when
    /// no such pair exists either.
    pub opposite: Vec<[Vec<usize>; 2]>,
}

/// The result of the four-cycle test (THEORY.md §3).
#[derive(Debug, Clone)]
pub struct Complexity {
    /// Low Cayley complexity: every endpoint is a ruler-and-compass value.
    pub low: bool,
    /// The complete Cayley vector: the base, then one non-edge `(x, v_k)` per later step.
    pub ccv: Vec<[usize; 2]>,
    /// For each step after the first, the pair that carries it (`None` for
    /// step 0, and from the failing step on when not LCC).
    pub carriers: Vec<Option<Carrier>>,
    /// The first step where the test fails (`None` when LCC).
    pub failure: Option<LccFailure>,
}

fn key(a: usize, b: usize) -> (usize, usize) {
    (a.min(b), a.max(b))
}

/// Run the four-cycle test along the construction.
pub fn four_cycle_test(dec: &Decomposition) -> Complexity {
    let clusters = &dec.clusters;
    let mut valid: IntMap<(usize, usize), PairOrigin> = int_map(4 * dec.steps.len());
    // Build position of each cluster (first time built), and per joint the
    // built clusters holding it, in build order.
    let mut built_at: Vec<usize> = vec![usize::MAX; clusters.nodes.len()];
    let mut n_built = 0usize;
    let mut holding_joint: Vec<Vec<usize>> = vec![Vec::new(); clusters.n_joints()];
    let mut ccv = Vec::with_capacity(dec.steps.len() + 1);
    ccv.push(dec.base);
    let mut carriers = vec![None; dec.steps.len()];
    let mut failure = None;
    let mut pairs = SingleSharedPairs::new();
    for (k, step) in dec.steps.iter().enumerate() {
        if k > 0 && failure.is_none() {
            let (us, ws) = (&holding_joint[step.u], &holding_joint[step.w]);
            // Only pairs hinged at one joint can carry the step or close a four-cycle.
            let hinged = pairs.find(clusters, us, ws);
            let mut best: Option<((usize, usize), Carrier)> = None;
            for &(_, _, tu, tw, x) in hinged {
                let Some(&origin) = valid.get(&key(tu, tw)) else { continue };
                let (bu, bw) = (built_at[tu], built_at[tw]);
                let rank = (bu.max(bw), bu.min(bw));
                if best.as_ref().is_none_or(|(r, _)| rank < *r) {
                    best = Some((rank, Carrier { tu, tw, x, origin }));
                }
            }
            match best {
                Some((_, carrier)) => {
                    carriers[k] = Some(carrier);
                    ccv.push([carrier.x, step.vertex]);
                    for &(_, _, tu, tw, far) in hinged {
                        valid.entry(key(step.cluster_u, tu)).or_insert(PairOrigin::FourCycle {
                            step: k,
                            on_u: true,
                            other: tu,
                            opposite: tw,
                            far,
                        });
                        valid.entry(key(step.cluster_w, tw)).or_insert(PairOrigin::FourCycle {
                            step: k,
                            on_u: false,
                            other: tw,
                            opposite: tu,
                            far,
                        });
                    }
                }
                None => {
                    failure = Some(explain_failure(dec, k, us, ws));
                }
            }
        }
        if failure.is_some() {
            ccv.push([fallback_partner(dec, k), step.vertex]);
        }
        valid.entry(key(step.cluster_u, step.cluster_w)).or_insert(PairOrigin::Step(k));
        for c in [step.cluster_u, step.cluster_w] {
            if built_at[c] == usize::MAX {
                built_at[c] = n_built;
                for &j in &clusters.nodes[c].joints {
                    holding_joint[j].push(c);
                }
            }
            n_built += 1;
        }
    }
    Complexity { low: failure.is_none(), ccv, carriers, failure }
}

/// The pairs of clusters `(tu, tw)`, `tu` from one list and `tw` from
/// another, that share exactly one joint, with that joint, in the order of
/// a loop over the first list and, inside it, the second (the order the
/// test's choices depend on). Buffers are kept from step to step.
struct SingleSharedPairs {
    /// The joints of the cluster marked last (made on first use).
    marks: Option<JointMarks>,
    /// (position in the first list, position in the second, tu, tw, joint).
    found: Vec<(usize, usize, usize, usize, usize)>,
}

impl SingleSharedPairs {
    fn new() -> Self {
        SingleSharedPairs { marks: None, found: Vec::new() }
    }

    /// The hinged pairs of `us` × `ws` as (·, ·, tu, tw, joint). A few pairs
    /// are compared directly. Otherwise each cluster of the list with fewer
    /// joints in all is marked in turn and the other list's clusters are
    /// read against it: a hub's many small clusters are read once per
    /// cluster on the other side (a few), and a big cluster (a crank body)
    /// is never merged joint by joint with each of them.
    fn find(&mut self, clusters: &ClusterSet, us: &[usize], ws: &[usize]) -> &[(usize, usize, usize, usize, usize)] {
        self.found.clear();
        if us.len() * ws.len() <= DIRECT_PAIRS {
            for (ui, &tu) in us.iter().enumerate() {
                for (wi, &tw) in ws.iter().enumerate() {
                    if let Some(joint) = clusters.single_shared(tu, tw) {
                        self.found.push((ui, wi, tu, tw, joint));
                    }
                }
            }
            return &self.found;
        }
        let marks = self.marks.get_or_insert_with(|| JointMarks::new(clusters.n_joints()));
        let size = |list: &[usize]| list.iter().map(|&c| clusters.nodes[c].joints.len()).sum::<usize>();
        let marked_us = size(us) + us.len() * size(ws) < size(ws) + ws.len() * size(us);
        let (marked, read) = if marked_us { (us, ws) } else { (ws, us) };
        for (mi, &m) in marked.iter().enumerate() {
            marks.set(&clusters.nodes[m].joints);
            for (ri, &r) in read.iter().enumerate() {
                // r's joints ascend, so the first shared one is the smallest (as `single_shared` gives).
                let mut shared = clusters.nodes[r].joints.iter().filter(|&&j| marks.has(j));
                let (Some(&joint), None) = (shared.next(), shared.next()) else { continue };
                let (ui, wi, tu, tw) = if marked_us { (mi, ri, m, r) } else { (ri, mi, r, m) };
                self.found.push((ui, wi, tu, tw, joint));
            }
        }
        if !marked_us {
            self.found.sort_unstable();
        }
        &self.found
    }
}

/// Pairs of clusters compared directly (below, marking costs more than it saves).
const DIRECT_PAIRS: usize = 16;

/// For a step past the failing one: a built joint other than `u`, `w`, so
/// that its distance to the vertex still tells the step's two orientations apart.
fn fallback_partner(dec: &Decomposition, k: usize) -> usize {
    let step = &dec.steps[k];
    let cluster = |c: usize| dec.clusters.nodes[c].joints.iter().copied();
    let built_joints = dec
        .base
        .into_iter()
        .chain(dec.steps[..k].iter().flat_map(|s| cluster(s.cluster_u).chain(cluster(s.cluster_w))));
    built_joints.into_iter().find(|&j| j != step.u && j != step.w).unwrap_or(dec.base[0])
}

fn explain_failure(dec: &Decomposition, k: usize, us: &[usize], ws: &[usize]) -> LccFailure {
    let joints = |c: usize| dec.clusters.nodes[c].joints.clone();
    let opposite = us
        .iter()
        .flat_map(|&tu| ws.iter().map(move |&tw| (tu, tw)))
        .filter(|&(tu, tw)| dec.clusters.shared(tu, tw).is_empty())
        .map(|(tu, tw)| [joints(tu), joints(tw)])
        .collect();
    LccFailure { step: k, opposite }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::decompose::Origin;
    use crate::linkage::Linkage;
    use crate::scene::parse_scene;

    /// Marking finds the hinged pairs that comparing every pair finds, in
    /// the same order, whichever list it marks: on clusters round a hub
    /// (joint 0, in many small clusters) and a big cluster (joints 10–29).
    #[test]
    fn hinged_pairs_are_those_of_every_pair_compared() {
        let mut text = String::from("bars = [\n");
        for i in 0..29 {
            text += &format!("[\"J{i}\", \"J{}\"],\n", i + 1);
        }
        text += "]\n[joints]\n";
        for i in 0..30 {
            text += &format!("J{i} = [{}, {}]\n", i as f64, (i % 3) as f64);
        }
        let linkage = Linkage::from_scene(&parse_scene(&text, "hub.toml", "hub").unwrap());
        let mut set = ClusterSet::initial(&linkage);
        set.add((10..30).collect(), Origin::Base);
        for j in 1..25 {
            set.add(vec![0, j, j + 1], Origin::Base);
        }
        for j in 0..8 {
            set.add(vec![15, j], Origin::Base);
        }
        let holding = |j: usize| (0..set.nodes.len()).filter(|&c| set.nodes[c].joints.contains(&j)).collect::<Vec<_>>();
        let size = |list: &[usize]| list.iter().map(|&c| set.nodes[c].joints.len()).sum::<usize>();
        let mut pairs = SingleSharedPairs::new();
        let mut marked = [0, 0];
        for a in 0..30 {
            for b in 0..30 {
                let (us, ws) = (holding(a), holding(b));
                let direct: Vec<_> = us
                    .iter()
                    .enumerate()
                    .flat_map(|(ui, &tu)| {
                        let set = &set;
                        ws.iter()
                            .enumerate()
                            .filter_map(move |(wi, &tw)| set.single_shared(tu, tw).map(|j| (ui, wi, tu, tw, j)))
                    })
                    .collect();
                assert_eq!(pairs.find(&set, &us, &ws), &direct[..], "joints {a} and {b}");
                if us.len() * ws.len() > DIRECT_PAIRS {
                    let marks_us = size(&us) + us.len() * size(&ws) < size(&ws) + ws.len() * size(&us);
                    marked[usize::from(marks_us)] += 1;
                }
            }
        }
        assert!(marked.iter().all(|&n| n > 0), "each list marked somewhere: {marked:?}");
    }
}
