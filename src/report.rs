//! `caymos report`: the analysis as JSON for scripts and as aligned text for people.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use schemars::JsonSchema;
use serde::Serialize;

pub use caymos_core::numfmt::{fmt_num, fmt_sci, fmt_sig};

use crate::analysis::{Analysis, NoRealization, Warning};
use crate::decompose::Outside;
use crate::linkage::{Constraint, Linkage};
use crate::minimal_vector::{MinimalOptions, Minimality};
use crate::present::{self, ComponentNo, ItemNo, Names, StepNo};
use crate::realize::Kind;

pub use crate::present::short_type;

/// The version of every `--format json` document (its `schema_version`):
/// raised when a field is removed or changes meaning, not when one is added.
pub const SCHEMA_VERSION: u32 = 1;

/// Typed data with its sentence: `{"kind": …, data…, "message": "…"}`. The
/// kind and data are the contract; the message is for people and may be reworded.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct Said<T> {
    #[serde(flatten)]
    pub data: T,
    pub message: String,
}

#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct StepReport {
    /// The step's number (from 1), as in the text and in events.
    pub step: StepNo,
    pub vertex: String,
    pub on: [String; 2],
    /// The two clusters of the step: the one holding `on[0]`, the one holding `on[1]`.
    pub clusters: [Vec<String>; 2],
    /// |u v| and |w v|.
    pub lengths: [f64; 2],
}

/// Joint pairs as `a–b, …`; past 16 the first 8 and last 4 with the count.
fn pairs_text(pairs: &[[String; 2]]) -> String {
    let text: Vec<String> = pairs.iter().map(|[a, b]| format!("{a}–{b}")).collect();
    if text.len() > 16 {
        format!("{}, …, {} ({} pairs)", text[..8].join(", "), text[text.len() - 4..].join(", "), text.len())
    } else {
        text.join(", ")
    }
}

/// The minimal complete Cayley vector (see `caymos_core::minimal_vector`).
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct MinimalReport {
    /// Its entries, a sub-list of `complete_cayley_vector` in the same order.
    pub entries: Vec<[String; 2]>,
    /// How far it is proven smallest.
    pub minimality: Minimality,
    /// Cells (pieces of components) enclosed and pairs of cells compared for the proofs.
    pub cells: usize,
    pub pairs: usize,
    /// A component could not be enclosed with proofs (then only the whole vector is claimed).
    pub unenclosed_component: bool,
    pub message: String,
}

#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct DrawnReport {
    pub lambda: f64,
    #[serde(rename = "type")]
    pub ty: String,
}

#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct EventReport {
    /// The step's number (from 1): `steps[step - 1]`.
    pub step: StepNo,
    pub vertex: String,
    pub kind: Kind,
}

#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct IntervalReport {
    #[serde(rename = "type")]
    pub ty: String,
    pub lower: f64,
    pub upper: f64,
    /// The flat steps at each end (one in a generic scene; none at an open end).
    pub lower_events: Vec<EventReport>,
    pub upper_events: Vec<EventReport>,
}

#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct ComponentReport {
    /// The component's number (from 1), as in the text and `--component`.
    pub component: ComponentNo,
    /// Indices (from 0) into `oriented_intervals`, in traversal order.
    pub intervals: Vec<usize>,
    pub lambda_range: [f64; 2],
    pub contains_drawn: bool,
    /// False only at a non-generic branch point or dead end.
    pub closed: bool,
    /// Its connected set (from 1): components that meet at a branch point
    /// share a realization there. In a generic scene each component is a
    /// set of its own. The count of sets bounds the realization space's
    /// connected pieces from above; at non-generic places it may differ
    /// between bases (see `caymos_core::motion::Components::connected`).
    pub connected_set: ComponentNo,
}

/// The arithmetic the f64 endpoints are checked against.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum ReferenceArithmetic {
    /// Double-double (106-bit significand).
    DoubleDouble,
}

#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct AccuracyReport {
    pub reference: ReferenceArithmetic,
    /// Largest |λ − λ_reference| over all endpoints, in scene units.
    pub max_endpoint_error_estimate: f64,
    /// The same divided by the scene scale.
    pub max_relative_error_estimate: f64,
    /// The largest error of an f64 endpoint relative to its own value.
    pub max_error_of_value: f64,
    pub same_structure: bool,
    /// The reported endpoints are the double-double ones, rounded to f64.
    pub refined_in_double_double: bool,
}

#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct SketchReport {
    pub max_length_change: f64,
    /// `null` when the drawn type has no realization (see the warnings).
    pub max_joint_move: Option<f64>,
}

/// How much of the realization space was computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum AnalysisKind {
    /// Every type and every component.
    Full,
    /// Only the component through the drawn realization (more than 2^16
    /// types, a full sweep estimated above its budget (`sweep_estimate`),
    /// or `--lazy`; `--all` forces full).
    Lazy,
}

