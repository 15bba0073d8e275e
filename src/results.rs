//! One record per rendered job, its CSV/JSON forms (as strings: `io` writes them), the aggregates
//! over replicates and the convergence slopes.

use crate::metrics::{ErrorStats, efficiency, loglog_slope, mean_sd};
use crate::plan::Job;
use crate::spec::Row;
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;

/// Column order of `results.csv`; the first fourteen are the ones issue 4 promises, so later columns
/// (whiteness_z, …) come after them.
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
    "efficiency",
    "covered_pixels",
    "key",
    "image",
];

/// The measurements of one job. Names are strings so a results file stays readable even if a
/// variant is renamed later.
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
    /// z-score of the error's 2-D portmanteau statistic against white noise (`metrics::whiteness`).
    pub whiteness_z: f64,
    /// Render wall time only (no reference, no IO).
    pub time_s: f64,
    /// 0 when the time was too short to measure.
    pub rays_per_s: f64,
    pub rays_cast: u64,
    /// 1 / (MSE · time); `None` (empty in CSV, null in JSON) when that is undefined.
    pub efficiency: Option<f64>,
    pub covered_pixels: u64,
    /// `Job::key()`: resume skips a job whose key is already here.
    pub key: String,
    /// The job's image file, relative to the output directory.
    pub image: String,
}

impl JobResult {
    pub fn new(job: &Job, stats: &ErrorStats, time_s: f64, rays_cast: u64, image: impl Into<String>) -> Self {
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
            time_s,
            rays_per_s: if time_s > 0.0 { rays_cast as f64 / time_s } else { 0.0 },
            rays_cast,
            efficiency: efficiency(stats.rmse, time_s),
            covered_pixels: stats.covered as u64,
            key: job.key(),
            image: image.into(),
        }
    }

    /// The configuration this record belongs to, replicates aside.
    pub fn config(&self) -> (&str, &str, &str, &str, u32) {
        (&self.scene, &self.distribution, &self.sequence, &self.seed_mode, self.rays)
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
            num(r.whiteness_z),
            r.rays_cast.to_string(),
            r.efficiency.map_or(String::new(), num),
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
    pub whiteness_z: Stat,
    pub time_s: Stat,
    pub rays_per_s: Stat,
    /// Over the replicates whose efficiency is defined (NaN when none).
    pub efficiency: Stat,
}

/// Mean and sd per (scene, distribution, sequence, seed_mode, rays), in order of first appearance.
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
                whiteness_z: st(&|r| r.whiteness_z),
                time_s: st(&|r| r.time_s),
                rays_per_s: st(&|r| r.rays_per_s),
                efficiency: st(&|r| r.efficiency.unwrap_or(f64::NAN)),
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
    c
}

const AGG_METRICS: [&str; 9] = [
    "rmse",
    "bias",
    "autocorr_x",
    "autocorr_y",
    "lowpass_rmse",
    "whiteness_z",
    "time_s",
    "rays_per_s",
    "efficiency",
];

/// `summary.csv`: one line per configuration.
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
        for st in [
            a.rmse,
            a.bias,
            a.autocorr_x,
            a.autocorr_y,
            a.lowpass_rmse,
            a.whiteness_z,
            a.time_s,
            a.rays_per_s,
            a.efficiency,
        ] {
            let _ = write!(s, ",{},{}", num(st.mean), num(st.sd));
        }
        s.push('\n');
    }
    s
}

/// Fitted convergence of one row (scene, distribution, sequence, seed mode).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Slope {
    pub scene: String,
    pub distribution: String,
    pub sequence: String,
    pub seed_mode: String,
    /// Ray counts used in the fit.
    pub points: usize,
    /// d ln(mean RMSE) / d ln(rays): -0.5 for plain Monte Carlo.
    pub vs_rays: Option<f64>,
    /// d ln(mean RMSE) / d ln(mean time).
    pub vs_time: Option<f64>,
}

