//! The equal-time comparison as the page's tables and as `equal_time.csv`: every configuration's
//! mean MSE at each time budget over the baseline's, the answer at each budget and its margin, and
//! the one-factor pairs at equal time. The numbers are `compare::equal_time`'s; this file words
//! and formats them (and the answer's sentences, `answer.rs`, use the same formatting).

use crate::compare::budget::Metric;
use crate::compare::equal_time::{AtTime, EqualTime, Ratio};
use crate::compare::one_factor_pairs;
use crate::report::Table;
use crate::report::run::data::row_label;
use crate::results::csv_field;
use crate::spec::Row;

/// `x` to two significant digits, as a reader compares ratios: 0.054, 0.60, 1.2, 12, 430.
pub fn sig2(x: f64) -> String {
    if !x.is_finite() || x == 0.0 {
        return if x.is_infinite() { "∞".into() } else { format!("{x}") };
    }
    let d = (1 - x.abs().log10().floor() as i32).max(0) as usize;
    format!("{x:.d$}")
}

/// "a–b", or one number when both ends print the same ("1.6", never "1.6–1.6").
pub fn range(values: impl IntoIterator<Item = f64>, f: impl Fn(f64) -> String) -> String {
    let v: Vec<f64> = values.into_iter().filter(|x| !x.is_nan()).collect();
    let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if v.is_empty() {
        return "–".into();
    }
    let (a, b) = (f(lo), f(hi));
    if a == b { a } else { format!("{a}–{b}") }
}

/// A margin in standard errors: "2.3", "∞".
pub fn se1(x: f64) -> String {
    if x.is_infinite() { "∞".into() } else { format!("{x:.1}") }
}

/// A budget: "8.1 ms", and 0.43 s stays "430 ms" (one unit on a page).
pub fn ms(budget_s: f64) -> String {
    format!("{} ms", sig2(budget_s * 1e3))
}

/// Budgets as one range: "6.2–30 ms", "1.9 ms".
pub fn ms_range(budgets_s: impl IntoIterator<Item = f64>) -> String {
    format!("{} ms", range(budgets_s, |b| sig2(b * 1e3)))
}

fn ratio_cell(r: &Ratio) -> String {
    if r.se > 0.0 { format!("{} ± {}", sig2(r.value), sig2(r.se)) } else { sig2(r.value) }
}

/// The answer at a budget and its margin over the runner-up, as one cell.
fn answer_cell(at: &AtTime) -> String {
    let Some(a) = at.answer() else { return "none: every one measured here is structured".into() };
    match at.runner_up() {
        Some(r) => {
            let m = Ratio::of(&r.at, &a.at);
            format!(
                "{} (runner-up {}: ×{} its MSE, {} SE)",
                row_label(a.at.row),
                row_label(r.at.row),
                sig2(m.value),
                se1(m.in_se())
            )
        }
        None => format!("{} (no runner-up)", row_label(a.at.row)),
    }
}

/// Rows × budgets: each configuration's MSE over the baseline's at the budget ± 1 σ, the rays per
/// pixel the budget buys it, and whether its error is structured there; the answer first.
pub fn table(et: &EqualTime, sweep: &str) -> Table {
    let mut header = vec!["configuration".to_string()];
    header.extend(et.at.iter().map(|a| ms(a.budget_s)));
    let mut rows = vec![{
        let mut r = vec!["answer: least MSE, error not structured (margin over the runner-up)".to_string()];
        r.extend(et.at.iter().map(answer_cell));
        r
    }];
    for c in &et.curves {
        let mut r = vec![row_label(c.row)];
        r.extend(et.at.iter().map(|at| match at.entry(c.row) {
            None => "not measured there".into(),
            Some(e) => {
                let ratio = e.vs_baseline.map_or("–".into(), |x| ratio_cell(&x));
                let base = if c.row == et.baseline {
                    format!("MSE {:.2e}", e.at.mean_mse(Metric::Rmse).value)
                } else {
                    ratio
                };
                let structured = if e.structured { " · structured" } else { "" };
                format!("{base} · {} rays{structured}", sig2(e.at.rays))
            }
        }));
        rows.push(r);
    }
    Table {
        title: format!(
            "Equal time ('{}', sweep '{sweep}', {} per image): each configuration's mean MSE at the budget \
             over that of {}, ± 1 σ (replicates paired by seed, and both times' spread), and the rays per \
             pixel the budget buys; lower is better",
            et.scene,
            et.view.name(),
            row_label(et.baseline)
        ),
        header,
        rows,
    }
}

