//! advice.md and index.html from advise's analysis (advice.json is `json`), and the lines
//! it prints: the answer per budget first, then what a time is, the rankings, and every measured point.

use super::maps::winner_note;
use super::text::{advice_line, default_at, label, ms, pm, shipped_rays, status};
use crate::advice::analysis::{Analysis, Measured, mean};
use crate::advice::{self, AtBudget, Metric, PAPER_DEFAULT, Ranking};
use crate::error::Result;
use crate::metrics::{LOWPASS_SIGMA, STRUCTURED_RATIO};
use crate::outdir;
use crate::report::{self, Figure, Table};
use crate::timing;
use std::fmt::Write as _;
use std::path::Path;

/// Rows of a budget's ranking table shown in the page (all are in advice.json).
const SHOWN: usize = 10;

pub fn write(m: &Measured, a: &Analysis, figures: &[Figure], out: &Path) -> Result<String> {
    let json = crate::report::advise::json::advice_json(m, a);
    let mut text = serde_json::to_string_pretty(&json).unwrap_or_default();
    text.push('\n');
    let lines: Vec<String> = a.rankings.iter().map(|(r, l)| advice_line(r, l)).collect();
    let [w, h] = m.setup.loaded.spec.resolution.unwrap_or([0, 0]);
    let title = format!("hemilab advise: {} at {w}x{h}", m.setup.stem);
    let mut intro = lines.clone();
    intro.push(time_text(m));
    intro.push(format!(
        "Configurations: {} (every distribution × sequence × seed mode that is a distinct, sensible \
         estimator, or the --only subset), each at {} rays per pixel, {} replicates (seeds; replicate r \
         has the same seed in every configuration, so comparisons are paired). At a budget each \
         configuration's RMSE is interpolated along its log-error against log-time line between the two \
         measured ray counts around it; a budget outside a configuration's measured times leaves it \
         unranked there (never extrapolated). ± are standard errors over the replicates; a gain is the \
         paper default's MSE over the configuration's at the same time, its ± also counting both \
         times' spread. {}. Reference noise floor {:.2e} ({}).",
        a.curves.len(),
        m.setup.rays.iter().map(u32::to_string).collect::<Vec<_>>().join(", "),
        m.setup.loaded.spec.replicates,
        m.setup.choice,
        m.reference.noise_floor(),
        m.reference.exr.display()
    ));
    intro.push(format!(
        "What is shipped is the best-ranked configuration whose error is not structured: its low-frequency \
         ratio — the error's energy after a Gaussian blur of σ = {LOWPASS_SIGMA} px over the energy \
         independent per-pixel errors of the same sizes would keep, mean over the replicates — at most \
         {STRUCTURED_RATIO}. 1 is white noise, below 1 blue noise (neighbouring errors cancel; shippable), \
         above {STRUCTURED_RATIO} blotches or bands that a blur or a denoiser keeps (a static seed reads \
         1.7 to 19 on the committed scenes). The whiteness z in advice.json tests for any correlation, \
         blue noise's negative one included, and is not used for this."
    ));
    if !a.maps.is_empty() {
        intro.push(winner_note(m, a));
    }
    intro.push(
        "Raw numbers: advice.json (every ranking), results.csv / results.json (one record per image).".into(),
    );
    let intro = intro.join("\n\n");
    let mut tables = vec![summary_table(a)];
    tables.extend(a.rankings.iter().filter(|(r, _)| !r.ranked.is_empty()).map(|(r, _)| ranking_table(r)));
    let collapsed = vec![ladder_table(a)];
    outdir::write_file(out, outdir::ADVICE_JSON, text.as_bytes())?;
    let page = report::Page {
        title: &title,
        lead: &[],
        intro: &intro,
        tables: &tables,
        figures,
        collapsed: &collapsed,
    };
    outdir::write_page(out, &report::html_page(&page), outdir::ADVICE_MD, &report::markdown_page(&page))?;
    let mut s = String::new();
    for l in &lines {
        let _ = writeln!(s, "{l}");
    }
    let floor = m.reference.noise_floor();
    let smallest =
        a.curves.iter().flat_map(|c| &c.points).map(|p| mean(&p.mse).sqrt()).fold(f64::INFINITY, f64::min);
    if smallest.is_finite() && floor > crate::reference::target_floor(smallest) {
        eprintln!(
            "warning: reference noise floor {floor:.2e} is above a tenth of the smallest RMSE measured \
             ({smallest:.2e}); errors near it are not resolved"
        );
    }
    let _ = writeln!(
        s,
        "timing: {} timed renders, {:.1} s of render CPU time in {:.1} s of wall time → {}",
        m.session.renders,
        m.session.cpu_s,
        m.session.wall_s,
        outdir::index(out).display()
    );
    Ok(s)
}

