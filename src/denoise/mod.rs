//! What the user of a real-time renderer sees instead of the raw frame: spatial filters (the
//! Gaussian; the edge-avoiding à-trous filter, guided by the primary hits' depth and normal in a
//! `render::GBuffer`, with what it shares with SVGF in `edges`), temporal accumulation of frames
//! through a `Motion` (running mean, warm-started EMA, TAA with neighbourhood clipping), SVGF
//! (temporal and spatial in one), and named pipelines of them (`pipeline`), run frame by frame by
//! a `FrameFilter` (`filter`, also the noise/bias split of a non-linear filter). Pure image
//! processing: no IO; imports `image` and `render`'s G-buffer. Every filter leaves background
//! pixels (coverage 0) as they are and never reads them.

pub mod accumulate;
pub mod atrous;
pub mod edges;
mod exp;
pub mod filter;
pub mod gaussian;
pub mod history;
pub mod motion;
pub mod pipeline;
pub mod svgf;
mod svgf_atrous;
pub mod taa;
pub mod taps;

pub use accumulate::{Accumulator, Temporal};
pub use atrous::{AtrousParams, atrous, atrous_pair};
pub use edges::{FOOTPRINT_SHARE, default_iterations, footprint};
pub use filter::{FrameFilter, Run};
pub use gaussian::{GAUSS_SIGMA, gaussian};
pub use motion::{Motion, Tap};
pub use pipeline::{Pipeline, PipelineError, Spatial};
pub use svgf::{Svgf, SvgfOptions, SvgfParams};
pub use taa::{TAA_GAMMA, Taa};