/// The rows that differ in one choice at equal time: b's MSE over a's at each budget, ± 1 σ and
/// in standard errors.
pub fn pairs_table(et: &EqualTime, rows: &[Row], sweep: &str) -> Table {
    let mut header = vec!["b vs a".to_string()];
    header.extend(et.at.iter().map(|a| ms(a.budget_s)));
    let rows = one_factor_pairs(rows)
        .into_iter()
        .map(|(a, b)| {
            let mut cells = vec![format!("{} vs {}", row_label(b), row_label(a))];
            cells.extend(et.at.iter().map(|at| match (at.entry(a), at.entry(b)) {
                (Some(ea), Some(eb)) => {
                    let r = Ratio::of(&eb.at, &ea.at);
                    format!("×{} ({:+.1} SE)", ratio_cell(&r), r.in_se())
                }
                _ => "not measured there".into(),
            }));
            cells
        })
        .collect();
    Table {
        title: format!(
            "Paired comparisons at equal time ('{}', sweep '{sweep}', {}): b's mean MSE over a's at the \
             budget, ± 1 σ, and ln(ratio) in standard errors (negative: b has less error)",
            et.scene,
            et.view.name()
        ),
        header,
        rows,
    }
}

/// The `equal_time.csv` header.
pub const CSV_COLUMNS: &[&str] = &[
    "scene",
    "sweep",
    "time",
    "budget_s",
    "distribution",
    "sequence",
    "seed_mode",
    "measured",
    "rank",
    "rays",
    "mse",
    "mse_se",
    "mse_over_baseline",
    "mse_over_baseline_se",
    "structured",
    "answer",
];

/// One line per (sweep, view, budget, configuration); a configuration not measured at a budget
/// has `measured` false and empty numbers.
pub fn csv(all: &[(String, EqualTime)]) -> String {
    let mut s = CSV_COLUMNS.join(",") + "\n";
    let num = |x: f64| if x.is_finite() { format!("{x}") } else { String::new() };
    for (sweep, et) in all {
        for at in &et.at {
            let answer = at.answer().map(|e| e.at.row);
            for c in &et.curves {
                let r = c.row;
                let mut f = vec![
                    csv_field(&et.scene),
                    csv_field(sweep),
                    et.view.key().into(),
                    num(at.budget_s),
                    r.distribution.name().into(),
                    r.sequence.name().into(),
                    r.seed_mode.name().into(),
                ];
                match at.ranked.iter().position(|e| e.at.row == r) {
                    Some(i) => {
                        let e = &at.ranked[i];
                        let m = e.at.mean_mse(Metric::Rmse);
                        let (v, se) = e.vs_baseline.map_or((f64::NAN, f64::NAN), |x| (x.value, x.se));
                        f.extend([
                            "true".into(),
                            (i + 1).to_string(),
                            num(e.at.rays),
                            num(m.value),
                            num(m.se),
                            num(v),
                            num(se),
                            e.structured.to_string(),
                            (answer == Some(r)).to_string(),
                        ]);
                    }
                    // Not measured: no rank, no numbers, not the answer.
                    None => {
                        f.push("false".into());
                        f.extend(std::iter::repeat_n(String::new(), 7));
                        f.push("false".into());
                    }
                }
                s += &f.join(",");
                s.push('\n');
            }
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_of_equal_ends_print_once() {
        assert_eq!(range([1.61, 1.64], |x| format!("{x:.1}")), "1.6");
        assert_eq!(range([0.83, 0.93], sig2), "0.83–0.93");
        assert_eq!(sig2(0.0543), "0.054");
        assert_eq!(sig2(430.2), "430");
        assert_eq!(sig2(1.0), "1.0");
    }
}
