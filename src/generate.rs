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
