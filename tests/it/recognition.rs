//! Issue 2: recognition, steps, four-cycle test and realization of the drawn pose.

use crate::helpers::*;
use caymos::analysis::{Analysis, Solved, analyse};
use caymos::builder::SceneBuilder;
use caymos::bundled;
use caymos::decompose::Outside;
use caymos::generate::random_linkage;
use caymos::realize::to_display;
use proptest::prelude::*;

fn pair_names(a: &Analysis, p: [usize; 2]) -> [String; 2] {
    [a.linkage.names[p[0]].clone(), a.linkage.names[p[1]].clone()]
}

/// Steps as (vertex, {u, w}) with u, w sorted, in order.
fn steps(a: &Analysis, s: &Solved) -> Vec<(String, [String; 2])> {
    s.dec
        .steps
        .iter()
        .map(|st| {
            let mut on = pair_names(a, [st.u, st.w]);
            on.sort();
            (a.linkage.names[st.vertex].clone(), on)
        })
        .collect()
}

#[test]
fn figure_1a_is_low_cayley_complexity() {
    let (_, s) = solved("fig1a");
    assert!(s.complexity.low);
    assert_eq!(s.complexity.ccv.len(), s.dec.steps.len());
}

#[test]
fn figure_1b_is_tree_decomposable_but_not_lcc() {
    let (a, s) = solved("fig1b");
    assert!(!s.complexity.low);
    let failure = s.complexity.failure.expect("names the failing step");
    let step = s.dec.steps[failure.step];
    assert_eq!(a.linkage.names[step.vertex], "v3");
    assert!(!failure.opposite.is_empty(), "{failure:?}");
    let text = caymos::present::lcc_failure(&failure, caymos::present::Names::new(&a.linkage, &s.dec.steps));
    assert!(text.contains("opposite"), "{text}");
}

#[test]
fn figure_1c_is_rejected_as_rigid_not_tree_decomposable() {
    let a = analyse(bundled::load("fig1c").unwrap(), None).unwrap();
    assert_eq!(a.outcome.unwrap_err(), Outside::Rigid { tree_decomposable: false });
}

#[test]
fn limacon_steps_and_complete_cayley_vector_match_theory() {
    let (a, s) = solved("limacon");
    assert_eq!(pair_names(&a, s.dec.base), ["v0", "v1"]);
    let st = steps(&a, &s);
    let on = |u: &str, w: &str| [u.to_string(), w.to_string()];
    // v2 and v5 on (v0, v1) in either order, then v6 on (v1, v4), v8 on (v5, v7).
    let mut first_two: Vec<&str> = st[..2].iter().map(|(v, _)| v.as_str()).collect();
    first_two.sort();
    assert_eq!(first_two, ["v2", "v5"]);
    assert!(st[..2].iter().all(|(_, p)| *p == on("v0", "v1")));
    assert_eq!(st[2], ("v6".to_string(), on("v1", "v4")));
    assert_eq!(st[3], ("v8".to_string(), on("v5", "v7")));
    assert!(s.complexity.low);
    let ccv: Vec<[String; 2]> = s
        .complexity
        .ccv
        .iter()
        .map(|&p| {
            let mut q = pair_names(&a, p);
            q.sort();
            q
        })
        .collect();
    assert_eq!(ccv, [on("v0", "v1"), on("v2", "v5"), on("v5", "v6"), on("v1", "v8")]);
}

#[test]
fn jansen_leg_has_four_steps_with_v_and_f_as_cluster_members() {
    let (a, s) = solved("jansen");
    assert_eq!(pair_names(&a, s.dec.base), ["P", "X"]);
    let st = steps(&a, &s);
    assert_eq!(st.len(), 4);
    let vertices: Vec<&str> = st.iter().map(|(v, _)| v.as_str()).collect();
    assert!(!vertices.contains(&"V") && !vertices.contains(&"F"));
    let mut first_three = vertices[..3].to_vec();
    first_three.sort();
    assert_eq!(first_three, ["O", "W", "Y"]);
    assert_eq!(st[3], ("K".to_string(), ["V".to_string(), "W".to_string()]));
    assert!(s.complexity.low);
    // 16 types: the drawn type has 4 bits.
    assert_eq!(s.drawn.ty.0.len(), 4);
}

fn outside(b: &SceneBuilder) -> Outside {
    analyse(b.build(), None).unwrap().outcome.unwrap_err()
}

#[test]
fn rigid_graph_is_rejected() {
    let mut b = SceneBuilder::new("triangle");
    b.joint("A", [0.0, 0.0]);
    b.joint("B", [1.0, 0.0]);
    b.joint("C", [0.3, 0.8]);
    b.bar("A", "B").bar("B", "C").bar("C", "A");
    assert_eq!(outside(&b), Outside::Rigid { tree_decomposable: true });
}

#[test]
fn two_dof_graph_is_rejected_with_its_count() {
    let mut b = SceneBuilder::new("pentagon");
    for (i, n) in ["A", "B", "C", "D", "E"].iter().enumerate() {
        let t = i as f64 * 1.2566;
        b.joint(n, [t.cos(), t.sin()]);
    }
    b.bar("A", "B").bar("B", "C").bar("C", "D").bar("D", "E").bar("E", "A");
    assert_eq!(outside(&b), Outside::ManyDof { dof: 2 });
}

