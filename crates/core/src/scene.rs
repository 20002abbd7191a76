//! Scene files: the TOML format a user writes (joints, bars, bodies), parsed and
//! validated into a [`Scene`]. Everything else (clusters, steps, intervals) is
//! derived by the solver; a scene states only what the mechanism is.
//!
//! Every error names the file and, where it applies, the line and column or the
//! offending joint or bar. Parsing never panics.

use std::collections::HashMap;
use std::fmt;
use std::ops::Range;
use std::path::Path;

use toml::Spanned;

use crate::exact::Decimal;
use crate::real::{Dd, Real};
use toml::de::{DeArray, DeString, DeTable, DeValue};

/// A joint as drawn: its name, position (y up) and the 1-based line it was declared on.
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    /// The joint's name, as in the file.
    pub name: String,
    /// Its drawn position (scene units, y up).
    pub pos: [f64; 2],
    /// The coordinates as written, in double-double (`pos` is them rounded).
    pub exact: [Dd; 2],
    /// The coordinates as written, exactly (`None`: made in code, where
    /// `pos` is what was written).
    pub written: [Option<Decimal>; 2],
    /// The 1-based line it is declared on.
    pub line: usize,
}

/// A bar between two joints (indices into `Scene::joints`). `length` is the
/// stated length when the file gives one; otherwise the drawn distance is meant.
#[derive(Debug, Clone, PartialEq)]
pub struct Bar {
    /// The two joints (indices into `Scene::joints`).
    pub joints: [usize; 2],
    /// The stated length, if any (scene units).
    pub length: Option<f64>,
    /// The stated length as written, in double-double.
    pub exact_length: Option<Dd>,
    /// The stated length as written, exactly (`None`: not stated, or made in code).
    pub written_length: Option<Decimal>,
    /// The 1-based line it is declared on.
    pub line: usize,
}

/// A rigid body of three or more joints whose shape is the drawn one.
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    /// Its joints (indices into `Scene::joints`).
    pub joints: Vec<usize>,
    /// The 1-based line it is declared on.
    pub line: usize,
}

/// A validated scene. Indices always refer to `joints`.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// The scene's name (from the file, else the default its reader was given).
    pub name: String,
    /// Its description, if the file gives one.
    pub description: Option<String>,
    /// Where the scene came from, as shown in error messages (a path, or `bundled:NAME`).
    pub source: String,
    /// The joints, in file order.
    pub joints: Vec<Joint>,
    /// The bars, in file order.
    pub bars: Vec<Bar>,
    /// The rigid bodies, in file order.
    pub bodies: Vec<Body>,
    /// The requested base non-edge and the line it was given on.
    pub base: Option<([usize; 2], usize)>,
    /// Joints held still on screen: one or two joints; defaults to the first bar's joints.
    pub ground: Vec<usize>,
}

