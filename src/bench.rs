//! `caymos bench`: speed against error, measured. Each method's median time
//! (after a warm-up) and its error against the double-double reference run
//! of the exact method: largest endpoint error, and intervals missed or
//! spurious. Also the motion stepper at several step sizes: time per
//! component against chord error (how far the straight line between two
//! samples strays from the true motion) and bar-length residual.

use std::collections::BTreeMap;
use std::hint::black_box;
use std::sync::Arc;
use std::time::Instant;

use serde::Serialize;

use crate::analysis::{Analysis, Solved, Timings};
use crate::cayley_space::{Method, cayley_space};
use crate::certify::Certifier;
use crate::invert::Inverter;
use crate::lazy::{LazyOptions, component_through, component_through_counted};
use crate::motion::{Stepper, component_segments, realization_at};
use crate::real::{Jet, Real};
use crate::realize::{Construction, RealizationType, bar_residual};
use crate::report::{fmt_num, fmt_sci, write_table};

/// One interval as (type, lower, upper), the common currency of the comparison.
type Span = (RealizationType, f64, f64);

/// A way of computing the Cayley space, as compared by `bench`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum BenchMethod {
    /// Closed-form endpoints (numeric only where the four-cycle test fails).
    Exact,
    /// The numeric root search with `samples` per piece, roots bisected to
    /// `tol` × scale (0: full precision).
    Numeric { samples: usize, tol: f64 },
    /// The classic approach: closed-form candidates classified at midpoints
    /// with the fixed absolute tolerance `tol`.
    Classic { tol: f64 },
    /// The lazy walk of the drawn component only.
    Lazy,
}

impl std::fmt::Display for BenchMethod {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            BenchMethod::Exact => write!(f, "exact (closed form)"),
            BenchMethod::Numeric { samples, tol: 0.0 } => {
                write!(f, "numeric {samples} samples, full precision")
            }
            BenchMethod::Numeric { samples, tol } => write!(f, "numeric {samples} samples, tol {tol:e}"),
            BenchMethod::Classic { tol } => write!(f, "classic (midpoints, abs tol {tol:e})"),
            BenchMethod::Lazy => write!(f, "lazy walk (drawn component only)"),
        }
    }
}

#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct MethodRow {
    pub scene: String,
    pub method: BenchMethod,
    pub median_us: f64,
    pub intervals: usize,
    pub reference_intervals: usize,
    /// Largest endpoint error of matched intervals, relative to the scene scale.
    pub max_endpoint_error: f64,
    pub missed: usize,
    pub spurious: usize,
    /// The certifier's decisions per stage in one run (zero for the
    /// classic method, which proves nothing).
    pub decisions: caymos_core::StageCounts,
}

#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct StepRow {
    pub scene: String,
    /// Step bound as a fraction of the drawing's extent (bounding-box diagonal).
    pub step: f64,
    pub median_us: f64,
    pub samples: usize,
    /// The walk stopped at the sample budget ([`crate::tolerance::DEFAULT_MAX_SAMPLES`]).
    pub truncated: bool,
    /// Jumps met (degenerate passes, see [`crate::motion::Sample::jump`]).
    pub jumps: usize,
    /// Largest chord error relative to the scale.
    pub max_chord_error: f64,
    /// Largest bar-length residual relative to the scale.
    pub max_bar_residual: f64,
}

/// The lazy walk on a generated family member (`caymos bench --scaling`).
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct ScalingRow {
    pub family: String,
    pub steps: usize,
    pub joints: usize,
    /// Intervals in the drawn realization's component.
    pub intervals: usize,
    /// Recognition, base and construction steps.
    pub decompose_ms: f64,
    /// The lazy walk of the drawn component.
    pub lazy_ms: f64,
    /// lazy_ms per step and per interval, in µs: flat when the walk is linear.
    pub us_per_step_interval: f64,
    /// Full-length realization equivalents the walk made per interval
    /// (construction steps realized / (steps · intervals)), counted.
    pub realizations_per_interval: f64,
    /// Slack evaluations per root located by Newton, counted.
    pub newton_evals_per_root: f64,
    /// Largest endpoint error against the ends refined in double-double
    /// (relative; `None` above [`crate::analysis::LAZY_REFERENCE_MAX_STEPS`] steps).
    pub max_endpoint_error: Option<f64>,
    /// The double-double self-check of the walk's ends (median, ms; `None` where skipped).
    pub self_check_ms: Option<f64>,
}

