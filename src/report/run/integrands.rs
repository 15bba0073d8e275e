//! The integrand verdicts as the page's and `quotes.md`'s tables: the paper's three statements
//! about which distribution suits which integrand, the infinite-variance cells and the lattice's
//! gain per integrand. The numbers are `compare::integrands`'; this file words and formats them.

use crate::compare::integrands::{Cell, RAYS, Verdicts, verdicts};
use crate::report::Table;
use crate::results::JobResult;
use std::fmt::Write as _;

fn cell(c: &Option<Cell>) -> String {
    match c {
        Some(c) => format!("{:+.1} SE ({:.4} vs {:.4})", c.margin.in_se(), c.better, c.worse),
        None => "–".into(),
    }
}

/// The three tables (verdicts, infinite cells, Fibonacci gain) as rows of text; empty when the run
/// measured a single integrand.
fn rows(results: &[JobResult]) -> Vec<(String, Vec<String>, Vec<Vec<String>>)> {
    let Some(Verdicts { scenes, statements, infinite, gains }) = verdicts(results) else { return Vec::new() };
    let mut header = vec!["the paper's statement".to_string(), "closed-form theory".to_string()];
    header.extend(scenes.iter().map(|s| format!("{s}: margin, RMSE at {RAYS} rays")));
    let verdicts = statements
        .iter()
        .map(|j| {
            let st = &j.statement;
            let mut row = vec![
                format!("{} — {}: {} < {}", st.paper, st.integrand, st.better, st.worse),
                format!("per-ray variance {:.3} < {:.3}", j.theory.0, j.theory.1),
            ];
            row.extend(j.cells.iter().map(cell));
            row
        })
        .collect();
    let infinite: Vec<Vec<String>> = infinite
        .iter()
        .map(|c| {
            let mut row =
                vec![format!("{} on {} (weight unbounded: not ranked)", c.distribution, c.integrand)];
            let f = |k: Option<f64>| k.map_or("–".into(), |k| format!("{k:+.2}"));
            row.extend(c.slopes.iter().map(|&(d, m)| format!("{} (matched {}: {})", f(d), c.matched, f(m))));
            row
        })
        .collect();
    let gains = gains
        .iter()
        .map(|g| {
            let mut row = vec![format!("{} ({})", g.integrand, g.matched)];
            row.extend(g.gains.iter().map(|x| x.map_or("–".into(), |x| format!("× {x:.2}"))));
            row
        })
        .collect();
    let scene_cols = |first: &str| {
        let mut h = vec![first.to_string()];
        h.extend(scenes.iter().cloned());
        h
    };
    let mut out = vec![(
        "Integrands: the paper's statements, theory and measured margins".to_string(),
        header,
        verdicts,
    )];
    if !infinite.is_empty() {
        out.push((
            "Integrands: infinite-variance cells, fitted slope of RMSE against rays (−0.5 for finite variance)".into(),
            scene_cols("cell"),
            infinite,
        ));
    }
    out.push((
        format!("Integrands: the Fibonacci lattice's gain, RMSE pseudo-random / Fibonacci per-pixel seed at {RAYS} rays"),
        scene_cols("integrand (matched distribution)"),
        gains,
    ));
    out
}

/// The report's tables (none for a run of one integrand).
pub fn tables(results: &[JobResult]) -> Vec<Table> {
    rows(results).into_iter().map(|(title, header, rows)| Table { title, header, rows }).collect()
}

/// The same tables in Markdown, for `quotes.md` (empty for a run of one integrand).
pub fn markdown(results: &[JobResult]) -> String {
    let mut s = String::new();
    for (title, header, rows) in rows(results) {
        let _ = writeln!(s, "{title}:\n");
        let _ = writeln!(s, "| {} |", header.join(" | "));
        let _ = writeln!(s, "|{}", "---|".repeat(header.len()));
        for r in rows {
            let _ = writeln!(s, "| {} |", r.join(" | "));
        }
        s.push('\n');
    }
    s
}