/// How the interval endpoints were found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum EndpointMethod {
    /// In closed form (low Cayley complexity).
    Exact,
    /// In closed form, and by the numeric search for `numeric_steps`.
    ExactNumeric,
    /// By the lazy walk, Newton to full precision.
    Lazy,
}

/// A bar or body the pebble game found redundant.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum ConstraintReport {
    /// `line`: where the scene file declares it (absent for a scene made in code).
    Bar {
        bar: ItemNo,
        joints: Vec<String>,
        #[serde(skip_serializing_if = "Option::is_none")]
        line: Option<usize>,
    },
    /// `line` as for a bar.
    Body {
        body: ItemNo,
        joints: Vec<String>,
        #[serde(skip_serializing_if = "Option::is_none")]
        line: Option<usize>,
    },
}

/// Why a scene is outside the handled class, joints by name.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum OutsideReport {
    Disconnected { parts: Vec<Vec<String>> },
    OverConstrained { redundant: Vec<ConstraintReport>, dof: usize },
    Rigid { tree_decomposable: bool },
    ManyDof { dof: usize },
    NotTreeDecomposable,
}

impl OutsideReport {
    /// The data of `o`, joints by name.
    pub fn new(o: &Outside, l: &Linkage) -> Self {
        let names = |js: &[usize]| js.iter().map(|&j| l.names[j].clone()).collect::<Vec<_>>();
        match o {
            Outside::Disconnected { parts } => {
                OutsideReport::Disconnected { parts: parts.iter().map(|p| names(p)).collect() }
            }
            Outside::OverConstrained { redundant, dof } => OutsideReport::OverConstrained {
                redundant: redundant
                    .iter()
                    .map(|c| match *c {
                        Constraint::Bar(i) => ConstraintReport::Bar {
                            bar: ItemNo::of_index(i),
                            joints: names(&l.bars[i].joints),
                            line: l.line_of(*c),
                        },
                        Constraint::Body(i) => ConstraintReport::Body {
                            body: ItemNo::of_index(i),
                            joints: names(&l.bodies[i]),
                            line: l.line_of(*c),
                        },
                    })
                    .collect(),
                dof: *dof,
            },
            Outside::Rigid { tree_decomposable } => OutsideReport::Rigid { tree_decomposable: *tree_decomposable },
            Outside::ManyDof { dof } => OutsideReport::ManyDof { dof: *dof },
            Outside::NotTreeDecomposable => OutsideReport::NotTreeDecomposable,
        }
    }
}

/// Where the four-cycle test fails, joints by name.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct LccFailureReport {
    pub step: StepNo,
    /// Pairs of built clusters holding the step's base joints that share no
    /// joint (opposite in a four-cycle); empty when there is no such pair.
    pub opposite_clusters: Vec<[Vec<String>; 2]>,
    pub message: String,
}

/// Everything `report` prints; the JSON form is this struct.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct Report {
    pub scene: String,
    pub description: Option<String>,
    pub source: String,
    pub joints: Vec<String>,
    /// (joint, joint, length), numbered from 1 in file order as in messages.
    pub bars: Vec<(String, String, f64)>,
    pub bodies: Vec<Vec<String>>,
    pub scale: f64,
    pub one_dof_tree_decomposable: bool,
    /// Why the scene is outside the handled class, in words (`outside` as data).
    pub reason: Option<String>,
    pub outside: Option<OutsideReport>,
    pub base: Option<[String; 2]>,
    pub base_chosen_automatically: bool,
    pub other_bases: Vec<[String; 2]>,
    pub steps: Vec<StepReport>,
    pub low_cayley_complexity: Option<bool>,
    pub lcc_failure: Option<LccFailureReport>,
    pub complete_cayley_vector: Vec<[String; 2]>,
    /// The smallest sub-vector proven to separate the realizations of every
    /// component computed (`null` outside the class).
    pub minimal_cayley_vector: Option<MinimalReport>,
    pub drawn: Option<DrawnReport>,
    pub sketch: Option<SketchReport>,
    pub analysis: AnalysisKind,
    /// The full sweep's estimated cost in realization steps, where it was
    /// estimated; above `sweep_budget` the analysis is lazy unless `--all`.
    pub sweep_estimate: Option<f64>,
    /// The budget `sweep_estimate` is held to.
    pub sweep_budget: f64,
    /// The non-oriented Cayley configuration space: disjoint closed intervals
    /// (in a lazy analysis: the λ range of the components computed).
    pub cayley_space: Vec<[f64; 2]>,
    pub oriented_intervals: Vec<IntervalReport>,
    pub endpoint_method: Option<EndpointMethod>,
    /// Steps whose endpoints came from the numeric search.
    pub numeric_steps: Vec<StepNo>,
    pub accuracy: Option<AccuracyReport>,
    pub components: Vec<ComponentReport>,
    /// Why there is no component (`null` when there is one).
    pub no_realization: Option<Said<NoRealization>>,
    /// The complete Cayley vector cannot tell mirror images apart (all clusters achiral).
    pub mirror_pairs: bool,
    pub warnings: Vec<Said<Warning>>,
    /// Wall-clock time of each phase in µs: `null` unless `--timings` (so
    /// two runs print the same document).
    pub timings_us: Option<BTreeMap<String, f64>>,
    /// How many decisions each stage of the certifier took (proven in f64
    /// balls, in double-double balls, exactly; resting on an estimate):
    /// `null` unless `--timings`.
    pub decisions: Option<caymos_core::StageCounts>,
}

