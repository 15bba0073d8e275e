//! hemilab: which way of generating points on the hemisphere gives the least error per unit of
//! run time for ray-traced ambient occlusion?
//!
//! Data flows one way, and the modules are declared in that order:
//!
//! ```text
//!   spec ──► plan ──► jobs ──────────► images ──► metrics ──► results ──► report
//!  (spec/,  (plan/)  (jobs/: runner,  (render/,   (metrics/) (results/,  (report/: run/,
//!   load)            executor,        scene/,                compare/,   advise/; outdir
//!                    calibrate)       sampling/,             advice/)    writes the files)
//!                                     denoise/)
//! ```
//!
//! `load` reads a spec and its scenes and refuses bad input before any work; `denoise` filters and accumulates images (no IO); `reference` owns what
//! a reference is and how it is stored; `shard` splits a plan over machines and merges it back;
//! `timing` is how a render's cost is measured (thread CPU time, interleaved repeats, per-image
//! overhead apart from per-ray cost); `compare` turns records into paired comparisons, the
//! paper's claims and `run`'s equal-time ranking; `advice` ranks configurations at equal time for
//! `hemilab advise`, with the interpolation `compare::equal_time` calls too. `outdir` names
//! every output file once and `io` is the only module that touches the filesystem;
//! `denoise_command` runs the user's own denoiser on a frame (its files through `io`). The command
//! line (`cli`) and the commands (`app`, one thin file each) are the binary's.

// Declared in pipeline order (blank lines keep rustfmt from sorting them).
pub mod spec;

pub mod load;

pub mod plan;

pub mod sampling;

pub mod scene;

pub mod render;

pub mod denoise;

pub mod jobs;

pub mod timing;

pub mod image;

pub mod metrics;

pub mod stats;

pub mod reference;

pub mod results;

pub mod compare;

pub mod advice;

pub mod shard;

pub mod report;

// The shell around the pipeline: errors, signals, the filesystem, progress.
pub mod error;

pub mod interrupt;

pub mod io;

pub mod denoise_command;

pub mod outdir;

pub mod progress;
