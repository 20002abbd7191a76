//! caymos: Cayley analysis of 1-dof tree-decomposable planar linkages.
//!
//! The solver (everything but `tui`) knows nothing of terminals; the report
//! and the terminal UI call the same functions.
pub mod analysis;
pub mod builder;
pub mod bundled;
pub mod cayley_space;
pub mod complexity;
pub mod decompose;
pub mod generate;
pub mod invert;
pub mod linkage;
pub mod real;
pub mod realize;
pub mod report;
pub mod scene;
pub mod tolerance;
