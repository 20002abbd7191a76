//! Scene files: the TOML format a user writes (joints, bars, bodies), parsed and
//! validated into a [`Scene`]. Everything else (clusters, steps, intervals) is
//! derived by the solver; a scene states only what the mechanism is.
//!
//! Every error names the file and, where it applies, the line and column or the
//! offending joint or bar. Parsing never panics.

use std::fmt;
use std::path::Path;

/// A joint as drawn: its name, position (y up) and the 1-based line it was declared on.
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    pub name: String,
    pub pos: [f64; 2],
    pub line: usize,
}

/// A bar between two joints (indices into `Scene::joints`). `length` is the
/// stated length when the file gives one; otherwise the drawn distance is meant.
#[derive(Debug, Clone, PartialEq)]
pub struct Bar {
    pub joints: [usize; 2],
    pub length: Option<f64>,
    pub line: usize,
}

/// A rigid body of three or more joints whose shape is the drawn one.
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    pub joints: Vec<usize>,
    pub line: usize,
}

/// A validated scene. Indices always refer to `joints`.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    pub name: String,
    pub description: Option<String>,
    /// Where the scene came from, as shown in error messages (a path, or `bundled:NAME`).
    pub source: String,
    pub joints: Vec<Joint>,
    pub bars: Vec<Bar>,
    pub bodies: Vec<Body>,
    /// The requested base non-edge and the line it was given on.
    pub base: Option<([usize; 2], usize)>,
    /// Joints held still on screen: one or two joints; defaults to the first bar's joints.
    pub ground: Vec<usize>,
}

/// A scene that could not be read, with where the problem is.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneError {
    pub file: String,
    pub line: Option<usize>,
    pub column: Option<usize>,
    pub message: String,
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file)?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
            if let Some(col) = self.column {
                write!(f, ":{col}")?;
            }
        }
        write!(f, ": {}", self.message)
    }
}

impl std::error::Error for SceneError {}

impl Scene {
    /// Index of the joint called `name`.
    pub fn joint_index(&self, name: &str) -> Option<usize> {
        self.joints.iter().position(|j| j.name == name)
    }

    /// Whether any bar states its length (then the drawing is only a sketch).
    pub fn is_sketch(&self) -> bool {
        self.bars.iter().any(|b| b.length.is_some())
    }

    /// A line-anchored error about this scene.
    pub fn error_at(&self, line: Option<usize>, message: impl Into<String>) -> SceneError {
        SceneError { file: self.source.clone(), line, column: None, message: message.into() }
    }
}

/// Parse scene text. `source` names the file in errors; `default_name` is used
/// when the file has no `name` key (callers pass the file stem).
pub fn parse_scene(text: &str, source: &str, default_name: &str) -> Result<Scene, SceneError> {
    let _ = (text, source, default_name);
    todo!("implemented by the scene parser work")
}

/// Read and parse a scene file; non-UTF-8 bytes and I/O errors become [`SceneError`]s.
pub fn load_scene(path: &Path) -> Result<Scene, SceneError> {
    let _ = path;
    todo!("implemented by the scene parser work")
}
