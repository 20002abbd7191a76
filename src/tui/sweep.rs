//! The sweep view (`s`, `S`): how the analysis changes as the selected bar's
//! length (or joint's coordinate) varies, the same sweep as `caymos sweep`
//! ([`commands::sweep_report`]), run on the solver thread and shown in place
//! of the drawing. It is swept again after every edit, so a designer sees
//! where the behaviour flips move as the mechanism changes.

use crate::commands::{self, Shard, SweepReport};
use crate::numfmt::fmt_sig;
use crate::scene::Scene;
use crate::sweep::{Parameter, Setup};

use super::app::{App, Job, Prompt, PromptKind, input_bars};
use super::edit::Item;
use super::keymap::{Action, Mode};

/// Samples of a sweep unless the user types another count (the chart's 73 columns at 80).
pub const DEFAULT_STEPS: usize = 60;

/// What a sweep varies, by joints (stable across edits; bar indices shift when a bar is deleted).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Swept {
    /// The length of the bar joining these two joints.
    Bar([usize; 2]),
    /// Coordinate `axis` (0: x, 1: y) of a joint.
    Joint { joint: usize, axis: usize },
}

impl Swept {
    /// The parameter on `scene`; `None` when the bar is gone.
    pub fn parameter(self, scene: &Scene) -> Option<Parameter> {
        match self {
            Swept::Bar([a, b]) => scene.bar_index(a, b).map(Parameter::BarLength),
            Swept::Joint { joint, axis } => (joint < scene.joints.len()).then_some(Parameter::Joint { joint, axis }),
        }
    }

    /// `A–B` or `C.x`, as `caymos sweep` names it.
    pub fn name(self, scene: &Scene) -> String {
        let n = |j: usize| scene.joints.get(j).map_or("?", |j| j.name.as_str());
        match self {
            Swept::Bar([a, b]) => format!("{}–{}", n(a), n(b)),
            Swept::Joint { joint, axis } => format!("{}.{}", n(joint), if axis == 0 { "x" } else { "y" }),
        }
    }

    /// Its value in `scene` now: the bar's stated (else drawn) length, or the coordinate.
    pub fn value(self, scene: &Scene) -> Option<f64> {
        match self.parameter(scene)? {
            Parameter::BarLength(i) => Some(scene.bar_length(i)),
            Parameter::Joint { joint, axis } => Some(scene.joints[joint].pos[axis]),
        }
    }

    /// "the swept bar A–B is gone", or the joint coordinate.
    pub fn gone(self, scene: &Scene) -> String {
        match self {
            Swept::Bar(_) => format!("the swept bar {} is gone", self.name(scene)),
            Swept::Joint { .. } => format!("the swept joint coordinate {} is gone", self.name(scene)),
        }
    }

    /// The range a designer most likely wants: for a bar, everything it can
    /// span, (0, Σ other bars] (its ends are joined through the rest of the
    /// linkage, so no realization is longer), from the first of `steps`
    /// equal parts; for a coordinate, the drawing's widest spread either side.
    pub fn default_range(self, scene: &Scene, steps: usize) -> [f64; 2] {
        match self.parameter(scene) {
            Some(Parameter::BarLength(i)) => {
                let others: f64 = (0..scene.bars.len()).filter(|&k| k != i).map(|k| scene.bar_length(k)).sum();
                let top = if others > 0.0 { others } else { 2.0 * scene.bar_length(i).max(f64::MIN_POSITIVE) };
                [top / steps as f64, top]
            }
            Some(Parameter::Joint { .. }) => {
                let v = self.value(scene).unwrap_or(0.0);
                let spread = |k: usize| {
                    let along = || scene.joints.iter().map(move |j| j.pos[k]);
                    along().fold(f64::NEG_INFINITY, f64::max) - along().fold(f64::INFINITY, f64::min)
                };
                let span = [spread(0).max(spread(1)), v.abs(), 1.0].into_iter().find(|x| *x > 0.0).unwrap_or(1.0);
                [v - span, v + span]
            }
            None => [0.0, 1.0],
        }
    }
}

/// A sweep asked for, and what came back.
#[derive(Clone, Debug)]
pub struct SweepView {
    pub swept: Swept,
    pub from: f64,
    pub to: f64,
    pub steps: usize,
    /// The latest sweep that came back (of an earlier scene while `pending`).
    pub report: Option<SweepReport>,
    /// A sweep of the current scene is running.
    pub pending: bool,
    /// The scene changed while the sweep was hidden: it runs again when shown.
    pub stale: bool,
    /// Why the sweep cannot run on the current scene (its bar was deleted).
    pub error: Option<String>,
    /// Shown in place of the drawing.
    pub shown: bool,
    /// How far its transition list is scrolled (`{` `}`).
    pub scroll: isize,
    /// The id of the sweep asked for last; older results are dropped.
    pub id: u64,
}

impl App {
    /// Apply a sweep action (`s`, `S`, and `{` `}` while the sweep shows); `false` when not one.
    pub(super) fn sweep_update(&mut self, action: Action) -> bool {
        match action {
            Action::Sweep => {
                self.message = None;
                match self.sweep_target() {
                    Ok(swept) => self.open_sweep_prompt(swept),
                    Err(why) => self.message = Some(why),
                }
            }
            Action::ToggleSweep => match &mut self.sweep {
                Some(s) => {
                    s.shown = !s.shown;
                    if s.shown && s.stale {
                        self.resweep();
                    }
                }
                None => self.message = Some("no sweep yet: s sweeps the selected bar or joint".into()),
            },
            Action::ScrollDown | Action::ScrollUp if self.sweep.as_ref().is_some_and(|s| s.shown) => {
                if let Some(s) = &mut self.sweep {
                    s.scroll += if action == Action::ScrollDown { 1 } else { -1 };
                }
            }
            _ => return false,
        }
        true
    }

