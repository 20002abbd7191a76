//! Scenes built in code (generators, property tests) rather than read from TOML.

use crate::real::Dd;
use crate::scene::{Bar, Body, Joint, Scene};

/// Accumulates joints, bars and bodies; joint names must be unique.
#[derive(Debug, Clone, Default)]
pub struct SceneBuilder {
    scene_name: String,
    joints: Vec<Joint>,
    bars: Vec<Bar>,
    bodies: Vec<Body>,
    base: Option<[usize; 2]>,
    ground: Vec<usize>,
}

impl SceneBuilder {
    pub fn new(name: &str) -> Self {
        SceneBuilder { scene_name: name.to_string(), ..Default::default() }
    }

    /// Add a joint and return its index.
    pub fn joint(&mut self, name: &str, pos: [f64; 2]) -> usize {
        self.joints.push(Joint {
            name: name.to_string(),
            pos,
            exact: pos.map(Dd::new),
            written: [None, None],
            line: 0,
        });
        self.joints.len() - 1
    }

    pub fn index(&self, name: &str) -> usize {
        self.joints.iter().position(|j| j.name == name).unwrap_or_else(|| panic!("no joint {name}"))
    }

    pub fn bar(&mut self, a: &str, b: &str) -> &mut Self {
        let joints = [self.index(a), self.index(b)];
        self.bars.push(Bar { joints, length: None, exact_length: None, written_length: None, line: 0 });
        self
    }

    /// A bar with a stated length (the drawing becomes a sketch).
    pub fn bar_len(&mut self, a: &str, b: &str, length: f64) -> &mut Self {
        let joints = [self.index(a), self.index(b)];
        self.bars.push(Bar {
            joints,
            length: Some(length),
            exact_length: Some(Dd::new(length)),
            written_length: None,
            line: 0,
        });
        self
    }

    pub fn bar_ix(&mut self, a: usize, b: usize, length: Option<f64>) -> &mut Self {
        self.bars.push(Bar {
            joints: [a, b],
            length,
            exact_length: length.map(Dd::new),
            written_length: None,
            line: 0,
        });
        self
    }

    pub fn body(&mut self, joints: &[&str]) -> &mut Self {
        let joints = joints.iter().map(|j| self.index(j)).collect();
        self.bodies.push(Body { joints, line: 0 });
        self
    }

    pub fn base(&mut self, a: &str, b: &str) -> &mut Self {
        self.base = Some([self.index(a), self.index(b)]);
        self
    }

    pub fn ground(&mut self, joints: &[&str]) -> &mut Self {
        self.ground = joints.iter().map(|j| self.index(j)).collect();
        self
    }

    pub fn build(&self) -> Scene {
        let ground = if self.ground.is_empty() {
            self.bars.first().map(|b| b.joints.to_vec()).unwrap_or_default()
        } else {
            self.ground.clone()
        };
        Scene {
            name: self.scene_name.clone(),
            description: None,
            source: format!("generated:{}", self.scene_name),
            joints: self.joints.clone(),
            bars: self.bars.clone(),
            bodies: self.bodies.clone(),
            base: self.base.map(|b| (b, 0)),
            ground,
        }
    }
}
