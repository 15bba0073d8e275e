//! The comparisons at equal ray count, which the answer's findings and tables quote beside the
//! equal-time ones: two configurations replicate by replicate (RMSE and time at each ray count),
//! the most efficient configuration per ray count (efficiency as a column, not the ranking), and
//! the rows that differ in one choice.

use crate::compare::claims::{ALPHA, critical_se};
use crate::compare::efficiency::{Best, best_per_ray_count};
use crate::compare::{self, per_pixel_unbiased};
use crate::report::Table;
use crate::report::run::data::{ReportInput, agg_label, row_label};
use crate::report::run::equal_time::range;
use crate::results::lookup;
use crate::spec::{Group, Row};

/// `picked` as runs of consecutive entries of `all`: "1–4, 16, 64–1024".
pub fn ray_list(picked: &[u32], all: &[u32]) -> String {
    let mut runs: Vec<(u32, u32)> = Vec::new();
    let mut prev: Option<usize> = None;
    for (i, r) in all.iter().enumerate() {
        if !picked.contains(r) {
            continue;
        }
        match (runs.last_mut(), prev) {
            (Some(run), Some(p)) if p + 1 == i => run.1 = *r,
            _ => runs.push((*r, *r)),
        }
        prev = Some(i);
    }
    let runs: Vec<String> =
        runs.iter().map(|&(a, b)| if a == b { a.to_string() } else { format!("{a}–{b}") }).collect();
    runs.join(", ")
}

/// `w` against `r` at every ray count of the sweep, replicate by replicate: where w's RMSE is
/// significantly lower or higher (paired t beyond the 1 % two-sided quantile at n − 1 degrees of
/// freedom, as the verdicts), and the ratio of their median render times.
pub fn head_to_head(data: &ReportInput, g: &Group, scene: &str, w: Row, r: Row) -> String {
    let (mut lower, mut higher, mut within) = (Vec::new(), Vec::new(), Vec::new());
    let (mut ratios, mut crit) = (Vec::new(), f64::NAN);
    for &n in &g.rays {
        if let Some(p) = compare::paired_rmse(data.results, scene, r, w, n) {
            crit = critical_se(p.n);
            let bucket = match p.sign(ALPHA) {
                -1 => &mut lower,
                1 => &mut higher,
                _ => &mut within,
            };
            bucket.push((n, 100.0 * p.relative()));
        }
        let t = |x: Row| lookup(&data.aggs, scene, x, n).and_then(|a| a.time).map(|t| t.median);
        if let (Some(tw), Some(tr)) = (t(w), t(r)) {
            ratios.push(tw / tr);
        }
    }
    let all = &g.rays;
    let part = |v: &[(u32, f64)], what: &str| {
        let rays: Vec<u32> = v.iter().map(|x| x.0).collect();
        (!v.is_empty()).then(|| {
            format!(
                "{} % {what} at {} of {} ray counts ({})",
                range(v.iter().map(|x| x.1.abs()), |x| format!("{x:.1}")),
                v.len(),
                all.len(),
                ray_list(&rays, all)
            )
        })
    };
    let mut parts: Vec<String> =
        [part(&lower, "lower"), part(&higher, "higher")].into_iter().flatten().collect();
    if !within.is_empty() {
        let rays: Vec<u32> = within.iter().map(|x| x.0).collect();
        parts.push(format!(
            "not significantly different (|t| < {crit:.2}) at {} ({})",
            within.len(),
            ray_list(&rays, all)
        ));
    }
    let time = if ratios.is_empty() {
        String::new()
    } else {
        format!("; its median render time is ×{} the other's", range(ratios, |x| format!("{x:.2}")))
    };
    format!(
        "At equal rays, {} against {}, replicate by replicate (the same seeds): RMSE {}{time}.",
        row_label(w),
        row_label(r),
        parts.join(", ")
    )
}

