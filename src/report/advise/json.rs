//! advice.json: per budget what to ship — measured at the integer ray count it names, with every
//! replicate's values so the answer, its gains and their σ can be recomputed — the finalists
//! measured beside it, both interpolated rankings, every point of the sweep (each replicate's MSE
//! and structure value), the error model every ± is 1 σ of, and the winner map's counts.

use super::text::{advice_line, outside_note, status};
use crate::advice::analysis::{Analysis, Measured};
use crate::advice::answer::{self, Answer, Candidate, FINALISTS, RankScored};
use crate::advice::{setup, winner};
use crate::compare::budget::{AtBudget, Metric, Place, Ranking, round_significant};
use crate::compare::model;
use crate::compare::per_ray::{AtRays, Entry};
use crate::compare::{PAPER_DEFAULT, structure};
use crate::spec::Row;
use crate::timing;
use serde_json::{Value, json};

/// Seconds as ms for advice.json, without the float noise of the conversion (5.1, not
/// 5.1000000000000005).
fn ms_value(s: f64) -> f64 {
    round_significant(s * 1e3, 15)
}

fn conf(row: Row) -> Value {
    json!({
        "distribution": row.distribution.name(),
        "sequence": row.sequence.name(),
        "seed_mode": row.seed_mode.name(),
    })
}

/// A finalist: measured at `rays` (or interpolated at the budget, `measured` false), with what a
/// recomputation needs: per-replicate values, its time's σ parts, its slopes.
fn entry(c: &Candidate, a: &Answer) -> Value {
    let sc = a.score(c);
    let (e, l, g, lg, t) = (sc.rmse, sc.lowpass_rmse, sc.gain, sc.lowpass_gain, sc.time_ms);
    json!({
        "configuration": conf(c.row),
        "measured": c.measured,
        "rays": c.rays,
        "rays_interpolated": c.rays_interpolated,
        "time_ms": c.measured.then_some(t.value),
        "time_sigma_ms": c.measured.then_some(t.se),
        "time_sigma_ln": c.time_sigma_ln,
        "timings": c.timings,
        "fits_budget": c.measured.then_some(a.fits(c)),
        "also_measured": c.others.iter().map(|&(rays, t, mse)| json!({"rays": rays, "time_ms": t * 1e3, "rmse": mse.sqrt()})).collect::<Vec<_>>(),
        "replicates": c.replicates,
        "mse": c.mse,
        "lowpass_mse": c.lowpass_mse,
        "structure": c.structure,
        "structure_mean": c.structure_mean(),
        "structured": c.structured(),
        "slope": c.slope,
        "lowpass_slope": c.lowpass_slope,
        "rmse": e.value,
        "rmse_se": e.se,
        "lowpass_rmse": l.value,
        "lowpass_rmse_se": l.se,
        "gain_vs_paper_default": g.map(|g| g.value),
        "gain_vs_paper_default_se": g.map(|g| g.se),
        "gain_se_replicates": g.map(|g| g.se_replicates),
        "gain_se_timing": g.map(|g| g.se_timing),
        "lowpass_gain_vs_paper_default": lg.map(|g| g.value),
        "lowpass_gain_vs_paper_default_se": lg.map(|g| g.se),
        "sigma_behind_recommended": sc.behind,
    })
}

/// A configuration in the sweep's interpolated ranking at the budget, as the answer scored it.
fn ranked(x: &AtBudget, sc: &RankScored) -> Value {
    let (e, l, g) = (sc.rmse, sc.lowpass_rmse, sc.gain);
    json!({
        "configuration": conf(x.row),
        "rays_interpolated": x.rays,
        "rays": answer::rays_for(x),
        "rmse": e.value,
        "rmse_se": e.se,
        "lowpass_rmse": l.value,
        "lowpass_rmse_se": l.se,
        "structure_mean": x.structure,
        "structured": x.structured(),
        "gain_vs_paper_default": g.map(|g| g.value),
        "gain_vs_paper_default_se": g.map(|g| g.se),
        "sigma_behind_best": sc.behind_best,
    })
}

