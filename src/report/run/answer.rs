//! The answer at the top of the page, generated from the run. For every `[[convergence]]` sweep,
//! one paragraph of at most three sentences: which configuration has the least MSE at equal total
//! render time among those whose error is noise (advise's rule: a structured estimator is never
//! the answer, it is named as rejected and why), and by how much; then, after the key figure, the
//! findings behind it (the answer against its runner-up at equal rays, seeds whose expected error
//! is identical by construction, the AO-time view); and the tables. Every sentence quotes a table
//! below it.

use crate::compare::claims::{ALPHA, critical_se};
use crate::compare::cost::{pooled_time_ratio, same_expected_error};
use crate::compare::equal_time::{AtTime, Entry, EqualTime, Ratio, TimeView};
use crate::compare::{self, PAPER_DEFAULT};
use crate::metrics::STRUCTURED_RATIO;
use crate::report::Table;
use crate::report::run::data::{ReportInput, row_label};
use crate::report::run::equal_time::{self as tables, ms, ms_range, range, se1, sig2};
use crate::report::run::rays;
use crate::spec::{Group, Row};

/// The answer's paragraphs and its tables.
pub struct Answer {
    /// One paragraph per sweep and scene, at most three sentences each: the page's first.
    pub lead: Vec<String>,
    /// What follows the key figure.
    pub findings: Vec<String>,
    pub tables: Vec<Table>,
    /// Every sweep at equal time in both views, with the sweep's name: `equal_time.csv`.
    pub equal_time: Vec<(String, EqualTime)>,
}

pub fn answer(data: &ReportInput) -> Answer {
    let mut a = Answer { lead: Vec::new(), findings: Vec::new(), tables: Vec::new(), equal_time: Vec::new() };
    for (g, _, scene) in data.sweeps() {
        let total = data.equal_time(g, scene, TimeView::Total, 1);
        let ao = data.equal_time(g, scene, TimeView::Ao, 1);
        a.lead.push(lead(&total, &g.name));
        if let Some((w, r)) = answer_and_rival(&total) {
            a.findings.push(rays::head_to_head(data, g, scene, w, r));
        }
        a.findings.extend(identities(data, g, scene));
        a.findings.push(ao_view(&ao));
        a.tables.push(tables::table(&total, &g.name));
        if !ao.at.is_empty() {
            a.tables.push(tables::table(&ao, &g.name));
        }
        let pairs = tables::pairs_table(&total, &g.rows, &g.name);
        if !pairs.rows.is_empty() {
            a.tables.push(pairs);
        }
        a.tables.push(rays::best_table(data, g, scene));
        let paired = rays::paired_table(data, g, scene);
        if !paired.rows.is_empty() {
            a.tables.push(paired);
        }
        a.equal_time.push((g.name.clone(), total));
        a.equal_time.push((g.name.clone(), ao));
    }
    if a.lead.is_empty() {
        a.lead.push(
            "This run has no [[convergence]] sweep, so it compares no configurations at equal time: its \
             tables compare RMSE at equal ray counts, and its verdicts the paper's claims."
                .into(),
        );
    }
    a
}

/// Each budget's answer, grouped by configuration, most budgets first.
fn winners(et: &EqualTime) -> Vec<(Row, Vec<&AtTime>)> {
    let mut wins: Vec<(Row, Vec<&AtTime>)> = Vec::new();
    for at in &et.at {
        let Some(a) = at.answer() else { continue };
        match wins.iter_mut().find(|(r, _)| *r == a.at.row) {
            Some((_, v)) => v.push(at),
            None => wins.push((a.at.row, vec![at])),
        }
    }
    wins.sort_by_key(|(_, v)| std::cmp::Reverse(v.len()));
    wins
}

/// ", sine-cosine, Fibonacci, shift at 2 (15–30 ms)" for every winner after the first.
fn other_winners(wins: &[(Row, Vec<&AtTime>)]) -> String {
    wins[1..]
        .iter()
        .map(|(r, v)| {
            format!(", {} at {} ({})", row_label(*r), v.len(), range(v.iter().map(|a| a.budget_s), ms))
        })
        .collect()
}

