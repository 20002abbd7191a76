//! The terminal UI's state and its update: actions in, new state out. No
//! terminal here, so every behaviour is testable with a list of key presses.

use crate::analysis::{Analysis, Solved};
use crate::commands::{self, PathReport, Walk};
use crate::distance::cayley_vector;
use crate::motion::{Realization, Segment, Stepper, arcs, component_segments, locate, realization_at};
use crate::realize::{P2, RealizationType};
use crate::report::fmt_num;
use crate::tolerance;

use super::keymap::Action;

/// What the main area shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    Linkage,
    CayleyCurve,
}

/// What stepping follows: a whole component (a cycle) or one path from A to B.
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

/// The state of an analysed scene in the UI.
pub struct Model {
    pub analysis: Analysis,
    pub solved: Solved,
    pub motion: Motion,
    /// Segments of the current motion, and where we are on them.
    pub segments: Vec<Segment>,
    pub seg: usize,
    pub lambda: f64,
    /// The current realization, display frame.
    pub positions: Vec<P2<f64>>,
    /// The component the current realization lies in.
    pub component: usize,
    /// Geometric step (largest joint move per small step), scene units.
    pub step: f64,
    /// The drawing's extent (bounding-box diagonal): the unit of steps.
    pub extent: f64,
    pub playing: bool,
    pub marks: [Option<Mark>; 2],
    pub path: Option<PathReport>,
    /// Arc segments of the path A→B (when in one component).
    pub path_arcs: Option<[Vec<Segment>; 2]>,
    pub traces_on: bool,
    pub traced: Vec<bool>,
    pub selected_joint: usize,
    pub view: View,
    pub yaw: f64,
    pub pitch: f64,
    /// Indices into the complete Cayley vector used as the curve's axes.
    pub axes: [usize; 3],
    /// Samples of the current motion: positions and Cayley vectors, kept in
    /// step with `segments` by every update (drawing only reads them).
    pub cache: Option<MotionSamples>,
    /// Bumped whenever `segments` change, so the cache knows it is stale.
    generation: u64,
    /// Joints' bounding box over the current component's motion, for a steady view.
    pub bounds: [f64; 4],
}

/// Samples of the current motion (for traces and the Cayley curve).
pub struct MotionSamples {
    pub generation: u64,
    pub positions: Vec<Vec<P2<f64>>>,
    pub cayley: Vec<Vec<f64>>,
    pub types: Vec<RealizationType>,
    /// Whether each sample is reached by a jump (drawn lines break there).
    pub jumps: Vec<bool>,
    /// The motion was longer than the sample budget: only its start is shown.
    pub truncated: bool,
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
    Ready(Box<Model>),
}

pub struct App {
    pub screen: Screen,
    pub help: bool,
    /// A line of input being typed after `g`.
    pub input: Option<String>,
    /// A one-line message for the status bar (results, errors).
    pub message: Option<String>,
    pub quit: bool,
}

impl App {
    pub fn loading(scene: &str) -> App {
        App {
            screen: Screen::Loading { scene: scene.to_string() },
            help: false,
            input: None,
            message: None,
            quit: false,
        }
    }

    /// Take the finished analysis.
    pub fn loaded(&mut self, analysis: Result<Analysis, String>) {
        let scene = match &self.screen {
            Screen::Loading { scene, .. } => scene.clone(),
            _ => String::new(),
        };
        self.screen = match analysis {
            Err(message) => Screen::Failed { scene, message },
            Ok(a) => match a.outcome.clone() {
                Err(outside) => {
                    let message =
                        format!("outside the handled class: {}", crate::present::outside(&outside, &a.linkage));
                    Screen::Failed { scene: a.scene.name.clone(), message }
                }
                Ok(solved) => match commands::require_component(&a.linkage, &solved).err() {
                    Some(why) => Screen::Empty { analysis: Box::new(a), why },
                    None => Screen::Ready(Box::new(Model::new(a, solved))),
                },
            },
        };
    }

    pub fn ready(analysis: Analysis) -> App {
        let mut app = App::loading(&analysis.scene.name);
        app.loaded(Ok(analysis));
        app
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
        if self.help && action == Action::FollowComponent {
            self.help = false;
            return;
        }
        let Screen::Ready(m) = &mut self.screen else { return };
        self.message = None;
        match action {
            Action::GoTo => self.input = Some(String::new()),
            other => match m.apply(other) {
                Err(e) => self.message = Some(e),
                Ok(Some(note)) => self.message = Some(note),
                Ok(None) => self.message = m.note_for(other),
            },
        }
        m.sync_samples();
    }

