//! The terminal UI's state and its update: actions in, new state out. No
//! terminal here, so every behaviour is testable with a list of key presses.
//! Everything the drawing shows is computed here, after each update and tick
//! ([`Model::sync`]); the view only reads.

use std::path::PathBuf;

use nalgebra::{Rotation3, Vector3};

use crate::analysis::{Analysis, Solved, analyse, nearest_attainable};
use crate::cayley_vector::cayley_vector;
use crate::commands::{self, PathReport, SweepReport, Walk};
use crate::motion::{Segment, Stepper, arcs, component_segments, locate, realization_at};
use crate::numfmt::fmt_sig;
use crate::realize::{Point2, Realization, RealizationType};
use crate::report::fmt_num;
use crate::scene::Scene;
use crate::sweep::{InputBar, Setup, wrap_angle};
use crate::tolerance;

use super::document::Document;
use super::edit::Editor;
use super::keymap::{Action, Mode};
use super::sweep::{SweepView, Swept};

/// What the main area shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    Linkage,
    CayleyCurve,
}

/// What stepping follows: a whole component (a cycle) or one path from A to B.
/// Indices are 0-based here; the view shows them 1-based.
#[derive(Clone, Debug, PartialEq)]
pub enum Motion {
    Component(usize),
    Path { arc: usize },
}

/// A marked realization.
#[derive(Clone, Debug, PartialEq)]
pub struct Mark {
    pub at: Realization,
    pub component: usize,
}

/// Where we are: the motion followed, the point on it and its realization.
#[derive(Clone, Debug)]
pub struct Cursor {
    pub motion: Motion,
    /// The component the current realization lies in (0-based).
    pub component: usize,
    /// Segments of the current motion, and where we are on them.
    pub segments: Vec<Segment>,
    pub seg: usize,
    pub lambda: f64,
    /// The current realization, display frame.
    pub positions: Vec<Point2<f64>>,
    /// Its complete Cayley vector (kept with `positions`).
    pub cayley: Vec<f64>,
    /// Bumped whenever `segments` change, so the samples know they are stale.
    generation: u64,
}

/// How far a step goes, and whether the motion plays.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pace {
    /// Geometric step (largest joint move per small step), scene units.
    pub step: f64,
    /// The drawing's extent (bounding-box diagonal): the unit of steps.
    pub extent: f64,
    pub playing: bool,
}

/// Marks A and B, and what joins them.
#[derive(Clone, Debug, Default)]
pub struct Marks {
    pub slots: [Option<Mark>; 2],
    pub path: Option<PathReport>,
    /// Arc segments of the path A→B (when in one component).
    pub arcs: Option<[Vec<Segment>; 2]>,
}

/// The angle drive: with an input bar chosen, steps, play and `g 90°` go
/// by degrees of that bar (measured from the ground line, as `trace --angle`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Drive {
    pub input: Option<InputBar>,
    /// Degrees per step.
    pub step: f64,
}

/// The bars that can drive, in file order ([`InputBar::of_bar`], as `--angle`).
pub fn input_bars(scene: &Scene) -> Vec<InputBar> {
    (0..scene.bars.len()).filter_map(|b| InputBar::of_bar(scene, b).ok()).collect()
}

/// Whether the turn from `a` to `b` reaches `t` (past `a`, up to and including `b`).
fn crosses(a: f64, b: f64, t: f64) -> bool {
    a != t && (a - t) * (b - t) <= 0.0
}

/// Where a scan of the input angle found its target.
struct AngleHit {
    /// Index into the cursor's segments, λ and the realization there.
    seg: usize,
    lambda: f64,
    positions: Vec<Point2<f64>>,
    /// Degrees the bar turned on the way, back and forth (radians).
    travel: f64,
    /// Reached across a jump (a degenerate pass): not bisected.
    jump: bool,
}

/// Why a scan found no target: how far the bar turned (radians from here, unwrapped) and where the walk ended.
struct AngleMiss {
    lo: f64,
    hi: f64,
    stopped_at: Option<f64>,
}

/// Which joints leave traces.
#[derive(Clone, Debug, PartialEq)]
pub struct Traces {
    pub on: bool,
    pub traced: Vec<bool>,
    pub selected: usize,
}

/// The Cayley curve's camera: three Cayley-vector entries as axes, turned
/// by `yaw` about the vertical axis, then tilted by `pitch`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub yaw: f64,
    pub pitch: f64,
    /// Indices into the complete Cayley vector used as the curve's axes.
    pub axes: [usize; 3],
}

/// How far `r`/`R` turn and `e`/`E` tilt, in radians, and the largest tilt.
pub const CAMERA_TURN: f64 = 0.15;
pub const CAMERA_MAX_PITCH: f64 = 1.5;

impl Camera {
    /// The rotation: yaw about the vertical (y) axis, then pitch about x.
    pub fn rotation(&self) -> Rotation3<f64> {
        Rotation3::from_axis_angle(&Vector3::x_axis(), self.pitch)
            * Rotation3::from_axis_angle(&Vector3::y_axis(), self.yaw)
    }

    /// The next triple of axes in lexicographic order (out of `n` entries); unchanged for n ≤ 3.
    fn next_axes(&mut self, n: usize) {
        if n <= 3 {
            return;
        }
        let mut t = self.axes;
        t[2] += 1;
        if t[2] >= n {
            t[1] += 1;
            if t[1] >= n - 1 {
                t[0] = (t[0] + 1) % (n - 2);
                t[1] = t[0] + 1;
            }
            t[2] = t[1] + 1;
        }
        self.axes = t;
    }
}

/// Samples of the current motion: positions and Cayley vectors.
#[derive(Clone, Debug, Default)]
pub struct MotionSamples {
    pub generation: u64,
    pub positions: Vec<Vec<Point2<f64>>>,
    pub cayley: Vec<Vec<f64>>,
    pub types: Vec<RealizationType>,
    /// Whether each sample is reached by a jump (drawn lines break there).
    pub jumps: Vec<bool>,
    /// The motion was longer than the sample budget: only its start is shown.
    pub truncated: bool,
}

/// The Cayley curve, projected: runs of one type (index into the types
/// met, for colour) not crossing a jump, and the current point.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Curve {
    pub runs: Vec<(usize, Vec<(f64, f64)>)>,
    pub here: (f64, f64),
    /// The samples' range on each axis, which scales it to [-1, 1].
    pub range: AxisRange,
}

/// Per axis, the smallest and largest value.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AxisRange {
    pub lo: Vector3<f64>,
    pub hi: Vector3<f64>,
}

/// What the drawing reads, derived from the state by [`Model::sync`].
#[derive(Clone, Debug, Default)]
pub struct Picture {
    /// Joints' bounding box over the current component's motion, for a steady view.
    pub bounds: [f64; 4],
    pub samples: MotionSamples,
    /// Each traced joint's path over the samples, in the unit frame of
    /// `bounds` (see [`unit_frame`]) where finite, when traces are on.
    pub traces: Vec<(usize, Vec<(f64, f64)>)>,
    pub curve: Curve,
    /// The curve stands for mirror pairs (every cluster is symmetric).
    pub mirror: bool,
    /// What the traces and curve were made from, to redo them only when it changes.
    made_from: Option<(u64, Camera, Traces)>,
}

/// The state of an analysed scene in the UI.
pub struct Model {
    /// The one analysis: its outcome is the solved scene (see [`Model::solved`]),
    /// extended in place when a lazy analysis walks more components.
    analysis: Analysis,
    pub cursor: Cursor,
    pub pace: Pace,
    pub marks: Marks,
    pub traces: Traces,
    pub camera: Camera,
    pub view: View,
    pub picture: Picture,
    pub drive: Drive,
    /// How far the side lists (Cayley vector, intervals) are scrolled from where they would stand.
    pub scroll: isize,
}

/// The whole UI state.
pub enum Screen {
    /// Analysis running in the background.
    Loading {
        scene: String,
    },
    /// The scene cannot be analysed, or is outside the class: say why.
    Failed {
        scene: String,
        message: String,
    },
    /// In the class, but with no realization to explore: the drawing, and why.
    Empty {
        analysis: Box<Analysis>,
        why: String,
    },
    /// Outside the handled class (2-dof, rigid, not tree-decomposable): the drawing, and why.
    Outside {
        analysis: Box<Analysis>,
        why: String,
    },
    Ready(Box<Model>),
}

