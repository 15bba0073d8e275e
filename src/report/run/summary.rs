//! The text `run` and `merge` print at the end: the session's timing, each reference's noise floor
//! against the smallest RMSE it must resolve, and a line per configuration.

use super::data::agg_label;
use crate::jobs::executor::Session;
use crate::reference as refmath;
use crate::reference::store::Reference;
use crate::results::{Aggregate, JobResult};
use crate::spec::Spec;
use std::fmt::Write;

/// More configurations than this are not listed at the end of a run: the report has them all.
const MAX_PRINTED_CONFIGURATIONS: usize = 24;

/// What to print: the summary, and warnings for standard error.
pub struct Summary {
    pub text: String,
    pub warnings: Vec<String>,
}

/// The smallest mean RMSE over replicates that scene `name`'s own reference must resolve: of every
/// measurement of the scene's static camera (raw or denoised, any frame), so that a spec whose rows
/// are all denoised still has one (it once read "smallest RMSE inf", and the noise-floor warning
/// could never fire). A camera path's frames are measured against references of their own.
fn smallest_rmse(results: &[JobResult], name: &str) -> f64 {
    // (configuration, pipeline, frame, schedule, denoiser) → (sum of RMSE, replicates).
    let mut groups: std::collections::HashMap<String, (f64, usize)> = std::collections::HashMap::new();
    for r in results.iter().filter(|r| r.scene == name && r.camera == "static" && r.rmse.is_finite()) {
        let key = format!("{:?};{};{};{};{}", r.config(), r.pipeline, r.frame, r.schedule, r.denoiser);
        let g = groups.entry(key).or_default();
        (g.0, g.1) = (g.0 + r.rmse, g.1 + 1);
    }
    groups.values().map(|&(sum, n)| sum / n as f64).fold(f64::INFINITY, f64::min)
}

pub fn summary(
    spec: &Spec,
    references: &[Reference],
    results: &[JobResult],
    aggs: &[Aggregate],
    session: &Session,
) -> Summary {
    let mut s = String::new();
    let mut warnings = Vec::new();
    let _ = writeln!(
        s,
        "timing: {} timed renders, {:.1} s of render CPU time in {:.1} s of wall time",
        session.renders, session.cpu_s, session.wall_s
    );
    for (si, r) in references.iter().enumerate() {
        // The spec's scene name (the file stem) is the results' `scene` column; the scene file's own
        // `name` may differ.
        let name = &spec.scenes[si].name;
        let smallest = smallest_rmse(results, name);
        let floor = r.noise_floor();
        let target = refmath::target_floor(smallest);
        let _ = writeln!(s, "reference '{name}': noise floor {floor:.2e}, smallest RMSE {smallest:.2e}");
        if smallest.is_finite() && floor > target {
            let need = refmath::rays_needed(floor, r.manifest.rays, target);
            warnings.push(format!(
                "warning: reference noise floor {floor:.2e} of '{name}' is above a tenth of the smallest RMSE \
                 ({smallest:.2e}); about {need} rays per replicate are needed (set [reference] rays)"
            ));
        }
    }
    if aggs.len() > MAX_PRINTED_CONFIGURATIONS {
        let _ = writeln!(
            s,
            "{} configurations: RMSE, times and efficiency of each in aggregates.csv and the report",
            aggs.len()
        );
        return Summary { text: s, warnings };
    }
    let width = aggs.iter().map(|a| agg_label(a).chars().count()).max().unwrap_or(0);
    let _ = writeln!(
        s,
        "per configuration: RMSE mean ± sd over replicates, lag-1 error autocorrelation ρ x/y, median render \
         time, ns per AO ray"
    );
    for a in aggs {
        let _ = writeln!(
            s,
            "  {:<12} {:<width$} {:>5} rays  RMSE {:.4} ± {:.4}  ρ {:+.2}/{:+.2}  {:.2} ms  {:.1} ns/ray",
            a.scene,
            agg_label(a),
            a.rays,
            a.rmse.mean,
            a.rmse.sd,
            a.autocorr_x.mean,
            a.autocorr_y.mean,
            a.time.map_or(f64::NAN, |t| t.median * 1e3),
            a.ns_per_ray
        );
    }
    Summary { text: s, warnings }
}
