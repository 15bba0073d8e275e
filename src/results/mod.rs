//! One record per rendered job and its CSV/JSON forms (as strings: `io` writes them); the timing
//! columns (`results/timing.rs`), the aggregates over replicates (`results/aggregate.rs`) and the
//! convergence slopes (`results/slopes.rs`).

mod aggregate;
mod csv;
mod slopes;
mod split;

pub use aggregate::{Aggregate, Stat, aggregate, aggregate_columns, aggregates_to_csv, lookup};
pub use csv::to_csv;
pub use slopes::{Slope, SlopeFit, SweepSlopes, convergence_slopes, sweep_slopes};
pub use split::{efficiency_spread, fill_timing};

use crate::metrics::ErrorStats;
use crate::plan::{Job, Measurement};
use crate::spec::Row;
use serde::{Deserialize, Serialize};

/// Column order of `results.csv`; the first fourteen are the original columns,
/// kept in place so that scripts reading them by position still work; later columns
/// (whiteness_z, the timing columns, …, lowfreq_ratio) were appended after them, in the order
/// they were added.
pub const CSV_COLUMNS: &[&str] = &[
    "scene",
    "distribution",
    "sequence",
    "seed_mode",
    "rays",
    "replicate",
    "seed",
    "rmse",
    "bias",
    "autocorr_x",
    "autocorr_y",
    "lowpass_rmse",
    "time_s",
    "rays_per_s",
    "whiteness_z",
    "rays_cast",
    "time_median_s",
    "time_min_s",
    "time_max_s",
    "timings",
    "overhead_s",
    "ao_time_s",
    "ns_per_ray",
    "efficiency",
    "timing_threads",
    "wall_s",
    "covered_pixels",
    "key",
    "image",
    "lowfreq_ratio",
    "pipeline",
    "frame",
    "schedule",
    "noise_rmse",
    "integrand",
    "camera",
    "denoiser",
    "flicker",
    "floor",
    "denoise_s",
    "flip",
    "bias_rmse",
    "bias_se",
];

/// The columns that hold measured times, or depend on them (how many renders a configuration got:
/// cheap ones get more); everything else is bit-identical between runs.
pub const TIME_COLUMNS: &[&str] = &[
    "time_s",
    "rays_per_s",
    "time_median_s",
    "time_min_s",
    "time_max_s",
    "timings",
    "overhead_s",
    "ao_time_s",
    "ns_per_ray",
    "efficiency",
    "wall_s",
    "denoise_s",
];

