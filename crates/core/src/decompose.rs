//! Recognition of 1-dof tree-decomposable linkages: rigidity counting (the
//! (2,3) pebble game), cluster decomposition by merging triangles of clusters,
//! the base non-edge, and the construction steps `v ◁ (u, w)`.

use crate::linkage::{Constraint, Linkage};

/// How a cluster was formed; the merge tree lets cluster shapes be computed
/// from bar lengths alone (a sketch's drawing only fixes orientations).
#[derive(Debug, Clone, PartialEq)]
pub enum Origin {
    /// The cluster of bar `i`.
    Bar(usize),
    /// The cluster of body `i`.
    Body(usize),
    /// The base non-edge (only in the merge from a base, never in `G`'s clusters).
    Base,
    /// Three clusters pairwise sharing one joint: `shared[i]` is the joint
    /// shared by `parts[i]` and `parts[(i + 1) % 3]`.
    Triangle {
        /// The three merged clusters.
        parts: [usize; 3],
        /// The joints they pairwise share.
        shared: [usize; 3],
    },
    /// Two clusters sharing two or more joints (only in over-constrained input).
    Overlap {
        /// The two merged clusters.
        parts: [usize; 2],
    },
}

/// One cluster: its joints and how it was formed.
#[derive(Debug, Clone)]
pub struct ClusterNode {
    /// Sorted joint indices.
    pub joints: Vec<usize>,
    /// How it was formed (a bar, a body, or a merge).
    pub origin: Origin,
}

/// Clusters under merging. Node ids are stable; merged nodes stay in the list
/// (dead) so the merge tree can be walked.
#[derive(Debug, Clone)]
pub struct ClusterSet {
    /// Every cluster ever formed, indexed by id (merged ones included).
    pub nodes: Vec<ClusterNode>,
    alive: Vec<bool>,
    by_joint: Memberships,
    /// Per joint: the live clusters holding it, and their joints in all.
    live_at: Vec<Held>,
}

/// The live clusters at a joint: how many, and their joints in all (what a
/// search through them reads).
#[derive(Debug, Clone, Copy, Default)]
struct Held {
    clusters: usize,
    joints: usize,
    /// Dead clusters still in the joint's list (see [`ClusterSet::add`]).
    dead: usize,
}

/// No entry (the end of a [`Memberships`] list).
const NONE: usize = usize::MAX;

/// Which clusters hold each joint: one list per joint, all in a single arena
/// (three allocations however many joints; a `Vec` per joint made building
/// and cloning a set allocate once per joint and again as each grew). A
/// list keeps insertion order, which is creation order, so the clusters at
/// a joint come out in the same order as before.
#[derive(Debug, Clone)]
struct Memberships {
    /// Per joint: its first entry, or [`NONE`].
    head: Vec<usize>,
    /// Per joint: its last entry, or [`NONE`] (appending is O(1)).
    tail: Vec<usize>,
    /// (cluster, next entry of the same joint or [`NONE`]).
    entries: Vec<(usize, usize)>,
}

impl Memberships {
    /// Lists for `n_joints` joints, with room for `capacity` entries.
    fn new(n_joints: usize, capacity: usize) -> Self {
        Memberships { head: vec![NONE; n_joints], tail: vec![NONE; n_joints], entries: Vec::with_capacity(capacity) }
    }

    fn n_joints(&self) -> usize {
        self.head.len()
    }

    /// Record that `cluster` holds `joint` (after every cluster recorded before).
    fn push(&mut self, joint: usize, cluster: usize) {
        let at = self.entries.len();
        self.entries.push((cluster, NONE));
        match self.tail[joint] {
            NONE => self.head[joint] = at,
            last => self.entries[last].1 = at,
        }
        self.tail[joint] = at;
    }

    /// Unlink the clusters `alive` says are dead from `joint`'s list (the
    /// others keep their order). Called at a joint of a new cluster once its
    /// dead clusters outnumber its live ones ([`ClusterSet::add`]), so a
    /// joint's list stays at most about twice as long as the live clusters
    /// holding it (on a strip of merged triangles it grew by one entry per
    /// merge, and every search at the joint walked them all).
    fn purge(&mut self, joint: usize, alive: &[bool]) {
        let (mut prev, mut at) = (NONE, self.head[joint]);
        while at != NONE {
            let (cluster, next) = self.entries[at];
            if alive[cluster] {
                prev = at;
            } else if prev == NONE {
                self.head[joint] = next;
            } else {
                self.entries[prev].1 = next;
            }
            at = next;
        }
        self.tail[joint] = prev;
    }

    /// The clusters holding `joint` in creation order (dead ones included
    /// until they are purged: see [`Self::purge`]).
    fn of(&self, joint: usize) -> impl Iterator<Item = usize> + '_ {
        let mut at = self.head[joint];
        std::iter::from_fn(move || {
            let (cluster, next) = *self.entries.get(at)?;
            at = next;
            Some(cluster)
        })
    }
}

/// The joints of one cluster marked in a reusable buffer: whether a joint
/// is in it is one lookup, not a binary search (and no allocation).
struct JointMarks {
    /// `stamp[j] == round`: joint j is in the marked cluster.
    stamp: Vec<u32>,
    round: u32,
}

impl JointMarks {
    fn new(n_joints: usize) -> Self {
        JointMarks { stamp: vec![0; n_joints], round: 0 }
    }

    /// Mark exactly `joints` (forgetting the previous marks).
    fn set(&mut self, joints: &[usize]) {
        self.round += 1;
        for &j in joints {
            self.stamp[j] = self.round;
        }
    }

    fn has(&self, joint: usize) -> bool {
        self.stamp[joint] == self.round
    }
}