/// The runner-up's name, or the most frequent one's: "most often concentric-cosine, Fibonacci,
/// shift" (a list of names that are themselves lists of words would not read).
fn runner_names(rows: impl IntoIterator<Item = Row>) -> String {
    let mut v: Vec<(Row, usize)> = Vec::new();
    for r in rows {
        match v.iter_mut().find(|(x, _)| *x == r) {
            Some((_, n)) => *n += 1,
            None => v.push((r, 1)),
        }
    }
    let Some(&(top, _)) = v.iter().max_by_key(|(_, n)| *n) else { return String::new() };
    if v.len() == 1 { row_label(top) } else { format!("most often {}", row_label(top)) }
}

/// The sweep's answer in at most three sentences.
fn lead(et: &EqualTime, sweep: &str) -> String {
    let k = et.at.len();
    let scene = &et.scene;
    let (Some(first), Some(last)) = (et.at.first(), et.at.last()) else {
        return format!(
            "The configurations of '{scene}' (sweep '{sweep}') share no measured time, so they are not \
             compared at equal time; the tables below compare them at equal ray counts."
        );
    };
    let span = if k == 1 {
        format!("a budget of {} per image", ms(first.budget_s))
    } else {
        format!("{k} budgets from {} to {} per image", ms(first.budget_s), ms(last.budget_s))
    };
    let wins = winners(et);
    let Some((w, ats)) = wins.first() else {
        return format!(
            "At equal {} on '{scene}' ({span}; sweep '{sweep}'), every configuration measured has structured \
             error, so none is an answer.",
            et.view.name()
        );
    };
    let mine = |at: &AtTime| at.answer().expect("a winner's budget has an answer").clone();
    let at_n = if ats.len() == k {
        String::new()
    } else {
        format!(" at {} of {k} budgets ({})", ats.len(), ms_range(ats.iter().map(|a| a.budget_s)))
    };
    // With several winners the margins are the first's, at its budgets.
    let its = if wins.len() > 1 { "; at the first's budgets its MSE is" } else { ": its MSE is" };
    let margin: Vec<(Row, Ratio)> = ats
        .iter()
        .filter_map(|at| at.runner_up().map(|r| (r.at.row, Ratio::of(&mine(at).at, &r.at))))
        .collect();
    let runner = if margin.is_empty() {
        String::new()
    } else {
        let se: Vec<f64> = margin.iter().map(|m| -m.1.in_se()).collect();
        let unresolved =
            if se.iter().all(|x| x.abs() < RESOLVED_SE) { ", which this run does not resolve" } else { "" };
        format!(
            "{its} ×{} the runner-up's ({}; {} SE{unresolved})",
            range(margin.iter().map(|m| m.1.value), sig2),
            runner_names(margin.iter().map(|m| m.0)),
            range(se, se1)
        )
    };
    let base_name = if et.baseline == PAPER_DEFAULT { "the paper default's" } else { "that of" };
    let base: Vec<(f64, f64)> =
        ats.iter().filter_map(|at| mine(at).vs_baseline.map(|r| (at.budget_s, r.value))).collect();
    let runner_is_base = !margin.is_empty() && margin.iter().all(|m| m.0 == et.baseline);
    let base = match (base.first(), base.last()) {
        (Some(a), Some(b)) if *w != et.baseline && !runner_is_base => {
            let join = if runner.is_empty() { its } else { " and" };
            let values = if base.len() == 1 {
                format!("×{} {base_name} ({})", sig2(a.1), row_label(et.baseline))
            } else {
                format!(
                    "from ×{} {base_name} ({}) at {} to ×{} at {}",
                    sig2(a.1),
                    row_label(et.baseline),
                    ms(a.0),
                    sig2(b.1),
                    ms(b.0)
                )
            };
            format!("{join} {values}")
        }
        _ => String::new(),
    };
    let mut s = vec![format!(
        "At equal {} on '{scene}' ({span}; sweep '{sweep}'), the estimator with the least MSE among those \
         whose error is noise, not structure, is {}{at_n}{}{runner}{base}.",
        et.view.name(),
        row_label(*w),
        other_winners(&wins)
    )];
    s.extend(rejected(et));
    s.extend(unbiased(et, *w));
    s.iter().map(|x| capitalized(x)).collect::<Vec<_>>().join(" ")
}

/// A margin below this many standard errors is said to be unresolved.
const RESOLVED_SE: f64 = 2.0;

