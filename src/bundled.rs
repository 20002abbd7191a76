//! Scenes embedded in the binary, so `caymos jansen` works without any file.
//! The sources live in `linkages/NAME.toml`.

use std::path::Path;

use crate::scene::{Scene, SceneError, load_scene, parse_scene};

/// A scene shipped with caymos: its name (the file stem) and TOML text.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Bundled {
    pub name: &'static str,
    pub text: &'static str,
}

/// Lists bundled scenes by name, embedding `linkages/NAME.toml` for each.
macro_rules! bundled {
    ($($name:literal),* $(,)?) => {
        &[$(Bundled {
            name: $name,
            text: include_str!(concat!("../linkages/", $name, ".toml")),
        }),*]
    };
}

/// Every bundled scene, in the order they are listed to the user.
pub const BUNDLED: &[Bundled] = bundled![
    "jansen",
    "fourbar-crank-rocker",
    "fourbar-non-grashof",
    "limacon",
    "peaucellier",
    "watt",
    "stephenson",
    "fig1a",
    "fig1b",
    "fig1c",
];

/// The scene shown when none is given.
pub const DEFAULT_SCENE: &str = "jansen";

/// The bundled scene called `name`.
pub fn find(name: &str) -> Option<&'static Bundled> {
    BUNDLED.iter().find(|bundled| bundled.name == name)
}

/// Parses the bundled scene called `name` (errors name the source `bundled:NAME`).
pub fn load(name: &str) -> Result<Scene, SceneError> {
    let source = format!("bundled:{name}");
    match find(name) {
        Some(bundled) => parse_scene(bundled.text, &source, bundled.name),
        None => Err(SceneError {
            file: source,
            line: None,
            column: None,
            message: format!("no bundled scene of that name; {}", bundled_list()),
        }),
    }
}

/// The scene a command-line argument names: `None` is the default scene; an
/// existing path is loaded from disk; otherwise the argument must be the name
/// of a bundled scene (optionally written `bundled:NAME`) or of a hard case
/// (`hard:sliver`, …, see [`crate::generate::hard_cases`]).
pub fn resolve(arg: Option<&str>) -> Result<Scene, SceneError> {
    let Some(arg) = arg else {
        return load(DEFAULT_SCENE);
    };
    let path = Path::new(arg);
    if path.exists() {
        return load_scene(path);
    }
    if let Some(hard) = crate::generate::hard_cases().into_iter().find(|h| h.name == arg) {
        return Ok(hard);
    }
    let name = arg.strip_prefix("bundled:").unwrap_or(arg);
    if find(name).is_some() {
        return load(name);
    }
    Err(SceneError {
        file: arg.to_string(),
        line: None,
        column: None,
        message: format!("no such file, and not the name of a bundled scene; {}", bundled_list()),
    })
}

/// "bundled scenes: jansen, …; hard cases: hard:sliver, …" for error messages.
fn bundled_list() -> String {
    let names: Vec<&str> = BUNDLED.iter().map(|bundled| bundled.name).collect();
    let hard: Vec<String> = crate::generate::hard_cases().into_iter().map(|h| h.name).collect();
    format!("bundled scenes: {}; hard cases: {}", names.join(", "), hard.join(", "))
}