    /// What `s` sweeps: the edit selection while editing; while exploring,
    /// the input bar of the angle drive, else the last sweep's parameter.
    fn sweep_target(&self) -> Result<Swept, String> {
        let scene = &self.doc.scene;
        if self.mode() == Mode::Edit {
            return Ok(match self.item() {
                Item::Bar(i) => Swept::Bar(scene.bars[i].joints),
                Item::Joint(j) => Swept::Joint { joint: j, axis: 0 },
            });
        }
        if let Some(bar) = self.model().and_then(|m| m.drive.input) {
            return Ok(Swept::Bar([bar.pivot, bar.tip]));
        }
        self.sweep.as_ref().map(|s| s.swept).ok_or_else(|| {
            "what to sweep: select a bar or joint in edit mode (m, then Tab or /) and press s, or choose an input bar (i)"
                .to_string()
        })
    }

    /// Open the prompt for a sweep of `swept`, filled with the range to sweep (the last one, else the default).
    fn open_sweep_prompt(&mut self, swept: Swept) {
        let scene = &self.doc.scene;
        let (range, steps) = match &self.sweep {
            Some(s) if s.swept == swept => ([s.from, s.to], s.steps),
            _ => (swept.default_range(scene, DEFAULT_STEPS), DEFAULT_STEPS),
        };
        let axis = match swept {
            Swept::Joint { axis, .. } => format!("{} ", if axis == 0 { "x" } else { "y" }),
            Swept::Bar(_) => String::new(),
        };
        let text = format!("{axis}{} {} {steps}", fmt_sig(range[0], 6), fmt_sig(range[1], 6));
        self.input = Some(Prompt { kind: PromptKind::Sweep(swept), text });
    }

    /// The typed range: `FROM TO [STEPS]`, for a joint after `x` or `y`; then sweep and show it.
    pub(super) fn submit_sweep(&mut self, swept: Swept, text: &str) -> Result<(), String> {
        let mut words: Vec<&str> = text.split([' ', ',']).filter(|w| !w.is_empty()).collect();
        let swept = match (swept, words.first()) {
            (Swept::Joint { joint, .. }, Some(&w)) if w == "x" || w == "y" => {
                words.remove(0);
                Swept::Joint { joint, axis: usize::from(w == "y") }
            }
            _ => swept,
        };
        let usage = || match swept {
            Swept::Bar(_) => "give FROM TO [STEPS], e.g. 0.5 3 60".to_string(),
            Swept::Joint { .. } => "give [x|y] FROM TO [STEPS], e.g. x -1 4 60".to_string(),
        };
        let number = |w: &str| w.parse::<f64>().map_err(|_| format!("\"{w}\" is not a number: {}", usage()));
        let (from, to, steps) = match words[..] {
            [a, b] => (number(a)?, number(b)?, DEFAULT_STEPS),
            [a, b, n] => (number(a)?, number(b)?, n.parse::<usize>().map_err(|_| format!("\"{n}\" is not a count"))?),
            _ => return Err(usage()),
        };
        let parameter = swept.parameter(&self.doc.scene).ok_or_else(|| swept.gone(&self.doc.scene))?;
        commands::check_sweep_range(parameter, from, to, steps, commands::Naming::Words)?;
        self.sweep = Some(SweepView {
            swept,
            from,
            to,
            steps,
            report: None,
            pending: false,
            stale: false,
            error: None,
            shown: true,
            scroll: 0,
            id: 0,
        });
        self.resweep();
        Ok(())
    }

    /// Ask for the sweep again on the current scene (after an edit, a
    /// reload, a new base or input bar); while hidden, only mark it stale
    /// (it runs again when shown), so hidden sweeps never compete with edits.
    pub(super) fn resweep(&mut self) {
        let scene = self.doc.scene.clone();
        let base = self.base;
        // The angle drive's input bar, if it is still one of this scene's.
        let input = self.model().and_then(|m| m.drive.input).filter(|b| input_bars(&scene).contains(b));
        let Some(s) = &mut self.sweep else { return };
        s.stale = !s.shown;
        if s.stale {
            return;
        }
        // Ids from one counter, so a result of an older sweep never passes for a newer one's.
        self.sweeps_asked += 1;
        s.id = self.sweeps_asked;
        s.error = None;
        s.pending = false;
        match s.swept.parameter(&scene) {
            Some(parameter) => {
                s.pending = true;
                let setup = Setup::new(scene, parameter, base, input);
                self.sweep_job = Some(Job::sweep(s.id, setup, s.from, s.to, s.steps));
            }
            None => s.error = Some(format!("{} (undo brings it back)", s.swept.gone(&scene))),
        }
    }

    /// Take a finished sweep, unless a newer one was asked for since.
    pub(super) fn install_sweep(&mut self, id: u64, report: SweepReport) {
        if let Some(s) = &mut self.sweep
            && s.id == id
        {
            s.report = Some(report);
            s.pending = false;
        }
    }

    /// Whether a sweep asked for has not arrived yet.
    pub fn sweeping(&self) -> bool {
        self.sweep.as_ref().is_some_and(|s| s.pending)
    }

    /// The swept parameter's value in the scene now (the chart's `▲`).
    pub fn swept_now(&self) -> Option<f64> {
        self.sweep.as_ref().and_then(|s| s.swept.value(&self.doc.scene))
    }
}

/// Run a sweep the way `caymos sweep` does (every sample, in parallel).
pub fn run(setup: &Setup, from: f64, to: f64, steps: usize) -> SweepReport {
    commands::sweep_report(setup, from, to, steps, Shard::ALL)
}
