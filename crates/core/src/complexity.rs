//! Low Cayley complexity by the four-cycle test, and the complete Cayley
//! vector (THEORY.md §3). About linear in the number of steps: the built
//! clusters holding a joint are kept per joint, and a cluster's build
//! position is stored, not searched. At a hub (a Strandbeest's pivot, held
//! by every leg) a step meets the clusters there through the joints of its
//! few clusters on the other side, or continues reading them where it last
//! stopped against the same cluster (a crank body holding every crank tip):
//! it never reads every cluster at the hub again.
//!
//! Determinism: when several valid pairs of built clusters carry a step, the
//! pair built earliest is used (smallest index of its later-built cluster,
//! then of its earlier one).

use crate::decompose::{ClusterSet, Decomposition};
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
    let asked = StepBases::new(dec);
    for (k, step) in dec.steps.iter().enumerate() {
        if k > 0 && failure.is_none() {
            let (us, ws) = (&holding_joint[step.u], &holding_joint[step.w]);
            // Only pairs hinged at one joint can carry the step or close a four-cycle.
            let hinged = pairs.find(clusters, &holding_joint, &built_at, [step.u, step.w]);
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
                        // Step k's cluster on each side hinged to the built cluster there.
                        for (own, other, opposite, on_u) in
                            [(step.cluster_u, tu, tw, true), (step.cluster_w, tw, tu, false)]
                        {
                            if asked.may_ask(clusters, own, other) {
                                let origin = PairOrigin::FourCycle { step: k, on_u, other, opposite, far };
                                valid.entry(key(own, other)).or_insert(origin);
                            }
                        }
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

/// Every step's base joints, as unordered pairs. The test asks whether a
/// pair of clusters is valid only of a pair holding some step's base
/// joints one each, so a four-cycle pair holding no such joints is never
/// stored: a fan of n steps on one base makes n²/2 of them (3,000 steps:
/// 1.5 GB), and none is ever asked.
struct StepBases(IntMap<(usize, usize), ()>);

impl StepBases {
    fn new(dec: &Decomposition) -> Self {
        let mut set = int_map(dec.steps.len());
        for s in &dec.steps {
            set.insert(key(s.u, s.w), ());
        }
        StepBases(set)
    }

    /// Whether some step's base joints lie one in each of clusters `p` and
    /// `q`. Past [`ASK_CHECK_PAIRS`] joint pairs it answers yes unread
    /// (storing a pair never asked changes nothing).
    fn may_ask(&self, clusters: &ClusterSet, p: usize, q: usize) -> bool {
        let (a, b) = (&clusters.nodes[p].joints, &clusters.nodes[q].joints);
        a.len() * b.len() > ASK_CHECK_PAIRS
            || a.iter().any(|&x| b.iter().any(|&y| x != y && self.0.contains_key(&key(x, y))))
    }
}

/// The most joint pairs [`StepBases::may_ask`] reads.
const ASK_CHECK_PAIRS: usize = 64;

/// The pairs of clusters `(tu, tw)`, `tu` built at joint u and `tw` at
/// joint w, that share exactly one joint, with that joint, in the order of
/// a loop over u's clusters and, inside it, w's (the order the test's
/// choices depend on). Buffers and reads are kept from step to step.
struct SingleSharedPairs {
    /// (position at u, position at w, tu, tw, joint).
    found: Vec<(usize, usize, usize, usize, usize)>,
    /// Per (joint, cluster): how many of the clusters at the joint were read
    /// against the cluster, and the hinged ones among them (position,
    /// shared joint). A joint's clusters only grow, in build order, so a
    /// second read starts where the first stopped.
    read: IntMap<(usize, usize), Read>,
    /// Scratch: (cluster, joint) met through a cluster's joints.
    met: Vec<(usize, usize)>,
    /// Scratch: one cluster's hinged partners (position, joint).
    partners: Vec<(usize, usize)>,
    /// How often each way was taken: [through joints, by reading].
    #[cfg(test)]
    ways: [usize; 2],
}

/// What [`SingleSharedPairs::read`] keeps for one (joint, cluster).
#[derive(Default)]
struct Read {
    seen: usize,
    hinged: Vec<(usize, usize)>,
}

impl SingleSharedPairs {
    fn new() -> Self {
        SingleSharedPairs {
            found: Vec::new(),
            read: IntMap::default(),
            met: Vec::new(),
            partners: Vec::new(),
            #[cfg(test)]
            ways: [0, 0],
        }
    }

    /// The hinged pairs of the clusters built at `u` and at `w`
    /// (`holding[j]`: the clusters built at joint j, in build order;
    /// `rank`: each cluster's build position). A few pairs are compared
    /// directly. Otherwise each cluster of the shorter list is met with
    /// the longer one ([`Self::partners_at`]): at a hub (a Strandbeest's
    /// pivot, held by every leg) a step reads only its few clusters on the
    /// other side, not every cluster at the hub.
    fn find(
        &mut self,
        clusters: &ClusterSet,
        holding: &[Vec<usize>],
        rank: &[usize],
        [u, w]: [usize; 2],
    ) -> &[(usize, usize, usize, usize, usize)] {
        self.found.clear();
        let (us, ws) = (&holding[u], &holding[w]);
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
        let short_at_w = ws.len() <= us.len();
        let (short, long_at) = if short_at_w { (ws, u) } else { (us, w) };
        let mut partners = std::mem::take(&mut self.partners);
        for (si, &s) in short.iter().enumerate() {
            self.partners_at(clusters, holding, rank, s, long_at, &mut partners);
            for &(li, joint) in &partners {
                let l = holding[long_at][li];
                let pair = if short_at_w { (li, si, l, s, joint) } else { (si, li, s, l, joint) };
                self.found.push(pair);
            }
        }
        self.partners = partners;
        self.found.sort_unstable();
        &self.found
    }

    /// The clusters built at joint `at` that share exactly one joint with
    /// cluster `s`, as (position at `at`, joint), into `out`. Found through
    /// `s`'s joints (the clusters at each that also hold `at`) where those
    /// are fewer than the clusters at `at`; otherwise by reading the
    /// clusters at `at` against `s`, continuing an earlier read of the same
    /// pair (a hub's list against a big cluster, a crank body, asked at
    /// every leg). A cluster holding `at` itself shares it with every
    /// cluster there; its read is not kept (the answer is as long as the
    /// list, and kept answers of that size would grow with the square of
    /// the hub).
    fn partners_at(
        &mut self,
        clusters: &ClusterSet,
        holding: &[Vec<usize>],
        rank: &[usize],
        s: usize,
        at: usize,
        out: &mut Vec<(usize, usize)>,
    ) {
        out.clear();
        let list = &holding[at];
        let joints = &clusters.nodes[s].joints;
        // A pair read before is read on (its count of the clusters through
        // `s`'s joints, a crank body's thousands, is not made again). Else
        // through the joints where the clusters there are fewer than at
        // `at`, counted only that far. (Where `s` holds `at`, every cluster
        // there shares it with `s`: the count reaches them all.)
        let through = !self.read.contains_key(&(at, s)) && {
            let mut count = 0;
            joints.iter().all(|&j| {
                count += holding[j].len();
                count < list.len()
            })
        };
        #[cfg(test)]
        {
            self.ways[usize::from(!through)] += 1;
        }
        if through {
            // A cluster at `at` met through exactly one of s's joints shares only that one.
            self.met.clear();
            for &j in joints {
                self.met.extend(holding[j].iter().filter(|&&c| clusters.contains(c, at)).map(|&c| (c, j)));
            }
            self.met.sort_unstable();
            for run in self.met.chunk_by(|a, b| a.0 == b.0) {
                if let [(c, joint)] = *run {
                    let position = list.binary_search_by_key(&rank[c], |&x| rank[x]).expect("built at `at`");
                    out.push((position, joint));
                }
            }
            return;
        }
        // Where `s` holds `at`, every cluster there shares it with `s`: the
        // answer is about as long as the list, so it is read afresh, not kept.
        let mut afresh = Read::default();
        let read = if clusters.contains(s, at) { &mut afresh } else { self.read.entry((at, s)).or_default() };
        for (position, &c) in list.iter().enumerate().skip(read.seen) {
            if let Some(joint) = clusters.single_shared(c, s) {
                read.hinged.push((position, joint));
            }
        }
        read.seen = list.len();
        out.extend_from_slice(&read.hinged);
    }
}

/// Pairs of clusters compared directly (below, a search costs more than it saves).
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

    /// The pair search finds the hinged pairs that comparing every pair
    /// finds, in the same order, both through a cluster's joints and by
    /// reading (continued as the lists grow): on clusters round a hub
    /// (joint 0, in many small clusters), a big cluster (joints 10–29) and
    /// a cluster holding the hub and one of the big cluster's joints.
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
        let mut added: Vec<Vec<usize>> = vec![(10..30).collect()];
        added.extend((1..25).map(|j| vec![0, j, j + 1]));
        added.extend((0..8).map(|j| vec![15, j]));
        added.push(vec![0, 3, 12]);
        let mut pairs = SingleSharedPairs::new();
        let n_added = added.len();
        for (i, joints) in added.into_iter().enumerate() {
            set.add(joints, Origin::Base);
            // Ask after every fourth cluster: later asks continue earlier reads.
            if i % 4 != 3 && i + 1 != n_added {
                continue;
            }
            let holding: Vec<Vec<usize>> =
                (0..30).map(|j| (0..set.nodes.len()).filter(|&c| set.nodes[c].joints.contains(&j)).collect()).collect();
            let rank: Vec<usize> = (0..set.nodes.len()).collect();
            for a in 0..30 {
                for b in 0..30 {
                    let (us, ws) = (&holding[a], &holding[b]);
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
                    assert_eq!(pairs.find(&set, &holding, &rank, [a, b]), &direct[..], "joints {a} and {b}, {i}");
                }
            }
        }
        assert!(pairs.ways.iter().all(|&n| n > 0), "each way taken somewhere: {:?}", pairs.ways);
    }
}
