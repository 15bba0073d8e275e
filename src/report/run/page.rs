//! `report.md` and `index.html`: one offline page that leads with the answer — one paragraph of
//! at most three sentences per sweep (`answer.rs`), then the key figure (MSE at equal time), the
//! equal-time table (with several scenes, the verdict on each claim per scene, `verdicts.rs`,
//! beside it) and the findings — with the method (how configurations are compared, what a time
//! is) folded after them; then the numbers (equal time, efficiency, references, each table's RMSE,
//! convergence slopes and costs) and every other figure `figures.rs` wrote, linked by relative
//! paths; the long tables (verdict margins, every aggregate) folded at the end.

use crate::metrics::whiteness::STRUCTURED_Z;
use crate::metrics::{LOWPASS_SIGMA, STRUCTURED_RATIO};
use crate::outdir::{self, File};
use crate::report::run::answer;
use crate::report::run::data::{
    ReportInput, agg_label, banding_stat, has_single_frames, row_label, sweep_slope,
};
use crate::report::run::figures::Figures;
use crate::report::{self, Table};
use crate::results::{self, SlopeFit, Stat};
use crate::spec::{GroupKind, Row};
use crate::timing;

/// The page (`report.md`, then `index.html`) and `equal_time.csv` before it, added to `files`.
pub fn page(data: &ReportInput, figures: &Figures, viewer: &str, files: &mut Vec<File>) {
    let spec = &data.loaded.spec;
    let answer = answer::answer(data);
    let (mut lead, mut tables, mut collapsed) = (Vec::new(), Vec::new(), Vec::new());
    // With several scenes the verdict per scene and claim comes right after the answer and its
    // figure (the per-scene tables that follow are long), and the per-scene tables, which would
    // push the figures down, are folded after them. With one scene it follows the answer's tables.
    let many = spec.scenes.len() > 1;
    let verdicts = super::verdicts::tables(data);
    let mut answer_tables = answer.tables.into_iter();
    // The first sweep's equal-time table (total render time) leads: the answer's numbers.
    lead.extend(answer_tables.next());
    if let Some((summary, details)) = verdicts {
        if many {
            lead.push(summary)
        } else {
            tables.push(summary)
        }
        collapsed.push(details);
    }
    tables.extend(answer_tables);
    // The real-time verdicts lead: a real-time spec is run for them.
    lead.extend(super::realtime::summary_table(data.results));
    lead.extend(super::realtime::stbn_summary_table(data.results));
    lead.extend(super::realtime::paper_table(data.results));
    lead.extend(super::realtime::stbn_table(data.results));
    lead.extend(super::realtime::seeds_table(data.results));
    lead.extend(super::realtime::engine_table(data.results));
    // The integrand verdicts lead: a spec with several integrands is run for them.
    lead.extend(super::integrands::tables(data.results));
    tables.push(reference_table(data));
    for g in spec.groups.iter().filter(|g| g.kind == GroupKind::Table && has_single_frames(g)) {
        for &si in &g.scenes {
            let t = rmse_table(data, &g.name, &spec.scenes[si].name, &g.rows, &g.rays, g.replicates);
            if many { collapsed.push(t) } else { tables.push(t) }
        }
    }
    let slopes = slope_table(data);
    if !slopes.rows.is_empty() {
        if many { collapsed.push(slopes) } else { tables.push(slopes) }
    }
    collapsed.push(aggregate_table(data));
    files.push(File::new(outdir::EQUAL_TIME_CSV, super::equal_time::csv(&answer.equal_time)));
    let title = format!("hemilab: {}", spec.name);
    let mut findings = answer.findings;
    findings.extend(super::verdicts::family_text(data));
    findings.extend(super::realtime::text(data.results));
    let mut method = vec![answer::method(), timing_text(data)];
    method.extend(data.notes.iter().cloned());
    method.push(format!(
        "Spec {} ({} jobs). Every number is measured against the reference of its scene over the \
         pixels that see a surface; mean ± sd over independent replicates (different seeds; replicate r \
         has the same seed in every configuration, so differences are paired). ρ is the lag-1 \
         autocorrelation of the error image (horizontal / vertical): near 0 for independent per-pixel \
         noise, near 1 for banding. Lowpass RMSE is the RMSE after a Gaussian blur (σ = {LOWPASS_SIGMA} \
         px) of the error: noise averages out under it, bands do not. R, the low-frequency ratio, is \
         the error's energy after that blur over the energy independent per-pixel errors of the same \
         sizes would keep: 1 for white noise at any image size, below 1 for blue noise (neighbouring \
         errors cancel, so a blur or the eye removes them), above 1 when they add up. An error is \
         called structured when its mean R is above {STRUCTURED_RATIO} (per-pixel seeds read 1.00 ± \
         0.10 on every committed scene, the static seed 1.7 to 19). The whiteness z-score tests the \
         error image against white noise over every lag up to 4 pixels in every direction (a 2-D \
         Ljung–Box statistic): about 0 ± 1 for independent per-pixel noise, above {STRUCTURED_Z} for \
         any significant correlation, blue noise's negative one included — a test, which grows with \
         the pixel count, not a measure of how much structure there is. Slopes carry 95 % confidence \
         intervals. A claim that fails on a scene is a result, not a bug: the verdict table says where \
         the paper's findings carry over and where they do not.",
        spec.path.display(),
        data.results.len()
    ));
    method.push(format!(
        "Raw numbers: results.csv, results.json (one record per image), aggregates.csv, slopes.json, \
         timing.json, {}.",
        outdir::EQUAL_TIME_CSV
    ));
    let (answer_text, findings, method) =
        (answer.lead.join("\n\n"), findings.join("\n\n"), method.join("\n\n"));
    let page = report::Page {
        title: &title,
        lead: &lead,
        intro: &findings,
        tables: &tables,
        interactive: viewer,
        figures: &figures.other,
        collapsed: &collapsed,
    };
    let opening = report::Opening { answer: &answer_text, figures: &figures.key, method: &method };
    files.push(File::new(outdir::REPORT_MD, report::markdown_page_opened(&page, &opening)));
    files.push(File::new(outdir::INDEX_HTML, report::html_page_opened(&page, &opening)));
}

