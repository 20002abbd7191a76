//! Export the current view: the current motion's trace as CSV (the traced
//! joints, and the input bar's angle when one is chosen) and the drawing
//! with its traces as SVG, next to each other in a directory, named after
//! the scene and never over an existing file.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use crate::commands::{self, TraceColumns, Walk};
use crate::tolerance;

use super::app::Model;

/// What an export wrote, and what its walk met.
#[derive(Clone, Debug)]
pub struct Exported {
    pub csv: PathBuf,
    pub svg: PathBuf,
    /// Data rows of the CSV.
    pub rows: usize,
    /// What the walks met (the sample budget, jumps), in words.
    pub notes: Vec<String>,
}

/// `name` as a file-name stem: ASCII letters, digits, `-` and `_` kept
/// (lower-cased), anything else `-`; `scene` when nothing is left.
pub fn file_safe(name: &str) -> String {
    let stem: String = name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '_' { c.to_ascii_lowercase() } else { '-' })
        .collect();
    if stem.trim_matches('-').is_empty() { "scene".to_string() } else { stem }
}

/// A file in `dir` that does not exist yet: `STEM-SUFFIX.EXT`, then `STEM-SUFFIX-1.EXT`, …
/// (`STEM.EXT`, `STEM-1.EXT`, … for an empty suffix); the stem made file-safe.
/// Created empty here (`create_new`), so two exports never write one file.
pub fn fresh_file(dir: &Path, stem: &str, suffix: &str, ext: &str) -> Result<(PathBuf, std::fs::File), String> {
    let stem = file_safe(stem);
    let base = if suffix.is_empty() { stem } else { format!("{stem}-{suffix}") };
    for k in 0..10_000 {
        let path = dir.join(if k == 0 { format!("{base}.{ext}") } else { format!("{base}-{k}.{ext}") });
        match std::fs::OpenOptions::new().write(true).create_new(true).open(&path) {
            Ok(f) => return Ok((path, f)),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(format!("cannot write {}: {e}", path.display())),
        }
    }
    Err(format!("{}: {base}.{ext} and 10000 numbered copies exist already", dir.display()))
}

/// Write `STEM-trace.csv` and `STEM.svg` into `dir` for the model's current
/// motion (a component, or the path being followed): the traced joints (all
/// when none is traced), with the input bar's angle column when one is chosen.
pub fn export(m: &Model, stem: &str, dir: &Path) -> Result<Exported, String> {
    let (a, s) = (m.analysis(), m.solved());
    let mut joints: Vec<usize> = (0..m.traces.traced.len()).filter(|&j| m.traces.traced[j]).collect();
    if joints.is_empty() {
        joints = (0..a.linkage.n_joints()).collect();
    }
    let walk = Walk { step: commands::default_step(a), max_samples: tolerance::DEFAULT_MAX_SAMPLES };
    let columns = TraceColumns { joints: joints.clone(), angle: m.drive.input, cayley: false };
    let (csv, file) = fresh_file(dir, stem, "trace", "csv")?;
    let mut out = std::io::BufWriter::new(file);
    let summary = commands::trace_csv(&a.linkage, s, m.cursor.segments.clone(), &columns, walk, &mut out)
        .and_then(|sm| out.flush().map(|_| sm))
        .map_err(|e| format!("cannot write {}: {e}", csv.display()))?;
    let (svg, mut file) = fresh_file(dir, stem, "", "svg")?;
    let drawing = commands::svg(&a.scene.name, &a.linkage, s, m.cursor.segments.clone(), &joints, walk);
    file.write_all(drawing.text.as_bytes()).map_err(|e| format!("cannot write {}: {e}", svg.display()))?;
    let mut notes = crate::present::walk_notes(&summary, walk.max_samples);
    if drawing.points_cut {
        notes.push(crate::present::svg_cut_note(joints.len()));
    }
    Ok(Exported { csv, svg, rows: summary.samples, notes })
}