/// What a line of typed input is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PromptKind {
    /// `g`: a λ or `TYPE@λ`.
    GoTo,
    /// `/`: a joint or bar name.
    Select,
    /// `=`: the selected joint's `x, y` or bar's length.
    Value,
    /// `s`: the range to sweep.
    Sweep(Swept),
    /// `A`: three Cayley-vector entries for the curve's axes.
    Axes,
}

/// A line of input being typed.
#[derive(Clone, Debug, PartialEq)]
pub struct Prompt {
    pub kind: PromptKind,
    pub text: String,
}

/// Work for the solver thread (or run inline in tests): an analysis or a
/// sweep. Of each kind the latest asked for wins; older results are dropped.
pub struct Job {
    id: u64,
    work: Work,
}

enum Work {
    Analyse { scene: Scene, base: Option<[usize; 2]> },
    Sweep { setup: Box<Setup>, from: f64, to: f64, steps: usize },
}

/// A finished [`Job`].
pub struct Done {
    id: u64,
    result: Finished,
}

enum Finished {
    Analysis {
        result: Result<Box<Analysis>, String>,
        /// The minimal complete Cayley vector's entries (the curve's default axes), made here off the UI thread.
        minimal: Option<Vec<usize>>,
    },
    Sweep(Box<SweepReport>),
}

impl Job {
    /// A sweep of `setup` (see [`super::sweep`]).
    pub fn sweep(id: u64, setup: Setup, from: f64, to: f64, steps: usize) -> Job {
        Job { id, work: Work::Sweep { setup: Box::new(setup), from, to, steps } }
    }

    /// Whether it is a sweep (sweeps run on a thread of their own).
    pub fn is_sweep(&self) -> bool {
        matches!(self.work, Work::Sweep { .. })
    }

    /// Analyse (errors in words), or sweep.
    pub fn run(self) -> Done {
        let result = match self.work {
            Work::Analyse { scene, base } => {
                let result = analyse(scene, base).map(Box::new).map_err(|e| e.to_string());
                let minimal = result.as_ref().ok().and_then(|a| a.outcome.as_ref().ok()).map(minimal_entries);
                Finished::Analysis { result, minimal }
            }
            Work::Sweep { setup, from, to, steps } => {
                Finished::Sweep(Box::new(super::sweep::run(&setup, from, to, steps)))
            }
        };
        Done { id: self.id, result }
    }
}

/// What the exploration was at, carried over to the next analysis of the scene (an edit, a reload).
#[derive(Clone, Debug)]
pub struct Carry {
    pub at: Realization,
    pub view: View,
    pub camera: Camera,
    pub traces: Traces,
    pub step: f64,
    pub drive: Drive,
}

pub struct App {
    pub screen: Screen,
    pub help: bool,
    /// A line of input being typed (after `g`, `/` or `=`).
    pub input: Option<Prompt>,
    /// A one-line message for the status bar (results, errors).
    pub message: Option<String>,
    pub quit: bool,
    /// The scene as text: what edits change, save writes and reload reads.
    pub doc: Document,
    pub editor: Editor,
    /// Why the scene file, changed on disk, was not taken; shown until it parses.
    pub file_error: Option<String>,
    /// Where a scene with no file is saved (the current directory).
    pub save_dir: PathBuf,
    pub(super) base: Option<[usize; 2]>,
    /// The sweep shown in place of the drawing (`s`), if one was asked for.
    pub sweep: Option<SweepView>,
    /// The sweep asked for and not yet handed out, and how many were asked for (each sweep's id).
    pub(super) sweep_job: Option<Job>,
    pub(super) sweeps_asked: u64,
    /// The analysis asked for and not yet handed out, and the ids asked and installed.
    job: Option<Job>,
    asked: u64,
    installed: u64,
    /// The exploration to restore when the next analysis can be explored.
    carry: Option<Carry>,
    /// The next analysis starts at the drawn realization (a new base: its
    /// (type, λ) name other realizations).
    fresh_start: bool,
}

impl App {
    /// An app on `scene`, its analysis asked for (see [`App::take_job`]).
    pub fn new(scene: Scene, base: Option<[usize; 2]>) -> App {
        let mut app = App::blank(&scene, base);
        app.reanalyse();
        app
    }

    fn blank(scene: &Scene, base: Option<[usize; 2]>) -> App {
        let doc = Document::of(scene);
        App {
            screen: Screen::Loading { scene: scene.name.clone() },
            help: false,
            input: None,
            message: None,
            quit: false,
            editor: Editor::new(&doc.scene),
            doc,
            file_error: None,
            save_dir: PathBuf::from("."),
            base,
            sweep: None,
            sweep_job: None,
            sweeps_asked: 0,
            job: None,
            asked: 0,
            installed: 0,
            carry: None,
            fresh_start: false,
        }
    }

    /// An app on an analysis already made.
    pub fn ready(analysis: Analysis) -> App {
        let mut app = App::blank(&analysis.scene, None);
        app.install(Ok(analysis), None);
        app
    }

    /// Ask for an analysis of the document's scene.
    pub(super) fn reanalyse(&mut self) {
        self.asked += 1;
        let work = Work::Analyse { scene: self.doc.scene.clone(), base: self.base };
        self.job = Some(Job { id: self.asked, work });
        self.resweep();
    }

    /// The work to run next (the analysis first, then the sweep), if any was asked for since the last call.
    pub fn take_job(&mut self) -> Option<Job> {
        self.job.take().or_else(|| self.sweep_job.take())
    }

    /// Whether an analysis or sweep asked for has not arrived yet.
    pub fn busy(&self) -> bool {
        self.installed != self.asked || self.sweeping()
    }

    /// Take a finished analysis or sweep, unless a newer one was asked for since.
    pub fn finish(&mut self, done: Done) {
        match done.result {
            Finished::Analysis { result, minimal } if done.id == self.asked => {
                self.installed = done.id;
                self.install(result.map(|a| *a), minimal);
            }
            Finished::Analysis { .. } => {}
            Finished::Sweep(report) => self.install_sweep(done.id, *report),
        }
    }

    /// Show an analysis (moved in, never copied); an explorable one keeps
    /// the cursor on the nearest realization to the one before.
    fn install(&mut self, analysis: Result<Analysis, String>, minimal: Option<Vec<usize>>) {
        let before = std::mem::replace(&mut self.screen, Screen::Loading { scene: String::new() });
        if let Screen::Ready(m) = &before {
            self.carry = (!self.fresh_start).then(|| m.carry());
        }
        self.fresh_start = false;
        drop(before);
        self.screen = match analysis {
            Err(message) => Screen::Failed { scene: self.doc.scene.name.clone(), message },
            Ok(a) => match &a.outcome {
                Err(outside) => {
                    let why = format!("outside the handled class: {}", crate::present::outside(outside, &a.linkage));
                    Screen::Outside { analysis: Box::new(a), why }
                }
                Ok(solved) => match commands::require_component(&a.linkage, solved).err() {
                    Some(why) => Screen::Empty { analysis: Box::new(a), why },
                    None => Screen::Ready(Box::new(Model::new(a, minimal))),
                },
            },
        };
        if let (Screen::Ready(m), Some(c)) = (&mut self.screen, self.carry.take()) {
            if let Some(note) = m.carry_from(&c) {
                self.message = Some(note);
            }
            m.sync();
        }
    }

    /// Which keys apply: editing or exploring.
    pub fn mode(&self) -> Mode {
        if self.editor.on { Mode::Edit } else { Mode::Explore }
    }

    pub fn model(&self) -> Option<&Model> {
        match &self.screen {
            Screen::Ready(m) => Some(m),
            _ => None,
        }
    }