impl Report {
    /// The report of an analysis, without timings (the same document every run).
    pub fn new(a: &Analysis) -> Report {
        Report::with_timings(a, false)
    }

    /// [`Report::new`], with the phase times when `timings` (they differ from run to run).
    pub fn with_timings(a: &Analysis, timings: bool) -> Report {
        let l = &a.linkage;
        let name = |j: usize| l.names[j].clone();
        let pair = |p: [usize; 2]| [name(p[0]), name(p[1])];
        let steps = a.outcome.as_ref().map(|s| s.dec.steps.as_slice()).unwrap_or(&[]);
        let names = Names::new(l, steps);
        let mut r = Report {
            scene: a.scene.name.clone(),
            description: a.scene.description.clone(),
            source: a.scene.source.clone(),
            joints: l.names.clone(),
            bars: l.bars.iter().map(|b| (name(b.joints[0]), name(b.joints[1]), b.length)).collect(),
            bodies: l.bodies.iter().map(|b| b.iter().map(|&j| name(j)).collect()).collect(),
            scale: l.scale,
            one_dof_tree_decomposable: a.outcome.is_ok(),
            reason: None,
            outside: None,
            base: None,
            base_chosen_automatically: false,
            other_bases: Vec::new(),
            steps: Vec::new(),
            low_cayley_complexity: None,
            lcc_failure: None,
            complete_cayley_vector: Vec::new(),
            minimal_cayley_vector: None,
            drawn: None,
            sketch: None,
            analysis: AnalysisKind::Full,
            sweep_estimate: None,
            sweep_budget: crate::tolerance::SWEEP_COST_MAX,
            cayley_space: Vec::new(),
            oriented_intervals: Vec::new(),
            endpoint_method: None,
            numeric_steps: Vec::new(),
            accuracy: None,
            components: Vec::new(),
            no_realization: None,
            mirror_pairs: false,
            warnings: a
                .warnings
                .iter()
                .map(|w| Said { data: w.clone(), message: present::warning(w, names) })
                .collect(),
            timings_us: timings.then(|| a.timings.0.iter().map(|(k, v)| (k.to_string(), *v)).collect()),
            decisions: a.outcome.as_ref().ok().filter(|_| timings).map(|s| s.certifier.stage_counts()),
        };
        match &a.outcome {
            Err(outside) => {
                r.reason = Some(present::outside(outside, l));
                r.outside = Some(OutsideReport::new(outside, l));
            }
            Ok(s) => {
                r.base = Some(pair(s.dec.base));
                r.base_chosen_automatically = s.dec.base_chosen;
                r.other_bases = s.dec.other_bases(l).into_iter().map(pair).collect();
                r.steps = s
                    .dec
                    .steps
                    .iter()
                    .zip(&s.construction.steps)
                    .enumerate()
                    .map(|(k, (st, g))| StepReport {
                        step: StepNo::of_index(k),
                        vertex: name(st.vertex),
                        on: [name(st.u), name(st.w)],
                        clusters: [st.cluster_u, st.cluster_w]
                            .map(|c| s.dec.clusters.nodes[c].joints.iter().map(|&j| name(j)).collect()),
                        lengths: [g.r1, g.r2],
                    })
                    .collect();
                r.low_cayley_complexity = Some(s.complexity.low);
                r.lcc_failure = s.complexity.failure.as_ref().map(|f| LccFailureReport {
                    step: StepNo::of_index(f.step),
                    opposite_clusters: f
                        .opposite
                        .iter()
                        .map(|[x, y]| [x, y].map(|c| c.iter().map(|&j| name(j)).collect()))
                        .collect(),
                    message: present::lcc_failure(f, names),
                });
                r.complete_cayley_vector = s.complexity.ccv.iter().map(|&p| pair(p)).collect();
                let m = s.minimal_vector(MinimalOptions::default());
                r.minimal_cayley_vector = Some(MinimalReport {
                    entries: m.entries.iter().map(|&e| pair(s.complexity.ccv[e])).collect(),
                    minimality: m.minimality,
                    cells: m.cells,
                    pairs: m.pairs,
                    unenclosed_component: m.unenclosed_component,
                    message: present::minimality(&m),
                });
                r.drawn = Some(DrawnReport { lambda: s.drawn.lambda, ty: s.drawn.ty.to_string() });
                r.sketch = s.sketch.as_ref().map(|f| SketchReport {
                    max_length_change: f.max_length_change,
                    max_joint_move: Some(f.max_joint_move).filter(|m| m.is_finite()),
                });
                r.cayley_space = s.union.clone();
                let event = |e: &crate::realize::Event| EventReport {
                    step: StepNo::of_index(e.step),
                    vertex: name(s.dec.steps[e.step].vertex),
                    kind: e.kind,
                };
                r.oriented_intervals = s
                    .space
                    .intervals
                    .iter()
                    .map(|i| IntervalReport {
                        ty: i.ty.to_string(),
                        lower: i.lower.lambda,
                        upper: i.upper.lambda,
                        lower_events: i.lower.events.iter().map(event).collect(),
                        upper_events: i.upper.events.iter().map(event).collect(),
                    })
                    .collect();
                r.analysis = if s.lazy { AnalysisKind::Lazy } else { AnalysisKind::Full };
                r.sweep_estimate = s.sweep_estimate;
                // (A lazy analysis whose walk was not confirmed gives the sweep's component.)
                let walked = s.lazy && matches!(s.space.method, caymos_core::Method::Numeric { .. });
                r.endpoint_method = Some(if walked {
                    EndpointMethod::Lazy
                } else if s.space.numeric_steps.is_empty() {
                    EndpointMethod::Exact
                } else {
                    EndpointMethod::ExactNumeric
                });
                if !walked {
                    r.numeric_steps = s.space.numeric_steps.iter().map(|&k| StepNo::of_index(k)).collect();
                }
                let sets = &s.components.connected;
                r.components = s
                    .components
                    .list
                    .iter()
                    .enumerate()
                    .map(|(k, c)| ComponentReport {
                        connected_set: ComponentNo::of_index(sets[k]),
                        component: ComponentNo::of_index(k),
                        intervals: c.intervals.clone(),
                        lambda_range: c.lambda_range,
                        contains_drawn: s.drawn_component == Some(k),
                        closed: c.closed,
                    })
                    .collect();
                r.no_realization = crate::analysis::no_realization(s, l.scale)
                    .map(|why| Said { message: present::no_realization(&why, names, &s.construction), data: why });
                r.mirror_pairs = s.mirrors.exist();
                r.accuracy = s.accuracy.as_ref().map(|acc| AccuracyReport {
                    reference: ReferenceArithmetic::DoubleDouble,
                    max_endpoint_error_estimate: acc.max_endpoint_error,
                    max_relative_error_estimate: acc.max_relative_error,
                    max_error_of_value: acc.max_error_of_value,
                    same_structure: acc.same_structure,
                    refined_in_double_double: acc.refined,
                });
            }
        }
        r
    }

