//! caymos: Cayley analysis of 1-dof tree-decomposable planar linkages.
pub mod scene;