/// The measurements of one job. Names are strings so a results file stays readable even if a
/// variant is renamed later. Times are those of the timing protocol (`crate::timing`): the CPU
/// time of the one thread that rendered the image, render only (no reference, metrics or IO).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JobResult {
    pub scene: String,
    pub distribution: String,
    pub sequence: String,
    pub seed_mode: String,
    pub rays: u32,
    pub replicate: u32,
    pub seed: u64,
    pub rmse: f64,
    pub bias: f64,
    pub autocorr_x: f64,
    pub autocorr_y: f64,
    pub lowpass_rmse: f64,
    /// z-score of the error's 2-D portmanteau statistic against white noise (`metrics::whiteness`).
    pub whiteness_z: f64,
    /// Low-pass energy of the error over that of independent per-pixel errors of the same
    /// magnitudes (`metrics::lowfreq`): 1 white, < 1 blue, > 1 clumped; the structure verdict.
    pub lowfreq_ratio: f64,
    /// This job's own render time (the median of its renders when it was rendered more than once).
    #[serde(deserialize_with = "split::nan_null")]
    pub time_s: f64,
    /// `rays_cast / time_s`; 0 when the time was too short to measure.
    pub rays_per_s: f64,
    pub rays_cast: u64,
    /// Median, min and max over every timed render of the configuration (all its replicates and
    /// timing-only re-renders), and how many there were.
    #[serde(deserialize_with = "split::nan_null")]
    pub time_median_s: f64,
    #[serde(deserialize_with = "split::nan_null")]
    pub time_min_s: f64,
    #[serde(deserialize_with = "split::nan_null")]
    pub time_max_s: f64,
    pub timings: usize,
    /// Median time of the scene's render with no AO rays: primary rays and per-image setup.
    #[serde(deserialize_with = "split::nan_null")]
    pub overhead_s: f64,
    /// `time_median_s − overhead_s`: what the AO rays cost (points, warps, tracing); NaN (empty)
    /// when not above the overhead.
    #[serde(deserialize_with = "split::nan_null")]
    pub ao_time_s: f64,
    /// `ao_time_s` per AO ray cast, in nanoseconds: the marginal cost of a ray.
    #[serde(deserialize_with = "split::nan_null")]
    pub ns_per_ray: f64,
    /// 1 / (MSE · ao_time_s), in 1/s; `None` (empty in CSV, null in JSON) when that is undefined.
    /// Overhead is left out so that it cannot dominate at low ray counts.
    pub efficiency: Option<f64>,
    /// Threads each timed render ran on.
    pub timing_threads: u32,
    /// Median wall time of this job's renders, for comparison with `time_s`.
    #[serde(deserialize_with = "split::nan_null")]
    pub wall_s: f64,
    pub covered_pixels: u64,
    /// The resume key: a rerun skips a job whose key is already here.
    pub key: String,
    /// The job's image file, relative to the output directory.
    pub image: String,
    /// Every timed render of this job (thread CPU seconds), in the order they ran.
    pub times: Vec<f64>,
    /// Their wall times.
    pub walls: Vec<f64>,
    /// What was done to the frames before measuring (`denoise::Pipeline`'s name); `rmse` and the
    /// other error columns are of the image after it, against the reference.
    #[serde(default = "raw")]
    pub pipeline: String,
    /// The measured frame, from 1 (`Job::frame`).
    #[serde(default = "one")]
    pub frame: u32,
    /// The per-frame randomization schedule.
    #[serde(default = "independent")]
    pub schedule: String,
    /// The noise part of the configuration's error, measured from its replicates
    /// (`metrics::replicates`): √(mean over covered pixels of each pixel's sample variance over the
    /// replicates), what a new seed changes. The same in every replicate's record; NaN (empty,
    /// null) with one replicate or where the images were not kept.
    #[serde(default = "nan", deserialize_with = "split::nan_null")]
    pub noise_rmse: f64,
    /// What the rays integrated (`sampling::Integrand`'s name): `ao` for every record written
    /// before the column existed.
    #[serde(default = "ao")]
    pub integrand: String,
    /// The camera path over the frames (`plan::CameraId`'s name): `static` for the scene's camera.
    #[serde(default = "static_camera")]
    pub camera: String,
    /// The user's denoiser run after the pipeline (its spec name), empty for none.
    #[serde(default)]
    pub denoiser: String,
    /// The image's temporal instability against the reference's: the RMS over covered pixels of
    /// (o_t − o_{t−1}) − (r_t − r_{t−1}) between this frame and the one before (`metrics::flicker`);
    /// None (empty, null) for frame 1, a single frame, and where it is not measured.
    #[serde(default)]
    pub flicker: Option<f64>,
    /// The floor of the pipeline at this place (scene, rays, pipeline, frame, camera, denoiser):
    /// its `bias_rmse` measured on input that is unbiased in every pixel (`jobs::replicates` says
    /// which configuration); None (empty, null) where no such configuration has two replicates.
    /// An RMSE below its floor is the filter's bias cancelling the sampler's, never a win.
    #[serde(default)]
    pub floor: Option<f64>,
    /// The user's denoiser's wall-clock time on this frame's image, seconds (0 without one): apart
    /// from the render's time, which never includes it.
    #[serde(default)]
    pub denoise_s: f64,
    /// Mean LDR-FLIP (`metrics::flip`, Andersson et al. 2020) of the image against its reference
    /// over covered pixels, at the spec's `flip_ppd` pixels per degree (default 67): the perceptual error
    /// the real-time field reports beside RMSE (the two can rank images differently). NaN (empty,
    /// null) where it was not measured, as in records written before the column existed.
    #[serde(default = "nan", deserialize_with = "split::nan_null")]
    pub flip: f64,
    /// The bias part of the configuration's error, measured from its replicates
    /// (`metrics::replicates`): √max(bias², 0), bias² = mean over covered pixels of
    /// (x̄ − ref)² − s²/R. With `noise_rmse`, bias² + noise² is the mean MSE over the replicates.
    /// The same in every replicate's record; NaN (empty, null) with one replicate.
    #[serde(default = "nan", deserialize_with = "split::nan_null")]
    pub bias_rmse: f64,
    /// The standard error of `bias_rmse` (the jackknife over replicates of bias², by the delta
    /// method); NaN below three replicates or where the bias is 0.
    #[serde(default = "nan", deserialize_with = "split::nan_null")]
    pub bias_se: f64,
    /// The first frame the run rendered (from 1) when a steady-state measurement started later
    /// than frame 1 (`plan::Measurement::first_frame`: advise after an accumulating pipeline);
    /// absent from the file when 1, so that every other record is written as before. Not a CSV
    /// column: `time_s` over the frames rendered is what a reader wants, and advise gives it.
    #[serde(default = "one", skip_serializing_if = "is_one")]
    pub first_frame: u32,
}

