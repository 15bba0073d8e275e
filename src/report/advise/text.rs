//! The sentences and small facts advise's page and advice.json share: the answer per budget, why a
//! budget has no answer, how numbers print.

use crate::advice::analysis::Analysis;
use crate::advice::answer::Answer;
use crate::compare::budget::{Place, Ranking, round_significant};
use crate::compare::model::{self, Estimate};
use crate::compare::per_ray::{AtRays, Entry};
use crate::compare::{PAPER_DEFAULT, structure};
use crate::spec::Row;
use std::fmt::Write as _;

pub fn ms(s: f64) -> String {
    format!("{}", round_significant(s * 1e3, 3))
}

fn rays(n: u32) -> String {
    if n == 1 { "1 ray".into() } else { format!("{n} rays") }
}

/// One sentence per budget: what to ship, measured at its ray count, and what it gains; or why
/// there is no answer. Every ± and margin is 1 σ of the error model (`compare::model`), as the
/// answer scored it (`Answer::score`). `per`: what a budget is the time of ("image", or "frame"
/// after a real-time pipeline).
pub fn advice_line(a: &Answer, per: &str) -> String {
    let b = ms(a.budget_s);
    let Some(best) = a.recommended() else {
        return format!("At {b} ms per {per}: {}.", outside_note(&a.ranking));
    };
    let scored = a.score(best);
    let e = scored.rmse;
    let px = if per == "frame" { "per pixel per frame" } else { "per pixel" };
    let mut s = format!("At {b} ms per {per}: ship {} with {} {px}", label(best.row), rays(best.rays));
    if a.measured {
        let _ = write!(s, " (measured there: RMSE {}, {} ms per {per})", pm(e, 4), pm(scored.time_ms, 2));
        if !a.fits(best) {
            let _ = write!(
                s,
                " — over the budget by {:.0} % even at its fewest measured count",
                100.0 * (best.time_s / a.budget_s - 1.0)
            );
        } else if scored.time_ms.value > a.budget_s * 1e3 * 1.005 {
            // Above the budget yet shipped: say why in one plain sentence, or it reads as a mistake.
            let _ = write!(
                s,
                " — its measured time is {:.0} % over the budget, which is within this machine's timing \
                 noise (its speed moves by about {:.0} % from one session to the next, and up to {} times that \
                 counts as fitting), so it ships rather than the next lower ray count",
                100.0 * (scored.time_ms.value / (a.budget_s * 1e3) - 1.0),
                100.0 * model::RUN_FACTOR,
                crate::advice::answer::FITS_SIGMA
            );
        }
    } else {
        let _ = write!(
            s,
            " (RMSE {} interpolated from the sweep, not measured at {}: this budget's finalists were not \
             rendered; run advise on this directory without --from to measure them)",
            pm(e, 4),
            rays(best.rays)
        );
    }
    if best.structured() {
        let _ = write!(
            s,
            " — its error is structured ({} {:.1}: bands or moiré that RMSE does not show), as is every \
             finalist's",
            structure::MEASURE,
            best.structure_mean()
        );
    }
    match a.paper_default() {
        Some(d) if d.row == best.row => s += ": the paper's default is the best here",
        Some(d) => {
            let g = scored.gain.expect("the default is there");
            let _ = write!(
                s,
                ": {} × less MSE than the paper's default with {} at the same budget",
                pm(g.estimate(), 2),
                rays(d.rays)
            );
        }
        None => s += "; the paper's default is outside its measured times here",
    }
    if let Some(second) = a.runner_up() {
        let z = a.score(second).behind.unwrap_or(f64::NAN);
        let _ = write!(s, "; runner-up {} with {} ({z:.1} σ behind)", label(second.row), rays(second.rays));
    }
    if let Some(top) = a.least_structured() {
        let _ = write!(
            s,
            "; {} has {:.0} % less RMSE but its error is structured ({} {:.1}), so it is not advised",
            label(top.row),
            100.0 * (1.0 - a.score(top).rmse.value / e.value),
            structure::MEASURE,
            top.structure_mean()
        );
    }
    if let Some(lb) = a.best_lowpass().filter(|l| l.row != best.row) {
        let _ = write!(s, "; least low-pass RMSE: {}", label(lb.row));
    }
    if !a.ranking.outside.is_empty() {
        let _ = write!(
            s,
            " ({} configurations outside their measured times here, unranked)",
            a.ranking.outside.len()
        );
    }
    s + "."
}

