//! Generated linkages: random 1-dof tree-decomposable linkages for property
//! tests, built step by step the way the theory constructs them.

use crate::builder::SceneBuilder;
use crate::scene::Scene;

/// SplitMix64: a tiny, well-mixed deterministic generator (seeded by tests).
#[derive(Debug, Clone)]
pub struct SplitMix(pub u64);

impl SplitMix {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
}

/// A random 1-dof tree-decomposable linkage with `steps` construction steps,
/// drawn in a well-conditioned pose (every step's triangle height and every
/// base length at least 5% of the scale). Each side of a step is a bar, or,
/// with probability `triangle_chance`, a triangle of bars (an extra joint).
/// The scene's base is the non-edge the construction started from.
pub fn random_linkage(seed: u64, steps: usize, triangle_chance: f64) -> Scene {
    let mut rng = SplitMix(seed);
    'attempt: loop {
        let mut b = SceneBuilder::new(&format!("random-{seed}-{steps}"));
        let mut pos: Vec<[f64; 2]> = Vec::new();
        let add = |b: &mut SceneBuilder, pos: &mut Vec<[f64; 2]>, p: [f64; 2]| {
            let name = format!("J{}", pos.len());
            pos.push(p);
            b.joint(&name, p)
        };
        let a = add(&mut b, &mut pos, [0.0, 0.0]);
        let far = [rng.range(0.3, 1.0), rng.range(-0.3, 0.3)];
        let bb = add(&mut b, &mut pos, far);
        let mut built = vec![a, bb];
        let far_enough = |p: [f64; 2], q: [f64; 2]| (p[0] - q[0]).hypot(p[1] - q[1]) > 0.05;
        for _ in 0..steps {
            let u = built[rng.below(built.len())];
            let mut w = built[rng.below(built.len())];
            while w == u {
                w = built[rng.below(built.len())];
            }
            let (pu, pw) = (pos[u], pos[w]);
            let v_pos = [rng.range(-1.0, 1.0) + 0.5, rng.range(-1.0, 1.0)];
            // Reject poses where the step is nearly flat or lengths nearly vanish.
            let base = [pw[0] - pu[0], pw[1] - pu[1]];
            let d = base[0].hypot(base[1]);
            let height = (base[0] * (v_pos[1] - pu[1]) - base[1] * (v_pos[0] - pu[0])) / d;
            if d < 0.05 || height.abs() < 0.05 || !far_enough(v_pos, pu) || !far_enough(v_pos, pw) {
                continue 'attempt;
            }
            let v = add(&mut b, &mut pos, v_pos);
            for side in [u, w] {
                if rng.unit() < triangle_chance {
                    let t_pos = [rng.range(-1.0, 1.0) + 0.5, rng.range(-1.0, 1.0)];
                    let (ps, pv) = (pos[side], pos[v]);
                    let e = [pv[0] - ps[0], pv[1] - ps[1]];
                    let h = (e[0] * (t_pos[1] - ps[1]) - e[1] * (t_pos[0] - ps[0])) / e[0].hypot(e[1]);
                    if h.abs() < 0.05 {
                        continue 'attempt;
                    }
                    let t = add(&mut b, &mut pos, t_pos);
                    b.bar_ix(side, t, None).bar_ix(t, v, None);
                }
                b.bar_ix(side, v, None);
            }
            built.push(v);
        }
        let mut scene = b.build();
        scene.base = Some(([a, bb], 0));
        if pos.iter().enumerate().any(|(i, p)| pos[..i].iter().any(|q| !far_enough(*p, *q))) {
            continue 'attempt;
        }
        return scene;
    }
}

