//! The real-time verdicts, as plain data (`report::run::realtime` words them): the records of a
//! spec's `frames`/`pipelines`/`schedules` groups (`JobResult::is_single_frame` false, plus the raw
//! frame-1 records beside them) read as two questions. (1) After each pipeline, at its last
//! measured frame, does the paper's sine-cosine × Fibonacci × per-pixel seed (independent schedule)
//! still have the least error of every configuration measured with it? (2) Under the accumulating
//! pipelines, does spatiotemporal blue noise (Wolfe, Morrical & Ramamoorthi 2022) beat the 2-D
//! blue-noise mask drawn afresh each frame (the same sequence, the independent schedule), as its
//! paper reports for AO? And, at the fewest rays per frame, the noise each seed mode leaves.
//!
//! Both are read on the RMSE against the reference (what the user sees), on mean LDR-FLIP (what the
//! field reports; it can rank two configurations the other way, so a cell says where the two
//! disagree and records without `flip` give no FLIP verdict) and on its noise part,
//! measured from the replicates (`JobResult::noise_rmse`, `metrics::replicates`): per replicate
//! √max(RMSE² − bias², 0), whose mean square over the replicates is exactly the configuration's
//! noise² (bias² + noise² is the mean MSE), so the same paired margin applies. A margin is the
//! paired difference over replicates (`margin::paired`), relative to the paper's (or blue noise's)
//! mean; a verdict is called only beyond Student's t at [`ALPHA`] two-sided, else a tie. The "best
//! other" is the least mean of many, so its margin is biased towards it (the winner's curse): a tie
//! there is a tie.
//!
//! An RMSE verdict is no win where it is the two sides' biases at work, not their noise: when the
//! RMSE margin is within the difference of their biases (`bias_rmse`) and their noise parts rank
//! the other way, the cell is a **bias interaction** (one side's systematic error offsetting the
//! filter's, e.g. a rotation's fixed elevations against SVGF's brightening); and where either
//! side's mean RMSE is below the pipeline's floor (its bias on per-pixel-unbiased input,
//! `JobResult::floor`) it is **below floor**. Configurations are typed (`Config`), never read back
//! from their labels. Records made before the split (no `bias_rmse`) are read as they were: their
//! noise RMSE is the joint application's, per replicate.

use crate::compare::margin::{self, Margin};
use crate::compare::model::Estimate;
use crate::results::JobResult;
use crate::sampling::{Distribution, Schedule, SeedMode, Sequence};
use crate::stats::mean_and_standard_error;
use std::collections::BTreeMap;
use std::fmt;

mod iterations;
mod questions;
#[cfg(test)]
mod tests;

pub use iterations::{Call, IterationsPair, Question, iterations_pairs};
pub use questions::{
    EngineCell, PaperCell, SeedsCell, StbnCell, engine_cells, paper_cells, seeds_cells, stbn_cells,
};

/// Two-sided level of a real-time verdict: a sweep of many cells at few replicates each, read as
/// a screen (how often the paper's configuration wins), not as the paper's claims (1 %, `claims`).
pub const ALPHA: f64 = 0.05;

/// One estimator of a real-time cell: distribution, sequence, seed mode and schedule.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub struct Config {
    pub distribution: Distribution,
    pub sequence: Sequence,
    pub seed_mode: SeedMode,
    pub schedule: Schedule,
}

impl Config {
    /// The paper's configuration: sine-cosine × Fibonacci × per-pixel seed, independent schedule.
    pub const PAPER: Config = Config {
        distribution: Distribution::SineCosine,
        sequence: Sequence::Fibonacci,
        seed_mode: SeedMode::Rotation,
        schedule: Schedule::Independent,
    };

    fn of(r: &JobResult) -> Option<Self> {
        let (row, schedule) = r.estimator()?;
        Some(Config {
            distribution: row.distribution,
            sequence: row.sequence,
            seed_mode: row.seed_mode,
            schedule,
        })
    }

    /// The same estimator under another seed mode and the independent schedule.
    fn with_mode(self, seed_mode: SeedMode) -> Self {
        Config { seed_mode, schedule: Schedule::Independent, ..self }
    }

    /// Everything but the schedule: the paper's under another schedule is still the paper's.
    fn estimator(self) -> (Distribution, Sequence, SeedMode) {
        (self.distribution, self.sequence, self.seed_mode)
    }

