//! The real binary: exit codes, JSON shape, one-line errors naming file and line.

use crate::helpers::*;

#[test]
fn report_runs_on_every_bundled_scene_with_the_right_exit_code() {
    for b in caymos::bundled::BUNDLED {
        let out = caymos(&["report", b.name, "--format", "json"]);
        let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("{}: {e}", b.name));
        let in_class = json["one_dof_tree_decomposable"].as_bool().unwrap();
        assert_eq!(out.status.code(), Some(if in_class { 0 } else { 2 }), "{}", b.name);
        if in_class {
            assert!(json["reason"].is_null());
            assert!(!json["cayley_space"].as_array().unwrap().is_empty(), "{}", b.name);
            let first = &json["oriented_intervals"][0];
            for key in ["type", "lower", "upper"] {
                assert!(!first[key].is_null(), "{}: {key}", b.name);
            }
            for key in ["lower_events", "upper_events"] {
                assert!(!first[key].as_array().unwrap().is_empty(), "{}: {key}", b.name);
            }
            assert!(json["accuracy"]["max_endpoint_error_estimate"].as_f64().unwrap() < 1e-9);
        } else {
            assert!(json["reason"].as_str().unwrap().contains("rigid"), "{}", b.name);
        }
        let text = caymos(&["report", b.name]);
        assert_eq!(text.status.code(), out.status.code());
        assert!(String::from_utf8_lossy(&text.stdout).contains("Class"));
    }
}

#[test]
fn default_scene_is_the_jansen_leg() {
    let out = caymos(&["report", "--format", "json"]);
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["scene"], "Jansen leg");
    assert_eq!(json["steps"].as_array().unwrap().len(), 4);
    assert_eq!(json["oriented_intervals"].as_array().unwrap().len(), 16);
}