/// A sentence that starts with a configuration's name ("sine-cosine, …") starts with a capital.
fn capitalized(s: &str) -> String {
    let mut c = s.chars();
    c.next().map_or(String::new(), |f| f.to_uppercase().chain(c).collect())
}

/// The structured configurations with less MSE than a budget's answer: one sentence naming them
/// as rejected, and why.
fn rejected(et: &EqualTime) -> Option<String> {
    // Per row, where it ranks above the answer: (budget, MSE over the answer's, low-frequency ratio).
    type Above = (f64, f64, f64);
    let mut by_row: Vec<(Row, Vec<Above>)> = Vec::new();
    for at in &et.at {
        let Some(a) = at.answer() else { continue };
        for e in at.rejected() {
            let x = (at.budget_s, Ratio::of(&e.at, &a.at).value, e.at.structure);
            match by_row.iter_mut().find(|(r, _)| *r == e.at.row) {
                Some((_, v)) => v.push(x),
                None => by_row.push((e.at.row, vec![x])),
            }
        }
    }
    if by_row.is_empty() {
        return None;
    }
    let k = et.at.len();
    let each: Vec<String> = by_row
        .iter()
        .map(|(r, v)| {
            let at = if v.len() == k {
                "at every budget".to_string()
            } else {
                format!("at {} of {k} budgets, {}", v.len(), ms_range(v.iter().map(|x| x.0)))
            };
            format!("{} ({at}: ×{} the answer's MSE)", row_label(*r), range(v.iter().map(|x| x.1), sig2))
        })
        .collect();
    let z = range(by_row.iter().flat_map(|(_, v)| v.iter().map(|x| x.2)), |x| format!("{x:.1}"));
    let (has, its) = if by_row.len() == 1 { ("has", "its error is") } else { ("have", "their error is") };
    Some(format!(
        "{} {has} less MSE still but {} rejected there: {its} structured (low-frequency ratio {z}, above \
         {STRUCTURED_RATIO}), bands or moiré a renderer cannot ship as noise.",
        each.join(" and "),
        if by_row.len() == 1 { "is" } else { "are" }
    ))
}

/// When the answer is not unbiased in every pixel, the best that is.
fn unbiased(et: &EqualTime, answer: Row) -> Option<String> {
    if compare::per_pixel_unbiased(answer) {
        return None;
    }
    // At the budgets whose answer is not unbiased: the best unbiased, unstructured one.
    let best = |at: &AtTime| -> Option<(Entry, Entry)> {
        let a = at.answer().filter(|a| !a.unbiased)?;
        let u = at.ranked.iter().find(|e| e.unbiased && !e.structured)?;
        Some((u.clone(), a.clone()))
    };
    let pairs: Vec<(Entry, Entry)> = et.at.iter().filter_map(best).collect();
    let mut rows: Vec<(Row, usize)> = Vec::new();
    for (u, _) in &pairs {
        match rows.iter_mut().find(|(r, _)| *r == u.at.row) {
            Some((_, n)) => *n += 1,
            None => rows.push((u.at.row, 1)),
        }
    }
    let (u, n) = *rows.iter().max_by_key(|(_, n)| *n)?;
    let ratios = pairs.iter().filter(|(x, _)| x.at.row == u).map(|(x, a)| Ratio::of(&x.at, &a.at).value);
    let at =
        if n == pairs.len() { String::new() } else { format!("at {n} of those {} budgets, ", pairs.len()) };
    Some(format!(
        "The answer is not unbiased in every pixel; of the estimators that are, the best is {} ({at}×{} the \
         answer's MSE).",
        row_label(u),
        range(ratios, sig2)
    ))
}

/// The answer and the runner-up it meets most often.
fn answer_and_rival(et: &EqualTime) -> Option<(Row, Row)> {
    let wins = winners(et);
    let (w, ats) = wins.first()?;
    let mut rivals: Vec<(Row, usize)> = Vec::new();
    for r in ats.iter().filter_map(|at| at.runner_up()) {
        match rivals.iter_mut().find(|(x, _)| *x == r.at.row) {
            Some((_, n)) => *n += 1,
            None => rivals.push((r.at.row, 1)),
        }
    }
    Some((*w, rivals.iter().max_by_key(|(_, n)| *n)?.0))
}