/// Near-ties a ray budget's sentence names (the closest first); the table and advice.json hold all.
pub const NEAR_TIES_NAMED: usize = 4;

/// One sentence per ray budget and camera after a real-time pipeline (`after`, e.g. "after svgf
/// at frame 64"): what to ship at that many rays per pixel per frame by RMSE — and by FLIP, named
/// when it differs — its RMSE, FLIP, flicker and bias/noise split, its time per frame here and its
/// sampler's cost per point, the near-ties within its paired margin, and the paper's default.
pub fn ray_line(at: &AtRays, a: &Analysis, after: &str) -> String {
    let per = format!("{} per pixel per frame", rays(at.rays));
    let cam = camera(&at.camera);
    let Some(best) = at.best() else { return format!("At {per}, {cam}, {after}: nothing was measured.") };
    let mut s = format!(
        "At {per}, {cam}, {after}: ship {} (RMSE {}; here {} ms per frame, its sampler {:.1} ns per point)",
        candidate(a, best),
        pm(best.rmse, 4),
        ms(best.time_s),
        a.sampler_ns(best.row, at.rays)
    );
    match at.best_flip() {
        Some(f) if f.candidate() == best.candidate() => {
            let _ = write!(s, "; it has the least FLIP too ({:.4})", f.flip.value);
        }
        Some(f) => {
            let _ = write!(
                s,
                "; by FLIP ship {} instead (FLIP {:.4} against {:.4})",
                candidate(a, f),
                f.flip.value,
                best.flip.value
            );
        }
        None => {}
    }
    if best.flicker.is_finite() {
        let _ = write!(s, "; flicker {:.4}", best.flicker);
    }
    let sp = best.split;
    if sp.bias_rmse.is_finite() && sp.noise_rmse.is_finite() {
        let _ = write!(s, "; its error is bias {:.4}", sp.bias_rmse);
        if sp.bias_se.is_finite() {
            let _ = write!(s, " ± {:.4}", sp.bias_se);
        }
        let _ = write!(s, " and noise {:.4}", sp.noise_rmse);
    }
    let ties: Vec<String> = at.near_ties().skip(1).map(|e| candidate(a, e)).collect();
    if ties.is_empty() {
        s += "; no other configuration is within its paired margin";
    } else if ties.len() <= NEAR_TIES_NAMED {
        let _ = write!(s, "; within its paired margin (near-ties): {}", ties.join("; "));
    } else {
        let _ = write!(
            s,
            "; within its paired margin, {} near-ties: {} and {} more (advice.json lists them all)",
            ties.len(),
            ties[..NEAR_TIES_NAMED].join("; "),
            ties.len() - NEAR_TIES_NAMED
        );
    }
    let default = at
        .entries
        .iter()
        .filter(|e| e.row == PAPER_DEFAULT)
        .min_by(|x, y| x.rmse.value.total_cmp(&y.rmse.value));
    match default {
        Some(d) if d.candidate() == best.candidate() => s += "; the paper's default is the best here",
        Some(d) => {
            let _ = write!(
                s,
                "; the paper's default has {:.0} % more RMSE ({})",
                100.0 * (d.rmse.value / best.rmse.value - 1.0),
                pm(d.rmse, 4)
            );
        }
        None => {}
    }
    s + "."
}

