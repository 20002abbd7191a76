//! What the motion commands compute, as plain data (JSON-ready) and text:
//! `path`, `trace`, `closest`, `svg`. The CLI only parses arguments and
//! prints; the terminal UI calls the same functions. Every walk has a sample
//! budget and says what it met (budget, jumps, unresolved stretches).

use std::fmt::Write as _;

use schemars::JsonSchema;
use serde::Serialize;

use crate::analysis::{Analysis, Solved, no_realization};
use crate::distance::{ClosestOptions, ClosestPair, Outcome, closest_pair};
use crate::linkage::Linkage;
use crate::motion::{
    Segment, Stepper, WalkSummary, arcs, bounding_diagonal, component_segments, explain_missing, locate, measure,
};
use crate::numfmt::fmt_num;
use crate::present::{self, ComponentNo, Names};
use crate::realize::{Point2, Realization};
use crate::scene::Scene;
use crate::sweep::{
    self, Change, ClassKind, InputBar, MAX_STEPS, NotInput, Parameter, Setup, SweepSample, Transition, Turn,
};
use crate::tolerance;

/// How finely and how far a command walks: the geometric step (largest joint
/// move between samples, scene units) and the sample budget.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Walk {
    pub step: f64,
    pub max_samples: usize,
}

/// The drawing's extent: the bounding-box diagonal of the drawn realization
/// (the drawing itself when it has none). Falls back to the scene scale for a
/// drawing of one point.
pub fn drawing_extent(a: &Analysis) -> f64 {
    extent_of(&a.linkage, a.outcome.as_ref().ok())
}

/// [`drawing_extent`] from the linkage and its solved analysis, if any.
pub fn extent_of(linkage: &Linkage, s: Option<&Solved>) -> f64 {
    let drawn = s.and_then(|s| s.drawn_positions.clone()).unwrap_or_else(|| linkage.drawn_points());
    let d = bounding_diagonal(&drawn);
    if d > 0.0 && d.is_finite() { d } else { linkage.scale }
}

/// The default geometric step: [`tolerance::DEFAULT_STEP_FRACTION`] of the drawing's extent.
pub fn default_step(a: &Analysis) -> f64 {
    tolerance::DEFAULT_STEP_FRACTION * drawing_extent(a)
}

/// `Err` with the reason in words when `s` has no component to walk.
pub fn require_component(linkage: &Linkage, s: &Solved) -> Result<(), String> {
    match no_realization(s, linkage.scale) {
        Some(why) => Err(present::no_realization(&why, Names::new(linkage, &s.dec.steps), &s.construction)),
        None => Ok(()),
    }
}

/// In a lazy analysis, walk components until at least `want` are known:
/// after the drawn one, those through the realizations at the drawn λ, taken
/// in type order (a depth-first search over the steps that prunes a prefix
/// as soon as it cannot close). At most [`tolerance::LAZY_SEED_PROBES`]
/// prefixes are tried and [`tolerance::LAZY_MAX_NEW_COMPONENTS`] components
/// walked per call. Returns the number of components known.
pub fn walk_components(s: &mut Solved, want: usize) -> usize {
    if !s.lazy || s.components.list.len() >= want {
        return s.components.list.len();
    }
    let want = want.min(s.components.list.len() + tolerance::LAZY_MAX_NEW_COMPONENTS);
    let lambda = s.drawn.lambda;
    let n = s.construction.steps.len();
    let mut probes = 0usize;
    // Depth-first over prefixes, `false` before `true` (the order types sort in).
    let mut stack: Vec<Vec<bool>> = vec![Vec::new()];
    while let Some(bits) = stack.pop() {
        if s.components.list.len() >= want || probes >= tolerance::LAZY_SEED_PROBES {
            break;
        }
        probes += 1;
        if !bits.is_empty() && s.construction.realize_prefix(lambda, &bits, bits.len()).is_err() {
            continue;
        }
        if bits.len() == n {
            let r = Realization { ty: crate::realize::RealizationType(bits), lambda };
            s.include(&r);
            continue;
        }
        for b in [true, false] {
            let mut next = bits.clone();
            next.push(b);
            stack.push(next);
        }
    }
    s.components.list.len()
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
pub fn resolve_realization(s: &Solved, spec: &str) -> Result<(Realization, usize), String> {
    let r = if spec.trim() == "drawn" {
        Realization { ty: s.drawn.ty.clone(), lambda: s.drawn.lambda }
    } else {
        Realization::parse(spec)?
    };
    match locate(&s.space, &r, s.construction.scale) {
        Some(i) => Ok((r, i)),
        None => Err(format!("{spec}: {}", present::missing(&explain_missing(&s.space, &r, s.dec.steps.len())))),
    }
}

#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct SegmentOut {
    #[serde(rename = "type")]
    pub ty: String,
    pub from: f64,
    pub to: f64,
}

/// Which way a path runs around its component.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Direction {
    /// In the component's listed order (`--arc 1`).
    Along,
    /// Against it (`--arc 2`).
    Against,
}

impl std::fmt::Display for Direction {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Direction::Along => "along",
            Direction::Against => "against",
        })
    }
}

#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct PathOut {
    pub direction: Direction,
    pub intervals: Vec<SegmentOut>,
    pub n_intervals: usize,
    pub lambda_range: [f64; 2],
    /// Lengths of the walked part (all of it when `complete`); jumps add nothing.
    pub cayley_length: f64,
    pub max_joint_travel: f64,
    pub shorter: bool,
    /// Realizations computed to measure this path.
    pub samples: usize,
    /// Whether the walk reached the end within the sample budget.
    pub complete: bool,
    /// λ of the jumps met (degenerate passes; see `notes`).
    pub jumps: Vec<f64>,
    /// Branch points passed (non-generic places where several ways meet) and the way taken at each.
    pub branch_points: Vec<BranchOut>,
    /// What the walk met, in words (budget, jumps, unresolved stretches, branch points).
    pub notes: Vec<String>,
}

