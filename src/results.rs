//! One record per rendered job, its CSV/JSON forms (as strings: `io` writes them), the aggregates
//! over replicates, the timing columns (`results/timing.rs`) and the convergence slopes
//! (`results/slopes.rs`).

mod slopes;
mod timing;

pub use slopes::{Slope, SlopeFit, convergence_slopes};
pub use timing::{efficiency_spread, fill_timing};

use crate::metrics::{ErrorStats, mean_sd};
use crate::plan::Job;
use crate::spec::Row;
use crate::timing::Summary;
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;

/// Column order of `results.csv`; the first fourteen are the ones issue 4 promises.
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
];

/// The columns that hold measured times (everything else is bit-identical between runs).
pub const TIME_COLUMNS: &[&str] = &[
    "time_s",
    "rays_per_s",
    "time_median_s",
    "time_min_s",
    "time_max_s",
    "overhead_s",
    "ao_time_s",
    "ns_per_ray",
    "efficiency",
    "wall_s",
];

/// The measurements of one job. Names are strings so a results file stays readable even if a
/// variant is renamed later. Times are those of the timing protocol (`crate::timing`): the CPU
/// time of the one thread that rendered the image, render only (no reference, metrics or IO).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
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
    /// This job's own render time (the median of its renders when it was rendered more than once).
    #[serde(deserialize_with = "timing::nan_null")]
    pub time_s: f64,
    /// `rays_cast / time_s`; 0 when the time was too short to measure.
    pub rays_per_s: f64,
    pub rays_cast: u64,
    /// Median, min and max over every timed render of the configuration (all its replicates and
    /// timing-only re-renders), and how many there were.
    #[serde(deserialize_with = "timing::nan_null")]
    pub time_median_s: f64,
    #[serde(deserialize_with = "timing::nan_null")]
    pub time_min_s: f64,
    #[serde(deserialize_with = "timing::nan_null")]
    pub time_max_s: f64,
    pub timings: usize,
    /// Median time of the scene's render with no AO rays: primary rays and per-image setup.
    #[serde(deserialize_with = "timing::nan_null")]
    pub overhead_s: f64,
    /// `time_median_s − overhead_s`: what the AO rays cost (points, warps, tracing); NaN (empty)
    /// when not above the overhead.
    #[serde(deserialize_with = "timing::nan_null")]
    pub ao_time_s: f64,
    /// `ao_time_s` per AO ray cast, in nanoseconds: the marginal cost of a ray.
    #[serde(deserialize_with = "timing::nan_null")]
    pub ns_per_ray: f64,
    /// 1 / (MSE · ao_time_s), in 1/s; `None` (empty in CSV, null in JSON) when that is undefined.
    /// Overhead is left out so that it cannot dominate at low ray counts.
    pub efficiency: Option<f64>,
    /// Threads each timed render ran on.
    pub timing_threads: u32,
    /// Median wall time of this job's renders, for comparison with `time_s`.
    #[serde(deserialize_with = "timing::nan_null")]
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
}

impl JobResult {
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
        }
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
            times: Vec::new(),
            walls: Vec::new(),
            ..self.clone()
        }
    }
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) { format!("\"{}\"", s.replace('"', "\"\"")) } else { s.to_string() }
}

/// Shortest text that reads back to the same f64; non-finite as empty.
fn num(x: f64) -> String {
    if x.is_finite() { format!("{x}") } else { String::new() }
}

