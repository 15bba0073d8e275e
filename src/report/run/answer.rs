//! The answer at the top of the page, generated from the run: for every `[[convergence]]` sweep,
//! the configuration with the least error per unit of time (highest efficiency) at each ray count,
//! overall and among per-pixel-unbiased ones, with its margin over the runner-up; and the paired
//! comparisons of rows that differ in one choice. Every sentence quotes the tables below it.

use crate::compare::{self, Best};
use crate::metrics::STRUCTURED_RATIO;
use crate::report::Table;
use crate::report::run::data::{ReportInput, agg_label, lowfreq_stat, row_label};
use crate::results::lookup;
use crate::spec::{Group, Row};

/// The answer's paragraphs and its tables.
pub struct Answer {
    pub text: Vec<String>,
    pub tables: Vec<Table>,
}

pub fn answer(data: &ReportInput) -> Answer {
    let mut text = Vec::new();
    let mut tables = Vec::new();
    for (g, _, scene) in data.sweeps() {
        let all = compare::best_per_ray_count(&data.aggs, scene, &g.rows, &g.rays, |_| true);
        let unbiased =
            compare::best_per_ray_count(&data.aggs, scene, &g.rows, &g.rays, compare::per_pixel_unbiased);
        if all.is_empty() {
            continue;
        }
        text.push(format!(
            "Answer for '{scene}' (sweep '{}'). The least error per unit of time — the highest efficiency, \
             1 / (MSE · AO time) — at each of its {} ray counts: {}.",
            g.name,
            all.len(),
            winners(data, scene, &all)
        ));
        if !unbiased.is_empty() {
            text.push(format!(
                "Among estimators that are unbiased in every pixel: {}.",
                winners(data, scene, &unbiased)
            ));
        }
        for set in [&all, &unbiased] {
            if let Some((w, r)) = top_two(set) {
                text.push(head_to_head(data, g, scene, w, r));
            }
        }
        let p = "A margin is the winner's efficiency over the runner-up's at the same ray count; under 3 \
                 combined spreads this run's timing does not resolve the order (tables below: the margin per \
                 ray count, and the paired RMSE differences and time ratios behind it)."
            .to_string();
        text.push(p);
        tables.push(best_table(g, scene, &all, &unbiased));
        let paired = paired_table(data, g, scene);
        if !paired.rows.is_empty() {
            tables.push(paired);
        }
    }
    Answer { text, tables }
}

/// "A at 7 of 11 ray counts (4, 16–512; ×1.05–1.14 the runner-up's efficiency, by more than 3
/// combined spreads at 2 of them); B at …", winners in order of how often they win ("at none of
/// them by more than 3 combined spreads" when no margin is resolved), a winner whose error is
/// structured (low-frequency ratio above `STRUCTURED_RATIO`, the verdict advise ships by) said so.
fn winners(data: &ReportInput, scene: &str, best: &[Best]) -> String {
    let mut groups: Vec<(String, Vec<&Best>)> = Vec::new();
    for b in best {
        let label = agg_label(b.best);
        match groups.iter_mut().find(|(l, _)| *l == label) {
            Some((_, v)) => v.push(b),
            None => groups.push((label, vec![b])),
        }
    }
    groups.sort_by_key(|(_, v)| std::cmp::Reverse(v.len()));
    let parts: Vec<String> = groups
        .iter()
        .map(|(label, v)| {
            let rays: Vec<u32> = v.iter().map(|b| b.rays).collect();
            let ratios: Vec<f64> = v.iter().filter_map(|b| b.ratio()).collect();
            let resolved = v.iter().filter(|b| b.spreads().is_some_and(|s| s > 3.0)).count();
            let margin = if ratios.is_empty() {
                String::new()
            } else {
                let lo = ratios.iter().copied().fold(f64::INFINITY, f64::min);
                let hi = ratios.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                let r = if (hi - lo) < 0.005 { format!("×{lo:.2}") } else { format!("×{lo:.2}–{hi:.2}") };
                let resolved = match resolved {
                    0 => "at none of them by more than 3 combined spreads".to_string(),
                    n if n == v.len() => "by more than 3 combined spreads at every one".to_string(),
                    n => format!("by more than 3 combined spreads at {n} of them"),
                };
                format!("; {r} the runner-up's efficiency, {resolved}")
            };
            let ratio = v
                .iter()
                .filter_map(|b| {
                    compare::row_of(b.best).and_then(|r| lowfreq_stat(data.results, scene, r, b.rays))
                })
                .map(|(m, _)| m)
                .fold(f64::NEG_INFINITY, f64::max);
            let band = if ratio > STRUCTURED_RATIO {
                format!(
                    " — its error is structured (low-frequency ratio up to {ratio:.2}, above \
                     {STRUCTURED_RATIO}: blotches or bands a blur keeps; table of all configurations)"
                )
            } else {
                String::new()
            };
            format!(
                "{label} at {} of {} ray counts ({}{margin}){band}",
                v.len(),
                best.len(),
                ray_list(&rays, &best.iter().map(|b| b.rays).collect::<Vec<_>>())
            )
        })
        .collect();
    parts.join("; ")
}