/// A scene that could not be read, with where the problem is.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneError {
    /// The file (or source) the error is in.
    pub file: String,
    /// The 1-based line, when known.
    pub line: Option<usize>,
    /// The 1-based column, when known.
    pub column: Option<usize>,
    /// What is wrong, as a sentence.
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

    /// Index of the bar joining joints `a` and `b` (either order).
    pub fn bar_index(&self, a: usize, b: usize) -> Option<usize> {
        self.bars.iter().position(|bar| bar.joints == [a, b] || bar.joints == [b, a])
    }

    /// The joints named by `text` as a pair (`B-C`, `B–C`, `B,C` or `B C`), if both exist.
    pub fn joint_pair(&self, text: &str) -> Option<[usize; 2]> {
        let names: Vec<&str> = text.split(['-', '–', ' ', ',']).filter(|p| !p.is_empty()).collect();
        match names[..] {
            [a, b] => Some([self.joint_index(a)?, self.joint_index(b)?]),
            _ => None,
        }
    }

    /// Bar `i`'s length: stated, else drawn.
    pub fn bar_length(&self, i: usize) -> f64 {
        let [a, b] = self.bars[i].joints;
        self.bars[i].length.unwrap_or_else(|| crate::linkage::dist(self.joints[a].pos, self.joints[b].pos))
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

/// The top-level keys a scene may use; anything else (such as a typo) is an error.
const TOP_LEVEL_KEYS: [&str; 7] = ["name", "description", "base", "ground", "bars", "bodies", "joints"];

/// A TOML value together with its byte span in the scene text.
type Value<'i> = Spanned<DeValue<'i>>;

/// Parse scene text. `source` names the file in errors; `default_name` is used
/// when the file has no `name` key (callers pass the file stem).
///
/// Validated here: TOML syntax; only known top-level keys; the type of every
/// value; joints (a non-empty `[joints]` table of finite `[x, y]` positions
/// with visible names, no two at the same point relative to the scene's
/// scale); bars (at least one; two known, distinct joints; an optional
/// positive finite length; no duplicates in either order; a bar between two
/// joints of one body must agree with the body's drawn shape); bodies (at
/// least three known, distinct joints); the base (two known, distinct joints
/// that are not a bar); the ground (one or two known, distinct joints).
/// Connectivity and rigidity are left to the solver.
pub fn parse_scene(text: &str, source: &str, default_name: &str) -> Result<Scene, SceneError> {
    let doc = Doc::new(text, source);
    let root = DeTable::parse(text).map_err(|e| doc.syntax_error(&e))?;
    let table = root.get_ref();
    if table.is_empty() {
        return Err(doc.error(None, "the file is empty: a scene needs a [joints] table and a `bars` array"));
    }
    check_top_level_keys(&doc, table)?;

    let name = match optional_string(&doc, table, "name")? {
        Some(name) => name,
        None => default_name.to_string(),
    };
    let description = optional_string(&doc, table, "description")?;
    let joints = parse_joints(&doc, table.get("joints"))?;
    let names = JointNames::new(&joints);
    let bars = parse_bars(&doc, &names, table.get("bars"))?;
    let bodies = parse_bodies(&doc, &names, table.get("bodies"))?;
    let half_scale = half_scale(&joints, &bars, &bodies);
    check_normal_scale(&doc, &bars, half_scale)?;
    check_distinct_positions(&doc, &joints, &bars, half_scale)?;
    check_bars_within_bodies(&doc, &joints, &bars, &bodies, half_scale)?;
    let base = parse_base(&doc, &names, &bars, table.get("base"))?;
    let ground = parse_ground(&doc, &names, &bars, table.get("ground"))?;

    Ok(Scene { name, description, source: source.to_string(), joints, bars, bodies, base, ground })
}

/// The largest scene file read: a 100,000-step chain takes about 30 MB, so
/// anything past this is not a scene (`/dev/zero`, a stray binary), and is
/// refused before it is held in memory.
pub const MAX_SCENE_BYTES: u64 = 40 << 20;

/// Read and parse a scene file; non-UTF-8 bytes, I/O errors and files over
/// [`MAX_SCENE_BYTES`] become [`SceneError`]s.
/// The file stem is the scene's name when the file has no `name` key.
pub fn load_scene(path: &Path) -> Result<Scene, SceneError> {
    use std::io::Read;
    let file = path.display().to_string();
    let error = |message: String| SceneError { file: file.clone(), line: None, column: None, message };
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(MAX_SCENE_BYTES + 1).read_to_end(&mut bytes))
        .map_err(|e| error(format!("cannot read: {e}")))?;
    if bytes.len() as u64 > MAX_SCENE_BYTES {
        return Err(error(format!(
            "the file is larger than {} MiB: not a scene (a 100,000-step chain takes about 30 MB)",
            MAX_SCENE_BYTES >> 20
        )));
    }
    let text = match String::from_utf8(bytes) {
        Ok(text) => text,
        Err(e) => return Err(not_utf8_error(&file, e.as_bytes(), e.utf8_error())),
    };
    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    parse_scene(&text, &file, &stem)
}

/// The error for a file that is not UTF-8, located at the first bad byte.
fn not_utf8_error(file: &str, bytes: &[u8], error: std::str::Utf8Error) -> SceneError {
    let offset = error.valid_up_to();
    let valid = std::str::from_utf8(&bytes[..offset]).unwrap_or_default();
    let doc = Doc::new(valid, file);
    let bad = bytes.get(offset).copied().unwrap_or_default();
    doc.error(Some(offset), format!("the file is not valid UTF-8 (byte 0x{bad:02X} at byte offset {offset})"))
}

// ---------------------------------------------------------------------------
// Positions in the text and error construction

/// The scene text being parsed: turns byte offsets into 1-based lines and
/// columns (columns count characters) and builds errors located there.
struct Doc<'a> {
    text: &'a str,
    file: &'a str,
    /// Byte offset where each line starts.
    line_starts: Vec<usize>,
}

impl<'a> Doc<'a> {
    fn new(text: &'a str, file: &'a str) -> Self {
        let line_starts = std::iter::once(0).chain(text.match_indices('\n').map(|(i, _)| i + 1)).collect();
        Doc { text, file, line_starts }
    }

