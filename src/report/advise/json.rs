//! advice.json: the recommendation per budget (what to ship, its rays, RMSE and gain over the
//! paper's default, with their standard errors), both full rankings, every measured point with each
//! replicate's MSE (so the advice can be recomputed), and the winner map's counts.

use super::text::{advice_line, default_at, outside_note, shipped_rays, status};
use crate::advice::analysis::mean;
use crate::advice::analysis::{Analysis, Measured};
use crate::advice::{self, AtBudget, Metric, PAPER_DEFAULT, Place, Ranking, winner};
use crate::metrics::{LOWPASS_SIGMA, STRUCTURED_RATIO};
use crate::spec::Row;
use crate::timing;
use serde_json::{Value, json};

/// Seconds as ms for advice.json, without the float noise of the conversion (5.1, not
/// 5.1000000000000005).
fn ms_value(s: f64) -> f64 {
    advice::round_significant(s * 1e3, 15)
}

/// What "structured" means in advice.json, for a reader without the source.
fn structured_rule() -> String {
    format!(
        "mean lowfreq_ratio over the replicates (interpolated to the budget) above {STRUCTURED_RATIO}: the \
         error's low-pass energy (Gaussian, sigma {LOWPASS_SIGMA} px) over what independent per-pixel errors \
         of the same sizes would have; 1 = white noise, < 1 = blue noise, > 1 = blotches or bands. \
         whiteness_z is reported as a test of any correlation, not used here"
    )
}

fn conf(row: Row) -> Value {
    json!({
        "distribution": row.distribution.name(),
        "sequence": row.sequence.name(),
        "seed_mode": row.seed_mode.name(),
    })
}

fn entry(a: &AtBudget, r: &Ranking) -> Value {
    let (e, l) = (a.rmse(Metric::Rmse), a.rmse(Metric::Lowpass));
    let g = default_at(r).map(|d| advice::gain(d, a, Metric::Rmse));
    let lg = default_at(r).map(|d| advice::gain(d, a, Metric::Lowpass));
    json!({
        "configuration": conf(a.row),
        "rays": shipped_rays(a),
        "rays_interpolated": a.rays,
        "rmse": e.value,
        "rmse_se": e.se,
        "lowpass_rmse": l.value,
        "lowpass_rmse_se": l.se,
        "whiteness_z": a.whiteness_z,
        "lowfreq_ratio": a.lowfreq_ratio,
        "gain_vs_paper_default": g.map(|g| g.value),
        "gain_vs_paper_default_se": g.map(|g| g.se),
        "gain_se_replicates": g.map(|g| g.se_replicates),
        "gain_se_timing": g.map(|g| g.se_timing),
        "lowpass_gain_vs_paper_default": lg.map(|g| g.value),
        "lowpass_gain_vs_paper_default_se": lg.map(|g| g.se),
        "z_vs_best": r.ranked.first().map(|b| advice::paired_z(b, a, r.metric)),
    })
}

fn recommendation(r: &Ranking, low: &Ranking) -> Value {
    let outside: Vec<Value> = r
        .outside
        .iter()
        .map(|(row, p)| match p {
            Place::Below { fastest_s } => {
                json!({"configuration": conf(*row), "where": "below", "time_ms": fastest_s * 1e3})
            }
            Place::Above { slowest_s } => {
                json!({"configuration": conf(*row), "where": "above", "time_ms": slowest_s * 1e3})
            }
            Place::Inside { .. } => json!({"configuration": conf(*row), "where": "inside"}),
        })
        .collect();
    let mut v = match advice::recommended(r) {
        Some(best) => entry(best, r),
        None => json!({ "configuration": null, "rays": null, "rmse": null, "gain_vs_paper_default": null }),
    };
    let note = if r.ranked.is_empty() { outside_note(r) } else { advice_line(r, low) };
    let o = v.as_object_mut().expect("an object");
    o.insert("budget_ms".into(), json!(ms_value(r.budget_s)));
    o.insert("status".into(), json!(status(r)));
    o.insert("note".into(), json!(note));
    o.insert("paper_default".into(), default_at(r).map_or(Value::Null, |d| entry(d, r)));
    o.insert("structured".into(), json!(advice::recommended(r).is_some_and(|b| b.structured())));
    o.insert("structured_rule".into(), json!(structured_rule()));
    let shipped = advice::recommended(r).map(|b| b.row);
    let least_structured = r.ranked.first().filter(|t| Some(t.row) != shipped);
    o.insert("least_rmse_structured".into(), least_structured.map_or(Value::Null, |t| entry(t, r)));
    let runner_up = r.ranked.iter().find(|a| Some(a.row) != shipped && !a.structured());
    o.insert("runner_up".into(), runner_up.map_or(Value::Null, |s| entry(s, r)));
    o.insert("best_lowpass".into(), low.ranked.first().map_or(Value::Null, |b| entry(b, low)));
    o.insert("ranking".into(), Value::Array(r.ranked.iter().map(|a| entry(a, r)).collect()));
    o.insert("lowpass_ranking".into(), Value::Array(low.ranked.iter().map(|a| entry(a, low)).collect()));
    o.insert("outside".into(), Value::Array(outside));
    v
}