/// What a time is and how it was measured.
fn timing_text(data: &ReportInput) -> String {
    let p = &data.protocol;
    let overhead: Vec<String> = data
        .loaded
        .spec
        .scenes
        .iter()
        .zip(&data.overhead)
        .filter_map(|(s, o)| {
            let o = o.as_ref()?;
            Some(format!(
                "'{}' {:.2} ms [{:.2}–{:.2}] over {} renders",
                s.name,
                o.median * 1e3,
                o.min * 1e3,
                o.max * 1e3,
                o.n
            ))
        })
        .collect();
    let overhead =
        if overhead.is_empty() { "not measured in this session".into() } else { overhead.join(", ") };
    format!(
        "Timing. A time is {}, read from the {}. Every configuration was rendered at least {} times (its \
         replicates, re-rendered for timing where fewer) in passes: each pass renders every configuration \
         once, in a seeded random order (seed {}), so drift of the machine lands on all configurations \
         alike. A second round, interleaved the same way, rendered again every configuration whose \
         renders added up to less than {} s, up to {} renders in all (cheap renders are timed more \
         often). {} worker(s) rendered side by side, each on {} thread, after {:.1} s of untimed warm-up \
         per scene. Times are the median over those renders, with min and max; the spread of a time is half \
         the width of its median's distribution-free 95 % interval (order statistics; min..max when there \
         are too few renders for 95 %), combined with a run-to-run scatter of {:.0} % of the median that one \
         run cannot see (measured between runs of the paper experiment; README, Timing). The per-image overhead \
         (primary rays and setup: an image with no AO rays) is {overhead}; AO time = median time − \
         overhead, the marginal cost of a ray = AO time / AO rays, and efficiency = 1 / (MSE · AO time) \
         in 1/s, which the overhead cannot dominate. The machine may be shared with other work: thread \
         CPU time does not count the time another process held the core (wall times are in \
         results.csv, wall_s).",
        timing::TIME_INCLUDES,
        timing::clock::NAME,
        p.repeats,
        p.seed,
        p.min_total_s,
        p.max_repeats,
        p.workers,
        p.threads_per_render,
        p.warmup_s,
        100.0 * timing::RUN_TO_RUN
    )
}

fn pm(s: Stat, digits: usize) -> String {
    if s.mean.is_finite() { format!("{:.digits$} ± {:.digits$}", s.mean, s.sd) } else { "–".into() }
}

fn reference_table(data: &ReportInput) -> Table {
    let header =
        ["scene", "size", "estimator", "replicates × rays", "noise floor", "smallest RMSE", "floor / RMSE"];
    let rows = data
        .references
        .iter()
        .enumerate()
        .map(|(si, r)| {
            let name = &data.loaded.spec.scenes[si].name;
            let smallest = data
                .aggs
                .iter()
                .filter(|a| &a.scene == name)
                .map(|a| a.rmse.mean)
                .fold(f64::INFINITY, f64::min);
            let floor = r.noise_floor();
            let m = &r.manifest;
            vec![
                name.clone(),
                format!("{}x{}", r.mean.width, r.mean.height),
                row_label(data.loaded.spec.reference.estimator),
                match &m.adaptive {
                    Some(a) => {
                        let pixels = crate::reference::noise_floor_pixels(&r.coverage).max(1) as f64;
                        let mean = a.total_rays.unwrap_or(0) as f64 / pixels;
                        format!(
                            "{} × adaptive, mean {mean:.0} (pilot {} × {})",
                            m.replicates, m.replicates, m.rays
                        )
                    }
                    None => format!("{} × {}", m.replicates, m.rays),
                },
                format!("{floor:.2e}"),
                format!("{smallest:.2e}"),
                format!("{:.3}", floor / smallest),
            ]
        })
        .collect();
    Table { title: "References".into(), header: header.map(String::from).to_vec(), rows }
}