fn recommendation(a: &Answer, per: &str) -> Value {
    let r = &a.ranking;
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
    let mut v = match a.recommended() {
        Some(best) => entry(best, a),
        None => json!({ "configuration": null, "rays": null, "rmse": null, "gain_vs_paper_default": null }),
    };
    let note = if r.ranked.is_empty() { outside_note(r) } else { advice_line(a, per) };
    let or_null = |c: Option<&Candidate>| c.map_or(Value::Null, |c| entry(c, a));
    let o = v.as_object_mut().expect("an object");
    o.insert("budget_ms".into(), json!(ms_value(a.budget_s)));
    o.insert("status".into(), json!(status(r)));
    o.insert("note".into(), json!(note));
    o.insert("measured".into(), json!(a.measured && a.recommended().is_some()));
    o.insert("paper_default".into(), or_null(a.paper_default()));
    o.insert("least_rmse_structured".into(), or_null(a.least_structured()));
    o.insert("runner_up".into(), or_null(a.runner_up()));
    o.insert("best_lowpass".into(), or_null(a.best_lowpass()));
    o.insert("finalists".into(), Value::Array(a.finalists.iter().map(|c| entry(c, a)).collect()));
    let scored = |r: &Ranking, s: &[RankScored]| {
        Value::Array(r.ranked.iter().zip(s).map(|(x, s)| ranked(x, s)).collect())
    };
    o.insert("ranking".into(), scored(r, &a.ranking_scores));
    o.insert("lowpass_ranking".into(), scored(&a.lowpass, &a.lowpass_scores));
    o.insert("outside".into(), Value::Array(outside));
    v
}

