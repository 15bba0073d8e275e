//! The sentences and small facts advise's page and advice.json share: the answer per budget, what
//! is shipped, why a budget has no answer.

use crate::advice::{self, AtBudget, Metric, PAPER_DEFAULT, Place, Ranking};
use crate::metrics::STRUCTURED_RATIO;
use crate::spec::Row;
use std::fmt::Write as _;

pub fn ms(s: f64) -> String {
    format!("{}", advice::round_significant(s * 1e3, 3))
}
/// One sentence per budget: what to ship and what it gains, or why there is no answer.
pub fn advice_line(r: &Ranking, low: &Ranking) -> String {
    let b = ms(r.budget_s);
    let Some(best) = advice::recommended(r) else {
        return format!("At {b} ms per image: {}.", outside_note(r));
    };
    let e = best.rmse(Metric::Rmse);
    let mut s = format!(
        "At {b} ms per image: ship {} with {} per pixel (RMSE {})",
        label(best.row),
        match shipped_rays(best) {
            1 => "1 ray".to_string(),
            n => format!("{n} rays"),
        },
        pm(e, 4)
    );
    if best.structured() {
        let _ = write!(
            s,
            " — its error is structured (low-frequency ratio {:.2} > {STRUCTURED_RATIO}: blotches or bands \
             that a blur keeps and RMSE does not show), as is every configuration measured here",
            best.lowfreq_ratio
        );
    }
    match default_at(r) {
        Some(d) if d.row == best.row => s += ": the paper's default is the best here",
        Some(d) => {
            let g = advice::gain(d, best, Metric::Rmse);
            let _ = write!(
                s,
                ": {:.2} ± {:.2} × less MSE than the paper's default at the same time",
                g.value, g.se
            );
        }
        None => s += "; the paper's default is outside its measured times here",
    }
    if let Some(second) = r.ranked.iter().find(|a| a.row != best.row && !a.structured()) {
        let z = advice::paired_z(best, second, Metric::Rmse);
        let _ = write!(s, "; runner-up {} ({:+.1} paired SE)", label(second.row), z);
    }
    if let Some(top) = r.ranked.first().filter(|t| t.row != best.row) {
        let _ = write!(
            s,
            "; {} has {:.0} % less RMSE but its error is structured (low-frequency ratio {:.2} > \
             {STRUCTURED_RATIO}), so it is not advised",
            label(top.row),
            100.0 * (1.0 - top.rmse(Metric::Rmse).value / e.value),
            top.lowfreq_ratio
        );
    }
    if let Some(lb) = low.ranked.first().filter(|l| l.row != best.row) {
        let _ = write!(s, "; least low-pass RMSE: {}", label(lb.row));
    }
    if !r.outside.is_empty() {
        let _ =
            write!(s, " ({} configurations outside their measured times here, unranked)", r.outside.len());
    }
    s + "."
}
/// The rays to ship: the interpolated count, rounded down (at least 1).
pub fn shipped_rays(a: &AtBudget) -> u32 {
    (a.rays.floor() as u32).max(1)
}
pub fn default_at(r: &Ranking) -> Option<&AtBudget> {
    r.ranked.iter().find(|a| a.row == PAPER_DEFAULT)
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
/// A configuration's name in tables and legends.
pub fn label(row: Row) -> String {
    let l = row.name();
    if row == PAPER_DEFAULT { format!("{l} (paper default)") } else { l }
}
/// "value ± se" with at least `digits` decimals, and more where the ± would round to zero (it
/// shows its first significant digit: "0.03330 ± 0.00004", not "0.0333 ± 0.0000").
pub fn pm(e: advice::Estimate, digits: usize) -> String {
    let need =
        if e.se > 0.0 && e.se.is_finite() { (-e.se.log10()).ceil().clamp(0.0, 8.0) as usize } else { 0 };
    let d = digits.max(need);
    format!("{:.d$} ± {:.d$}", e.value, e.se)
}