/// The like-for-like figure of one scene: the full analysis (recognition →
/// components, no self-check) against one f64 realization of the drawn type,
/// both medians from the same run.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct AnalysisRow {
    pub scene: String,
    /// Recognition, four-cycle test, constructions, Cayley space (exact) and components.
    pub full_analysis_us: f64,
    /// One full realization of the drawn type at the drawn λ, in f64.
    pub realization_us: f64,
    /// Median time of each phase of the full analysis.
    pub phases_us: BTreeMap<String, f64>,
}

impl AnalysisRow {
    /// The full analysis in realizations-equivalent.
    pub fn realizations(&self) -> f64 {
        self.full_analysis_us / self.realization_us
    }
}

/// A scene that was not benchmarked, and why.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct Skipped {
    pub scene: String,
    pub reason: String,
}

#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct BenchReport {
    pub repeat: usize,
    pub methods: Vec<MethodRow>,
    pub analysis: Vec<AnalysisRow>,
    pub stepping: Vec<StepRow>,
    pub scaling: Vec<ScalingRow>,
    pub skipped: Vec<Skipped>,
}

/// The generated families of the scaling curve: chains of four-cycles and
/// Strandbeests with more legs on one crank.
pub fn scaling_scenes() -> Vec<(String, crate::scene::Scene)> {
    let chains = [10, 30, 100, 300, 1000].map(|n| ("chain".to_string(), crate::generate::chain(n)));
    let beests = [1, 3, 6, 12].map(|n| ("strandbeest".to_string(), crate::generate::strandbeest(n)));
    chains.into_iter().chain(beests).collect()
}

/// Time the lazy walk of the drawn component of one generated scene.
pub fn scaling_row(family: &str, scene: crate::scene::Scene, repeat: usize) -> Option<ScalingRow> {
    let linkage = crate::linkage::Linkage::from_scene(&scene);
    let requested = scene.base.map(|b| b.0);
    let (decompose_us, dec) = median_us(repeat, || crate::decompose::decompose(&linkage, requested));
    let dec = dec.ok()?.ok()?;
    let con = Construction::<f64>::new(&linkage, &dec).ok()?;
    let jet = con.convert::<Jet<f64>>();
    let cert = Certifier::new(&linkage, &dec)?;
    let drawn = crate::realize::drawn_realization(&linkage, &dec);
    let walk =
        |cert: Certifier| component_through_counted(&con, &cert, &jet, &drawn.ty, drawn.lambda, LazyOptions::default());
    let (lazy_us, walked) = median_us_each(repeat, || cert.fork(), walk);
    let (space, counts) = walked.ok()?;
    let checked = (dec.steps.len() <= crate::analysis::LAZY_REFERENCE_MAX_STEPS)
        .then(|| median_us(repeat, || crate::analysis::lazy_reference_accuracy(&linkage, &dec, &mut space.clone())));
    let self_check_ms = checked.as_ref().map(|(us, _)| us / 1e3);
    let max_endpoint_error =
        checked.and_then(|(_, a)| a).map(|a| if a.same_structure { a.max_relative_error } else { f64::INFINITY });
    let n = dec.steps.len();
    Some(ScalingRow {
        family: family.to_string(),
        steps: n,
        joints: linkage.n_joints(),
        intervals: space.intervals.len(),
        decompose_ms: decompose_us / 1e3,
        lazy_ms: lazy_us / 1e3,
        us_per_step_interval: lazy_us / (n * space.intervals.len().max(1)) as f64,
        realizations_per_interval: counts.realizations_per_interval(),
        newton_evals_per_root: counts.newton_evals_per_root(),
        max_endpoint_error,
        self_check_ms,
    })
}

