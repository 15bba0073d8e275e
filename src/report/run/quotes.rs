//! `quotes.md`: the numbers of a run that the README quotes, as named blocks, made from nothing but
//! the spec, the records and the session's timing — so that a test can rebuild them from the
//! committed outputs and hold the README against them, and a number typed by hand cannot go stale
//! (one did: a headline stayed "8 of 11 ray counts" after the code it measured got faster).
//!
//! A block is `<!-- quote NAME -->`, its Markdown, `<!-- /quote -->`; NAME is `<spec>/<what>`. The
//! README holds copies of some blocks; `examples/readme_quotes.rs` copies them in after a rerun.

use super::data::{banding_stat, has_single_frames, row_label};
use crate::compare::claims::{COSINE_FIB_PIXEL, fmt_se};
use crate::compare::equal_time::{Ratio, TimeView, equal_time};
use crate::results::{self, JobResult, Stat};
use crate::sampling::{Distribution, Sequence};
use crate::spec::Row;
use crate::spec::{Group, GroupKind, Spec};
use std::fmt::Write as _;

/// The opening and closing lines of a quoted block.
pub fn open(name: &str) -> String {
    format!("<!-- quote {name} -->")
}
pub const CLOSE: &str = "<!-- /quote -->";

/// What the session did, as `timing.json`'s `session` records it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cost {
    pub jobs: usize,
    pub timed_renders: usize,
    pub cpu_s: f64,
    pub wall_s: f64,
}

impl Cost {
    /// From `timing.json`'s session record, for `jobs` records.
    pub fn of(s: &crate::timing::SessionRecord, jobs: usize) -> Self {
        Self { jobs, timed_renders: s.timed_renders, cpu_s: s.timed_cpu_s, wall_s: s.wall_s }
    }
}

/// Every block of a run, in spec order: one per `[[table]]` and `[[convergence]]` group and scene,
/// a real-time spec's verdicts (`realtime::summary_table`, its two questions, their sentences), and
/// the run's cost.
pub fn quotes(spec: &Spec, records: &[JobResult], cost: Option<Cost>) -> String {
    let aggs = results::aggregate(records);
    let mut s = String::new();
    let mut block = |name: String, body: String| {
        let _ = write!(s, "{}\n{}{CLOSE}\n\n", open(&name), body);
    };
    for g in &spec.groups {
        for &si in &g.scenes {
            let scene = &spec.scenes[si].name;
            let name = if g.scenes.len() > 1 {
                format!("{}/{}/{scene}", spec.name, g.name)
            } else {
                format!("{}/{}", spec.name, g.name)
            };
            match g.kind {
                GroupKind::Table if has_single_frames(g) => block(name, rmse_table(g, scene, &aggs, records)),
                GroupKind::Table => {}
                GroupKind::Convergence => {
                    block(name.clone(), slopes(spec, g, scene, &aggs));
                    block(format!("{name}/times"), times(g, scene, &aggs));
                    if let Some(t) = times_vs_lattice(g, scene, &aggs) {
                        block(format!("{name}/times-vs-lattice"), t);
                    }
                    if let Some(t) = equal_time_vs_lattice(g, scene, records) {
                        block(format!("{name}/equal-time"), t);
                    }
                }
            }
        }
    }
    // A real-time spec's verdicts (`realtime`): the short table, both full tables, the sentences.
    let rt = [
        ("realtime-summary", super::realtime::summary_table(records)),
        ("realtime-paper", super::realtime::paper_table(records)),
        ("realtime-stbn", super::realtime::stbn_table(records)),
        ("realtime-stbn-summary", super::realtime::stbn_summary_table(records)),
        ("realtime-paper-compact", super::realtime::paper_compact_table(records)),
        ("realtime-stbn-compact", super::realtime::stbn_compact_table(records)),
        ("realtime-seeds", super::realtime::seeds_table(records)),
        ("realtime-engine", super::realtime::engine_table(records)),
    ];
    for (what, t) in rt {
        if let Some(t) = t {
            block(format!("{}/{what}", spec.name), crate::report::markdown_table(&t));
        }
    }
    let said = super::realtime::text(records);
    if !said.is_empty() {
        block(format!("{}/realtime-verdicts", spec.name), said.iter().map(|l| format!("{l}\n")).collect());
    }
    let integrands = super::integrands::markdown(records);
    if !integrands.is_empty() {
        block(format!("{}/verdicts", spec.name), integrands);
    }
    if let Some(c) = cost {
        block(
            format!("{}/cost", spec.name),
            format!(
                "{} jobs, {} timed renders: {:.1} s of render CPU time in {:.1} s of wall time.\n",
                c.jobs, c.timed_renders, c.cpu_s, c.wall_s
            ),
        );
    }
    s
}

