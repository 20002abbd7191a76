//! Edit mode: select a joint or a bar, move the joint or change the bar's
//! length, by keys or typed values; undo and redo; save; reload when the
//! file changes. Every change is a new text of the
//! [`Document`](super::document::Document), which the app re-analyses (see
//! `App::reanalyse`).

use crate::scene::Scene;
use crate::tolerance;

use super::app::{App, Prompt, PromptKind};
use super::document::{Reload, decimal};
use super::keymap::Action;

/// What edit keys act on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Item {
    Joint(usize),
    Bar(usize),
}

/// One state to go back (or forward) to: the text, and what the change did.
#[derive(Clone, Debug)]
struct Change {
    text: String,
    what: String,
}

/// The edit mode's state: whether it is on, the selection, the undo and redo stacks, the steps.
#[derive(Clone, Debug)]
pub struct Editor {
    pub on: bool,
    pub item: Item,
    undo: Vec<Change>,
    redo: Vec<Change>,
    /// The fine and coarse steps of moves and nudges, scene units (powers of ten).
    pub steps: [f64; 2],
}

impl Editor {
    /// Off, on the first joint, with steps for `scene`'s drawing.
    pub fn new(scene: &Scene) -> Editor {
        Editor { on: false, item: Item::Joint(0), undo: Vec::new(), redo: Vec::new(), steps: steps(scene) }
    }

    /// How many changes undo and redo can go through.
    pub fn depth(&self) -> (usize, usize) {
        (self.undo.len(), self.redo.len())
    }
}

/// The fine and coarse edit steps: the powers of ten at or below
/// [`tolerance::TUI_EDIT_FINE_FRACTION`] and [`tolerance::TUI_EDIT_COARSE_FRACTION`]
/// of the drawing's extent (its bounding-box diagonal; the longest stated
/// length, or 1, when the joints are all at one point).
pub fn steps(scene: &Scene) -> [f64; 2] {
    let along = |k: usize| scene.joints.iter().map(move |j| j.pos[k]);
    let lo = [0, 1].map(|k| along(k).fold(f64::INFINITY, f64::min));
    let hi = [0, 1].map(|k| along(k).fold(f64::NEG_INFINITY, f64::max));
    let diagonal = (hi[0] / 2.0 - lo[0] / 2.0).hypot(hi[1] / 2.0 - lo[1] / 2.0) * 2.0;
    let longest = scene.bars.iter().filter_map(|b| b.length).fold(0.0, f64::max);
    let extent = [diagonal, longest, 1.0].into_iter().find(|x| x.is_finite() && *x > 0.0).unwrap_or(1.0);
    let power_below = |x: f64| {
        let p = 10f64.powf(x.log10().floor());
        if p.is_finite() && p > 0.0 { p } else { x }
    };
    [power_below(extent * tolerance::TUI_EDIT_FINE_FRACTION), power_below(extent * tolerance::TUI_EDIT_COARSE_FRACTION)]
}

impl App {
    /// Apply an edit-mode action (and undo, redo, save, which work in both
    /// modes); `false` when `action` is not one of them.
    pub(super) fn edit_update(&mut self, action: Action) -> bool {
        let [fine, coarse] = self.editor.steps;
        let result = match action {
            Action::ToggleEdit => {
                self.editor.on = !self.editor.on;
                Ok(Some(if self.editor.on {
                    "editing: Tab selects, arrows move a joint, +/- change a bar, = types a value, u undoes, w saves, m ends"
                        .to_string()
                } else {
                    "exploring".to_string()
                }))
            }
            Action::ExitEdit => {
                self.editor.on = false;
                Ok(None)
            }
            Action::Undo => self.undo(),
            Action::Redo => self.redo(),
            Action::Save => self.save(),
            Action::SelectNext => Ok(Some(self.select_by(1))),
            Action::SelectPrev => Ok(Some(self.select_by(-1))),
            Action::SelectByName => {
                self.input = Some(Prompt { kind: PromptKind::Select, text: String::new() });
                Ok(None)
            }
            Action::MoveLeft => self.move_joint([-1.0, 0.0], fine),
            Action::MoveRight => self.move_joint([1.0, 0.0], fine),
            Action::MoveUp => self.move_joint([0.0, 1.0], fine),
            Action::MoveDown => self.move_joint([0.0, -1.0], fine),
            Action::MoveLeftFar => self.move_joint([-1.0, 0.0], coarse),
            Action::MoveRightFar => self.move_joint([1.0, 0.0], coarse),
            Action::MoveUpFar => self.move_joint([0.0, 1.0], coarse),
            Action::MoveDownFar => self.move_joint([0.0, -1.0], coarse),
            Action::Lengthen => self.nudge_length(fine),
            Action::Shorten => self.nudge_length(-fine),
            Action::LengthenFar => self.nudge_length(coarse),
            Action::ShortenFar => self.nudge_length(-coarse),
            Action::SetValue => {
                let text = match self.item() {
                    Item::Joint(j) => {
                        let p = self.doc.scene.joints[j].pos;
                        format!("{}, {}", p[0], p[1])
                    }
                    Item::Bar(i) => format!("{}", self.bar_length(i)),
                };
                self.input = Some(Prompt { kind: PromptKind::Value, text });
                Ok(None)
            }
            Action::DeleteBar => self.delete_bar(),
            _ => return false,
        };
        self.message = match result {
            Ok(note) => note,
            Err(e) => Some(e),
        };
        true
    }