/// Least-squares log-log slopes per row, over the aggregates whose ray count is in `rays`
/// (all of them when `rays` is empty), rows in order of first appearance.
pub fn convergence_slopes(aggs: &[Aggregate], rays: &[u32]) -> Vec<Slope> {
    let use_it = |a: &Aggregate| rays.is_empty() || rays.contains(&a.rays);
    let mut rows: Vec<(&str, &str, &str, &str)> = Vec::new();
    for a in aggs.iter().filter(|a| use_it(a)) {
        let k = (a.scene.as_str(), a.distribution.as_str(), a.sequence.as_str(), a.seed_mode.as_str());
        if !rows.contains(&k) {
            rows.push(k);
        }
    }
    rows.into_iter()
        .map(|k| {
            let pts: Vec<&Aggregate> = aggs
                .iter()
                .filter(|a| {
                    use_it(a)
                        && (
                            a.scene.as_str(),
                            a.distribution.as_str(),
                            a.sequence.as_str(),
                            a.seed_mode.as_str(),
                        ) == k
                })
                .collect();
            let rmse: Vec<f64> = pts.iter().map(|a| a.rmse.mean).collect();
            let rays: Vec<f64> = pts.iter().map(|a| a.rays as f64).collect();
            let time: Vec<f64> = pts.iter().map(|a| a.time_s.mean).collect();
            Slope {
                scene: k.0.into(),
                distribution: k.1.into(),
                sequence: k.2.into(),
                seed_mode: k.3.into(),
                points: pts.len(),
                vs_rays: loglog_slope(&rays, &rmse),
                vs_time: loglog_slope(&time, &rmse),
            }
        })
        .collect()
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
            whiteness_z: 0.5,
        };
        JobResult::new(
            &job(rays, replicate),
            &stats,
            time_s,
            16 * rays as u64,
            format!("img{rays}-{replicate}.exr"),
        )
    }

    #[test]
    fn csv_header_columns_are_exact() {
        let csv = to_csv(&[result(8, 0, 0.1, 0.5)]);
        let mut lines = csv.lines();
        assert_eq!(
            lines.next().unwrap(),
            "scene,distribution,sequence,seed_mode,rays,replicate,seed,rmse,bias,autocorr_x,autocorr_y,\
             lowpass_rmse,time_s,rays_per_s,whiteness_z,rays_cast,efficiency,covered_pixels,key,image"
        );
        let row: Vec<&str> = lines.next().unwrap().split(',').collect();
        assert_eq!(row.len(), CSV_COLUMNS.len());
        assert_eq!(&row[..6], &["k", "sine-cosine", "fibonacci", "rotation", "8", "0"]);
        assert_eq!(row[7], "0.1");
        assert_eq!(row[13], "256");
        assert_eq!(row[14], "0.5");
        assert_eq!(row[16], (1.0 / (0.1f64 * 0.1 * 0.5)).to_string());
        assert_eq!(row[18], job(8, 0).key());
    }

    #[test]
    fn csv_quotes_awkward_fields_and_leaves_undefined_empty() {
        let mut r = result(8, 0, 0.0, 0.0);
        r.image = "a,b \"c\".exr".into();
        let csv = to_csv(&[r]);
        let line = csv.lines().nth(1).unwrap();
        assert!(line.ends_with(",\"a,b \"\"c\"\".exr\""), "{line}");
        assert!(line.contains(",0,0.5,128,,16,"), "rays_per_s 0, efficiency empty: {line}");
    }

    #[test]
    fn json_round_trips_exactly() {
        // 0.10253214158314959 reads back one ulp off without serde_json's `float_roundtrip`, which
        // made a resumed run's numbers differ from an uninterrupted one's.
        let rs = vec![
            result(8, 0, 0.1, 0.5),
            result(8, 1, 0.12345678901234567, 0.0),
            result(4, 0, 0.10253214158314959, 1.0),
        ];
        let back = from_json(&to_json(&rs)).unwrap();
        assert_eq!(back, rs);
        let e = from_json("[{\"scene\": 1}]").unwrap_err();
        assert!(e.contains("line"), "{e}");
    }

    #[test]
    fn aggregates_over_replicates_and_slopes() {
        let mut rs = Vec::new();
        for rays in [1u32, 4, 16, 64] {
            for rep in 0..3 {
                // RMSE ∝ rays^-1/2, time ∝ rays; replicate spread ±10 %.
                let wobble = 1.0 + 0.1 * (rep as f64 - 1.0);
                rs.push(result(rays, rep, 0.4 / (rays as f64).sqrt() * wobble, 0.01 * rays as f64));
            }
        }
        let aggs = aggregate(&rs);
        assert_eq!(aggs.len(), 4);
        let a = &aggs[1];
        assert_eq!((a.rays, a.replicates), (4, 3));
        assert!((a.rmse.mean - 0.2).abs() < 1e-12);
        assert!((a.rmse.sd - 0.02).abs() < 1e-12, "{:?}", a.rmse);
        assert!((a.bias.mean - 0.01).abs() < 1e-12);
        let slopes = convergence_slopes(&aggs, &[]);
        assert_eq!(slopes.len(), 1);
        assert_eq!(slopes[0].points, 4);
        assert!((slopes[0].vs_rays.unwrap() + 0.5).abs() < 1e-9);
        assert!((slopes[0].vs_time.unwrap() + 0.5).abs() < 1e-9);
        let two = convergence_slopes(&aggs, &[4, 16]);
        assert_eq!(two[0].points, 2);
        assert_eq!(convergence_slopes(&aggs, &[4])[0].vs_rays, None);
        let row = Row::new(Distribution::SineCosine, Sequence::Fibonacci, SeedMode::Rotation);
        assert_eq!(lookup(&aggs, "k", row, 16).map(|a| a.rays), Some(16));
        assert!(lookup(&aggs, "k", row, 32).is_none());
        assert!(lookup(&aggs, "other", row, 16).is_none());
        let csv = aggregates_to_csv(&aggs);
        assert!(csv.starts_with("scene,distribution,sequence,seed_mode,rays,replicates,rmse_mean,rmse_sd,"));
        assert_eq!(csv.lines().count(), 5);
        // Every value sits under its own header (the test records all have whiteness z 0.5).
        let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
        let first: Vec<&str> = csv.lines().nth(1).unwrap().split(',').collect();
        assert_eq!(header.len(), first.len());
        let col = |name: &str| first[header.iter().position(|h| *h == name).unwrap()];
        assert_eq!((col("whiteness_z_mean"), col("whiteness_z_sd")), ("0.5", "0"));
        assert_eq!(col("rays"), "1");
    }
}