    /// Apply one action.
    pub fn update(&mut self, action: Action) {
        if action == Action::Quit {
            self.quit = true;
            return;
        }
        if action == Action::Help {
            self.help = !self.help;
            return;
        }
        if self.help && matches!(action, Action::FollowComponent | Action::ExitEdit) {
            self.help = false;
            return;
        }
        if self.edit_update(action) || self.sweep_update(action) {
            return;
        }
        let Screen::Ready(m) = &mut self.screen else { return };
        self.message = None;
        match action {
            Action::GoTo => self.input = Some(Prompt { kind: PromptKind::GoTo, text: String::new() }),
            Action::NameAxes => {
                let l = &m.analysis().linkage;
                let ccv = &m.solved().complexity.ccv;
                let names: Vec<String> =
                    m.camera.axes.iter().filter_map(|&k| ccv.get(k)).map(|&p| l.pair_name(p)).collect();
                self.input = Some(Prompt { kind: PromptKind::Axes, text: names.join(" ") });
            }
            Action::NextBase => {
                // Every valid base in one fixed order (by joint index), so `B` cycles through them all.
                let (l, dec) = (&m.analysis().linkage, &m.solved().dec);
                let sorted = |[p, q]: [usize; 2]| [p.min(q), p.max(q)];
                let mut bases: Vec<[usize; 2]> = dec.other_bases(l).into_iter().map(sorted).collect();
                bases.push(sorted(dec.base));
                bases.sort_unstable();
                bases.dedup();
                let here = bases.iter().position(|&b| b == sorted(dec.base)).unwrap_or(0);
                let next = bases[(here + 1) % bases.len()];
                self.message = Some(if bases.len() == 1 {
                    format!("{} is the only valid base non-edge", l.pair_name(next))
                } else {
                    format!(
                        "base {} (the realization space is the same; λ and types are of the new base: at the drawn realization)",
                        l.pair_name(next)
                    )
                });
                if bases.len() > 1 {
                    self.base = Some(next);
                    // A (type, λ) of one base names nothing on another: start at the drawn realization.
                    self.fresh_start = true;
                    self.reanalyse();
                }
                return;
            }
            Action::Export => {
                self.message = Some(match super::export::export(m, self.doc.stem(), &self.save_dir) {
                    Ok(e) => {
                        let mut note = format!(
                            "exported the trace ({} rows) to {} and the drawing to {}",
                            e.rows,
                            e.csv.display(),
                            e.svg.display()
                        );
                        for n in &e.notes {
                            note.push_str("; ");
                            note.push_str(n);
                        }
                        note
                    }
                    Err(e) => e,
                })
            }
            other => match m.apply(other) {
                Err(e) => self.message = Some(e),
                Ok(Some(note)) => self.message = Some(note),
                Ok(None) => self.message = m.note_for(other),
            },
        }
        m.sync();
        if action == Action::NextInputBar {
            self.resweep(); // the sweep counts the full turns of the input bar
        }
    }

    /// A character typed while a prompt is open; Enter applies it.
    pub fn type_char(&mut self, c: char) {
        if let Some(p) = &mut self.input {
            p.text.push(c);
        }
    }
    pub fn backspace(&mut self) {
        if let Some(p) = &mut self.input {
            p.text.pop();
        }
    }
    pub fn cancel_input(&mut self) {
        self.input = None;
    }
    pub fn submit_input(&mut self) {
        let Some(Prompt { kind, text }) = self.input.take() else { return };
        let text = text.trim();
        match kind {
            PromptKind::GoTo => {
                if let Screen::Ready(m) = &mut self.screen {
                    self.message = m.go_to(text).err();
                    m.sync();
                }
            }
            PromptKind::Select => {
                if let Err(e) = self.select_named(text) {
                    self.message = Some(e);
                }
            }
            PromptKind::Value => {
                self.message = match self.set_value(text) {
                    Ok(note) => note,
                    Err(e) => Some(e),
                }
            }
            PromptKind::Sweep(swept) => self.message = self.submit_sweep(swept, text).err(),
            PromptKind::Axes => {
                if let Screen::Ready(m) = &mut self.screen {
                    self.message = m.name_axes(text).err();
                    m.sync();
                }
            }
        }
    }

    /// One animation frame.
    pub fn tick(&mut self) {
        if let Screen::Ready(m) = &mut self.screen
            && m.pace.playing
        {
            match m.advance(1, 1.0) {
                Ok(None) => {}
                Ok(Some(note)) => self.message = Some(note),
                Err(_) => m.pace.playing = false,
            }
            m.sync();
        }
    }

    pub fn animating(&self) -> bool {
        self.model().is_some_and(|m| m.pace.playing)
    }
}

/// A closest pair's distance in words: the significant digits its
/// certificate vouches for (one past the relative gap), and whether it is certified.
fn closest_words(c: &commands::ClosestOut) -> String {
    let gap = if c.relative_gap > 0.0 { c.relative_gap } else { c.requested_gap };
    let digits = (-gap.log10()).ceil();
    let digits = if digits.is_finite() { (digits as usize + 1).clamp(3, 17) } else { 17 };
    let status = if c.mirror_images {
        "exactly 0: mirror images".to_string()
    } else if c.certified {
        "certified".to_string()
    } else {
        format!("not certified (proven in [{}, {}])", fmt_sig(c.lower_bound, 6), fmt_sig(c.upper_bound, 6))
    };
    format!("Cayley distance {} · {status}", fmt_sig(c.distance, digits))
}

/// The solved scene of an analysis a [`Model`] was made from.
fn solved_of(a: &Analysis) -> &Solved {
    match &a.outcome {
        Ok(s) => s,
        Err(_) => unreachable!("a Model is made only from a solved analysis (App::loaded)"),
    }
}

fn solved_of_mut(a: &mut Analysis) -> &mut Solved {
    match &mut a.outcome {
        Ok(s) => s,
        Err(_) => unreachable!("a Model is made only from a solved analysis (App::loaded)"),
    }
}

impl Model {
    /// A model on a solved analysis with at least one component (see [`App::loaded`]).
    /// `minimal`: the minimal complete Cayley vector's entries, when already made (else made here).
    fn new(analysis: Analysis, minimal: Option<Vec<usize>>) -> Model {
        let solved = solved_of(&analysis);
        let n = analysis.linkage.n_joints();
        let extent = commands::drawing_extent(&analysis);
        let traced = vec![false; n];
        // Until a realization is computed: the drawn one (never empty).
        let positions = solved.drawn_positions.clone().unwrap_or_else(|| analysis.linkage.drawn_points());
        let ccv_len = solved.complexity.ccv.len();
        let cayley = cayley_vector(&positions, &solved.complexity.ccv);
        let minimal = minimal.unwrap_or_else(|| minimal_entries(solved));
        let axes = default_axes(&minimal, ccv_len);
        let picture = Picture { mirror: solved.mirrors.exist(), ..Picture::default() };
        let mut m = Model {
            cursor: Cursor {
                motion: Motion::Component(0),
                component: 0,
                segments: Vec::new(),
                seg: 0,
                lambda: 0.0,
                positions,
                cayley,
                generation: 0,
            },
            pace: Pace { step: tolerance::TUI_STEP_FRACTION * extent, extent, playing: false },
            marks: Marks::default(),
            traces: Traces { on: true, traced, selected: n.saturating_sub(1) },
            camera: Camera { yaw: 0.6, pitch: 0.35, axes },
            view: View::Linkage,
            picture,
            drive: Drive { input: None, step: tolerance::TUI_ANGLE_STEP_DEGREES },
            analysis,
            scroll: 0,
        };
        m.reset();
        // Trace the joint that moves farthest (a ground pivot's trace is a dot).
        let j = m.farthest_mover();
        m.traces.traced[j] = true;
        m.traces.selected = j;
        m.sync();
        m
    }

    /// The analysis explored (scene, linkage, warnings; its outcome is [`Self::solved`]).
    pub fn analysis(&self) -> &Analysis {
        &self.analysis
    }

    /// The solved scene: the one value the commands take too.
    pub fn solved(&self) -> &Solved {
        solved_of(&self.analysis)
    }

    pub fn n_components(&self) -> usize {
        self.solved().components.list.len()
    }

    /// Current realization as type and λ.
    pub fn current(&self) -> Realization {
        let c = &self.cursor;
        Realization { ty: c.segments[c.seg].ty.clone(), lambda: c.lambda }
    }

    /// Steps flat at the current point (when exactly on an interval endpoint).
    pub fn flat_here(&self) -> &[usize] {
        let c = &self.cursor;
        let s = &c.segments[c.seg];
        if c.lambda == s.to {
            &s.flat_to
        } else if c.lambda == s.from {
            &s.flat_from
        } else {
            &[]
        }
    }

    /// At a branch point (several steps flat at once: a non-generic place,
    /// see [`crate::motion::BranchPoint`]) the oriented intervals that meet
    /// there ([`crate::motion::ways_at`]), the current one included; empty anywhere else.
    pub fn branch_here(&self) -> Vec<usize> {
        let c = &self.cursor;
        let seg = &c.segments[c.seg];
        if c.lambda != seg.from && c.lambda != seg.to {
            return Vec::new();
        }
        crate::motion::ways_at(&solved_of(&self.analysis).components, c.lambda, seg.interval)
    }