    /// A character typed while the `g` prompt is open; Enter applies it.
    pub fn type_char(&mut self, c: char) {
        if let Some(s) = &mut self.input {
            s.push(c);
        }
    }
    pub fn backspace(&mut self) {
        if let Some(s) = &mut self.input {
            s.pop();
        }
    }
    pub fn cancel_input(&mut self) {
        self.input = None;
    }
    pub fn submit_input(&mut self) {
        let Some(text) = self.input.take() else { return };
        if let Screen::Ready(m) = &mut self.screen {
            self.message = m.go_to(text.trim()).err();
            m.sync_samples();
        }
    }

    /// One animation frame.
    pub fn tick(&mut self) {
        if let Screen::Ready(m) = &mut self.screen
            && m.playing
        {
            match m.move_by(1, m.step) {
                Ok(None) => {}
                Ok(Some(note)) => self.message = Some(note),
                Err(_) => m.playing = false,
            }
        }
    }

    pub fn animating(&self) -> bool {
        self.model().is_some_and(|m| m.playing)
    }
}

impl Model {
    pub fn new(analysis: Analysis, solved: Solved) -> Model {
        let n = analysis.linkage.n_joints();
        let extent = commands::drawing_extent(&analysis);
        let step = tolerance::TUI_STEP_FRACTION * extent;
        let mut traced = vec![false; n];
        if let Some(last) = traced.last_mut() {
            *last = true; // the last joint is usually the coupler point or the foot
        }
        // Until a realization is computed: the drawn one (never empty).
        let positions = solved.drawn_positions.clone().unwrap_or_else(|| analysis.linkage.drawn.clone());
        let ccv_len = solved.complexity.ccv.len();
        let axes = [0, 1.min(ccv_len.saturating_sub(1)), 2.min(ccv_len.saturating_sub(1))];
        let mut m = Model {
            analysis,
            solved,
            motion: Motion::Component(0),
            segments: Vec::new(),
            seg: 0,
            lambda: 0.0,
            positions,
            component: 0,
            step,
            extent,
            playing: false,
            marks: [None, None],
            path: None,
            path_arcs: None,
            traces_on: true,
            traced,
            selected_joint: n.saturating_sub(1),
            view: View::Linkage,
            yaw: 0.6,
            pitch: 0.35,
            axes,
            cache: None,
            generation: 0,
            bounds: [0.0; 4],
        };
        m.reset();
        m.sync_samples();
        m
    }

    pub fn n_components(&self) -> usize {
        self.solved.components.list.len()
    }

    /// Current realization as type and λ.
    pub fn current(&self) -> Realization {
        Realization { ty: self.segments[self.seg].ty.clone(), lambda: self.lambda }
    }

    /// Steps flat at the current point (when exactly on an interval endpoint).
    pub fn flat_here(&self) -> &[usize] {
        let s = &self.segments[self.seg];
        if self.lambda == s.to {
            &s.flat_to
        } else if self.lambda == s.from {
            &s.flat_from
        } else {
            &[]
        }
    }

    pub fn cayley_vector(&self) -> Vec<f64> {
        cayley_vector(&self.positions, &self.solved.complexity.ccv)
    }

    /// Back to the drawn realization, in its component.
    pub fn reset(&mut self) {
        let s = &self.solved;
        let drawn = Realization { ty: s.drawn.ty.clone(), lambda: s.drawn.lambda };
        let at = s.drawn_interval.map(|i| (i, drawn.lambda));
        self.playing = false;
        self.enter_component(s.drawn_component.unwrap_or(0), at);
    }

    /// Follow component `k`, standing at (interval, λ) or at its start.
    fn enter_component(&mut self, k: usize, at: Option<(usize, f64)>) {
        self.motion = Motion::Component(k);
        self.component = k;
        self.segments = component_segments(&self.solved.space, &self.solved.components.list[k]);
        self.generation += 1;
        let (seg, lambda) = at
            .and_then(|(i, l)| self.segments.iter().position(|s| s.interval == i).map(|p| (p, l)))
            .unwrap_or((0, self.segments[0].from));
        self.seg = seg;
        self.lambda = lambda;
        self.refresh();
        self.bounds = self.component_bounds();
    }

