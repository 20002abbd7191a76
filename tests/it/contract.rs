//! The report contract: every `--format json` document validates against
//! `caymos schema NAME`, is the same bytes on every run, and errors are JSON
//! too; a snapshot of the report of each bundled scene.

use serde_json::Value;

use crate::helpers::*;

/// Check `doc` against the schema the binary prints for `name`.
fn check(name: &str, doc: &Value) -> Result<(), String> {
    let out = caymos(&["schema", name]);
    assert_eq!(out.status.code(), Some(0), "schema {name}: {}", stderr(&out));
    let schema: Value = serde_json::from_slice(&out.stdout).unwrap();
    let url = format!("urn:caymos:schema:{name}");
    let mut schemas = boon::Schemas::new();
    let mut compiler = boon::Compiler::new();
    compiler.add_resource(&url, schema).unwrap();
    let id = compiler.compile(&url, &mut schemas).unwrap_or_else(|e| panic!("schema {name}: {e}"));
    schemas.validate(doc, id).map_err(|e| format!("{e:#}"))
}

/// Validate `doc` against the schema the binary prints for `name`.
fn validate(name: &str, doc: &Value) {
    if let Err(e) = check(name, doc) {
        panic!("{name} document does not match `caymos schema {name}`: {e}\n{doc:#}");
    }
}

#[test]
fn every_report_validates_and_two_runs_are_byte_identical() {
    let hard: Vec<String> = caymos::generate::hard_cases().into_iter().map(|h| h.name).collect();
    let names = caymos::bundled::BUNDLED.iter().map(|b| b.name).chain(hard.iter().map(String::as_str));
    for name in names {
        let first = caymos(&["report", name, "--format", "json"]);
        let second = caymos(&["report", name, "--format", "json"]);
        assert_eq!(first.stdout, second.stdout, "{name}: two runs differ");
        let doc = json(&first);
        assert_eq!(doc["schema_version"], 1);
        assert!(doc["timings_us"].is_null(), "{name}: timings only with --timings");
        validate("report", &doc);
    }
    // A sketch whose stated lengths cannot close: no realization, said as data.
    let dir = scratch("contract-sketch");
    let file =
        write(&dir, "cannot-close.toml", &caymos::generate::to_toml(&caymos::generate::four_bar(1.0, 10.0, 1.0, 1.0)));
    let doc = json(&caymos(&["report", &file, "--format", "json"]));
    validate("report", &doc);
    assert_eq!(doc["no_realization"]["kind"], "base_ranges_miss", "{doc:#}");
    assert!(doc["sketch"].is_object(), "{doc:#}");
    std::fs::remove_dir_all(&dir).ok();
    // A lazy analysis and one with timings.
    for scene in ["jansen --lazy", "limacon --timings"] {
        let mut args = vec!["report", "--format", "json"];
        args.extend(scene.split(' '));
        let doc = json(&caymos(&args));
        validate("report", &doc);
        if scene.ends_with("--timings") {
            assert!(doc["timings_us"]["cayley_space"].as_f64().is_some(), "{doc:#}");
        }
    }
}

#[test]
fn steps_and_components_are_numbered_from_one_everywhere() {
    let doc = json(&caymos(&["report", "jansen", "--format", "json"]));
    let steps = doc["steps"].as_array().unwrap();
    for (k, s) in steps.iter().enumerate() {
        assert_eq!(s["step"], k + 1);
    }
    let components = doc["components"].as_array().unwrap();
    for (k, c) in components.iter().enumerate() {
        assert_eq!(c["component"], k + 1);
    }
    for iv in doc["oriented_intervals"].as_array().unwrap() {
        for e in iv["lower_events"].as_array().unwrap().iter().chain(iv["upper_events"].as_array().unwrap()) {
            let k = e["step"].as_u64().unwrap() as usize;
            assert!((1..=steps.len()).contains(&k));
            assert_eq!(e["vertex"], steps[k - 1]["vertex"], "event step {k} names its step's vertex");
        }
    }
    // The text's component table and the CLI take the same numbers.
    let text = stdout(&caymos(&["report", "jansen"]));
    let last = components.len();
    assert!(text.lines().any(|l| l.trim_start().starts_with(&format!("{last} "))), "{text}");
    assert_eq!(caymos(&["trace", "jansen", "--component", &last.to_string()]).status.code(), Some(0));
    let out = caymos(&["trace", "jansen", "--component", "0"]);
    assert_eq!(out.status.code(), Some(1), "component 0 does not exist");
    let out = caymos(&["trace", "jansen", "--component", &(last + 1).to_string()]);
    assert!(stderr(&out).contains(&format!("(1..{last})")), "{}", stderr(&out));
}

