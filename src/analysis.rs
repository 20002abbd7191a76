//! The one entry point both the report and the terminal UI use: scene in,
//! everything the solver knows about it out.

use std::time::Instant;

use crate::complexity::{four_cycle_test, Complexity};
use crate::decompose::{decompose, Decomposition, Outside};
use crate::linkage::Linkage;
use crate::realize::{bar_residual, drawn_realization, to_display, Construction, Drawn, P2, Unrealizable};
use crate::scene::{Scene, SceneError};

/// Wall-clock time of each phase, in microseconds (for the report; never asserted).
#[derive(Debug, Clone, Default)]
pub struct Timings(pub Vec<(&'static str, f64)>);

impl Timings {
    fn time<R>(&mut self, phase: &'static str, f: impl FnOnce() -> R) -> R {
        let start = Instant::now();
        let out = f();
        self.0.push((phase, start.elapsed().as_secs_f64() * 1e6));
        out
    }
}

/// How far a sketch (a scene with stated lengths) was from its realization.
#[derive(Debug, Clone, PartialEq)]
pub struct SketchFit {
    /// Largest |stated − drawn| bar length.
    pub max_length_change: f64,
    /// Largest joint displacement from the drawing to the realization (display frame).
    pub max_joint_move: f64,
}

/// A scene recognised as 1-dof tree-decomposable.
#[derive(Debug, Clone)]
pub struct Solved {
    pub dec: Decomposition,
    pub complexity: Complexity,
    pub construction: Construction<f64>,
    pub drawn: Drawn,
    /// The drawn realization in the display frame (the drawing itself unless a sketch).
    pub drawn_positions: Option<Vec<P2<f64>>>,
    pub sketch: Option<SketchFit>,
}

#[derive(Debug, Clone)]
pub struct Analysis {
    pub scene: Scene,
    pub linkage: Linkage,
    pub outcome: Result<Solved, Outside>,
    pub warnings: Vec<String>,
    pub timings: Timings,
}

/// Where a requested base came from, for the error message.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BaseSource {
    Scene,
    CommandLine,
}

/// Analyse a scene. Errors are for input that cannot be analysed at all
/// (an invalid base, contradictory stated lengths); a valid scene outside the
/// handled class is an `Ok` whose `outcome` says why.
pub fn analyse(scene: Scene, base_override: Option<[usize; 2]>) -> Result<Analysis, SceneError> {
    let mut timings = Timings::default();
    let linkage = timings.time("linkage", || Linkage::from_scene(&scene));
    let (requested, source) = match (base_override, scene.base) {
        (Some(b), _) => (Some(b), BaseSource::CommandLine),
        (None, Some((b, _))) => (Some(b), BaseSource::Scene),
        (None, None) => (None, BaseSource::Scene),
    };
    let mut warnings = Vec::new();
    let dec = match timings.time("decompose", || decompose(&linkage, requested)) {
        Err(outside) => return Ok(Analysis { scene, linkage, outcome: Err(outside), warnings, timings }),
        Ok(Err(base_error)) => {
            let line = if source == BaseSource::Scene { scene.base.map(|b| b.1) } else { None };
            let mut err = scene.error_at(line, base_error.message);
            if source == BaseSource::CommandLine {
                err.message = format!("--base: {}", err.message);
            }
            return Err(err);
        }
        Ok(Ok(dec)) => dec,
    };
    let complexity = timings.time("four_cycle", || four_cycle_test(&linkage, &dec));
    let construction = timings
        .time("construction", || Construction::<f64>::new(&linkage, &dec))
        .map_err(|e| scene.error_at(None, e.0))?;
    let drawn = drawn_realization(&linkage, &dec);
    for &k in &drawn.flat_steps {
        let s = &dec.steps[k];
        warnings.push(format!(
            "step {} ({} ◁ ({}, {})) is flat in the drawing; its orientation is taken as +",
            k + 1,
            linkage.names[s.vertex],
            linkage.names[s.u],
            linkage.names[s.w]
        ));
    }
    let realized = timings.time("realize", || construction.realize(drawn.lambda, &drawn.ty));
    let drawn_positions = match realized {
        Ok(pos) => Some(to_display(&linkage, dec.base, &pos)),
        Err(why) => {
            warnings.push(describe_unrealizable(&linkage, &dec, &why, drawn.lambda, &drawn.ty.to_string()));
            None
        }
    };
    let sketch = if scene.is_sketch() {
        let max_length_change = linkage.bars.iter().map(|b| b.sketch_error.abs()).fold(0.0, f64::max);
        let max_joint_move = drawn_positions.as_ref().map_or(f64::NAN, |pos| {
            pos.iter().zip(&linkage.drawn).map(|(p, d)| (p[0] - d[0]).hypot(p[1] - d[1])).fold(0.0, f64::max)
        });
        Some(SketchFit { max_length_change, max_joint_move })
    } else {
        if let Some(pos) = &drawn_positions {
            let r = bar_residual(&linkage, pos);
            if r > crate::tolerance::BAR_RESIDUAL * linkage.scale {
                warnings.push(format!("the drawn realization misses a bar length by {r:.3e}"));
            }
        }
        None
    };
    let solved = Solved { dec, complexity, construction, drawn, drawn_positions, sketch };
    Ok(Analysis { scene, linkage, outcome: Ok(solved), warnings, timings })
}

/// A sentence saying why (λ, type) has no realization.
pub fn describe_unrealizable(linkage: &Linkage, dec: &Decomposition, why: &Unrealizable, lambda: f64, ty: &str) -> String {
    let n = &linkage.names;
    match *why {
        Unrealizable::Infeasible { step, slack } => {
            let s = &dec.steps[step];
            format!(
                "type {ty} has no realization at λ = {lambda}: step {} ({} ◁ ({}, {})) cannot close (short by {:.3e})",
                step + 1,
                n[s.vertex],
                n[s.u],
                n[s.w],
                -slack
            )
        }
        Unrealizable::Degenerate { step } => {
            let s = &dec.steps[step];
            format!(
                "type {ty} at λ = {lambda}: step {} has {} and {} at the same point, so {} is undetermined",
                step + 1,
                n[s.u],
                n[s.w],
                n[s.vertex]
            )
        }
    }
}