/// A chain of `steps` four-cycles: each step hangs a vertex on the two extra
/// joints of the previous step's triangles, so every base distance depends
/// on the one before (low Cayley complexity, depth = steps). Lengths are the
/// drawn ones; the drawing is a slightly irregular strip so no two bars are equal.
pub fn chain(steps: usize) -> Scene {
    let mut b = SceneBuilder::new(&format!("chain-{steps}"));
    let wobble = |k: usize, s: f64| 0.07 * ((k as f64) * s).sin();
    let mut p = b.joint("P0", [0.0, 0.0]);
    let mut q = b.joint("Q0", [wobble(0, 1.3), 1.0]);
    let base = (p, q);
    for k in 1..=steps {
        let x = k as f64;
        let v = b.joint(&format!("V{k}"), [x - 0.5 + wobble(k, 2.1), 0.42 + wobble(k, 0.7)]);
        b.bar_ix(p, v, None).bar_ix(q, v, None);
        if k < steps {
            let p2 = b.joint(&format!("P{k}"), [x + wobble(k, 1.7), wobble(k, 3.1)]);
            let q2 = b.joint(&format!("Q{k}"), [x + wobble(k, 0.9), 1.0 + wobble(k, 2.3)]);
            b.bar_ix(p, p2, None).bar_ix(v, p2, None);
            b.bar_ix(q, q2, None).bar_ix(v, q2, None);
            p = p2;
            q = q2;
        }
    }
    let mut scene = b.build();
    scene.base = Some(([base.0, base.1], 0));
    scene.description = Some(format!("generated chain of {steps} four-cycles (each step carried by the one before)"));
    scene
}

/// A fan: `joints` joints, each built on the base pair A, B by two bars of
/// unequal drawn lengths (a dyad per joint, every step on the one base).
/// The drawing places them pseudo-randomly above and below the base, so
/// every step has its own flat places.
pub fn fan(joints: usize) -> Scene {
    let mut b = SceneBuilder::new(&format!("fan-{joints}"));
    let mut rng = SplitMix(joints as u64);
    let a = b.joint("A", [0.0, 0.0]);
    let bb = b.joint("B", [1.0, 0.0]);
    for k in 0..joints {
        let side = if rng.unit() < 0.5 { -1.0 } else { 1.0 };
        let c = b.joint(&format!("C{k}"), [rng.range(-1.0, 2.0), side * rng.range(0.3, 2.0)]);
        b.bar_ix(a, c, None).bar_ix(bb, c, None);
    }
    let mut scene = b.build();
    scene.base = Some(([a, bb], 0));
    scene.description = Some(format!("generated fan of {joints} joints, each built on the base pair A, B"));
    scene
}

/// `legs` Jansen legs on one crank: the crank is a rigid body of the centre O
/// and one crank tip per leg (phases spread round the circle); every leg uses
/// the holy numbers and the shared pivot P.
pub fn strandbeest(legs: usize) -> Scene {
    let legs = legs.max(1);
    let mut b = SceneBuilder::new(&format!("strandbeest-{legs}"));
    let o = b.joint("O", [0.0, 0.0]);
    let p = b.joint("P", [-38.0, -7.8]);
    b.bar_ix(o, p, None);
    let mut crank = vec!["O".to_string()];
    let circle = |c: [f64; 2], r: f64, d: [f64; 2], s: f64, left: bool| -> [f64; 2] {
        let (dx, dy) = (d[0] - c[0], d[1] - c[1]);
        let l = dx.hypot(dy);
        let a = (l * l + r * r - s * s) / (2.0 * l);
        let h = (r * r - a * a).max(0.0).sqrt();
        let (ex, ey) = (dx / l, dy / l);
        let sgn = if left { 1.0 } else { -1.0 };
        [c[0] + a * ex - sgn * h * ey, c[1] + a * ey + sgn * h * ex]
    };
    for i in 0..legs {
        // Phases avoid the crank's dead points so every leg is drawn in a valid pose.
        let phase = 1.0 + std::f64::consts::TAU * i as f64 / legs as f64 + 0.1 * (i as f64).sin();
        let xp = [15.0 * phase.cos(), 15.0 * phase.sin()];
        let n = |s: &str| format!("{s}{i}");
        let x = b.joint(&n("X"), xp);
        crank.push(n("X"));
        let pp = [-38.0, -7.8];
        let y = circle(pp, 41.5, xp, 50.0, false);
        let w = circle(pp, 39.3, xp, 61.9, true);
        let v = circle(pp, 40.1, y, 55.8, false);
        let k = circle(w, 36.7, v, 39.4, true);
        let f = circle(w, 49.0, k, 65.7, true);
        let ids: Vec<usize> = [(n("Y"), y), (n("V"), v), (n("W"), w), (n("K"), k), (n("F"), f)]
            .iter()
            .map(|(name, pos)| b.joint(name, *pos))
            .collect();
        let (y, v, w, k, f) = (ids[0], ids[1], ids[2], ids[3], ids[4]);
        for (a, c) in [(x, y), (x, w), (p, w), (v, k), (p, y), (p, v), (y, v), (w, k), (w, f), (k, f)] {
            b.bar_ix(a, c, None);
        }
    }
    if legs == 1 {
        b.bar_ix(o, 2, None);
    } else {
        let names: Vec<&str> = crank.iter().map(String::as_str).collect();
        b.body(&names);
    }
    b.ground(&["O", "P"]);
    let mut scene = b.build();
    let x0 = scene.joint_index("X0").expect("first crank tip");
    scene.base = Some(([p, x0], 0));
    scene.description = Some(format!("generated Strandbeest: {legs} Jansen legs on one crank"));
    scene
}