#[test]
fn list_names_every_bundled_scene() {
    let out = caymos(&["list"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    for b in caymos::bundled::BUNDLED {
        assert!(text.contains(b.name));
    }
}

#[test]
fn bad_input_is_one_line_naming_file_and_line_with_exit_code_1() {
    let dir = std::env::temp_dir().join(format!("caymos-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let cases = [
        (
            "unknown-joint.toml",
            "bars = [[\"A\", \"B\"], [\"B\", \"Q\"]]\n[joints]\nA = [0, 0]\nB = [1, 0]\n",
            ":1:",
            "\"Q\"",
        ),
        ("syntax.toml", "bars = [[\"A\", \"B\"]\n[joints]\n", "syntax.toml:", ""),
        ("typo.toml", "bar = []\n[joints]\nA = [0, 0]\n", ":1:", "bar"),
        ("empty.toml", "", "empty.toml", "empty"),
    ];
    for (name, text, location, item) in cases {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        let out = caymos(&["report", path.to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(1), "{name}");
        let err = stderr(&out);
        assert_eq!(err.trim().lines().count(), 1, "{name}: {err}");
        assert!(err.contains(name) && err.contains(location) && err.contains(item), "{name}: {err}");
    }
    std::fs::write(dir.join("binary.toml"), [0xff, 0xfe, 0x00, 0x41]).unwrap();
    let out = caymos(&["report", dir.join("binary.toml").to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("UTF-8"), "{}", stderr(&out));
    std::fs::remove_dir_all(&dir).ok();
}

/// An over-constrained scene names the redundant bar or body with the line
/// the file declares it on, in the text and in JSON, and exits with 2.
#[test]
fn a_redundant_bar_or_body_is_named_with_its_line() {
    let dir = scratch("redundant");
    let k4 = "bars = [[\"A\", \"B\"], [\"B\", \"C\"], [\"C\", \"A\"],\n  [\"A\", \"D\"],\n  [\"B\", \"D\"],\n  [\"C\", \"D\"]]\n[joints]\nA = [0, 0]\nB = [1, 0]\nC = [0, 1]\nD = [1, 1]\n";
    let bodies = "bars = [[\"A\", \"D\"]]\nbodies = [[\"A\", \"B\", \"C\"],\n  [\"A\", \"B\", \"C\", \"D\"]]\n[joints]\nA = [0, 0]\nB = [1, 0]\nC = [0, 1]\nD = [1, 1]\n";
    for (name, text, named, line) in [("k4.toml", k4, "bar C–D (line 4)", 4), ("bodies.toml", bodies, "(line 3)", 3)]
    {
        let path = write(&dir, name, text);
        let out = caymos(&["report", &path]);
        assert_eq!(out.status.code(), Some(2), "{name}");
        assert!(stdout(&out).contains(named), "{name}: {}", stdout(&out));
        let doc = json(&caymos(&["report", &path, "--format", "json"]));
        assert_eq!(doc["outside"]["redundant"][0]["line"], line, "{name}: {doc}");
    }
}

#[test]
fn bad_arguments_exit_with_1() {
    for args in [
        vec!["report", "no-such-scene"],
        vec!["report", "jansen", "--base", "P"],
        vec!["report", "jansen", "--base", "P,Nope"],
        vec!["report", "jansen", "--base", "O,K"],
        vec!["report", "jansen", "--base", "O,X"],
        vec!["report", "--format", "yaml"],
        vec!["frobnicate"],
    ] {
        let out = caymos(&args);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {}", stderr(&out));
        assert!(!stderr(&out).is_empty());
    }
    let ok = caymos(&["report", "jansen", "--base", "O,Y", "--format", "json"]);
    assert_eq!(ok.status.code(), Some(0), "{}", stderr(&ok));
}

#[test]
fn motion_commands_through_the_binary() {
    // path: JSON with both arcs, as the issue specifies.
    let out = caymos(&["path", "limacon", "--from", "drawn", "--to", "-+-+@200", "--format", "json"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["same_component"], true);
    assert_eq!(json["paths"].as_array().unwrap().len(), 2);
    for key in ["intervals", "n_intervals", "cayley_length", "max_joint_travel"] {
        assert!(!json["paths"][0][key].is_null(), "{key}");
    }
    assert!(json["closest_pair"].is_null());
    // Different components: the closest pair instead.
    let out = caymos(&["path", "limacon", "--from", "----@150", "--to", "+---@150", "--format", "json"]);
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["same_component"], false);
    assert!(json["closest_pair"]["distance"].as_f64().unwrap() >= 0.0);
    // An unrealizable realization is a clear error, exit 1.
    let out = caymos(&["path", "jansen", "--from", "--+-@24", "--to", "drawn"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("not realizable"), "{}", stderr(&out));
    // trace: CSV header and rows, to a file.
    let file = std::env::temp_dir().join(format!("caymos-trace-{}.csv", std::process::id()));
    let out =
        caymos(&["trace", "jansen", "--joints", "F,K", "--step", "1", "--cayley", "--output", file.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let csv = std::fs::read_to_string(&file).unwrap();
    assert!(csv.starts_with("index,lambda,type,jump,F.x,F.y,K.x,K.y,P-X,"), "{}", csv.lines().next().unwrap());
    assert!(csv.lines().count() > 50);
    std::fs::remove_file(&file).ok();
    // closest and svg.
    let out = caymos(&["closest", "jansen", "--components", "1,3", "--format", "json"]);
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(json["distance"].as_f64().unwrap() > 0.0 && !json["certificate"].as_str().unwrap().is_empty());
    assert_eq!(caymos(&["closest", "jansen", "--components", "1,99"]).status.code(), Some(1));
    let out = caymos(&["svg", "jansen", "--joints", "F"]);
    assert!(String::from_utf8_lossy(&out.stdout).starts_with("<svg"));
    // A scene outside the class: exit 2 for motion commands too.
    assert_eq!(caymos(&["path", "fig1c", "--from", "drawn", "--to", "drawn"]).status.code(), Some(2));
}