    /// The selection, kept within the scene (a bar may have been deleted).
    pub fn item(&self) -> Item {
        let s = &self.doc.scene;
        match self.editor.item {
            Item::Joint(j) if j < s.joints.len() => Item::Joint(j),
            Item::Bar(i) if i < s.bars.len() => Item::Bar(i),
            _ => Item::Joint(0),
        }
    }

    /// `joint C` or `bar B–C`.
    pub fn item_name(&self, item: Item) -> String {
        let s = &self.doc.scene;
        match item {
            Item::Joint(j) => format!("joint {}", s.joints[j].name),
            Item::Bar(i) => {
                let [a, b] = s.bars[i].joints;
                format!("bar {}–{}", s.joints[a].name, s.joints[b].name)
            }
        }
    }

    /// A bar's length: stated, else drawn.
    pub fn bar_length(&self, i: usize) -> f64 {
        self.doc.scene.bar_length(i)
    }

    /// Select the next (`by` = 1) or previous joint or bar: joints first, then bars.
    fn select_by(&mut self, by: isize) -> String {
        let (nj, nb) = (self.doc.scene.joints.len(), self.doc.scene.bars.len());
        let k = match self.item() {
            Item::Joint(j) => j,
            Item::Bar(i) => nj + i,
        };
        let n = (nj + nb) as isize;
        let k = (k as isize + by).rem_euclid(n) as usize;
        self.editor.item = if k < nj { Item::Joint(k) } else { Item::Bar(k - nj) };
        format!("selected {}", self.item_name(self.item()))
    }

    /// Select the joint named `text`, or the bar between the two joints it names (`B-C`, `B–C`, `B C`).
    pub(super) fn select_named(&mut self, text: &str) -> Result<(), String> {
        let s = &self.doc.scene;
        let item = if let Some(j) = s.joint_index(text) {
            Item::Joint(j)
        } else {
            let bar = s.joint_pair(text).and_then(|[a, b]| s.bar_index(a, b));
            let joints: Vec<&str> = s.joints.iter().map(|j| j.name.as_str()).collect();
            Item::Bar(bar.ok_or_else(|| {
                format!("no joint or bar {text:?}: type a joint ({}) or a bar like A-B", joints.join(", "))
            })?)
        };
        self.editor.item = item;
        self.message = Some(format!("selected {}", self.item_name(item)));
        Ok(())
    }

    /// Set the selection's value from typed text: `x, y` for a joint, a length for a bar.
    pub(super) fn set_value(&mut self, text: &str) -> Result<Option<String>, String> {
        match self.item() {
            Item::Joint(j) => {
                let parts: Vec<&str> = text.split([',', ' ']).filter(|p| !p.is_empty()).collect();
                let [x, y] = parts.as_slice() else {
                    return Err(format!("{text:?}: type the joint's position as x, y"));
                };
                let what = format!("{} at ({x}, {y})", self.item_name(Item::Joint(j)));
                let coords = [Some(x.to_string()), Some(y.to_string())];
                self.change(what, |doc| doc.set_joint(j, coords))
            }
            Item::Bar(i) => {
                let what = format!("{} length {}", self.item_name(Item::Bar(i)), text.trim());
                let text = text.trim().to_string();
                self.change(what, |doc| doc.set_length(i, &text))
            }
        }
    }