/// For one cluster `a`: how many joints each live cluster shares with it
/// (counted up to two) and the smallest shared one, found in one pass over
/// the clusters at `a`'s joints. The triangle search then asks "does c share
/// exactly one joint with a" by a lookup instead of merging two joint lists
/// for every cluster it meets. Buffers are reused from cluster to cluster.
struct Meets {
    /// `stamp[c] == round`: cluster c shares a joint with the current `a`.
    stamp: Vec<u32>,
    round: u32,
    /// Joints shared with `a`, counted up to two.
    count: Vec<u8>,
    /// The smallest joint shared with `a`.
    first: Vec<usize>,
}

impl Meets {
    /// Room for `clusters` clusters (more grow the buffers).
    fn with_capacity(clusters: usize) -> Self {
        Meets { stamp: vec![0; clusters], round: 0, count: vec![0; clusters], first: vec![usize::MAX; clusters] }
    }

    /// Count the joints every live cluster shares with `a` (`a` itself excluded).
    fn around(&mut self, set: &ClusterSet, a: usize) {
        self.round += 1;
        let n = set.nodes.len();
        if self.stamp.len() < n {
            self.stamp.resize(n, 0);
            self.count.resize(n, 0);
            self.first.resize(n, usize::MAX);
        }
        // a's joints ascend, so the first one recorded is the smallest.
        for &p in &set.nodes[a].joints {
            for c in set.containing(p) {
                if c == a {
                    continue;
                }
                if self.stamp[c] == self.round {
                    self.count[c] = 2;
                } else {
                    self.stamp[c] = self.round;
                    self.count[c] = 1;
                    self.first[c] = p;
                }
            }
        }
    }

    /// Like [`ClusterSet::meet`] of `a` and `c`: the shared joints counted up
    /// to two, and the first (`usize::MAX` when none).
    fn with(&self, c: usize) -> (usize, usize) {
        if self.stamp[c] == self.round { (usize::from(self.count[c]), self.first[c]) } else { (0, usize::MAX) }
    }
}

fn sorted_intersection(a: &[usize], b: &[usize]) -> Vec<usize> {
    let (mut i, mut j, mut out) = (0, 0, Vec::new());
    while i < a.len() && j < b.len() {
        match a[i].cmp(&b[j]) {
            std::cmp::Ordering::Less => i += 1,
            std::cmp::Ordering::Greater => j += 1,
            std::cmp::Ordering::Equal => {
                out.push(a[i]);
                i += 1;
                j += 1;
            }
        }
    }
    out
}

/// Joint lists this many times longer than the other are searched, not merged.
const LOPSIDED: usize = 8;

/// A cluster of at most this many joints, beside a hub, is merged by
/// [`ClusterSet::merge_by_pairs`].
const PAIR_SEARCH_JOINTS: usize = 8;

/// A joint in more clusters than this may be a hub (see [`ClusterSet::merge_at_joints`]).
const HUB_CLUSTERS: usize = 8;

/// Joints in the clusters at a cluster's joints, in all, above which the
/// search from its joints' clusters ([`ClusterSet::merge_at_joints`]) costs
/// more than the one by pairs of its joints.
const PAIR_SEARCH_ABOVE: usize = 64;

/// [`ClusterSet::meet`] of a few joints and many (a crank body): each of
/// the few looked up. They ascend, so the first found is the smallest shared.
#[inline(never)]
fn meet_lopsided(x: &[usize], y: &[usize]) -> (usize, usize) {
    let (short, long) = if x.len() <= y.len() { (x, y) } else { (y, x) };
    let mut shared = short.iter().filter(|j| long.binary_search(j).is_ok());
    match (shared.next(), shared.next()) {
        (None, _) => (0, usize::MAX),
        (Some(&j), None) => (1, j),
        (Some(&j), Some(_)) => (2, j),
    }
}

/// A merge found by [`ClusterSet::find_merge`].
#[derive(Debug, Clone, Copy, PartialEq)]
enum Merge {
    Triangle { parts: [usize; 3], shared: [usize; 3] },
    Overlap { parts: [usize; 2] },
}

impl ClusterSet {
    /// One cluster per bar and per body (a bar that a body already holds,
    /// agreeing with it, is no cluster of its own: see [`bars_within_bodies`]).
    pub fn initial(linkage: &Linkage) -> ClusterSet {
        // Each merge kills two or three clusters and makes one, so a set ends
        // with fewer than twice its initial clusters: reserved once, not grown.
        let initial = linkage.bars.len() + linkage.bodies.len();
        let memberships = 2 * linkage.bars.len() + linkage.bodies.iter().map(Vec::len).sum::<usize>();
        let mut set = ClusterSet {
            nodes: Vec::with_capacity(2 * initial),
            alive: Vec::with_capacity(2 * initial),
            by_joint: Memberships::new(linkage.n_joints(), 2 * memberships),
            live_at: vec![Held::default(); linkage.n_joints()],
        };
        let within = bars_within_bodies(linkage);
        let ignored = |i: usize| within.iter().any(|b| b.agrees && b.bar == i);
        for (i, bar) in linkage.bars.iter().enumerate() {
            if !ignored(i) {
                set.add(bar.joints.to_vec(), Origin::Bar(i));
            }
        }
        for (i, body) in linkage.bodies.iter().enumerate() {
            set.add(body.clone(), Origin::Body(i));
        }
        set
    }

    /// Add a cluster on `joints` (sorted and deduplicated) formed by `origin`; its id.
    pub fn add(&mut self, mut joints: Vec<usize>, origin: Origin) -> usize {
        joints.sort_unstable();
        joints.dedup();
        let id = self.nodes.len();
        for &j in &joints {
            // Purged once the dead outnumber the live: a list stays at most
            // about twice as long as the live clusters at its joint, and a
            // hub's list is not walked at every merge there.
            if self.live_at[j].dead > self.live_at[j].clusters {
                self.by_joint.purge(j, &self.alive);
                self.live_at[j].dead = 0;
            }
            self.by_joint.push(j, id);
            self.live_at[j].clusters += 1;
            self.live_at[j].joints += joints.len();
        }
        self.nodes.push(ClusterNode { joints, origin });
        self.alive.push(true);
        id
    }

