//! Integration tests for the scene parser (`caymos::scene`) and the bundled
//! scenes (`caymos::bundled`).

use std::path::{Path, PathBuf};

use caymos::bundled::*;
use caymos::scene::*;
use proptest::prelude::*;

fn parse(text: &str) -> Result<Scene, SceneError> {
    parse_scene(text, "test.toml", "test")
}

/// Parses `text`, expecting an error on `line` whose message contains every
/// needle; the rendered error must be a single line.
#[track_caller]
fn assert_error(text: &str, line: Option<usize>, needles: &[&str]) -> SceneError {
    let error = match parse(text) {
        Ok(scene) => panic!("expected an error, parsed {scene:?} from:\n{text}"),
        Err(error) => error,
    };
    assert_eq!(error.line, line, "wrong line in `{error}`");
    for needle in needles {
        assert!(error.message.contains(needle), "`{error}` does not mention {needle:?}");
    }
    assert_eq!(error.file, "test.toml");
    assert!(!error.to_string().contains('\n'), "multi-line error `{error}`");
    error
}

fn distance(scene: &Scene, a: &str, b: &str) -> f64 {
    let p = scene.joints[scene.joint_index(a).unwrap()].pos;
    let q = scene.joints[scene.joint_index(b).unwrap()].pos;
    (p[0] - q[0]).hypot(p[1] - q[1])
}

/// A scratch file path unique to this test process.
fn temp_path(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("caymos-scene-test-{}-{name}", std::process::id()))
}

// ---------------------------------------------------------------------------
// Round trip

const JANSEN: &str = r#"name = "Jansen leg"                 # optional
description = "Theo Jansen's Strandbeest leg"
base = ["P", "X"]
ground = ["O", "P"]
bars = [
  ["O", "P"],
  ["O", "X", 15],
  ["X", "Y", 50.0],
  ["X", "W"],
  ["P", "W"],
  ["V", "K"],
]
bodies = [["P", "Y", "V"], ["W", "K", "F"]]

[joints]
O = [0, 0]
"P" = [-38.0, -7.8]
X = [7.5, 12.990381056767]
Y = [-38.00946855288, 33.699998919837]
V = [-78.015573229828, -5.19925028342]
W = [-19.733495562068, -42.596908133037]
K = [-56.140504949211, -37.96876946998]
F = [-18.150294681174, -91.571324668313]
"#;

#[test]
fn jansen_example_round_trips() {
    let scene = parse(JANSEN).unwrap();
    assert_eq!(scene.name, "Jansen leg");
    assert_eq!(scene.description.as_deref(), Some("Theo Jansen's Strandbeest leg"));
    assert_eq!(scene.source, "test.toml");

    let names: Vec<&str> = scene.joints.iter().map(|j| j.name.as_str()).collect();
    assert_eq!(names, ["O", "P", "X", "Y", "V", "W", "K", "F"]);
    let lines: Vec<usize> = scene.joints.iter().map(|j| j.line).collect();
    assert_eq!(lines, [16, 17, 18, 19, 20, 21, 22, 23]);
    assert_eq!(scene.joints[0].pos, [0.0, 0.0]);
    assert_eq!(scene.joints[1].pos, [-38.0, -7.8]);

    let bars: Vec<([usize; 2], Option<f64>, usize)> = scene.bars.iter().map(|b| (b.joints, b.length, b.line)).collect();
    assert_eq!(
        bars,
        [
            ([0, 1], None, 6),
            ([0, 2], Some(15.0), 7),
            ([2, 3], Some(50.0), 8),
            ([2, 5], None, 9),
            ([1, 5], None, 10),
            ([4, 6], None, 11),
        ]
    );
    assert!(scene.is_sketch());
    assert_eq!(scene.bodies, [Body { joints: vec![1, 3, 4], line: 13 }, Body { joints: vec![5, 6, 7], line: 13 }]);
    assert_eq!(scene.base, Some(([1, 2], 3)));
    assert_eq!(scene.ground, [0, 1]);
    assert!((distance(&scene, "X", "Y") - 50.0).abs() < 1e-9);
}

#[test]
fn optional_keys_have_defaults() {
    let scene = parse("bars = [[\"B\", \"A\"]]\n[joints]\nA = [0, 0]\nB = [1, 1]\n").unwrap();
    assert_eq!(scene.name, "test");
    assert_eq!(scene.description, None);
    assert_eq!(scene.base, None);
    assert_eq!(scene.bodies, []);
    assert_eq!(scene.ground, [1, 0], "ground defaults to the first bar's joints");
    assert!(!scene.is_sketch());
}