fn is_one(f: &u32) -> bool {
    *f == 1
}

/// Two records are the same when their files are: an undefined column (NaN, null in JSON) equals
/// an undefined one, so that two runs' records with an undefined split (one replicate, no jackknife
/// below three) still compare equal (resume, merge's duplicate check).
impl PartialEq for JobResult {
    fn eq(&self, other: &Self) -> bool {
        serde_json::to_value(self).ok() == serde_json::to_value(other).ok()
    }
}

fn raw() -> String {
    "raw".into()
}
fn one() -> u32 {
    1
}
fn independent() -> String {
    "independent".into()
}
fn nan() -> f64 {
    f64::NAN
}
fn ao() -> String {
    "ao".into()
}
fn static_camera() -> String {
    crate::plan::CameraId::STATIC_NAME.into()
}

/// The one "this record belongs to that configuration" rule, for records and aggregates alike:
/// the row is canonicalized first (`Row::canonical`: pseudo-random with a shift names the same
/// images as with a rotation).
fn names_row(names: [&str; 3], row: Row) -> bool {
    let row = row.canonical();
    names == [row.distribution.name(), row.sequence.name(), row.seed_mode.name()]
}

impl JobResult {
    /// Whether this record is an image of `row` (any scene, any ray count).
    pub fn is_row(&self, row: Row) -> bool {
        names_row([&self.distribution, &self.sequence, &self.seed_mode], row)
    }

    /// Whether this record is an image of (scene, row, rays).
    /// A paper-table image: real-time records (`is_single_frame` false) are not.
    pub fn is(&self, scene: &str, row: Row, rays: u32) -> bool {
        self.scene == scene && self.rays == rays && self.is_row(row) && self.is_single_frame()
    }

    /// A record with its error metrics and no time yet (`add_time`, then `fill_timing`).
    pub fn new(job: &Job, stats: &ErrorStats, rays_cast: u64, image: impl Into<String>) -> Self {
        Self {
            scene: job.scene_name.clone(),
            distribution: job.distribution.name().into(),
            sequence: job.sequence.name().into(),
            seed_mode: job.seed_mode.name().into(),
            rays: job.rays,
            replicate: job.replicate,
            seed: job.seed,
            rmse: stats.rmse,
            bias: stats.bias,
            autocorr_x: stats.autocorr_x,
            autocorr_y: stats.autocorr_y,
            lowpass_rmse: stats.lowpass_rmse,
            whiteness_z: stats.whiteness_z,
            lowfreq_ratio: stats.lowfreq_ratio,
            time_s: f64::NAN,
            rays_per_s: 0.0,
            rays_cast,
            time_median_s: f64::NAN,
            time_min_s: f64::NAN,
            time_max_s: f64::NAN,
            timings: 0,
            overhead_s: f64::NAN,
            ao_time_s: f64::NAN,
            ns_per_ray: f64::NAN,
            efficiency: None,
            timing_threads: 1,
            wall_s: f64::NAN,
            covered_pixels: stats.covered as u64,
            key: job.key(),
            image: image.into(),
            times: Vec::new(),
            walls: Vec::new(),
            pipeline: job.measurement.pipeline.to_string(),
            frame: job.measurement.frame,
            schedule: job.measurement.schedule.name().into(),
            noise_rmse: f64::NAN,
            integrand: job.measurement.integrand.to_string(),
            camera: job.measurement.camera.name(),
            denoiser: job.measurement.denoiser.name(),
            flicker: None,
            floor: None,
            denoise_s: 0.0,
            flip: f64::NAN,
            bias_rmse: f64::NAN,
            bias_se: f64::NAN,
            first_frame: job.measurement.first_frame,
        }
    }

