//! The executor: planned jobs become images and records. `runner` renders a job on every thread
//! (references); `executor` renders the measured jobs under the timing protocol, one thread each,
//! and owns the one resume rule; `calibrate` times a few short renders so that `plan` (and `run`'s
//! long-run warning, `long_run`) can say how long a run will take on this machine.

pub mod calibrate;
pub mod executor;
pub mod long_run;
pub mod measure;
pub mod reference;
pub mod runner;
pub mod sweep;

use crate::spec::Spec;
use crate::timing::Protocol;

/// The timing protocol of a run of `spec`: `--timing-repeats` (`repeats`) over `[timing] repeats`;
/// one one-thread worker per thread (`--threads`, default one per core).
pub fn protocol(threads: Option<u32>, repeats: Option<u32>, spec: &Spec) -> Protocol {
    let workers = match threads {
        Some(t) => t as usize,
        None => std::thread::available_parallelism().map_or(1, |n| n.get()),
    };
    Protocol::new(repeats.unwrap_or(spec.timing.repeats), spec.timing.seed, workers)
}