#[test]
fn quoted_names_dotted_keys_and_unused_joints_are_accepted() {
    let text = r#"bars = [["v0'", "v1"]]
ground = ["v1"]
joints."v0'" = [0.5, 0.25]
joints.v1 = [2, -3]
joints.lonely = [7, 7]
"#;
    let scene = parse(text).unwrap();
    assert_eq!(scene.joint_index("v0'"), Some(0));
    assert_eq!(scene.joints[1].pos, [2.0, -3.0]);
    assert_eq!(scene.joints[2].line, 5);
    assert_eq!(scene.ground, [1]);
}

#[test]
fn negative_zero_and_other_number_forms_are_read() {
    let text = "bars = [[\"A\", \"B\", 1_000]]\n[joints]\nA = [-0.0, -0]\nB = [0x10, 1e1]\n";
    let scene = parse(text).unwrap();
    assert_eq!(scene.joints[0].pos, [0.0, 0.0]);
    assert!(scene.joints[0].pos[0].is_sign_positive());
    assert_eq!(scene.joints[1].pos, [16.0, 10.0]);
    assert_eq!(scene.bars[0].length, Some(1000.0));
}

// ---------------------------------------------------------------------------
// Errors: files and syntax

#[test]
fn toml_syntax_error_has_line_and_column() {
    let error =
        assert_error("bars = [[\"A\", \"B\"]]\n[joints]\nA = [0; 0]\nB = [1, 1]\n", Some(3), &["TOML syntax error"]);
    assert_eq!(error.column, Some(6));
    // A missing `]` is noticed where the next element starts.
    assert_error(
        "bars = [[\"A\", \"B\"]]\n[joints]\nA = [0, 0\nB = [1, 1]\n",
        Some(4),
        &["TOML syntax error", "comma"],
    );
    let error =
        assert_error("bars = [[\"A\", \"B\"]]\n[joints]\nA = [0, 0]\nA = [1, 1]\n", Some(4), &["TOML syntax error"]);
    assert_eq!(error.column, Some(1));
}

#[test]
fn empty_files_are_rejected() {
    assert_error("", None, &["empty"]);
    assert_error("  \n\t\n# only a comment\n", None, &["empty"]);
}

#[test]
fn load_scene_reports_non_utf8_with_its_line() {
    let path = temp_path("latin1.toml");
    std::fs::write(&path, b"name = \"ok\"\nbars = [[\"A\", \"\xE9\"]]\n").unwrap();
    let error = load_scene(&path).unwrap_err();
    std::fs::remove_file(&path).unwrap();
    assert_eq!(error.file, path.display().to_string());
    assert_eq!((error.line, error.column), (Some(2), Some(16)));
    assert!(error.message.contains("not valid UTF-8"), "{error}");
    assert!(error.message.contains("0xE9"), "{error}");
}

#[test]
fn load_scene_reports_io_errors() {
    let error = load_scene(Path::new("/nonexistent/caymos/scene.toml")).unwrap_err();
    assert_eq!(error.file, "/nonexistent/caymos/scene.toml");
    assert_eq!(error.line, None);
    assert!(error.message.starts_with("cannot read: "), "{error}");
}

#[test]
fn load_scene_uses_the_file_stem_as_default_name() {
    let path = temp_path("my-linkage.toml");
    std::fs::write(&path, "bars = [[\"A\", \"B\"]]\n[joints]\nA = [0, 0]\nB = [1, 0]\n").unwrap();
    let scene = load_scene(&path);
    std::fs::remove_file(&path).unwrap();
    let scene = scene.unwrap();
    assert!(scene.name.ends_with("my-linkage"), "{}", scene.name);
    assert_eq!(scene.source, path.display().to_string());
}

// ---------------------------------------------------------------------------
// Errors: keys and types

#[test]
fn unknown_top_level_keys_are_rejected() {
    let text = "bar = [[\"A\", \"B\"]]\n[joints]\nA = [0, 0]\nB = [1, 0]\n";
    let error = assert_error(text, Some(1), &["unknown key `bar`", "did you mean `bars`", "name, description"]);
    assert_eq!(error.column, Some(1));
    assert_error(
        "bars = [[\"A\", \"B\"]]\nscale = 2\n[joints]\nA = [0, 0]\nB = [1, 0]\n",
        Some(2),
        &["unknown key `scale`", "allowed keys are name, description, base, ground, bars, bodies, joints"],
    );
}

