//! The integration tests: one crate (one link step) with shared helpers.
mod helpers;

mod bench;
mod bounds;
mod cayley_space;
mod cli;
mod closest;
mod contract;
mod drive;
mod edit;
mod exact;
mod graph;
mod hostile;
mod lazy;
mod minimal;
mod motion;
mod perf;
mod recognition;
mod scales;
mod scene_parse;
mod sweep;
mod sweep_view;
mod trust;
mod tui;
