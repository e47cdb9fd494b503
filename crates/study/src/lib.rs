//! Studies: many cases of a sweep run to one results table, locally (in parallel, resumably)
//! or as a Slurm job array.
//!
//! - [`run_study`] runs every case of an expanded [`case::SweepPlan`] through a
//!   [`CaseRunner`] (the simulation, [`SimulationRunner`], or a stand-in in tests) and keeps
//!   `study.json`, `cases/<id>/…`, `results.csv` and `failures.json` up to date;
//! - [`prepare_study`], [`run_task`] and [`collect_study`] are the same study cut into the
//!   tasks of a Slurm array; [`array_script`] and [`report_script`] write its job scripts.

#![warn(missing_docs)]

pub mod cluster;
pub mod sweep;
