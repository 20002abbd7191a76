//! The linkage a scene states: joints, bars with their lengths, rigid bodies.
//! Derived once from a [`Scene`]; the solver never looks at TOML again. As a
//! graph ([`Linkage::graph`]): joints are nodes, bars and the edges holding
//! each rigid body together are edges; connectivity is asked of that graph.

use petgraph::graph::{NodeIndex, UnGraph};
use petgraph::visit::Dfs;

use crate::exact::Decimal;
use crate::real::{Dd, Real};
use crate::scene::Scene;

/// A bar with its length (stated, or the drawn distance).
#[derive(Debug, Clone, PartialEq)]
pub struct LinkBar {
    /// The two joints it joins.
    pub joints: [usize; 2],
    /// Its length in scene units (f64).
    pub length: f64,
    /// The length from the input as written (stated, or the distance of the
    /// written coordinates) in double-double; `length` is it rounded.
    pub exact: Dd,
    /// The stated length as written, exactly, where `exact` is its
    /// double-double (`None`: not stated, or changed in code since).
    pub written: Option<Decimal>,
    /// Difference stated − drawn length (zero when the length is not stated).
    pub sketch_error: f64,
    /// The 1-based line of the scene file it is declared on (0: made in code).
    pub line: usize,
    /// Whether the scene states its length (else it is the drawn distance).
    pub stated: bool,
}

/// The linkage of a scene: named joints, bars, bodies, and its scale.
#[derive(Debug, Clone)]
pub struct Linkage {
    /// Joint names, indexed by joint.
    pub names: Vec<String>,
    /// Positions as drawn (y up).
    pub drawn: Vec<[f64; 2]>,
    /// The same as written, in double-double.
    pub drawn_exact: Vec<[Dd; 2]>,
    /// The same as written, exactly, where `drawn_exact` is its
    /// double-double (`None`: made or changed in code).
    pub drawn_written: Vec<[Option<Decimal>; 2]>,
    /// The bars, in scene order.
    pub bars: Vec<LinkBar>,
    /// Rigid bodies: the joints of each, 3 or more.
    pub bodies: Vec<Vec<usize>>,
    /// Per body, the 1-based line of the scene file it is declared on (0: made in code).
    pub body_lines: Vec<usize>,
    /// The ground joints, which the display frame keeps in place.
    pub ground: Vec<usize>,
    /// Largest bar length or body span: the unit all tolerances are relative to.
    pub scale: f64,
}

/// Euclidean distance between two points (scene units).
pub fn dist(p: [f64; 2], q: [f64; 2]) -> f64 {
    (q[0] - p[0]).hypot(q[1] - p[1])
}

impl Linkage {
    /// The linkage a scene states; the scale is 1 for a scene with no positive length.
    pub fn from_scene(scene: &Scene) -> Linkage {
        let drawn: Vec<[f64; 2]> = scene.joints.iter().map(|j| j.pos).collect();
        // The written value where it still rounds to the f64 one (a scene
        // edited in code keeps only its f64 numbers).
        let exact = |text: Dd, value: f64| if text.to_f64() == value { text } else { Dd::new(value) };
        let drawn_exact: Vec<[Dd; 2]> =
            scene.joints.iter().map(|j| [exact(j.exact[0], j.pos[0]), exact(j.exact[1], j.pos[1])]).collect();
        // The decimal where the double-double read is still its own.
        let written = |w: &Option<Decimal>, dd: Dd| w.clone().filter(|w| w.dd() == Some(dd));
        let drawn_written: Vec<[Option<Decimal>; 2]> = scene
            .joints
            .iter()
            .zip(&drawn_exact)
            .map(|(j, e)| [written(&j.written[0], e[0]), written(&j.written[1], e[1])])
            .collect();
        let bars: Vec<LinkBar> = scene
            .bars
            .iter()
            .map(|b| {
                let d = dist(drawn[b.joints[0]], drawn[b.joints[1]]);
                let exact = match (b.length, b.exact_length) {
                    (Some(l), Some(text)) => exact(text, l),
                    (Some(l), None) => Dd::new(l),
                    (None, _) => {
                        let [p, q] = b.joints.map(|j| drawn_exact[j]);
                        Dd::hypot(q[0] - p[0], q[1] - p[1])
                    }
                };
                let length = exact.to_f64();
                LinkBar {
                    joints: b.joints,
                    length,
                    exact,
                    written: written(&b.written_length, exact),
                    sketch_error: length - d,
                    line: b.line,
                    stated: b.length.is_some(),
                }
            })
            .collect();
        let bodies: Vec<Vec<usize>> = scene.bodies.iter().map(|b| b.joints.clone()).collect();
        let mut scale = bars.iter().map(|b| b.length).fold(0.0, f64::max);
        for body in &bodies {
            for (i, &p) in body.iter().enumerate() {
                for &q in &body[i + 1..] {
                    scale = scale.max(dist(drawn[p], drawn[q]));
                }
            }
        }
        if scale <= 0.0 || !scale.is_finite() {
            scale = 1.0;
        }
        Linkage {
            names: scene.joints.iter().map(|j| j.name.clone()).collect(),
            drawn,
            drawn_exact,
            drawn_written,
            bars,
            bodies,
            body_lines: scene.bodies.iter().map(|b| b.line).collect(),
            ground: scene.ground.clone(),
            scale,
        }
    }

