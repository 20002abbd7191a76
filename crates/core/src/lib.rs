//! caymos-core: Cayley analysis of 1-dof tree-decomposable planar linkages.
//!
//! The modules follow the data flow: a [`scene`] file becomes a
//! [`linkage`]; [`decompose`](mod@decompose) recognises the class and builds the
//! construction steps; [`complexity`] decides low Cayley complexity;
//! [`realize`] places joints for a (λ, type); [`invert`] gives the closed-form
//! endpoint candidates; [`cayley_space`](mod@cayley_space) (exhaustive) and [`lazy`] (one
//! component) compute the Cayley configuration space from the shared parts of
//! [`roots`], with structural decisions proven in [`certify`]; [`motion`]
//! joins intervals into components and paths; [`cayley_vector`](mod@cayley_vector) gives the
//! complete Cayley distance vectors and [`minimal_vector`](mod@minimal_vector) the smallest
//! sub-vector proven to separate; [`distance`] certifies the closest pair.
//! [`sweep`] varies one number of the scene and locates where the structure changes.
//! All tolerances live in [`tolerance`]; [`real`] and [`interval`] are the
//! arithmetics (double-double, jets, balls, intervals).
//! [`analysis`] runs it all, in f64 with a double-double self-check.
//!
//! Results are data (enums and structs carrying joints, steps and numbers,
//! such as [`analysis::Warning`] and [`decompose::Outside`]); the caller says
//! them in words. With the `serde` feature they serialize as
//! `{"kind": …, data…}` and describe themselves as JSON Schemas (schemars);
//! steps are then numbered from 1, as people count them ([`numbering`]).
//!
//! ```
//! let text = r#"
//! ground = ["D", "A"]
//! bars = [["A", "B", 3], ["B", "C", 4], ["C", "D", 2.5], ["D", "A", 5]]
//! [joints]
//! A = [0, 0]
//! B = [1.026060429977, 2.819077862358]
//! C = [5.013310949129, 2.499964563476]
//! D = [5, 0]
//! "#;
//! let scene = caymos_core::scene::parse_scene(text, "four-bar.toml", "four-bar").unwrap();
//! let solved = caymos_core::analysis::analyse(scene, None).unwrap().outcome.unwrap();
//! // THEORY.md §7: AB=3, BC=4, CD=2.5, DA=5 gives [2.5, 7] for every type.
//! assert_eq!(solved.union, vec![[2.5, 7.0]]);
//! assert_eq!(solved.space.intervals.len(), 4);
//! ```

#![warn(missing_docs)]

pub mod analysis;
pub mod cayley_space;
pub mod cayley_vector;
pub mod certify;
pub mod complexity;
pub mod decompose;
pub mod distance;
pub mod enclosure;
pub mod exact;
mod hinge;
pub mod interval;
pub mod inthash;
pub mod invert;
pub mod lazy;
pub mod linkage;
pub mod minimal_vector;
pub mod motion;
pub mod numbering;
pub mod numfmt;
pub mod real;
pub mod realize;
pub mod roots;
pub mod scene;
pub mod sweep;
pub mod tolerance;

/// nalgebra, at the version whose [`Point2`] the positions are.
pub use nalgebra;

// The main types and entry points, in data-flow order; every module stays
// public for the rest.
pub use analysis::{Analysis, Scope, SelfCheck, Solved, analyse, analyse_checked, analyse_with};
pub use cayley_space::{CayleySpace, Method, Note, OrientedInterval, cayley_space};
pub use cayley_vector::{cayley_vector, euclid};
pub use certify::{Certifier, Sign, StageCounts};
pub use complexity::{Complexity, four_cycle_test};
pub use decompose::{Decomposition, Outside, decompose};
pub use distance::{Certificate, ClosestOptions, ClosestPair, closest_pair};
pub use lazy::{LazyOptions, component_through};
pub use linkage::Linkage;
pub use minimal_vector::{MinimalVector, minimal_vector};
pub use motion::{Component, Components, Sample, Segment, Stepper, WalkSummary, components, realization_at};
pub use real::{Ball, Dd, Jet, Real};
pub use realize::{Construction, Drawn, Event, Kind, Point2, Realization, RealizationType, Unrealizable};
pub use roots::Endpoint;
pub use scene::{Scene, SceneError, load_scene, parse_scene};
