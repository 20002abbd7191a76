//! What the motion commands compute, as plain data (JSON-ready) and text:
//! `path`, `trace`, `closest`, `svg`. The CLI only parses arguments and
//! prints; the terminal UI calls the same functions.

use std::fmt::Write as _;

use serde::Serialize;

use crate::analysis::{Analysis, Solved};
use crate::distance::{Certificate, ClosestOptions, ClosestPair, Outcome, closest_pair};
use crate::motion::{Realization, Segment, Stepper, arcs, component_segments, explain_missing, locate, measure};

/// The default geometric step: 1% of the scene scale.
pub fn default_step(a: &Analysis) -> f64 {
    a.linkage.scale / 100.0
}

/// In a lazy analysis, walk the components through the realizations named
/// by `specs` (`TYPE@LAMBDA`; `drawn` is always known) so that they resolve.
pub fn include_specs(s: &mut Solved, specs: &[&str]) {
    for spec in specs {
        if let Ok(r) = Realization::parse(spec) {
            s.include(&r);
        }
    }
}

/// `drawn` or `TYPE@LAMBDA` → a located realization (interval index).
pub fn resolve_realization(a: &Analysis, s: &Solved, spec: &str) -> Result<(Realization, usize), String> {
    let r = if spec.trim() == "drawn" {
        Realization { ty: s.drawn.ty.clone(), lambda: s.drawn.lambda }
    } else {
        Realization::parse(spec)?
    };
    match locate(&s.space, &r, a.linkage.scale) {
        Some(i) => Ok((r, i)),
        None => Err(format!("{spec}: {}", explain_missing(&s.space, &r, s.dec.steps.len()))),
    }
}

#[derive(Debug, Clone, Serialize)]
pub struct SegmentOut {
    #[serde(rename = "type")]
    pub ty: String,
    pub from: f64,
    pub to: f64,
}

#[derive(Debug, Clone, Serialize)]
pub struct PathOut {
    /// `along` the component's listed order, or `against` it.
    pub direction: &'static str,
    pub intervals: Vec<SegmentOut>,
    pub n_intervals: usize,
    pub lambda_range: [f64; 2],
    pub cayley_length: f64,
    pub max_joint_travel: f64,
    pub shorter: bool,
}

#[derive(Debug, Clone, Serialize)]
pub struct RealizationOut {
    #[serde(rename = "type")]
    pub ty: String,
    pub lambda: f64,
    pub component: usize,
}

/// The closest pair between two components with its certificate: the
/// numbers are the solver's ([`Certificate`]); `certificate` says them in words.
#[derive(Debug, Clone, Serialize)]
pub struct ClosestOut {
    pub distance: f64,
    pub a: RealizationOut,
    pub b: RealizationOut,
    /// Proven: no pair of realizations, one in each component, is closer.
    pub lower_bound: f64,
    /// Proven: the exact realizations named by `a` and `b` are at most this far apart.
    pub upper_bound: f64,
    /// (upper_bound − lower_bound) / upper_bound.
    pub relative_gap: f64,
    pub requested_gap: f64,
    /// The requested gap was reached with every interval end verified.
    pub certified: bool,
    pub outcome: Outcome,
    pub boxes: usize,
    pub max_boxes: usize,
    pub end_pairs: usize,
    pub unverified_ends: usize,
    pub mirror_images: bool,
    /// Zero distance between different realizations: the Cayley curves cross.
    pub curves_cross: bool,
    pub certificate: String,
}

impl ClosestOut {
    pub fn to_text(&self) -> String {
        format!(
            "Closest pair between components {} and {}: Cayley distance {}\n  {}@{}  and  {}@{}\n  {}\n",
            self.a.component,
            self.b.component,
            full(self.distance),
            self.a.ty,
            self.a.lambda,
            self.b.ty,
            self.b.lambda,
            self.certificate
        )
    }
}

/// A distance to full precision: the shortest form that reads back exactly,
/// in scientific notation when tiny or huge.
fn full(x: f64) -> String {
    if x == 0.0 || (1e-4..1e15).contains(&x.abs()) { format!("{x}") } else { format!("{x:e}") }
}