    /// The number of joints (cluster joints are below it).
    pub fn n_joints(&self) -> usize {
        self.by_joint.n_joints()
    }

    /// Whether cluster `id` has not been merged into a bigger one.
    pub fn is_alive(&self, id: usize) -> bool {
        self.alive[id]
    }

    /// Ids of the clusters not merged into a bigger one, in creation order.
    pub fn alive_ids(&self) -> Vec<usize> {
        (0..self.nodes.len()).filter(|&i| self.alive[i]).collect()
    }

    /// The joints clusters `a` and `b` share, sorted.
    pub fn shared(&self, a: usize, b: usize) -> Vec<usize> {
        sorted_intersection(&self.nodes[a].joints, &self.nodes[b].joints)
    }

    pub(crate) fn contains(&self, id: usize, joint: usize) -> bool {
        self.nodes[id].joints.binary_search(&joint).is_ok()
    }

    /// Whether a live cluster holds both joints (they are rigidly joined).
    pub fn clustered(&self, a: usize, b: usize) -> bool {
        self.holding_both(a, b).next().is_some()
    }

    /// The joints clusters `a` and `b` share, counted up to two, and the
    /// first of them (`usize::MAX` when none): [`Self::shared`] without allocating.
    fn meet(&self, a: usize, b: usize) -> (usize, usize) {
        let (x, y) = (&self.nodes[a].joints, &self.nodes[b].joints);
        if x.len() * LOPSIDED < y.len() || y.len() * LOPSIDED < x.len() {
            return meet_lopsided(x, y);
        }
        let (mut i, mut j, mut count, mut first) = (0, 0, 0, usize::MAX);
        while i < x.len() && j < y.len() {
            match x[i].cmp(&y[j]) {
                std::cmp::Ordering::Less => i += 1,
                std::cmp::Ordering::Greater => j += 1,
                std::cmp::Ordering::Equal => {
                    if count == 0 {
                        first = x[i];
                    }
                    count += 1;
                    if count == 2 {
                        break;
                    }
                    i += 1;
                    j += 1;
                }
            }
        }
        (count, first)
    }

    /// The joint clusters `a` and `b` share when they share exactly one.
    pub fn single_shared(&self, a: usize, b: usize) -> Option<usize> {
        match self.meet(a, b) {
            (1, j) => Some(j),
            _ => None,
        }
    }