    /// What this record measured, its names parsed (`None` if one is a name this version does not
    /// know: such a record belongs to no table).
    pub fn measurement(&self) -> Option<Measurement> {
        Some(Measurement {
            integrand: self.integrand.parse().ok()?,
            frame: self.frame,
            schedule: self.schedule.parse().ok()?,
            pipeline: self.pipeline.parse().ok()?,
            camera: crate::plan::CameraId::named(&self.camera)?,
            denoiser: crate::plan::DenoiserId::named(&self.denoiser)?,
            // Not a column: every record of a run shares the spec's `[tiles]`, and each image's
            // provenance names the tile set (`jobs::executor::provenance_tiled`).
            tiles: None,
            first_frame: self.first_frame,
        })
    }

    /// The estimator this record measured, its names parsed: (distribution, sequence, seed mode)
    /// and the schedule (`None` if one is a name this version does not know).
    pub fn estimator(&self) -> Option<(Row, crate::sampling::Schedule)> {
        let row = Row::new(
            self.distribution.parse().ok()?,
            self.sequence.parse().ok()?,
            self.seed_mode.parse().ok()?,
        );
        Some((row, self.schedule.parse().ok()?))
    }

    /// Whether this is a paper-table record (one raw frame, `Measurement::is_single_frame`): the
    /// aggregates, comparisons and verdicts of the paper read only these; the multi-frame records
    /// have their own section.
    pub fn is_single_frame(&self) -> bool {
        self.measurement().is_some_and(|m| m.is_single_frame())
    }

    /// A record of `scene` with only what the statistics read (configuration, rays, replicate,
    /// RMSE, low-frequency ratio): the data unit tests of the comparisons and verdicts build.
    #[cfg(test)]
    pub(crate) fn for_test(
        scene: &str,
        row: crate::spec::Row,
        rays: u32,
        replicate: u32,
        rmse: f64,
        lowfreq_ratio: f64,
    ) -> Self {
        let job = Job {
            scene: scene.into(),
            scene_id: scene.into(),
            scene_name: scene.into(),
            distribution: row.distribution,
            sequence: row.sequence,
            seed_mode: row.seed_mode,
            rays,
            replicate,
            seed: replicate as u64,
            resolution: None,
            ao_distance: None,
            measurement: Measurement::PAPER,
        };
        let stats = ErrorStats {
            covered: 1,
            rmse,
            bias: 0.0,
            autocorr_x: 0.0,
            autocorr_y: 0.0,
            lowpass_rmse: 0.0,
            whiteness_z: 0.0,
            lowfreq_ratio,
        };
        Self::new(&job, &stats, rays as u64, "")
    }

    /// Adds one timed render of this job (CPU and wall seconds) and updates its own time.
    pub fn add_time(&mut self, cpu_s: f64, wall_s: f64) {
        self.times.push(cpu_s);
        self.walls.push(wall_s);
        self.time_s = crate::stats::median(&self.times);
        self.wall_s = crate::stats::median(&self.walls);
        self.rays_per_s = if self.time_s > 0.0 { self.rays_cast as f64 / self.time_s } else { 0.0 };
    }

    /// The configuration this record belongs to, replicates aside.
    pub fn config(&self) -> (&str, &str, &str, &str, u32) {
        (&self.scene, &self.distribution, &self.sequence, &self.seed_mode, self.rays)
    }

    /// The record with every measured time blanked (`TIME_COLUMNS` and the sample lists): what
    /// must be identical between two runs of the same spec.
    pub fn without_times(&self) -> Self {
        Self {
            time_s: 0.0,
            rays_per_s: 0.0,
            time_median_s: 0.0,
            time_min_s: 0.0,
            time_max_s: 0.0,
            timings: 0,
            overhead_s: 0.0,
            ao_time_s: 0.0,
            ns_per_ray: 0.0,
            efficiency: None,
            wall_s: 0.0,
            denoise_s: 0.0,
            times: Vec::new(),
            walls: Vec::new(),
            ..self.clone()
        }
    }
}

pub(crate) fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) { format!("\"{}\"", s.replace('"', "\"\"")) } else { s.to_string() }
}

/// Shortest text that reads back to the same f64; non-finite as empty.
pub(crate) fn num(x: f64) -> String {
    if x.is_finite() { format!("{x}") } else { String::new() }
}

/// `results.json`: a pretty array of records (the resume source).
pub fn to_json(results: &[JobResult]) -> String {
    let mut s = serde_json::to_string_pretty(results).expect("plain records always serialize");
    s.push('\n');
    s
}

/// Reads `results.json` back; the message says what is wrong and where (line, column).
pub fn from_json(text: &str) -> Result<Vec<JobResult>, String> {
    serde_json::from_str(text).map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests;