pub fn advice_json(m: &Measured, a: &Analysis) -> Value {
    let spec = &m.setup.loaded.spec;
    let configurations: Vec<Value> = a
        .curves
        .iter()
        .map(|c| {
            let points: Vec<Value> = c
                .points
                .iter()
                .map(|p| {
                    json!({
                        "rays": p.rays,
                        "time_ms": p.time_s * 1e3,
                        "time_spread_ms": p.time_spread_s * 1e3,
                        "replicates": p.replicates,
                        "mse": p.mse,
                        "lowpass_mse": p.lowpass_mse,
                        "rmse": mean(&p.mse).sqrt(),
                        "lowpass_rmse": mean(&p.lowpass_mse).sqrt(),
                        "whiteness_z": p.whiteness_z,
                        "lowfreq_ratio": p.lowfreq_ratio,
                    })
                })
                .collect();
            json!({ "configuration": conf(c.row), "points": points })
        })
        .collect();
    let maps: Vec<Value> = a
        .maps
        .iter()
        .map(|map| {
            let (won, unresolved, covered) = winner::tally(&map.pixels, map.rows.len());
            let wins: Vec<Value> = map
                .rows
                .iter()
                .zip(won)
                .filter(|(_, n)| *n > 0)
                .map(|(r, n)| json!({"configuration": conf(*r), "pixels": n}))
                .collect();
            json!({ "budget_ms": ms_value(map.budget_s), "covered_pixels": covered, "unresolved_pixels": unresolved, "wins": wins })
        })
        .collect();
    let manifest = &m.reference.manifest;
    json!({
        "hemilab_version": env!("CARGO_PKG_VERSION"),
        "scene": m.setup.stem,
        "scene_file": spec.scenes[0].path.display().to_string(),
        "resolution": spec.resolution,
        "time_per_image": format!(
            "{}, of one thread rendering the whole image at {}x{}: {}",
            timing::clock::NAME,
            spec.resolution.map_or(0, |r| r[0]),
            spec.resolution.map_or(0, |r| r[1]),
            timing::TIME_INCLUDES
        ),
        "protocol": m.protocol,
        "overhead_ms": m.session.overhead.first().copied().flatten().map(|s| s.median * 1e3),
        "replicates": spec.replicates,
        "rays": m.setup.rays,
        "setup": m.setup.choice,
        "reference": {
            "file": m.reference.exr.display().to_string(),
            "noise_floor": m.reference.noise_floor(),
            "estimator": { "distribution": manifest.distribution, "sequence": manifest.sequence, "seed_mode": manifest.seed_mode },
            "rays": manifest.rays,
            "replicates": manifest.replicates,
        },
        "paper_default": conf(PAPER_DEFAULT),
        "budgets_ms": a.budgets_s.iter().map(|&b| ms_value(b)).collect::<Vec<_>>(),
        "budgets_chosen_by_advise": a.default_budgets,
        "recommendations": a.rankings.iter().map(|(r, l)| recommendation(r, l)).collect::<Vec<_>>(),
        "winner_map": {
            "file": (!a.maps.is_empty()).then_some("winner_map.png"),
            "significance": format!(
                "per pixel, the runner-up's MSE (3x3 pooled, at the budget) minus the winner's, paired over the \
                 replicates, above {:.3} standard errors (Student's t, one-sided {} %, n - 1 dof)",
                a.threshold,
                winner::LEVEL * 100.0
            ),
            "budgets": maps,
        },
        "configurations": configurations,
        "session": { "timed_renders": m.session.renders, "cpu_s": m.session.cpu_s, "wall_s": m.session.wall_s },
    })
}