    /// Go on at a branch point by the next way (in interval order, round),
    /// into the component that holds it; says which way and which key goes along it.
    fn take_branch(&mut self) -> Result<String, String> {
        let ways = self.branch_here();
        if ways.len() < 2 {
            return Err("not at a branch point: f chooses the way on where several steps are flat at once".into());
        }
        let here = self.cursor.segments[self.cursor.seg].interval;
        let k = ways.iter().position(|&i| i == here).map_or(0, |p| (p + 1) % ways.len());
        let (way, lambda) = (ways[k], self.cursor.lambda);
        let flat: Vec<String> = self.flat_here().iter().map(|s| (s + 1).to_string()).collect();
        let component = solved_of(&self.analysis).components.of_interval[way];
        self.enter_component(component, Some((way, lambda)));
        let seg = &self.cursor.segments[self.cursor.seg];
        let along = if seg.from == lambda { "→" } else { "←" };
        Ok(format!(
            "branch point λ = {} (steps {} flat): way {} of {}, type {} in component {}; {along} goes along it",
            crate::present::sig(lambda),
            flat.join(", "),
            k + 1,
            ways.len(),
            seg.ty,
            component + 1
        ))
    }

    /// What to carry over to the next analysis of the scene.
    fn carry(&self) -> Carry {
        Carry {
            at: self.current(),
            view: self.view,
            camera: self.camera,
            traces: self.traces.clone(),
            step: self.pace.step,
            drive: self.drive,
        }
    }

    /// Take over the exploration `c` was at: the view, camera, traces and
    /// step where they still fit, and the realization of the same type at
    /// the nearest λ (a lazy analysis walks its component first). When no
    /// interval of that type is left the cursor stays at the drawn one and
    /// the note says the realization vanished; a note also says when λ moved.
    fn carry_from(&mut self, c: &Carry) -> Option<String> {
        self.view = c.view;
        let n_ccv = self.solved().complexity.ccv.len();
        if c.camera.axes.iter().all(|&a| a < n_ccv) {
            self.camera = c.camera;
        }
        if c.traces.traced.len() == self.traces.traced.len() {
            self.traces = c.traces.clone();
        }
        // The input bar, while the edited scene still has it.
        let bars = input_bars(&self.analysis.scene);
        self.drive = Drive { input: c.drive.input.filter(|b| bars.contains(b)), step: c.drive.step };
        self.pace.step = c.step.clamp(self.pace.extent * tolerance::TUI_MIN_STEP_FRACTION, self.pace.extent);
        let scale = self.analysis.linkage.scale;
        let s = solved_of_mut(&mut self.analysis);
        if s.lazy {
            s.include(&c.at);
        }
        let ty = &c.at.ty;
        let found = nearest_attainable(&s.space, ty, c.at.lambda).and_then(|l| {
            let i = locate(&s.space, &Realization { ty: ty.clone(), lambda: l }, scale)?;
            Some((i, l))
        });
        match found {
            Some((i, l)) => {
                let k = s.components.of_interval[i];
                self.enter_component(k, Some((i, l)));
                (l != c.at.lambda).then(|| {
                    format!(
                        "{ty}: λ = {} is no longer reached; at the nearest, λ = {}",
                        fmt_num(c.at.lambda),
                        fmt_num(l)
                    )
                })
            }
            None => Some(format!("the realization {ty}@{} vanished: back at the drawn one", fmt_num(c.at.lambda))),
        }
    }

    /// Back to the drawn realization, in its component.
    pub fn reset(&mut self) {
        let s = self.solved();
        let at = s.drawn_interval.map(|i| (i, s.drawn.lambda));
        let k = s.drawn_component.unwrap_or(0);
        self.pace.playing = false;
        self.enter_component(k, at);
    }

    /// Follow component `k`, standing at (interval, λ) or at its start.
    fn enter_component(&mut self, k: usize, at: Option<(usize, f64)>) {
        let s = solved_of(&self.analysis);
        let c = &mut self.cursor;
        c.motion = Motion::Component(k);
        c.component = k;
        c.segments = component_segments(&s.space, &s.components.list[k]);
        c.generation += 1;
        let (seg, lambda) = at
            .and_then(|(i, l)| c.segments.iter().position(|s| s.interval == i).map(|p| (p, l)))
            .unwrap_or((0, c.segments[0].from));
        c.seg = seg;
        c.lambda = lambda;
        self.refresh();
        self.picture.bounds = self.component_bounds();
    }

    /// Positions at the current λ; where none can be computed (or they are
    /// not finite) the last ones stay, and `false` says so.
    fn refresh(&mut self) -> bool {
        let s = solved_of(&self.analysis);
        let c = &mut self.cursor;
        match realization_at(&s.construction, &self.analysis.linkage, &c.segments[c.seg], c.lambda) {
            Some(p) => {
                c.cayley = cayley_vector(&p, &s.complexity.ccv);
                c.positions = p;
                true
            }
            None => false,
        }
    }

    fn cyclic(&self) -> bool {
        matches!(self.cursor.motion, Motion::Component(_))
    }

    /// Segments from the current point onward (`dir` = 1) or backward, with
    /// each one's index in `segments`; a component wraps around once.
    fn ahead(&self, dir: i8) -> Vec<(usize, Segment)> {
        let c = &self.cursor;
        let m = c.segments.len();
        let cur = &c.segments[c.seg];
        let mut out = Vec::new();
        if dir > 0 {
            let flat_from = if c.lambda == cur.from { cur.flat_from.clone() } else { Vec::new() };
            out.push((c.seg, Segment { from: c.lambda, flat_from, ..cur.clone() }));
            for k in 1..=m {
                let i = c.seg + k;
                if i >= m && !self.cyclic() {
                    break;
                }
                out.push((i % m, c.segments[i % m].clone()));
            }
        } else {
            let flat_from = if c.lambda == cur.to { cur.flat_to.clone() } else { Vec::new() };
            out.push((
                c.seg,
                Segment { from: c.lambda, to: cur.from, flat_from, flat_to: cur.flat_from.clone(), ..cur.clone() },
            ));
            for k in 1..=m {
                if c.seg < k && !self.cyclic() {
                    break;
                }
                let i = (c.seg + m * 2 - k) % m;
                out.push((i, c.segments[i].reversed()));
            }
        }
        out
    }

    /// Move by one geometric step of at most `bound` along the motion. A
    /// move across a degenerate pass (a jump) is made and said.
    pub fn move_by(&mut self, dir: i8, bound: f64) -> Result<Option<String>, String> {
        let ahead = self.ahead(dir);
        let segs: Vec<Segment> = ahead.iter().map(|(_, s)| s.clone()).collect();
        let s = solved_of(&self.analysis);
        let mut walk = Stepper::new(&s.construction, &self.analysis.linkage, segs, bound).with_budget(2);
        walk.next();
        match walk.next() {
            Some(sample) => {
                let c = &mut self.cursor;
                c.seg = ahead[sample.segment].0;
                c.lambda = sample.lambda;
                c.cayley = cayley_vector(&sample.positions, &s.complexity.ccv);
                c.positions = sample.positions;
                Ok(sample.jump.then(|| {
                    format!(
                        "jumped at λ = {}: a degenerate pass (joints move farther than the step between adjacent λ)",
                        fmt_num(sample.lambda)
                    )
                }))
            }
            None => match walk.summary().stopped_at {
                Some(l) => Err(format!("no realization could be computed at λ = {}: cannot move on", fmt_num(l))),
                None => Err("end of the path: press 1/2 to walk it again, Esc for the whole component".into()),
            },
        }
    }

    /// Jump to the next (or previous) interval endpoint along the motion.
    fn jump(&mut self, dir: i8) -> Result<(), String> {
        let lambda = self.cursor.lambda;
        let (i, s) = self.ahead(dir).into_iter().find(|(_, s)| s.to != lambda).ok_or("end of the path")?;
        self.cursor.seg = i;
        self.cursor.lambda = s.to;
        self.refreshed()
    }

    /// [`Self::refresh`], with a message when no realization could be computed.
    fn refreshed(&mut self) -> Result<(), String> {
        if self.refresh() {
            Ok(())
        } else {
            Err(format!(
                "no realization could be computed at λ = {}: the joints shown are the last ones computed",
                fmt_num(self.cursor.lambda)
            ))
        }
    }