/// A ray budget's answer for one camera (after a real-time pipeline): every configuration under
/// each schedule at that many rays per pixel per frame, least RMSE first, with its paired margin to
/// the best, whether it is a near-tie, its FLIP, flicker and bias/noise split; `recommended` the
/// best by RMSE, `recommended_by_flip` the best by FLIP, `near_ties` the best and those within its
/// margin.
fn ray_budget(x: &AtRays, a: &Analysis) -> Value {
    let schedule = |e: &Entry| {
        if a.one_schedule.contains(&e.row) { "any".to_string() } else { e.schedule.name().to_string() }
    };
    let which = |e: &Entry| json!({"configuration": conf(e.row), "schedule": schedule(e)});
    let entry = |e: &Entry| {
        json!({
            "configuration": conf(e.row),
            "schedule": schedule(e),
            "rmse": e.rmse.value,
            "rmse_se": e.rmse.se,
            "mse": e.mse.iter().map(|(r, v)| json!({"replicate": r, "mse": v})).collect::<Vec<_>>(),
            "flip": e.flip.value,
            "flip_se": e.flip.se,
            "flips": e.flips.iter().map(|(r, v)| json!({"replicate": r, "flip": v})).collect::<Vec<_>>(),
            "flicker": e.flicker,
            "bias_rmse": e.split.bias_rmse,
            "bias_se": e.split.bias_se,
            "noise_rmse": e.split.noise_rmse,
            "time_per_frame_ms": e.time_s * 1e3,
            "sampler_ns_per_point": a.sampler_ns(e.row, x.rays),
            "mse_above_best": e.behind.map(|m| m.mean),
            "mse_above_best_se": e.behind.map(|m| m.se),
            "near_tie": e.near_tie,
        })
    };
    let by_flip = x.best_flip();
    json!({
        "rays_per_pixel_per_frame": x.rays,
        "camera": x.camera,
        "recommended": x.best().map(|e| conf(e.row)),
        "recommended_schedule": x.best().map(schedule),
        "recommended_by_flip": by_flip.map(which),
        "flip_differs": match (x.best(), by_flip) {
            (Some(b), Some(f)) => Value::Bool(b.candidate() != f.candidate()),
            _ => Value::Null,
        },
        "near_ties": x.near_ties().map(which).collect::<Vec<_>>(),
        "alpha": crate::compare::per_ray::ALPHA,
        "ranking": x.entries.iter().map(entry).collect::<Vec<_>>(),
    })
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
                        "time_sigma_ms": p.time_ms().se,
                        "time_sigma_ln": p.time_sigma_ln,
                        "timings": p.timings,
                        "replicates": p.replicates,
                        "mse": p.mse,
                        "lowpass_mse": p.lowpass_mse,
                        "structure": p.structure,
                        "rmse": p.rmse(Metric::Rmse).value,
                        "lowpass_rmse": p.rmse(Metric::Lowpass).value,
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
    let [w, h] = spec.resolution.unwrap_or([0, 0]);
    json!({
        "hemilab_version": env!("CARGO_PKG_VERSION"),
        "scene": m.setup.stem,
        "scene_file": spec.scenes[0].path.display().to_string(),
        "resolution": spec.resolution,
        "time_per_image": format!(
            "{}, of one thread rendering the whole image at {w}x{h}: {}",
            timing::clock::NAME,
            timing::TIME_INCLUDES
        ),
        "protocol": m.protocol,
        "overhead_ms": m.session.overhead.first().copied().flatten().map(|s| s.median * 1e3),
        "replicates": spec.replicates,
        "rays": m.setup.rays,
        "pipeline": spec.groups.first().and_then(|g| g.pipelines.first()).map(|p| p.to_string()),
        "frames": spec.groups.first().map(|g| g.frames),
        "setup": m.setup.choice,
        "from": m.from.as_ref().map(|d| d.display().to_string()),
        "jobs": { "rendered": m.rendered, "reused": m.reused },
        "finalists_session_time_ratio": a.session_ratio,
        "error_model": {
            "sigma": "every ± and margin is 1 σ of this model",
            "run_factor_sigma_ln": model::RUN_FACTOR,
            "text": super::text::model_text(),
        },
        "structure": { "measure": structure::MEASURE, "threshold": structure::THRESHOLD, "rule": structure::rule() },
        "finalists": {
            "best_by_interpolation": FINALISTS,
            "replicates": m.replicates,
            "seed": setup::VERIFY_SEED,
            "rule": "per budget: the best by interpolated RMSE, the best two unstructured, the best by low-pass \
                     RMSE and the paper default, each rendered and timed at the count where its time line crosses \
                     the budget rounded down, the multiple of 32 below it (rays are traced in packets of 32, so \
                     time steps there) and the sweep's count below the budget; each is shipped at the most of \
                     those whose measured time, on the sweep's time scale, is not above the budget by more than \
                     2 σ of the session factor; the answer is decided on those measurements",
            "fits_sigma": answer::FITS_SIGMA,
        },
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
        "recommendations": a.answers.iter().map(|x| recommendation(x, m.setup.per())).collect::<Vec<_>>(),
        "ray_budgets": a.per_ray.iter().map(|x| ray_budget(x, a)).collect::<Vec<_>>(),
        "winner_map": {
            "file": (!a.maps.is_empty()).then_some("winner_map.png"),
            "significance": format!(
                "per pixel (3x3 pooled squared error), the finalist with the least mean over the first half of \
                 the replicates wins and the next is its runner-up; on the second half the runner-up's minus the \
                 winner's, paired by replicate, gives a one-sided p (Student's t); coloured: Benjamini-Hochberg \
                 over the map's covered pixels at false discovery rate {}",
                winner::FDR
            ),
            "fdr": winner::FDR,
            "budgets": maps,
        },
        "configurations": configurations,
        // The sessions as `timing.json` records them (`timing::SessionRecord`).
        "session": m.session.record(),
        "finalists_session": m.verify_session.as_ref().map(|s| s.record()),
    })
}
