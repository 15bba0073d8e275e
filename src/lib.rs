//! hemilab: which way of generating points on the hemisphere gives the least error per unit of
//! run time for ray-traced ambient occlusion?
//!
//! Data flows one way:
//!
//! ```text
//!   spec ──► plan ──► jobs ──► images ──► metrics ──► report
//!  (spec.rs) (plan.rs)  (render/,     (image.rs) (metrics.rs) (report/)
//!                       scene/,
//!                       sampling/)
//! ```
//!
//! `timing` is how a render's cost is measured (thread CPU time, interleaved repeats, per-image
//! overhead apart from per-ray cost); `compare` turns the records into the answer (best per unit
//! time, paired differences), and `advice` ranks configurations at equal time for `hemilab advise`. `app` is the one orchestrator; `io` is the only module that touches
//! the filesystem.

// Declared in pipeline order (blank lines keep rustfmt from sorting them).
pub mod spec;

pub mod load;

pub mod plan;

pub mod sampling;

pub mod scene;

pub mod render;

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

// The shell around the pipeline: command line, orchestration, errors, the filesystem.
pub mod cli;

pub mod app;

pub mod error;

pub mod io;

pub mod outdir;

pub mod progress;