/// A branch point a path or trace passes, and which way it went on.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct BranchOut {
    pub lambda: f64,
    /// The steps flat there, numbered from 1.
    pub steps: Vec<usize>,
    /// The type it went on into.
    pub took: String,
    /// The types of every way meeting there (the one arrived from and the one taken included).
    pub ways: Vec<String>,
}

/// The branch points `segments` pass, as data (round a whole closed
/// component, the way from its last interval back to its first too).
pub fn branches_out(s: &Solved, segments: &[Segment]) -> Vec<BranchOut> {
    let ty = |i: usize| s.space.intervals[i].ty.to_string();
    let whole = segments.first().is_some_and(|f| {
        let c = &s.components.list[s.components.of_interval[f.interval]];
        c.closed && segments.iter().map(|x| x.interval).eq(c.intervals.iter().copied())
    });
    crate::motion::branches_passed(&s.components, segments, whole)
        .into_iter()
        .map(|b| BranchOut {
            lambda: b.lambda,
            steps: b.flat.iter().map(|k| k + 1).collect(),
            took: ty(b.taken),
            ways: b.ways.iter().map(|&i| ty(i)).collect(),
        })
        .collect()
}

#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct RealizationOut {
    #[serde(rename = "type")]
    pub ty: String,
    pub lambda: f64,
    /// Numbered from 1, as in the report and `--component`.
    pub component: ComponentNo,
}

/// The closest pair between two components with its certificate: the
/// numbers are the solver's ([`Certificate`](crate::distance::Certificate)); `certificate` says them in words.
#[derive(Debug, Clone, Serialize, JsonSchema)]
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
            present::full(self.distance),
            self.a.ty,
            self.a.lambda,
            self.b.ty,
            self.b.lambda,
            self.certificate
        )
    }
}

#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct PathReport {
    pub from: RealizationOut,
    pub to: RealizationOut,
    pub same_component: bool,
    /// In different components that meet at a branch point or a singular
    /// place (one connected set: see `components::connected`), which the
    /// listing of components does not pass.
    pub same_connected_set: bool,
    pub same_type_path: bool,
    pub paths: Vec<PathOut>,
    pub closest_pair: Option<ClosestOut>,
}

fn realization_out(s: &Solved, r: &Realization, interval: usize) -> RealizationOut {
    RealizationOut {
        ty: r.ty.to_string(),
        lambda: r.lambda,
        component: ComponentNo::of_index(s.components.of_interval[interval]),
    }
}

fn closest_out(s: &Solved, c: &ClosestPair, (ca, cb): (usize, usize)) -> ClosestOut {
    let comp = |r: &Realization, fallback: usize| {
        locate(&s.space, r, s.construction.scale).map_or(fallback, |i| s.components.of_interval[i])
    };
    let cert = &c.certificate;
    ClosestOut {
        distance: c.distance,
        a: RealizationOut {
            ty: c.a.ty.to_string(),
            lambda: c.a.lambda,
            component: ComponentNo::of_index(comp(&c.a, ca)),
        },
        b: RealizationOut {
            ty: c.b.ty.to_string(),
            lambda: c.b.lambda,
            component: ComponentNo::of_index(comp(&c.b, cb)),
        },
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
        certificate: present::certificate(cert),
    }
}

/// Closest pair between components `i` and `j` (indices into the component
/// list), certified to the default relative gap. In a lazy analysis the
/// components are walked first if needed.
pub fn closest(linkage: &Linkage, s: &Solved, i: usize, j: usize) -> Result<ClosestOut, String> {
    closest_with(linkage, s, i, j, ClosestOptions::default())
}

/// [`closest`] with the gap and work budget chosen.
pub fn closest_with(
    linkage: &Linkage,
    s: &Solved,
    i: usize,
    j: usize,
    opts: ClosestOptions,
) -> Result<ClosestOut, String> {
    require_component(linkage, s)?;
    if let Some(&k) = [i, j].iter().find(|&&k| k >= s.components.list.len()) {
        return Err(present::missing_component(s, k));
    }
    if i == j {
        return Err("the two components must differ (distance within one component is 0)".into());
    }
    if !(opts.gap > 0.0 && opts.gap < 1.0) {
        return Err(format!("--gap {}: give a relative gap between 0 and 1, e.g. 1e-9", opts.gap));
    }
    let (ci, cj) = (&s.components.list[i], &s.components.list[j]);
    let c = closest_pair(&s.construction, s.mirrors, &s.space, &s.complexity.ccv, (ci, cj), opts)
        .ok_or_else(|| "no realizations to compare".to_string())?;
    Ok(closest_out(s, &c, (i, j)))
}