/// The scene as TOML in the documented format (lengths as drawn, so only positions are written).
pub fn to_toml(scene: &Scene) -> String {
    let q = |s: &str| format!("\"{}\"", s.replace('\\', "\\\\").replace('"', "\\\""));
    let name = |j: usize| q(&scene.joints[j].name);
    let mut o = format!("name = {}\n", q(&scene.name));
    if let Some(d) = &scene.description {
        o.push_str(&format!("description = {}\n", q(d)));
    }
    if let Some(([a, b], _)) = scene.base {
        o.push_str(&format!("base = [{}, {}]\n", name(a), name(b)));
    }
    let ground: Vec<String> = scene.ground.iter().map(|&j| name(j)).collect();
    o.push_str(&format!("ground = [{}]\n", ground.join(", ")));
    o.push_str("bars = [\n");
    for bar in &scene.bars {
        match bar.length {
            Some(l) => o.push_str(&format!("  [{}, {}, {l:?}],\n", name(bar.joints[0]), name(bar.joints[1]))),
            None => o.push_str(&format!("  [{}, {}],\n", name(bar.joints[0]), name(bar.joints[1]))),
        }
    }
    o.push_str("]\n");
    if !scene.bodies.is_empty() {
        let bodies: Vec<String> = scene
            .bodies
            .iter()
            .map(|b| format!("[{}]", b.joints.iter().map(|&j| name(j)).collect::<Vec<_>>().join(", ")))
            .collect();
        o.push_str(&format!("bodies = [{}]\n", bodies.join(", ")));
    }
    o.push_str("\n[joints]\n");
    for j in &scene.joints {
        o.push_str(&format!("{} = [{:?}, {:?}]\n", q(&j.name), j.pos[0], j.pos[1]));
    }
    o
}

/// A four-bar A-B-C-D on base A–C with stated lengths (the drawing fixes only orientations).
pub fn four_bar(ab: f64, bc: f64, cd: f64, da: f64) -> Scene {
    let mut b = SceneBuilder::new("four-bar");
    b.joint("A", [0.0, 0.0]);
    b.joint("B", [0.2 * da, 0.9 * ab.min(da)]);
    b.joint("C", [0.8 * da, 0.5 * ab.min(da)]);
    b.joint("D", [da, 0.0]);
    b.bar_len("A", "B", ab).bar_len("B", "C", bc).bar_len("C", "D", cd).bar_len("D", "A", da);
    b.base("A", "C").ground(&["D", "A"]);
    b.build()
}

/// A four-bar A-B-C-D on base A–C plus E ◁ (B, D): E's base distance |BD|
/// varies along the motion, so its endpoints come from the hinge chain.
pub fn four_bar_with_dyad(lengths: [f64; 4], be: f64, de: f64) -> Scene {
    let [ab, bc, cd, da] = lengths;
    let mut b = SceneBuilder::new("four-bar-dyad");
    b.joint("A", [0.0, 0.0]);
    b.joint("B", [0.3, 2.0]);
    b.joint("C", [3.0, 0.4]);
    b.joint("D", [1.5, -1.8]);
    b.joint("E", [2.4, 2.6]);
    b.bar_len("A", "B", ab).bar_len("B", "C", bc).bar_len("C", "D", cd).bar_len("D", "A", da);
    b.bar_len("B", "E", be).bar_len("D", "E", de);
    b.base("A", "C");
    b.build()
}

