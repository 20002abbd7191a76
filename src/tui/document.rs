//! The scene being edited, kept as its TOML text (`toml_edit`, so the user's
//! comments and layout survive an edit and a save). Every edit changes the
//! text and re-parses it: the scene is always exactly what the text says,
//! validated like a file (an edit that would make a bad scene is refused with
//! the parse error), and undo is a stack of texts.

use std::path::{Path, PathBuf};
use std::time::SystemTime;

use toml_edit::{DocumentMut, Value};

use crate::scene::{Scene, SceneError, parse_scene};

/// The scene's text and where it lives.
#[derive(Clone, Debug)]
pub struct Document {
    doc: DocumentMut,
    /// The scene the text states.
    pub scene: Scene,
    /// The file it is read from, watched at and saved to; `None` for a bundled
    /// or generated scene until it is saved.
    pub path: Option<PathBuf>,
    /// How errors name it (a path, or `bundled:NAME`).
    source: String,
    /// The scene's name when the text has no `name` key.
    default_name: String,
    /// The text as last read from or written to the file.
    saved: Option<String>,
    /// The file's modification time and length when last read or written.
    stamp: Option<Stamp>,
}

/// What a poll of the file compares: its modification time and length.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Stamp {
    modified: Option<SystemTime>,
    len: u64,
}

impl Stamp {
    fn of(path: &Path) -> Option<Stamp> {
        let m = std::fs::metadata(path).ok()?;
        Some(Stamp { modified: m.modified().ok(), len: m.len() })
    }
}

/// What a poll of the file found.
#[derive(Debug, PartialEq)]
pub enum Reload {
    /// The file did not change.
    Unchanged,
    /// It changed, to the text the document already has.
    Same,
    /// A new valid text was taken; the previous text is returned (for undo).
    Reloaded { before: String },
    /// The file changed but does not parse: the document is unchanged.
    Bad(SceneError),
}

impl Document {
    /// The document of a scene: its file's text when it came from a file
    /// (its `source` is an existing path), the bundled text for a bundled
    /// scene, else the scene written out as TOML.
    pub fn of(scene: &Scene) -> Document {
        let path = Path::new(&scene.source);
        let bundled = scene.source.strip_prefix("bundled:").and_then(crate::bundled::find);
        let (text, file, default_name) = if path.is_file() {
            let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
            (std::fs::read_to_string(path).ok(), Some(path.to_path_buf()), stem)
        } else if let Some(b) = bundled {
            (Some(b.text.to_string()), None, b.name.to_string())
        } else {
            (None, None, scene.name.clone())
        };
        let text = text.unwrap_or_else(|| crate::generate::to_toml(scene));
        // The text must state this very scene (not so for a scene changed in code).
        let parsed = parse_scene(&text, &scene.source, &default_name).ok().filter(|p| p == scene);
        let (doc, scene, file) = match (text.parse::<DocumentMut>(), parsed) {
            (Ok(doc), Some(parsed)) => (doc, parsed, file),
            // Start from the scene written out; never save that over a file it did not come from.
            _ => {
                let text = crate::generate::to_toml(scene);
                (text.parse().unwrap_or_default(), scene.clone(), None)
            }
        };
        let stamp = file.as_deref().and_then(Stamp::of);
        let saved = file.as_ref().map(|_| doc.to_string());
        let source = scene.source.clone();
        Document { doc, scene, path: file, source, default_name, saved, stamp }
    }

    /// The name files made from the scene take: its file's stem, the bundled name, else the scene's name.
    pub fn stem(&self) -> &str {
        &self.default_name
    }

    /// The text as it would be saved.
    pub fn text(&self) -> String {
        self.doc.to_string()
    }

    /// Whether the text differs from the file's (always, for a scene with no file).
    pub fn modified(&self) -> bool {
        self.saved.as_deref() != Some(self.text().as_str())
    }

    /// Replace the text (undo, redo, reload); a text that does not parse leaves the document as it was.
    pub fn set_text(&mut self, text: &str) -> Result<(), SceneError> {
        let scene = parse_scene(text, &self.source, &self.default_name)?;
        let doc = text.parse::<DocumentMut>().map_err(|e| SceneError {
            file: self.source.clone(),
            line: None,
            column: None,
            message: e.to_string(),
        })?;
        self.doc = doc;
        self.scene = scene;
        Ok(())
    }

    /// Apply an edit to a copy of the text; keep it only if the scene it states is valid.
    fn edit(&mut self, f: impl FnOnce(&mut DocumentMut) -> Result<(), String>) -> Result<(), String> {
        let mut doc = self.doc.clone();
        f(&mut doc)?;
        let text = doc.to_string();
        let scene = parse_scene(&text, &self.source, &self.default_name).map_err(|e| e.to_string())?;
        self.doc = doc;
        self.scene = scene;
        Ok(())
    }

    /// Set joint `j`'s drawn coordinates to the numbers written (TOML
    /// numbers); a `None` coordinate stays as written.
    pub fn set_joint(&mut self, j: usize, coords: [Option<String>; 2]) -> Result<(), String> {
        let name = self.scene.joints.get(j).ok_or("no such joint")?.name.clone();
        let [x, y] = coords.map(|c| c.as_deref().map(number).transpose());
        let (x, y) = (x?, y?);
        self.edit(|doc| {
            let pos = doc
                .get_mut("joints")
                .and_then(|t| t.as_table_like_mut())
                .and_then(|t| t.get_mut(&name))
                .and_then(|item| item.as_array_mut())
                .ok_or_else(|| format!("joint {name:?} is not written as [x, y] in the [joints] table"))?;
            if pos.len() != 2 {
                return Err(format!("joint {name:?} is not written as [x, y]"));
            }
            if let Some(x) = x {
                pos.replace(0, x);
            }
            if let Some(y) = y {
                pos.replace(1, y);
            }
            Ok(())
        })
    }