/// Both paths between two realizations, or the closest pair when none exists.
/// Each path is walked within `walk`'s sample budget and says if it was cut.
pub fn path(linkage: &Linkage, s: &Solved, from: &str, to: &str, walk: Walk) -> Result<PathReport, String> {
    require_component(linkage, s)?;
    let (ra, ia) = resolve_realization(s, from).map_err(|e| format!("--from {e}"))?;
    let (rb, ib) = resolve_realization(s, to).map_err(|e| format!("--to {e}"))?;
    let (ca, cb) = (s.components.of_interval[ia], s.components.of_interval[ib]);
    let from_out = realization_out(s, &ra, ia);
    let to_out = realization_out(s, &rb, ib);
    if ca != cb {
        let closest = closest(linkage, s, ca, cb)?;
        return Ok(PathReport {
            from: from_out,
            to: to_out,
            same_component: false,
            same_connected_set: s.components.connected[ca] == s.components.connected[cb],
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
        .zip([Direction::Along, Direction::Against])
        .filter(|(segs, _)| !segs.is_empty())
        .map(|(segs, direction)| {
            let m = measure(&s.construction, linkage, segs.clone(), walk.step, &s.complexity.ccv, walk.max_samples);
            let lo = segs.iter().map(|x| x.from.min(x.to)).fold(f64::INFINITY, f64::min);
            let hi = segs.iter().map(|x| x.from.max(x.to)).fold(f64::NEG_INFINITY, f64::max);
            let branch_points = branches_out(s, &segs);
            let mut notes = present::walk_notes(&m.walk, walk.max_samples);
            notes.extend(branch_points.iter().map(present::branch_taken));
            PathOut {
                direction,
                n_intervals: segs.len(),
                intervals: segs.iter().map(|x| SegmentOut { ty: x.ty.to_string(), from: x.from, to: x.to }).collect(),
                lambda_range: [lo, hi],
                cayley_length: m.cayley_length,
                max_joint_travel: m.max_joint_travel,
                shorter: false,
                samples: m.walk.samples,
                complete: m.walk.complete(),
                jumps: m.walk.jumps.clone(),
                branch_points,
                notes,
            }
        })
        .collect();
    // Which is shorter is only known when both were walked to the end (an
    // open component has one path only).
    if paths.len() == 2 && paths.iter().all(|p| p.complete) {
        let shorter = if paths[0].cayley_length <= paths[1].cayley_length { 0 } else { 1 };
        paths[shorter].shorter = true;
    }
    Ok(PathReport {
        from: from_out,
        to: to_out,
        same_component: true,
        same_connected_set: true,
        same_type_path: ia == ib,
        paths,
        closest_pair: None,
    })
}

impl PathReport {
    pub fn to_text(&self) -> String {
        let mut o = String::new();
        let r = |x: &RealizationOut| format!("{}@{} (component {})", x.ty, fmt_num(x.lambda), x.component);
        let _ = writeln!(o, "From {}  to {}", r(&self.from), r(&self.to));
        if let Some(c) = &self.closest_pair {
            if self.same_connected_set {
                let _ = writeln!(
                    o,
                    "No path along one component: the realizations lie in different components of one connected set, which meet at a branch point or a singular place (see the report's warnings) that the listing of components does not pass."
                );
            } else {
                let _ = writeln!(o, "No path: the realizations lie in different components.");
            }
            let _ = writeln!(o, "Closest pair by Cayley distance: {}", present::full(c.distance));
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
                "\nPath {} the component{}: {} intervals, Cayley length {}{}, largest joint travel {} ({} samples)",
                p.direction,
                if p.shorter { " (shorter)" } else { "" },
                p.n_intervals,
                if p.complete { "" } else { "at least " },
                fmt_num(p.cayley_length),
                fmt_num(p.max_joint_travel),
                p.samples
            );
            for note in &p.notes {
                let _ = writeln!(o, "  note: {note}");
            }
            let rows: Vec<[String; 3]> =
                p.intervals.iter().map(|x| [x.ty.clone(), fmt_num(x.from), fmt_num(x.to)]).collect();
            crate::report::write_table(&mut o, &["type", "from λ", "to λ"], &rows);
        }
        o
    }
}

/// Segments for `trace`: a whole component (default: the drawn
/// realization's), or the shorter (or chosen) arc between two realizations.
pub fn trace_segments(
    linkage: &Linkage,
    s: &Solved,
    component: Option<usize>,
    between: Option<(&str, &str, Option<usize>)>,
) -> Result<Vec<Segment>, String> {
    require_component(linkage, s)?;
    if let Some((from, to, arc)) = between {
        let (ra, ia) = resolve_realization(s, from).map_err(|e| format!("--from {e}"))?;
        let (rb, ib) = resolve_realization(s, to).map_err(|e| format!("--to {e}"))?;
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
    let k = match (component, s.drawn_component) {
        (Some(k), _) | (None, Some(k)) => k,
        (None, None) => {
            return Err(format!(
                "the drawn realization ({}@{}) lies in no component found (see the warnings of `caymos report`); choose one with --component 1..{}",
                present::short_type(&s.drawn.ty.to_string()),
                fmt_num(s.drawn.lambda),
                s.components.list.len()
            ));
        }
    };
    let comp = s.components.list.get(k).ok_or_else(|| present::missing_component(s, k))?;
    Ok(component_segments(&s.space, comp))
}

/// Joint indices from `A,B,...` (all joints when `None`).
pub fn parse_joints(linkage: &Linkage, list: Option<&str>) -> Result<Vec<usize>, String> {
    match list {
        None => Ok((0..linkage.n_joints()).collect()),
        Some(text) => text
            .split(',')
            .map(|n| {
                let n = n.trim();
                linkage.names.iter().position(|x| x == n).ok_or_else(|| format!("--joints: no joint named \"{n}\""))
            })
            .collect(),
    }
}

/// The columns of a trace after `index,lambda,type,jump`.
#[derive(Debug, Clone, Default)]
pub struct TraceColumns {
    /// Joints whose positions are written (`A.x,A.y`).
    pub joints: Vec<usize>,
    /// An input bar whose angle from the ground line is written in degrees
    /// (`A-B.angle`, pivot first).
    pub angle: Option<InputBar>,
    /// Write the complete Cayley distance vector (columns named `A-B`).
    pub cayley: bool,
}

/// CSV of the walk, written row by row to `out` (memory stays small however
/// long the walk): `index,lambda,type,jump,A.x,A.y,...`; `jump` is 1 on a row
/// that no continuous motion joins to the row before (see
/// [`crate::motion::Sample::jump`]). Then, as `columns` asks, the input bar's
/// angle in degrees from the ground line (counter-clockwise, in (−180, 180];
/// [`InputBar::angle`]) and the complete Cayley distance vector: the Cayley
/// curve of the component or path. Numbers are written in full precision.
pub fn trace_csv(
    linkage: &Linkage,
    s: &Solved,
    segments: Vec<Segment>,
    columns: &TraceColumns,
    walk: Walk,
    out: &mut dyn std::io::Write,
) -> std::io::Result<WalkSummary> {
    let name = |j: usize| &linkage.names[j];
    let mut row = String::from("index,lambda,type,jump");
    for &j in &columns.joints {
        let _ = write!(row, ",{},{}", csv_field(&format!("{}.x", name(j))), csv_field(&format!("{}.y", name(j))));
    }
    if let Some(bar) = columns.angle {
        let _ = write!(row, ",{}", csv_field(&format!("{}-{}.angle", name(bar.pivot), name(bar.tip))));
    }
    if columns.cayley {
        for &[p, q] in &s.complexity.ccv {
            let _ = write!(row, ",{}", csv_field(&format!("{}-{}", name(p), name(q))));
        }
    }
    row.push('\n');
    out.write_all(row.as_bytes())?;
    let mut stepper = Stepper::new(&s.construction, linkage, segments, walk.step).with_budget(walk.max_samples);
    for (i, sample) in stepper.by_ref().enumerate() {
        row.clear();
        let _ = write!(row, "{i},{},{},{}", sample.lambda, sample.ty, u8::from(sample.jump));
        for &j in &columns.joints {
            let p = sample.positions[j];
            let _ = write!(row, ",{},{}", p[0], p[1]);
        }
        if let Some(bar) = columns.angle {
            let _ = write!(row, ",{}", bar.angle(&sample.positions).to_degrees());
        }
        if columns.cayley {
            for d in crate::cayley_vector::cayley_vector(&sample.positions, &s.complexity.ccv) {
                let _ = write!(row, ",{d}");
            }
        }
        row.push('\n');
        out.write_all(row.as_bytes())?;
    }
    Ok(stepper.summary().clone())
}

/// A CSV field as RFC 4180 writes it: quoted, with inner quotes doubled,
/// where it holds a comma, a quote or a line break (a joint named `a,b`).
fn csv_field(text: &str) -> std::borrow::Cow<'_, str> {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\"")).into()
    } else {
        text.into()
    }
}

/// An SVG and what its walk met.
#[derive(Debug, Clone)]
pub struct SvgOut {
    pub text: String,
    pub walk: WalkSummary,
    /// The traces reached [`tolerance::SVG_MAX_POINTS`] points and end there.
    pub points_cut: bool,
}

/// An SVG of the drawn realization with the traces of `joints` over the
/// segments. A trace breaks at every jump. Coordinates are mapped to a
/// 1000-unit view box, so drawings at any scale keep their digits.
pub fn svg(title: &str, linkage: &Linkage, s: &Solved, segments: Vec<Segment>, joints: &[usize], walk: Walk) -> SvgOut {
    // Per joint, runs of points between jumps; a point closer than `gap` to
    // the last one kept is not drawn (it would not show), unless it ends a run.
    let gap = tolerance::SVG_POINT_GAP_FRACTION * extent_of(linkage, Some(s));
    let mut runs: Vec<Vec<Vec<Point2<f64>>>> = vec![vec![Vec::new()]; joints.len()];
    let mut pending: Vec<Option<Point2<f64>>> = vec![None; joints.len()];
    let mut stepper = Stepper::new(&s.construction, linkage, segments, walk.step).with_budget(walk.max_samples);
    let (mut kept, mut points_cut) = (0usize, false);
    for sample in stepper.by_ref() {
        if kept + joints.len() > tolerance::SVG_MAX_POINTS {
            points_cut = true;
            break;
        }
        for (k, &j) in joints.iter().enumerate() {
            let Some(run) = runs[k].last_mut() else { continue };
            if sample.jump {
                run.extend(pending[k].take());
                runs[k].push(Vec::new());
            }
            let Some(run) = runs[k].last_mut() else { continue };
            let p = sample.positions[j];
            match run.last() {
                Some(q) if (p[0] - q[0]).hypot(p[1] - q[1]) < gap => pending[k] = Some(p),
                _ => {
                    run.push(p);
                    kept += 1;
                    pending[k] = None;
                }
            }
        }
    }
    for (run, p) in runs.iter_mut().zip(pending) {
        if let Some(run) = run.last_mut() {
            run.extend(p);
        }
    }
    let pose = s.drawn_positions.clone().unwrap_or_else(|| linkage.drawn_points());
    let (mut x0, mut y0, mut x1, mut y1) = (f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY);
    for p in pose.iter().chain(runs.iter().flatten().flatten()) {
        x0 = x0.min(p[0]);
        y0 = y0.min(p[1]);
        x1 = x1.max(p[0]);
        y1 = y1.max(p[1]);
    }
    // Scene units → view units: the larger side spans 1000 (halved to keep huge drawings finite).
    let span = ((x1 / 2.0 - x0 / 2.0).max(y1 / 2.0 - y0 / 2.0) * 2.0).min(f64::MAX);
    let unit = if span > 0.0 && span.is_finite() { 1000.0 / span } else { 1.0 };
    let pad = 60.0;
    let (w, h) = ((x1 - x0) * unit + 2.0 * pad, (y1 - y0) * unit + 2.0 * pad);
    let (w, h) =
        (if w.is_finite() { w } else { 1000.0 + 2.0 * pad }, if h.is_finite() { h } else { 1000.0 + 2.0 * pad });
    let stroke = 0.004 * w.max(h);
    // y up in the scene, down in SVG.
    let (sx, sy) = (|x: f64| (x - x0) * unit + pad, |y: f64| (y1 - y) * unit + pad);
    let mut o = String::new();
    let _ = writeln!(
        o,
        r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {w:.3} {h:.3}" width="800" height="{:.0}">"#,
        800.0 * h / w
    );
    let _ = writeln!(o, "<title>{} — caymos</title>", xml_escape(title));
    let _ = writeln!(o, "<!-- 1 view unit = {} scene units -->", fmt_num(1.0 / unit));
    let w_sum = stepper.summary().clone();
    let mut notes = present::walk_notes(&w_sum, walk.max_samples);
    if points_cut {
        notes.insert(0, present::svg_cut_note(joints.len()));
    }
    for note in notes {
        let _ = writeln!(o, "<!-- note: {} -->", xml_escape(&note).replace("--", "—"));
    }
    let palette = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf"];
    for (k, joint_runs) in runs.iter().enumerate() {
        for run in joint_runs.iter().filter(|r| !r.is_empty()) {
            let pts: Vec<String> = run.iter().map(|p| format!("{:.3},{:.3}", sx(p[0]), sy(p[1]))).collect();
            let _ = writeln!(
                o,
                r#"<polyline fill="none" stroke="{}" stroke-width="{:.3}" stroke-opacity="0.7" points="{}"/>"#,
                palette[k % palette.len()],
                stroke * 0.6,
                pts.join(" ")
            );
        }
    }
    for bar in &linkage.bars {
        let (p, q) = (pose[bar.joints[0]], pose[bar.joints[1]]);
        let _ = writeln!(
            o,
            r##"<line x1="{:.3}" y1="{:.3}" x2="{:.3}" y2="{:.3}" stroke="#333" stroke-width="{stroke:.3}"/>"##,
            sx(p[0]),
            sy(p[1]),
            sx(q[0]),
            sy(q[1])
        );
    }
    for body in &linkage.bodies {
        let pts: Vec<String> = body.iter().map(|&j| format!("{:.3},{:.3}", sx(pose[j][0]), sy(pose[j][1]))).collect();
        let _ = writeln!(
            o,
            r##"<polygon points="{}" fill="#999" fill-opacity="0.3" stroke="#333" stroke-width="{stroke:.3}"/>"##,
            pts.join(" ")
        );
    }
    for (j, p) in pose.iter().enumerate() {
        let ground = linkage.ground.contains(&j);
        let _ = writeln!(
            o,
            r##"<circle cx="{:.3}" cy="{:.3}" r="{:.3}" fill="{}"/><text x="{:.3}" y="{:.3}" font-size="{:.3}" font-family="sans-serif">{}</text>"##,
            sx(p[0]),
            sy(p[1]),
            stroke * 2.0,
            if ground { "#000" } else { "#fff" },
            sx(p[0]) + stroke * 3.0,
            sy(p[1]) - stroke * 3.0,
            stroke * 8.0,
            xml_escape(&linkage.names[j])
        );
    }
    o.push_str("</svg>\n");
    SvgOut { text: o, walk: w_sum, points_cut }
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

// ---------------------------------------------------------------------------
// sweep

/// `--shard I/N`: this process takes the samples whose index is ≡ I − 1 (mod N).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
pub struct Shard {
    /// I, from 1.
    pub index: usize,
    /// N.
    pub count: usize,
}

impl Shard {
    /// The whole sweep.
    pub const ALL: Shard = Shard { index: 1, count: 1 };

    /// `I/N` with 1 ≤ I ≤ N.
    pub fn parse(text: &str) -> Result<Shard, String> {
        let bad = || format!("--shard {text}: give I/N with 1 ≤ I ≤ N, e.g. --shard 2/8");
        let (i, n) = text.split_once('/').ok_or_else(bad)?;
        let (index, count) =
            (i.trim().parse::<usize>().map_err(|_| bad())?, n.trim().parse::<usize>().map_err(|_| bad())?);
        if index == 0 || count == 0 || index > count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }

    /// Whether sample `i` (from 0) is this shard's.
    pub fn owns(self, i: usize) -> bool {
        i % self.count == self.index - 1
    }
}

/// `--bar A,B` or `--joint C.x` → the parameter, checked against the scene.
pub fn sweep_parameter(scene: &Scene, bar: Option<&str>, joint: Option<&str>) -> Result<Parameter, String> {
    match (bar, joint) {
        (Some(text), None) => find_bar(scene, text, "--bar").map(Parameter::BarLength),
        (None, Some(text)) => {
            let bad = |m: String| format!("--joint {text}: {m}");
            let (name, axis) = text
                .rsplit_once('.')
                .ok_or_else(|| bad("give a joint and a coordinate, e.g. --joint C.x or --joint C.y".into()))?;
            let axis = match axis.trim() {
                "x" => 0,
                "y" => 1,
                other => return Err(bad(format!("no coordinate \"{other}\": use x or y"))),
            };
            let joint = scene
                .joint_index(name.trim())
                .ok_or_else(|| bad(format!("no joint named \"{}\" in {}", name.trim(), scene.source)))?;
            Ok(Parameter::Joint { joint, axis })
        }
        _ => Err("give what to sweep: --bar A,B (a bar's length) or --joint C.x (a joint coordinate)".into()),
    }
}

/// The bar `A,B` (either order) of the scene, by index.
fn find_bar(scene: &Scene, text: &str, flag: &str) -> Result<usize, String> {
    let bad = |m: String| format!("{flag} {text}: {m}");
    let names: Vec<&str> = text.split(',').map(str::trim).collect();
    let [a, b] = names[..] else {
        return Err(bad("give two joint names separated by a comma, e.g. A,B".into()));
    };
    let find = |n: &str| scene.joint_index(n).ok_or_else(|| bad(format!("no joint named \"{n}\" in {}", scene.source)));
    let (a, b) = (find(a)?, find(b)?);
    scene.bar_index(a, b).ok_or_else(|| {
        bad(format!("no bar joins {} and {} in {}", scene.joints[a].name, scene.joints[b].name, scene.source))
    })
}

/// `C,D` after `flag` (`--input-bar`, `--angle`): a bar with exactly one
/// ground joint (the pivot), its angle measured from the line to the first
/// other ground joint.
pub fn input_bar(scene: &Scene, text: &str, flag: &str) -> Result<InputBar, String> {
    InputBar::of_bar(scene, find_bar(scene, text, flag)?).map_err(|why| match why {
        NotInput::GroundLink => format!("{flag} {text}: both joints are ground joints: it is the ground link"),
        NotInput::NoGroundJoint => {
            let names: Vec<&str> = scene.ground.iter().map(|&g| scene.joints[g].name.as_str()).collect();
            format!("{flag} {text}: neither joint is a ground joint (ground: {})", names.join(", "))
        }
        NotInput::NoGroundLine => {
            format!("{flag} {text}: the scene has one ground joint, so no ground line to measure the angle from")
        }
    })
}

/// The range and sample count, checked: finite, from < to, 2 ≤ steps ≤ [`MAX_STEPS`],
/// and a length range above zero.
pub fn check_sweep_range(parameter: Parameter, from: f64, to: f64, steps: usize, naming: Naming) -> Result<(), String> {
    let [f, t, n] = match naming {
        Naming::Flags => ["--from ", "--to ", "--steps "],
        Naming::Words => ["from ", "to ", "steps "],
    };
    if !from.is_finite() || !to.is_finite() {
        return Err(format!("{f}{from} {t}{to}: give finite numbers"));
    }
    if from >= to {
        return Err(format!("{f}{from} must be below {t}{to}"));
    }
    if !(to - from).is_finite() {
        let (a, b) = (present::full(from), present::full(to));
        return Err(format!("{f}{a} {t}{b}: the range is wider than f64 holds"));
    }
    if matches!(parameter, Parameter::BarLength(_)) && from <= 0.0 {
        return Err(format!("{f}{from}: a bar length must be positive"));
    }
    if !(2..=MAX_STEPS).contains(&steps) {
        let split = if naming == Naming::Flags { "; a long sweep can be split with --shard I/N" } else { "" };
        return Err(format!("{n}{steps}: give 2 to {MAX_STEPS} samples (a bounded cost{split})"));
    }
    Ok(())
}

/// How an error names what was given: by its command-line flag, or in words (the TUI's prompt).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Naming {
    Flags,
    Words,
}

/// `caymos sweep --format json`: every sample and every transition of this shard.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct SweepReport {
    /// The scene's name.
    pub scene: String,
    /// What varies, e.g. `A–B` (a bar's length) or `C.x`.
    pub parameter: String,
    pub parameter_kind: ParameterKind,
    pub from: f64,
    pub to: f64,
    /// Samples in the whole sweep (evenly spaced, both ends included).
    pub steps: usize,
    pub shard: Shard,
    /// The input bar `pivot–tip`, if one was given.
    pub input_bar: Option<String>,
    /// This shard's samples, by index.
    pub samples: Vec<SweepSampleOut>,
    /// The transitions in this shard's sample gaps (gap i lies between samples i and i + 1), in order.
    pub transitions: Vec<TransitionOut>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum ParameterKind {
    BarLength,
    JointX,
    JointY,
}

#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct SweepSampleOut {
    /// Sample index, from 0.
    pub index: usize,
    pub value: f64,
    pub class: ClassKind,
    /// Why there is no Cayley space, in words (`null` when solved).
    pub reason: Option<String>,
    /// The non-oriented Cayley space: disjoint λ-intervals.
    pub cayley_space: Vec<[f64; 2]>,
    pub oriented_intervals: usize,
    pub components: Vec<ComponentSizeOut>,
    /// Only the drawn component was computed (a scene above 2^16 types or
    /// whose full sweep is estimated above its budget).
    pub lazy: bool,
    /// Decisions of the analysis resting on a double-double estimate, not a proof.
    pub estimated_decisions: usize,
}

