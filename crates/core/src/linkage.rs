//! The linkage a scene states: joints, bars with their lengths, rigid bodies.
//! Derived once from a [`Scene`]; the solver never looks at TOML again.

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
    /// Difference stated − drawn length (zero when the length is not stated).
    pub sketch_error: f64,
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
    /// The bars, in scene order.
    pub bars: Vec<LinkBar>,
    /// Rigid bodies: the joints of each, 3 or more.
    pub bodies: Vec<Vec<usize>>,
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
                LinkBar { joints: b.joints, length, exact, sketch_error: length - d }
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
            bars,
            bodies,
            ground: scene.ground.clone(),
            scale,
        }
    }

    /// The drawn positions as points (scene units, y up).
    pub fn drawn_points(&self) -> Vec<nalgebra::Point2<f64>> {
        self.drawn.iter().map(|&p| p.into()).collect()
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
}

/// Where a constraint edge comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Constraint {
    /// Bar `i` of the linkage.
    Bar(usize),
    /// Body `i` of the linkage (one of its fan edges).
    Body(usize),
}