#[test]
fn wrong_value_types_are_rejected() {
    let joints = "\n[joints]\nA = [0, 0]\nB = [1, 0]\n";
    let case = |top: &str| format!("{top}{joints}");
    assert_error(&case("name = 5\nbars = [[\"A\", \"B\"]]"), Some(1), &["`name` must be a string", "integer"]);
    assert_error(&case("name = \"  \"\nbars = [[\"A\", \"B\"]]"), Some(1), &["`name` must not be empty"]);
    assert_error(&case("description = [1]\nbars = [[\"A\", \"B\"]]"), Some(1), &["`description` must be a string"]);
    assert_error(&case("bars = \"A-B\""), Some(1), &["`bars` must be an array", "found a string"]);
    assert_error(&case("bars = [\"A\", \"B\"]"), Some(1), &["bar 1 must be an array", "found a string"]);
    assert_error(&case("bars = [[\"A\", 2]]"), Some(1), &["bar 1: expected a joint name", "integer"]);
    assert_error(&case("bars = [[\"A\", \"B\"]]\nbodies = \"ABC\""), Some(2), &["`bodies` must be an array"]);
    assert_error(&case("bars = [[\"A\", \"B\"]]\nbase = \"A\""), Some(2), &["`base` must be two joint names"]);
    assert_error(&case("bars = [[\"A\", \"B\"]]\nground = 1"), Some(2), &["`ground` must be one or two joint names"]);
    assert_error(
        "[[bars]]\nfrom = \"A\"\n[joints]\nA = [0, 0]\nB = [1, 0]\n",
        Some(1),
        &["bar 1 must be an array", "found a table"],
    );
}

// ---------------------------------------------------------------------------
// Errors: joints

#[test]
fn missing_or_empty_joints_are_rejected() {
    assert_error("bars = [[\"A\", \"B\"]]\n", None, &["missing [joints]"]);
    assert_error("bars = [[\"A\", \"B\"]]\njoints = 5\n", Some(2), &["`joints` must be a table"]);
    assert_error("bars = [[\"A\", \"B\"]]\n[joints]\n", Some(2), &["[joints] lists no joints"]);
}

#[test]
fn missing_bars_are_rejected() {
    assert_error("[joints]\nA = [0, 0]\nB = [1, 0]\n", None, &["no bars"]);
    assert_error("bars = []\n[joints]\nA = [0, 0]\nB = [1, 0]\n", Some(1), &["`bars` is empty"]);
}

#[test]
fn bad_joint_coordinates_are_rejected() {
    let case = |b: &str| format!("bars = [[\"A\", \"B\"]]\n[joints]\nA = [0, 0]\nB = {b}\n");
    assert_error(&case("[1]"), Some(4), &["joint \"B\"", "[x, y]", "found 1 element"]);
    assert_error(&case("[1, 2, 3]"), Some(4), &["joint \"B\"", "found 3 element"]);
    assert_error(&case("\"far\""), Some(4), &["joint \"B\"", "found a string"]);
    assert_error(&case("[1, \"2\"]"), Some(4), &["joint \"B\": y coordinate must be a number"]);
    assert_error(&case("[nan, 0]"), Some(4), &["joint \"B\": x coordinate must be a finite number, found nan"]);
    assert_error(&case("[0, -inf]"), Some(4), &["joint \"B\": y coordinate", "-inf"]);
    assert_error(&case("[1e999, 0]"), Some(4), &["joint \"B\"", "finite", "1e999"]);
    assert_error(&case("[99999999999999999999999, 0]"), Some(4), &["joint \"B\"", "out of range"]);
    assert_error(&case("{ x = 1, y = 2 }"), Some(4), &["joint \"B\"", "found a table"]);
    let error = assert_error(&case("[1, true]"), Some(4), &["joint \"B\""]);
    assert_eq!(error.column, Some(9), "the column points at the bad coordinate");
    assert_error("bars = [[\"A\", \"B\"]]\n[joints]\n\"\" = [0, 0]\n", Some(3), &["joint name must not be empty"]);
    assert_error(
        &case("[1, 0]\nbase = [\"A\", \"B\"]"),
        Some(5),
        &["joint \"base\"", "put it before the [joints] table"],
    );
}