    /// State bar `i`'s length as the number written `length`.
    pub fn set_length(&mut self, i: usize, length: &str) -> Result<(), String> {
        let length = number(length)?;
        self.edit(|doc| {
            let bar = bars_mut(doc)?.get_mut(i).and_then(Value::as_array_mut).ok_or("no such bar")?;
            if bar.len() >= 3 {
                bar.replace(2, length);
            } else {
                bar.push(length);
            }
            Ok(())
        })
    }

    /// Remove bar `i` (the last bar cannot go: a scene needs one).
    pub fn delete_bar(&mut self, i: usize) -> Result<(), String> {
        self.edit(|doc| {
            let bars = bars_mut(doc)?;
            if i >= bars.len() {
                return Err("no such bar".into());
            }
            bars.remove(i);
            Ok(())
        })
    }

    /// Poll the file: when its time or length changed, read it and take it if it parses.
    pub fn poll(&mut self) -> Reload {
        let Some(path) = self.path.clone() else { return Reload::Unchanged };
        let stamp = Stamp::of(&path);
        if stamp.is_none() || stamp == self.stamp {
            return Reload::Unchanged;
        }
        self.stamp = stamp;
        let Ok(text) = std::fs::read_to_string(&path) else { return Reload::Unchanged };
        if text == self.text() {
            self.saved = Some(text);
            return Reload::Same;
        }
        let before = self.text();
        match self.set_text(&text) {
            Ok(()) => {
                self.saved = Some(text);
                Reload::Reloaded { before }
            }
            Err(e) => Reload::Bad(e),
        }
    }

    /// Write the text to its file, or (a scene with no file) to a new file in
    /// `dir` named after the scene, which becomes its file. Returns the path.
    pub fn save(&mut self, dir: &Path) -> Result<PathBuf, String> {
        let path = match &self.path {
            Some(p) => p.clone(),
            None => new_file(dir, &self.default_name),
        };
        let text = self.text();
        std::fs::write(&path, &text).map_err(|e| format!("cannot save {}: {e}", path.display()))?;
        if self.path.is_none() {
            // From now on errors name the file, and it is watched.
            self.source = path.display().to_string();
            self.scene = parse_scene(&text, &self.source, &self.default_name).unwrap_or_else(|_| self.scene.clone());
            self.path = Some(path.clone());
        }
        self.saved = Some(text);
        self.stamp = Stamp::of(&path);
        Ok(path)
    }
}

/// The `bars` array of the text.
fn bars_mut(doc: &mut DocumentMut) -> Result<&mut toml_edit::Array, String> {
    doc.get_mut("bars").and_then(|b| b.as_array_mut()).ok_or_else(|| "the scene has no `bars` array".to_string())
}

/// A finite TOML number, kept as written.
fn number(text: &str) -> Result<Value, String> {
    let value: Value = text.trim().parse().map_err(|_| format!("{text:?} is not a number"))?;
    match &value {
        Value::Float(f) if f.value().is_finite() => Ok(value),
        Value::Integer(_) => Ok(value),
        _ => Err(format!("{text:?} is not a finite number")),
    }
}

/// `NAME.toml` in `dir`, or `NAME-2.toml`, … : a file that does not exist yet.
fn new_file(dir: &Path, name: &str) -> PathBuf {
    let stem = super::export::file_safe(name);
    (1..)
        .map(|k| dir.join(if k == 1 { format!("{stem}.toml") } else { format!("{stem}-{k}.toml") }))
        .find(|p| !p.exists())
        .unwrap_or_else(|| dir.join("scene.toml"))
}

/// A number written for the file: `value` with enough decimals to keep every
/// digit of `old` and to land on the grid of `step` (a power of ten), so a
/// nudge of 0.1 from 0.2 writes 0.3, not 0.30000000000000004.
pub fn decimal(value: f64, old: f64, step: f64) -> String {
    let decimals_of = |x: f64| format!("{x}").split_once('.').map_or(0, |(_, f)| f.len());
    let step_decimals = if step > 0.0 && step < 1.0 { (-step.log10()).round() as usize } else { 0 };
    let d = decimals_of(old).max(step_decimals).min(330);
    let s = format!("{value:.d$}");
    // A decimal point, so it reads as a float.
    if d == 0 { format!("{s}.0") } else { s }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decimals_land_on_the_grid_and_keep_the_old_digits() {
        assert_eq!(decimal(0.2 + 0.1, 0.2, 0.1), "0.3");
        assert_eq!(decimal(0.342020143326 + 0.01, 0.342020143326, 0.01), "0.352020143326");
        assert_eq!(decimal(3.0 + 10.0, 3.0, 10.0), "13.0");
        assert_eq!(decimal(-0.05 - 0.01, -0.05, 0.01), "-0.06");
    }

    #[test]
    fn new_files_are_named_after_the_scene_and_never_overwrite() {
        let dir = std::env::temp_dir().join(format!("caymos-newfile-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = new_file(&dir, "Grashof crank-rocker");
        assert_eq!(p.file_name().unwrap(), "grashof-crank-rocker.toml");
        std::fs::write(&p, "").unwrap();
        assert_eq!(new_file(&dir, "Grashof crank-rocker").file_name().unwrap(), "grashof-crank-rocker-2.toml");
        std::fs::remove_dir_all(&dir).ok();
    }
}
