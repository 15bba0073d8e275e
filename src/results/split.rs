//! The timing columns of the records: per configuration, median / min / max over every timed
//! render of it, the scene's per-image overhead, the AO time and per-ray cost, and efficiency.

use super::{JobResult, Stat};
use crate::timing::{Split, Summary};

/// Sets the configuration-level timing columns of every record from the records' own samples
/// (`JobResult::times`), with `overhead(scene)` the median time of that scene's no-AO-ray render.
pub fn fill_timing(results: &mut [JobResult], overhead: &dyn Fn(&str) -> Option<f64>) {
    // A real-time record's frames, schedule and pipeline are part of its configuration here.
    let configs: Vec<(String, String, String, String, u32, String)> = results
        .iter()
        .map(|r| {
            let c = r.config();
            let rt = format!("{}/{}/{}", r.frame, r.schedule, r.pipeline);
            (c.0.to_string(), c.1.to_string(), c.2.to_string(), c.3.to_string(), c.4, rt)
        })
        .collect();
    for (i, c) in configs.iter().enumerate() {
        let same = |j: usize| configs[j] == *c;
        if (0..i).any(same) {
            continue; // done with the first record of the configuration
        }
        let samples: Vec<f64> =
            (0..results.len()).filter(|&j| same(j)).flat_map(|j| results[j].times.clone()).collect();
        let Some(t) = Summary::of(&samples) else { continue };
        let over = overhead(&c.0).unwrap_or(f64::NAN);
        for j in (0..results.len()).filter(|&j| same(j)) {
            let r = &mut results[j];
            let split = Split::of(t.median, over, r.rays_cast);
            r.time_median_s = t.median;
            r.time_min_s = t.min;
            r.time_max_s = t.max;
            r.timings = t.n;
            r.overhead_s = over;
            r.ao_time_s = split.ao_time_s;
            r.ns_per_ray = split.ns_per_ray;
            r.efficiency = crate::metrics::efficiency(r.rmse, split.ao_time_s);
        }
    }
}

/// The spread of an efficiency E = 1 / (MSE · T): E · √((se(MSE)/MSE)² + (δT/T)²), with se(MSE)
/// the standard error of the mean MSE over `replicates` and δT the spread of the median time
/// (`Summary::spread`: half its 95 % interval and the run-to-run scatter). The overhead's own uncertainty is left out: it
/// shifts every configuration of a scene alike. NaN when E is.
pub fn efficiency_spread(
    efficiency: f64,
    mse: Stat,
    replicates: usize,
    time: Option<Summary>,
    ao_time_s: f64,
) -> f64 {
    let se = if replicates > 1 { mse.sd / (replicates as f64).sqrt() } else { 0.0 };
    let dt = time.map_or(f64::NAN, |t| t.spread());
    let rel = ((se / mse.mean).powi(2) + (dt / ao_time_s).powi(2)).sqrt();
    efficiency * rel
}

/// Reads JSON `null` (how serde_json writes NaN) back as NaN, for columns that may be undefined.
pub(super) fn nan_null<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    use serde::Deserialize;
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}