    /// The drawn positions as points (scene units, y up).
    pub fn drawn_points(&self) -> Vec<nalgebra::Point2<f64>> {
        self.drawn.iter().map(|&p| p.into()).collect()
    }

    /// Joint j's coordinate `axis` as read: its double-double and, where
    /// known, its decimal.
    pub fn coordinate(&self, j: usize, axis: usize) -> crate::realize::Written<'_> {
        (self.drawn_exact[j][axis], self.drawn_written[j][axis].as_ref())
    }

    /// The number of joints.
    pub fn n_joints(&self) -> usize {
        self.names.len()
    }

    /// The bar between `p` and `q`, if any.
    pub fn bar_between(&self, p: usize, q: usize) -> Option<&LinkBar> {
        self.bars.iter().find(|b| b.joints == [p, q] || b.joints == [q, p])
    }

    /// `A–B` for display.
    pub fn pair_name(&self, [p, q]: [usize; 2]) -> String {
        format!("{}–{}", self.names[p], self.names[q])
    }

    /// Whether the joints form at most one connected part (bars and bodies
    /// joining them); [`connected_parts`] lists the parts. A union-find over
    /// the bars and bodies, without building the graph.
    pub fn is_connected(&self) -> bool {
        let mut parent: Vec<usize> = (0..self.n_joints()).collect();
        fn root(parent: &mut [usize], mut j: usize) -> usize {
            while parent[j] != j {
                parent[j] = parent[parent[j]];
                j = parent[j];
            }
            j
        }
        let mut parts = self.n_joints();
        let mut join = |p: usize, q: usize| {
            let (rp, rq) = (root(&mut parent, p), root(&mut parent, q));
            if rp != rq {
                parent[rp] = rq;
                parts -= 1;
            }
        };
        for bar in &self.bars {
            join(bar.joints[0], bar.joints[1]);
        }
        for body in &self.bodies {
            for w in body.windows(2) {
                join(w[0], w[1]);
            }
        }
        parts <= 1
    }

    /// The constraint graph as edges: each bar, and each body as a minimally
    /// rigid fan (2k − 3 edges), each tagged with the bar or body it came from.
    pub fn constraint_edges(&self) -> Vec<([usize; 2], Constraint)> {
        let mut edges: Vec<([usize; 2], Constraint)> =
            self.bars.iter().enumerate().map(|(i, b)| (b.joints, Constraint::Bar(i))).collect();
        for (i, body) in self.bodies.iter().enumerate() {
            edges.push(([body[0], body[1]], Constraint::Body(i)));
            for &j in &body[2..] {
                edges.push(([body[0], j], Constraint::Body(i)));
                edges.push(([body[1], j], Constraint::Body(i)));
            }
        }
        edges
    }

    /// The line of the scene file that declares the bar or body (`None`
    /// for one made in code, line 0).
    pub fn line_of(&self, c: Constraint) -> Option<usize> {
        let line = match c {
            Constraint::Bar(i) => self.bars[i].line,
            Constraint::Body(i) => self.body_lines.get(i).copied().unwrap_or(0),
        };
        (line > 0).then_some(line)
    }
}