fn summary_table(a: &Analysis) -> Table {
    let rows = a
        .rankings
        .iter()
        .map(|(r, l)| {
            let b = ms(r.budget_s);
            let Some(best) = advice::recommended(r) else {
                return vec![b, status(r).into(), String::new(), String::new(), String::new(), String::new()];
            };
            let gain = default_at(r)
                .map_or("—".into(), |d| pm(advice::gain(d, best, Metric::Rmse).into_estimate(), 2));
            let low = l.ranked.first().map_or(String::new(), |x| {
                let g = default_at(l).map_or(String::new(), |d| {
                    format!(" (×{:.2})", advice::gain(d, x, Metric::Lowpass).value)
                });
                format!("{}{g}", label(x.row))
            });
            vec![
                b,
                label(best.row),
                shipped_rays(best).to_string(),
                pm(best.rmse(Metric::Rmse), 4),
                gain,
                low,
            ]
        })
        .collect();
    Table {
        title: "Advice per budget".into(),
        header: [
            "budget (ms)",
            "ship",
            "rays",
            "RMSE",
            "MSE gain vs paper default",
            "least low-pass RMSE (gain)",
        ]
        .map(String::from)
        .to_vec(),
        rows,
    }
}

trait IntoEstimate {
    fn into_estimate(self) -> advice::Estimate;
}

impl IntoEstimate for advice::Gain {
    fn into_estimate(self) -> advice::Estimate {
        advice::Estimate { value: self.value, se: self.se }
    }
}

fn ranking_table(r: &Ranking) -> Table {
    let mut shown: Vec<(usize, &AtBudget)> = r.ranked.iter().enumerate().take(SHOWN).collect();
    if let Some(i) = r.ranked.iter().position(|a| a.row == PAPER_DEFAULT).filter(|&i| i >= SHOWN) {
        shown.push((i, &r.ranked[i]));
    }
    let best = &r.ranked[0];
    let rows = shown
        .into_iter()
        .map(|(i, a)| {
            let gain = default_at(r)
                .map_or("—".into(), |d| pm(advice::gain(d, a, Metric::Rmse).into_estimate(), 2));
            let z = if i == 0 {
                String::new()
            } else {
                format!("{:+.1}", advice::paired_z(best, a, Metric::Rmse))
            };
            vec![
                (i + 1).to_string(),
                label(a.row),
                format!("{:.1}", a.rays),
                pm(a.rmse(Metric::Rmse), 4),
                pm(a.rmse(Metric::Lowpass), 4),
                ratio_cell(a.lowfreq_ratio),
                gain,
                z,
            ]
        })
        .collect();
    Table {
        title: format!(
            "At {} ms per image: {} configurations ranked by RMSE{}",
            ms(r.budget_s),
            r.ranked.len(),
            if r.outside.is_empty() {
                String::new()
            } else {
                format!(" ({} outside their measured times)", r.outside.len())
            }
        ),
        header: [
            "#",
            "configuration",
            "rays",
            "RMSE",
            "low-pass RMSE",
            "low-freq ratio",
            "MSE gain vs paper default",
            "paired z vs #1",
        ]
        .map(String::from)
        .to_vec(),
        rows,
    }
}

/// A mean low-frequency ratio, marked when it makes the configuration structured.
fn ratio_cell(r: f64) -> String {
    if r > STRUCTURED_RATIO { format!("{r:.2} (structured)") } else { format!("{r:.2}") }
}

fn ladder_table(a: &Analysis) -> Table {
    let mut rows = Vec::new();
    for c in &a.curves {
        for p in &c.points {
            let sd = |v: &[f64]| crate::metrics::mean_sd(&v.iter().map(|x| x.sqrt()).collect::<Vec<_>>());
            let (e, esd) = sd(&p.mse);
            let (l, lsd) = sd(&p.lowpass_mse);
            rows.push(vec![
                label(c.row),
                p.rays.to_string(),
                format!("{:.3} ± {:.3}", p.time_s * 1e3, p.time_spread_s * 1e3),
                format!("{e:.4} ± {esd:.4}"),
                format!("{l:.4} ± {lsd:.4}"),
                ratio_cell(mean(&p.lowfreq_ratio)),
            ]);
        }
    }
    Table {
        title: "Every measured point (time: median ± spread; errors: mean ± sd over replicates)".into(),
        header: ["configuration", "rays", "time per image (ms)", "RMSE", "low-pass RMSE", "low-freq ratio"]
            .map(String::from)
            .to_vec(),
        rows,
    }
}

/// What a time is, once.
fn time_text(m: &Measured) -> String {
    let [w, h] = m.setup.loaded.spec.resolution.unwrap_or([0, 0]);
    let p = &m.protocol;
    let overhead = m.session.overhead.first().copied().flatten().map_or(String::new(), |s| {
        format!(" An image with no AO rays takes {} ms (primary rays and per-image setup).", ms(s.median))
    });
    format!(
        "A budget is a time per image at {w}x{h}: the {} of one thread rendering the whole image ({}). \
         Each configuration and ray count is the median of at least {} timed renders, interleaved in seeded \
         passes across {} one-thread workers after a {} s warm-up; cheap ones are timed up to {} times. \
         A frame on your renderer and machine differs by a factor; the ranking at equal time is what carries over.{overhead}",
        timing::clock::NAME,
        timing::TIME_INCLUDES,
        p.repeats,
        p.workers,
        p.warmup_s,
        p.max_repeats
    )
}
