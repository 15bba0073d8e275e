//! The run configuration resolved once from the command line (as ripgrep's `HiArgs` are): how many
//! threads do what. `--threads N` means two things that are kept apart here: the number of
//! one-thread timing workers that render measured jobs side by side (`workers`), and the size of
//! the rayon pool that renders references, pilots and untimed images on all threads at once
//! (`pool_threads`). Each default is decided here and nowhere else: one of each per core.

use crate::spec::Spec;
use crate::timing::{Protocol, cores};

/// Threads of a command, resolved.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Threads {
    /// One-thread timing workers (the timing protocol's `workers`).
    pub workers: usize,
    /// Threads of the pool that renders one image on all of them (references, `hemilab render`).
    pub pool_threads: usize,
}

impl Threads {
    /// From `--threads` (default: one per core, for both).
    pub fn resolve(flag: Option<u32>) -> Self {
        let n = flag.map_or_else(cores, |t| t as usize).max(1);
        Self { workers: n, pool_threads: n }
    }

    /// The rayon pool of `pool_threads` threads.
    pub fn pool(&self) -> crate::error::Result<rayon::ThreadPool> {
        crate::render::pool(Some(self.pool_threads as u32))
    }

    /// The timing protocol of a run of `spec` on these workers: `repeats` (`--timing-repeats`)
    /// over `[timing] repeats`.
    pub fn protocol(&self, repeats: Option<u32>, spec: &Spec) -> Protocol {
        Protocol::new(repeats.unwrap_or(spec.timing.repeats), spec.timing.seed, self.workers)
    }
}