/// The group's shipped (`Sequence::shipped`) sine-cosine rows, if it has one of them and the
/// lattice with a per-pixel seed to hold them against.
fn shipped_beside_lattice(g: &Group) -> Option<Vec<Row>> {
    let others: Vec<Row> = g
        .rows
        .iter()
        .copied()
        .filter(|r| Sequence::shipped().contains(&r.sequence) && r.distribution == Distribution::SineCosine)
        .collect();
    (g.rows.contains(&COSINE_FIB_PIXEL) && !others.is_empty()).then_some(others)
}

/// Each of the group's shipped (`Sequence::shipped`) rows against the lattice with a per-pixel seed at equal time
/// (`compare::equal_time`, total render time, one budget to each doubling of time): its MSE over
/// the lattice's, ± 1 σ, and ln of that ratio in its standard errors (positive: the lattice has
/// less error). `None` unless the group has the lattice and one of them.
fn equal_time_vs_lattice(g: &Group, scene: &str, records: &[JobResult]) -> Option<String> {
    let lattice = COSINE_FIB_PIXEL;
    let others = shipped_beside_lattice(g)?;
    let mut rows = vec![lattice];
    rows.extend(&others);
    let et = equal_time(records, scene, &rows, &g.rays, TimeView::Total, 1);
    let mut s = format!("| MSE over {}'s at equal time | ", row_label(lattice));
    for at in &et.at {
        let _ = write!(s, "{} ms | ", fixed(at.budget_s * 1e3, 1));
    }
    s = s.trim_end().to_string();
    s.push_str("\n|---|");
    s.push_str(&"---|".repeat(et.at.len()));
    s.push('\n');
    for &row in &others {
        let _ = write!(s, "| {} |", row_label(row));
        for at in &et.at {
            match (at.entry(row), at.entry(lattice)) {
                (Some(a), Some(b)) => {
                    let r = Ratio::of(&a.at, &b.at);
                    let _ = write!(s, " × {:.2} ± {:.2} ({}) |", r.value, r.se, fmt_se(r.in_se()));
                }
                _ => s.push_str(" – |"),
            }
        }
        s.push('\n');
    }
    Some(s)
}

/// `x` to `digits` decimals, without a minus sign on a value that rounds to zero.
fn fixed(x: f64, digits: usize) -> String {
    let t = format!("{x:.digits$}");
    if t.trim_start_matches('-').chars().all(|c| c == '0' || c == '.') {
        t.trim_start_matches('-').into()
    } else {
        t
    }
}

fn pm(s: Stat) -> String {
    if s.mean.is_finite() { format!("{:.4} ± {:.4}", s.mean, s.sd) } else { "–".into() }
}

/// RMSE mean ± sd over the replicates, with ρ (the lag-1 error autocorrelation) where it is above
/// noise, at every ray count of the table.
fn rmse_table(g: &Group, scene: &str, aggs: &[results::Aggregate], records: &[JobResult]) -> String {
    let mut s = String::from("| configuration |");
    for n in &g.rays {
        let _ = write!(s, " {n} rays |");
    }
    s.push_str("\n|---|");
    s.push_str(&"---|".repeat(g.rays.len()));
    s.push('\n');
    for &row in &g.rows {
        let _ = write!(s, "| {} |", row_label(row));
        for &n in &g.rays {
            let cell = results::lookup(aggs, scene, row, n).map_or("–".into(), |a| {
                let rho = banding_stat(records, scene, row, n).map_or(f64::NAN, |b| b.0);
                format!("{} (ρ {})", pm(a.rmse), fixed(rho, 2))
            });
            let _ = write!(s, " {cell} |");
        }
        s.push('\n');
    }
    s
}

/// Each row's slope of log RMSE against log rays, with its 95 % interval, over the sweep's rays.
fn slopes(spec: &Spec, g: &Group, scene: &str, aggs: &[results::Aggregate]) -> String {
    let mut s = String::from(
        "| configuration | RMSE ∝ rays^slope, 95 % interval | against render time |\n|---|---|---|\n",
    );
    let sweep = results::sweep_slopes(spec, aggs);
    let fits =
        sweep.iter().filter(|w| w.group == g.name).flat_map(|w| &w.slopes).filter(|f| f.scene == scene);
    for f in fits {
        let label = crate::compare::row_of_names(&f.distribution, &f.sequence, &f.seed_mode)
            .map_or_else(|| format!("{}, {}, {}", f.distribution, f.sequence, f.seed_mode), row_label);
        let text = |v: Option<results::SlopeFit>| v.map_or("–".into(), |k| k.text());
        let _ = writeln!(s, "| {label} | {} | {} |", text(f.vs_rays), text(f.vs_time));
    }
    s
}