    /// 1-based line and character column of a byte offset (clamped into the text).
    fn line_column(&self, offset: usize) -> (usize, usize) {
        let mut offset = offset.min(self.text.len());
        while !self.text.is_char_boundary(offset) {
            offset -= 1;
        }
        let line = self.line_starts.partition_point(|&start| start <= offset);
        let start = self.line_starts[line - 1];
        let column = self.text[start..offset].chars().count() + 1;
        (line, column)
    }

    /// 1-based line of the start of `span`.
    fn line(&self, span: Range<usize>) -> usize {
        self.line_column(span.start).0
    }

    /// The source text of `span`, as the user wrote it.
    fn raw(&self, span: Range<usize>) -> &str {
        self.text.get(span).unwrap_or("?").trim()
    }

    /// An error at a byte offset, or not tied to a place when `offset` is `None`.
    fn error(&self, offset: Option<usize>, message: impl Into<String>) -> SceneError {
        let (line, column) = match offset.map(|o| self.line_column(o)) {
            Some((line, column)) => (Some(line), Some(column)),
            None => (None, None),
        };
        SceneError { file: self.file.to_string(), line, column, message: one_line(&message.into()) }
    }

    /// An error at the start of a spanned value.
    fn error_at<T>(&self, value: &Spanned<T>, message: impl Into<String>) -> SceneError {
        self.error(Some(value.span().start), message)
    }

    /// An error on a whole line (no column).
    fn error_on_line(&self, line: usize, message: impl Into<String>) -> SceneError {
        SceneError { file: self.file.to_string(), line: Some(line), column: None, message: one_line(&message.into()) }
    }

    /// A TOML syntax error as one line: the parser's message, without the snippet.
    fn syntax_error(&self, error: &toml::de::Error) -> SceneError {
        let offset = error.span().map(|span| span.start);
        self.error(offset, format!("TOML syntax error: {}", error.message()))
    }
}

/// Collapses line breaks and other control characters so an error stays on one line.
fn one_line(message: &str) -> String {
    let words: Vec<&str> =
        message.split(|c: char| c.is_control()).map(str::trim).filter(|part| !part.is_empty()).collect();
    words.join("; ")
}

/// A name as shown inside labels such as `bar 3 (X–Q)`: as written, unless it
/// contains control characters, which are escaped.
fn shown(name: &str) -> String {
    if name.chars().any(char::is_control) { name.escape_debug().to_string() } else { name.to_string() }
}

/// "a string", "an integer", ... for messages about a value of the wrong type.
fn kind(value: &DeValue<'_>) -> &'static str {
    match value {
        DeValue::String(_) => "a string",
        DeValue::Integer(_) => "an integer",
        DeValue::Float(_) => "a float",
        DeValue::Boolean(_) => "a boolean",
        DeValue::Datetime(_) => "a date-time",
        DeValue::Array(_) => "an array",
        DeValue::Table(_) => "a table",
    }
}

// ---------------------------------------------------------------------------
// Top-level keys and scalars

/// Every top-level key must be one of [`TOP_LEVEL_KEYS`]; a near miss gets a suggestion.
fn check_top_level_keys(doc: &Doc, table: &DeTable) -> Result<(), SceneError> {
    for (key, _) in table.iter() {
        let key_name = key.get_ref().as_ref();
        if TOP_LEVEL_KEYS.contains(&key_name) {
            continue;
        }
        let lowercase = key_name.to_lowercase();
        let hint = TOP_LEVEL_KEYS
            .iter()
            .map(|known| (edit_distance(known, &lowercase), known))
            .filter(|&(distance, _)| distance <= 2)
            .min()
            .map(|(_, known)| format!(" (did you mean `{known}`?)"))
            .unwrap_or_default();
        return Err(doc.error_at(
            key,
            format!("unknown key `{}`{hint}; the allowed keys are {}", shown(key_name), TOP_LEVEL_KEYS.join(", ")),
        ));
    }
    Ok(())
}

/// Levenshtein distance between two short strings.
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let substitution = diagonal + usize::from(ca != cb);
            diagonal = row[j + 1];
            row[j + 1] = substitution.min(row[j] + 1).min(row[j + 1] + 1);
        }
    }
    row[b.len()]
}