#[test]
fn path_closest_bench_and_list_validate() {
    let out = caymos(&["path", "limacon", "--from", "drawn", "--to", "-+-+@200", "--format", "json"]);
    let doc = json(&out);
    validate("path", &doc);
    assert!(["along", "against"].contains(&doc["paths"][0]["direction"].as_str().unwrap()));
    // Different components: the path document carries a closest pair.
    let doc = json(&caymos(&["path", "limacon", "--from", "----@150", "--to", "+---@150", "--format", "json"]));
    validate("path", &doc);
    let doc = json(&caymos(&["closest", "limacon", "--components", "1,3", "--format", "json"]));
    validate("closest", &doc);
    assert_eq!((doc["a"]["component"].as_u64(), doc["b"]["component"].as_u64()), (Some(1), Some(3)));
    let out = caymos(&["bench", "fourbar-crank-rocker", "fig1c", "--repeat", "1", "--format", "json"]);
    let doc = json(&out);
    validate("bench", &doc);
    assert_eq!(doc["skipped"].as_array().unwrap().len(), 1, "fig1c is rigid: skipped, and said so");
    let doc = json(&caymos(&["graph", "jansen", "--format", "json"]));
    validate("graph", &doc);
    assert_eq!(doc["steps"].as_array().unwrap().len(), 4);
    let outside = caymos(&["graph", "fig1c", "--format", "json"]);
    assert_eq!(outside.status.code(), Some(2));
    let doc = json(&outside);
    validate("graph", &doc);
    assert_eq!(doc["outside"]["kind"], "rigid");
    let doc = json(&caymos(&["list", "--format", "json"]));
    validate("list", &doc);
    let names: Vec<&str> = doc["scenes"].as_array().unwrap().iter().map(|s| s["name"].as_str().unwrap()).collect();
    for b in caymos::bundled::BUNDLED {
        assert!(names.contains(&b.name), "{names:?}");
    }
    for h in caymos::generate::hard_cases() {
        assert!(names.contains(&h.name.as_str()), "{names:?}");
    }
}

#[test]
fn sweep_validates() {
    // Bar and joint sweeps, with a shard, an input bar, and samples where the linkage cannot close.
    for args in [
        vec!["--bar", "A,B", "--from", "0.5", "--to", "3", "--input-bar", "A,B", "--steps", "8"],
        vec!["--bar", "B,C", "--from", "0.5", "--to", "12", "--steps", "12", "--shard", "2/3"],
        vec!["--joint", "C.x", "--from", "-2", "--to", "6", "--steps", "6"],
    ] {
        let out = caymos(&[&["sweep", "fourbar-crank-rocker", "--format", "json"][..], &args[..]].concat());
        assert_eq!(out.status.code(), Some(0), "{args:?}: {}", stderr(&out));
        let doc = json(&out);
        validate("sweep", &doc);
        assert!(!doc["samples"].as_array().unwrap().is_empty(), "{args:?}");
    }
    let doc = json(&caymos(&[
        "sweep",
        "fourbar-crank-rocker",
        "--bar",
        "B,C",
        "--from",
        "0.5",
        "--to",
        "12",
        "--steps",
        "12",
        "--format",
        "json",
    ]));
    let classes: Vec<&str> = doc["samples"].as_array().unwrap().iter().map(|s| s["class"].as_str().unwrap()).collect();
    assert!(classes.contains(&"solved") && classes.contains(&"no_realization"), "{classes:?}");
    // A bad shard is an argument error, as JSON too.
    let out = caymos(&[
        "sweep",
        "fourbar-crank-rocker",
        "--bar",
        "A,B",
        "--from",
        "1",
        "--to",
        "2",
        "--shard",
        "0/1",
        "--format",
        "json",
    ]);
    assert_eq!(out.status.code(), Some(1));
    let doc = json(&out);
    validate("error", &doc);
    assert_eq!(doc["error"]["kind"], "arguments");
}

