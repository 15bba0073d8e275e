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
//! `app` is the one orchestrator; `io` is the only module that touches the filesystem.

pub mod app;
pub mod cli;
pub mod error;
pub mod image;
pub mod io;
pub mod progress;
pub mod render;
pub mod sampling;
pub mod scene;