    /// Live clusters containing `joint`.
    pub fn containing(&self, joint: usize) -> impl Iterator<Item = usize> + '_ {
        self.by_joint.of(joint).filter(|&c| self.alive[c])
    }

    /// A merge involving cluster `a`: a triangle of clusters (pairwise one
    /// shared joint, three distinct joints) or an overlap of two or more joints.
    /// `marks` and `meets` are scratch space (they end up describing `a`).
    fn find_merge(&self, a: usize, marks: &mut JointMarks, meets: &mut Meets) -> Option<Merge> {
        let joints = &self.nodes[a].joints;
        if joints.len() <= PAIR_SEARCH_JOINTS {
            // What each search reads first: every cluster at each joint, or
            // for each two joints the clusters at the one in fewer.
            let read = |j: usize| self.live_at[j].joints;
            let around: usize = joints.iter().map(|&j| read(j)).sum();
            let by_pairs = || {
                let pairs = joints.iter().enumerate().flat_map(|(i, &p)| joints[i + 1..].iter().map(move |&r| (p, r)));
                pairs.map(|(p, r)| 2 * read(p).min(read(r))).sum::<usize>()
            };
            if around > PAIR_SEARCH_ABOVE && by_pairs() < around {
                return self.merge_by_pairs(a);
            }
        }
        self.merge_at_joints(a, marks, meets)
    }

    /// [`Self::find_merge`] through the clusters at each joint of `a` in
    /// turn: the first merge in the order of a's joints p, the clusters b at
    /// p (an overlap before b's triangles), b's joints q, the clusters c at q.
    fn merge_at_joints(&self, a: usize, marks: &mut JointMarks, meets: &mut Meets) -> Option<Merge> {
        let joints = &self.nodes[a].joints;
        marks.set(joints);
        meets.around(self, a);
        // The clusters at a's joints: a c closing a triangle is one of them.
        let at_a = || joints.iter().map(|&r| self.live_at[r].clusters).sum::<usize>();
        for &p in joints {
            for b in self.containing(p) {
                if b == a {
                    continue;
                }
                if meets.with(b).0 >= 2 {
                    return Some(Merge::Overlap { parts: [a, b] });
                }
                for &q in &self.nodes[b].joints {
                    if q == p || marks.has(q) {
                        continue;
                    }
                    // Most clusters at q miss `a`: that test first.
                    let closes =
                        |c: usize| c != a && c != b && meets.with(c).0 == 1 && self.single_shared(b, c) == Some(q);
                    // The first such c at q; at a hub q, the first of those at
                    // a's joints that hold q (the same cluster: the one of least id).
                    let held = self.live_at[q].clusters;
                    let c = if held > HUB_CLUSTERS && held > at_a() {
                        joints
                            .iter()
                            .flat_map(|&r| self.containing(r))
                            .filter(|&c| self.contains(c, q) && closes(c))
                            .min()
                    } else {
                        self.containing(q).find(|&c| closes(c))
                    };
                    if let Some(c) = c {
                        return Some(Merge::Triangle { parts: [a, b, c], shared: [p, q, meets.with(c).1] });
                    }
                }
            }
        }
        None
    }

    /// [`Self::merge_at_joints`]'s answer for a small cluster `a` beside a
    /// hub (a joint in many clusters) or a big cluster: for each two of its
    /// joints p and r, the clusters holding both (overlaps), and the
    /// triangles whose b holds p and c holds r, searched from the side whose
    /// clusters hold fewer joints, each other cluster found among those
    /// holding two given joints ([`Self::holding_both`]). Of everything found,
    /// the first in `merge_at_joints`' order: so the same merge.
    fn merge_by_pairs(&self, a: usize) -> Option<Merge> {
        let joints = &self.nodes[a].joints;
        let outside = |q: usize| joints.binary_search(&q).is_err();
        // (p, b, 0, …) an overlap, (p, b, 1, q, c, r) a triangle.
        let mut first: Option<(usize, usize, u8, usize, usize, usize)> = None;
        let mut keep = |found: (usize, usize, u8, usize, usize, usize)| {
            if first.is_none_or(|f| found < f) {
                first = Some(found);
            }
        };
        for &p in joints {
            for &r in joints.iter().filter(|&&r| r != p) {
                if p < r {
                    for b in self.holding_both(p, r).filter(|&b| b != a) {
                        // Met first at its smallest joint shared with a.
                        keep((self.meet(a, b).1, b, 0, 0, 0, 0));
                    }
                }
                if self.live_at[p].joints <= self.live_at[r].joints {
                    for b in self.containing(p).filter(|&b| b != a && self.meet(a, b).0 < 2) {
                        for &q in self.nodes[b].joints.iter().filter(|&&q| outside(q)) {
                            for c in self.holding_both(q, r) {
                                if c != a && c != b && self.meet(a, c) == (1, r) && self.single_shared(b, c) == Some(q)
                                {
                                    keep((p, b, 1, q, c, r));
                                }
                            }
                        }
                    }
                } else {
                    for c in self.containing(r).filter(|&c| c != a && self.meet(a, c) == (1, r)) {
                        for &q in self.nodes[c].joints.iter().filter(|&&q| outside(q)) {
                            for b in self.holding_both(q, p) {
                                if b != a && b != c && self.meet(a, b).0 < 2 && self.single_shared(b, c) == Some(q) {
                                    keep((p, b, 1, q, c, r));
                                }
                            }
                        }
                    }
                }
            }
        }
        first.map(|(p, b, kind, q, c, r)| match kind {
            0 => Merge::Overlap { parts: [a, b] },
            _ => Merge::Triangle { parts: [a, b, c], shared: [p, q, r] },
        })
    }

    /// Live clusters holding both joints, from the joint in fewer clusters.
    fn holding_both(&self, x: usize, y: usize) -> impl Iterator<Item = usize> + '_ {
        let (few, other) = if self.live_at[x].clusters <= self.live_at[y].clusters { (x, y) } else { (y, x) };
        self.containing(few).filter(move |&c| self.contains(c, other))
    }

    fn apply(&mut self, merge: Merge) -> usize {
        let (buf, len, origin) = match merge {
            Merge::Triangle { parts, shared } => (parts, 3, Origin::Triangle { parts, shared }),
            Merge::Overlap { parts: [a, b] } => ([a, b, b], 2, Origin::Overlap { parts: [a, b] }),
        };
        let parts = &buf[..len];
        let mut joints = Vec::with_capacity(parts.iter().map(|&p| self.nodes[p].joints.len()).sum());
        for &p in parts {
            self.alive[p] = false;
            let part = &self.nodes[p].joints;
            joints.extend_from_slice(part);
            for &j in part {
                self.live_at[j].clusters -= 1;
                self.live_at[j].joints -= part.len();
                self.live_at[j].dead += 1;
            }
        }
        self.add(joints, origin)
    }

    /// Merge until nothing merges. A new triangle can only involve a newly
    /// made cluster, so each cluster is examined once when it appears.
    pub fn merge_all(&mut self) {
        let mut work: Vec<usize> = Vec::with_capacity(self.nodes.capacity());
        work.extend((0..self.nodes.len()).rev().filter(|&i| self.alive[i]));
        // Every cluster the merges can make fits the set's reserved room.
        let (mut marks, mut meets) = (JointMarks::new(self.n_joints()), Meets::with_capacity(self.nodes.capacity()));
        while let Some(a) = work.pop() {
            if !self.alive[a] {
                continue;
            }
            if let Some(m) = self.find_merge(a, &mut marks, &mut meets) {
                let d = self.apply(m);
                work.push(d);
            }
        }
    }
}

/// Result of the (2,3) pebble game on the constraint graph.
#[derive(Debug, Clone)]
pub struct Rigidity {
    /// Degrees of freedom after removing rigid motions: 2n − 3 − independent.
    pub dof: usize,
    /// Constraints rejected as dependent (each over-constrains the linkage).
    pub redundant: Vec<Constraint>,
}

/// A bar between two joints of one body.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BodyBar {
    /// The bar (index into the linkage's bars).
    pub bar: usize,
    /// The body holding both its joints.
    pub body: usize,
    /// Its length agrees with the body's drawn shape ([`crate::scene::body_bar_agrees`]).
    pub agrees: bool,
}

/// Bars joining two joints of one body. The body holds those joints rigidly
/// already: a bar that agrees with it adds no constraint, so recognition
/// ignores it (and the report says so); one that disagrees over-constrains
/// the linkage, and the rigidity count names that bar as redundant.
pub fn bars_within_bodies(linkage: &Linkage) -> Vec<BodyBar> {
    let mut out = Vec::new();
    if linkage.bodies.is_empty() {
        return out;
    }
    // The bodies holding each joint, ascending (one pass over the bodies,
    // not a search of every body for every bar: a crank body holds a
    // Strandbeest's every leg).
    let mut bodies_at: Vec<Vec<usize>> = vec![Vec::new(); linkage.n_joints()];
    for (i, body) in linkage.bodies.iter().enumerate() {
        for &j in body {
            bodies_at[j].push(i);
        }
    }
    let at = |j: usize| &bodies_at[j];
    for (bar, b) in linkage.bars.iter().enumerate() {
        let [p, q] = b.joints;
        if let Some(&body) = at(p).iter().find(|i| at(q).contains(i)) {
            let drawn = crate::linkage::dist(linkage.drawn[p], linkage.drawn[q]);
            let agrees = crate::scene::body_bar_agrees(b.length, drawn, linkage.scale);
            out.push(BodyBar { bar, body, agrees });
        }
    }
    out
}