/// Where a constraint edge comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Constraint {
    /// Bar `i` of the linkage.
    Bar(usize),
    /// Body `i` of the linkage (one of its fan edges).
    Body(usize),
}

/// A joint as a node of the [`LinkageGraph`]; its node index is its joint index.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct JointNode {
    /// The joint's name in the scene.
    pub name: String,
    /// Whether the joint is fixed to the ground.
    pub ground: bool,
}

/// The constraint graph: node `j` is joint `j`; each edge is a bar, or one
/// edge of a body's minimally rigid fan ([`Linkage::constraint_edges`]),
/// tagged with the bar or body it came from.
pub type LinkageGraph = UnGraph<JointNode, Constraint>;

impl Linkage {
    /// The linkage's constraint graph (see [`LinkageGraph`]).
    pub fn graph(&self) -> LinkageGraph {
        let edges = self.constraint_edges();
        let mut g = LinkageGraph::with_capacity(self.n_joints(), edges.len());
        for (j, name) in self.names.iter().enumerate() {
            g.add_node(JointNode { name: name.clone(), ground: self.ground.contains(&j) });
        }
        for ([u, v], c) in edges {
            g.add_edge(NodeIndex::new(u), NodeIndex::new(v), c);
        }
        g
    }
}

/// The connected parts of a graph as sorted joint indices, ordered by their
/// smallest joint (a graph with no node has no part).
pub fn connected_parts(g: &LinkageGraph) -> Vec<Vec<usize>> {
    let mut seen = vec![false; g.node_count()];
    let mut parts = Vec::new();
    for start in g.node_indices() {
        if seen[start.index()] {
            continue;
        }
        let mut part = Vec::new();
        let mut dfs = Dfs::new(g, start);
        while let Some(n) = dfs.next(g) {
            seen[n.index()] = true;
            part.push(n.index());
        }
        part.sort_unstable();
        parts.push(part);
    }
    parts
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::parse_scene;
    use petgraph::visit::EdgeRef;

    fn linkage(text: &str) -> Linkage {
        Linkage::from_scene(&parse_scene(text, "t.toml", "t").unwrap())
    }

    #[test]
    fn nodes_are_joints_and_edges_are_bars_and_body_fans() {
        let l = linkage(
            r#"
ground = ["A", "B"]
bars = [["A", "B"], ["B", "C"]]
bodies = [["C", "D", "E", "F"]]
[joints]
A = [0, 0]
B = [1, 0]
C = [2, 0]
D = [3, 1]
E = [3, -1]
F = [4, 0]
"#,
        );
        let g = l.graph();
        assert_eq!(g.node_count(), 6);
        // 2 bars + a fan of 2·4 − 3 = 5 edges for the body.
        assert_eq!(g.edge_count(), 7);
        assert_eq!(g[NodeIndex::new(2)], JointNode { name: "C".into(), ground: false });
        assert!(g[NodeIndex::new(0)].ground && g[NodeIndex::new(1)].ground);
        let bars: Vec<[usize; 2]> = g
            .edge_references()
            .filter(|e| matches!(e.weight(), Constraint::Bar(_)))
            .map(|e| [e.source().index(), e.target().index()])
            .collect();
        assert_eq!(bars, vec![[0, 1], [1, 2]]);
        assert_eq!(connected_parts(&g), vec![vec![0, 1, 2, 3, 4, 5]]);
        assert!(l.is_connected());
    }

    #[test]
    fn parts_are_found_in_order_of_their_smallest_joint() {
        let l = linkage(
            r#"
bars = [["A", "C"], ["B", "D"], ["D", "E"]]
[joints]
A = [0, 0]
B = [1, 0]
C = [2, 0]
D = [3, 1]
E = [3, -1]
F = [5, 5]
"#,
        );
        assert_eq!(connected_parts(&l.graph()), vec![vec![0, 2], vec![1, 3, 4], vec![5]]);
        assert!(!l.is_connected());
    }
}