#[test]
fn joints_at_the_same_point_are_rejected() {
    let case = |b: &str| format!("bars = [[\"A\", \"B\"]]\n[joints]\nA = [1, 2]\nC = [5, 5]\nB = {b}\n");
    assert_error(&case("[1.0, 2.0]"), Some(5), &["joint \"B\" is drawn at the same point as joint \"A\" (line 3)"]);
    assert_error(&case("[1.000000000000001, 2]"), Some(5), &["joint \"B\"", "joint \"A\""]);
    // Well apart, relative to a huge drawing: still distinct.
    let scene = parse("bars = [[\"A\", \"B\"]]\n[joints]\nA = [1e300, 0]\nB = [-1e300, 0]\nC = [0, 1]\n");
    assert!(scene.is_ok(), "{scene:?}");
    assert_error("bars = [[\"A\", \"B\"]]\n[joints]\nA = [1e-300, 0]\nB = [1e-300, 0]\n", Some(4), &["same point"]);
    // Apart in the drawing, but not at the scale a stated length sets: the
    // error says what sets it, by bar and line.
    assert_error(
        "bars = [[\"A\", \"B\", 1e308], [\"B\", \"C\"]]\n[joints]\nA = [0, 0]\nB = [0.3, 0.9]\nC = [3, 3]\n",
        Some(4),
        &["joint \"B\" is drawn at the same point as joint \"A\"", "scale 1e308", "bar A–B's stated length, line 1"],
    );
}

/// A scene whose scale is below f64's normal range (subnormal lengths) is
/// refused: at 1e-310 the analysis gave a wrong Cayley space. 1e-300 is fine.
#[test]
fn a_subnormal_scale_is_refused() {
    let at = |s: &str| {
        format!("bars = [[\"A\", \"B\"], [\"B\", \"C\"]]\n[joints]\nA = [0, 0]\nB = [1{s}, 0]\nC = [1{s}, 1{s}]\n")
    };
    assert_error(&at("e-310"), Some(1), &["scale", "below f64's normal range", "larger units"]);
    assert!(parse(&at("e-300")).is_ok());
}

/// Issue 10: "the same point" is relative to the scene's scale (its longest
/// bar or body span), not to the drawing's extent, which a far-away joint
/// can make as large as it likes.
#[test]
fn the_same_point_is_relative_to_the_scenes_scale() {
    let four_bar_at = |x: f64, extra: &str| {
        format!(
            "bars = [[\"A\", \"B\"], [\"B\", \"C\"], [\"C\", \"D\"], [\"D\", \"A\"]]\n[joints]\nA = [{x:?}, 0.0]\nB = [{:?}, 3.0]\nC = [{:?}, 3.0]\nD = [{:?}, 0.0]\n{extra}",
            x + 1.0,
            x + 5.0,
            x + 4.0
        )
    };
    // Joints 4 apart at 1e13 with a joint at the origin: distinct (scale 5).
    assert!(parse(&four_bar_at(1e13, "Far = [0.0, 0.0]\n")).is_ok());
    // At a scale of 1e13 (a bar that long), 4 apart is below 1e-12 × scale.
    let long =
        "bars = [[\"A\", \"B\"], [\"B\", \"C\"]]\n[joints]\nA = [0.0, 0.0]\nB = [1e13, 0.0]\nC = [1.0e13, 4.0]\n";
    assert_error(long, Some(5), &["joint \"C\" is drawn at the same point as joint \"B\""]);
    // Below what the coordinates resolve (a few ulps), however small the scale.
    assert_error(
        "bars = [[\"A\", \"B\"]]\n[joints]\nA = [1.0, 0.0]\nB = [1.0000000000000002, 0.0]\n",
        Some(4),
        &["same point"],
    );
    // A tiny scene far from the origin: distinct when apart by many ulps.
    assert!(parse(&four_bar_at(1e6, "")).is_ok());
}

#[test]
fn a_blank_joint_name_is_called_blank() {
    let error = assert_error(
        "bars = [[\"A\", \"\\t\"]]\n[joints]\nA = [0, 0]\n\"\\t\" = [1, 0]\n",
        Some(4),
        &["only whitespace"],
    );
    assert!(error.message.contains("\"\\t\""), "{error}");
    assert!(!error.message.contains("empty"), "{error}");
}

// ---------------------------------------------------------------------------
// Errors: bars and bodies