/// Generic 2D rigidity by the (2,3) pebble game (Jacobs–Hendrickson), O(n·m).
/// Bars within bodies are ignored when they agree with the body, and counted
/// last when they do not (so they, not the body, are named redundant).
pub fn rigidity(linkage: &Linkage) -> Rigidity {
    let n = linkage.n_joints();
    let mut pebbles = vec![2u8; n];
    let mut out = vec![OutEdges::default(); n];
    let mut independent = 0usize;
    let mut redundant = Vec::new();
    let mut search = PebbleSearch::new(n);
    let within = bars_within_bodies(linkage);
    let is = |c: &Constraint, agrees: bool| within.iter().any(|b| *c == Constraint::Bar(b.bar) && b.agrees == agrees);
    let edges = linkage.constraint_edges();
    let ordered =
        edges.iter().filter(|(_, c)| !is(c, true) && !is(c, false)).chain(edges.iter().filter(|(_, c)| is(c, false)));
    for &([u, v], origin) in ordered {
        let accepted = loop {
            if pebbles[u] + pebbles[v] >= 4 {
                break true;
            }
            let found = (pebbles[u] < 2 && search.fetch(u, v, &mut pebbles, &mut out))
                || (pebbles[v] < 2 && search.fetch(v, u, &mut pebbles, &mut out));
            if !found {
                break false;
            }
        };
        if accepted {
            pebbles[u] -= 1;
            out[u].push(v);
            independent += 1;
        } else if !redundant.contains(&origin) {
            redundant.push(origin);
        }
    }
    Rigidity { dof: (2 * n).saturating_sub(3 + independent), redundant }
}

/// A joint's out-edges in the pebble game: each covers one of its two
/// pebbles, so there are at most two (kept inline, no allocation). Order as
/// a `Vec` with `swap_remove` and `push` would keep it.
#[derive(Debug, Clone, Copy, Default)]
struct OutEdges {
    to: [usize; 2],
    len: u8,
}

impl OutEdges {
    fn as_slice(&self) -> &[usize] {
        &self.to[..usize::from(self.len)]
    }

    fn push(&mut self, j: usize) {
        debug_assert!(self.len < 2, "a joint covers at most two edges");
        self.to[usize::from(self.len)] = j;
        self.len += 1;
    }

    fn swap_remove(&mut self, pos: usize) {
        self.len -= 1;
        self.to[pos] = self.to[usize::from(self.len)];
    }
}

/// The depth-first search of the pebble game, with its buffers kept
/// between searches (a search visits few joints; clearing n of them each
/// time made the game quadratic).
struct PebbleSearch {
    parent: Vec<usize>,
    /// `seen[j] == round`: visited in the current search.
    seen: Vec<u32>,
    round: u32,
    stack: Vec<usize>,
}

impl PebbleSearch {
    fn new(n: usize) -> Self {
        PebbleSearch { parent: vec![usize::MAX; n], seen: vec![0; n], round: 0, stack: Vec::new() }
    }

    /// Move a free pebble to `start` by reversing a directed path, never taking one
    /// from `start` or `keep`. Returns whether a pebble was found.
    fn fetch(&mut self, start: usize, keep: usize, pebbles: &mut [u8], out: &mut [OutEdges]) -> bool {
        self.round += 1;
        let round = self.round;
        let (parent, seen, stack) = (&mut self.parent, &mut self.seen, &mut self.stack);
        seen[start] = round;
        seen[keep] = round;
        stack.clear();
        stack.push(start);
        while let Some(x) = stack.pop() {
            for &y in out[x].as_slice() {
                if seen[y] == round {
                    continue;
                }
                seen[y] = round;
                parent[y] = x;
                if pebbles[y] > 0 {
                    pebbles[y] -= 1;
                    pebbles[start] += 1;
                    let mut child = y;
                    while child != start {
                        let p = parent[child];
                        let pos = out[p].as_slice().iter().position(|&t| t == child).expect("path edge exists");
                        out[p].swap_remove(pos);
                        out[child].push(p);
                        child = p;
                    }
                    return true;
                }
                stack.push(y);
            }
        }
        false
    }
}

/// One construction step `vertex ◁ (u, w)`: the clusters `cluster_u ∋ u` and
/// `cluster_w ∋ w` (ids in [`Decomposition::clusters`]) share `vertex`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Step {
    /// v_k: the joint the step places.
    pub vertex: usize,
    /// u_k: the base joint on `cluster_u`.
    pub u: usize,
    /// w_k: the base joint on `cluster_w`.
    pub w: usize,
    /// The cluster holding u and v.
    pub cluster_u: usize,
    /// The cluster holding w and v.
    pub cluster_w: usize,
}

/// A recognised 1-dof tree-decomposable linkage.
#[derive(Debug, Clone)]
pub struct Decomposition {
    /// The clusters of the linkage without its base, with their merge tree.
    pub clusters: ClusterSet,
    /// The base non-edge f = (a, b): a at (0, 0), b at (λ, 0).
    pub base: [usize; 2],
    /// The construction steps, in order.
    pub steps: Vec<Step>,
    /// Whether the base was chosen automatically.
    pub base_chosen: bool,
}

/// Other valid bases listed at most (a bound on output, not on the search).
pub const MAX_OTHER_BASES: usize = 32;

