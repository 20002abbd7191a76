//! caymos: Cayley analysis of 1-dof tree-decomposable planar linkages.
//!
//! The solver (everything but `tui`) knows nothing of terminals; the report
//! and the terminal UI call the same functions. One call analyses a scene:
//!
//! ```
//! let scene = caymos::bundled::load("fourbar-non-grashof").unwrap();
//! let analysis = caymos::analysis::analyse(scene, None).unwrap();
//! let solved = analysis.outcome.unwrap();
//! // THEORY.md §7: AB=3, BC=4, CD=2.5, DA=5 gives [2.5, 7] for every type.
//! assert_eq!(solved.union, vec![[2.5, 7.0]]);
//! assert_eq!(solved.space.intervals.len(), 4);
//! ```
pub mod analysis;
pub mod bench;
pub mod builder;
pub mod bundled;
pub mod cayley_space;
pub mod certify;
pub mod commands;
pub mod complexity;
pub mod decompose;
pub mod distance;
pub mod enclosure;
pub mod generate;
pub mod interval;
pub mod invert;
pub mod lazy;
pub mod linkage;
pub mod motion;
pub mod real;
pub mod realize;
pub mod report;
pub mod scene;
pub mod tolerance;
pub mod tui;