    /// The JSON document (with `schema_version`).
    pub fn to_json(&self) -> String {
        crate::schema::Versioned::new(self).to_json()
    }

    /// The text form: aligned tables, for people. `all` lists every oriented
    /// interval even when there are many.
    pub fn to_text(&self) -> String {
        self.to_text_with(false)
    }

    pub fn to_text_with(&self, all: bool) -> String {
        let mut o = String::new();
        let _ = writeln!(o, "{}  ({})", self.scene, self.source);
        if let Some(d) = &self.description {
            let _ = writeln!(o, "  {d}");
        }
        let _ = writeln!(
            o,
            "  {} joints, {} bars, {} bodies, scale {}",
            self.joints.len(),
            self.bars.len(),
            self.bodies.len(),
            fmt_num(self.scale)
        );
        let _ = writeln!(o);
        if !self.one_dof_tree_decomposable {
            let _ = writeln!(o, "{:<24}outside the handled class", "Class");
            let _ = writeln!(o, "{:<24}{}", "Reason", self.reason.as_deref().unwrap_or("?"));
            self.write_warnings(&mut o);
            return o;
        }
        let _ = writeln!(o, "{:<24}1-dof tree-decomposable", "Class");
        if let Some([a, b]) = &self.base {
            let how = if self.base_chosen_automatically { "chosen automatically" } else { "given" };
            let _ = writeln!(o, "{:<24}{a}–{b} ({how})", "Base non-edge");
        }
        let others: Vec<String> = self.other_bases.iter().map(|[a, b]| format!("{a}–{b}")).collect();
        let _ = writeln!(
            o,
            "{:<24}{}",
            "Other valid bases",
            if others.is_empty() { "none".into() } else { others.join(", ") }
        );
        let _ = writeln!(o);
        let _ = writeln!(o, "Construction steps ({})", self.steps.len());
        let rows: Vec<[String; 5]> = self
            .steps
            .iter()
            .map(|s| {
                [
                    s.step.to_string(),
                    present::step_shape(&s.vertex, &s.on[0], &s.on[1]),
                    present::joint_set(&s.clusters[0]),
                    present::joint_set(&s.clusters[1]),
                    format!("{}, {}", fmt_num(s.lengths[0]), fmt_num(s.lengths[1])),
                ]
            })
            .collect();
        write_table(&mut o, &["#", "step", "cluster on u", "cluster on w", "|uv|, |wv|"], &rows);
        let _ = writeln!(o);
        let lcc = match (self.low_cayley_complexity, &self.lcc_failure) {
            (Some(true), _) => "yes (four-cycle test)".to_string(),
            (_, Some(f)) => format!("no: {}", f.message),
            _ => "unknown".to_string(),
        };
        let _ = writeln!(o, "{:<24}{lcc}", "Low Cayley complexity");
        let _ = writeln!(o, "{:<24}{}", "Complete Cayley vector", pairs_text(&self.complete_cayley_vector));
        if let Some(m) = &self.minimal_cayley_vector {
            let _ = writeln!(o, "{:<24}{}: {}", "Minimal Cayley vector", pairs_text(&m.entries), m.message);
        }
        if let Some(d) = &self.drawn {
            let _ = writeln!(o, "{:<24}λ = {}  type {}", "Drawn realization", fmt_num(d.lambda), short_type(&d.ty));
            let steps = d.ty.chars().count();
            if steps > present::TYPE_GROUPED {
                let _ = writeln!(o, "{:<24}{}", "", present::type_label_legend(steps));
            }
        }
        if let Some(s) = &self.sketch {
            let moved = match s.max_joint_move {
                Some(m) => format!("joints moved up to {}", fmt_sci(m)),
                None => "the drawn type has no realization (see warnings)".to_string(),
            };
            let _ = writeln!(
                o,
                "{:<24}stated lengths differ from the drawing by up to {}; {moved}",
                "Sketch",
                fmt_sci(s.max_length_change)
            );
        }
        let _ = writeln!(o);
        self.write_cayley_space(&mut o, all);
        self.write_warnings(&mut o);
        o
    }