/// An optional non-empty string value such as `name` or `description`.
fn optional_string(doc: &Doc, table: &DeTable, key: &str) -> Result<Option<String>, SceneError> {
    let Some(value) = table.get(key) else {
        return Ok(None);
    };
    match value.get_ref() {
        DeValue::String(s) if s.trim().is_empty() => Err(doc.error_at(value, format!("`{key}` must not be empty"))),
        DeValue::String(s) => Ok(Some(s.to_string())),
        other => Err(doc.error_at(value, format!("`{key}` must be a string, found {}", kind(other)))),
    }
}

/// A finite number as written: its f64, its double-double and the exact
/// decimal (TOML integer or float). `what` names it in errors, e.g.
/// `joint "A": x coordinate`. `-0` is read as `0`.
fn exact_number(doc: &Doc, value: &Value, what: &str) -> Result<(f64, Dd, Option<Decimal>), SceneError> {
    let raw = doc.raw(value.span());
    let number = match value.get_ref() {
        DeValue::Integer(int) => i64::from_str_radix(int.as_str(), int.radix())
            .map_err(|_| doc.error_at(value, format!("{what} {raw} is out of range")))?
            as f64,
        DeValue::Float(float) => float.as_str().parse::<f64>().unwrap_or(f64::NAN),
        other => {
            return Err(doc.error_at(value, format!("{what} must be a number, found {}", kind(other))));
        }
    };
    if !number.is_finite() {
        return Err(doc.error_at(value, format!("{what} must be a finite number, found {raw}")));
    }
    let number = number + 0.0;
    let exact = match value.get_ref() {
        DeValue::Float(float) => Dd::parse_decimal(float.as_str()).filter(|x| x.to_f64() == number),
        _ => None,
    };
    let written = match value.get_ref() {
        DeValue::Float(float) => exact.and(Decimal::parse(float.as_str())),
        // An integer as f64 is itself where it is exact (below 2^53).
        DeValue::Integer(_) => (number.abs() < 2f64.powi(53)).then(|| Decimal::integer(number as i64)),
        _ => None,
    };
    Ok((number, exact.unwrap_or(Dd::new(number)), written))
}

/// The elements of an array value, or an error saying what was expected instead.
fn array<'v, 'i>(doc: &Doc, value: &'v Value<'i>, what: &str, expected: &str) -> Result<&'v DeArray<'i>, SceneError> {
    match value.get_ref() {
        DeValue::Array(items) => Ok(items),
        other => Err(doc.error_at(value, format!("{what} must be {expected}, found {}", kind(other)))),
    }
}

// ---------------------------------------------------------------------------
// Joints

/// Parses `[joints]`: a non-empty table of `NAME = [x, y]` with finite numbers,
/// kept in file order. Each joint's line is the line of its name.
fn parse_joints(doc: &Doc, value: Option<&Value>) -> Result<Vec<Joint>, SceneError> {
    let Some(value) = value else {
        return Err(doc.error(None, "missing [joints] table: list each joint as NAME = [x, y]"));
    };
    let DeValue::Table(table) = value.get_ref() else {
        return Err(
            doc.error_at(value, format!("`joints` must be a table of NAME = [x, y], found {}", kind(value.get_ref())))
        );
    };
    if table.is_empty() {
        return Err(doc.error_at(value, "[joints] lists no joints"));
    }
    table
        .iter()
        .map(|(key, position)| parse_joint(doc, key, position).map_err(|error| misplaced_key_hint(error, key)))
        .collect()
}

/// A top-level key written after `[joints]` lands inside the table as a joint;
/// when such a "joint" is invalid, say how to fix it.
fn misplaced_key_hint(mut error: SceneError, key: &Spanned<DeString>) -> SceneError {
    let name = key.get_ref().as_ref();
    if TOP_LEVEL_KEYS.contains(&name) {
        error.message += &format!(" (to set `{name}`, put it before the [joints] table)");
    }
    error
}

/// One joint: a non-empty name and a position `[x, y]` of two finite numbers.
fn parse_joint(doc: &Doc, key: &Spanned<DeString>, value: &Value) -> Result<Joint, SceneError> {
    let name = key.get_ref().as_ref();
    if name.is_empty() {
        return Err(doc.error_at(key, "a joint name must not be empty"));
    }
    if name.trim().is_empty() {
        return Err(doc.error_at(key, format!("joint name {name:?} is only whitespace: give the joint a visible name")));
    }
    let what = format!("joint {name:?}");
    let DeValue::Array(coords) = value.get_ref() else {
        return Err(doc.error_at(value, format!("{what}: expected a position [x, y], found {}", kind(value.get_ref()))));
    };
    let [x, y] = coords.as_ref() else {
        return Err(doc.error_at(
            value,
            format!("{what}: expected a position [x, y] of 2 numbers, found {} element(s)", coords.len()),
        ));
    };
    let (x, exact_x, written_x) = exact_number(doc, x, &format!("{what}: x coordinate"))?;
    let (y, exact_y, written_y) = exact_number(doc, y, &format!("{what}: y coordinate"))?;
    let (pos, exact, written) = ([x, y], [exact_x, exact_y], [written_x, written_y]);
    Ok(Joint { name: name.to_string(), pos, exact, written, line: doc.line(key.span()) })
}

