//! The JSON contract: every `--format json` document is a [`Versioned`]
//! value, and `caymos schema NAME` prints its JSON Schema, derived from the
//! Rust types (one table, [`SCHEMAS`]: a new document is one line there).

use schemars::{JsonSchema, Schema, schema_for};
use serde::Serialize;

use crate::report::SCHEMA_VERSION;

/// A JSON document: `schema_version` first, then the document's own fields.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct Versioned<T> {
    /// The contract's version ([`SCHEMA_VERSION`]).
    pub schema_version: u32,
    #[serde(flatten)]
    pub doc: T,
}

impl<T: Serialize> Versioned<T> {
    pub fn new(doc: T) -> Self {
        Versioned { schema_version: SCHEMA_VERSION, doc }
    }

    /// Pretty JSON, deterministic (struct fields in declaration order, maps sorted).
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("output types serialize")
    }
}

/// What went wrong, for scripts: `{"error": {...}}`.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct ErrorDoc {
    pub error: ErrorBody,
}

#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct ErrorBody {
    pub kind: ErrorKind,
    /// The reason in words (the file and place are in the fields below).
    pub message: String,
    /// The scene file (or `bundled:NAME`) the error is in, for scene errors.
    pub file: Option<String>,
    pub line: Option<usize>,
    pub column: Option<usize>,
}

/// Kinds of error, with the exit code each gives.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum ErrorKind {
    /// The scene cannot be read or is invalid (exit 1).
    Scene,
    /// Bad command-line arguments (exit 1).
    Arguments,
    /// The scene is valid but outside the handled class (exit 2).
    OutsideClass,
    /// The scene has no realization to work on (exit 1).
    NoRealization,
    /// Output could not be written, or no terminal (exit 1).
    Io,
}

/// One scene `caymos list` offers.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct ListedScene {
    /// The name to open it by (`caymos report NAME`).
    pub name: String,
    pub description: Option<String>,
    pub origin: SceneOrigin,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum SceneOrigin {
    /// Shipped in `linkages/`.
    Bundled,
    /// Generated (THEORY.md §6 hard cases).
    HardCase,
}

/// `caymos list --format json`.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct ListDoc {
    pub scenes: Vec<ListedScene>,
}

/// Makes one document's schema.
pub type MakeSchema = fn() -> Schema;

/// Every `--format json` document by name, with its schema.
pub const SCHEMAS: &[(&str, MakeSchema)] = &[
    ("report", || schema_for!(Versioned<crate::report::Report>)),
    ("path", || schema_for!(Versioned<crate::commands::PathReport>)),
    ("closest", || schema_for!(Versioned<crate::commands::ClosestOut>)),
    ("bench", || schema_for!(Versioned<crate::bench::BenchReport>)),
    ("list", || schema_for!(Versioned<ListDoc>)),
    ("graph", || schema_for!(Versioned<crate::graph::GraphReport>)),
    ("sweep", || schema_for!(Versioned<crate::commands::SweepReport>)),
    ("error", || schema_for!(Versioned<ErrorDoc>)),
];

/// The schema called `name` (see [`SCHEMAS`]), titled, with `schema_version`
/// pinned to [`SCHEMA_VERSION`].
pub fn schema(name: &str) -> Option<Schema> {
    let (_, make) = SCHEMAS.iter().find(|(n, _)| *n == name)?;
    let mut schema = make();
    schema.insert("title".into(), format!("caymos {name} --format json").into());
    if let Some(version) = schema.get_mut("properties").and_then(|p| p.get_mut("schema_version")) {
        *version = serde_json::json!({ "const": SCHEMA_VERSION, "description": "The contract's version." });
    }
    Some(schema)
}