/// Why a budget has no ranked configuration.
pub fn outside_note(r: &Ranking) -> String {
    let below: Vec<f64> = r
        .outside
        .iter()
        .filter_map(|(_, p)| if let Place::Below { fastest_s } = p { Some(*fastest_s) } else { None })
        .collect();
    let above: Vec<f64> = r
        .outside
        .iter()
        .filter_map(|(_, p)| if let Place::Above { slowest_s } = p { Some(*slowest_s) } else { None })
        .collect();
    if above.is_empty() {
        let t = below.iter().copied().fold(f64::INFINITY, f64::min);
        format!(
            "below the measured range: no configuration renders an image this fast (the cheapest measured render takes {} ms)",
            ms(t)
        )
    } else if below.is_empty() {
        let t = above.iter().copied().fold(0.0, f64::max);
        format!(
            "above the measured range: every configuration's dearest measured render is faster (the dearest takes {} ms); add larger ray counts with --rays",
            ms(t)
        )
    } else {
        "outside every configuration's measured times".into()
    }
}

pub fn status(r: &Ranking) -> &'static str {
    if !r.ranked.is_empty() {
        return "inside";
    }
    let all = |f: fn(&Place) -> bool| r.outside.iter().all(|(_, p)| f(p));
    if all(|p| matches!(p, Place::Below { .. })) {
        "below"
    } else if all(|p| matches!(p, Place::Above { .. })) {
        "above"
    } else {
        "outside"
    }
}

/// A ranked candidate's name: its configuration, and after an accumulating pipeline its schedule
/// ("either schedule" where both draw the same points, `Analysis::one_schedule`).
pub fn candidate(a: &Analysis, e: &Entry) -> String {
    let l = label(e.row);
    if !a.temporal {
        l
    } else if a.one_schedule.contains(&e.row) {
        format!("{l}, either schedule (the same points)")
    } else {
        format!("{l}, {} schedule", e.schedule.name())
    }
}

/// A camera's name in sentences: "the still camera", "camera 'orbit'".
pub fn camera(name: &str) -> String {
    if name == crate::plan::CameraId::STATIC_NAME {
        "the scene's still camera".into()
    } else {
        format!("the moving camera '{name}'")
    }
}

/// A configuration's name in tables and legends.
pub fn label(row: Row) -> String {
    let l = row.name();
    if row == PAPER_DEFAULT { format!("{l} (paper default)") } else { l }
}

/// "value ± σ" with at least `digits` decimals, and more where the ± would round to zero (it
/// shows its first significant digit: "0.03330 ± 0.00004", not "0.0333 ± 0.0000").
pub fn pm(e: Estimate, digits: usize) -> String {
    let need =
        if e.se > 0.0 && e.se.is_finite() { (-e.se.log10()).ceil().clamp(0.0, 8.0) as usize } else { 0 };
    let d = digits.max(need);
    format!("{:.d$} ± {:.d$}", e.value, e.se)
}

/// The error model, once, as the page and advice.json state it (`compare::model`).
pub fn model_text() -> String {
    format!(
        "Every ± and margin is 1 σ of one error model. Replicates: replicate r has the same seed in every \
         configuration, so an MSE is the mean over replicates (σ = sd/√n) and two configurations are compared \
         replicate by replicate. Times: a time is the median of its timed renders, ln t = ln T + u + e, with u \
         the session's factor shared by every configuration timed together (σ {:.0} %, measured between runs) \
         and e the median's own scatter (σ from its samples: their order-statistic interval at its coverage). \
         At a budget an MSE moves with its time by the local slope k = d ln MSE / d ln t (a longer time fits \
         fewer rays), so a gain's or margin's σ² is the paired replicate part plus (k₁ − k₂)² σ_u² + k₁² σ_e₁² + \
         k₂² σ_e₂²: the shared factor cancels but for the slopes' difference. What is shipped is measured at \
         its ray count: its RMSE carries the replicates' σ, its time √(σ_u² + σ_e²).",
        100.0 * model::RUN_FACTOR
    )
}