#[test]
fn right_bar_count_but_rigid_part_and_two_dof_part_is_rejected() {
    // K4 (one bar redundant) plus a three-joint chain back to it: 7 joints,
    // 10 bars = 2·7 − 4, the count of a 1-dof linkage, yet not one.
    let mut b = SceneBuilder::new("k4-and-chain");
    for (n, p) in [("A", [0.0, 0.0]), ("B", [1.0, 0.1]), ("C", [1.2, 1.0]), ("D", [0.1, 1.1])] {
        b.joint(n, p);
    }
    for (n, p) in [("E", [-0.5, 2.0]), ("F", [-1.5, 1.0]), ("G", [-1.0, -0.4])] {
        b.joint(n, p);
    }
    for (x, y) in [("A", "B"), ("B", "C"), ("C", "D"), ("D", "A"), ("A", "C"), ("B", "D")] {
        b.bar(x, y);
    }
    b.bar("D", "E").bar("E", "F").bar("F", "G").bar("G", "A");
    let a = analyse(b.build(), None).unwrap();
    let o = a.outcome.clone().unwrap_err();
    assert!(matches!(o, Outside::OverConstrained { dof: 2, .. }), "{o:?}");
    let text = caymos::present::outside(&o, &a.linkage);
    assert!(text.contains("redundant") && text.contains("2 degrees of freedom"), "{text}");
}

#[test]
fn disconnected_linkage_is_rejected_naming_its_parts() {
    let mut b = SceneBuilder::new("two-bars");
    b.joint("A", [0.0, 0.0]);
    b.joint("B", [1.0, 0.0]);
    b.joint("C", [3.0, 0.0]);
    b.joint("D", [4.0, 1.0]);
    b.bar("A", "B").bar("C", "D");
    let a = analyse(b.build(), None).unwrap();
    let text = caymos::present::outside(&a.outcome.unwrap_err(), &a.linkage);
    assert!(text.contains("{A, B}") && text.contains("{C, D}"), "{text}");
}

#[test]
fn invalid_base_is_an_error_naming_valid_ones() {
    let mut scene = bundled::load("jansen").unwrap();
    let (o, y) = (scene.joint_index("O").unwrap(), scene.joint_index("Y").unwrap());
    let k = scene.joint_index("K").unwrap();
    scene.base = Some(([o, k], 3));
    let err = analyse(scene.clone(), None).unwrap_err();
    assert_eq!(err.line, Some(3));
    assert!(err.message.contains("O–K") && err.message.contains("valid bases"), "{}", err.message);
    // A valid alternative base works and gives the same number of steps.
    let a = analyse(scene, Some([o, y])).unwrap();
    assert_eq!(a.outcome.unwrap().dec.steps.len(), 4);
}

#[test]
fn automatic_base_prefers_the_crank_parameter() {
    let mut scene = bundled::load("fourbar-non-grashof").unwrap();
    scene.base = None;
    let a = analyse(scene, None).unwrap();
    let s = a.outcome.unwrap();
    assert!(s.dec.base_chosen);
    let mut base = [a.linkage.names[s.dec.base[0]].clone(), a.linkage.names[s.dec.base[1]].clone()];
    base.sort();
    assert_eq!(base, ["A", "C"]);
}