    /// "sine-cosine/fibonacci": what the mask questions hold fixed.
    pub fn prefix(self) -> String {
        format!("{}/{}", self.distribution.name(), self.sequence.name())
    }
}

impl fmt::Display for Config {
    /// "sine-cosine/fibonacci/rotation/independent".
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}/{}", self.prefix(), self.seed_mode.name(), self.schedule.name())
    }
}

/// The paper's configuration as the cells label it.
pub fn paper_label() -> String {
    Config::PAPER.to_string()
}

/// One record's errors: its replicate, RMSE, the noise part of it (per replicate, module doc),
/// and the configuration's bias, noise and the place's floor.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Measured {
    replicate: u32,
    rmse: f64,
    noise: f64,
    bias_rmse: f64,
    bias_se: f64,
    noise_rmse: f64,
    floor: f64,
    /// Mean LDR-FLIP (`JobResult::flip`); NaN in records made before the column.
    flip: f64,
}

/// Where a cell is: scene, rays per frame, camera path, the user's denoiser (empty: none),
/// pipeline (as results name it) and frame; whether the pipeline accumulates and whether it is
/// raw, from the record's typed measurement.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
struct At<'a> {
    scene: &'a str,
    rays: u32,
    camera: &'a str,
    denoiser: &'a str,
    pipeline: &'a str,
    frame: u32,
    temporal: bool,
    raw: bool,
}

impl At<'_> {
    /// The same place at another frame.
    fn same_run(&self, o: &At) -> bool {
        (self.scene, self.rays, self.camera, self.denoiser, self.pipeline)
            == (o.scene, o.rays, o.camera, o.denoiser, o.pipeline)
    }
}

/// A cell's place as the verdicts carry it.
#[derive(Debug, Clone, PartialEq)]
pub struct Place {
    pub scene: String,
    pub rays: u32,
    pub camera: String,
    pub denoiser: String,
    pub pipeline: String,
    pub frame: u32,
    /// The pipeline's floor (`JobResult::floor`: its bias on per-pixel-unbiased input) here.
    pub floor: f64,
}

impl Place {
    fn of(at: &At, floor: f64) -> Self {
        Place {
            scene: at.scene.into(),
            rays: at.rays,
            camera: at.camera.into(),
            denoiser: at.denoiser.into(),
            pipeline: at.pipeline.into(),
            frame: at.frame,
            floor,
        }
    }

    /// "svgf (frame 64)", with the camera unless static and the denoiser if any.
    pub fn pipeline_text(&self) -> String {
        let mut s = self.pipeline.clone();
        if !self.denoiser.is_empty() {
            s = format!("{s} + {}", self.denoiser);
        }
        format!("{s} (frame {})", self.frame)
    }
}

/// (place) → configuration → its replicates, in replicate order.
type Cells<'a> = BTreeMap<At<'a>, BTreeMap<Config, Vec<Measured>>>;

fn cells(results: &[JobResult]) -> Cells<'_> {
    let mut out: Cells = BTreeMap::new();
    for r in results {
        let (Some(config), Some(m)) = (Config::of(r), r.measurement()) else { continue };
        let at = At {
            scene: &r.scene,
            rays: r.rays,
            camera: &r.camera,
            denoiser: &r.denoiser,
            pipeline: &r.pipeline,
            frame: r.frame,
            temporal: m.pipeline.is_temporal(),
            raw: m.pipeline == crate::denoise::Pipeline::RAW,
        };
        // Records made before the split from replicates carry the joint application's noise RMSE
        // (against the reference under the noisy frames' weights) per replicate: read as it was.
        let noise = if r.bias_rmse.is_finite() {
            (r.rmse * r.rmse - r.bias_rmse * r.bias_rmse).max(0.0).sqrt()
        } else {
            r.noise_rmse
        };
        out.entry(at).or_default().entry(config).or_default().push(Measured {
            replicate: r.replicate,
            rmse: r.rmse,
            noise,
            bias_rmse: r.bias_rmse,
            bias_se: r.bias_se,
            noise_rmse: r.noise_rmse,
            floor: r.floor.unwrap_or(f64::NAN),
            flip: r.flip,
        });
    }
    for configs in out.values_mut() {
        configs.values_mut().for_each(|v| v.sort_by_key(|m| m.replicate));
    }
    out
}