#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct ComponentSizeOut {
    /// Oriented intervals in the component.
    pub intervals: usize,
    /// λ travelled once around it.
    pub lambda_length: f64,
    pub lambda_range: [f64; 2],
    /// Whether the input bar turns fully along it (`null` without `--input-bar`).
    pub input_turn: Option<Turn>,
}

#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct TransitionOut {
    /// Between samples `gap` and `gap + 1`.
    pub gap: usize,
    /// The first float whose structure differs from the one before.
    pub value: f64,
    /// The last float with the structure before.
    pub before: f64,
    /// The first float with the structure after.
    pub after: f64,
    pub changes: Vec<Change>,
    /// The changes in words.
    pub label: String,
    /// Structures met on single floats inside the bracket (non-generic places).
    pub between: Vec<PointOut>,
    /// The bracket reached adjacent floats.
    pub resolved: bool,
    /// A sample in the bracket rests on estimated decisions, not proven ones.
    pub estimated: bool,
}

#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct PointOut {
    pub value: f64,
    /// How it differs from the structure before the transition.
    pub changes: Vec<Change>,
    pub label: String,
    pub components: usize,
    pub branch_points: usize,
    /// Its analysis rests on estimated decisions, not proven ones.
    pub estimated: bool,
}

fn sample_out(index: usize, s: &SweepSample, linkage: &Linkage) -> SweepSampleOut {
    SweepSampleOut {
        index,
        value: s.value,
        class: s.class.kind(),
        reason: present::sweep_reason(&s.class, linkage),
        cayley_space: s.union.clone(),
        oriented_intervals: s.oriented_intervals,
        components: s
            .components
            .iter()
            .map(|c| ComponentSizeOut {
                intervals: c.intervals,
                lambda_length: c.lambda_length,
                lambda_range: c.lambda_range,
                input_turn: c.turn,
            })
            .collect(),
        lazy: s.lazy,
        estimated_decisions: s.estimated,
    }
}