/// A four-joint scene with `bars` (the array's elements, one per line from
/// line 2) and `extra` top-level lines after them.
fn with_bars(bars: &[&str], extra: &str) -> String {
    let mut text = String::from("bars = [\n");
    for bar in bars {
        text.push_str(&format!("  {bar},\n"));
    }
    text.push_str("]\n");
    text.push_str(extra);
    text.push_str("\n[joints]\nA = [0, 0]\nB = [1, 0.2]\nC = [1.3, 1.1]\nD = [0.1, 0.9]\n");
    text
}

#[test]
fn bad_bars_are_rejected() {
    let ab = r#"["A", "B"]"#;
    assert_error(&with_bars(&[ab, r#"["X"]"#], ""), Some(3), &["bar 2 (X)", "found 1 element"]);
    assert_error(&with_bars(&[ab, r#"["B", "C", 1, 2]"#], ""), Some(3), &["bar 2 (B–C)", "found 4 element"]);
    assert_error(
        &with_bars(&[ab, r#"["B", "C"]"#, r#"["X", "Q"]"#], ""),
        Some(4),
        &["bar 3 (X–Q): unknown joint \"X\""],
    );
    assert_error(&with_bars(&[ab, r#"["C", "Q"]"#], ""), Some(3), &["bar 2 (C–Q): unknown joint \"Q\""]);
    assert_error(&with_bars(&[ab, r#"["C", "C"]"#], ""), Some(3), &["bar 2 (C–C)", "to itself"]);
    assert_error(
        &with_bars(&[ab, r#"["B", "C"]"#, r#"["B", "A"]"#], ""),
        Some(4),
        &["bar 3 (B–A): duplicates bar 1 on line 2"],
    );
    assert_error(
        &with_bars(&[ab, r#"["B", "C"]"#, r#"["B", "C", 2]"#], ""),
        Some(4),
        &["bar 3 (B–C): duplicates bar 2 on line 3"],
    );
}

#[test]
fn bad_bar_lengths_are_rejected() {
    let case = |length: &str| with_bars(&[r#"["A", "B"]"#, &format!(r#"["B", "C", {length}]"#)], "");
    assert_error(&case("0"), Some(3), &["bar 2 (B–C): length must be positive, found 0"]);
    assert_error(&case("-0.0"), Some(3), &["bar 2 (B–C): length must be positive"]);
    assert_error(&case("-2.5"), Some(3), &["bar 2 (B–C): length must be positive, found -2.5"]);
    assert_error(&case("nan"), Some(3), &["bar 2 (B–C): length must be a finite number, found nan"]);
    assert_error(&case("inf"), Some(3), &["bar 2 (B–C): length", "inf"]);
    assert_error(&case("\"5\""), Some(3), &["bar 2 (B–C): length must be a number, found a string"]);
    let error = assert_error(&case("[5]"), Some(3), &["bar 2 (B–C): length must be a number"]);
    assert_eq!(error.column, Some(14));
}

#[test]
fn bad_bodies_are_rejected() {
    let bars = [r#"["A", "B"]"#];
    let case = |bodies: &str| with_bars(&bars, &format!("bodies = {bodies}"));
    // The `bodies` line is line 4.
    assert_error(&case(r#"[["A", "B"]]"#), Some(4), &["body 1 (A–B): a body needs at least 3 joints, found 2"]);
    assert_error(&case(r#"[["A", "B", "C"], ["A", "Q", "D"]]"#), Some(4), &["body 2 (A–Q–D): unknown joint \"Q\""]);
    assert_error(&case(r#"[["A", "B", "A"]]"#), Some(4), &["body 1 (A–B–A): joint \"A\" is listed twice"]);
    assert_error(&case(r#"["A", "B", "C"]"#), Some(4), &["body 1 must be an array"]);
    let scene = parse(&case("[\n  [\"A\", \"B\", \"C\"],\n  [\"B\", \"C\", \"D\"],\n]")).unwrap();
    assert_eq!(scene.bodies[1], Body { joints: vec![1, 2, 3], line: 6 });
}

// ---------------------------------------------------------------------------
// Errors: base and ground

#[test]
fn bad_bases_are_rejected() {
    let bars = [r#"["A", "B"]"#, r#"["B", "C"]"#, r#"["C", "D"]"#];
    let case = |base: &str| with_bars(&bars, &format!("base = {base}"));
    // The `base` line is line 6.
    assert_error(&case(r#"["A"]"#), Some(6), &["base A", "exactly 2 joints, found 1"]);
    assert_error(&case(r#"["A", "C", "D"]"#), Some(6), &["exactly 2 joints, found 3"]);
    assert_error(&case(r#"["A", "Q"]"#), Some(6), &["base A–Q: unknown joint \"Q\""]);
    assert_error(&case(r#"["C", "C"]"#), Some(6), &["base C–C", "must be different"]);
    assert_error(
        &case(r#"["C", "B"]"#),
        Some(6),
        &["base C–B is a bar; the base must be a non-edge (bar 2 on line 3)"],
    );
    assert_eq!(parse(&case(r#"["A", "C"]"#)).unwrap().base, Some(([0, 2], 6)));
}

#[test]
fn bad_grounds_are_rejected() {
    let case = |ground: &str| with_bars(&[r#"["A", "B"]"#], &format!("ground = {ground}"));
    // The `ground` line is line 4.
    assert_error(&case("[]"), Some(4), &["ground must name 1 or 2 joints, found 0"]);
    assert_error(&case(r#"["A", "B", "C"]"#), Some(4), &["ground must name 1 or 2 joints, found 3"]);
    assert_error(&case(r#"["A", "Z"]"#), Some(4), &["ground: unknown joint \"Z\""]);
    assert_error(&case(r#"["D", "D"]"#), Some(4), &["ground: joint \"D\" is listed twice"]);
    assert_eq!(parse(&case(r#"["D"]"#)).unwrap().ground, [3]);
}

// ---------------------------------------------------------------------------
// Bundled scenes

#[test]
fn every_bundled_scene_parses() {
    let mut names: Vec<&str> = BUNDLED.iter().map(|b| b.name).collect();
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), BUNDLED.len(), "bundled names are unique");
    for bundled in BUNDLED {
        let scene = load(bundled.name).unwrap_or_else(|e| panic!("{e}"));
        assert!(!scene.name.trim().is_empty(), "{}: empty name", bundled.name);
        assert!(scene.description.as_deref().is_some_and(|d| !d.trim().is_empty()), "{}: no description", bundled.name);
        assert_eq!(scene.source, format!("bundled:{}", bundled.name));
        for bar in scene.bars.iter().filter(|bar| bar.length.is_none()) {
            let [a, b] = bar.joints.map(|j| scene.joints[j].pos);
            assert!((a[0] - b[0]).hypot(a[1] - b[1]) > 0.0, "{}: bar on line {}", bundled.name, bar.line);
        }
    }
    assert!(find(DEFAULT_SCENE).is_some());
}

#[test]
fn bundled_scenes_have_the_stated_lengths() {
    let check = |name: &str, lengths: &[(&str, &str, f64)]| {
        let scene = load(name).unwrap();
        for &(a, b, length) in lengths {
            let drawn = distance(&scene, a, b);
            assert!((drawn - length).abs() < 1e-9, "{name}: |{a}{b}| = {drawn}, want {length}");
        }
    };
    check("fourbar-crank-rocker", &[("A", "B", 1.0), ("B", "C", 4.0), ("C", "D", 3.0), ("D", "A", 3.5)]);
    check("fourbar-non-grashof", &[("A", "B", 3.0), ("B", "C", 4.0), ("C", "D", 2.5), ("D", "A", 5.0)]);
    check(
        "jansen",
        &[
            ("O", "X", 15.0),
            ("P", "Y", 41.5),
            ("X", "Y", 50.0),
            ("P", "V", 40.1),
            ("Y", "V", 55.8),
            ("P", "W", 39.3),
            ("X", "W", 61.9),
            ("V", "K", 39.4),
            ("W", "K", 36.7),
            ("K", "F", 65.7),
            ("W", "F", 49.0),
        ],
    );
    let jansen = load("jansen").unwrap();
    assert_eq!(jansen.joints[jansen.joint_index("P").unwrap()].pos, [-38.0, -7.8]);
    let peaucellier = load("peaucellier").unwrap();
    let [ob, od] = [distance(&peaucellier, "O", "B"), distance(&peaucellier, "O", "D")];
    assert!((ob - od).abs() < 1e-9);
    let rhombus = ["CB", "BP", "PD", "DC"].map(|s| distance(&peaucellier, &s[..1], &s[1..]));
    assert!(rhombus.iter().all(|side| (side - rhombus[0]).abs() < 1e-9), "{rhombus:?}");
    assert!((distance(&peaucellier, "O", "A") - distance(&peaucellier, "A", "C")).abs() < 1e-9);
}

#[test]
fn resolve_finds_defaults_files_and_bundled_names() {
    assert_eq!(resolve(None).unwrap().source, format!("bundled:{DEFAULT_SCENE}"));
    assert_eq!(resolve(Some("watt")).unwrap().source, "bundled:watt");
    assert_eq!(resolve(Some("bundled:limacon")).unwrap().source, "bundled:limacon");

    let path = temp_path("resolve.toml");
    std::fs::write(&path, find("fig1b").unwrap().text).unwrap();
    let from_file = resolve(path.to_str());
    std::fs::remove_file(&path).unwrap();
    assert_eq!(from_file.unwrap().source, path.display().to_string());

    let error = resolve(Some("no-such-linkage.toml")).unwrap_err();
    assert_eq!(error.file, "no-such-linkage.toml");
    assert!(error.message.contains("no such file"), "{error}");
    assert!(error.message.contains("jansen, fourbar-crank-rocker"), "{error}");
    assert!(load("nope").is_err());
}

// ---------------------------------------------------------------------------
// Robustness: parse_scene never panics

/// An edit to a scene's bytes.
#[derive(Debug, Clone)]
enum Mutation {
    Delete(usize),
    Insert(usize, u8),
    Swap(usize, usize),
    Truncate(usize),
    /// Replace the n-th number in the text with an awkward one.
    ReplaceNumber(usize, &'static str),
}

const AWKWARD_NUMBERS: &[&str] = &[
    "nan",
    "-nan",
    "inf",
    "-inf",
    "1e999",
    "-1e999",
    "-0",
    "-0.0",
    "0",
    "99999999999999999999999",
    "1e-320",
    "0x7fffffffffffffff",
    "1e308",
];

fn mutation() -> impl Strategy<Value = Mutation> {
    let interesting = prop::sample::select(b"[]{}=,.\"'#\n -0123456789eEinfaxABOPXYZ".to_vec());
    prop_oneof![
        any::<usize>().prop_map(Mutation::Delete),
        (any::<usize>(), prop_oneof![interesting, any::<u8>()]).prop_map(|(at, b)| Mutation::Insert(at, b)),
        (any::<usize>(), any::<usize>()).prop_map(|(i, j)| Mutation::Swap(i, j)),
        any::<usize>().prop_map(Mutation::Truncate),
        (any::<usize>(), prop::sample::select(AWKWARD_NUMBERS)).prop_map(|(n, s)| Mutation::ReplaceNumber(n, s)),
    ]
}

/// Byte ranges of the numbers in `text` (runs starting with a digit or sign).
fn number_ranges(text: &[u8]) -> Vec<(usize, usize)> {
    let mut ranges = Vec::new();
    let mut i = 0;
    while i < text.len() {
        let starts = text[i].is_ascii_digit() || (text[i] == b'-' && text.get(i + 1).is_some_and(u8::is_ascii_digit));
        if starts && (i == 0 || !text[i - 1].is_ascii_alphanumeric()) {
            let end = (i + 1..text.len())
                .find(|&j| !(text[j].is_ascii_alphanumeric() || matches!(text[j], b'.' | b'_' | b'-' | b'+')))
                .unwrap_or(text.len());
            ranges.push((i, end));
            i = end;
        } else {
            i += 1;
        }
    }
    ranges
}

fn apply(text: &mut Vec<u8>, mutation: &Mutation) {
    let len = text.len();
    match *mutation {
        Mutation::Delete(at) if len > 0 => {
            text.remove(at % len);
        }
        Mutation::Insert(at, byte) => text.insert(at % (len + 1), byte),
        Mutation::Swap(i, j) if len > 0 => text.swap(i % len, j % len),
        Mutation::Truncate(at) => text.truncate(at % (len + 1)),
        Mutation::ReplaceNumber(n, number) => {
            let ranges = number_ranges(text);
            if !ranges.is_empty() {
                let (start, end) = ranges[n % ranges.len()];
                text.splice(start..end, number.bytes());
            }
        }
        _ => {}
    }
}

/// Invariants of every scene `parse_scene` accepts.
fn check_invariants(scene: &Scene) {
    let n = scene.joints.len();
    assert!(n >= 2 && !scene.bars.is_empty());
    assert!(scene.joints.iter().all(|j| j.pos.iter().all(|c| c.is_finite())));
    for bar in &scene.bars {
        assert!(bar.joints[0] != bar.joints[1] && bar.joints.iter().all(|&j| j < n));
        assert!(bar.length.is_none_or(|l| l.is_finite() && l > 0.0));
    }
    assert!(scene.bodies.iter().all(|b| b.joints.len() >= 3 && b.joints.iter().all(|&j| j < n)));
    assert!((1..=2).contains(&scene.ground.len()) && scene.ground.iter().all(|&j| j < n));
    if let Some(([a, b], _)) = scene.base {
        assert!(a != b && a < n && b < n);
    }
}

fn check_never_panics(text: &str) {
    match parse_scene(text, "fuzz.toml", "fuzz") {
        Ok(scene) => check_invariants(&scene),
        Err(error) => assert!(!error.to_string().contains('\n'), "multi-line error: {error}"),
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn random_strings_never_panic(text in any::<String>()) {
        check_never_panics(&text);
    }

    #[test]
    fn toml_like_strings_never_panic(text in "[\\[\\]{}=,.\"'# \n\\-0-9a-zA-Z_]{0,200}") {
        check_never_panics(&text);
    }

    #[test]
    fn mutated_bundled_scenes_never_panic(
        index in 0..BUNDLED.len(),
        mutations in prop::collection::vec(mutation(), 1..8),
    ) {
        let mut bytes = BUNDLED[index].text.as_bytes().to_vec();
        for mutation in &mutations {
            apply(&mut bytes, mutation);
        }
        check_never_panics(&String::from_utf8_lossy(&bytes));
    }
}

/// The joint named in a same-point error is the first (in file order) that
/// is at the same point as an earlier one, and the earlier joint named is
/// the first such: the grid search gives the pair a comparison of every
/// pair gives (computed here with the same rule), also for points a
/// rounding error or a tolerance apart across cell boundaries, and for a
/// joint within the tolerance of two earlier ones that are not.
#[test]
fn the_same_point_error_names_the_first_pair() {
    // B (line 5) is 0.75e-12 from A and from C, which are 1.5e-12 apart (the tolerance is 1e-12 × scale 1).
    assert_error(
        "bars = [[\"A\", \"Z\", 1.0]]\n[joints]\nA = [0.1, 0.1]\nC = [0.1000000000015, 0.1]\nB = [0.10000000000075, 0.1]\nZ = [0.3, 0.3]\n",
        Some(5),
        &["joint \"B\" is drawn at the same point as joint \"A\" (line 3)"],
    );
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn the_first_same_point_pair_is_the_one_every_pair_gives(
        points in prop::collection::vec((0u32..6, 0u32..6, -5i32..=5, -5i32..=5), 2..40)
    ) {
        // Lattice points 0.01 apart, moved by multiples of 3e-13 (the tolerance is 1e-12).
        let pos: Vec<[f64; 2]> = points
            .iter()
            .map(|&(x, y, dx, dy)| [0.1 + 0.01 * f64::from(x) + 3e-13 * f64::from(dx), 0.1 + 0.01 * f64::from(y) + 3e-13 * f64::from(dy)])
            .collect();
        let mut text = String::from("bars = [[\"J0\", \"J1\", 1.0]]\n[joints]\n");
        for (i, p) in pos.iter().enumerate() {
            text += &format!("J{i} = [{:?}, {:?}]\n", p[0], p[1]);
        }
        let half = |p: [f64; 2]| p.iter().fold(0.0f64, |m, x| m.max(x.abs())) / 2.0;
        let same = |p: [f64; 2], q: [f64; 2]| {
            let half_distance = (p[0] / 2.0 - q[0] / 2.0).hypot(p[1] / 2.0 - q[1] / 2.0);
            p == q || caymos::tolerance::same_drawn_point(half_distance, half(p).max(half(q)), 0.5)
        };
        let first = (0..pos.len()).find_map(|i| (0..i).find(|&j| same(pos[i], pos[j])).map(|j| (i, j)));
        match (first, parse(&text)) {
            (None, Ok(_)) => {}
            (Some((i, j)), Err(e)) => prop_assert!(
                e.message.starts_with(&format!("joint \"J{i}\" is drawn at the same point as joint \"J{j}\" ")),
                "{e}"
            ),
            (want, got) => prop_assert!(false, "expected {want:?}, got {got:?}"),
        }
    }
}