/// `picked` as runs of consecutive entries of `all`: "1–4, 16, 64–1024".
fn ray_list(picked: &[u32], all: &[u32]) -> String {
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

/// The most frequent winner and the row it most often beats or loses to: the pair the answer
/// turns on. `None` when one row has no rival.
fn top_two(best: &[Best]) -> Option<(Row, Row)> {
    let mut wins: Vec<(Row, usize)> = Vec::new();
    for b in best {
        let r = compare::row_of(b.best)?;
        match wins.iter_mut().find(|(x, _)| *x == r) {
            Some((_, k)) => *k += 1,
            None => wins.push((r, 1)),
        }
    }
    let w = wins.iter().max_by_key(|(_, k)| *k)?.0;
    let mut rivals: Vec<(Row, usize)> = Vec::new();
    for b in best {
        let (Some(x), Some(y)) = (compare::row_of(b.best), b.runner_up.and_then(compare::row_of)) else {
            continue;
        };
        let other = if x == w {
            y
        } else if y == w {
            x
        } else {
            continue;
        };
        match rivals.iter_mut().find(|(o, _)| *o == other) {
            Some((_, k)) => *k += 1,
            None => rivals.push((other, 1)),
        }
    }
    Some((w, rivals.iter().max_by_key(|(_, k)| *k)?.0))
}

/// `w` against `r` at every ray count of the sweep, replicate by replicate: where w's RMSE is lower
/// or higher by at least 5 paired standard errors, and the ratio of their median times.
fn head_to_head(data: &ReportInput, g: &Group, scene: &str, w: Row, r: Row) -> String {
    let (mut lower, mut higher, mut within) = (Vec::new(), Vec::new(), Vec::new());
    let mut ratios = Vec::new();
    for &n in &g.rays {
        if let Some(p) = compare::paired_rmse(data.results, scene, r, w, n) {
            let bucket = if p.z() <= -5.0 {
                &mut lower
            } else if p.z() >= 5.0 {
                &mut higher
            } else {
                &mut within
            };
            bucket.push((n, 100.0 * p.relative));
        }
        let t = |x: Row| lookup(&data.aggs, scene, x, n).and_then(|a| a.time).map(|t| t.median);
        if let (Some(tw), Some(tr)) = (t(w), t(r)) {
            ratios.push(tw / tr);
        }
    }
    let all: Vec<u32> = g.rays.clone();
    let part = |v: &[(u32, f64)], what: &str| {
        if v.is_empty() {
            return None;
        }
        let lo = v.iter().map(|x| x.1.abs()).fold(f64::INFINITY, f64::min);
        let hi = v.iter().map(|x| x.1.abs()).fold(f64::NEG_INFINITY, f64::max);
        let rays: Vec<u32> = v.iter().map(|x| x.0).collect();
        Some(format!(
            "{lo:.1}–{hi:.1} % {what} at {} of {} ray counts ({})",
            v.len(),
            all.len(),
            ray_list(&rays, &all)
        ))
    };
    let mut parts: Vec<String> =
        [part(&lower, "lower"), part(&higher, "higher")].into_iter().flatten().collect();
    if !within.is_empty() {
        let rays: Vec<u32> = within.iter().map(|x| x.0).collect();
        parts.push(format!(
            "within 5 paired standard errors at {} ({})",
            within.len(),
            ray_list(&rays, &all)
        ));
    }
    let time = if ratios.is_empty() {
        String::new()
    } else {
        let lo = ratios.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = ratios.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        format!("; its median render time is ×{lo:.2}–{hi:.2} the other's")
    };
    format!(
        "{} against {}, replicate by replicate (the same seeds): RMSE {}{time}.",
        row_label(w),
        row_label(r),
        parts.join(", ")
    )
}

fn best_cells(b: Option<&Best>) -> [String; 3] {
    let Some(b) = b else { return ["–".into(), "–".into(), "–".into()] };
    let e = format!("{:.3e} ± {:.1e}", b.best.efficiency, b.best.efficiency_spread);
    let margin = match (b.runner_up, b.ratio(), b.spreads()) {
        (Some(r), Some(x), Some(s)) => format!("×{x:.3} over {} ({s:.1} spreads)", agg_label(r)),
        _ => "no runner-up".into(),
    };
    [agg_label(b.best), e, margin]
}

fn best_table(g: &Group, scene: &str, all: &[Best], unbiased: &[Best]) -> Table {
    let header = [
        "rays",
        "best per unit time",
        "efficiency (1/(MSE·s))",
        "margin",
        "best per-pixel-unbiased",
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
            "Answer: the most efficient configuration at each ray count ('{scene}', sweep '{}'); efficiency = \
             1 / (MSE · AO time) ± spread",
            g.name
        ),
        header: header.map(String::from).to_vec(),
        rows,
    }
}

/// Rows that differ in one choice, compared replicate by replicate (the same seeds): the RMSE
/// difference in percent with its paired z, and the ratio of their median render times.
fn paired_table(data: &ReportInput, g: &Group, scene: &str) -> Table {
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
            "Paired comparisons ('{scene}', sweep '{}'): RMSE of b relative to a, mean over replicates with the \
             same seed (z = difference / paired standard error), and b's median render time over a's",
            g.name
        ),
        header,
        rows,
    }
}

fn paired_cell(data: &ReportInput, scene: &str, a: Row, b: Row, n: u32) -> String {
    let Some(p) = compare::paired_rmse(data.results, scene, a, b, n) else { return "–".into() };
    let z = p.z();
    let z = if z.is_finite() { format!("z {z:+.1}") } else { "every replicate".into() };
    let time = |r: Row| lookup(&data.aggs, scene, r, n).and_then(|x| x.time).map(|t| t.median);
    let ratio = match (time(a), time(b)) {
        (Some(ta), Some(tb)) if ta > 0.0 => format!("; time ×{:.2}", tb / ta),
        _ => String::new(),
    };
    format!("{:+.1} % ({z}){ratio}", 100.0 * p.relative)
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