fn transition_out(t: &Transition) -> TransitionOut {
    TransitionOut {
        gap: t.gap,
        value: t.value,
        before: t.before,
        after: t.after,
        changes: t.changes.clone(),
        label: present::sweep_changes(&t.changes),
        between: t
            .between
            .iter()
            .map(|p| PointOut {
                value: p.value,
                changes: p.changes.clone(),
                label: present::sweep_changes(&p.changes),
                components: p.sample.components.len(),
                branch_points: p.sample.structure.branch_points,
                estimated: p.sample.estimated > 0,
            })
            .collect(),
        resolved: t.resolved,
        estimated: t.estimated,
    }
}

/// Sweep `setup` over `steps` evenly spaced values from `from` to `to`
/// (checked by [`check_sweep_range`]), keeping this shard's samples and
/// the transitions in their gaps. Samples and gaps are computed in
/// parallel (rayon: each is an independent analysis).
pub fn sweep(setup: &Setup, from: f64, to: f64, steps: usize, shard: Shard) -> (Vec<SweepSample>, Vec<Transition>) {
    use rayon::prelude::*;
    let own: Vec<usize> = (0..steps).filter(|&i| shard.owns(i)).collect();
    // Every gap's right end too, computed once.
    let mut needed: Vec<usize> = own.iter().flat_map(|&i| [i, i + 1]).filter(|&i| i < steps).collect();
    needed.dedup();
    let samples: Vec<SweepSample> =
        needed.par_iter().map(|&i| sweep::sample(setup, sweep::sample_value(from, to, i, steps))).collect();
    let at = |i: usize| &samples[needed.binary_search(&i).expect("computed")];
    let transitions: Vec<Transition> = own
        .par_iter()
        .filter(|&&i| i + 1 < steps)
        .flat_map_iter(|&i| sweep::locate(setup, i, at(i), at(i + 1)))
        .collect();
    // A sample on a transition's point structure: the brackets either side are one transition.
    let transitions = sweep::join(transitions);
    let kept = own.iter().map(|&i| at(i).clone()).collect();
    (kept, transitions)
}