    fn write_cayley_space(&self, o: &mut String, all: bool) {
        let spans: Vec<String> =
            self.cayley_space.iter().map(|[a, b]| format!("[{}, {}]", fmt_num(*a), fmt_num(*b))).collect();
        let n_types = 1usize.checked_shl(self.steps.len() as u32).unwrap_or(usize::MAX);
        let n_types_text = if n_types == usize::MAX { format!("2^{}", self.steps.len()) } else { n_types.to_string() };
        let lazy = self.analysis == AnalysisKind::Lazy;
        if lazy {
            let why = crate::present::lazy_reason(self.sweep_estimate, self.sweep_budget)
                .map_or(String::new(), |r| format!(": {r}"));
            let _ = writeln!(
                o,
                "{:<24}lazy: only the component through the drawn realization ({n_types_text} types not enumerated{why}; --all forces the full analysis)",
                "Analysis"
            );
        }
        let _ = writeln!(
            o,
            "{:<24}{}",
            if lazy { "Component spans" } else { "Cayley space" },
            if spans.is_empty() { "empty: no realization".into() } else { spans.join(" ∪ ") }
        );
        let mut types: Vec<&str> = self.oriented_intervals.iter().map(|i| i.ty.as_str()).collect();
        types.sort_unstable();
        types.dedup();
        let _ = writeln!(
            o,
            "{:<24}{} intervals over {} of {} types ({})",
            "Oriented intervals",
            self.oriented_intervals.len(),
            types.len(),
            n_types_text,
            match self.endpoint_method {
                Some(EndpointMethod::Exact) => "endpoints in closed form".to_string(),
                Some(EndpointMethod::Lazy) => "endpoints by the lazy walk, Newton to full precision".to_string(),
                _ => format!(
                    "closed form, and numeric search for steps {}",
                    self.numeric_steps.iter().map(|k| k.to_string()).collect::<Vec<_>>().join(", ")
                ),
            }
        );
        if let (Some(_), true) = (&self.accuracy, self.oriented_intervals.is_empty()) {
            let _ = writeln!(o, "{:<24}no endpoints to compare", "Accuracy");
        } else if let Some(a) = &self.accuracy {
            let _ = writeln!(
                o,
                "{:<24}f64 endpoints within {} of the double-double run from the input as written ({} of the scale, {} of their own value){}",
                "Accuracy",
                fmt_sci(a.max_endpoint_error_estimate),
                fmt_sci(a.max_relative_error_estimate),
                fmt_sci(a.max_error_of_value),
                if !a.same_structure {
                    "; STRUCTURE DIFFERS"
                } else if a.refined_in_double_double {
                    "; endpoints shown are the double-double ones"
                } else {
                    ""
                }
            );
        }
        self.write_components(o);
        let drawn_ty = self.drawn.as_ref().map(|d| d.ty.clone()).unwrap_or_default();
        let many = self.oriented_intervals.len() > 32 && !all;
        let shown: Vec<&IntervalReport> =
            self.oriented_intervals.iter().filter(|i| !many || i.ty == drawn_ty).collect();
        if shown.is_empty() {
            return;
        }
        let _ = writeln!(o);
        if many {
            let _ = writeln!(
                o,
                "Intervals of the drawn type {drawn_ty} (all {} with --all)",
                self.oriented_intervals.len()
            );
        }
        let ev = |all: &[EventReport]| match all.first() {
            Some(e) => {
                let extra = if all.len() > 1 { format!(" +{}", all.len() - 1) } else { String::new() };
                format!("{} {} (step {}){extra}", e.vertex, e.kind.name(), e.step)
            }
            None => "-".to_string(),
        };
        let rows: Vec<[String; 5]> = shown
            .iter()
            .map(|i| {
                [self.type_text(&i.ty), fmt_num(i.lower), fmt_num(i.upper), ev(&i.lower_events), ev(&i.upper_events)]
            })
            .collect();
        write_table(o, &["type", "lower", "upper", "lower event", "upper event"], &rows);
        let _ = writeln!(o);
        self.write_chart(o, &shown);
        let _ = writeln!(o);
    }

