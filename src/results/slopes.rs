//! Convergence of one row: log-log slopes of RMSE against rays, render time and AO time, each
//! with a 95 % interval, and the row's fitted cost (overhead + per-ray cost).

use super::Aggregate;
use crate::spec::{GroupKind, Spec};
use crate::stats::{LinearFit, loglog_fit};
use crate::timing::Calibration;
use serde::Serialize;

/// A fitted slope and its two-sided 95 % Student-t confidence interval (`None` with fewer than
/// three points). The interval is wide when the points do not lie on a power law.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SlopeFit {
    pub value: f64,
    pub ci95: Option<[f64; 2]>,
}

impl SlopeFit {
    fn of(fit: LinearFit) -> Self {
        Self { value: fit.slope, ci95: fit.slope_interval(0.95).map(|(a, b)| [a, b]) }
    }

    /// "−0.77 [−0.79, −0.75]".
    pub fn text(&self) -> String {
        let f = |k: f64| format!("{}{:.2}", if k < 0.0 { "−" } else { "+" }, k.abs());
        match self.ci95 {
            Some([a, b]) => format!("{} [{}, {}]", f(self.value), f(a), f(b)),
            None => f(self.value),
        }
    }
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
    /// d ln(mean RMSE) / d ln(rays): −0.5 for plain Monte Carlo.
    pub vs_rays: Option<SlopeFit>,
    /// d ln(mean RMSE) / d ln(median render time). The per-image overhead bends this curve: at
    /// low ray counts time hardly grows with rays, so this slope is steeper than `vs_rays`
    /// for every row alike.
    pub vs_time: Option<SlopeFit>,
    /// d ln(mean RMSE) / d ln(AO time), the render time minus the overhead: equal to `vs_rays`
    /// when a ray costs the same at every ray count; the difference is how the per-ray cost
    /// changes with the ray count.
    pub vs_ao_time: Option<SlopeFit>,
    /// time = overhead + cost · AO rays, fitted through the row's median times.
    pub cost: Option<Calibration>,
}

/// Least-squares log-log slopes per row, over the aggregates whose ray count is in `rays`
/// (all of them when `rays` is empty), rows in order of first appearance.
pub fn convergence_slopes(aggs: &[Aggregate], rays: &[u32]) -> Vec<Slope> {
    let use_it = |a: &Aggregate| rays.is_empty() || rays.contains(&a.rays);
    let key =
        |a: &Aggregate| (a.scene.clone(), a.distribution.clone(), a.sequence.clone(), a.seed_mode.clone());
    let mut rows: Vec<(String, String, String, String)> = Vec::new();
    for a in aggs.iter().filter(|a| use_it(a)) {
        if !rows.contains(&key(a)) {
            rows.push(key(a));
        }
    }
    rows.into_iter()
        .map(|k| {
            let pts: Vec<&Aggregate> = aggs.iter().filter(|a| use_it(a) && key(a) == k).collect();
            let rmse: Vec<f64> = pts.iter().map(|a| a.rmse.mean).collect();
            let rays: Vec<f64> = pts.iter().map(|a| a.rays as f64).collect();
            let time: Vec<f64> = pts.iter().map(|a| a.time.map_or(f64::NAN, |t| t.median)).collect();
            let ao: Vec<f64> = pts.iter().map(|a| a.ao_time_s).collect();
            let cost_pts: Vec<(u64, f64)> = pts
                .iter()
                .zip(&time)
                .filter(|(_, t)| t.is_finite())
                .map(|(a, t)| (a.rays_cast as u64, *t))
                .collect();
            Slope {
                scene: k.0,
                distribution: k.1,
                sequence: k.2,
                seed_mode: k.3,
                points: pts.len(),
                vs_rays: loglog_fit(&rays, &rmse).map(SlopeFit::of),
                vs_time: loglog_fit(&time, &rmse).map(SlopeFit::of),
                vs_ao_time: loglog_fit(&ao, &rmse).map(SlopeFit::of),
                cost: Calibration::fit(&cost_pts),
            }
        })
        .collect()
}
/// The slopes of one `[[convergence]]` sweep (`slopes.json`).
#[derive(Serialize)]
pub struct SweepSlopes<'a> {
    pub group: &'a str,
    pub slopes: Vec<Slope>,
}

/// Per sweep, per row and scene, over the sweep's own ray counts only: a table that shares a row
/// must not add its points to the fit.
pub fn sweep_slopes<'a>(spec: &'a Spec, aggs: &[Aggregate]) -> Vec<SweepSlopes<'a>> {
    let sweeps = spec.groups.iter().filter(|g| g.kind == GroupKind::Convergence);
    sweeps
        .map(|g| {
            let in_sweep = |a: &Aggregate| {
                g.scenes.iter().any(|&si| spec.scenes[si].name == a.scene)
                    && g.rows.iter().any(|&r| a.is_row(r))
            };
            let pts: Vec<Aggregate> = aggs.iter().filter(|a| in_sweep(a)).cloned().collect();
            SweepSlopes { group: &g.name, slopes: convergence_slopes(&pts, &g.rays) }
        })
        .collect()
}