/// The sweep as a report (this shard's samples and transitions).
pub fn sweep_report(setup: &Setup, from: f64, to: f64, steps: usize, shard: Shard) -> SweepReport {
    let (samples, transitions) = sweep(setup, from, to, steps, shard);
    let linkage = Linkage::from_scene(&setup.scene);
    let scene = &setup.scene;
    let (parameter, parameter_kind) = match setup.parameter {
        Parameter::BarLength(i) => (linkage.pair_name(scene.bars[i].joints), ParameterKind::BarLength),
        Parameter::Joint { joint, axis } => (
            format!("{}.{}", scene.joints[joint].name, if axis == 0 { "x" } else { "y" }),
            if axis == 0 { ParameterKind::JointX } else { ParameterKind::JointY },
        ),
    };
    let indices: Vec<usize> = (0..steps).filter(|&i| shard.owns(i)).collect();
    SweepReport {
        scene: scene.name.clone(),
        parameter,
        parameter_kind,
        from,
        to,
        steps,
        shard,
        input_bar: setup.input.map(|b| linkage.pair_name([b.pivot, b.tip])),
        samples: indices.iter().zip(&samples).map(|(&i, s)| sample_out(i, s, &linkage)).collect(),
        transitions: transitions.iter().map(transition_out).collect(),
    }
}