/// Why a linkage is outside the handled class (as data: joints, bars and
/// bodies by index; sentences are made by the caller).
#[derive(Debug, Clone, PartialEq)]
pub enum Outside {
    /// The joints fall apart into `parts` (not one linkage).
    Disconnected {
        /// The joints of each connected part.
        parts: Vec<Vec<usize>>,
    },
    /// Some constraints are dependent (they over-constrain the linkage).
    OverConstrained {
        /// The constraints the pebble game rejected as dependent.
        redundant: Vec<Constraint>,
        /// Degrees of freedom that remain (without rigid motions).
        dof: usize,
    },
    /// No degree of freedom (whether ruler-and-compass constructible or not).
    Rigid {
        /// Whether it is one cluster by merging (ruler-and-compass constructible).
        tree_decomposable: bool,
    },
    /// More than one degree of freedom (`dof` of them).
    ManyDof {
        /// The number of degrees of freedom (2 or more).
        dof: usize,
    },
    /// 1-dof, but no base non-edge makes it one cluster by merging.
    NotTreeDecomposable,
}

/// A requested base that cannot be used.
#[derive(Debug, Clone, PartialEq)]
pub struct BaseError {
    /// The base as asked.
    pub base: [usize; 2],
    /// Why it cannot be used, as a sentence.
    pub message: String,
}

/// Classify the linkage; on success its maximal clusters (merge tree included).
pub fn classify(linkage: &Linkage) -> Result<ClusterSet, Outside> {
    if !linkage.is_connected() {
        return Err(Outside::Disconnected { parts: crate::linkage::connected_parts(&linkage.graph()) });
    }
    let rig = rigidity(linkage);
    if !rig.redundant.is_empty() {
        return Err(Outside::OverConstrained { redundant: rig.redundant, dof: rig.dof });
    }
    let mut clusters = ClusterSet::initial(linkage);
    clusters.merge_all();
    match rig.dof {
        0 => Err(Outside::Rigid { tree_decomposable: clusters.alive_ids().len() == 1 }),
        1 => Ok(clusters),
        dof => Err(Outside::ManyDof { dof }),
    }
}

/// Construction steps from base `f`, or `None` if `f` is not a valid base.
/// Each round merges the part built so far (which contains `f`) with two
/// clusters sharing a joint; among the possible rounds the one whose base
/// joints were placed earliest is taken, so the order is deterministic.
///
/// Candidate rounds wait in a heap keyed by (when u was placed, when w was
/// placed, vertex), which never changes once a candidate exists; each joint
/// that joins the built part is examined once for new candidates, and a
/// popped candidate is re-checked (its clusters may have been used since).
/// So the cost is about linear in the size of the linkage.
pub fn steps_from_base(clusters: &ClusterSet, n_joints: usize, f: [usize; 2]) -> Option<Vec<Step>> {
    use std::cmp::Reverse;
    use std::collections::BinaryHeap;
    let [a, b] = f;
    if a == b || clusters.containing(a).any(|c| clusters.contains(c, b)) {
        return None;
    }
    // The built part is the set of placed joints; clusters merged into it die.
    let mut alive = clusters.alive.clone();
    let mut placed_at = vec![usize::MAX; n_joints];
    placed_at[a] = 0;
    placed_at[b] = 0;
    let joints = |c: usize| clusters.nodes[c].joints.as_slice();
    // The joint cluster `c` shares with the built part when it shares exactly one.
    let single_built = |placed_at: &[usize], c: usize| {
        let mut placed = joints(c).iter().copied().filter(|&j| placed_at[j] != usize::MAX);
        match (placed.next(), placed.next()) {
            (Some(j), None) => Some(j),
            _ => None,
        }
    };
    // One step per joint past the base. The work lists start with room for
    // a small scene's frontier (growing them from empty was a tenth of a
    // four-bar's recognition) and grow past it on large ones.
    let mut steps = Vec::with_capacity(n_joints.saturating_sub(2));
    let frontier = n_joints.min(64);
    // (key, p, y, z, q, r): triangle built–y–z with p = built ∩ y, q = y ∩ z, r = built ∩ z.
    type Candidate = ((usize, usize, usize), usize, usize, usize, usize, usize);
    let mut heap: BinaryHeap<Reverse<Candidate>> = BinaryHeap::with_capacity(2 * frontier);
    let mut fresh: Vec<usize> = Vec::with_capacity(frontier);
    fresh.extend([a, b]);
    let mut batch: Vec<usize> = Vec::with_capacity(frontier);
    let mut placed_count = 2;
    loop {
        // New joints of the built part: over-constraint checks and new candidates.
        std::mem::swap(&mut fresh, &mut batch);
        for &p in &batch {
            for y in clusters.by_joint.of(p).filter(|&c| alive[c]) {
                if single_built(&placed_at, y) != Some(p) {
                    return None; // shares two joints: over-constrained
                }
                for &q in joints(y) {
                    if placed_at[q] != usize::MAX {
                        continue;
                    }
                    for z in clusters.by_joint.of(q).filter(|&c| alive[c]) {
                        if z == y || clusters.single_shared(y, z) != Some(q) {
                            continue;
                        }
                        let Some(r) = single_built(&placed_at, z) else { continue };
                        let key = (placed_at[p].max(placed_at[r]), placed_at[p].min(placed_at[r]), q);
                        heap.push(Reverse((key, p, y, z, q, r)));
                    }
                }
            }
        }
        batch.clear();
        let candidate = loop {
            let Some(Reverse((_, p, y, z, q, r))) = heap.pop() else { break None };
            let valid = alive[y]
                && alive[z]
                && placed_at[q] == usize::MAX
                && single_built(&placed_at, y) == Some(p)
                && single_built(&placed_at, z) == Some(r);
            if valid {
                break Some((p, y, z, q, r));
            }
        };
        let Some((p, y, z, q, r)) = candidate else { break };
        let (mut u, mut w, mut cu, mut cw) = (p, r, y, z);
        let older = |s: usize, t: usize| (placed_at[s], s) < (placed_at[t], t);
        let on_base = (u == b && w == a) || (!(u == a && w == b) && older(w, u));
        if on_base {
            std::mem::swap(&mut u, &mut w);
            std::mem::swap(&mut cu, &mut cw);
        }
        steps.push(Step { vertex: q, u, w, cluster_u: cu, cluster_w: cw });
        let placed = steps.len();
        for &j in joints(y).iter().chain(joints(z)) {
            if placed_at[j] == usize::MAX {
                placed_at[j] = placed;
                placed_count += 1;
                fresh.push(j);
            }
        }
        alive[y] = false;
        alive[z] = false;
    }
    (placed_count == n_joints).then_some(steps)
}