/// `results.csv`: a header with `CSV_COLUMNS`, then one line per record.
pub fn to_csv(results: &[JobResult]) -> String {
    let mut s = CSV_COLUMNS.join(",");
    s.push('\n');
    for r in results {
        let fields = [
            csv_field(&r.scene),
            csv_field(&r.distribution),
            csv_field(&r.sequence),
            csv_field(&r.seed_mode),
            r.rays.to_string(),
            r.replicate.to_string(),
            r.seed.to_string(),
            num(r.rmse),
            num(r.bias),
            num(r.autocorr_x),
            num(r.autocorr_y),
            num(r.lowpass_rmse),
            num(r.time_s),
            num(r.rays_per_s),
            r.rays_cast.to_string(),
            num(r.time_median_s),
            num(r.time_min_s),
            num(r.time_max_s),
            r.timings.to_string(),
            num(r.overhead_s),
            num(r.ao_time_s),
            num(r.ns_per_ray),
            r.efficiency.map_or(String::new(), num),
            r.timing_threads.to_string(),
            num(r.wall_s),
            r.covered_pixels.to_string(),
            csv_field(&r.key),
            csv_field(&r.image),
        ];
        s.push_str(&fields.join(","));
        s.push('\n');
    }
    s
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

#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Stat {
    pub mean: f64,
    pub sd: f64,
}

impl Stat {
    fn of(values: &[f64]) -> Self {
        let (mean, sd) = mean_sd(values);
        Self { mean, sd }
    }
}

/// One configuration, over its replicates.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Aggregate {
    pub scene: String,
    pub distribution: String,
    pub sequence: String,
    pub seed_mode: String,
    pub rays: u32,
    pub replicates: usize,
    pub rmse: Stat,
    pub bias: Stat,
    pub autocorr_x: Stat,
    pub autocorr_y: Stat,
    pub lowpass_rmse: Stat,
    /// Mean squared error per replicate, mean ± sd: what efficiency divides by.
    pub mse: Stat,
    /// Over every timed render of the configuration (`None` before any).
    pub time: Option<Summary>,
    pub overhead_s: f64,
    pub ao_time_s: f64,
    pub ns_per_ray: f64,
    /// Mean AO rays per image.
    pub rays_cast: f64,
    /// `rays_cast / time.median`.
    pub rays_per_s: f64,
    /// 1 / (mean MSE · AO time), in 1/s (NaN when undefined), and its spread (see
    /// [`efficiency_spread`]).
    pub efficiency: f64,
    pub efficiency_spread: f64,
}

/// Mean and sd per (scene, distribution, sequence, seed_mode, rays), in order of first appearance;
/// the timing columns from the records (`fill_timing` has set them).
pub fn aggregate(results: &[JobResult]) -> Vec<Aggregate> {
    let mut configs: Vec<(&str, &str, &str, &str, u32)> = Vec::new();
    for r in results {
        if !configs.contains(&r.config()) {
            configs.push(r.config());
        }
    }
    configs
        .into_iter()
        .map(|c| {
            let rs: Vec<&JobResult> = results.iter().filter(|r| r.config() == c).collect();
            let st = |f: &dyn Fn(&JobResult) -> f64| Stat::of(&rs.iter().map(|r| f(r)).collect::<Vec<_>>());
            let samples: Vec<f64> = rs.iter().flat_map(|r| r.times.iter().copied()).collect();
            let time = Summary::of(&samples);
            let first = rs[0];
            let mse = st(&|r| r.rmse * r.rmse);
            let rays_cast = rs.iter().map(|r| r.rays_cast as f64).sum::<f64>() / rs.len() as f64;
            let median = time.map_or(f64::NAN, |t| t.median);
            let efficiency = crate::metrics::efficiency(mse.mean.sqrt(), first.ao_time_s).unwrap_or(f64::NAN);
            Aggregate {
                scene: c.0.into(),
                distribution: c.1.into(),
                sequence: c.2.into(),
                seed_mode: c.3.into(),
                rays: c.4,
                replicates: rs.len(),
                rmse: st(&|r| r.rmse),
                bias: st(&|r| r.bias),
                autocorr_x: st(&|r| r.autocorr_x),
                autocorr_y: st(&|r| r.autocorr_y),
                lowpass_rmse: st(&|r| r.lowpass_rmse),
                mse,
                time,
                overhead_s: first.overhead_s,
                ao_time_s: first.ao_time_s,
                ns_per_ray: first.ns_per_ray,
                rays_cast,
                rays_per_s: if median > 0.0 { rays_cast / median } else { f64::NAN },
                efficiency,
                efficiency_spread: efficiency_spread(efficiency, mse, rs.len(), time, first.ao_time_s),
            }
        })
        .collect()
}