    /// Move the selected joint by `dir` × `step`; the numbers land on the step's decimals.
    fn move_joint(&mut self, dir: [f64; 2], step: f64) -> Result<Option<String>, String> {
        let Item::Joint(j) = self.item() else {
            return Err("a bar is selected: +/- change its length (Tab selects a joint)".into());
        };
        let old = self.doc.scene.joints[j].pos;
        let coords: [Option<String>; 2] =
            [0, 1].map(|k| (dir[k] != 0.0).then(|| decimal(old[k] + dir[k] * step, old[k], step)));
        let shown: Vec<String> =
            [0, 1].map(|k| coords[k].clone().unwrap_or_else(|| format!("{}", old[k]))).into_iter().collect();
        let what = format!("{} to ({})", self.item_name(Item::Joint(j)), shown.join(", "));
        self.change(what, |doc| doc.set_joint(j, coords))
    }

    /// Lengthen (or shorten, `by` < 0) the selected bar; it states its length from then on.
    fn nudge_length(&mut self, by: f64) -> Result<Option<String>, String> {
        let Item::Bar(i) = self.item() else {
            return Err("a joint is selected: arrows move it (Tab selects a bar)".into());
        };
        let old = self.bar_length(i);
        if old + by <= 0.0 {
            return Err(format!("{} is {}: it cannot get shorter by {}", self.item_name(Item::Bar(i)), old, by.abs()));
        }
        let text = decimal(old + by, old, by.abs());
        let what = format!("{} length {text}", self.item_name(Item::Bar(i)));
        self.change(what, |doc| doc.set_length(i, &text))
    }

    fn delete_bar(&mut self) -> Result<Option<String>, String> {
        let Item::Bar(i) = self.item() else {
            return Err("select a bar to delete (Tab, or / and its name)".into());
        };
        if self.doc.scene.bars.len() == 1 {
            return Err("the last bar cannot be deleted: a scene needs one".into());
        }
        let what = format!("deleted {}", self.item_name(Item::Bar(i)));
        self.change(what, |doc| doc.delete_bar(i))
    }

    /// Make a change to the document; if it is valid, remember the text
    /// before it for undo and re-analyse. An invalid change changes nothing.
    fn change(
        &mut self,
        what: String,
        f: impl FnOnce(&mut super::document::Document) -> Result<(), String>,
    ) -> Result<Option<String>, String> {
        let before = self.doc.text();
        f(&mut self.doc)?;
        self.editor.undo.push(Change { text: before, what: what.clone() });
        self.editor.redo.clear();
        self.reanalyse();
        Ok(Some(what))
    }

    fn undo(&mut self) -> Result<Option<String>, String> {
        let what = self.travel(true)?;
        Ok(Some(format!("undid: {what} ({} more to undo)", self.editor.undo.len())))
    }

    fn redo(&mut self) -> Result<Option<String>, String> {
        Ok(Some(format!("redid: {}", self.travel(false)?)))
    }

    /// Undo (`back`) or redo one change: its text becomes the document's and
    /// the text before goes on the other stack; what the change was, in words.
    fn travel(&mut self, back: bool) -> Result<String, String> {
        let editor = &mut self.editor;
        let (from, to) = if back { (&mut editor.undo, &mut editor.redo) } else { (&mut editor.redo, &mut editor.undo) };
        let c = from.pop().ok_or(if back { "nothing to undo" } else { "nothing to redo" })?;
        let now = self.doc.text();
        if let Err(e) = self.doc.set_text(&c.text) {
            from.push(c);
            return Err(e.to_string());
        }
        to.push(Change { text: now, what: c.what.clone() });
        self.reanalyse();
        Ok(c.what)
    }

    fn save(&mut self) -> Result<Option<String>, String> {
        let new = self.doc.path.is_none();
        let path = self.doc.save(&self.save_dir)?;
        self.file_error = None;
        Ok(Some(if new {
            format!("saved to a new file {} (the scene had no file)", path.display())
        } else {
            format!("saved {}", path.display())
        }))
    }

    /// Poll the scene's file and take a changed text (undo goes back to the
    /// one before); a text that does not parse is shown as the error and
    /// leaves everything as it was. Whether the screen changed.
    pub fn check_file(&mut self) -> bool {
        match self.doc.poll() {
            Reload::Unchanged => false,
            Reload::Same => self.file_error.take().is_some(),
            Reload::Reloaded { before } => {
                let name = self.doc.path.as_ref().map(|p| p.display().to_string()).unwrap_or_default();
                self.editor.undo.push(Change { text: before, what: format!("reload of {name}") });
                self.editor.redo.clear();
                self.file_error = None;
                self.message = Some(format!("reloaded {name} (u goes back)"));
                self.reanalyse();
                true
            }
            Reload::Bad(e) => {
                self.message = None; // the status line shows the error
                self.file_error = Some(format!("{e} (the file is watched; the last good scene stays)"));
                true
            }
        }
    }
}