/// Non-edges that could start a construction: `a` and `b` in two clusters
/// that share a joint (the first step must be a triangle with them), not
/// already in a common cluster. Ordered by preference: a base from a ground
/// joint to a joint clustered with the other ground joint (the crank
/// parameter), then any base touching the ground, then the rest by index.
///
/// Lazy in two tiers: the bases touching the ground are listed first (a
/// few per pair of clusters); the rest, which pair every joint of one
/// cluster with every joint of the other (a quarter of a million on a
/// strip of 1000 triangles hinged in the middle), only when the first tier
/// runs out.
pub fn base_candidates<'a>(clusters: &'a ClusterSet, linkage: &'a Linkage) -> impl Iterator<Item = [usize; 2]> + 'a {
    let ground = &linkage.ground;
    let clustered = move |x: usize, y: usize| clusters.clustered(x, y);
    let rank = move |[a, b]: [usize; 2]| -> usize {
        let crank = |g: usize, t: usize| ground.contains(&g) && ground.iter().any(|&h| h != g && clustered(h, t));
        if crank(a, b) || crank(b, a) {
            0
        } else if ground.contains(&a) || ground.contains(&b) {
            1
        } else {
            2
        }
    };
    // Pairs (a ∈ y, b ∈ z) of every two clusters sharing exactly one joint
    // v, with a, b ≠ v and not clustered: those with a ground joint
    // (`touching`), or those without.
    let candidates = move |touching: bool| {
        let on_ground = |a: usize| ground.contains(&a);
        // Sized for a small scene at once (growing them cost more than filling them).
        let (mut out, mut around, mut found) = (Vec::with_capacity(16), Vec::with_capacity(8), Vec::with_capacity(16));
        // With the ground, a pair gives a base only where one of its
        // clusters holds a ground joint other than v: at a hub, those few
        // clusters are paired with all, not all with all.
        let grounded = |y: usize, v: usize| ground.iter().any(|&g| g != v && clusters.contains(y, g));
        let (mut tagged, mut pairs) = (Vec::new(), Vec::new());
        for v in 0..linkage.n_joints() {
            around.clear();
            around.extend(clusters.containing(v));
            pairs.clear();
            if touching {
                tagged.clear();
                tagged.extend(around.iter().map(|&y| grounded(y, v)));
                for (i, &y) in around.iter().enumerate().filter(|&(i, _)| tagged[i]) {
                    // Each pair once: one with an earlier tagged cluster came up as that one's.
                    let others = around.iter().enumerate().filter(|&(j, _)| j != i && !(tagged[j] && j < i));
                    pairs.extend(others.map(|(_, &z)| (y, z)));
                }
            } else {
                for (i, &y) in around.iter().enumerate() {
                    pairs.extend(around[i + 1..].iter().map(|&z| (y, z)));
                }
            }
            for &(y, z) in &pairs {
                if clusters.single_shared(y, z) != Some(v) {
                    continue;
                }
                let (ys, zs) = (&clusters.nodes[y].joints, &clusters.nodes[z].joints);
                found.clear();
                if touching {
                    for &g in ground {
                        found.extend(zs.iter().filter(|_| ys.binary_search(&g).is_ok()).map(|&b| [g, b]));
                        found.extend(ys.iter().filter(|_| zs.binary_search(&g).is_ok()).map(|&a| [a, g]));
                    }
                } else {
                    for &a in ys.iter().filter(|&&a| !on_ground(a)) {
                        found.extend(zs.iter().filter(|&&b| !on_ground(b)).map(|&b| [a, b]));
                    }
                }
                out.extend(
                    found
                        .iter()
                        .filter(|&&[a, b]| a != v && b != v && !clustered(a, b))
                        .map(|&[a, b]| [a.min(b), a.max(b)]),
                );
            }
        }
        // Each pair once.
        out.sort_unstable();
        out.dedup();
        out
    };
    let mut first: Vec<(usize, [usize; 2])> = candidates(true).into_iter().map(|p| (rank(p), p)).collect();
    first.sort_unstable();
    first.into_iter().map(|(_, p)| p).chain(std::iter::once_with(move || candidates(false)).flatten())
}

/// Recognise the class and build the construction from the requested base,
/// or from the preferred valid base. Other valid bases are listed only when
/// asked for ([`Decomposition::other_bases`]) or when the requested one is not valid.
pub fn decompose(
    linkage: &Linkage,
    requested: Option<[usize; 2]>,
) -> Result<Result<Decomposition, BaseError>, Outside> {
    let clusters = classify(linkage)?;
    let n = linkage.n_joints();
    let (base, steps, base_chosen) = match requested {
        Some(f) => match steps_from_base(&clusters, n, f) {
            Some(steps) => (f, steps, false),
            None => {
                let valid = valid_bases(&clusters, linkage, MAX_OTHER_BASES + 1);
                if valid.is_empty() {
                    return Err(Outside::NotTreeDecomposable);
                }
                let why = if clusters.clustered(f[0], f[1]) {
                    "its joints are already held rigidly together"
                } else {
                    "adding it as a bar does not make the linkage buildable by ruler and compass"
                };
                let list: Vec<String> = valid.iter().map(|g| linkage.pair_name(*g)).collect();
                return Ok(Err(BaseError {
                    base: f,
                    message: format!(
                        "base {} is not a valid base non-edge: {why}; valid bases: {}",
                        linkage.pair_name(f),
                        list.join(", ")
                    ),
                }));
            }
        },
        None => {
            let first = base_candidates(&clusters, linkage)
                .take(MAX_BASE_CANDIDATES)
                .find_map(|f| steps_from_base(&clusters, n, f).map(|steps| (f, steps)));
            let Some((f, steps)) = first else { return Err(Outside::NotTreeDecomposable) };
            (f, steps, true)
        }
    };
    Ok(Ok(Decomposition { clusters, base, steps, base_chosen }))
}