/// The aggregate of one cell of a table (`row` is canonicalized, so random+shift finds random+rotation).
pub fn lookup<'a>(aggs: &'a [Aggregate], scene: &str, row: Row, rays: u32) -> Option<&'a Aggregate> {
    let row = row.canonical();
    aggs.iter().find(|a| {
        a.scene == scene
            && a.rays == rays
            && a.distribution == row.distribution.name()
            && a.sequence == row.sequence.name()
            && a.seed_mode == row.seed_mode.name()
    })
}

/// Column order of the aggregate CSV.
pub fn aggregate_columns() -> Vec<String> {
    let mut c: Vec<String> =
        ["scene", "distribution", "sequence", "seed_mode", "rays", "replicates"].map(String::from).to_vec();
    for m in AGG_METRICS {
        c.push(format!("{m}_mean"));
        c.push(format!("{m}_sd"));
    }
    c.extend(AGG_TIMING.map(String::from));
    c
}

const AGG_METRICS: [&str; 5] = ["rmse", "bias", "autocorr_x", "autocorr_y", "lowpass_rmse"];
const AGG_TIMING: [&str; 10] = [
    "time_median_s",
    "time_min_s",
    "time_max_s",
    "timings",
    "overhead_s",
    "ao_time_s",
    "ns_per_ray",
    "rays_per_s",
    "efficiency",
    "efficiency_spread",
];