/// Half the scene's scale, as the solver defines it
/// (`Linkage::scale`): the longest bar (stated length, else
/// drawn) or body span. Halved so that drawings near ±f64::MAX stay finite.
fn half_scale(joints: &[Joint], bars: &[Bar], bodies: &[Body]) -> f64 {
    let half_dist = |a: usize, b: usize| half_distance(joints[a].pos, joints[b].pos);
    let bar_lengths = bars.iter().map(|b| b.length.map_or_else(|| half_dist(b.joints[0], b.joints[1]), |l| l / 2.0));
    let spans = bodies.iter().flat_map(|body| {
        body.joints.iter().enumerate().flat_map(move |(i, &p)| body.joints[i + 1..].iter().map(move |&q| (p, q)))
    });
    bar_lengths.chain(spans.map(|(p, q)| half_dist(p, q))).fold(0.0, f64::max)
}

/// Half the distance between two points (finite for any finite points).
fn half_distance(p: [f64; 2], q: [f64; 2]) -> f64 {
    (p[0] / 2.0 - q[0] / 2.0).hypot(p[1] / 2.0 - q[1] / 2.0)
}

/// Whether two points are drawn at the same point: exactly equal, or the
/// same to [`crate::tolerance::same_drawn_point`].
fn same_point(p: [f64; 2], q: [f64; 2], half_scale: f64) -> bool {
    let half_magnitude = p.iter().chain(&q).fold(0.0f64, |m, x| m.max(x.abs())) / 2.0;
    p == q || crate::tolerance::same_drawn_point(half_distance(p, q), half_magnitude, half_scale)
}

/// The scene's scale must be a normal f64 (at least `f64::MIN_POSITIVE`,
/// 2.2e-308): below it lengths lose digits (subnormal numbers), and a
/// scene at 1e-310 gave a wrong Cayley space. The error is on the first
/// bar's line; a scale of zero (every joint at one point) is left to the
/// same-point check.
fn check_normal_scale(doc: &Doc, bars: &[Bar], half_scale: f64) -> Result<(), SceneError> {
    let scale = 2.0 * half_scale;
    if scale == 0.0 || scale >= f64::MIN_POSITIVE {
        return Ok(());
    }
    let line = bars.first().map_or(1, |b| b.line);
    Err(doc.error_on_line(
        line,
        format!(
            "the scene's scale (its longest bar or body) is {scale:e}, below f64's normal range ({:e}): write the scene in larger units",
            f64::MIN_POSITIVE
        ),
    ))
}

/// No two joints may be drawn at the same point (see [`same_point`]): the
/// error is on the later joint's line. The scale is the scene's, not the
/// drawing's extent, so a far-away joint does not merge two near ones.
fn check_distinct_positions(doc: &Doc, joints: &[Joint], bars: &[Bar], half_scale: f64) -> Result<(), SceneError> {
    let Some((i, j)) = first_same_point(joints, half_scale) else { return Ok(()) };
    let (later, earlier) = (&joints[i], &joints[j]);
    // Apart, but not at the scene's scale: say what sets it (a stated
    // length far beyond the drawing, say).
    let scale = if later.pos == earlier.pos {
        String::new()
    } else {
        let stated = bars.iter().find(|b| b.length.is_some_and(|l| l / 2.0 == half_scale));
        let by = stated.map_or(String::new(), |b| {
            let [p, q] = b.joints.map(|j| joints[j].name.as_str());
            format!(" (bar {p}–{q}'s stated length, line {})", b.line)
        });
        format!(", to within {:e} of the scene's scale {:e}{by}", crate::tolerance::COINCIDENT, 2.0 * half_scale)
    };
    Err(doc.error_on_line(
        later.line,
        format!(
            "joint {:?} is drawn at the same point as joint {:?} (line {}){scale}",
            later.name, earlier.name, earlier.line
        ),
    ))
}