/// Each row's median render time in ms (thread CPU time, every timed render of the configuration)
/// at up to six of the sweep's ray counts (every other one of a longer sweep, and its last), and
/// each row's time relative to the first row's.
fn times(g: &Group, scene: &str, aggs: &[results::Aggregate]) -> String {
    let rays = quoted_rays(g);
    let ms = |row, n| median_ms(aggs, scene, row, n);
    let mut s = String::from("| configuration, median ms per render (× the first row's) |");
    for n in &rays {
        let _ = write!(s, " {n} rays |");
    }
    s.push_str("\n|---|");
    s.push_str(&"---|".repeat(rays.len()));
    s.push('\n');
    let first = g.rows.first().copied();
    for &row in &g.rows {
        let _ = write!(s, "| {} |", row_label(row));
        for &n in &rays {
            let cell = match (ms(row, n), first.and_then(|f| ms(f, n))) {
                (Some(t), Some(f)) => format!("{t:.2} (× {:.2})", t / f),
                _ => "–".into(),
            };
            let _ = write!(s, " {cell} |");
        }
        s.push('\n');
    }
    s
}

/// Up to six of the sweep's ray counts: every other one of a longer sweep, and its last.
fn quoted_rays(g: &Group) -> Vec<u32> {
    let mut rays: Vec<u32> =
        if g.rays.len() > 6 { g.rays.iter().step_by(2).copied().collect() } else { g.rays.clone() };
    if let Some(&last) = g.rays.last()
        && !rays.contains(&last)
    {
        rays.push(last);
    }
    rays
}

/// A row's median render time in ms at `rays` (thread CPU time, every timed render).
fn median_ms(aggs: &[results::Aggregate], scene: &str, row: Row, rays: u32) -> Option<f64> {
    results::lookup(aggs, scene, row, rays).and_then(|a| a.time).map(|t| t.median * 1e3)
}

/// Each shipped sampler's (`Sequence::shipped`, sine-cosine) median render time over the lattice's
/// with a per-pixel seed, at `times`' ray counts: what a sampler costs to render with, beside the
/// paper's configuration. `None` unless the group has the lattice and one of them.
fn times_vs_lattice(g: &Group, scene: &str, aggs: &[results::Aggregate]) -> Option<String> {
    let lattice = COSINE_FIB_PIXEL;
    let others = shipped_beside_lattice(g)?;
    let rays = quoted_rays(g);
    let mut s = format!("| configuration, render time × {}'s |", row_label(lattice));
    for n in &rays {
        let _ = write!(s, " {n} rays |");
    }
    s.push_str("\n|---|");
    s.push_str(&"---|".repeat(rays.len()));
    s.push('\n');
    for row in others {
        let _ = write!(s, "| {} |", row_label(row));
        for &n in &rays {
            let cell = match (median_ms(aggs, scene, row, n), median_ms(aggs, scene, lattice, n)) {
                (Some(t), Some(l)) => format!("× {:.2}", t / l),
                _ => "–".into(),
            };
            let _ = write!(s, " {cell} |");
        }
        s.push('\n');
    }
    Some(s)
}

/// The blocks of a quotes file (or a README), by name, each as its full text from the opening to
/// the closing line.
pub fn blocks(text: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(i) = rest.find("<!-- quote ") {
        let after = &rest[i + "<!-- quote ".len()..];
        let Some(end_name) = after.find(" -->") else { break };
        let name = after[..end_name].to_string();
        let Some(close) = rest[i..].find(CLOSE) else { break };
        out.push((name, rest[i..i + close + CLOSE.len()].to_string()));
        rest = &rest[i + close + CLOSE.len()..];
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blocks_are_found_by_name_with_their_text() {
        let t =
            "a\n<!-- quote p/t2 -->\n| x |\n<!-- /quote -->\nb <!-- quote p/cost -->\n1 job\n<!-- /quote -->";
        let b = blocks(t);
        assert_eq!(b.len(), 2);
        assert_eq!(b[0].0, "p/t2");
        assert_eq!(b[0].1, "<!-- quote p/t2 -->\n| x |\n<!-- /quote -->");
        assert_eq!(b[1].0, "p/cost");
    }
}