    /// Where we stand as (interval, λ).
    fn here(&self) -> (usize, f64) {
        (self.cursor.segments[self.cursor.seg].interval, self.cursor.lambda)
    }

    /// Apply an action; `Ok(Some(note))` when it has something to say.
    fn apply(&mut self, action: Action) -> Result<Option<String>, String> {
        let step = self.pace.step;
        match action {
            Action::StepForward => return self.advance(1, 1.0),
            Action::StepBack => return self.advance(-1, 1.0),
            Action::LargeForward => return self.advance(1, 10.0),
            Action::LargeBack => return self.advance(-1, 10.0),
            Action::NextInputBar => return self.next_input_bar().map(Some),
            Action::NextEndpoint => self.jump(1)?,
            Action::PrevEndpoint => self.jump(-1)?,
            Action::PlayPause => self.pace.playing = !self.pace.playing,
            Action::NextComponent | Action::PrevComponent => {
                // A lazy analysis walks the next component when asked for it,
                // into the one analysis (indices already known stay valid).
                let mut note = None;
                let k = self.cursor.component;
                if action == Action::NextComponent && self.solved().lazy && k + 1 == self.n_components() {
                    let before = self.n_components();
                    let s = solved_of_mut(&mut self.analysis);
                    if commands::walk_components(s, before + 1) == before {
                        note = Some(crate::present::missing_component(s, before));
                    }
                }
                let n = self.n_components();
                let next = if action == Action::NextComponent { (k + 1) % n } else { (k + n - 1) % n };
                self.enter_component(next, None);
                return Ok(note);
            }
            Action::MarkA | Action::MarkB => {
                let slot = usize::from(action == Action::MarkB);
                let component = self.solved().components.of_interval[self.here().0];
                self.marks.slots[slot] = Some(Mark { at: self.current(), component });
                self.update_path()?;
            }
            Action::ClearMarks => {
                self.marks = Marks::default();
                if let Motion::Path { .. } = self.cursor.motion {
                    self.enter_component(self.cursor.component, Some(self.here()));
                }
            }
            Action::FollowArc1 | Action::FollowArc2 => {
                let arc = usize::from(action == Action::FollowArc2);
                // Marks in different components: visit the closest pair's two realizations.
                if let Some(c) = self.marks.path.as_ref().and_then(|p| p.closest_pair.clone()) {
                    let r = if arc == 0 { &c.a } else { &c.b };
                    self.go_to(&format!("{}@{}", r.ty, r.lambda))?;
                    return Ok(Some(format!(
                        "closest pair, realization {} of 2 ({}, component {}): {}",
                        arc + 1,
                        if arc == 0 { "near A" } else { "near B" },
                        r.component,
                        closest_words(&c)
                    )));
                }
                let Some(arcs) = &self.marks.arcs else {
                    return Err("mark A and B in one component first (a, then b)".into());
                };
                if arcs[arc].is_empty() {
                    return Err(format!(
                        "this component is an open chain (it ends at dead ends): A and B are joined only by path {}",
                        2 - arc
                    ));
                }
                let segments = arcs[arc].clone();
                let c = &mut self.cursor;
                c.component = solved_of(&self.analysis).components.of_interval[segments[0].interval];
                c.lambda = segments[0].from;
                c.segments = segments;
                c.generation += 1;
                c.motion = Motion::Path { arc };
                c.seg = 0;
                self.refreshed()?;
            }
            Action::FollowComponent => {
                if let Motion::Path { .. } = self.cursor.motion {
                    self.enter_component(self.cursor.component, Some(self.here()));
                }
            }
            Action::ToggleTraces => self.traces.on = !self.traces.on,
            Action::NextJoint => self.traces.selected = (self.traces.selected + 1) % self.traces.traced.len(),
            Action::ToggleJointTrace => {
                let j = self.traces.selected;
                self.traces.traced[j] = !self.traces.traced[j];
                self.traces.on = true;
            }
            Action::SwitchView => {
                self.view = if self.view == View::Linkage { View::CayleyCurve } else { View::Linkage };
            }
            Action::RotateLeft => self.camera.yaw -= CAMERA_TURN,
            Action::RotateRight => self.camera.yaw += CAMERA_TURN,
            Action::TiltUp => self.camera.pitch = (self.camera.pitch + CAMERA_TURN).min(CAMERA_MAX_PITCH),
            Action::TiltDown => self.camera.pitch = (self.camera.pitch - CAMERA_TURN).max(-CAMERA_MAX_PITCH),
            Action::NextAxes => {
                let n = self.solved().complexity.ccv.len();
                self.camera.next_axes(n);
            }
            Action::StepBigger if self.drive.input.is_some() => self.drive.step = (self.drive.step * 2.0).min(360.0),
            Action::StepSmaller if self.drive.input.is_some() => {
                self.drive.step = (self.drive.step / 2.0).max(tolerance::TUI_MIN_STEP_FRACTION)
            }
            Action::StepBigger => self.pace.step = (step * 2.0).min(self.pace.extent),
            Action::StepSmaller => {
                self.pace.step = (step / 2.0).max(self.pace.extent * tolerance::TUI_MIN_STEP_FRACTION)
            }
            Action::Reset => self.reset(),
            Action::ScrollDown | Action::ScrollUp => {
                // Bounded by the longest list, so coming back takes no more presses than going.
                let s = self.solved();
                let most = s.complexity.ccv.len().max(s.components.list[self.cursor.component].intervals.len());
                let by = if action == Action::ScrollDown { 1 } else { -1 };
                self.scroll = (self.scroll + by).clamp(-(most as isize), most as isize);
            }
            // Handled by the app: the prompt, help, quit, and the edits.
            Action::GoTo
            | Action::Help
            | Action::Quit
            | Action::ToggleEdit
            | Action::Undo
            | Action::Redo
            | Action::Save
            | Action::SelectNext
            | Action::SelectPrev
            | Action::SelectByName
            | Action::MoveLeft
            | Action::MoveRight
            | Action::MoveUp
            | Action::MoveDown
            | Action::MoveLeftFar
            | Action::MoveRightFar
            | Action::MoveUpFar
            | Action::MoveDownFar
            | Action::Lengthen
            | Action::Shorten
            | Action::LengthenFar
            | Action::ShortenFar
            | Action::SetValue
            | Action::DeleteBar
            | Action::ExitEdit
            | Action::Export
            | Action::NextBase
            | Action::Sweep
            | Action::ToggleSweep
            | Action::NameAxes => {}
            Action::TakeBranch => return self.take_branch().map(Some),
        }
        Ok(None)
    }

    /// A status line after some actions.
    fn note_for(&self, action: Action) -> Option<String> {
        match action {
            Action::MarkA | Action::MarkB => Some(match (&self.marks.slots, &self.marks.path) {
                ([Some(_), Some(_)], Some(p)) if p.same_component => {
                    let n: Vec<String> = p.paths.iter().map(|x| x.n_intervals.to_string()).collect();
                    format!("A and B share a component: two paths of {} intervals (1/2 to follow)", n.join(" and "))
                }
                ([Some(_), Some(_)], Some(p)) => match &p.closest_pair {
                    Some(c) => format!(
                        "different components: closest pair {}@{} / {}@{} (1/2 to visit): {}",
                        c.a.ty,
                        fmt_num(c.a.lambda),
                        c.b.ty,
                        fmt_num(c.b.lambda),
                        closest_words(c)
                    ),
                    None => "different components".into(),
                },
                _ => format!("marked {}", if action == Action::MarkA { "A" } else { "B" }),
            }),
            Action::StepBigger | Action::StepSmaller if self.drive.input.is_some() => {
                Some(format!("angle step {}°", fmt_num(self.drive.step)))
            }
            Action::StepBigger | Action::StepSmaller => Some(format!("step {}", fmt_num(self.pace.step))),
            _ if self.branch_here().len() > 1 => Some(format!(
                "a branch point: {} ways meet here (f takes the next; the listed components each follow one)",
                self.branch_here().len()
            )),
            _ => None,
        }
    }