/// Base candidates tried at most when listing valid bases (listing them is
/// a courtesy; this caps the work on very large scenes).
const MAX_BASE_CANDIDATES: usize = 4096;

/// Up to `limit` valid bases, in order of preference ([`base_candidates`]).
fn valid_bases(clusters: &ClusterSet, linkage: &Linkage, limit: usize) -> Vec<[usize; 2]> {
    let n = linkage.n_joints();
    base_candidates(clusters, linkage)
        .take(MAX_BASE_CANDIDATES)
        .filter(|&f| steps_from_base(clusters, n, f).is_some())
        .take(limit)
        .collect()
}

impl Decomposition {
    /// Other valid base non-edges (up to [`MAX_OTHER_BASES`]), found on
    /// request: each costs a construction from that base.
    pub fn other_bases(&self, linkage: &Linkage) -> Vec<[usize; 2]> {
        let base = self.base;
        let same = |g: &[usize; 2]| (g[0] == base[0] && g[1] == base[1]) || (g[0] == base[1] && g[1] == base[0]);
        valid_bases(&self.clusters, linkage, MAX_OTHER_BASES + 1)
            .into_iter()
            .filter(|g| !same(g))
            .take(MAX_OTHER_BASES)
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::parse_scene;

    /// A strip of `n` triangles with the diagonal from joint n/2 left out.
    fn strip(n: usize) -> Linkage {
        let mut text = String::from("bars = [\n");
        for i in 0..n - 1 {
            text += &format!("[\"J{i}\", \"J{}\"],\n", i + 1);
        }
        for i in (0..n - 2).filter(|&i| i != n / 2) {
            text += &format!("[\"J{i}\", \"J{}\"],\n", i + 2);
        }
        text += "]\n[joints]\n";
        for i in 0..n {
            text += &format!("J{i} = [{}, {}]\n", i as f64 * 0.5, (i % 2) as f64);
        }
        Linkage::from_scene(&parse_scene(&text, "strip.toml", "strip").unwrap())
    }

    /// The search by pairs of joints finds the merge the search at each
    /// joint finds, for every small live cluster, while a fan of legs round
    /// a hub (joint H, in every leg) with a big cluster on the legs' feet
    /// merges step by step: overlaps and triangles alike.
    #[test]
    fn merges_found_by_pairs_are_those_found_at_joints() {
        let legs = 12;
        let mut text = String::from("bars = [\n");
        for i in 0..legs {
            for (x, y) in [("H", "A"), ("H", "B"), ("A", "B"), ("A", "C"), ("B", "C")] {
                let name = |s: &str| if s == "H" { s.to_string() } else { format!("{s}{i}") };
                text += &format!("[\"{}\", \"{}\"],\n", name(x), name(y));
            }
        }
        text += "]\n[joints]\nH = [0.0, 0.0]\n";
        for i in 0..legs {
            let t = i as f64 * 0.5;
            text += &format!(
                "A{i} = [{}, {}]\nB{i} = [{}, {}]\n",
                3.0 * t.cos(),
                3.0 * t.sin(),
                4.0 * (t + 0.2).cos(),
                4.0 * (t + 0.2).sin()
            );
            text += &format!("C{i} = [{}, {}]\n", 6.0 * (t + 0.1).cos(), 6.5 * (t + 0.1).sin());
        }
        let linkage = Linkage::from_scene(&parse_scene(&text, "fan.toml", "fan").unwrap());
        let mut set = ClusterSet::initial(&linkage);
        let feet: Vec<usize> =
            (0..legs).step_by(3).map(|i| linkage.names.iter().position(|n| *n == format!("C{i}")).unwrap()).collect();
        set.add(feet, Origin::Base);
        let (mut marks, mut meets) = (JointMarks::new(set.n_joints()), Meets::with_capacity(0));
        let (mut compared, mut kinds) = (0, [0, 0]);
        loop {
            let mut next = None;
            for a in set.alive_ids() {
                let at_joints = set.merge_at_joints(a, &mut marks, &mut meets);
                if set.nodes[a].joints.len() <= PAIR_SEARCH_JOINTS {
                    assert_eq!(set.merge_by_pairs(a), at_joints, "cluster {a}: {:?}", set.nodes[a].joints);
                    compared += 1;
                }
                if let Some(m) = at_joints {
                    kinds[usize::from(matches!(m, Merge::Triangle { .. }))] += 1;
                    next = next.or(Some(m));
                }
            }
            let Some(m) = next else { break };
            set.apply(m);
        }
        assert!(compared > 200 && kinds.iter().all(|&n| n > 0), "{compared} compared, {kinds:?} overlaps, triangles");
    }

    /// Merging purges the dead clusters from the lists of the merged
    /// cluster's joints once they outnumber the live ones: after the
    /// strip's halves merge, every joint lists at most one dead cluster more
    /// than it has live ones (it listed one dead cluster per merge before,
    /// and the merge search walked them all: cubic in the strip's length).
    #[test]
    fn a_joint_lists_few_dead_clusters_after_its_merges() {
        let clusters = classify(&strip(40)).unwrap();
        assert_eq!(clusters.alive_ids().len(), 2, "two rigid halves");
        for j in 0..clusters.n_joints() {
            let (listed, live) = (clusters.by_joint.of(j).count(), clusters.containing(j).count());
            assert!((1..=2).contains(&live), "joint {j}: {live} live");
            assert!(listed <= 2 * live + 1, "joint {j}: {listed} listed, {live} live");
        }
    }
}