/// Seeds whose expected MSE is identical by construction: said as what it is, with the pooled
/// cost test that can resolve the difference between them.
fn identities(data: &ReportInput, g: &Group, scene: &str) -> Vec<String> {
    same_expected_error(&g.rows)
        .into_iter()
        .map(|(fixed, pixel)| {
            let t: Vec<f64> = g
                .rays
                .iter()
                .filter_map(|&n| compare::paired_rmse(data.results, scene, pixel, fixed, n))
                .filter(|p| p.n >= 2)
                .map(|p| p.in_se())
                .collect();
            let pairs = g.replicates as usize;
            let same = format!(
                "{} against {}: their expected MSE is identical by construction (each pixel's point set, an \
                 index offset of the same set, has the same distribution under both seeds), so equal RMSE at \
                 equal rays is an identity, not a finding (paired t {} over {} ray counts, significant beyond \
                 ±{:.2}).",
                row_label(fixed),
                row_label(pixel),
                t_range(&t),
                t.len(),
                critical_se(pairs)
            );
            let cost = match pooled_time_ratio(&data.aggs, scene, pixel, fixed, &g.rays) {
                Some(p) => format!(
                    " What differs is cost: pooled over {} ray counts (mean of the log time ratios), the static \
                     seed's median total render time is ×{:.3} the per-pixel seed's (×{} at single ray counts; \
                     standard error {:.1} %, t {:+.1} at {} degrees of freedom, p {:.1e}){}.",
                    p.n,
                    p.ratio,
                    range([p.min, p.max], |x| format!("{x:.2}")),
                    100.0 * p.se_log,
                    p.t,
                    p.n - 1,
                    p.p,
                    if p.p <= ALPHA {
                        ": resolved pooled, where one ray count's time is within its spread"
                    } else {
                        ": not significant at 1 % even pooled"
                    }
                ),
                None => String::new(),
            };
            capitalized(&same) + &cost
        })
        .collect()
}

/// "from −2.4 to +1.5", or one value.
fn t_range(t: &[f64]) -> String {
    let lo = t.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = t.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    match t.len() {
        0 => "–".into(),
        _ if format!("{lo:+.1}") == format!("{hi:+.1}") => format!("{lo:+.1}"),
        _ => format!("from {lo:+.1} to {hi:+.1}"),
    }
}

/// The AO-time view in one sentence.
fn ao_view(ao: &EqualTime) -> String {
    if ao.at.is_empty() {
        return "By AO time (render time less the per-image overhead) the configurations share no measured \
                time, so there is no second view."
            .into();
    }
    let wins = winners(ao);
    let Some((w, ats)) = wins.first() else {
        return "By AO time (render time less the per-image overhead) every configuration measured has \
                structured error."
            .into();
    };
    format!(
        "By AO time instead (render time less the per-image overhead, the second view: at low ray counts the \
         overhead is most of a render and subtracting it magnifies time ratios), the answer is {} at {} of {} \
         budgets{} (table below).",
        row_label(*w),
        ats.len(),
        ao.at.len(),
        other_winners(&wins)
    )
}

/// How the answer is found, for the folded method text.
pub fn method() -> String {
    format!(
        "How configurations are compared. At equal time, not at equal rays: each configuration's measured \
         points (median total render time per image, mean MSE over replicates) are joined by straight lines \
         in log time and log MSE, so at a time budget between two of its ray counts it has the MSE that line \
         gives (advise's interpolation); outside its measured times it is not measured there, never \
         extrapolated. The budgets are spaced a factor 2 apart over the times every configuration of the \
         sweep was measured at. A ratio's ± is 1 σ: the replicates' spread of the MSE at the two \
         neighbouring points, interpolated replicate by replicate and paired across configurations \
         (replicate r has the same seed in every configuration), and each time's spread moving the budget \
         along the line; a margin in SE is ln(ratio) over that error. Total render time is the default \
         because it is what a renderer pays and what advise ranks by; AO time is the second view. \
         Efficiency, 1 / (MSE · AO time), stays as a column: it orders two configurations as their MSE at \
         equal time only where MSE ∝ 1/time, and the lattice's MSE falls faster (a 13 % time penalty is a \
         29–36 % MSE penalty at equal time, which efficiency reports as 13 %). The answer follows advise's \
         rule: the least MSE among estimators whose error is not structured (mean low-frequency ratio at \
         most {STRUCTURED_RATIO}); a structured one is named as rejected, never as the answer. All equal-time numbers \
         are in equal_time.csv."
    )
}