/// The certificate in words: "certified to …" only when it is.
pub fn certificate_sentence(c: &Certificate) -> String {
    let (lo, hi, req) = (full(c.lower), full(c.upper), c.requested_gap);
    let range = format!("the minimum distance lies in [{lo}, {hi}] (relative gap {:.1e})", c.gap);
    let mut o = match c.outcome {
        Outcome::Mirror => {
            return "distance exactly 0: the components are mirror images (every realization's mirror lies in the \
                    other, with the same Cayley vector)"
                .into();
        }
        Outcome::GapReached if c.certified => format!(
            "certified to {req:e}: no two realizations, one in each component, are closer than {lo}, and the pair \
             above is at most {hi} apart (interval arithmetic with outward rounding over {} boxes and {} pairs of \
             interval ends, every end verified)",
            c.boxes, c.end_pairs
        ),
        Outcome::GapReached => format!("gap {req:e} reached over the intervals as computed: {range}"),
        Outcome::Resolution if c.upper.is_infinite() => format!(
            "not certified: f64 interval arithmetic cannot enclose these realizations (their construction is too \
             deep for its rounding to stay small); proven: no two realizations are closer than {lo}"
        ),
        Outcome::Resolution if c.lower == 0.0 && c.upper > 0.0 => format!(
            "not certified to {req:e}: the Cayley curves meet or nearly so (the pair above is 0 apart up to \
             rounding); proven: the minimum distance lies in [0, {hi}]"
        ),
        Outcome::Resolution => {
            format!(
                "not certified to {req:e}: f64 interval arithmetic does not resolve the distance that finely here; proven: {range}"
            )
        }
        Outcome::Budget => {
            format!("not certified to {req:e}: the budget of {} boxes ran out; proven: {range}", c.max_boxes)
        }
    };
    if c.unverified_ends > 0 {
        let _ = write!(
            o,
            "; not certified: {} interval ends could not be verified (several steps flat at once, or a tangency), \
             so the bounds hold for the intervals as computed",
            c.unverified_ends
        );
    }
    o
}

#[derive(Debug, Clone, Serialize)]
pub struct PathReport {
    pub from: RealizationOut,
    pub to: RealizationOut,
    pub same_component: bool,
    pub same_type_path: bool,
    pub paths: Vec<PathOut>,
    pub closest_pair: Option<ClosestOut>,
}

fn realization_out(s: &Solved, r: &Realization, interval: usize) -> RealizationOut {
    RealizationOut { ty: r.ty.to_string(), lambda: r.lambda, component: s.components.of_interval[interval] }
}

fn closest_out(s: &Solved, c: &ClosestPair, (ca, cb): (usize, usize)) -> ClosestOut {
    let comp = |r: &Realization, fallback: usize| {
        locate(&s.space, r, s.construction.scale).map_or(fallback, |i| s.components.of_interval[i])
    };
    let cert = &c.certificate;
    ClosestOut {
        distance: c.distance,
        a: RealizationOut { ty: c.a.ty.to_string(), lambda: c.a.lambda, component: comp(&c.a, ca) },
        b: RealizationOut { ty: c.b.ty.to_string(), lambda: c.b.lambda, component: comp(&c.b, cb) },
        lower_bound: cert.lower,
        upper_bound: cert.upper,
        relative_gap: cert.gap,
        requested_gap: cert.requested_gap,
        certified: cert.certified,
        outcome: cert.outcome,
        boxes: cert.boxes,
        max_boxes: cert.max_boxes,
        end_pairs: cert.end_pairs,
        unverified_ends: cert.unverified_ends,
        mirror_images: c.mirror,
        curves_cross: c.crossing,
        certificate: certificate_sentence(cert),
    }
}

/// Closest pair between components `i` and `j` (indices into the component
/// list), certified to the default relative gap.
pub fn closest(a: &Analysis, s: &Solved, i: usize, j: usize) -> Result<ClosestOut, String> {
    closest_with(a, s, i, j, ClosestOptions::default())
}

