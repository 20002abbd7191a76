//! `caymos graph`: the linkage and its decomposition as data and as DOT for
//! Graphviz: joints (ground marked), bars with their lengths, the maximal
//! clusters, the base non-edge and the construction steps `v ◁ (u, w)`.
//! Numbers a person sees (clusters, steps) are 1-based, as everywhere.

use std::fmt::Write as _;

use schemars::JsonSchema;
use serde::Serialize;

use crate::decompose::{Decomposition, decompose};
use petgraph::visit::EdgeRef;

use crate::linkage::{Constraint, Linkage};
use crate::present;
use crate::report::{OutsideReport, Said, fmt_num};
use crate::scene::{Scene, SceneError};

/// The linkage graph and its decomposition (JSON of `caymos graph --format json`).
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct GraphReport {
    /// The scene's name.
    pub scene: String,
    /// Every joint, in scene order (DOT ids `j1`, `j2`, … follow it).
    pub joints: Vec<JointOut>,
    /// Every bar, in scene order.
    pub bars: Vec<BarOut>,
    /// Rigid bodies, each as its joints' names.
    pub bodies: Vec<Vec<String>>,
    /// The maximal clusters of the linkage without its base, numbered from 1.
    pub clusters: Vec<ClusterOut>,
    /// The base non-edge (two joint names); `None` outside the handled class.
    pub base: Option<[String; 2]>,
    /// Whether the base was chosen automatically (not stated in the scene or by `--base`).
    pub base_chosen: bool,
    /// The construction steps from the base, numbered from 1.
    pub steps: Vec<StepOut>,
    /// Why the linkage is outside the handled class (then no base and no steps).
    pub outside: Option<Said<OutsideReport>>,
}

#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct JointOut {
    /// The joint's name in the scene.
    pub name: String,
    /// Whether the joint is fixed to the ground.
    pub ground: bool,
    /// Position as drawn (x).
    pub x: f64,
    /// Position as drawn (y, up).
    pub y: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct BarOut {
    /// The two joints' names.
    pub joints: [String; 2],
    /// Stated length, or the drawn distance.
    pub length: f64,
    /// Whether the scene states the length.
    pub stated: bool,
}

#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct ClusterOut {
    /// 1-based.
    pub number: usize,
    /// Joint names, in joint order.
    pub joints: Vec<String>,
}

#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct StepOut {
    /// 1-based, in construction order.
    pub number: usize,
    /// The joint placed: `vertex ◁ (u, w)`.
    pub vertex: String,
    /// The placed joint that `vertex` is at a fixed distance from, in the first cluster.
    pub u: String,
    /// The same in the second cluster.
    pub w: String,
    /// The clusters (numbers as in `clusters`) holding `u`–`vertex` and `w`–`vertex`.
    pub clusters: [usize; 2],
    /// `v ◁ (u, w)`.
    pub label: String,
}

/// The graph report of a scene on its base (stated, `base`, or chosen).
/// Errors are a base that cannot be used; a linkage outside the class is
/// reported (joints and bars) with `outside` set.
pub fn graph_report(scene: &Scene, base: Option<[usize; 2]>) -> Result<GraphReport, SceneError> {
    let linkage = Linkage::from_scene(scene);
    let graph = linkage.graph();
    let from_scene = base.is_none();
    let requested = base.or(scene.base.map(|b| b.0));
    let names = |js: &[usize]| js.iter().map(|&j| linkage.names[j].clone()).collect::<Vec<_>>();
    let mut report = GraphReport {
        scene: scene.name.clone(),
        joints: graph
            .node_indices()
            .map(|j| JointOut {
                name: graph[j].name.clone(),
                ground: graph[j].ground,
                x: linkage.drawn[j.index()][0],
                y: linkage.drawn[j.index()][1],
            })
            .collect(),
        // Bars are the graph's edges tagged as bars (body edges are not listed), in the scene's order.
        bars: graph
            .edge_references()
            .filter_map(|e| match *e.weight() {
                Constraint::Bar(i) => Some(BarOut {
                    joints: [graph[e.source()].name.clone(), graph[e.target()].name.clone()],
                    length: linkage.bars[i].length,
                    stated: scene.bars[i].length.is_some(),
                }),
                Constraint::Body(_) => None,
            })
            .collect(),
        bodies: linkage.bodies.iter().map(|b| names(b)).collect(),
        clusters: Vec::new(),
        base: None,
        base_chosen: false,
        steps: Vec::new(),
        outside: None,
    };
    match decompose(&linkage, requested) {
        Err(outside) => {
            report.outside = Some(Said {
                data: OutsideReport::new(&outside, &linkage),
                message: present::outside(&outside, &linkage),
            });
        }
        Ok(Err(e)) => {
            let line = if from_scene { scene.base.map(|b| b.1) } else { None };
            let mut err = scene.error_at(line, e.message);
            if !from_scene {
                err.message = format!("--base: {}", err.message);
            }
            return Err(err);
        }
        Ok(Ok(dec)) => add_decomposition(&mut report, &linkage, &dec),
    }
    Ok(report)
}