/// `aggregates.csv`: one line per configuration.
pub fn aggregates_to_csv(aggs: &[Aggregate]) -> String {
    let mut s = aggregate_columns().join(",");
    s.push('\n');
    for a in aggs {
        let _ = write!(
            s,
            "{},{},{},{},{},{}",
            csv_field(&a.scene),
            csv_field(&a.distribution),
            csv_field(&a.sequence),
            csv_field(&a.seed_mode),
            a.rays,
            a.replicates
        );
        for st in [a.rmse, a.bias, a.autocorr_x, a.autocorr_y, a.lowpass_rmse] {
            let _ = write!(s, ",{},{}", num(st.mean), num(st.sd));
        }
        let t = a.time;
        let f = |g: fn(&Summary) -> f64| t.as_ref().map_or(String::new(), |t| num(g(t)));
        let _ = write!(
            s,
            ",{},{},{},{},{},{},{},{},{},{}",
            f(|t| t.median),
            f(|t| t.min),
            f(|t| t.max),
            t.map_or(0, |t| t.n),
            num(a.overhead_s),
            num(a.ao_time_s),
            num(a.ns_per_ray),
            num(a.rays_per_s),
            num(a.efficiency),
            num(a.efficiency_spread)
        );
        s.push('\n');
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{Distribution, SeedMode, Sequence};

    fn job(rays: u32, replicate: u32) -> Job {
        Job {
            scene: "scenes/k.toml".into(),
            scene_id: "../scenes/k.toml".into(),
            scene_name: "k".into(),
            distribution: Distribution::SineCosine,
            sequence: Sequence::Fibonacci,
            seed_mode: SeedMode::Rotation,
            rays,
            replicate,
            seed: crate::plan::replicate_seed(1, replicate),
            resolution: Some([4, 4]),
            ao_distance: None,
        }
    }

    fn result(rays: u32, replicate: u32, rmse: f64, time_s: f64) -> JobResult {
        let stats = ErrorStats {
            covered: 16,
            rmse,
            bias: 0.01 * replicate as f64,
            autocorr_x: 0.1,
            autocorr_y: -0.1,
            lowpass_rmse: rmse / 4.0,
        };
        let mut r = JobResult::new(
            &job(rays, replicate),
            &stats,
            16 * rays as u64,
            format!("img{rays}-{replicate}.exr"),
        );
        r.add_time(time_s, time_s * 1.5);
        r
    }

    /// Records with their configuration's timing columns, the overhead 0.1 s.
    fn timed(mut rs: Vec<JobResult>, overhead: f64) -> Vec<JobResult> {
        fill_timing(&mut rs, &|scene| (scene == "k").then_some(overhead));
        rs
    }

    #[test]
    fn csv_header_columns_are_exact() {
        let csv = to_csv(&timed(vec![result(8, 0, 0.1, 0.5)], 0.1));
        let mut lines = csv.lines();
        assert_eq!(
            lines.next().unwrap(),
            "scene,distribution,sequence,seed_mode,rays,replicate,seed,rmse,bias,autocorr_x,autocorr_y,\
             lowpass_rmse,time_s,rays_per_s,rays_cast,time_median_s,time_min_s,time_max_s,timings,overhead_s,\
             ao_time_s,ns_per_ray,efficiency,timing_threads,wall_s,covered_pixels,key,image"
        );
        let row: Vec<&str> = lines.next().unwrap().split(',').collect();
        assert_eq!(row.len(), CSV_COLUMNS.len());
        let col = |name: &str| row[CSV_COLUMNS.iter().position(|c| *c == name).unwrap()];
        assert_eq!(&row[..6], &["k", "sine-cosine", "fibonacci", "rotation", "8", "0"]);
        assert_eq!(col("rmse"), "0.1");
        assert_eq!((col("time_s"), col("rays_per_s"), col("rays_cast")), ("0.5", "256", "128"));
        assert_eq!(
            (col("time_median_s"), col("time_min_s"), col("time_max_s"), col("timings")),
            ("0.5", "0.5", "0.5", "1")
        );
        assert_eq!((col("overhead_s"), col("ao_time_s")), ("0.1", "0.4"));
        assert_eq!(col("ns_per_ray"), (1e9 * 0.4 / 128.0).to_string());
        assert_eq!(col("efficiency"), (1.0 / (0.1f64 * 0.1 * 0.4)).to_string());
        assert_eq!((col("timing_threads"), col("wall_s")), ("1", "0.75"));
        assert_eq!(col("key"), job(8, 0).key());
        for c in TIME_COLUMNS {
            assert!(CSV_COLUMNS.contains(c), "{c}");
        }
    }

    #[test]
    fn csv_quotes_awkward_fields_and_leaves_undefined_empty() {
        let mut r = result(8, 0, 0.0, 0.0);
        r.image = "a,b \"c\".exr".into();
        let csv = to_csv(&timed(vec![r], 0.1));
        let line = csv.lines().nth(1).unwrap();
        assert!(line.ends_with(",\"a,b \"\"c\"\".exr\""), "{line}");
        assert!(line.contains(",0,0,128,"), "time and rays_per_s 0: {line}");
        assert!(
            line.contains(",0.1,,,,1,"),
            "below the overhead: AO time, ns per ray, efficiency empty: {line}"
        );
    }

    #[test]
    fn json_round_trips_exactly() {
        // 0.10253214158314959 reads back one ulp off without serde_json's `float_roundtrip`, which
        // made a resumed run's numbers differ from an uninterrupted one's.
        let rs = timed(
            vec![
                result(8, 0, 0.1, 0.5),
                result(8, 1, 0.12345678901234567, 0.0),
                result(4, 0, 0.10253214158314959, 1.0),
            ],
            0.3,
        );
        let back = from_json(&to_json(&rs)).unwrap();
        assert_eq!(back[2], rs[2]);
        // Undefined columns (NaN) are null in JSON and read back as NaN.
        assert!(rs[0].ao_time_s.is_nan() && back[0].ao_time_s.is_nan());
        assert_eq!(to_json(&back), to_json(&rs));
        assert_eq!(to_csv(&back), to_csv(&rs));
        let e = from_json("[{\"scene\": 1}]").unwrap_err();
        assert!(e.contains("line"), "{e}");
    }

    #[test]
    fn aggregates_over_replicates_and_slopes() {
        let mut rs = Vec::new();
        for rays in [1u32, 4, 16, 64] {
            for rep in 0..3 {
                // RMSE ∝ rays^-1/2, time = 5 ms overhead + 10 ms per ray per pixel; replicate spread ±10 %.
                let wobble = 1.0 + 0.1 * (rep as f64 - 1.0);
                rs.push(result(rays, rep, 0.4 / (rays as f64).sqrt() * wobble, 0.005 + 0.01 * rays as f64));
            }
        }
        let rs = timed(rs, 0.005);
        let aggs = aggregate(&rs);
        assert_eq!(aggs.len(), 4);
        let a = &aggs[1];
        assert_eq!((a.rays, a.replicates), (4, 3));
        assert!((a.rmse.mean - 0.2).abs() < 1e-12);
        assert!((a.rmse.sd - 0.02).abs() < 1e-12, "{:?}", a.rmse);
        assert!((a.bias.mean - 0.01).abs() < 1e-12);
        let t = a.time.unwrap();
        assert_eq!((t.n, t.median), (3, 0.045));
        assert!((a.ao_time_s - 0.04).abs() < 1e-15 && (a.ns_per_ray - 0.04e9 / 64.0).abs() < 1e-6);
        // MSE ∝ 1/rays and AO time ∝ rays: the same efficiency at every ray count, whatever the overhead.
        let e = 1.0 / (0.0016 * (0.81 + 1.0 + 1.21) / 3.0);
        for a in &aggs {
            assert!((a.efficiency - e).abs() < 1e-9 * e, "{}", a.efficiency);
            let se = a.mse.sd / 3f64.sqrt() / a.mse.mean;
            assert!((a.efficiency_spread - e * se).abs() < 1e-9 * e, "identical times: only the MSE's error");
        }
        let slopes = convergence_slopes(&aggs, &[]);
        assert_eq!(slopes.len(), 1);
        assert_eq!(slopes[0].points, 4);
        let fit = slopes[0].vs_rays.unwrap();
        assert!((fit.value + 0.5).abs() < 1e-9);
        let [lo, hi] = fit.ci95.unwrap();
        assert!(lo <= fit.value && fit.value <= hi && hi - lo < 1e-6, "an exact power law: {fit:?}");
        assert!((slopes[0].vs_ao_time.unwrap().value + 0.5).abs() < 1e-9);
        assert!(slopes[0].vs_time.unwrap().value < -0.5, "the overhead steepens the slope against time");
        let cost = slopes[0].cost.unwrap();
        assert!(
            (cost.overhead_s - 0.005).abs() < 1e-12 && (cost.ns_per_ray - 0.01e9 / 16.0).abs() < 1e-3,
            "{cost:?}"
        );
        let two = convergence_slopes(&aggs, &[4, 16]);
        assert_eq!(two[0].points, 2);
        assert_eq!(two[0].vs_rays.unwrap().ci95, None, "two points: no interval");
        assert_eq!(convergence_slopes(&aggs, &[4])[0].vs_rays, None);
        let row = Row::new(Distribution::SineCosine, Sequence::Fibonacci, SeedMode::Rotation);
        assert_eq!(lookup(&aggs, "k", row, 16).map(|a| a.rays), Some(16));
        assert!(lookup(&aggs, "k", row, 32).is_none());
        assert!(lookup(&aggs, "other", row, 16).is_none());
        let csv = aggregates_to_csv(&aggs);
        assert!(csv.starts_with("scene,distribution,sequence,seed_mode,rays,replicates,rmse_mean,rmse_sd,"));
        assert_eq!(csv.lines().count(), 5);
    }
}