/// [`closest`] with the gap and work budget chosen.
pub fn closest_with(_a: &Analysis, s: &Solved, i: usize, j: usize, opts: ClosestOptions) -> Result<ClosestOut, String> {
    let n = s.components.list.len();
    if i >= n || j >= n {
        return Err(format!(
            "component index out of range: this scene has {n} components (0..{})",
            n.saturating_sub(1)
        ));
    }
    if i == j {
        return Err("the two components must differ (distance within one component is 0)".into());
    }
    if !(opts.gap > 0.0 && opts.gap < 1.0) {
        return Err(format!("--gap {}: give a relative gap between 0 and 1, e.g. 1e-9", opts.gap));
    }
    let (ci, cj) = (&s.components.list[i], &s.components.list[j]);
    let c = closest_pair(&s.construction, &s.dec, &s.space, &s.complexity.ccv, (ci, cj), opts)
        .ok_or_else(|| "no realizations to compare".to_string())?;
    Ok(closest_out(s, &c, (i, j)))
}

/// Both paths between two realizations, or the closest pair when none exists.
pub fn path(a: &Analysis, s: &Solved, from: &str, to: &str, step: f64) -> Result<PathReport, String> {
    let (ra, ia) = resolve_realization(a, s, from)?;
    let (rb, ib) = resolve_realization(a, s, to)?;
    let (ca, cb) = (s.components.of_interval[ia], s.components.of_interval[ib]);
    let from_out = realization_out(s, &ra, ia);
    let to_out = realization_out(s, &rb, ib);
    if ca != cb {
        let closest = closest(a, s, ca, cb)?;
        return Ok(PathReport {
            from: from_out,
            to: to_out,
            same_component: false,
            same_type_path: false,
            paths: Vec::new(),
            closest_pair: Some(closest),
        });
    }
    let comp = &s.components.list[ca];
    let both =
        arcs(&s.space, comp, (ia, ra.lambda), (ib, rb.lambda)).ok_or("both realizations must lie in the component")?;
    // An open component (a chain between dead ends) has one path only.
    let mut paths: Vec<PathOut> = both
        .into_iter()
        .zip(["along", "against"])
        .filter(|(segs, _)| !segs.is_empty())
        .map(|(segs, direction)| {
            let m = measure(&s.construction, &a.linkage, segs.clone(), step, &s.complexity.ccv);
            let lo = segs.iter().map(|x| x.from.min(x.to)).fold(f64::INFINITY, f64::min);
            let hi = segs.iter().map(|x| x.from.max(x.to)).fold(f64::NEG_INFINITY, f64::max);
            PathOut {
                direction,
                n_intervals: segs.len(),
                intervals: segs.iter().map(|x| SegmentOut { ty: x.ty.to_string(), from: x.from, to: x.to }).collect(),
                lambda_range: [lo, hi],
                cayley_length: m.cayley_length,
                max_joint_travel: m.max_joint_travel,
                shorter: false,
            }
        })
        .collect();
    let shorter = (0..paths.len()).min_by(|&i, &j| paths[i].cayley_length.total_cmp(&paths[j].cayley_length));
    if let Some(k) = shorter.filter(|_| paths.len() > 1) {
        paths[k].shorter = true;
    }
    Ok(PathReport {
        from: from_out,
        to: to_out,
        same_component: true,
        same_type_path: ia == ib,
        paths,
        closest_pair: None,
    })
}

impl PathReport {
    pub fn to_text(&self) -> String {
        let mut o = String::new();
        let r =
            |x: &RealizationOut| format!("{}@{} (component {})", x.ty, crate::report::fmt_num(x.lambda), x.component);
        let _ = writeln!(o, "From {}  to {}", r(&self.from), r(&self.to));
        if let Some(c) = &self.closest_pair {
            let _ = writeln!(o, "No path: the realizations lie in different components.");
            let _ = writeln!(o, "Closest pair by Cayley distance: {}", full(c.distance));
            let _ = writeln!(o, "  {}  and  {}", r(&c.a), r(&c.b));
            let _ = writeln!(o, "  {}", c.certificate);
            return o;
        }
        let _ = writeln!(
            o,
            "Same component; a path keeping the type {}",
            if self.same_type_path { "exists" } else { "does not exist" }
        );
        for p in &self.paths {
            let _ = writeln!(
                o,
                "\nPath {} the component{}: {} intervals, Cayley length {}, largest joint travel {}",
                p.direction,
                if p.shorter { " (shorter)" } else { "" },
                p.n_intervals,
                crate::report::fmt_num(p.cayley_length),
                crate::report::fmt_num(p.max_joint_travel)
            );
            let rows: Vec<[String; 3]> = p
                .intervals
                .iter()
                .map(|x| [x.ty.clone(), crate::report::fmt_num(x.from), crate::report::fmt_num(x.to)])
                .collect();
            crate::report::write_table(&mut o, &["type", "from λ", "to λ"], &rows);
        }
        o
    }
}

