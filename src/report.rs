//! `caymos report`: the analysis as JSON for scripts and as aligned text for people.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use serde::Serialize;

pub use caymos_core::numfmt::{fmt_num, fmt_sci, fmt_sig};

use crate::analysis::Analysis;

#[derive(Debug, Clone, Serialize)]
pub struct StepReport {
    pub vertex: String,
    pub on: [String; 2],
    /// The two clusters of the step: the one holding `on[0]`, the one holding `on[1]`.
    pub clusters: [Vec<String>; 2],
    /// |u v| and |w v|.
    pub lengths: [f64; 2],
}

#[derive(Debug, Clone, Serialize)]
pub struct DrawnReport {
    pub lambda: f64,
    #[serde(rename = "type")]
    pub ty: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct EventReport {
    /// Index into `steps`.
    pub step: usize,
    pub vertex: String,
    /// `stretched` or `folded`.
    pub kind: &'static str,
}

#[derive(Debug, Clone, Serialize)]
pub struct IntervalReport {
    #[serde(rename = "type")]
    pub ty: String,
    pub lower: f64,
    pub upper: f64,
    /// The flat step at each end (the first, when several are flat at once).
    pub lower_event: Option<EventReport>,
    pub upper_event: Option<EventReport>,
    /// Every flat step at each end (more than one only in non-generic scenes).
    pub lower_events: Vec<EventReport>,
    pub upper_events: Vec<EventReport>,
}

#[derive(Debug, Clone, Serialize)]
pub struct ComponentReport {
    /// Indices into `oriented_intervals`, in traversal order.
    pub intervals: Vec<usize>,
    pub lambda_range: [f64; 2],
    pub contains_drawn: bool,
    /// False only at a non-generic branch point or dead end.
    pub closed: bool,
}

#[derive(Debug, Clone, Serialize)]
pub struct AccuracyReport {
    pub reference: &'static str,
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

#[derive(Debug, Clone, Serialize)]
pub struct SketchReport {
    pub max_length_change: f64,
    pub max_joint_move: f64,
}

/// A type for a text table: long ones (many steps) keep their ends.
pub fn short_type(ty: &str) -> String {
    let n = ty.chars().count();
    if n <= 40 {
        return ty.to_string();
    }
    let head: String = ty.chars().take(16).collect();
    let tail: String = ty.chars().skip(n - 8).collect();
    format!("{head}…{tail} ({n} signs)")
}

/// Everything `report` prints; the JSON form is this struct.
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    pub scene: String,
    pub description: Option<String>,
    pub source: String,
    pub joints: Vec<String>,
    pub bars: Vec<(String, String, f64)>,
    pub bodies: Vec<Vec<String>>,
    pub scale: f64,
    pub one_dof_tree_decomposable: bool,
    pub reason: Option<String>,
    pub reason_kind: Option<String>,
    pub base: Option<[String; 2]>,
    pub base_chosen_automatically: bool,
    pub other_bases: Vec<[String; 2]>,
    pub steps: Vec<StepReport>,
    pub low_cayley_complexity: Option<bool>,
    pub lcc_failure: Option<String>,
    pub complete_cayley_vector: Vec<[String; 2]>,
    pub drawn: Option<DrawnReport>,
    pub sketch: Option<SketchReport>,
    /// `full` (every type) or `lazy` (only the component through the drawn
    /// realization: the scene has more than 2^16 types; `--all` forces full).
    pub analysis: &'static str,
    /// The non-oriented Cayley configuration space: disjoint closed intervals
    /// (in a lazy analysis: the λ range of the components computed).
    pub cayley_space: Vec<[f64; 2]>,
    pub oriented_intervals: Vec<IntervalReport>,
    /// `exact` (closed form, LCC) or `numeric`; steps searched numerically.
    pub endpoint_method: Option<&'static str>,
    pub numeric_steps: Vec<usize>,
    pub accuracy: Option<AccuracyReport>,
    pub components: Vec<ComponentReport>,
    /// Why there is no component, in words (`None` when there is one).
    pub no_realization: Option<String>,
    /// The complete Cayley vector cannot tell mirror images apart (all clusters achiral).
    pub mirror_pairs: bool,
    pub warnings: Vec<String>,
    pub timings_us: BTreeMap<String, f64>,
}

impl Report {
    pub fn new(a: &Analysis) -> Report {
        let l = &a.linkage;
        let name = |j: usize| l.names[j].clone();
        let pair = |p: [usize; 2]| [name(p[0]), name(p[1])];
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
            reason_kind: None,
            base: None,
            base_chosen_automatically: false,
            other_bases: Vec::new(),
            steps: Vec::new(),
            low_cayley_complexity: None,
            lcc_failure: None,
            complete_cayley_vector: Vec::new(),
            drawn: None,
            sketch: None,
            analysis: "full",
            cayley_space: Vec::new(),
            oriented_intervals: Vec::new(),
            endpoint_method: None,
            numeric_steps: Vec::new(),
            accuracy: None,
            components: Vec::new(),
            no_realization: None,
            mirror_pairs: false,
            warnings: a.warnings.clone(),
            timings_us: a.timings.0.iter().map(|(k, v)| (k.to_string(), *v)).collect(),
        };
        r.warnings.extend(body_bar_warnings(a));
        match &a.outcome {
            Err(outside) => {
                r.reason = Some(outside.describe(l));
                r.reason_kind = Some(outside.kind().to_string());
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
                    .map(|(st, g)| StepReport {
                        vertex: name(st.vertex),
                        on: [name(st.u), name(st.w)],
                        clusters: [st.cluster_u, st.cluster_w]
                            .map(|c| s.dec.clusters.nodes[c].joints.iter().map(|&j| name(j)).collect()),
                        lengths: [g.r1, g.r2],
                    })
                    .collect();
                r.low_cayley_complexity = Some(s.complexity.low);
                r.lcc_failure = s.complexity.failure.as_ref().map(|f| f.message.clone());
                r.complete_cayley_vector = s.complexity.ccv.iter().map(|&p| pair(p)).collect();
                r.drawn = Some(DrawnReport { lambda: s.drawn.lambda, ty: s.drawn.ty.to_string() });
                r.sketch = s
                    .sketch
                    .as_ref()
                    .map(|f| SketchReport { max_length_change: f.max_length_change, max_joint_move: f.max_joint_move });
                r.cayley_space = s.union.clone();
                let event = |e: &crate::realize::Event| EventReport {
                    step: e.step,
                    vertex: name(s.dec.steps[e.step].vertex),
                    kind: e.kind.name(),
                };
                r.oriented_intervals = s
                    .space
                    .intervals
                    .iter()
                    .map(|i| IntervalReport {
                        ty: i.ty.to_string(),
                        lower: i.lower.lambda,
                        upper: i.upper.lambda,
                        lower_event: i.lower.events.first().map(event),
                        upper_event: i.upper.events.first().map(event),
                        lower_events: i.lower.events.iter().map(event).collect(),
                        upper_events: i.upper.events.iter().map(event).collect(),
                    })
                    .collect();
                r.analysis = if s.lazy { "lazy" } else { "full" };
                r.endpoint_method = Some(if s.lazy {
                    "lazy"
                } else if s.space.numeric_steps.is_empty() {
                    "exact"
                } else {
                    "exact+numeric"
                });
                if !s.lazy {
                    r.numeric_steps = s.space.numeric_steps.clone();
                }
                r.components = s
                    .components
                    .list
                    .iter()
                    .enumerate()
                    .map(|(k, c)| ComponentReport {
                        intervals: c.intervals.clone(),
                        lambda_range: c.lambda_range,
                        contains_drawn: s.drawn_component == Some(k),
                        closed: c.closed,
                    })
                    .collect();
                r.no_realization = crate::commands::no_realization(a, s);
                r.mirror_pairs = crate::cayley_vector::mirror_images_exist(&s.construction, &s.dec);
                r.accuracy = s.accuracy.as_ref().map(|acc| AccuracyReport {
                    reference: "double-double (106-bit)",
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

    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("report serializes")
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
            .enumerate()
            .map(|(k, s)| {
                [
                    format!("{}", k + 1),
                    format!("{} ◁ ({}, {})", s.vertex, s.on[0], s.on[1]),
                    format!("{{{}}}", s.clusters[0].join(",")),
                    format!("{{{}}}", s.clusters[1].join(",")),
                    format!("{}, {}", fmt_num(s.lengths[0]), fmt_num(s.lengths[1])),
                ]
            })
            .collect();
        write_table(&mut o, &["#", "step", "cluster on u", "cluster on w", "|uv|, |wv|"], &rows);
        let _ = writeln!(o);
        let lcc = match (self.low_cayley_complexity, &self.lcc_failure) {
            (Some(true), _) => "yes (four-cycle test)".to_string(),
            (_, Some(f)) => format!("no: {f}"),
            _ => "unknown".to_string(),
        };
        let _ = writeln!(o, "{:<24}{lcc}", "Low Cayley complexity");
        let ccv: Vec<String> = self.complete_cayley_vector.iter().map(|[a, b]| format!("{a}–{b}")).collect();
        let ccv = if ccv.len() > 16 {
            format!("{}, …, {} ({} pairs)", ccv[..8].join(", "), ccv[ccv.len() - 4..].join(", "), ccv.len())
        } else {
            ccv.join(", ")
        };
        let _ = writeln!(o, "{:<24}{ccv}", "Complete Cayley vector");
        if let Some(d) = &self.drawn {
            let _ = writeln!(o, "{:<24}λ = {}  type {}", "Drawn realization", fmt_num(d.lambda), short_type(&d.ty));
        }
        if let Some(s) = &self.sketch {
            let moved = if s.max_joint_move.is_finite() {
                format!("joints moved up to {}", fmt_sci(s.max_joint_move))
            } else {
                "the drawn type has no realization (see warnings)".to_string()
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
        let lazy = self.analysis == "lazy";
        if lazy {
            let _ = writeln!(
                o,
                "{:<24}lazy: only the component through the drawn realization ({n_types_text} types not enumerated; --all forces the full analysis)",
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
                Some("exact") => "endpoints in closed form".to_string(),
                Some("lazy") => "endpoints by the lazy walk, Newton to full precision".to_string(),
                _ => format!(
                    "closed form, and numeric search for steps {}",
                    self.numeric_steps.iter().map(|k| (k + 1).to_string()).collect::<Vec<_>>().join(", ")
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
        let ev = |e: &Option<EventReport>, all: &[EventReport]| match e {
            Some(e) => {
                let extra = if all.len() > 1 { format!(" +{}", all.len() - 1) } else { String::new() };
                format!("{} {} (step {}){extra}", e.vertex, e.kind, e.step + 1)
            }
            None => "-".to_string(),
        };
        let rows: Vec<[String; 5]> = shown
            .iter()
            .map(|i| {
                [
                    short_type(&i.ty),
                    fmt_num(i.lower),
                    fmt_num(i.upper),
                    ev(&i.lower_event, &i.lower_events),
                    ev(&i.upper_event, &i.upper_events),
                ]
            })
            .collect();
        write_table(o, &["type", "lower", "upper", "lower event", "upper event"], &rows);
        let _ = writeln!(o);
        self.write_chart(o, &shown);
        let _ = writeln!(o);
    }

    fn write_components(&self, o: &mut String) {
        if let Some(why) = &self.no_realization {
            let _ = writeln!(o, "{:<24}0: {why}", "Components");
            return;
        }
        let _ = writeln!(
            o,
            "{:<24}{}{}",
            "Components",
            self.components.len(),
            if self.mirror_pairs { " (all clusters achiral: mirror images share Cayley vectors)" } else { "" }
        );
        let rows: Vec<[String; 4]> = self
            .components
            .iter()
            .enumerate()
            .map(|(k, c)| {
                let types: Vec<String> =
                    c.intervals.iter().map(|&i| short_type(&self.oriented_intervals[i].ty)).collect();
                let shown = if types.len() > 6 {
                    format!("{} … ({} more)", types[..6].join(" "), types.len() - 6)
                } else {
                    types.join(" ")
                };
                [
                    format!("{k}{}", if c.contains_drawn { " *" } else { "" }),
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
        let label_width = shown.iter().map(|i| i.ty.chars().count()).max().unwrap_or(4).max(5);
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
            let _ = writeln!(o, "  {:<label_width$} |{row}|", i.ty);
        }
    }

    fn write_warnings(&self, o: &mut String) {
        if self.warnings.is_empty() {
            let _ = writeln!(o, "{:<24}none", "Warnings");
        } else {
            let _ = writeln!(o, "Warnings");
            for w in &self.warnings {
                let _ = writeln!(o, "  - {w}");
            }
        }
    }
}

/// One warning per bar that repeats a body it agrees with (recognition ignores it).
fn body_bar_warnings(a: &Analysis) -> Vec<String> {
    let l = &a.linkage;
    crate::decompose::bars_within_bodies(l)
        .into_iter()
        .filter(|b| b.agrees)
        .map(|b| {
            let line = a.scene.bars.get(b.bar).map_or(0, |bar| bar.line);
            let at = if line > 0 { format!(", line {line}") } else { String::new() };
            let body: Vec<&str> = l.bodies[b.body].iter().map(|&j| l.names[j].as_str()).collect();
            format!(
                "bar {} ({}{at}) joins two joints of body {} [{}], which already holds them at that length: the bar adds nothing and is ignored",
                b.bar + 1,
                l.pair_name(l.bars[b.bar].joints),
                b.body + 1,
                body.join(", ")
            )
        })
        .collect()
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