    /// Positions at the current λ; where none can be computed (or they are
    /// not finite) the last ones stay, and `false` says so.
    fn refresh(&mut self) -> bool {
        let a = &self.analysis;
        match realization_at(&self.solved.construction, &a.linkage, &self.segments[self.seg], self.lambda) {
            Some(p) => {
                self.positions = p;
                true
            }
            None => false,
        }
    }

    fn cyclic(&self) -> bool {
        matches!(self.motion, Motion::Component(_))
    }

    /// Segments from the current point onward (`dir` = 1) or backward, with
    /// each one's index in `segments`; a component wraps around once.
    fn ahead(&self, dir: i8) -> Vec<(usize, Segment)> {
        let m = self.segments.len();
        let cur = &self.segments[self.seg];
        let mut out = Vec::new();
        if dir > 0 {
            let flat_from = if self.lambda == cur.from { cur.flat_from.clone() } else { Vec::new() };
            out.push((self.seg, Segment { from: self.lambda, flat_from, ..cur.clone() }));
            for k in 1..=m {
                let i = self.seg + k;
                if i >= m && !self.cyclic() {
                    break;
                }
                out.push((i % m, self.segments[i % m].clone()));
            }
        } else {
            let flat_from = if self.lambda == cur.to { cur.flat_to.clone() } else { Vec::new() };
            out.push((
                self.seg,
                Segment { from: self.lambda, to: cur.from, flat_from, flat_to: cur.flat_from.clone(), ..cur.clone() },
            ));
            for k in 1..=m {
                if self.seg < k && !self.cyclic() {
                    break;
                }
                let i = (self.seg + m * 2 - k) % m;
                out.push((i, self.segments[i].reversed()));
            }
        }
        out
    }