    /// A type as the text tables write it: long ones against the drawn type.
    fn type_text(&self, ty: &str) -> String {
        present::type_label(ty, self.drawn.as_ref().map(|d| d.ty.as_str()))
    }

    fn write_components(&self, o: &mut String) {
        if let Some(why) = &self.no_realization {
            let _ = writeln!(o, "{:<24}0: {}", "Components", why.message);
            return;
        }
        let sets = self.components.iter().map(|c| c.connected_set.index() + 1).max().unwrap_or(0);
        let joined = sets < self.components.len();
        let mut notes = Vec::new();
        if joined {
            notes.push(
                "components that meet at a branch point share a realization there; at such a non-generic place \
                 another base may count sets differently",
            );
        }
        if self.mirror_pairs {
            notes.push("all clusters achiral: mirror images share Cayley vectors");
        }
        let _ = writeln!(
            o,
            "{:<24}{}{}{}",
            "Components",
            self.components.len(),
            if joined {
                format!(" in {sets} connected set{}", if sets == 1 { "" } else { "s" })
            } else {
                String::new()
            },
            if notes.is_empty() { String::new() } else { format!(" ({})", notes.join("; ")) }
        );
        let rows: Vec<[String; 4]> = self
            .components
            .iter()
            .map(|c| {
                let types: Vec<String> =
                    c.intervals.iter().map(|&i| self.type_text(&self.oriented_intervals[i].ty)).collect();
                // Labels of long types have spaces of their own.
                let gap = if types.iter().any(|t| t.contains(' ')) { " | " } else { " " };
                let shown = if types.len() > 6 {
                    format!("{} … ({} more)", types[..6].join(gap), types.len() - 6)
                } else {
                    types.join(gap)
                };
                [
                    format!("{}{}", c.component, if c.contains_drawn { " *" } else { "" }),
                    c.intervals.len().to_string(),
                    format!(
                        "[{}, {}]{}",
                        fmt_num(c.lambda_range[0]),
                        fmt_num(c.lambda_range[1]),
                        if c.closed { "" } else { " open" }
                    ),
                    shown,
                ]
            })
            .collect();
        if rows.len() <= 40 {
            write_table(o, &["#", "intervals", "λ range", "types in order"], &rows);
            if self.components.iter().any(|c| c.contains_drawn) {
                let _ = writeln!(o, "  (* holds the drawn realization)");
            } else {
                let _ = writeln!(o, "  (the drawn realization lies in none of these components; see the warnings)");
            }
        } else {
            let _ = writeln!(o, "  ({} components: the table is left out; --format json lists them)", rows.len());
        }
    }