/// The full analysis of a small scene (recognition → components, without
/// the double-double self-check), timed by phase; `None` outside the class
/// or above [`crate::analysis::LAZY_ABOVE_STEPS`] steps (no full analysis there).
pub fn analysis_row(scene: &crate::scene::Scene, repeat: usize) -> Option<AnalysisRow> {
    let linkage = crate::linkage::Linkage::from_scene(scene);
    let requested = scene.base.map(|b| b.0);
    let dec = crate::decompose::decompose(&linkage, requested).ok()?.ok()?;
    if dec.steps.len() > crate::analysis::LAZY_ABOVE_STEPS {
        return None;
    }
    let con = Construction::<f64>::new(&linkage, &dec).ok()?;
    let drawn = crate::realize::drawn_realization(&linkage, &dec);
    // Runs of a few µs: each sample times a batch sized to about 200 µs.
    let batch = |f: &mut dyn FnMut()| {
        let t = Instant::now();
        f();
        let once = t.elapsed().as_secs_f64() * 1e6;
        ((200.0 / once.max(1e-3)) as usize).clamp(1, 100_000)
    };
    let mut realize = || {
        black_box(con.realize(black_box(drawn.lambda), black_box(&drawn.ty)).ok());
    };
    let n_real = batch(&mut realize);
    let mut full = || {
        black_box(full_analysis(black_box(scene), requested));
    };
    let n_full = batch(&mut full);
    let mut real_times = Vec::with_capacity(repeat);
    let mut full_times = Vec::with_capacity(repeat);
    let mut phases: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    // Interleaved, so both medians see the same machine load.
    for _ in 0..repeat.max(1) {
        let t = Instant::now();
        for _ in 0..n_real {
            realize();
        }
        real_times.push(t.elapsed().as_secs_f64() * 1e6 / n_real as f64);
        let t = Instant::now();
        for _ in 0..n_full {
            full();
        }
        full_times.push(t.elapsed().as_secs_f64() * 1e6 / n_full as f64);
        let (_, timings) = full_analysis_phases(scene, requested);
        for (phase, us) in timings.0 {
            phases.entry(phase.to_string()).or_default().push(us);
        }
    }
    Some(AnalysisRow {
        scene: scene.name.clone(),
        full_analysis_us: median(full_times),
        realization_us: median(real_times),
        phases_us: phases.into_iter().map(|(k, v)| (k, median(v))).collect(),
    })
}

/// The phases of [`crate::analysis::analyse_with`] from the scene to the
/// components, without the double-double self-check or the display frame:
/// the like-for-like figure. Returns the component count (to keep the work
/// observable) and each phase's time.
pub fn full_analysis_phases(scene: &crate::scene::Scene, requested: Option<[usize; 2]>) -> (usize, Timings) {
    let mut timings = Timings::default();
    let components = full_analysis_by(scene, requested, &mut timings);
    (components, timings)
}

/// [`full_analysis_phases`] without reading a clock: what `full_analysis_us`
/// times (a dozen clock reads and the phase list are about a tenth of a
/// four-bar's analysis). Returns the component count.
pub fn full_analysis(scene: &crate::scene::Scene, requested: Option<[usize; 2]>) -> usize {
    full_analysis_by(scene, requested, &mut Untimed)
}