/// Width of the sweep's text output (a terminal's 80 columns).
const SWEEP_TEXT_WIDTH: usize = 80;

/// `text` if it fits `width`, else its first `keep` items joined and "+N"
/// for the rest (so a cut cell says so).
fn fit_list(items: &[String], width: usize) -> String {
    let all = items.join(",");
    if all.chars().count() <= width {
        return all;
    }
    let mut shown = String::new();
    for (k, item) in items.iter().enumerate() {
        let rest = format!(" +{}", items.len() - k);
        let next = if shown.is_empty() { item.clone() } else { format!("{shown},{item}") };
        if next.chars().count() + format!(" +{}", items.len() - k - 1).len() > width {
            return format!("{shown}{rest}");
        }
        shown = next;
    }
    shown
}

impl SweepReport {
    /// The table of samples, the chart of components over the parameter with
    /// the transitions marked, and the transitions in words (80 columns).
    pub fn to_text(&self) -> String {
        let mut o = String::new();
        let shard = if self.shard.count > 1 {
            format!(", shard {}/{} ({} samples)", self.shard.index, self.shard.count, self.samples.len())
        } else {
            String::new()
        };
        let what = match self.parameter_kind {
            ParameterKind::BarLength => format!("bar {} length", self.parameter),
            _ => format!("joint coordinate {}", self.parameter),
        };
        let _ = writeln!(
            o,
            "Sweep of {what} from {} to {}: {} samples{shard}",
            present::full(self.from),
            present::full(self.to),
            self.steps
        );
        if let Some(bar) = &self.input_bar {
            let _ = writeln!(o, "Input bar {bar}: turns = components along which it turns fully / components");
        }
        if self.samples.iter().any(|s| s.lazy) {
            let _ = writeln!(
                o,
                "Lazy analysis of every sample (the scene as given has more than 2^16 types, or its full sweep is \
                 estimated above its budget): comps counts the component through the drawn realization only"
            );
        }
        let _ = writeln!(o);
        let header = format!(
            "{:>6} {:<11} {:<14} {:>5} {:>4} {:<8} {:<20}{}",
            "#",
            self.parameter,
            "class",
            "comps",
            "ivs",
            "sizes",
            "Cayley space",
            if self.input_bar.is_some() { " turns" } else { "" }
        );
        let _ = writeln!(o, "{}", header.trim_end());
        for s in &self.samples {
            let sizes: Vec<String> = s.components.iter().map(|c| c.intervals.to_string()).collect();
            let pieces: Vec<String> =
                s.cayley_space.iter().map(|[a, b]| format!("[{}, {}]", fmt_num(*a), fmt_num(*b))).collect();
            let turns = if self.input_bar.is_some() {
                let full = s.components.iter().filter(|c| c.input_turn == Some(Turn::Full)).count();
                let unknown = s.components.iter().any(|c| c.input_turn == Some(Turn::Unknown));
                format!(" {full}/{}{}", s.components.len(), if unknown { "?" } else { "" })
            } else {
                String::new()
            };
            let line = format!(
                "{:>6} {:<11} {:<14} {:>5} {:>4} {:<8} {:<20}{turns}",
                s.index,
                fmt_num(s.value),
                present::sweep_class(s.class),
                s.components.len(),
                s.oriented_intervals,
                fit_list(&sizes, 8),
                fit_list(&pieces, 20),
            );
            let _ = writeln!(o, "{}", line.trim_end());
        }
        // Why samples have no Cayley space: each reason once, with where it holds.
        let mut reasons: Vec<(&str, Vec<usize>)> = Vec::new();
        for s in &self.samples {
            if let Some(r) = &s.reason {
                match reasons.iter_mut().find(|(text, _)| text == r) {
                    Some((_, at)) => at.push(s.index),
                    None => reasons.push((r, vec![s.index])),
                }
            }
        }
        for (text, at) in &reasons {
            let first = at[0];
            let more = if at.len() > 1 { format!(" and {} more", at.len() - 1) } else { String::new() };
            let _ = writeln!(o, "  sample {first}{more}: {text}");
        }
        o.push('\n');
        for line in self.chart(SWEEP_TEXT_WIDTH, None) {
            let _ = writeln!(o, "{line}");
        }
        for line in self.transition_lines() {
            let _ = writeln!(o, "{line}");
        }
        let mut wrapped = String::new();
        for line in o.lines() {
            wrapped.push_str(&wrap_line(line, SWEEP_TEXT_WIDTH));
        }
        wrapped
    }