/// Segments for `trace`: a whole component, or the shorter (or chosen) arc between two realizations.
pub fn trace_segments(
    a: &Analysis,
    s: &Solved,
    component: Option<usize>,
    between: Option<(&str, &str, Option<usize>)>,
) -> Result<Vec<Segment>, String> {
    if let Some((from, to, arc)) = between {
        let (ra, ia) = resolve_realization(a, s, from)?;
        let (rb, ib) = resolve_realization(a, s, to)?;
        let c = s.components.of_interval[ia];
        if c != s.components.of_interval[ib] {
            return Err("no path: the two realizations lie in different components (see `caymos path`)".into());
        }
        let both = arcs(&s.space, &s.components.list[c], (ia, ra.lambda), (ib, rb.lambda))
            .ok_or("both realizations must lie in the component")?;
        let len = |segs: &[Segment]| {
            if segs.is_empty() { f64::INFINITY } else { segs.iter().map(|x| (x.to - x.from).abs()).sum::<f64>() }
        };
        let pick = match arc {
            Some(k @ (1 | 2)) if both[k - 1].is_empty() => {
                return Err(format!(
                    "--arc {k}: the component is an open chain (it ends at dead ends); the only path is arc {}",
                    3 - k
                ));
            }
            Some(k @ (1 | 2)) => k - 1,
            Some(_) => return Err("--arc is 1 or 2".into()),
            None => {
                if len(&both[0]) <= len(&both[1]) {
                    0
                } else {
                    1
                }
            }
        };
        return Ok(both[pick].clone());
    }
    let k = component.or(s.drawn_component).unwrap_or(0);
    let comp = s.components.list.get(k).ok_or_else(|| {
        format!(
            "no component {k}: this scene has {} (0..{})",
            s.components.list.len(),
            s.components.list.len().saturating_sub(1)
        )
    })?;
    Ok(component_segments(&s.space, comp))
}

/// Joint indices from `A,B,...` (all joints when `None`).
pub fn parse_joints(a: &Analysis, list: Option<&str>) -> Result<Vec<usize>, String> {
    match list {
        None => Ok((0..a.linkage.n_joints()).collect()),
        Some(text) => text
            .split(',')
            .map(|n| {
                let n = n.trim();
                a.linkage.names.iter().position(|x| x == n).ok_or_else(|| format!("--joints: no joint named \"{n}\""))
            })
            .collect(),
    }
}

/// CSV of the walk: `index,lambda,type,A.x,A.y,...`; with `cayley`, the
/// complete Cayley distance vector follows (columns named `A-B`): the Cayley
/// curve of the component or path.
pub fn trace_csv(
    a: &Analysis,
    s: &Solved,
    segments: Vec<Segment>,
    joints: &[usize],
    step: f64,
    cayley: bool,
) -> String {
    let mut o = String::from("index,lambda,type");
    for &j in joints {
        let _ = write!(o, ",{0}.x,{0}.y", a.linkage.names[j]);
    }
    if cayley {
        for &[p, q] in &s.complexity.ccv {
            let _ = write!(o, ",{}-{}", a.linkage.names[p], a.linkage.names[q]);
        }
    }
    o.push('\n');
    for (i, sample) in Stepper::new(&s.construction, &a.linkage, segments, step).enumerate() {
        let _ = write!(o, "{i},{},{}", sample.lambda, sample.ty);
        for &j in joints {
            let p = sample.positions[j];
            let _ = write!(o, ",{},{}", p[0], p[1]);
        }
        if cayley {
            for d in crate::distance::cayley_vector(&sample.positions, &s.complexity.ccv) {
                let _ = write!(o, ",{d}");
            }
        }
        o.push('\n');
    }
    o
}