#[test]
fn every_bundled_scene_loads_and_reports() {
    for b in bundled::BUNDLED {
        let a = analyse(bundled::load(b.name).unwrap(), None).unwrap();
        let report = caymos::report::Report::new(&a);
        let json: serde_json::Value = serde_json::from_str(&report.to_json()).unwrap();
        for key in [
            "scene",
            "joints",
            "bars",
            "one_dof_tree_decomposable",
            "reason",
            "base",
            "other_bases",
            "steps",
            "low_cayley_complexity",
            "complete_cayley_vector",
            "drawn",
            "warnings",
            "timings_us",
        ] {
            assert!(json.get(key).is_some(), "{}: no {key}", b.name);
        }
        assert!(!report.to_text().is_empty());
        if let Ok(s) = &a.outcome {
            let pos = s.drawn_positions.as_ref().expect("drawn realization exists");
            let residual = caymos::realize::bar_residual(&a.linkage, pos);
            assert!(residual <= 1e-12 * a.linkage.scale, "{}: residual {residual}", b.name);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    /// Random 1-dof linkages built by random steps (with and without
    /// triangles) are recognised, and realizing their drawn (λ, type)
    /// reproduces every drawn joint to 1e-10 of the scene size. The lengths
    /// are measured from the drawing (each to half an ulp), and a random
    /// construction amplifies that rounding along its levels: 2.5e-12 of the
    /// scale at seed 7553503569457194624 (8 steps), so 1e-12 was too tight;
    /// a wrong realization is off by a fraction of the scale.
    #[test]
    fn random_linkages_are_recognised_and_reproduced(seed in any::<u64>(), steps in 1usize..9, tri in 0.0f64..0.8) {
        let scene = random_linkage(seed, steps, tri);
        let a = analyse(scene, None).unwrap();
        let s = a.outcome.as_ref().map_err(|o| caymos::present::outside(o, &a.linkage)).unwrap();
        let pos = s.construction.realize(s.drawn.lambda, &s.drawn.ty).unwrap();
        let shown = to_display(&a.linkage, s.dec.base, &pos);
        let size = a.linkage.scale;
        for (p, d) in shown.iter().zip(&a.linkage.drawn) {
            prop_assert!((p[0] - d[0]).hypot(p[1] - d[1]) <= 1e-10 * size, "{p:?} vs {d:?}");
        }
        prop_assert_eq!(s.complexity.ccv.len(), s.dec.steps.len());
    }
}

/// Two ground joints that no rigid part holds together (here the base
/// diagonal of a four-bar, whose length is the motion's parameter) are
/// named in a warning: the display cannot hold both still. Ground joints
/// joined by a bar (every bundled scene), or by a rigid cluster without a
/// bar of their own, are not.
#[test]
fn ground_joints_in_no_rigid_part_together_are_warned_about() {
    use caymos::analysis::Warning;
    let moves = |a: &Analysis| a.warnings.iter().any(|w| matches!(w, Warning::GroundMoves { .. }));
    let four_bar = |ground: &str| {
        format!(
            "base = [\"A\", \"C\"]\nground = {ground}\nbars = [[\"A\", \"B\"], [\"B\", \"C\"], [\"C\", \"D\"], [\"D\", \"A\"]]\n[joints]\nA = [0, 0]\nC = [2, 0]\nB = [0.9, 1.5]\nD = [1.2, -1]\n"
        )
    };
    let a = analyse(caymos::scene::parse_scene(&four_bar("[\"A\", \"C\"]"), "g", "g").unwrap(), None).unwrap();
    let w = a.warnings.iter().find(|w| matches!(w, Warning::GroundMoves { .. })).expect("a warning");
    assert_eq!(*w, Warning::GroundMoves { joints: ["A".to_string(), "C".to_string()] });
    let a = analyse(caymos::scene::parse_scene(&four_bar("[\"A\", \"B\"]"), "g", "g").unwrap(), None).unwrap();
    assert!(!moves(&a));
    // Two triangles A, B, X and B, C, X (rigid together, no bar A–C) and a
    // dyad A–E–F–C: a 1-dof linkage whose rigid part holds A and C.
    let mut b = SceneBuilder::new("braced");
    let joints = [("A", [0.0, 0.0]), ("B", [1.0, 0.2]), ("C", [2.0, 0.0]), ("X", [1.0, -1.0])];
    for (n, p) in joints.into_iter().chain([("E", [0.3, 1.5]), ("F", [1.8, 1.4])]) {
        b.joint(n, p);
    }
    b.bar("A", "B").bar("B", "C").bar("C", "X").bar("X", "A").bar("B", "X");
    b.bar("A", "E").bar("E", "F").bar("F", "C");
    let mut scene = b.build();
    scene.ground = vec![0, 2];
    let a = analyse(scene, None).unwrap();
    assert!(a.outcome.is_ok(), "1-dof tree-decomposable");
    assert!(!moves(&a), "{:?}", a.warnings);
    for s in bundled::BUNDLED {
        assert!(!moves(&analyse(bundled::load(s.name).unwrap(), None).unwrap()), "{}", s.name);
    }
}

/// A kite A-B-C-D (AB = BC = 3, CD = DA = 4) with a dyad E ◁ (B, D). On
/// base A–C both steps on the base have equal sides, so at λ = 0 A and C
/// meet and B and D turn freely about them: a motion no λ follows, and
/// that base counts 4 connected sets where the three bases that keep
/// their joints apart count 2. With no base named, caymos chooses one of
/// those (it used to choose A–C); named, A–C is kept and the report says
/// where its count stops.
#[test]
fn an_automatic_base_keeps_its_joints_apart() {
    let kite = |base| four_bar_with_dyad_text(base, ["3", "3", "4", "4"], ["6.5", "6.5"]);
    let (a, s) = solve_text(&kite(None), "kite.toml");
    assert!(s.dec.base_chosen);
    assert_ne!(pair_names(&a, s.dec.base), ["A", "C"]);
    assert_eq!(s.components.connected_set_count(), 2);
    for base in s.dec.other_bases(&a.linkage) {
        let (_, t) = solve_with(a.scene.clone(), Some(base), caymos::analysis::Scope::Full);
        let sets = t.components.connected_set_count();
        if pair_names(&a, base) == ["A", "C"] {
            assert_eq!(sets, 4, "base A–C does not follow the turn at λ = 0");
        } else {
            assert_eq!(sets, 2, "base {:?}", pair_names(&a, base));
        }
    }
    let dir = scratch("kite-base");
    let named = write(&dir, "kite.toml", &kite(Some(["A", "C"])));
    let text = stdout(&caymos(&["report", &named]));
    assert!(text.contains("Base non-edge           A–C (given)"), "{text}");
    assert!(text.contains("a base whose joints never meet follows them"), "{text}");
}