    /// Bars over the λ axis: the union on top, then one row per type.
    fn write_chart(&self, o: &mut String, shown: &[&IntervalReport]) {
        const WIDTH: usize = 56;
        let (Some(first), Some(last)) = (self.cayley_space.first(), self.cayley_space.last()) else { return };
        let (lo, hi) = (first[0], last[1]);
        let span = if hi > lo { hi - lo } else { 1.0 };
        let col = |x: f64| (((x - lo) / span) * (WIDTH - 1) as f64).round().clamp(0.0, (WIDTH - 1) as f64) as usize;
        let bar = |spans: &mut dyn Iterator<Item = (f64, f64)>| {
            let mut row = vec![' '; WIDTH];
            for (a, b) in spans {
                let (ca, cb) = (col(a), col(b));
                if ca == cb {
                    row[ca] = if a == b { '•' } else { '█' };
                } else {
                    row[ca..=cb].iter_mut().for_each(|c| *c = '█');
                }
            }
            row.into_iter().collect::<String>()
        };
        let label_width = shown.iter().map(|i| self.type_text(&i.ty).chars().count()).max().unwrap_or(4).max(5);
        let left = fmt_num(lo);
        let right = fmt_num(hi);
        let pad = (WIDTH + 2).saturating_sub(left.len() + right.len());
        let _ = writeln!(o, "  {:<label_width$} {left}{}{right}", "λ", " ".repeat(pad));
        let union = bar(&mut self.cayley_space.iter().map(|s| (s[0], s[1])));
        let _ = writeln!(o, "  {:<label_width$} |{union}|", "union");
        let mut seen: Vec<&str> = Vec::new();
        for i in shown {
            if seen.contains(&i.ty.as_str()) {
                continue;
            }
            seen.push(&i.ty);
            let row = bar(&mut shown.iter().filter(|j| j.ty == i.ty).map(|j| (j.lower, j.upper)));
            let _ = writeln!(o, "  {:<label_width$} |{row}|", self.type_text(&i.ty));
        }
    }

    fn write_warnings(&self, o: &mut String) {
        if self.warnings.is_empty() {
            let _ = writeln!(o, "{:<24}none", "Warnings");
        } else {
            let _ = writeln!(o, "Warnings");
            for w in &self.warnings {
                let _ = writeln!(o, "  - {}", w.message);
            }
        }
        self.write_costs(o);
    }

    /// With `--timings`: the certifier's decisions per stage and each phase's time.
    fn write_costs(&self, o: &mut String) {
        if let Some(d) = &self.decisions {
            let _ = writeln!(
                o,
                "{:<24}{} in f64 balls, {} in double-double balls, {} exact, {} estimated",
                "Decisions", d.f64, d.double_double, d.exact, d.estimated
            );
        }
        if let Some(t) = &self.timings_us {
            let phases: Vec<String> = t.iter().map(|(k, v)| format!("{k} {v:.0}")).collect();
            let _ = writeln!(o, "{:<24}{} (µs)", "Timings", phases.join(", "));
        }
    }
}