/// The first joint (in file order) drawn at the same point as an earlier
/// one ([`same_point`]), and the first such earlier joint. Each joint is
/// compared only with those in the 3 × 3 cells of a grid around it, cells
/// twice as wide as the farthest two same points can be apart: linear in
/// the joints for a drawing (every pair was compared: a path of 100,000
/// joints spent 37 s here). Where no such grid exists (a scale of zero, or
/// cells too fine to index) every pair is compared.
fn first_same_point(joints: &[Joint], half_scale: f64) -> Option<(usize, usize)> {
    let same = |i: usize, j: usize| same_point(joints[i].pos, joints[j].pos, half_scale);
    let every_pair = || (0..joints.len()).find_map(|i| (0..i).find(|&j| same(i, j)).map(|j| (i, j)));
    let half_magnitude = joints.iter().flat_map(|j| j.pos).fold(0.0f64, |m, x| m.max(x.abs())) / 2.0;
    let width = 2.0 * crate::tolerance::same_drawn_point_reach(half_magnitude, half_scale);
    // Cell indices stay well inside i64 (|x| / width ≤ 1 / (16 ε) for the widths the resolution term sets).
    let cell_of = |p: [f64; 2]| p.map(|x| (x / 2.0 / width).floor());
    if !(width > 0.0 && width.is_finite()) || joints.iter().any(|j| cell_of(j.pos).iter().any(|c| c.abs() > 1e17)) {
        return every_pair();
    }
    let mut cells: crate::inthash::IntMap<[i64; 2], Vec<usize>> = crate::inthash::int_map(joints.len());
    for (i, joint) in joints.iter().enumerate() {
        let [cx, cy] = cell_of(joint.pos).map(|c| c as i64);
        let earlier = (-1..=1)
            .flat_map(|dx| (-1..=1).map(move |dy| [cx + dx, cy + dy]))
            .filter_map(|c| cells.get(&c))
            .flatten()
            .copied()
            .filter(|&j| same(i, j))
            .min();
        if let Some(j) = earlier {
            return Some((i, j));
        }
        cells.entry([cx, cy]).or_default().push(i);
    }
    None
}

/// Whether a bar's length agrees with the distance at which a body holds its
/// joints: within [`crate::tolerance::BAR_RESIDUAL`] × the scene's scale (the
/// accuracy a realization meets its bars to). The solver uses the same test.
pub fn body_bar_agrees(bar_length: f64, body_distance: f64, scale: f64) -> bool {
    (bar_length - body_distance).abs() <= crate::tolerance::BAR_RESIDUAL * scale
}

/// A bar between two joints of one body repeats what the body holds: with a
/// stated length that disagrees with the body's drawn shape it contradicts
/// the body, an error on the bar's line. (One that agrees is accepted; the
/// solver ignores it and says so.)
fn check_bars_within_bodies(
    doc: &Doc,
    joints: &[Joint],
    bars: &[Bar],
    bodies: &[Body],
    half_scale: f64,
) -> Result<(), SceneError> {
    for (i, bar) in bars.iter().enumerate() {
        let [a, b] = bar.joints;
        let Some(stated) = bar.length else { continue };
        let Some((k, body)) =
            bodies.iter().enumerate().find(|(_, body)| body.joints.contains(&a) && body.joints.contains(&b))
        else {
            continue;
        };
        let half_drawn = half_distance(joints[a].pos, joints[b].pos);
        if !body_bar_agrees(stated / 2.0, half_drawn, half_scale) {
            let names: Vec<&str> = body.joints.iter().map(|&j| joints[j].name.as_str()).collect();
            return Err(doc.error_on_line(
                bar.line,
                format!(
                    "bar {} ({}–{}): its stated length {stated} disagrees with body {} [{}] (line {}), which holds {} and {} {} apart as drawn; drop the bar or make them agree",
                    i + 1,
                    shown(&joints[a].name),
                    shown(&joints[b].name),
                    k + 1,
                    names.join(", "),
                    body.line,
                    shown(&joints[a].name),
                    shown(&joints[b].name),
                    crate::numfmt::fmt_num(half_drawn * 2.0)
                ),
            ));
        }
    }
    Ok(())
}

/// Joint name → index, for resolving the names used by bars, bodies, base and ground.
struct JointNames<'s> {
    index: HashMap<&'s str, usize>,
}

impl<'s> JointNames<'s> {
    fn new(joints: &'s [Joint]) -> Self {
        let index = joints.iter().enumerate().map(|(i, joint)| (joint.name.as_str(), i)).collect();
        JointNames { index }
    }