#[test]
fn errors_are_json_with_format_json() {
    let dir = scratch("contract-errors");
    let bad = write(&dir, "bad.toml", "bars = [[\"A\", \"B\"]]\n[joints]\nA = [0, 0]\nB = [1, \"x\"]\n");
    let out = caymos(&["report", &bad, "--format", "json"]);
    assert_eq!(out.status.code(), Some(1));
    let doc = json(&out);
    validate("error", &doc);
    let e = &doc["error"];
    assert_eq!(e["kind"], "scene");
    assert_eq!(e["file"], bad.as_str());
    assert_eq!(e["line"], 4, "{doc:#}");
    let message = e["message"].as_str().unwrap();
    assert!(!message.is_empty() && stderr(&out).contains(message), "the message is on stderr too: {}", stderr(&out));
    // Without --format json: stderr only.
    let out = caymos(&["report", &bad]);
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stdout.is_empty());
    // Arguments (a bad --base, a bad value for clap), outside the class (exit 2), no realization.
    for (args, kind, code) in [
        (vec!["report", "jansen", "--base", "P", "--format", "json"], "arguments", 1),
        (vec!["report", "jansen", "--format", "json", "--frobnicate"], "arguments", 1),
        (vec!["closest", "jansen", "--components", "1,99", "--format", "json"], "arguments", 1),
        (vec!["path", "fig1c", "--from", "drawn", "--to", "drawn", "--format", "json"], "outside_class", 2),
        (vec!["report", "no-such-scene", "--format=json"], "scene", 1),
    ] {
        let out = caymos(&args);
        assert_eq!(out.status.code(), Some(code), "{args:?}");
        let doc = json(&out);
        validate("error", &doc);
        assert_eq!(doc["error"]["kind"], kind, "{args:?}: {doc:#}");
        assert!(!stderr(&out).is_empty(), "{args:?}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn markdown_report_is_a_job_summary() {
    for name in ["jansen", "fig1c", "peaucellier"] {
        let out = caymos(&["report", name, "--format", "markdown"]);
        let md = stdout(&out);
        assert!(md.starts_with("## caymos report: "), "{md}");
        assert!(md.contains("| --- |") && md.contains("### Warnings"), "{md}");
        assert!(!md.contains('\u{1b}'), "no colour: {md}");
        assert!(!md.chars().any(|c| ('\u{2500}'..='\u{257f}').contains(&c)), "no box drawing: {md}");
    }
    let md = stdout(&caymos(&["report", "jansen", "--format", "markdown"]));
    assert!(md.contains("### Construction steps (4)") && md.contains("### Components (6)"), "{md}");
    // Every table row has as many cells as its header (a `|` in a cell is escaped).
    let cells = |line: &str| line.replace("\\|", "").matches('|').count();
    let mut width = None;
    for line in md.lines() {
        if !line.starts_with('|') {
            width = None;
            continue;
        }
        let w = *width.get_or_insert(cells(line));
        assert_eq!(cells(line), w, "{line}\n{md}");
    }
}

#[test]
fn schema_names_one_table() {
    for name in ["report", "path", "closest", "bench", "graph", "list", "error", "sweep"] {
        let schema: Value = serde_json::from_slice(&caymos(&["schema", name]).stdout).unwrap();
        assert_eq!(schema["properties"]["schema_version"]["const"], 1, "{name}");
    }
    assert_eq!(caymos(&["schema", "nope"]).status.code(), Some(1));
    // The schemas reject what the contract excludes.
    let doc = json(&caymos(&["report", "jansen", "--format", "json"]));
    let broken = |f: &dyn Fn(&mut Value)| {
        let mut d = doc.clone();
        f(&mut d);
        d
    };
    assert!(check("report", &doc).is_ok());
    assert!(check("report", &broken(&|d| d["schema_version"] = 2.into())).is_err());
    assert!(check("report", &broken(&|d| d["steps"][0]["step"] = 0.into())).is_err(), "steps count from 1");
    assert!(check("report", &broken(&|d| d["analysis"] = "partial".into())).is_err());
    assert!(check("report", &broken(&|d| d["warnings"] = serde_json::json!([{"kind": "nonsense"}]))).is_err());
    assert!(check("report", &broken(&|d| d.as_object_mut().unwrap().remove("components").map(drop).unwrap())).is_err());
}

#[test]
fn report_json_snapshots() {
    for b in caymos::bundled::BUNDLED {
        let doc = json(&caymos(&["report", b.name, "--format", "json"]));
        insta::assert_json_snapshot!(format!("report_{}", b.name), doc);
    }
}