    fn update_path(&mut self) -> Result<(), String> {
        self.marks.path = None;
        self.marks.arcs = None;
        let [Some(a), Some(b)] = &self.marks.slots else { return Ok(()) };
        let (an, s) = (&self.analysis, solved_of(&self.analysis));
        let walk = Walk { step: self.pace.step, max_samples: tolerance::TUI_MAX_SAMPLES };
        let report = commands::path(&an.linkage, s, &a.at.to_string(), &b.at.to_string(), walk)?;
        if report.same_component {
            let ia = locate(&s.space, &a.at, an.linkage.scale).ok_or("A is no longer located")?;
            let ib = locate(&s.space, &b.at, an.linkage.scale).ok_or("B is no longer located")?;
            let comp = &s.components.list[s.components.of_interval[ia]];
            self.marks.arcs = arcs(&s.space, comp, (ia, a.at.lambda), (ib, b.at.lambda));
        }
        self.marks.path = Some(report);
        Ok(())
    }

    /// `λ` (in the current component, nearest occurrence) or `TYPE@λ`; a
    /// lazy analysis walks the component through `TYPE@λ` into the one analysis.
    pub fn go_to(&mut self, text: &str) -> Result<(), String> {
        let scale = self.analysis.linkage.scale;
        if let Some(degrees) = text.strip_suffix('°').or_else(|| text.strip_suffix("deg")) {
            return self.go_to_angle(degrees.trim());
        }
        if text.contains('@') || text == "drawn" {
            commands::include_specs(solved_of_mut(&mut self.analysis), &[text]);
            let s = self.solved();
            let (r, i) = commands::resolve_realization(s, text)?;
            let k = s.components.of_interval[i];
            self.enter_component(k, Some((i, r.lambda)));
            return Ok(());
        }
        let lambda: f64 =
            text.parse().map_err(|_| format!("\"{text}\": type a λ like 41.2, or TYPE@λ like -+-+@41.2"))?;
        // Prefer the current type, then any interval of the current motion.
        let c = &self.cursor;
        let here = &c.segments[c.seg].ty;
        let candidates: Vec<usize> = (0..c.segments.len())
            .filter(|&i| {
                let sg = &c.segments[i];
                lambda >= sg.from.min(sg.to) - tolerance::TUI_GOTO_MARGIN * scale
                    && lambda <= sg.from.max(sg.to) + tolerance::TUI_GOTO_MARGIN * scale
            })
            .collect();
        let pick = candidates.iter().copied().find(|&i| &c.segments[i].ty == here).or(candidates.first().copied());
        match pick {
            Some(i) => {
                self.cursor.seg = i;
                self.cursor.lambda = lambda;
                self.refreshed()
            }
            None => Err(format!("λ = {lambda} is not reached by this motion")),
        }
    }

    /// The curve's axes by name: three entries of the complete Cayley vector
    /// (`P-X O-Y O-W`; a pair as `P-X`, `P–X` or `P,X`, either order); the view turns to the curve.
    pub fn name_axes(&mut self, text: &str) -> Result<(), String> {
        let l = &self.analysis.linkage;
        let ccv = &solved_of(&self.analysis).complexity.ccv;
        let entries = || ccv.iter().map(|&p| l.pair_name(p)).collect::<Vec<_>>().join(" ");
        let words: Vec<&str> = text.split([' ', ';']).filter(|w| !w.is_empty()).collect();
        if words.len() != 3 || ccv.len() < 3 {
            return Err(format!("name three entries of the complete Cayley vector: {}", entries()));
        }
        let mut axes = [0; 3];
        for (axis, word) in axes.iter_mut().zip(&words) {
            let found = self
                .analysis
                .scene
                .joint_pair(word)
                .and_then(|[p, q]| ccv.iter().position(|&e| e == [p, q] || e == [q, p]));
            *axis = found.ok_or_else(|| format!("{word} is not in the complete Cayley vector: {}", entries()))?;
        }
        if axes[0] == axes[1] || axes[1] == axes[2] || axes[0] == axes[2] {
            return Err(format!("name three different entries: {}", entries()));
        }
        self.camera.axes = axes;
        self.view = View::CayleyCurve;
        Ok(())
    }

    /// One step (`times` steps) along the motion: by degrees of the input
    /// bar when one is chosen, else geometric.
    pub fn advance(&mut self, dir: i8, times: f64) -> Result<Option<String>, String> {
        match self.drive.input {
            Some(bar) => self.turn_by(bar, dir, (self.drive.step * times).to_radians()),
            None => self.move_by(dir, self.pace.step * times),
        }
    }

    /// The input bar's name (pivot first) and its angle here, degrees from the ground line.
    pub fn input_angle(&self) -> Option<(String, f64)> {
        let bar = self.drive.input?;
        let names = &self.analysis.linkage.names;
        Some((format!("{}–{}", names[bar.pivot], names[bar.tip]), bar.angle(&self.cursor.positions).to_degrees()))
    }

    /// The readout's line for the angle drive, when an input bar is chosen.
    pub fn drive_line(&self) -> Option<String> {
        let (name, deg) = self.input_angle()?;
        Some(format!("{name} {}° ±{}°", fmt_sig(deg, 8), fmt_num(self.drive.step)))
    }

    /// The next input bar (none after the last): see [`input_bars`].
    fn next_input_bar(&mut self) -> Result<String, String> {
        let bars = input_bars(&self.analysis.scene);
        if bars.is_empty() {
            return Err("no bar has exactly one ground joint (and another ground joint to measure from): \
                        nothing to drive by angle"
                .into());
        }
        self.drive.input = match self.drive.input.and_then(|b| bars.iter().position(|x| *x == b)) {
            None => Some(bars[0]),
            Some(k) => bars.get(k + 1).copied(),
        };
        let names = &self.analysis.linkage.names;
        Ok(match (self.drive.input, self.input_angle()) {
            (Some(b), Some((name, deg))) => format!(
                "input bar {name} at {}° from the ground line {}–{}: steps, play and g 90° go by degrees \
                 (±{}°, +/- change); i: next bar",
                fmt_sig(deg, 8),
                names[b.pivot],
                names[b.reference],
                fmt_num(self.drive.step)
            ),
            _ => "no input bar: steps are geometric again".into(),
        })
    }

    /// Turn the input bar by `delta` radians, moving along the motion in
    /// `dir`: to the first point where it has turned that far either way.
    fn turn_by(&mut self, bar: InputBar, dir: i8, delta: f64) -> Result<Option<String>, String> {
        let scan = self.scan_angle(bar, dir, |a, b| [delta, -delta].into_iter().find(|&t| crosses(a, b, t)));
        match scan {
            Ok(hit) => {
                let turned_back = hit.travel > delta * (1.0 + 1e-9) + 1e-12;
                let note = self.land(hit);
                Ok(note.or_else(|| {
                    turned_back.then(|| {
                        "the input bar turned back on the way (a dead point): it is not monotone here".to_string()
                    })
                }))
            }
            Err(miss) => Err(self.miss_words(&miss, &format!("turn {}°", fmt_num(delta.to_degrees())))),
        }
    }

