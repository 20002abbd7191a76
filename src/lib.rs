//! caymos: the terminal tool over the [`caymos_core`] solver: the CLI
//! commands, the report, the benchmarks and the terminal UI.
//!
//! The solver's modules are re-exported under their own names, so
//! `caymos::analysis` is `caymos_core::analysis`; the modules defined here
//! are the ones that print, time, generate or draw.
pub use caymos_core::{
    analysis, cayley_space, cayley_vector, certify, complexity, decompose, distance, enclosure, exact, interval,
    invert, lazy, linkage, minimal_vector, motion, numfmt, real, realize, roots, scene, sweep, tolerance,
};

pub mod alloc;
pub mod bench;
pub mod builder;
pub mod bundled;
pub mod commands;
pub mod generate;
pub mod graph;
pub mod present;
pub mod report;
pub mod schema;
pub mod tui;