    /// The index of the joint named by `value`, which must be a string naming a
    /// declared joint. `item` (e.g. `bar 3 (X–Q)`) prefixes the error.
    fn resolve(&self, doc: &Doc, value: &Value, item: &str) -> Result<usize, SceneError> {
        let DeValue::String(name) = value.get_ref() else {
            return Err(doc.error_at(
                value,
                format!("{item}: expected a joint name (a string), found {}", kind(value.get_ref())),
            ));
        };
        self.index
            .get(name.as_ref())
            .copied()
            .ok_or_else(|| doc.error_at(value, format!("{item}: unknown joint {name:?}")))
    }
}

/// The joint names an array lists, as `A–B–C`; `None` when some element is
/// not a string or the array is empty.
fn joint_list(parts: &[Value]) -> Option<String> {
    let names: Option<Vec<String>> = parts.iter().map(|part| part.get_ref().as_str().map(shown)).collect();
    names.filter(|names| !names.is_empty()).map(|names| names.join("–"))
}

/// `prefix (A–B–C)` naming an item by the joints it lists, or just `prefix`
/// when the joints cannot be shown.
fn label(prefix: &str, parts: &[Value]) -> String {
    match joint_list(parts) {
        Some(list) => format!("{prefix} ({list})"),
        None => prefix.to_string(),
    }
}

// ---------------------------------------------------------------------------
// Bars and bodies

/// Parses `bars`: a non-empty array of `[A, B]` or `[A, B, length]`. Each bar
/// joins two known, distinct joints; a stated length is a positive finite
/// number; no two bars join the same pair of joints (in either order).
fn parse_bars(doc: &Doc, names: &JointNames, value: Option<&Value>) -> Result<Vec<Bar>, SceneError> {
    let Some(value) = value else {
        return Err(doc.error(None, "no bars: add `bars = [[\"A\", \"B\"], ...]` before the [joints] table"));
    };
    let items = array(doc, value, "`bars`", "an array of bars like [\"A\", \"B\"]")?;
    if items.is_empty() {
        return Err(doc.error_at(value, "`bars` is empty: a scene needs at least one bar"));
    }
    let mut earlier: HashMap<[usize; 2], (usize, usize)> = HashMap::new();
    let mut bars = Vec::with_capacity(items.len());
    for (i, item) in items.iter().enumerate() {
        let number = i + 1;
        let bar = parse_bar(doc, names, number, item)?;
        let [a, b] = bar.joints;
        let pair = [a.min(b), a.max(b)];
        if let Some((other, other_line)) = earlier.get(&pair) {
            let item_label = label(&format!("bar {number}"), &items_of(item)[..2]);
            return Err(doc.error_at(item, format!("{item_label}: duplicates bar {other} on line {other_line}")));
        }
        earlier.insert(pair, (number, bar.line));
        bars.push(bar);
    }
    Ok(bars)
}

/// The elements of an array value (empty for any other value).
fn items_of<'v, 'i>(value: &'v Value<'i>) -> &'v [Value<'i>] {
    match value.get_ref() {
        DeValue::Array(items) => items,
        _ => &[],
    }
}

/// One bar, number `number` (1-based) in the `bars` array.
fn parse_bar(doc: &Doc, names: &JointNames, number: usize, item: &Value) -> Result<Bar, SceneError> {
    let prefix = format!("bar {number}");
    let parts = array(doc, item, &prefix, "an array [\"A\", \"B\"] or [\"A\", \"B\", length]")?;
    let item_label = label(&prefix, &parts[..parts.len().min(2)]);
    let (first, second, length) = match parts.as_ref() {
        [a, b] => (a, b, None),
        [a, b, length] => (a, b, Some(length)),
        _ => {
            return Err(doc.error_at(
                item,
                format!(
                    "{item_label}: expected 2 joint names and an optional length, found {} element(s)",
                    parts.len()
                ),
            ));
        }
    };
    let a = names.resolve(doc, first, &item_label)?;
    let b = names.resolve(doc, second, &item_label)?;
    if a == b {
        return Err(doc.error_at(item, format!("{item_label}: a bar cannot join a joint to itself")));
    }
    let (length, exact_length, written_length) = match length {
        Some(value) => {
            let (l, exact, written) = positive_length(doc, value, &item_label)?;
            (Some(l), Some(exact), written)
        }
        None => (None, None, None),
    };
    Ok(Bar { joints: [a, b], length, exact_length, written_length, line: doc.line(item.span()) })
}

