//! `caymos graph`: the linkage, its clusters, base and construction steps as
//! DOT and JSON. The DOT is parsed here (a small parser for the DOT
//! language's statements), and by Graphviz's `dot` where it is installed.

use std::collections::{BTreeMap, BTreeSet};

use serde_json::Value;

use crate::helpers::{caymos, solved, stderr, stdout};

/// A DOT token: an ID (bare or quoted, unescaped) or punctuation.
#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Id(String),
    P(&'static str),
}

fn tokens(text: &str) -> Vec<Tok> {
    let mut out = Vec::new();
    let mut it = text.chars().peekable();
    while let Some(c) = it.next() {
        match c {
            c if c.is_whitespace() => {}
            '/' if it.peek() == Some(&'/') => {
                for c in it.by_ref() {
                    if c == '\n' {
                        break;
                    }
                }
            }
            '{' => out.push(Tok::P("{")),
            '}' => out.push(Tok::P("}")),
            '[' => out.push(Tok::P("[")),
            ']' => out.push(Tok::P("]")),
            ';' => out.push(Tok::P(";")),
            ',' => out.push(Tok::P(",")),
            '=' => out.push(Tok::P("=")),
            '-' if it.peek() == Some(&'-') => {
                it.next();
                out.push(Tok::P("--"));
            }
            '"' => {
                let mut s = String::new();
                loop {
                    match it.next().expect("unterminated string") {
                        '\\' => s.push(it.next().expect("escape")),
                        '"' => break,
                        c => s.push(c),
                    }
                }
                out.push(Tok::Id(s));
            }
            c if c.is_alphanumeric() || c == '_' || c == '.' || c == '-' => {
                let mut s = c.to_string();
                while let Some(&d) = it.peek() {
                    if d.is_alphanumeric() || d == '_' || d == '.' {
                        s.push(d);
                        it.next();
                    } else {
                        break;
                    }
                }
                out.push(Tok::Id(s));
            }
            c => panic!("unexpected character {c:?} in DOT"),
        }
    }
    out
}

type Attrs = BTreeMap<String, String>;

/// What the parser collects: nodes with their attributes, edges, graph
/// attributes and subgraphs with their member node ids.
#[derive(Debug, Default)]
struct Dot {
    name: String,
    attrs: Attrs,
    nodes: BTreeMap<String, Attrs>,
    edges: Vec<(String, String, Attrs)>,
    subgraphs: Vec<(String, Attrs, Vec<String>)>,
}

struct Parser {
    toks: Vec<Tok>,
    at: usize,
}

impl Parser {
    fn next(&mut self) -> Tok {
        let t = self.toks.get(self.at).cloned().expect("unexpected end of DOT");
        self.at += 1;
        t
    }
    fn peek(&self) -> Option<&Tok> {
        self.toks.get(self.at)
    }
    fn eat(&mut self, p: &'static str) -> bool {
        if self.peek() == Some(&Tok::P(p)) {
            self.at += 1;
            true
        } else {
            false
        }
    }
    fn id(&mut self) -> String {
        match self.next() {
            Tok::Id(s) => s,
            t => panic!("expected an ID, got {t:?}"),
        }
    }
    fn expect(&mut self, p: &'static str) {
        assert_eq!(self.next(), Tok::P(p));
    }
    fn attr_list(&mut self) -> Attrs {
        let mut a = Attrs::new();
        while self.eat("[") {
            while !self.eat("]") {
                let k = self.id();
                self.expect("=");
                a.insert(k, self.id());
                let _ = self.eat(",") || self.eat(";");
            }
        }
        a
    }
    /// Statements up to the closing brace; node ids met go into `members`.
    fn stmts(&mut self, dot: &mut Dot, graph_attrs: &mut Attrs, members: &mut Vec<String>) {
        while !self.eat("}") {
            let first = self.id();
            if first == "subgraph" {
                let name = self.id();
                self.expect("{");
                let (mut attrs, mut inner) = (Attrs::new(), Vec::new());
                self.stmts(dot, &mut attrs, &mut inner);
                members.extend(inner.iter().cloned());
                dot.subgraphs.push((name, attrs, inner));
            } else if ["node", "edge", "graph"].contains(&first.as_str()) {
                self.attr_list();
            } else if self.eat("=") {
                graph_attrs.insert(first, self.id());
            } else if self.eat("--") {
                let mut chain = vec![first, self.id()];
                while self.eat("--") {
                    chain.push(self.id());
                }
                let attrs = self.attr_list();
                for w in chain.windows(2) {
                    dot.edges.push((w[0].clone(), w[1].clone(), attrs.clone()));
                }
                members.extend(chain);
            } else {
                let attrs = self.attr_list();
                dot.nodes.entry(first.clone()).or_default().extend(attrs);
                members.push(first);
            }
            self.eat(";");
        }
    }
}