/// Whether the spec measured anything real-time (more than one frame, schedule or pipeline).
pub fn any(results: &[JobResult]) -> bool {
    results.iter().any(|r| !r.is_single_frame())
}

/// Which error a margin is of.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Of {
    Rmse,
    Noise,
    /// Mean LDR-FLIP: the perceptual error engine developers report, which can rank two
    /// configurations the other way from RMSE (issue 45).
    Flip,
}

fn keyed(v: &[Measured], of: Of) -> Vec<(u32, f64)> {
    let value = |m: &Measured| match of {
        Of::Rmse => m.rmse,
        Of::Noise => m.noise,
        Of::Flip => m.flip,
    };
    v.iter().map(|m| (m.replicate, value(m))).collect()
}

/// A configuration's mean error over its replicates and that mean's standard error (∞ for one).
fn estimate(v: &[Measured], of: Of) -> Estimate {
    let (value, se) = mean_and_standard_error(&keyed(v, of).into_iter().map(|x| x.1).collect::<Vec<_>>());
    Estimate { value, se }
}

fn mean_rmse(v: &[Measured]) -> f64 {
    v.iter().map(|m| m.rmse).sum::<f64>() / v.len() as f64
}

/// A configuration's split (`JobResult::bias_rmse`, `noise_rmse`): the same in each replicate's
/// record; NaN where not measured (one replicate).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Parts {
    /// The bias and its standard error.
    pub bias: Estimate,
    pub noise: f64,
}

impl Parts {
    fn of(v: &[Measured]) -> Self {
        // A record made before the split has no bias: its noise RMSE is another measure.
        let m = v.first().copied().filter(|m| m.bias_rmse.is_finite());
        Parts {
            bias: Estimate {
                value: m.map_or(f64::NAN, |m| m.bias_rmse),
                se: m.map_or(f64::NAN, |m| m.bias_se),
            },
            noise: m.map_or(f64::NAN, |m| m.noise_rmse),
        }
    }
}

/// The cell's floor (the same for every configuration of one place; NaN if none was measured).
fn floor_of(configs: &BTreeMap<Config, Vec<Measured>>) -> f64 {
    configs.values().flatten().map(|m| m.floor).find(|f| f.is_finite()).unwrap_or(f64::NAN)
}

/// Whether either mean RMSE is below the floor: the filter's bias cancelling a sampler's, so the
/// cell's RMSE verdict is no win (`report` says so beside it).
fn below(floor: f64, means: &[f64]) -> bool {
    floor.is_finite() && floor > 0.0 && means.iter().any(|&m| m < floor)
}

/// `b` against `a`: the paired margin b − a (`relative()` to a's mean) and its verdict at
/// [`ALPHA`]: +1 when b has significantly more error (a wins), −1 less (b wins), 0 a tie (or
/// fewer than two pairs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Versus {
    pub margin: Margin,
    pub sign: i32,
}

impl Versus {
    fn of(a: &[Measured], b: &[Measured], of: Of) -> Self {
        let margin = margin::paired(&keyed(a, of), &keyed(b, of));
        Self { margin, sign: margin.sign(ALPHA) }
    }
}

impl Versus {
    /// Whether the margin was measured (two or more replicates with the metric): records without
    /// `flip` give no FLIP verdict ("—"), never a tie.
    pub fn measured(&self) -> bool {
        self.margin.n >= 2 && self.margin.relative().is_finite()
    }
}

/// Whether RMSE and FLIP disagree in a cell: FLIP was measured and the two verdicts differ, one of
/// them a win (the other a tie, the other side's win, or an RMSE verdict withheld as below floor or
/// a bias interaction).
fn disagree(rmse: &Versus, withheld: bool, flip: &Versus) -> bool {
    let rmse_sign = if withheld { 0 } else { rmse.sign };
    flip.measured() && rmse_sign != flip.sign
}

/// Whether `rmse` (b against a) is a bias interaction (module doc): a verdict whose margin is
/// within the difference of the two biases while the noise parts rank the other way.
fn interaction(a: &[Measured], b: &[Measured], rmse: &Versus) -> bool {
    let (pa, pb) = (Parts::of(a), Parts::of(b));
    let d_bias = (pb.bias.value - pa.bias.value).abs();
    let d_noise = pb.noise - pa.noise;
    rmse.sign != 0 && rmse.margin.mean.abs() <= d_bias && d_noise * rmse.margin.mean < 0.0
}