fn rmse_table(data: &ReportInput, name: &str, scene: &str, rows: &[Row], rays: &[u32], reps: u32) -> Table {
    let mut header = vec!["configuration".to_string()];
    header.extend(rays.iter().map(|r| format!("{r} rays")));
    let rows = rows
        .iter()
        .map(|&row| {
            let mut cells = vec![row_label(row)];
            for &n in rays {
                cells.push(match results::lookup(&data.aggs, scene, row, n) {
                    Some(a) => {
                        let b = banding_stat(data.results, scene, row, n).map_or(f64::NAN, |b| b.0);
                        format!(
                            "{}  (ρ {b:+.2}, R {:.2}, z {:.1}, lowpass {:.4})",
                            pm(a.rmse, 4),
                            a.lowfreq_ratio.mean,
                            a.whiteness_z.mean,
                            a.lowpass_rmse.mean
                        )
                    }
                    None => "–".into(),
                });
            }
            cells
        })
        .collect();
    let title = format!(
        "{name} ('{scene}'): RMSE, mean ± sd over {reps} replicates (ρ: lag-1 autocorrelation; R: \
         low-frequency ratio, 1 = noise, < 1 = blue, > {STRUCTURED_RATIO} = structured; z: whiteness \
         z-score, a test; lowpass: RMSE of the blurred error)"
    );
    Table { title, header, rows }
}

fn slope_table(data: &ReportInput) -> Table {
    let header = [
        "sweep",
        "scene",
        "configuration",
        "ray counts",
        "slope vs rays",
        "slope vs AO time",
        "slope vs render time",
        "ns per AO ray (fit)",
        "overhead (fit, ms)",
    ];
    let f = |v: Option<SlopeFit>| v.map_or("–".into(), |k| k.text());
    let interval = |v: f64, i: Option<(f64, f64)>, scale: f64, d: usize| match i {
        Some((a, b)) => format!("{:.d$} [{:.d$}, {:.d$}]", v * scale, a * scale, b * scale),
        None if v.is_finite() => format!("{:.d$}", v * scale),
        None => "–".into(),
    };
    let mut rows = Vec::new();
    for (g, _, scene) in data.sweeps() {
        for &row in &g.rows {
            let Some(s) = sweep_slope(data, g, scene, row) else { continue };
            let (ns, over) = match s.cost {
                Some(c) => (
                    interval(c.ns_per_ray, c.ns_per_ray_interval, 1.0, 1),
                    interval(c.overhead_s, c.overhead_interval, 1e3, 2),
                ),
                None => ("–".into(), "–".into()),
            };
            rows.push(vec![
                g.name.clone(),
                scene.to_string(),
                row_label(row),
                s.points.to_string(),
                f(s.vs_rays),
                f(s.vs_ao_time),
                f(s.vs_time),
                ns,
                over,
            ]);
        }
    }
    Table {
        title:
            "Convergence: least-squares slope of log RMSE with its 95 % interval (−0.5 = plain Monte Carlo), \
                against rays, AO time (render time minus the overhead) and render time; and the fit \
                time = overhead + cost · AO rays through the median times"
                .into(),
        header: header.map(String::from).to_vec(),
        rows,
    }
}

fn aggregate_table(data: &ReportInput) -> Table {
    let header = [
        "scene",
        "configuration",
        "rays",
        "replicates",
        "RMSE",
        "bias",
        "ρ x",
        "ρ y",
        "lowpass RMSE",
        "whiteness z",
        "low-freq ratio",
        "time (ms): median [min–max], n",
        "AO time (ms)",
        "ns per AO ray",
        "efficiency (1/(MSE·s))",
    ];
    let rows = data
        .aggs
        .iter()
        .map(|a| {
            let time = a.time.map_or("–".into(), |t| {
                format!("{:.2} [{:.2}–{:.2}], {}", t.median * 1e3, t.min * 1e3, t.max * 1e3, t.n)
            });
            let num = |v: f64, s: String| if v.is_finite() { s } else { "–".into() };
            vec![
                a.scene.clone(),
                agg_label(a),
                a.rays.to_string(),
                a.replicates.to_string(),
                pm(a.rmse, 4),
                pm(a.bias, 4),
                pm(a.autocorr_x, 2),
                pm(a.autocorr_y, 2),
                pm(a.lowpass_rmse, 4),
                pm(a.whiteness_z, 1),
                pm(a.lowfreq_ratio, 2),
                time,
                num(a.ao_time_s, format!("{:.2}", a.ao_time_s * 1e3)),
                num(a.ns_per_ray, format!("{:.1}", a.ns_per_ray)),
                num(a.efficiency, format!("{:.3e} ± {:.1e}", a.efficiency, a.efficiency_spread)),
            ]
        })
        .collect();
    Table {
        title: "All configurations (mean ± sd over replicates; times over every timed render)".into(),
        header: header.map(String::from).to_vec(),
        rows,
    }
}