/// Parse a whole `graph NAME { … }`; panics on anything else.
fn parse_dot(text: &str) -> Dot {
    let mut p = Parser { toks: tokens(text), at: 0 };
    assert_eq!(p.id(), "graph", "an undirected graph");
    let mut dot = Dot { name: p.id(), ..Dot::default() };
    p.expect("{");
    let (mut attrs, mut members) = (Attrs::new(), Vec::new());
    p.stmts(&mut dot, &mut attrs, &mut members);
    assert!(p.peek().is_none(), "text after the graph");
    dot.attrs = attrs;
    for m in members {
        dot.nodes.entry(m).or_default();
    }
    dot
}

fn class(a: &Attrs) -> &str {
    a.get("class").map_or("", String::as_str)
}

fn jansen_dot() -> (String, Dot) {
    let out = caymos(&["graph", "jansen", "--format", "dot"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    let dot = parse_dot(&text);
    (text, dot)
}

#[test]
fn jansen_as_dot_has_its_joints_bars_base_clusters_and_steps() {
    let (_, dot) = jansen_dot();
    assert_eq!(dot.name, "Jansen leg");
    let label = |id: &str| dot.nodes[id]["label"].clone();
    let joints: BTreeMap<String, String> = dot
        .nodes
        .iter()
        .filter(|(_, a)| class(a).split(' ').any(|c| c == "joint"))
        .map(|(id, a)| (a["label"].clone(), id.clone()))
        .collect();
    let names: BTreeSet<&str> = joints.keys().map(String::as_str).collect();
    assert_eq!(names, BTreeSet::from(["F", "K", "O", "P", "V", "W", "X", "Y"]));
    let ground: BTreeSet<String> =
        dot.nodes.values().filter(|a| class(a) == "joint ground").map(|a| a["label"].clone()).collect();
    assert_eq!(ground, BTreeSet::from(["O".to_string(), "P".to_string()]));
    assert!(dot.nodes.values().filter(|a| class(a) == "joint ground").all(|a| a["shape"] == "doublecircle"));

    // 12 bars between joints, each labelled with its length.
    let bars: Vec<(String, String, f64)> = dot
        .edges
        .iter()
        .filter(|e| class(&e.2) == "bar")
        .map(|(a, b, at)| (label(a), label(b), at["label"].parse().expect("a length")))
        .collect();
    assert_eq!(bars.len(), 12, "{bars:?}");
    assert!(bars.contains(&("O".into(), "X".into(), 15.0)) && bars.contains(&("K".into(), "F".into(), 65.7)));
    // O–P has no stated length: the drawn one, √(38² + 7.8²).
    let op = bars.iter().find(|b| b.0 == "O" && b.1 == "P").unwrap().2;
    assert!((op - (38.0f64.hypot(7.8))).abs() < 1e-4, "{op}");

    // The base P–X, dashed, and not a bar.
    let base: Vec<_> = dot.edges.iter().filter(|e| class(&e.2) == "base").collect();
    assert_eq!(base.len(), 1);
    assert_eq!((label(&base[0].0), label(&base[0].1)), ("P".into(), "X".into()));
    assert_eq!(base[0].2["style"], "dashed");

    // Four construction steps, numbered from 1, each joined to u and w and pointing at v.
    let steps: BTreeMap<String, String> =
        dot.nodes.iter().filter(|(_, a)| class(a) == "step").map(|(id, a)| (id.clone(), a["label"].clone())).collect();
    let mut labels: Vec<&str> = steps.values().map(String::as_str).collect();
    labels.sort();
    assert_eq!(labels, ["1: O ◁ (P, X)", "2: Y ◁ (P, X)", "3: W ◁ (P, X)", "4: K ◁ (V, W)"]);
    for (id, text) in &steps {
        let (_, rest) = text.split_once(": ").unwrap();
        let (v, uw) = rest.split_once(" ◁ (").unwrap();
        let (u, w) = uw.trim_end_matches(')').split_once(", ").unwrap();
        let into: Vec<String> =
            dot.edges.iter().filter(|e| &e.1 == id && class(&e.2) == "step").map(|e| label(&e.0)).collect();
        assert_eq!(into, [u, w], "{text}");
        let out: Vec<&(String, String, Attrs)> = dot.edges.iter().filter(|e| &e.0 == id).collect();
        assert_eq!(out.len(), 1);
        assert_eq!((label(&out[0].1), out[0].2["dir"].as_str()), (v.to_string(), "forward"));
    }

    // The rigid triangles are cluster subgraphs; their members are joints.
    let clusters: Vec<BTreeSet<String>> = dot
        .subgraphs
        .iter()
        .inspect(|(name, _, _)| assert!(name.starts_with("cluster_"), "{name}"))
        .map(|(_, _, members)| members.iter().map(|m| label(m)).collect())
        .collect();
    let set = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<BTreeSet<String>>();
    assert_eq!(clusters, [set(&["P", "V", "Y"]), set(&["F", "K", "W"])]);
    assert!(dot.attrs["label"].contains("base P–X, 4 construction steps"));
}

#[test]
fn jansen_as_json_is_the_same_data() {
    let out = caymos(&["graph", "jansen", "--format", "json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v: Value = serde_json::from_str(&stdout(&out)).unwrap();
    let (_, dot) = jansen_dot();
    let joints = v["joints"].as_array().unwrap();
    assert_eq!(joints.len(), 8);
    let ground: Vec<&str> =
        joints.iter().filter(|j| j["ground"] == true).map(|j| j["name"].as_str().unwrap()).collect();
    assert_eq!(ground, ["O", "P"]);
    let bars = v["bars"].as_array().unwrap();
    assert_eq!(bars.len(), 12);
    assert_eq!(bars.iter().filter(|b| b["stated"] == false).count(), 1, "only O–P is drawn, not stated");
    assert_eq!(v["base"], serde_json::json!(["P", "X"]));
    assert_eq!(v["base_chosen"], false, "the scene states its base");
    assert!(v["outside"].is_null());
    let steps = v["steps"].as_array().unwrap();
    assert_eq!(steps.len(), 4);
    for (k, s) in steps.iter().enumerate() {
        assert_eq!(s["number"], k + 1);
        let label =
            format!("{} ◁ ({}, {})", s["vertex"].as_str().unwrap(), s["u"].as_str().unwrap(), s["w"].as_str().unwrap());
        assert_eq!(s["label"], label);
        // The DOT's step k has the same label.
        assert_eq!(dot.nodes[&format!("s{}", k + 1)]["label"], format!("{}: {label}", k + 1));
        // Its clusters are numbers of listed clusters holding u (resp. w) and v.
        for (c, end) in s["clusters"].as_array().unwrap().iter().zip(["u", "w"]) {
            let n = c.as_u64().unwrap() as usize;
            let members: Vec<&str> =
                v["clusters"][n - 1]["joints"].as_array().unwrap().iter().map(|j| j.as_str().unwrap()).collect();
            assert_eq!(v["clusters"][n - 1]["number"], n);
            assert!(members.contains(&s[end].as_str().unwrap()) && members.contains(&s["vertex"].as_str().unwrap()));
        }
    }
    // The bars as in the DOT (same joints, same lengths to the digits printed).
    let dot_bars: BTreeSet<(String, String)> = dot
        .edges
        .iter()
        .filter(|e| class(&e.2) == "bar")
        .map(|(a, b, _)| (dot.nodes[a]["label"].clone(), dot.nodes[b]["label"].clone()))
        .collect();
    let json_bars: BTreeSet<(String, String)> = bars
        .iter()
        .map(|b| (b["joints"][0].as_str().unwrap().to_string(), b["joints"][1].as_str().unwrap().to_string()))
        .collect();
    assert_eq!(dot_bars, json_bars);
}

/// The steps and clusters are the solver's decomposition (1-based numbers).
#[test]
fn the_steps_are_the_decomposition_of_the_analysis() {
    let (a, s) = solved("jansen");
    let out = caymos(&["graph", "jansen", "--format", "json"]);
    let v: Value = serde_json::from_str(&stdout(&out)).unwrap();
    let n = &a.linkage.names;
    for (k, step) in s.dec.steps.iter().enumerate() {
        let j = &v["steps"][k];
        assert_eq!(
            [&j["vertex"], &j["u"], &j["w"]].map(|x| x.as_str().unwrap().to_string()),
            [&n[step.vertex], &n[step.u], &n[step.w]].map(String::clone)
        );
    }
    assert_eq!(v["clusters"].as_array().unwrap().len(), s.dec.clusters.alive_ids().len());
}

/// Graphviz reads the DOT (where it is installed; the parser above always runs).
#[test]
fn graphviz_renders_the_dot() {
    let (text, dot) = jansen_dot();
    assert_eq!(dot.nodes.len(), 8 + 4);
    let Ok(mut child) = std::process::Command::new("dot")
        .arg("-Tsvg")
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
    else {
        eprintln!("graphviz `dot` is not installed: the DOT was checked by this test's parser only");
        return;
    };
    use std::io::Write;
    child.stdin.take().unwrap().write_all(text.as_bytes()).unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success(), "dot: {}", String::from_utf8_lossy(&out.stderr));
    assert!(out.stderr.is_empty(), "dot warned: {}", String::from_utf8_lossy(&out.stderr));
    let svg = String::from_utf8_lossy(&out.stdout);
    assert!(svg.contains("<svg") && svg.contains("class=\"edge base\"") && svg.contains("◁"), "{svg}");
}

/// A scene outside the class: the linkage is still exported, the reason
/// given, exit code 2 like `report`.
#[test]
fn outside_the_class_exports_the_linkage_and_exits_2() {
    let out = caymos(&["graph", "fig1c", "--format", "json"]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let v: Value = serde_json::from_str(&stdout(&out)).unwrap();
    assert!(v["base"].is_null() && v["steps"].as_array().unwrap().is_empty());
    assert_eq!(v["outside"]["kind"], "rigid");
    assert!(stderr(&out).contains("outside the handled class"));
    let out = caymos(&["graph", "fig1c"]);
    assert_eq!(out.status.code(), Some(2));
    let dot = parse_dot(&stdout(&out));
    assert!(dot.edges.iter().all(|e| class(&e.2) == "bar") && !dot.edges.is_empty());
}

/// `--base` picks another base (O–Y is one of Jansen's other valid bases);
/// a bar or a non-edge that is no base is refused like in `report`.
#[test]
fn another_base_and_bad_ones() {
    let out = caymos(&["graph", "jansen", "--format", "json", "--base", "O,Y"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v: Value = serde_json::from_str(&stdout(&out)).unwrap();
    assert_eq!(v["base"], serde_json::json!(["O", "Y"]));
    let labels: Vec<&str> = v["steps"].as_array().unwrap().iter().map(|s| s["label"].as_str().unwrap()).collect();
    assert_eq!(labels, ["P ◁ (O, Y)", "X ◁ (O, Y)", "W ◁ (P, X)", "K ◁ (V, W)"]);
    let out = caymos(&["graph", "jansen", "--base", "O,X"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("that is a bar"), "{}", stderr(&out));
    let out = caymos(&["graph", "jansen", "--base", "O,F"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("not a valid base non-edge") && stdout(&out).is_empty(), "{}", stderr(&out));
}

/// THEORY.md §7's four-bar: base A–C, steps B ◁ (A, C) and D ◁ (A, C);
/// its four bars are its four clusters (none drawn as a DOT cluster).
#[test]
fn the_four_bar_of_theory() {
    let out = caymos(&["graph", "fourbar-crank-rocker", "--format", "json"]);
    let v: Value = serde_json::from_str(&stdout(&out)).unwrap();
    assert_eq!(v["base"], serde_json::json!(["A", "C"]));
    let labels: Vec<&str> = v["steps"].as_array().unwrap().iter().map(|s| s["label"].as_str().unwrap()).collect();
    assert_eq!(labels, ["B ◁ (A, C)", "D ◁ (A, C)"]);
    assert_eq!(v["clusters"].as_array().unwrap().len(), 4);
    let dot = parse_dot(&stdout(&caymos(&["graph", "fourbar-crank-rocker"])));
    assert!(dot.subgraphs.is_empty());
    assert_eq!(dot.edges.iter().filter(|e| class(&e.2) == "bar").count(), 4);
    assert_eq!(dot.edges.iter().filter(|e| class(&e.2) == "step").count(), 6);
}

/// Joint names that need quoting in DOT are escaped.
#[test]
fn names_are_quoted_for_dot() {
    use caymos::graph::{GraphReport, JointOut, to_dot};
    let r = GraphReport {
        scene: "a \"quoted\" \\ scene".into(),
        joints: vec![JointOut { name: "say \"hi\"".into(), ground: true, x: 0.0, y: 0.0 }],
        bars: Vec::new(),
        bodies: Vec::new(),
        clusters: Vec::new(),
        base: None,
        base_chosen: false,
        steps: Vec::new(),
        outside: None,
    };
    let dot = parse_dot(&to_dot(&r));
    assert_eq!(dot.name, "a \"quoted\" \\ scene");
    assert_eq!(dot.nodes["j1"]["label"], "say \"hi\"");
}