/// An SVG of the drawn realization with the traces of `joints` over the segments.
pub fn svg(a: &Analysis, s: &Solved, segments: Vec<Segment>, joints: &[usize], step: f64) -> String {
    let traces: Vec<Vec<[f64; 2]>> = {
        let mut t = vec![Vec::new(); joints.len()];
        for sample in Stepper::new(&s.construction, &a.linkage, segments, step) {
            for (k, &j) in joints.iter().enumerate() {
                t[k].push(sample.positions[j]);
            }
        }
        t
    };
    let pose = s.drawn_positions.clone().unwrap_or_else(|| a.linkage.drawn.clone());
    let all = pose.iter().chain(traces.iter().flatten());
    let (mut x0, mut y0, mut x1, mut y1) = (f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY);
    for p in all {
        x0 = x0.min(p[0]);
        y0 = y0.min(p[1]);
        x1 = x1.max(p[0]);
        y1 = y1.max(p[1]);
    }
    let pad = 0.06 * (x1 - x0).max(y1 - y0).max(1e-9);
    let (w, h) = (x1 - x0 + 2.0 * pad, y1 - y0 + 2.0 * pad);
    let stroke = 0.004 * w.max(h);
    // y up in the scene, down in SVG: flip through the view box.
    let (sx, sy) = (|x: f64| x - x0 + pad, |y: f64| y1 + pad - y);
    let mut o = String::new();
    let _ = writeln!(
        o,
        r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {w:.6} {h:.6}" width="800" height="{:.0}">"#,
        800.0 * h / w
    );
    let _ = writeln!(o, "<title>{} — caymos</title>", xml_escape(&a.scene.name));
    let palette = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf"];
    for (k, t) in traces.iter().enumerate() {
        let pts: Vec<String> = t.iter().map(|p| format!("{:.6},{:.6}", sx(p[0]), sy(p[1]))).collect();
        let _ = writeln!(
            o,
            r#"<polyline fill="none" stroke="{}" stroke-width="{:.6}" stroke-opacity="0.7" points="{}"/>"#,
            palette[k % palette.len()],
            stroke * 0.6,
            pts.join(" ")
        );
    }
    for bar in &a.linkage.bars {
        let (p, q) = (pose[bar.joints[0]], pose[bar.joints[1]]);
        let _ = writeln!(
            o,
            r##"<line x1="{:.6}" y1="{:.6}" x2="{:.6}" y2="{:.6}" stroke="#333" stroke-width="{stroke:.6}"/>"##,
            sx(p[0]),
            sy(p[1]),
            sx(q[0]),
            sy(q[1])
        );
    }
    for body in &a.linkage.bodies {
        let pts: Vec<String> = body.iter().map(|&j| format!("{:.6},{:.6}", sx(pose[j][0]), sy(pose[j][1]))).collect();
        let _ = writeln!(
            o,
            r##"<polygon points="{}" fill="#999" fill-opacity="0.3" stroke="#333" stroke-width="{stroke:.6}"/>"##,
            pts.join(" ")
        );
    }
    for (j, p) in pose.iter().enumerate() {
        let ground = a.linkage.ground.contains(&j);
        let _ = writeln!(
            o,
            r##"<circle cx="{:.6}" cy="{:.6}" r="{:.6}" fill="{}"/><text x="{:.6}" y="{:.6}" font-size="{:.6}" font-family="sans-serif">{}</text>"##,
            sx(p[0]),
            sy(p[1]),
            stroke * 2.0,
            if ground { "#000" } else { "#fff" },
            sx(p[0]) + stroke * 3.0,
            sy(p[1]) - stroke * 3.0,
            stroke * 8.0,
            xml_escape(&a.linkage.names[j])
        );
    }
    o.push_str("</svg>\n");
    o
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}