    /// The transitions in words: a heading, then each with its bracket and
    /// the structures met on single floats inside it (unwrapped lines).
    pub fn transition_lines(&self) -> Vec<String> {
        let mut o = vec![String::new()];
        if self.transitions.is_empty() {
            o.push(
                "No transition: the structure is the same at every sample (a change that comes and goes between two samples is not seen; --steps raises the resolution)."
                    .to_string(),
            );
        } else {
            o.push(format!("Transitions ({}), each to adjacent floats:", self.transitions.len()));
        }
        for (k, t) in self.transitions.iter().enumerate() {
            o.push(format!(
                "  {}. {} = {}: {}",
                k + 1,
                self.parameter,
                present::sig(t.value),
                present::sweep_changes(&t.changes)
            ));
            o.push(format!(
                "     bracket [{}, {}] (between samples {} and {}){}{}",
                present::sig(t.before),
                present::sig(t.after),
                t.gap,
                t.gap + 1,
                if t.resolved { "" } else { ", not resolved to adjacent floats" },
                if t.estimated { ", rests on estimated decisions" } else { "" }
            ));
            for p in &t.between {
                let label =
                    if p.changes.is_empty() { "the structure before, again".to_string() } else { p.label.clone() };
                let estimated = if p.estimated { " (on estimated decisions)" } else { "" };
                o.push(format!("     at {} only: {label}{estimated}", present::sig(p.value)));
            }
        }
        o
    }

    /// Components over the parameter in `width` columns: one column per
    /// stretch of the range (the nearest sample's count), transitions marked
    /// by number below, and `now` (the parameter's current value) marked `▲`.
    pub fn chart(&self, width: usize, now: Option<f64>) -> Vec<String> {
        let mut o = Vec::new();
        let Some(max) = self.samples.iter().map(|s| s.components.len()).max() else {
            return o;
        };
        let margin = 6;
        let cols = (width.saturating_sub(margin + 1)).min(self.samples.len().max(2) * 8).max(2);
        let (lo, hi) = (self.from, self.to);
        let col_of =
            |v: f64| (((v - lo) / (hi - lo)) * (cols - 1) as f64).round().clamp(0.0, (cols - 1) as f64) as usize;
        let counts: Vec<Option<(usize, ClassKind)>> = (0..cols)
            .map(|c| {
                let v = lo + (hi - lo) * c as f64 / (cols - 1) as f64;
                let nearest = self.samples.iter().min_by(|a, b| (a.value - v).abs().total_cmp(&(b.value - v).abs()));
                nearest.map(|s| (s.components.len(), s.class))
            })
            .collect();
        let lazy = if self.samples.iter().any(|s| s.lazy) { "; lazy: the drawn one's only" } else { "" };
        o.push(format!("Components over {} (█: that many components{lazy}; x: no Cayley space):", self.parameter));
        for row in (1..=max.max(1)).rev() {
            let line: String = counts
                .iter()
                .map(|c| match c {
                    Some((n, _)) if *n >= row => '█',
                    _ => ' ',
                })
                .collect();
            o.push(format!("{row:>5} |{}", line.trim_end()));
        }
        let bottom: String = counts
            .iter()
            .map(|c| match c {
                Some((_, ClassKind::Solved)) | None => '─',
                Some(_) => 'x',
            })
            .collect();
        o.push(format!("{:>5} +{bottom}", 0));
        let mut marks = vec![' '; cols];
        for (k, t) in self.transitions.iter().enumerate() {
            let c = col_of(t.value);
            marks[c] = if marks[c] == ' ' && k < 9 { char::from_digit(k as u32 + 1, 10).unwrap_or('^') } else { '^' };
        }
        if !self.transitions.is_empty() {
            let line: String = marks.iter().collect();
            o.push(format!("{:>5}  {}", "", line.trim_end()));
        }
        let (a, b) = (fmt_num(lo), fmt_num(hi));
        let pad = (cols + 1).saturating_sub(a.len() + b.len());
        o.push(format!("{:>5}  {a}{}{b}", "", " ".repeat(pad.saturating_sub(1))));
        if let Some(v) = now {
            let here = format!("now {} = {}", self.parameter, present::sig(v));
            if (lo..=hi).contains(&v) {
                // The marker under its column; the words beside it where they fit, else on a line of their own.
                let (c, n) = (col_of(v), here.chars().count());
                let marker = " ".repeat(c);
                if c + 2 + n <= cols {
                    o.push(format!("{:>5}  {marker}▲ {here}", ""));
                } else if n < c {
                    o.push(format!("{:>5}  {}{here} ▲", "", " ".repeat(c - n - 1)));
                } else {
                    o.push(format!("{:>5}  {marker}▲", ""));
                    o.push(format!("{:>5}  {here}", ""));
                }
            } else {
                o.push(format!("{:>5}  {here}: outside the range swept", ""));
            }
        }
        if !self.transitions.is_empty() {
            o.push("       (digits: the transitions listed below, by number)".to_string());
        }
        o
    }
}

/// One line broken at spaces to at most `width` columns (continuations
/// indented), ending in a newline: nothing is cut.
fn wrap_line(line: &str, width: usize) -> String {
    if line.chars().count() <= width {
        return format!("{line}\n");
    }
    let lead = line.len() - line.trim_start().len();
    let mut out = String::new();
    let mut current = line[..lead].to_string();
    let mut start = lead;
    for word in line.trim_start().split(' ') {
        let len = current.chars().count();
        if len > start && len + 1 + word.chars().count() > width {
            out.push_str(current.trim_end());
            out.push('\n');
            current = " ".repeat(lead + 2);
            start = lead + 2;
        } else if len > start {
            current.push(' ');
        }
        current.push_str(word);
    }
    out.push_str(&current);
    out.push('\n');
    out
}
