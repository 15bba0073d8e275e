//! The executor: planned jobs become images and records. `runner` renders a job on every thread
//! (references); `executor` renders the measured jobs under the timing protocol, one thread each,
//! and owns the one resume rule; `calibrate` times a few short renders so that `plan` (and `run`'s
//! long-run warning, `long_run`) can say how long a run will take on this machine.

pub mod calibrate;
pub mod config;
pub mod executor;
mod filter_cost;
pub mod flip_refs;
pub mod forecast;
pub mod guides;
pub mod long_run;
pub mod measure;
pub mod post_cost;
pub mod reference;
pub mod replicates;
pub mod runner;
pub mod sampler_cost;
pub mod sweep;
pub mod tiles;
mod to_build;

pub use config::Threads;
