//! Per configuration, over its replicates: mean ± sd of every error metric, the timing summary
//! over all its timed renders, and efficiency with its spread; and `aggregates.csv`.

use super::{JobResult, csv_field, efficiency_spread, num};
use crate::metrics::mean_sd;
use crate::spec::Row;
use crate::timing::Summary;
use serde::Serialize;
use std::fmt::Write as _;

#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Stat {
    pub mean: f64,
    pub sd: f64,
}

impl Stat {
    pub(crate) fn of(values: &[f64]) -> Self {
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
    /// Mean LDR-FLIP per replicate (`JobResult::flip`), mean ± sd over the replicates that have it.
    pub flip: Stat,
    pub bias: Stat,
    pub autocorr_x: Stat,
    pub autocorr_y: Stat,
    pub lowpass_rmse: Stat,
    pub whiteness_z: Stat,
    pub lowfreq_ratio: Stat,
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
    /// The configuration's error split from its replicates (`JobResult::bias_rmse`, `bias_se`,
    /// `noise_rmse`: the same in every record of it); NaN with one replicate.
    pub bias_rmse: f64,
    pub bias_se: f64,
    pub noise_rmse: f64,
}

/// Mean and sd per (scene, distribution, sequence, seed_mode, rays), in order of first appearance;
/// the timing columns from the records (`fill_timing` has set them). Single raw frames only
/// (`JobResult::is_single_frame`): the real-time records are read by their own report section.
pub fn aggregate(results: &[JobResult]) -> Vec<Aggregate> {
    let single: Vec<JobResult> = results.iter().filter(|r| r.is_single_frame()).cloned().collect();
    let results = &single[..];
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
                flip: st(&|r| r.flip),
                bias: st(&|r| r.bias),
                autocorr_x: st(&|r| r.autocorr_x),
                autocorr_y: st(&|r| r.autocorr_y),
                lowpass_rmse: st(&|r| r.lowpass_rmse),
                whiteness_z: st(&|r| r.whiteness_z),
                lowfreq_ratio: st(&|r| r.lowfreq_ratio),
                mse,
                time,
                overhead_s: first.overhead_s,
                ao_time_s: first.ao_time_s,
                ns_per_ray: first.ns_per_ray,
                rays_cast,
                rays_per_s: if median > 0.0 { rays_cast / median } else { f64::NAN },
                efficiency,
                efficiency_spread: efficiency_spread(efficiency, mse, rs.len(), time, first.ao_time_s),
                bias_rmse: first.bias_rmse,
                bias_se: first.bias_se,
                noise_rmse: first.noise_rmse,
            }
        })
        .collect()
}

/// The aggregate of one cell of a table (`row` is canonicalized, so random+shift finds random+rotation).
pub fn lookup<'a>(aggs: &'a [Aggregate], scene: &str, row: Row, rays: u32) -> Option<&'a Aggregate> {
    aggs.iter().find(|a| a.is(scene, row, rays))
}

impl Aggregate {
    /// Whether this aggregate is of `row` (any scene, any ray count).
    pub fn is_row(&self, row: Row) -> bool {
        super::names_row([&self.distribution, &self.sequence, &self.seed_mode], row)
    }

    /// Whether this aggregate is the cell (scene, row, rays).
    pub fn is(&self, scene: &str, row: Row, rays: u32) -> bool {
        self.scene == scene && self.rays == rays && self.is_row(row)
    }
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
    for m in AGG_APPENDED {
        c.push(format!("{m}_mean"));
        c.push(format!("{m}_sd"));
    }
    c.extend(AGG_SPLIT.map(String::from));
    c
}

/// The split from replicates, one value per configuration, appended after everything else.
const AGG_SPLIT: [&str; 3] = ["bias_rmse", "bias_se", "noise_rmse"];

const AGG_METRICS: [&str; 6] = ["rmse", "bias", "autocorr_x", "autocorr_y", "lowpass_rmse", "whiteness_z"];
/// Metrics added later, after the timing columns so that every earlier column keeps its position.
const AGG_APPENDED: [&str; 2] = ["lowfreq_ratio", "flip"];
const AGG_TIMING: [&str; 12] = [
    "time_median_s",
    "time_min_s",
    "time_max_s",
    "time_ci_low_s",
    "time_ci_high_s",
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
        for st in [a.rmse, a.bias, a.autocorr_x, a.autocorr_y, a.lowpass_rmse, a.whiteness_z] {
            let _ = write!(s, ",{},{}", num(st.mean), num(st.sd));
        }
        let t = a.time;
        let f = |g: fn(&Summary) -> f64| t.as_ref().map_or(String::new(), |t| num(g(t)));
        let _ = write!(
            s,
            ",{},{},{},{},{},{},{},{},{},{},{},{}",
            f(|t| t.median),
            f(|t| t.min),
            f(|t| t.max),
            f(|t| t.ci_low),
            f(|t| t.ci_high),
            t.map_or(0, |t| t.n),
            num(a.overhead_s),
            num(a.ao_time_s),
            num(a.ns_per_ray),
            num(a.rays_per_s),
            num(a.efficiency),
            num(a.efficiency_spread)
        );
        for st in [a.lowfreq_ratio, a.flip] {
            let _ = write!(s, ",{},{}", num(st.mean), num(st.sd));
        }
        let _ = write!(s, ",{},{},{}", num(a.bias_rmse), num(a.bias_se), num(a.noise_rmse));
        s.push('\n');
    }
    s
}

#[cfg(test)]
mod tests {
    use super::super::tests::{result, timed};
    use super::*;
    use crate::results::convergence_slopes;
    use crate::sampling::{Distribution, SeedMode, Sequence};

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
            // Identical times: the MSE's error and the run-to-run scatter of the median time.
            let t = a.time.unwrap().median;
            let rel = se.hypot(crate::timing::RUN_TO_RUN * t / a.ao_time_s);
            assert!((a.efficiency_spread - e * rel).abs() < 1e-9 * e, "{} {}", a.efficiency_spread, e * rel);
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
        let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
        assert_eq!(header[header.len() - 3..], ["bias_rmse", "bias_se", "noise_rmse"], "appended last");
        assert_eq!(
            header[header.len() - 7..header.len() - 3],
            ["lowfreq_ratio_mean", "lowfreq_ratio_sd", "flip_mean", "flip_sd"],
            "appended in the order they were added"
        );
        assert_eq!(header[header.len() - 8], "efficiency_spread", "every earlier column in place");
        let first: Vec<&str> = csv.lines().nth(1).unwrap().split(',').collect();
        assert_eq!(first.len(), header.len());
        assert_eq!(
            first[first.len() - 7..first.len() - 3],
            ["0.75", "0", "0.5", "0"],
            "mean ± sd of the records' ratios and FLIPs"
        );
        assert_eq!(first[first.len() - 3..], ["", "", ""], "no split without the images");
    }
}