    /// `g 90°`: the nearest realization along the motion (either way, by
    /// degrees turned) where the input bar is at that angle.
    fn go_to_angle(&mut self, text: &str) -> Result<(), String> {
        let Some(bar) = self.drive.input else {
            return Err("choose an input bar first (i), then g 90° goes to its angle".into());
        };
        let target: f64 = text
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| format!("\"{text}°\": type an angle in degrees like 90°"))?
            .to_radians();
        let rel = wrap_angle(target - bar.angle(&self.cursor.positions));
        if rel == 0.0 {
            return Ok(());
        }
        // The first angle ≡ target (mod a full turn) between a and b.
        let find = |a: f64, b: f64| {
            let k = ((a.min(b) - rel) / std::f64::consts::TAU).ceil();
            let t = rel + k * std::f64::consts::TAU;
            (t <= a.max(b) && crosses(a, b, t)).then_some(t)
        };
        let forward = self.scan_angle(bar, 1, find);
        let back = self.scan_angle(bar, -1, find);
        let hit = match (forward, back) {
            (Ok(f), Ok(b)) => {
                if b.travel < f.travel {
                    b
                } else {
                    f
                }
            }
            (Ok(h), Err(_)) | (Err(_), Ok(h)) => h,
            (Err(miss), Err(_)) => return Err(self.miss_words(&miss, &format!("reach {text}°"))),
        };
        match self.land(hit) {
            Some(note) => Err(note),
            None => Ok(()),
        }
    }

    /// Stand at a scan's hit; a note when it was reached across a jump.
    fn land(&mut self, hit: AngleHit) -> Option<String> {
        let s = solved_of(&self.analysis);
        let c = &mut self.cursor;
        c.seg = hit.seg;
        c.lambda = hit.lambda;
        c.cayley = cayley_vector(&hit.positions, &s.complexity.ccv);
        c.positions = hit.positions;
        hit.jump.then(|| {
            format!("jumped at λ = {}: a degenerate pass (the angle is reached across it)", fmt_num(hit.lambda))
        })
    }

    /// Why a scan missed, in words.
    fn miss_words(&self, miss: &AngleMiss, what: &str) -> String {
        let range = format!(
            "it turns only from {}° to {}° from here",
            fmt_sig(miss.lo.to_degrees(), 6),
            fmt_sig(miss.hi.to_degrees(), 6)
        );
        match miss.stopped_at {
            Some(l) => format!("cannot {what}: no realization could be computed at λ = {} ({range})", fmt_num(l)),
            None if self.cyclic() => format!("cannot {what} along this component: {range}"),
            None => format!("cannot {what} before the end of the path: {range} (Esc: whole component)"),
        }
    }

    /// Walk the motion from here in `dir` (around a component once), the
    /// input bar's angle unwrapped from its value here, until `target(a, b)`
    /// names an angle reached between two samples; there bisect λ within the
    /// later sample's segment to the float nearest that angle. The samples
    /// are close enough for the angle to unwrap (see [`tolerance::TUI_ANGLE_SCAN_TURN`]).
    #[allow(clippy::type_complexity)]
    fn scan_angle(
        &self,
        bar: InputBar,
        dir: i8,
        target: impl Fn(f64, f64) -> Option<f64>,
    ) -> Result<AngleHit, AngleMiss> {
        let (a, s) = (&self.analysis, self.solved());
        let p = &self.cursor.positions;
        let length = (p[bar.tip][0] - p[bar.pivot][0]).hypot(p[bar.tip][1] - p[bar.pivot][1]);
        let bound = (tolerance::TUI_ANGLE_SCAN_TURN * length).min(self.pace.step).max(f64::MIN_POSITIVE);
        let ahead = self.ahead(dir);
        let segs: Vec<Segment> = ahead.iter().map(|(_, sg)| sg.clone()).collect();
        let mut walk =
            Stepper::new(&s.construction, &a.linkage, segs.clone(), bound).with_budget(tolerance::TUI_MAX_SAMPLES);
        let here = bar.angle(p);
        let (mut lo, mut hi, mut travel) = (0.0f64, 0.0f64, 0.0f64);
        // The previous sample: segment, λ, positions, raw and unwrapped angle.
        let mut prev: Option<(usize, f64, Vec<Point2<f64>>, f64, f64)> = None;
        for sm in walk.by_ref() {
            let raw = bar.angle(&sm.positions);
            let Some((pseg, plambda, ppos, praw, pu)) = prev.take() else {
                prev = Some((sm.segment, sm.lambda, sm.positions, raw, wrap_angle(raw - here)));
                continue;
            };
            let u = pu + wrap_angle(raw - praw);
            if let Some(t) = target(pu, u) {
                let seg = &segs[sm.segment];
                let hit = |lambda: f64, positions: Vec<Point2<f64>>, jump: bool| AngleHit {
                    seg: ahead[sm.segment].0,
                    lambda,
                    positions,
                    travel: travel + (t - pu).abs(),
                    jump,
                };
                if sm.jump {
                    return Ok(hit(sm.lambda, sm.positions, true));
                }
                // The stretch of this segment from the previous sample (or the segment's start).
                let (l0, pos0) = if pseg == sm.segment {
                    (plambda, ppos)
                } else {
                    match realization_at(&s.construction, &a.linkage, seg, seg.from) {
                        Some(q) => (seg.from, q),
                        None => (seg.from, ppos),
                    }
                };
                let f = |q: &[Point2<f64>]| pu + wrap_angle(bar.angle(q) - praw) - t;
                let (lambda, positions) = bisect((l0, f(&pos0), pos0), (sm.lambda, u - t, sm.positions), |l| {
                    realization_at(&s.construction, &a.linkage, seg, l).map(|q| (f(&q), q))
                });
                return Ok(hit(lambda, positions, false));
            }
            travel += (u - pu).abs();
            lo = lo.min(u);
            hi = hi.max(u);
            prev = Some((sm.segment, sm.lambda, sm.positions, raw, u));
        }
        Err(AngleMiss { lo, hi, stopped_at: walk.summary().stopped_at })
    }

    /// Bring what the drawing reads up to date: the samples of the current
    /// motion (walked within the UI's budgets, at most a few million
    /// numbers) when the motion changed; the traces and the projected curve
    /// when the samples, the traced joints or the camera changed; the
    /// current point on the curve always.
    pub fn sync(&mut self) {
        if self.picture.samples.generation != self.cursor.generation {
            self.picture.samples = self.walk_samples();
        }
        let key = (self.cursor.generation, self.camera, self.traces.clone());
        if self.picture.made_from.as_ref() != Some(&key) {
            let p = &mut self.picture;
            p.traces = trace_paths(&p.samples, &self.traces, p.bounds);
            p.curve.range = axis_range(&p.samples, &self.camera);
            p.curve.runs = curve_runs(&p.samples, &self.camera, &p.curve.range);
            p.made_from = Some(key);
        }
        let curve = &mut self.picture.curve;
        curve.here = project(&curve.range, &self.camera, &self.cursor.cayley);
    }

    /// The samples of the current motion (for traces and the Cayley curve).
    fn walk_samples(&self) -> MotionSamples {
        let (a, s) = (&self.analysis, self.solved());
        let bound = tolerance::TUI_TRACE_STEP_FRACTION * self.pace.extent;
        let per_sample = a.linkage.n_joints() + s.complexity.ccv.len();
        let limit = (tolerance::TUI_MAX_NUMBERS / per_sample.max(1)).clamp(2, tolerance::TUI_MAX_SAMPLES);
        let mut walk =
            Stepper::new(&s.construction, &a.linkage, self.cursor.segments.clone(), bound).with_budget(limit);
        let mut out = MotionSamples { generation: self.cursor.generation, ..MotionSamples::default() };
        for sm in walk.by_ref() {
            out.cayley.push(cayley_vector(&sm.positions, &s.complexity.ccv));
            out.types.push(sm.ty);
            out.jumps.push(sm.jump);
            out.positions.push(sm.positions);
        }
        out.truncated = walk.summary().truncated;
        out
    }

    /// The joint whose path over the current component has the largest
    /// bounding-box diagonal (display frame, as drawn), from a coarse walk
    /// of at most [`tolerance::TUI_MOVER_SAMPLES`] samples; ties go to the
    /// last such joint in the file, as does a linkage where nothing moves.
    fn farthest_mover(&self) -> usize {
        let (a, s) = (&self.analysis, self.solved());
        let n = a.linkage.n_joints();
        let mut boxes = vec![[f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY]; n];
        let mut add = |ps: &[Point2<f64>]| {
            for (b, p) in boxes.iter_mut().zip(ps).filter(|(_, p)| p[0].is_finite() && p[1].is_finite()) {
                *b = [b[0].min(p[0]), b[1].min(p[1]), b[2].max(p[0]), b[3].max(p[1])];
            }
        };
        add(&self.cursor.positions);
        let segs = component_segments(&s.space, &s.components.list[self.cursor.component]);
        let bound = tolerance::TUI_BOUNDS_STEP_FRACTION * self.pace.extent;
        for sm in Stepper::new(&s.construction, &a.linkage, segs, bound).with_budget(tolerance::TUI_MOVER_SAMPLES) {
            add(&sm.positions);
        }
        let diag = |b: &[f64; 4]| if b[2] >= b[0] { (b[2] - b[0]).hypot(b[3] - b[1]) } else { 0.0 };
        (0..n).max_by(|&i, &j| diag(&boxes[i]).total_cmp(&diag(&boxes[j]))).unwrap_or(0)
    }

    /// Bounding box [x0, y0, x1, y1] of every joint over the current component (coarse walk).
    fn component_bounds(&self) -> [f64; 4] {
        let (a, s) = (&self.analysis, self.solved());
        let mut b = [f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY];
        let mut add = |p: &Point2<f64>| {
            b[0] = b[0].min(p[0]);
            b[1] = b[1].min(p[1]);
            b[2] = b[2].max(p[0]);
            b[3] = b[3].max(p[1]);
        };
        self.cursor.positions.iter().for_each(&mut add);
        let segs = component_segments(&s.space, &s.components.list[self.cursor.component]);
        let limit = (tolerance::TUI_MAX_NUMBERS / 2 / a.linkage.n_joints().max(1)).clamp(2, 5000);
        let bound = tolerance::TUI_BOUNDS_STEP_FRACTION * self.pace.extent;
        for sm in Stepper::new(&s.construction, &a.linkage, segs, bound).with_budget(limit) {
            sm.positions.iter().for_each(&mut add);
        }
        b
    }
}