/// |BD| of [`four_bar_with_dyad`] at λ for the given sides of B and D, by plain geometry.
pub fn bd_distance(lengths: [f64; 4], lambda: f64, b_plus: bool, d_plus: bool) -> f64 {
    let [ab, bc, cd, da] = lengths;
    let apex = |r1: f64, r2: f64, plus: bool| {
        let x = (lambda * lambda + r1 * r1 - r2 * r2) / (2.0 * lambda);
        let y = (r1 * r1 - x * x).max(0.0).sqrt();
        [x, if plus { y } else { -y }]
    };
    let (pb, pd) = (apex(ab, bc, b_plus), apex(da, cd, d_plus));
    (pb[0] - pd[0]).hypot(pb[1] - pd[1])
}

/// An exact tangency: v1 ◁ (a, b) with |a v1| = |b v1| = 5; triangles a-v1-p
/// and b-v1-q hinge at v1 with |v1 p| = 3, |v1 q| = 4, so |pq| ≤ 7, with
/// equality where p, v1, q line up; v2 ◁ (p, q) with |p v2| = 10, |q v2| = 3
/// needs |pq| ≥ 7: one isolated λ = 10 sin((π − 30° − 60°)/2).
pub fn tangency() -> Scene {
    let (alpha, beta) = (30f64.to_radians(), 60f64.to_radians());
    let ap = (25.0f64 + 9.0 - 30.0 * alpha.cos()).sqrt();
    let bq = (25.0f64 + 16.0 - 40.0 * beta.cos()).sqrt();
    let theta = 150f64.to_radians();
    let lam = 10.0 * (theta / 2.0).sin();
    let v1 = [lam / 2.0, 5.0 * (theta / 2.0).cos()];
    let dir = |from: [f64; 2], to: [f64; 2]| (to[1] - from[1]).atan2(to[0] - from[0]);
    let at = |angle: f64, r: f64| [v1[0] + r * angle.cos(), v1[1] + r * angle.sin()];
    let p = at(dir(v1, [0.0, 0.0]) - alpha, 3.0);
    let q = at(dir(v1, [lam, 0.0]) + beta, 4.0);
    let mut b = SceneBuilder::new("tangency");
    b.joint("a", [0.0, 0.0]);
    b.joint("b", [lam, 0.0]);
    b.joint("v1", v1);
    b.joint("p", p);
    b.joint("q", q);
    b.joint("v2", [(p[0] + q[0]) / 2.0 + 0.5, (p[1] + q[1]) / 2.0 + 2.0]);
    b.bar_len("a", "v1", 5.0).bar_len("b", "v1", 5.0).bar_len("v1", "p", 3.0).bar_len("a", "p", ap);
    b.bar_len("v1", "q", 4.0).bar_len("b", "q", bq).bar_len("p", "v2", 10.0).bar_len("q", "v2", 3.0);
    b.base("a", "b");
    b.build()
}

/// The hard cases of THEORY.md §6 as named scenes (also used by the test suite).
pub fn hard_cases() -> Vec<Scene> {
    let lengths = [3.0, 4.0, 3.5, 2.0];
    let named = |mut s: Scene, name: &str, what: &str| {
        s.name = name.to_string();
        s.source = format!("generated:{name}");
        s.description = Some(what.to_string());
        s
    };
    let sliver = bd_distance(lengths, 5.5 - 2e-8, true, false);
    let close = bd_distance(lengths, 5.5 - 3e-7, true, false);
    vec![
        named(
            four_bar_with_dyad(lengths, sliver / 2.0 + 0.25, sliver / 2.0 - 0.25),
            "hard:sliver",
            "an oriented interval 2e-8 wide",
        ),
        named(
            four_bar_with_dyad(lengths, close / 2.0 + 0.25, close / 2.0 - 0.25),
            "hard:near-coincident",
            "endpoints of two steps 3e-7 apart",
        ),
        named(tangency(), "hard:tangency", "an isolated point from an exact tangency"),
        named(
            four_bar_with_dyad([1e-3, 1e3, 999.9995, 1.0], 0.55, 0.4505),
            "hard:scale-spread",
            "bars from 1e-3 to 1e3 in one scene",
        ),
        named(four_bar(2.0, 3.0, 2.0 * (1.0 + 1e-6), 3.0), "hard:near-parallelogram", "opposite bars differ by 1e-6"),
    ]
}