/// How [`full_analysis_by`] runs each phase: timed ([`Timings`]) or not.
trait Phases {
    fn phase<R>(&mut self, name: &'static str, f: impl FnOnce() -> R) -> R;
}

impl Phases for Timings {
    fn phase<R>(&mut self, name: &'static str, f: impl FnOnce() -> R) -> R {
        self.time(name, f)
    }
}

/// Phases run without a clock.
struct Untimed;

impl Phases for Untimed {
    fn phase<R>(&mut self, _: &'static str, f: impl FnOnce() -> R) -> R {
        f()
    }
}

/// The one pipeline of [`full_analysis_phases`] and [`full_analysis`].
fn full_analysis_by(scene: &crate::scene::Scene, requested: Option<[usize; 2]>, t: &mut impl Phases) -> usize {
    let linkage = Arc::new(t.phase("linkage", || crate::linkage::Linkage::from_scene(scene)));
    let Ok(Ok(dec)) = t.phase("decompose", || crate::decompose::decompose(&linkage, requested)) else {
        return 0;
    };
    let dec = Arc::new(dec);
    let cx = t.phase("four_cycle", || crate::complexity::four_cycle_test(&dec));
    let built = t.phase("construction", || {
        let con = Arc::new(Construction::<f64>::new(&linkage, &dec).ok()?);
        let cert = Certifier::shared(linkage.clone(), dec.clone(), con.clone())?;
        let drawn = crate::realize::drawn_realization(&linkage, &dec);
        Some((con, cert, drawn))
    });
    let Some((con, cert, _drawn)) = built else { return 0 };
    let space = t.phase("cayley_space", || cayley_space(&con, &cert, &dec, &cx, Method::Exact));
    let comps = t.phase("components", || {
        black_box(crate::cayley_space::union(&space.intervals, linkage.scale));
        crate::motion::components(&space)
    });
    comps.list.len()
}

/// Median wall time of `f` in microseconds over `repeat` runs after one warm-up.
fn median_us<R>(repeat: usize, mut f: impl FnMut() -> R) -> (f64, R) {
    median_us_each(repeat, || (), |()| f())
}

/// [`median_us`] with each run given a fresh value from `setup`, made
/// untimed: a certifier's fork, whose caches start empty in every run as in
/// one analysis (a certifier used before answers its earlier questions from
/// its caches).
fn median_us_each<S, R>(repeat: usize, mut setup: impl FnMut() -> S, mut f: impl FnMut(S) -> R) -> (f64, R) {
    let mut out = f(setup());
    let mut times = Vec::with_capacity(repeat);
    for _ in 0..repeat.max(1) {
        let input = setup();
        let t = Instant::now();
        out = f(input);
        times.push(t.elapsed().as_secs_f64() * 1e6);
    }
    (median(times), out)
}

/// The median of a non-empty list of times (the upper one of an even count).
fn median(mut times: Vec<f64>) -> f64 {
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

/// One run of [`interleaved_medians_us`]: an untimed preparation (as in
/// [`median_us_each`]) that returns the timed work.
type Run<'a> = Box<dyn FnMut() -> Box<dyn FnOnce() + 'a> + 'a>;

/// Each of `runs`' median wall time in microseconds over `repeat` rounds
/// after one warm-up round; each round runs every one in turn.
fn interleaved_medians_us(repeat: usize, runs: &mut [Run<'_>]) -> Vec<f64> {
    for run in runs.iter_mut() {
        run()();
    }
    let mut times = vec![Vec::with_capacity(repeat); runs.len()];
    for _ in 0..repeat.max(1) {
        for (run, times) in runs.iter_mut().zip(&mut times) {
            let work = run();
            let t = Instant::now();
            work();
            times.push(t.elapsed().as_secs_f64() * 1e6);
        }
    }
    times.into_iter().map(median).collect()
}

/// Match each reference interval with the method's interval of the same type
/// that overlaps it with the smallest endpoint error.
pub fn compare(method: &[Span], reference: &[Span], scale: f64) -> (f64, usize, usize) {
    let slack = crate::tolerance::BENCH_MATCH_SLACK * scale;
    let mut used = vec![false; method.len()];
    let (mut worst, mut missed) = (0.0f64, 0usize);
    for (ty, lo, hi) in reference {
        let best = method
            .iter()
            .enumerate()
            .filter(|(i, (t, a, b))| !used[*i] && t == ty && *a <= hi + slack && *b >= lo - slack)
            .map(|(i, (_, a, b))| (i, (a - lo).abs().max((b - hi).abs())))
            .min_by(|x, y| x.1.total_cmp(&y.1));
        match best {
            Some((i, e)) => {
                used[i] = true;
                worst = worst.max(e / scale);
            }
            None => missed += 1,
        }
    }
    (worst, missed, used.iter().filter(|u| !**u).count())
}

fn spans<T: Real>(space: &crate::cayley_space::CayleySpace<T>) -> Vec<Span> {
    space.intervals.iter().map(|i| (i.ty.clone(), i.lower.lambda.to_f64(), i.upper.lambda.to_f64())).collect()
}

/// The classic approach (CayMos, THEORY.md §6): candidate endpoints from the
/// closed form, then each classified by realizing at the midpoints to its
/// neighbours with a fixed absolute tolerance of 1e-4. Only for LCC scenes.
pub fn classic_space(con: &Construction<f64>, s: &Solved) -> Option<Vec<Span>> {
    if !s.complexity.low {
        return None;
    }
    let inv = Inverter::new(con, &s.dec, &s.complexity, None);
    let mut cands: Vec<f64> = Vec::new();
    for (k, st) in con.steps.iter().enumerate() {
        cands.extend(inv.candidates(k, st.r1 + st.r2));
        cands.extend(inv.candidates(k, (st.r1 - st.r2).abs()));
    }
    cands.sort_by(f64::total_cmp);
    cands.dedup();
    let n = con.steps.len();
    if n > 16 {
        return None;
    }
    let realizable =
        |l: f64, ty: &[bool]| con.realize_with_tolerance(l, ty, crate::tolerance::CLASSIC_ABSOLUTE_TOL).is_ok();
    let mut out = Vec::new();
    for code in 0..(1usize << n) {
        let bits: Vec<bool> = (0..n).map(|k| code & (1 << (n - 1 - k)) == 0).collect();
        let mut start: Option<f64> = None;
        for (i, &cur) in cands.iter().enumerate() {
            let before = i.checked_sub(1).map(|j| cands[j]);
            let after = cands.get(i + 1).copied();
            let p = before.is_some_and(|b| realizable((b + cur) / 2.0, &bits));
            let q = after.is_some_and(|a| realizable((cur + a) / 2.0, &bits));
            match (p, q) {
                (false, false) if realizable(cur, &bits) => out.push((RealizationType(bits.clone()), cur, cur)),
                (true, false) => {
                    if let Some(s0) = start.take() {
                        out.push((RealizationType(bits.clone()), s0, cur));
                    }
                }
                (false, true) => start = Some(cur),
                _ => {}
            }
        }
    }
    Some(out)
}

/// Benchmark one analysed scene.
pub fn bench_scene(a: &Analysis, s: &Solved, repeat: usize) -> (Vec<MethodRow>, Vec<StepRow>) {
    let scale = a.linkage.scale;
    let name = a.scene.name.clone();
    let con = &s.construction;
    let jet = con.convert::<Jet<f64>>();
    if s.lazy {
        // Too many types to enumerate: only the lazy walk, against its ends refined in double-double.
        let (t, walked) = median_us_each(
            repeat,
            || s.certifier.fork(),
            |cert| component_through(con, &cert, &jet, &s.drawn.ty, s.drawn.lambda, LazyOptions::default()),
        );
        let n = walked.as_ref().map_or(0, |w| w.intervals.len());
        let cert = s.certifier.fork();
        let _ = component_through(con, &cert, &jet, &s.drawn.ty, s.drawn.lambda, LazyOptions::default());
        let accuracy =
            walked.ok().and_then(|mut w| crate::analysis::lazy_reference_accuracy(&a.linkage, &s.dec, &mut w));
        let row = MethodRow {
            scene: name,
            method: BenchMethod::Lazy,
            median_us: t,
            intervals: n,
            reference_intervals: n,
            max_endpoint_error: accuracy.as_ref().map_or(f64::NAN, |a| a.max_relative_error),
            missed: usize::from(accuracy.is_some_and(|a| !a.same_structure)),
            spurious: 0,
            decisions: cert.stage_counts(),
        };
        return (vec![row], Vec::new());
    }
    let reference = {
        let dd = crate::analysis::reference_space(&a.linkage, &s.dec, &s.complexity, &s.certifier, Method::Exact);
        spans(&dd.expect("shapes close in f64, so in dd"))
    };
    let mut rows = Vec::new();
    let methods: [Method; 4] = [
        Method::Exact,
        Method::Numeric { samples: 32, tol: 0.0 },
        Method::Numeric { samples: 16, tol: 1e-8 },
        Method::Numeric { samples: 8, tol: 1e-4 },
    ];
    let row = |method: BenchMethod, median_us: f64, got: &[Span], decisions| {
        let (max_endpoint_error, missed, spurious) = compare(got, &reference, scale);
        MethodRow {
            scene: name.clone(),
            method,
            median_us,
            intervals: got.len(),
            reference_intervals: reference.len(),
            max_endpoint_error,
            missed,
            spurious,
            decisions,
        }
    };
    // The methods take turns within each repetition, so that every median
    // (and the ratio between two) sees the same machine load.
    // Each run of a method asks a fresh fork of the certifier (see `median_us_each`).
    let space = |cert: &Certifier, method: Method| cayley_space(con, cert, &s.dec, &s.complexity, method);
    let mut runs: Vec<Run> = methods
        .iter()
        .map(|&method| -> Run {
            Box::new(move || {
                let cert = s.certifier.fork();
                Box::new(move || drop(black_box(space(&cert, method))))
            })
        })
        .collect();
    runs.push(Box::new(|| Box::new(|| drop(black_box(classic_space(con, s))))));
    let times = interleaved_medians_us(repeat, &mut runs);
    for (&method, &t) in methods.iter().zip(&times) {
        let label = match method {
            Method::Exact => BenchMethod::Exact,
            Method::Numeric { samples, tol } => BenchMethod::Numeric { samples, tol },
        };
        let cert = s.certifier.fork();
        let got = spans(&space(&cert, method));
        rows.push(row(label, t, &got, cert.stage_counts()));
    }
    if let Some(got) = classic_space(con, s) {
        rows.push(row(
            BenchMethod::Classic { tol: crate::tolerance::CLASSIC_ABSOLUTE_TOL },
            times[methods.len()],
            &got,
            caymos_core::StageCounts::default(),
        ));
    }
    // The lazy walk computes one component: compare it with the reference
    // intervals of the same component (the exhaustive run's drawn component).
    if let (false, Some(k)) = (s.lazy, s.drawn_component) {
        let component: Vec<Span> = s.components.list[k]
            .intervals
            .iter()
            .map(|&i| &s.space.intervals[i])
            .map(|iv| (iv.ty.clone(), iv.lower.lambda, iv.upper.lambda))
            .collect();
        let overlaps = |(t, a, b): &Span, (u, c, d): &Span| t == u && a <= d && c <= b;
        let reference_component: Vec<Span> =
            reference.iter().filter(|r| component.iter().any(|c| overlaps(r, c))).cloned().collect();
        let (t, walked) = median_us_each(
            repeat,
            || s.certifier.fork(),
            |cert| component_through(con, &cert, &jet, &s.drawn.ty, s.drawn.lambda, LazyOptions::default()),
        );
        let cert = s.certifier.fork();
        let _ = component_through(con, &cert, &jet, &s.drawn.ty, s.drawn.lambda, LazyOptions::default());
        if let Ok(walked) = walked {
            let got = spans(&walked);
            let (max_endpoint_error, missed, spurious) = compare(&got, &reference_component, scale);
            rows.push(MethodRow {
                scene: name.clone(),
                method: BenchMethod::Lazy,
                median_us: t,
                intervals: got.len(),
                reference_intervals: reference_component.len(),
                max_endpoint_error,
                missed,
                spurious,
                decisions: cert.stage_counts(),
            });
        }
    }
    let mut steps = Vec::new();
    let extent = crate::commands::drawing_extent(a);
    if let Some(comp) = s.drawn_component.and_then(|k| s.components.list.get(k)) {
        let segs = component_segments(&s.space, comp);
        for frac in [0.1, 0.03, 0.01, 0.003] {
            let bound = frac * extent;
            let walk = || Stepper::new(con, &a.linkage, segs.clone(), bound);
            let (t, _) = median_us(repeat, || walk().count());
            // Errors in a second walk, two samples at a time (memory stays small).
            let mut stepper = walk();
            let (mut chord, mut residual): (f64, f64) = (0.0, 0.0);
            let mut prev: Option<crate::motion::Sample> = None;
            for cur in stepper.by_ref() {
                residual = residual.max(bar_residual(&a.linkage, &cur.positions));
                if let Some(p) = prev.as_ref().filter(|p| p.segment == cur.segment && !cur.jump) {
                    let mid = (p.lambda + cur.lambda) / 2.0;
                    if let Some(truth) = realization_at(con, &a.linkage, &segs[cur.segment], mid) {
                        for ((x, y), t) in p.positions.iter().zip(&cur.positions).zip(&truth) {
                            chord = chord.max(((x[0] + y[0]) / 2.0 - t[0]).hypot((x[1] + y[1]) / 2.0 - t[1]));
                        }
                    }
                }
                prev = Some(cur);
            }
            let summary = stepper.summary();
            steps.push(StepRow {
                scene: name.clone(),
                step: frac,
                median_us: t,
                samples: summary.samples,
                truncated: summary.truncated,
                jumps: summary.jumps.len(),
                max_chord_error: chord / scale,
                max_bar_residual: residual / scale,
            });
        }
    }
    (rows, steps)
}

impl BenchReport {
    pub fn to_text(&self) -> String {
        let mut o = String::new();
        for sk in &self.skipped {
            o.push_str(&format!("Skipped {}: {}\n", sk.scene, sk.reason));
        }
        if self.methods.is_empty() && self.scaling.is_empty() && self.analysis.is_empty() {
            o.push_str("Nothing to benchmark.\n");
            return o;
        }
        if !self.analysis.is_empty() {
            o.push_str(&format!(
                "Full analysis (recognition → components, no self-check) against one f64 realization: median of {} runs\n",
                self.repeat
            ));
            let rows: Vec<[String; 5]> = self
                .analysis
                .iter()
                .map(|r| {
                    let phases: Vec<String> = r.phases_us.iter().map(|(k, v)| format!("{k} {}", fmt_num(*v))).collect();
                    [
                        r.scene.clone(),
                        fmt_num(r.full_analysis_us),
                        fmt_num(r.realization_us),
                        format!("{:.0}", r.realizations()),
                        phases.join(", "),
                    ]
                })
                .collect();
            write_table(&mut o, &["scene", "analysis µs", "realization µs", "realizations", "phases µs"], &rows);
            o.push('\n');
        }
        o.push_str(&format!(
            "Cayley space: median of {} runs; errors against the double-double exact run, relative to scene scale\n",
            self.repeat
        ));
        let rows: Vec<[String; 7]> = self
            .methods
            .iter()
            .map(|r| {
                let d = &r.decisions;
                [
                    r.scene.clone(),
                    r.method.to_string(),
                    fmt_num(r.median_us),
                    fmt_sci(r.max_endpoint_error),
                    format!("{}/{}", r.intervals, r.reference_intervals),
                    format!("{} / {}", r.missed, r.spurious),
                    format!("{}/{}/{}/{}", d.f64, d.double_double, d.exact, d.estimated),
                ]
            })
            .collect();
        let head = ["scene", "method", "time µs", "max error", "intervals", "missed / spurious", "decisions"];
        write_table(&mut o, &head, &rows);
        o.push_str("(decisions: proven in f64 balls / double-double balls / exactly / estimated)\n");
        o.push('\n');
        o.push_str(&self.chart());
        o.push_str(
            "\nMotion stepper on the drawn realization's component (step as a fraction of the drawing's diagonal)\n",
        );
        let rows: Vec<[String; 7]> = self
            .stepping
            .iter()
            .map(|r| {
                [
                    r.scene.clone(),
                    fmt_num(r.step),
                    fmt_num(r.median_us),
                    format!("{}{}", r.samples, if r.truncated { " (budget)" } else { "" }),
                    r.jumps.to_string(),
                    fmt_sci(r.max_chord_error),
                    fmt_sci(r.max_bar_residual),
                ]
            })
            .collect();
        write_table(&mut o, &["scene", "step", "time µs", "samples", "jumps", "chord error", "bar residual"], &rows);
        if !self.scaling.is_empty() {
            o.push_str("\nLazy walk of the drawn component on generated families (median times)\n");
            let rows: Vec<[String; 11]> = self
                .scaling
                .iter()
                .map(|r| {
                    [
                        r.family.clone(),
                        r.steps.to_string(),
                        r.joints.to_string(),
                        r.intervals.to_string(),
                        fmt_num(r.decompose_ms),
                        fmt_num(r.lazy_ms),
                        fmt_num(r.us_per_step_interval),
                        format!("{:.1}", r.realizations_per_interval),
                        format!("{:.1}", r.newton_evals_per_root),
                        r.max_endpoint_error.map_or("-".into(), fmt_sci),
                        r.self_check_ms.map_or("-".into(), fmt_num),
                    ]
                })
                .collect();
            let head = [
                "family",
                "steps",
                "joints",
                "intervals",
                "decompose ms",
                "lazy ms",
                "µs/(step·interval)",
                "realizations/interval",
                "Newton evals/root",
                "error",
                "self-check ms",
            ];
            write_table(&mut o, &head, &rows);
        }
        o
    }

    /// A log-log text chart of time (x) against error (y), one letter per method.
    fn chart(&self) -> String {
        const W: usize = 56;
        const H: usize = 12;
        let mut names: Vec<BenchMethod> = Vec::new();
        for r in &self.methods {
            if !names.contains(&r.method) {
                names.push(r.method);
            }
        }
        let floor = 1e-17;
        let pts: Vec<(f64, f64, usize)> = self
            .methods
            .iter()
            .map(|r| {
                let err = if r.missed + r.spurious > 0 { r.max_endpoint_error.max(1.0) } else { r.max_endpoint_error };
                let m = names.iter().position(|n| *n == r.method).unwrap_or(0);
                (r.median_us.max(1e-3).log10(), err.max(floor).log10(), m)
            })
            .collect();
        if pts.is_empty() {
            return String::new();
        }
        let (x0, x1) = pts.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |a, p| (a.0.min(p.0), a.1.max(p.0)));
        let (y0, y1) = (floor.log10(), 0.5);
        let mut grid = vec![vec![' '; W]; H];
        for &(x, y, m) in &pts {
            let c = if x1 > x0 { ((x - x0) / (x1 - x0) * (W - 1) as f64).round() as usize } else { W / 2 };
            let r = ((y1 - y) / (y1 - y0) * (H - 1) as f64).round().clamp(0.0, (H - 1) as f64) as usize;
            grid[r][c.min(W - 1)] = (b'a' + m as u8) as char;
        }
        let mut o = String::from("  error (log) ↑; rows from ≥1 (wrong intervals) down to 1e-17\n");
        for row in grid {
            o.push_str("  |");
            o.push_str(&row.into_iter().collect::<String>());
            o.push('\n');
        }
        o.push_str(&format!("  +{}→ time, {:.0} µs … {:.0} µs (log)\n", "-".repeat(W), 10f64.powf(x0), 10f64.powf(x1)));
        for (i, n) in names.iter().enumerate() {
            o.push_str(&format!("  {} {n}\n", (b'a' + i as u8) as char));
        }
        o
    }
}