/// Clusters (1-based, in the decomposition's order), base and steps.
fn add_decomposition(report: &mut GraphReport, linkage: &Linkage, dec: &Decomposition) {
    let n = &linkage.names;
    let alive = dec.clusters.alive_ids();
    let number = |id: usize| alive.iter().position(|&c| c == id).map_or(0, |k| k + 1);
    report.clusters = alive
        .iter()
        .enumerate()
        .map(|(k, &id)| ClusterOut {
            number: k + 1,
            joints: dec.clusters.nodes[id].joints.iter().map(|&j| n[j].clone()).collect(),
        })
        .collect();
    report.base = Some([n[dec.base[0]].clone(), n[dec.base[1]].clone()]);
    report.base_chosen = dec.base_chosen;
    report.steps = dec
        .steps
        .iter()
        .enumerate()
        .map(|(k, s)| StepOut {
            number: k + 1,
            vertex: n[s.vertex].clone(),
            u: n[s.u].clone(),
            w: n[s.w].clone(),
            clusters: [number(s.cluster_u), number(s.cluster_w)],
            label: present::step_shape(&n[s.vertex], &n[s.u], &n[s.w]),
        })
        .collect();
}

/// A DOT string literal.
fn quoted(text: &str) -> String {
    format!("\"{}\"", text.replace('\\', "\\\\").replace('"', "\\\""))
}

/// The report as an undirected DOT graph. Joints are `j1…`, steps `s1…`
/// (boxes with dotted edges from `u` and `w`, an arrow to `v`); every
/// element has a `class` (joint, ground, bar, base, step), which Graphviz
/// carries into SVG. Clusters of three or more joints are `subgraph
/// cluster_N` (N as in the JSON); a two-joint cluster is one bar, drawn as
/// its edge. Graphviz draws a joint shared by two clusters in the first.
pub fn to_dot(r: &GraphReport) -> String {
    let id = |name: &str| r.joints.iter().position(|j| j.name == name).map_or(0, |k| k + 1);
    let mut out = String::new();
    let _ = writeln!(out, "graph {} {{", quoted(&r.scene));
    let title = match (&r.base, &r.outside) {
        (Some([a, b]), _) => format!("{}: base {a}–{b}, {} construction steps", r.scene, r.steps.len()),
        (None, Some(o)) => format!("{}: {}", r.scene, o.message),
        (None, None) => r.scene.clone(),
    };
    let _ = writeln!(out, "  label={};", quoted(&title));
    let _ = writeln!(out, "  node [shape=circle];");
    let _ = writeln!(out, "  // joints (ground: double circle)");
    for (k, j) in r.joints.iter().enumerate() {
        let (shape, class) = if j.ground { ("doublecircle", "joint ground") } else { ("circle", "joint") };
        let _ = writeln!(out, "  j{} [label={}, shape={shape}, class=\"{class}\"];", k + 1, quoted(&j.name));
    }
    let _ = writeln!(out, "  // clusters of three or more joints (a two-joint cluster is its bar)");
    for c in r.clusters.iter().filter(|c| c.joints.len() >= 3) {
        let members: Vec<String> = c.joints.iter().map(|j| format!("j{};", id(j))).collect();
        let _ = writeln!(
            out,
            "  subgraph cluster_{} {{ label=\"cluster {}\"; style=rounded; {} }}",
            c.number,
            c.number,
            members.join(" ")
        );
    }
    let _ = writeln!(out, "  // bars, labelled with their lengths");
    for b in &r.bars {
        let _ = writeln!(
            out,
            "  j{} -- j{} [label={}, class=\"bar\"];",
            id(&b.joints[0]),
            id(&b.joints[1]),
            quoted(&fmt_num(b.length))
        );
    }
    if let Some([a, b]) = &r.base {
        let _ = writeln!(out, "  // the base non-edge");
        let _ = writeln!(out, "  j{} -- j{} [style=dashed, label=\"base\", class=\"base\"];", id(a), id(b));
    }
    if !r.steps.is_empty() {
        let _ = writeln!(out, "  // construction steps v ◁ (u, w), in order");
    }
    for s in &r.steps {
        let _ = writeln!(
            out,
            "  s{} [shape=box, style=rounded, label={}, class=\"step\"];",
            s.number,
            quoted(&format!("{}: {}", s.number, s.label))
        );
        for from in [&s.u, &s.w] {
            let _ = writeln!(out, "  j{} -- s{} [style=dotted, class=\"step\"];", id(from), s.number);
        }
        let _ = writeln!(out, "  s{} -- j{} [style=dotted, dir=forward, class=\"step\"];", s.number, id(&s.vertex));
    }
    out.push_str("}\n");
    out
}