/// Bisect λ between two points where `f` (a residual, with the realization
/// there) has opposite signs, to adjacent floats; the point of smallest
/// |residual| met wins (an end may be the best: next to a segment's end the
/// residual can change like a square root of λ). Where no realization can be
/// computed the bisection stops with the best so far.
#[allow(clippy::type_complexity)]
fn bisect(
    a: (f64, f64, Vec<Point2<f64>>),
    b: (f64, f64, Vec<Point2<f64>>),
    at: impl Fn(f64) -> Option<(f64, Vec<Point2<f64>>)>,
) -> (f64, Vec<Point2<f64>>) {
    let (mut l0, mut f0) = (a.0, a.1);
    let mut l1 = b.0;
    let mut best = if a.1.abs() < b.1.abs() { (a.0, a.1.abs(), a.2) } else { (b.0, b.1.abs(), b.2) };
    for _ in 0..200 {
        let mid = l0 / 2.0 + l1 / 2.0;
        if mid == l0 || mid == l1 || best.1 == 0.0 {
            break;
        }
        let Some((fm, q)) = at(mid) else { break };
        if fm.abs() < best.1 {
            best = (mid, fm.abs(), q);
        }
        if (fm < 0.0) == (f0 < 0.0) && fm != 0.0 {
            (l0, f0) = (mid, fm);
        } else {
            l1 = mid;
        }
    }
    (best.0, best.2)
}

/// The minimal complete Cayley vector's entries (indices into the complete one).
fn minimal_entries(s: &Solved) -> Vec<usize> {
    s.minimal_vector(crate::minimal_vector::MinimalOptions::default()).entries
}

/// The Cayley curve's default axes: the minimal vector's entries first, then
/// the first other entries of the complete vector (`n` of them), repeating the
/// last when there are fewer than three.
pub fn default_axes(minimal: &[usize], n: usize) -> [usize; 3] {
    let mut axes: Vec<usize> = minimal.iter().copied().filter(|&e| e < n).take(3).collect();
    for e in 0..n {
        if axes.len() == 3 {
            break;
        }
        if !axes.contains(&e) {
            axes.push(e);
        }
    }
    let last = axes.last().copied().unwrap_or(0);
    axes.resize(3, last);
    [axes[0], axes[1], axes[2]]
}

/// The drawing in units of its own extent (the box `b`), centred: the
/// canvas never sees scene coordinates (a scene at 1e307 or 1e-320 would
/// overflow or vanish in its arithmetic). A box of no or infinite extent
/// gives unit span; a non-finite centre gives the origin.
pub fn unit_frame(b: [f64; 4]) -> impl Fn([f64; 2]) -> [f64; 2] {
    let (cx, cy) = (b[0] / 2.0 + b[2] / 2.0, b[1] / 2.0 + b[3] / 2.0);
    let span = (b[2] / 2.0 - b[0] / 2.0).max(b[3] / 2.0 - b[1] / 2.0) * 2.0;
    let span = if span.is_finite() && span > 0.0 { span } else { 1.0 };
    let (cx, cy) = if cx.is_finite() && cy.is_finite() { (cx, cy) } else { (0.0, 0.0) };
    move |p| [(p[0] - cx) / span, (p[1] - cy) / span]
}

/// Each traced joint's positions over the samples in the unit frame of
/// `bounds`, the non-finite left out (none when traces are off).
fn trace_paths(samples: &MotionSamples, traces: &Traces, bounds: [f64; 4]) -> Vec<(usize, Vec<(f64, f64)>)> {
    if !traces.on {
        return Vec::new();
    }
    let unit = &unit_frame(bounds);
    let path = |j: usize| {
        samples
            .positions
            .iter()
            .map(move |p| unit(p[j].into()))
            .filter(|p| p[0].is_finite() && p[1].is_finite())
            .map(|p| (p[0], p[1]))
    };
    (0..traces.traced.len()).filter(|&j| traces.traced[j]).map(|j| (j, path(j).collect())).collect()
}

/// The camera's three axes of a Cayley vector (0 where it has no such entry).
fn pick(camera: &Camera, v: &[f64]) -> Vector3<f64> {
    Vector3::from(camera.axes.map(|a| v.get(a).copied().unwrap_or(0.0)))
}

/// The samples' range [lo, hi] on each of the camera's axes.
fn axis_range(samples: &MotionSamples, camera: &Camera) -> AxisRange {
    let mut lo = Vector3::repeat(f64::INFINITY);
    let mut hi = Vector3::repeat(f64::NEG_INFINITY);
    for v in &samples.cayley {
        let u = pick(camera, v);
        lo = lo.inf(&u);
        hi = hi.sup(&u);
    }
    AxisRange { lo, hi }
}

/// A Cayley vector on screen: each axis scaled to [-1, 1] over the samples'
/// range (0 for an axis of no extent), the first axis across, the third up,
/// the second in depth; rotated by the camera, projected orthographically.
fn project(range: &AxisRange, camera: &Camera, v: &[f64]) -> (f64, f64) {
    let AxisRange { lo, hi } = range;
    let u = pick(camera, v);
    let n = Vector3::from_fn(|k, _| if hi[k] > lo[k] { 2.0 * (u[k] - lo[k]) / (hi[k] - lo[k]) - 1.0 } else { 0.0 });
    let p = camera.rotation() * Vector3::new(n[0], n[2], n[1]);
    (p.x, p.y)
}

/// The projected curve in runs of one type that do not cross a jump.
fn curve_runs(samples: &MotionSamples, camera: &Camera, range: &AxisRange) -> Vec<(usize, Vec<(f64, f64)>)> {
    let mut types: Vec<&RealizationType> = Vec::new();
    let mut runs: Vec<(usize, Vec<(f64, f64)>)> = Vec::new();
    for ((v, ty), &jump) in samples.cayley.iter().zip(&samples.types).zip(&samples.jumps) {
        let k = types.iter().position(|t| *t == ty).unwrap_or_else(|| {
            types.push(ty);
            types.len() - 1
        });
        let p = project(range, camera, v);
        // A new run at a type change, and at a jump (no line across it).
        match runs.last_mut() {
            Some((kk, pts)) if *kk == k && !jump => pts.push(p),
            _ => runs.push((k, vec![p])),
        }
    }
    runs
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_camera_turns_about_the_vertical_then_tilts() {
        let c = Camera { yaw: std::f64::consts::FRAC_PI_2, pitch: 0.0, axes: [0, 1, 2] };
        // A quarter turn about y takes the depth axis (z) across (x).
        let p = c.rotation() * Vector3::new(0.0, 0.0, 1.0);
        assert!((p.x - 1.0).abs() < 1e-15 && p.y.abs() < 1e-15, "{p}");
        let c = Camera { yaw: 0.0, pitch: std::f64::consts::FRAC_PI_2, axes: [0, 1, 2] };
        // A quarter tilt about x takes depth to down.
        let p = c.rotation() * Vector3::new(0.0, 0.0, 1.0);
        assert!((p.y + 1.0).abs() < 1e-15 && p.x.abs() < 1e-15, "{p}");
    }

    #[test]
    fn axes_cycle_through_every_triple_in_order() {
        let mut c = Camera { yaw: 0.0, pitch: 0.0, axes: [0, 1, 2] };
        let mut seen = vec![c.axes];
        for _ in 0..9 {
            c.next_axes(5);
            seen.push(c.axes);
        }
        // All C(5, 3) = 10 triples, increasing, then back to the first.
        assert_eq!(seen.len(), 10);
        assert!(seen.windows(2).all(|w| w[0] < w[1]), "{seen:?}");
        assert!(seen.iter().all(|t| t[0] < t[1] && t[1] < t[2] && t[2] < 5));
        c.next_axes(5);
        assert_eq!(c.axes, [0, 1, 2]);
        c.next_axes(3);
        assert_eq!(c.axes, [0, 1, 2], "three entries: one triple");
    }
}