fn best_cells(b: Option<&Best>) -> [String; 3] {
    let Some(b) = b else { return ["–".into(), "–".into(), "–".into()] };
    let e = format!("{:.3e} ± {:.1e}", b.best.efficiency, b.best.efficiency_spread);
    let margin = match (b.runner_up, b.ratio(), b.margin_se) {
        (Some(r), Some(x), Some(s)) => format!("×{x:.3} over {} ({s:.1} paired SE)", agg_label(r)),
        (Some(r), Some(x), None) => format!("×{x:.3} over {}", agg_label(r)),
        _ => "no runner-up".into(),
    };
    [agg_label(b.best), e, margin]
}

/// The most efficient configuration at each ray count, overall and among the per-pixel-unbiased.
pub fn best_table(data: &ReportInput, g: &Group, scene: &str) -> Table {
    let all = best_per_ray_count(&data.aggs, data.results, scene, &g.rows, &g.rays, |_| true);
    let unbiased = best_per_ray_count(&data.aggs, data.results, scene, &g.rows, &g.rays, per_pixel_unbiased);
    let header = [
        "rays",
        "most efficient",
        "efficiency (1/(MSE·s))",
        "margin",
        "most efficient per-pixel-unbiased",
        "efficiency (1/(MSE·s))",
        "margin",
    ];
    let rows = g
        .rays
        .iter()
        .filter_map(|&n| {
            let a = all.iter().find(|b| b.rays == n);
            let u = unbiased.iter().find(|b| b.rays == n);
            a?;
            let mut cells = vec![n.to_string()];
            cells.extend(best_cells(a));
            cells.extend(best_cells(u));
            Some(cells)
        })
        .collect();
    Table {
        title: format!(
            "Efficiency at each ray count ('{scene}', sweep '{}'): 1 / (MSE · AO time) ± spread, and the \
             margin over the runner-up in paired standard errors (replicates paired by seed, both times' \
             spread). A column, not the ranking: it orders two configurations as their MSE at equal time \
             only where MSE ∝ 1/time",
            g.name
        ),
        header: header.map(String::from).to_vec(),
        rows,
    }
}

/// Rows that differ in one choice, compared replicate by replicate (the same seeds): the RMSE
/// difference in percent with its paired t, and the ratio of their median render times.
pub fn paired_table(data: &ReportInput, g: &Group, scene: &str) -> Table {
    let mut header = vec!["b vs a".to_string()];
    header.extend(g.rays.iter().map(|r| format!("{r} rays")));
    let rows = compare::one_factor_pairs(&g.rows)
        .into_iter()
        .map(|(a, b)| {
            let mut cells = vec![format!("{} vs {}", row_label(b), row_label(a))];
            cells.extend(g.rays.iter().map(|&n| paired_cell(data, scene, a, b, n)));
            cells
        })
        .collect();
    Table {
        title: format!(
            "Paired comparisons at equal rays ('{scene}', sweep '{}'): RMSE of b relative to a, mean over \
             replicates with the same seed (t = difference / paired standard error), and b's median render \
             time over a's",
            g.name
        ),
        header,
        rows,
    }
}

fn paired_cell(data: &ReportInput, scene: &str, a: Row, b: Row, n: u32) -> String {
    let Some(p) = compare::paired_rmse(data.results, scene, a, b, n) else { return "–".into() };
    let t = p.in_se();
    let t = if t.is_finite() { format!("t {t:+.1}") } else { "every replicate".into() };
    let time = |r: Row| lookup(&data.aggs, scene, r, n).and_then(|x| x.time).map(|t| t.median);
    let ratio = match (time(a), time(b)) {
        (Some(ta), Some(tb)) if ta > 0.0 => format!("; time ×{:.2}", tb / ta),
        _ => String::new(),
    };
    format!("{:+.1} % ({t}){ratio}", 100.0 * p.relative())
}

#[cfg(test)]
mod tests {
    #[test]
    fn ray_lists_read_as_runs() {
        let all = [1, 2, 4, 8, 16, 32, 64];
        assert_eq!(super::ray_list(&[1, 2, 4, 16, 32, 64], &all), "1–4, 16–64");
        assert_eq!(super::ray_list(&[8], &all), "8");
        assert_eq!(super::ray_list(&[1, 4], &all), "1, 4");
    }
}