    /// Move by one geometric step of at most `bound` along the motion. A
    /// move across a degenerate pass (a jump) is made and said.
    pub fn move_by(&mut self, dir: i8, bound: f64) -> Result<Option<String>, String> {
        let ahead = self.ahead(dir);
        let segs: Vec<Segment> = ahead.iter().map(|(_, s)| s.clone()).collect();
        let a = &self.analysis;
        let mut walk = Stepper::new(&self.solved.construction, &a.linkage, segs, bound).with_budget(2);
        walk.next();
        match walk.next() {
            Some(sample) => {
                self.seg = ahead[sample.segment].0;
                self.lambda = sample.lambda;
                self.positions = sample.positions;
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
        let (i, s) = self.ahead(dir).into_iter().find(|(_, s)| s.to != self.lambda).ok_or("end of the path")?;
        self.seg = i;
        self.lambda = s.to;
        self.refreshed()
    }

    /// [`Self::refresh`], with a message when no realization could be computed.
    fn refreshed(&mut self) -> Result<(), String> {
        if self.refresh() {
            Ok(())
        } else {
            Err(format!(
                "no realization could be computed at λ = {}: the joints shown are the last ones computed",
                fmt_num(self.lambda)
            ))
        }
    }

    /// Apply an action; `Ok(Some(note))` when it has something to say.
    fn apply(&mut self, action: Action) -> Result<Option<String>, String> {
        match action {
            Action::StepForward => return self.move_by(1, self.step),
            Action::StepBack => return self.move_by(-1, self.step),
            Action::LargeForward => return self.move_by(1, self.step * 10.0),
            Action::LargeBack => return self.move_by(-1, self.step * 10.0),
            Action::NextEndpoint => self.jump(1)?,
            Action::PrevEndpoint => self.jump(-1)?,
            Action::PlayPause => self.playing = !self.playing,
            Action::NextComponent | Action::PrevComponent => {
                // A lazy analysis walks the next component when asked for it.
                let mut note = None;
                if action == Action::NextComponent && self.solved.lazy && self.component + 1 == self.n_components() {
                    let before = self.n_components();
                    if commands::walk_components(&mut self.solved, before + 1) == before {
                        note = Some(crate::present::missing_component(&self.solved, before));
                    }
                }
                let n = self.n_components();
                let k = if action == Action::NextComponent {
                    (self.component + 1) % n
                } else {
                    (self.component + n - 1) % n
                };
                self.enter_component(k, None);
                return Ok(note);
            }
            Action::MarkA | Action::MarkB => {
                let slot = usize::from(action == Action::MarkB);
                let component = self.solved.components.of_interval[self.segments[self.seg].interval];
                self.marks[slot] = Some(Mark { at: self.current(), component });
                self.update_path()?;
            }
            Action::ClearMarks => {
                self.marks = [None, None];
                self.path = None;
                self.path_arcs = None;
                if let Motion::Path { .. } = self.motion {
                    let at = (self.segments[self.seg].interval, self.lambda);
                    self.enter_component(self.component, Some(at));
                }
            }
            Action::FollowArc1 | Action::FollowArc2 => {
                let arc = usize::from(action == Action::FollowArc2);
                let Some(arcs) = &self.path_arcs else {
                    return Err("mark A and B in one component first (a, then b)".into());
                };
                if arcs[arc].is_empty() {
                    return Err(format!(
                        "this component is an open chain (it ends at dead ends): A and B are joined only by path {}",
                        2 - arc
                    ));
                }
                self.segments = arcs[arc].clone();
                self.generation += 1;
                self.motion = Motion::Path { arc };
                self.component = self.solved.components.of_interval[self.segments[0].interval];
                self.seg = 0;
                self.lambda = self.segments[0].from;
                self.refreshed()?;
            }
            Action::FollowComponent => {
                if let Motion::Path { .. } = self.motion {
                    let at = (self.segments[self.seg].interval, self.lambda);
                    self.enter_component(self.component, Some(at));
                }
            }
            Action::ToggleTraces => self.traces_on = !self.traces_on,
            Action::NextJoint => self.selected_joint = (self.selected_joint + 1) % self.traced.len(),
            Action::ToggleJointTrace => {
                let j = self.selected_joint;
                self.traced[j] = !self.traced[j];
                self.traces_on = true;
            }
            Action::SwitchView => {
                self.view = if self.view == View::Linkage { View::CayleyCurve } else { View::Linkage };
            }
            Action::RotateLeft => self.yaw -= 0.15,
            Action::RotateRight => self.yaw += 0.15,
            Action::TiltUp => self.pitch = (self.pitch + 0.15).min(1.5),
            Action::TiltDown => self.pitch = (self.pitch - 0.15).max(-1.5),
            Action::NextAxes => {
                let n = self.solved.complexity.ccv.len();
                if n > 3 {
                    // Cycle through the triples in lexicographic order.
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
            Action::StepBigger => self.step = (self.step * 2.0).min(self.extent),
            Action::StepSmaller => self.step = (self.step / 2.0).max(self.extent * 1e-6),
            Action::Reset => self.reset(),
            Action::GoTo | Action::Help | Action::Quit => {}
        }
        Ok(None)
    }

    /// A status line after some actions.
    fn note_for(&self, action: Action) -> Option<String> {
        match action {
            Action::MarkA | Action::MarkB => Some(match (&self.marks, &self.path) {
                ([Some(_), Some(_)], Some(p)) if p.same_component => {
                    let n: Vec<String> = p.paths.iter().map(|x| x.n_intervals.to_string()).collect();
                    format!("A and B share a component: two paths of {} intervals (1/2 to follow)", n.join(" and "))
                }
                ([Some(_), Some(_)], Some(p)) => match &p.closest_pair {
                    Some(c) => format!(
                        "different components: closest pair {}@{} / {}@{} at Cayley distance {}",
                        c.a.ty,
                        fmt_num(c.a.lambda),
                        c.b.ty,
                        fmt_num(c.b.lambda),
                        fmt_num(c.distance)
                    ),
                    None => "different components".into(),
                },
                _ => format!("marked {}", if action == Action::MarkA { "A" } else { "B" }),
            }),
            Action::StepBigger | Action::StepSmaller => Some(format!("step {}", fmt_num(self.step))),
            _ => None,
        }
    }

    fn update_path(&mut self) -> Result<(), String> {
        self.path = None;
        self.path_arcs = None;
        let [Some(a), Some(b)] = &self.marks else { return Ok(()) };
        let (an, s) = (&self.analysis, &self.solved);
        let walk = Walk { step: self.step, max_samples: tolerance::TUI_MAX_SAMPLES };
        let report = commands::path(&an.linkage, s, &a.at.to_string(), &b.at.to_string(), walk)?;
        if report.same_component {
            let ia = locate(&s.space, &a.at, an.linkage.scale).ok_or("A is no longer located")?;
            let ib = locate(&s.space, &b.at, an.linkage.scale).ok_or("B is no longer located")?;
            let comp = &s.components.list[s.components.of_interval[ia]];
            self.path_arcs = arcs(&s.space, comp, (ia, a.at.lambda), (ib, b.at.lambda));
        }
        self.path = Some(report);
        Ok(())
    }

    /// `λ` (in the current component, nearest occurrence) or `TYPE@λ`.
    pub fn go_to(&mut self, text: &str) -> Result<(), String> {
        let scale = self.analysis.linkage.scale;
        if text.contains('@') || text == "drawn" {
            commands::include_specs(&mut self.solved, &[text]);
            let s = &self.solved;
            let (r, i) = commands::resolve_realization(s, text)?;
            let k = s.components.of_interval[i];
            self.enter_component(k, Some((i, r.lambda)));
            return Ok(());
        }
        let lambda: f64 =
            text.parse().map_err(|_| format!("\"{text}\": type a λ like 41.2, or TYPE@λ like -+-+@41.2"))?;
        // Prefer the current type, then any interval of the current motion.
        let here = &self.segments[self.seg].ty;
        let candidates: Vec<usize> = (0..self.segments.len())
            .filter(|&i| {
                let sg = &self.segments[i];
                lambda >= sg.from.min(sg.to) - 1e-12 * scale && lambda <= sg.from.max(sg.to) + 1e-12 * scale
            })
            .collect();
        let pick = candidates.iter().copied().find(|&i| &self.segments[i].ty == here).or(candidates.first().copied());
        match pick {
            Some(i) => {
                self.seg = i;
                self.lambda = lambda;
                self.refreshed()
            }
            None => Err(format!("λ = {lambda} is not reached by this motion")),
        }
    }

    /// Bring the samples of the current motion (traces, Cayley curve) up to
    /// date: walked within the UI's budgets, at most a few million numbers.
    pub fn sync_samples(&mut self) {
        if self.cache.as_ref().is_some_and(|c| c.generation == self.generation) {
            return;
        }
        let a = &self.analysis;
        let bound = tolerance::TUI_TRACE_STEP_FRACTION * self.extent;
        let per_sample = a.linkage.n_joints() + self.solved.complexity.ccv.len();
        let limit = (tolerance::TUI_MAX_NUMBERS / per_sample.max(1)).clamp(2, tolerance::TUI_MAX_SAMPLES);
        let mut walk =
            Stepper::new(&self.solved.construction, &a.linkage, self.segments.clone(), bound).with_budget(limit);
        let (mut positions, mut cayley, mut types, mut jumps) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for sm in walk.by_ref() {
            cayley.push(cayley_vector(&sm.positions, &self.solved.complexity.ccv));
            types.push(sm.ty);
            jumps.push(sm.jump);
            positions.push(sm.positions);
        }
        let truncated = walk.summary().truncated;
        self.cache = Some(MotionSamples { generation: self.generation, positions, cayley, types, jumps, truncated });
    }

    /// Bounding box [x0, y0, x1, y1] of every joint over the current component (coarse walk).
    fn component_bounds(&self) -> [f64; 4] {
        let a = &self.analysis;
        let mut b = [f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY];
        let mut add = |p: &P2<f64>| {
            b[0] = b[0].min(p[0]);
            b[1] = b[1].min(p[1]);
            b[2] = b[2].max(p[0]);
            b[3] = b[3].max(p[1]);
        };
        self.positions.iter().for_each(&mut add);
        let segs = component_segments(&self.solved.space, &self.solved.components.list[self.component]);
        let limit = (tolerance::TUI_MAX_NUMBERS / 2 / a.linkage.n_joints().max(1)).clamp(2, 5000);
        let bound = tolerance::TUI_BOUNDS_STEP_FRACTION * self.extent;
        for sm in Stepper::new(&self.solved.construction, &a.linkage, segs, bound).with_budget(limit) {
            sm.positions.iter().for_each(&mut add);
        }
        b
    }
}
