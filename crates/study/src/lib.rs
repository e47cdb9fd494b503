//! Hopper cases and everything around a run: configuration, measurements and writers.
//!
//! The engine (`dem`) knows nothing of hoppers or files; the analysis (`analysis`) knows
//! nothing of the engine. This crate wires the two for the hopper problem.

pub mod bench;
pub mod cluster;

pub mod hopper;

pub mod run;
pub mod sweep;