/// A stated bar length: a finite number greater than zero.
fn positive_length(doc: &Doc, value: &Value, item_label: &str) -> Result<(f64, Dd, Option<Decimal>), SceneError> {
    let (length, exact, written) = exact_number(doc, value, &format!("{item_label}: length"))?;
    if length <= 0.0 {
        return Err(
            doc.error_at(value, format!("{item_label}: length must be positive, found {}", doc.raw(value.span())))
        );
    }
    Ok((length, exact, written))
}

/// Parses the optional `bodies`: an array of arrays of at least three known,
/// distinct joints.
fn parse_bodies(doc: &Doc, names: &JointNames, value: Option<&Value>) -> Result<Vec<Body>, SceneError> {
    let Some(value) = value else {
        return Ok(Vec::new());
    };
    let items = array(doc, value, "`bodies`", "an array of bodies like [\"A\", \"B\", \"C\"]")?;
    items.iter().enumerate().map(|(i, item)| parse_body(doc, names, i + 1, item)).collect()
}

/// One body, number `number` (1-based) in the `bodies` array.
fn parse_body(doc: &Doc, names: &JointNames, number: usize, item: &Value) -> Result<Body, SceneError> {
    let prefix = format!("body {number}");
    let parts = array(doc, item, &prefix, "an array of joint names [\"A\", \"B\", \"C\", ...]")?;
    let item_label = label(&prefix, parts);
    if parts.len() < 3 {
        return Err(doc.error_at(item, format!("{item_label}: a body needs at least 3 joints, found {}", parts.len())));
    }
    let joints = distinct_joints(doc, names, parts, &item_label)?;
    Ok(Body { joints, line: doc.line(item.span()) })
}

/// Resolves a list of joint names, rejecting unknown and repeated joints.
fn distinct_joints(doc: &Doc, names: &JointNames, parts: &[Value], item_label: &str) -> Result<Vec<usize>, SceneError> {
    let mut joints = Vec::with_capacity(parts.len());
    for part in parts {
        let joint = names.resolve(doc, part, item_label)?;
        if joints.contains(&joint) {
            return Err(doc.error_at(
                part,
                format!("{item_label}: joint {:?} is listed twice", part.get_ref().as_str().unwrap_or_default()),
            ));
        }
        joints.push(joint);
    }
    Ok(joints)
}

// ---------------------------------------------------------------------------
// Base and ground

/// Parses the optional `base`: exactly two known, distinct joints that are not
/// joined by a bar. Whether the non-edge is a valid base is the solver's call.
fn parse_base(
    doc: &Doc,
    names: &JointNames,
    bars: &[Bar],
    value: Option<&Value>,
) -> Result<Option<([usize; 2], usize)>, SceneError> {
    let Some(value) = value else {
        return Ok(None);
    };
    let parts = array(doc, value, "`base`", "two joint names like [\"P\", \"X\"]")?;
    let item_label = match joint_list(parts) {
        Some(list) => format!("base {list}"),
        None => "base".to_string(),
    };
    if parts.len() != 2 {
        return Err(
            doc.error_at(value, format!("{item_label}: the base must name exactly 2 joints, found {}", parts.len()))
        );
    }
    let a = names.resolve(doc, &parts[0], &item_label)?;
    let b = names.resolve(doc, &parts[1], &item_label)?;
    if a == b {
        return Err(doc.error_at(value, format!("{item_label}: the two joints must be different")));
    }
    if let Some((i, bar)) = bars.iter().enumerate().find(|(_, bar)| bar.joints == [a, b] || bar.joints == [b, a]) {
        return Err(doc.error_at(
            value,
            format!("{item_label} is a bar; the base must be a non-edge (bar {} on line {})", i + 1, bar.line),
        ));
    }
    Ok(Some(([a, b], doc.line(value.span()))))
}

/// Parses the optional `ground`: one or two known, distinct joints. Without it
/// the first bar's two joints are held still.
fn parse_ground(doc: &Doc, names: &JointNames, bars: &[Bar], value: Option<&Value>) -> Result<Vec<usize>, SceneError> {
    let Some(value) = value else {
        return Ok(bars.first().map(|bar| bar.joints.to_vec()).unwrap_or_default());
    };
    let parts = array(doc, value, "`ground`", "one or two joint names like [\"O\", \"P\"]")?;
    if !(1..=2).contains(&parts.len()) {
        return Err(doc.error_at(value, format!("ground must name 1 or 2 joints, found {}", parts.len())));
    }
    distinct_joints(doc, names, parts, "ground")
}
