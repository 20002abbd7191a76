//! `caymos report`: the analysis as JSON for scripts and as aligned text for people.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use serde::Serialize;

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
pub struct SketchReport {
    pub max_length_change: f64,
    pub max_joint_move: f64,
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
            warnings: a.warnings.clone(),
            timings_us: a.timings.0.iter().map(|(k, v)| (k.to_string(), *v)).collect(),
        };
        match &a.outcome {
            Err(outside) => {
                r.reason = Some(outside.describe(l));
                r.reason_kind = Some(outside.kind().to_string());
            }
            Ok(s) => {
                r.base = Some(pair(s.dec.base));
                r.base_chosen_automatically = s.dec.base_chosen;
                r.other_bases = s.dec.other_bases.iter().map(|&p| pair(p)).collect();
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
            }
        }
        r
    }

    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("report serializes")
    }

    /// The text form: aligned tables, for people.
    pub fn to_text(&self) -> String {
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
            let _ = writeln!(o, "{:<24}{}", "Class", "outside the handled class");
            let _ = writeln!(o, "{:<24}{}", "Reason", self.reason.as_deref().unwrap_or("?"));
            self.write_warnings(&mut o);
            return o;
        }
        let _ = writeln!(o, "{:<24}{}", "Class", "1-dof tree-decomposable");
        if let Some([a, b]) = &self.base {
            let how = if self.base_chosen_automatically { "chosen automatically" } else { "given" };
            let _ = writeln!(o, "{:<24}{a}–{b} ({how})", "Base non-edge");
        }
        let others: Vec<String> = self.other_bases.iter().map(|[a, b]| format!("{a}–{b}")).collect();
        let _ = writeln!(o, "{:<24}{}", "Other valid bases", if others.is_empty() { "none".into() } else { others.join(", ") });
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
        let _ = writeln!(o, "{:<24}{}", "Complete Cayley vector", ccv.join(", "));
        if let Some(d) = &self.drawn {
            let _ = writeln!(o, "{:<24}λ = {}  type {}", "Drawn realization", fmt_num(d.lambda), d.ty);
        }
        if let Some(s) = &self.sketch {
            let _ = writeln!(
                o,
                "{:<24}stated lengths differ from the drawing by up to {}; joints moved up to {}",
                "Sketch",
                fmt_num(s.max_length_change),
                fmt_num(s.max_joint_move)
            );
        }
        self.write_warnings(&mut o);
        o
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

/// A number with 6 significant digits, without trailing zeros.
pub fn fmt_num(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let digits = (6 - 1 - x.abs().log10().floor() as i32).clamp(0, 12) as usize;
    let s = format!("{x:.digits$}");
    if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_string() } else { s }
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
