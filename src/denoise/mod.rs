//! What the user of a real-time renderer sees instead of the raw frame: spatial filters (the
//! Gaussian; the edge-avoiding à-trous filter, guided by the primary hits' depth and normal in a
//! `render::GBuffer`, what it shares with SVGF in `edges`), temporal accumulation of frames
//! (running mean, EMA) and named pipelines of the two (`pipeline`). Pure image processing: no IO;
//! imports `image` and `render`'s G-buffer.
//! Every filter leaves background pixels (coverage 0) as they are and never reads them.

pub mod accumulate;
pub mod atrous;
pub mod edges;
pub mod gaussian;
pub mod motion;
pub mod pipeline;

pub use accumulate::{Accumulator, Temporal};
pub use atrous::{AtrousParams, atrous, atrous_pair};
pub use edges::{FOOTPRINT_SHARE, default_iterations, footprint};
pub use gaussian::{GAUSS_SIGMA, gaussian};
pub use motion::{Motion, Tap};
pub use pipeline::{Pipeline, PipelineError, Spatial};