impl Report {
    /// Markdown for a CI job summary: headings and tables, no colour, no box
    /// drawing. `all` lists every oriented interval however many.
    pub fn to_markdown(&self, all: bool) -> String {
        let mut o = String::new();
        let _ = writeln!(o, "## caymos report: {}\n", md(&self.scene));
        if let Some(d) = &self.description {
            let _ = writeln!(o, "{}\n", md(d));
        }
        let mut facts: Vec<[String; 2]> = vec![
            ["Source".into(), format!("`{}`", self.source)],
            [
                "Size".into(),
                format!(
                    "{} joints, {} bars, {} bodies, scale {}",
                    self.joints.len(),
                    self.bars.len(),
                    self.bodies.len(),
                    fmt_num(self.scale)
                ),
            ],
        ];
        if !self.one_dof_tree_decomposable {
            facts.push(["Class".into(), "outside the handled class".into()]);
            facts.push(["Reason".into(), md(self.reason.as_deref().unwrap_or("?"))]);
            md_table(&mut o, &["", ""], &facts);
            self.md_warnings(&mut o);
            return o;
        }
        facts.push(["Class".into(), "1-dof tree-decomposable".into()]);
        if let Some([a, b]) = &self.base {
            let how = if self.base_chosen_automatically { "chosen automatically" } else { "given" };
            facts.push(["Base non-edge".into(), md(&format!("{a}–{b} ({how})"))]);
        }
        let lcc = match (self.low_cayley_complexity, &self.lcc_failure) {
            (Some(true), _) => "yes (four-cycle test)".to_string(),
            (_, Some(f)) => format!("no: {}", f.message),
            _ => "unknown".to_string(),
        };
        facts.push(["Low Cayley complexity".into(), md(&lcc)]);
        if let Some(d) = &self.drawn {
            facts
                .push(["Drawn realization".into(), format!("λ = {}, type `{}`", fmt_num(d.lambda), short_type(&d.ty))]);
        }
        let spans: Vec<String> =
            self.cayley_space.iter().map(|[a, b]| format!("[{}, {}]", fmt_num(*a), fmt_num(*b))).collect();
        let label = if self.analysis == AnalysisKind::Lazy { "Component spans (lazy)" } else { "Cayley space" };
        facts.push([label.into(), if spans.is_empty() { "empty: no realization".into() } else { spans.join(" ∪ ") }]);
        if let Some(a) = &self.accuracy {
            facts.push([
                "Accuracy".into(),
                format!(
                    "within {} of the double-double run{}",
                    fmt_sci(a.max_endpoint_error_estimate),
                    if a.same_structure { "" } else { "; **structure differs**" }
                ),
            ]);
        }
        md_table(&mut o, &["", ""], &facts);
        let _ = writeln!(o, "\n### Construction steps ({})\n", self.steps.len());
        let rows: Vec<[String; 3]> = self
            .steps
            .iter()
            .map(|s| {
                [
                    s.step.to_string(),
                    md(&present::step_shape(&s.vertex, &s.on[0], &s.on[1])),
                    format!("{}, {}", fmt_num(s.lengths[0]), fmt_num(s.lengths[1])),
                ]
            })
            .collect();
        md_table(&mut o, &["#", "step", "|uv|, |wv|"], &rows);
        let _ = writeln!(o, "\n### Components ({})\n", self.components.len());
        if let Some(why) = &self.no_realization {
            let _ = writeln!(o, "{}", md(&why.message));
        } else {
            let rows: Vec<[String; 4]> = self
                .components
                .iter()
                .map(|c| {
                    [
                        c.component.to_string(),
                        c.intervals.len().to_string(),
                        format!(
                            "[{}, {}]{}",
                            fmt_num(c.lambda_range[0]),
                            fmt_num(c.lambda_range[1]),
                            if c.closed { "" } else { " open" }
                        ),
                        if c.contains_drawn { "yes".into() } else { String::new() },
                    ]
                })
                .collect();
            md_table(&mut o, &["#", "intervals", "λ range", "drawn"], &rows);
        }
        let many = self.oriented_intervals.len() > 32 && !all;
        let drawn_ty = self.drawn.as_ref().map(|d| d.ty.as_str()).unwrap_or("");
        let shown: Vec<&IntervalReport> =
            self.oriented_intervals.iter().filter(|i| !many || i.ty == drawn_ty).collect();
        if !shown.is_empty() {
            let _ = writeln!(
                o,
                "\n### Oriented intervals ({}{})\n",
                self.oriented_intervals.len(),
                if many { ", the drawn type's shown" } else { "" }
            );
            let ev = |all: &[EventReport]| {
                let list: Vec<String> =
                    all.iter().map(|e| format!("{} {} (step {})", e.vertex, e.kind.name(), e.step)).collect();
                if list.is_empty() { "-".to_string() } else { md(&list.join(", ")) }
            };
            let rows: Vec<[String; 5]> = shown
                .iter()
                .map(|i| {
                    [
                        format!("`{}`", self.type_text(&i.ty)),
                        fmt_num(i.lower),
                        fmt_num(i.upper),
                        ev(&i.lower_events),
                        ev(&i.upper_events),
                    ]
                })
                .collect();
            md_table(&mut o, &["type", "lower", "upper", "lower event", "upper event"], &rows);
        }
        self.md_warnings(&mut o);
        o
    }

    fn md_warnings(&self, o: &mut String) {
        let _ = writeln!(o, "\n### Warnings ({})\n", self.warnings.len());
        if self.warnings.is_empty() {
            let _ = writeln!(o, "None.");
        }
        for w in &self.warnings {
            let _ = writeln!(o, "- {}", md(&w.message));
        }
    }
}

/// Text safe in a Markdown table cell: `|` escaped, no line breaks.
fn md(text: &str) -> String {
    text.replace('|', "\\|").replace('\n', " ")
}

/// A GitHub-flavoured Markdown table.
fn md_table<const N: usize>(o: &mut String, header: &[&str; N], rows: &[[String; N]]) {
    let header: Vec<String> = header.iter().map(|h| md(h)).collect();
    let _ = writeln!(o, "| {} |", header.join(" | "));
    let _ = writeln!(o, "|{}", " --- |".repeat(N));
    for row in rows {
        let _ = writeln!(o, "| {} |", row.join(" | "));
    }
}

/// Columns padded to their widest cell (by characters, so `◁` counts as one).
pub fn write_table<const N: usize>(o: &mut String, header: &[&str; N], rows: &[[String; N]]) {
    let mut width = header.map(|h| h.chars().count());
    for row in rows {
        for (w, cell) in width.iter_mut().zip(row) {
            *w = (*w).max(cell.chars().count());
        }
    }
    let line = |o: &mut String, cells: Vec<&str>| {
        let mut s = String::from("  ");
        for (i, c) in cells.iter().enumerate() {
            s.push_str(c);
            if i + 1 < N {
                s.push_str(&" ".repeat(width[i] - c.chars().count() + 2));
            }
        }
        let _ = writeln!(o, "{}", s.trim_end());
    };
    line(o, header.to_vec());
    for row in rows {
        line(o, row.iter().map(String::as_str).collect());
    }
}
