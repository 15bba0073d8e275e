//! advice.md and index.html from advise's analysis (advice.json is `json`), and the lines it
//! prints: the answer per budget first, then the error model and what a time is, the finalists
//! measured, the interpolated rankings, and every measured point.

use super::maps::winner_note;
use super::text::{advice_line, camera, candidate, label, model_text, ms, pm, ray_line, status};
use crate::advice::analysis::{Analysis, Measured};
use crate::advice::answer::{Answer, FINALISTS, RankScored};
use crate::compare::budget::{Metric, Ranking};
use crate::compare::per_ray::AtRays;
use crate::compare::{PAPER_DEFAULT, structure};
use crate::outdir::{self, File};
use crate::report::{self, Figure, Table};
use crate::timing;
use std::fmt::Write as _;
use std::path::Path;

/// Rows of a budget's ranking table shown in the page (all are in advice.json).
const SHOWN: usize = 10;

/// advice.json, advice.md and index.html, added to `files`; returns the lines to print, naming
/// `shown` (where the output set will be) as the page's place, and the warnings.
pub fn page(
    m: &Measured,
    a: &Analysis,
    (figures, images): (&[Figure], &(Vec<Figure>, String)),
    files: &mut Vec<File>,
    shown: &Path,
) -> (String, Vec<String>) {
    let json = crate::report::advise::json::advice_json(m, a);
    let mut text = serde_json::to_string_pretty(&json).unwrap_or_default();
    text.push('\n');
    let per = m.setup.per();
    let after = format!("after {} at frame {}", m.setup.pipeline, m.setup.frames);
    // The answer first: per ray budget after a real-time pipeline, then per ms budget.
    let mut lines: Vec<String> = a.per_ray.iter().map(|x| ray_line(x, a, &after)).collect();
    lines.extend(a.answers.iter().map(|x| advice_line(x, per)));
    let title = format!("hemilab advise: {} (budgets in ms per {per})", m.setup.title());
    // The answer first: its sentences, then the final frames of the top configurations.
    let mut answer = lines.clone();
    if m.setup.pipeline.is_temporal() {
        answer.push(crate::advice::REPEATING_ERROR.into());
    }
    let answer = answer.join("\n\n");
    let mut intro = Vec::new();
    if !a.per_ray.is_empty() {
        intro.push(format!(
            "After a real-time pipeline the budget is rays per pixel per frame, as an engine has it, and the \
             answer is given for each camera (the scene's still camera, and a moving one: a jittered path \
             through the scene's own view) at steady state: at each ray count every configuration — under \
             each per-frame schedule, independent and r1, where the schedule changes its points — is ranked \
             by its RMSE {after}, and the near-ties are those whose MSE is not behind the best's by a paired \
             margin significant at {} (two-sided Student's t over the replicates). The best by mean FLIP \
             (LDR-FLIP at {} pixels per degree) is named too when it is another. Beside each: its FLIP, its \
             flicker (the RMS of its frame-to-frame change against the reference's), the bias and noise parts \
             of its error (from its replicates: bias² + noise² is the mean MSE), one frame's CPU time here \
             (one thread, the whole image) and its sampler's own cost per point (points drawn and mapped, no \
             ray traced). Budgets in ms only with --budget-ms (then the still camera, independent schedule).",
            crate::compare::per_ray::ALPHA,
            crate::metrics::DEFAULT_PPD
        ));
    }
    intro.push(model_text());
    intro.push(time_text(m));
    intro.push(format!(
        "Configurations: {} (every distribution × sequence × seed mode that is a distinct, sensible estimator, \
         or the --only subset), swept at {} rays per pixel, {} replicates. At a budget each configuration's \
         RMSE is interpolated along its log-error against log-time line between the two measured ray counts \
         around it (a budget outside its measured times leaves it unranked there, never extrapolated). Then \
         each budget's finalists — the {FINALISTS} best by that interpolation, the best two unstructured, the \
         best by low-pass RMSE and the paper default — are rendered again, {} replicates each with seeds of \
         their own, timed together, at the interpolated count rounded down, the multiple of 32 below it \
         (rays are traced in packets of 32, so a render's time steps up there and the line under-predicts \
         it) and the sweep's count below the budget; each is shipped at the most of those that fit (its \
         measured time, put on the sweep's time scale, not above the budget by more than 2 σ of the \
         session factor). The answer is decided on those measurements: the least RMSE whose error is not \
         structured ({}). A gain is the paper default's MSE over the configuration's at the same budget. {}. Reference \
         noise floor {:.2e} ({}).",
        a.curves.len(),
        m.setup.rays.iter().map(u32::to_string).collect::<Vec<_>>().join(", "),
        m.setup.loaded.spec.replicates,
        m.replicates,
        structure::rule(),
        m.setup.choice,
        m.reference.noise_floor(),
        m.reference.exr.display()
    ));
    if let Some(dir) = &m.from {
        intro.push(format!(
            "Re-analysed from {} without rendering (advise --from): budgets whose finalists were not measured \
             there are answered from the sweep's interpolation, and say so.",
            dir.display()
        ));
    }
    if !a.maps.is_empty() {
        intro.push(winner_note(m));
    }
    intro.push(
        "Raw numbers: advice.json (every answer with each replicate's values, every ranking and point), \
         results.csv / results.json (one record per image: the sweep's and the finalists')."
            .into(),
    );
    let intro = intro.join("\n\n");
    let lead: Vec<Table> = a.per_ray.iter().map(|x| per_ray_table(x, a, &after)).collect();
    let mut tables: Vec<Table> = Vec::new();
    if !a.answers.is_empty() || a.per_ray.is_empty() {
        tables.push(summary_table(a));
    }
    tables.extend(a.answers.iter().filter(|x| !x.finalists.is_empty()).map(|x| finalists_table(x, per)));
    tables.extend(
        a.answers
            .iter()
            .filter(|x| !x.ranking.ranked.is_empty())
            .map(|x| ranking_table(&x.ranking, &x.ranking_scores, per)),
    );
    let collapsed = vec![ladder_table(a, per)];
    files.push(File::new(outdir::ADVICE_JSON, text));
    let page = report::Page {
        title: &title,
        lead: &lead,
        intro: &intro,
        interactive: &images.1,
        tables: &tables,
        figures,
        collapsed: &collapsed,
    };
    let opening = report::Opening { answer: &answer, figures: &images.0, method: "" };
    files.push(File::new(outdir::ADVICE_MD, report::markdown_page_opened(&page, &opening)));
    files.push(File::new(outdir::INDEX_HTML, report::html_page_opened(&page, &opening)));
    let mut s = String::new();
    for l in &lines {
        let _ = writeln!(s, "{l}");
    }
    let mut warnings = Vec::new();
    let floor = m.reference.noise_floor();
    let smallest = a
        .curves
        .iter()
        .flat_map(|c| &c.points)
        .map(|p| p.rmse(Metric::Rmse).value)
        .fold(f64::INFINITY, f64::min);
    if smallest.is_finite() && floor > crate::reference::target_floor(smallest) {
        warnings.push(format!(
            "warning: reference noise floor {floor:.2e} is above a tenth of the smallest RMSE measured \
             ({smallest:.2e}); errors near it are not resolved"
        ));
    }
    let cpu: f64 = [Some(&m.session), m.verify_session.as_ref()].iter().flatten().map(|s| s.cpu_s).sum();
    let renders: usize =
        [Some(&m.session), m.verify_session.as_ref()].iter().flatten().map(|s| s.renders).sum();
    let _ = writeln!(
        s,
        "jobs: {} rendered, {} reused; timing: {renders} timed renders, {cpu:.1} s of render CPU time → {}",
        m.rendered,
        m.reused,
        outdir::index(shown).display()
    );
    (s, warnings)
}

/// A ray budget's ranking for one camera: the first `SHOWN` candidates (all are in advice.json).
fn per_ray_table(x: &AtRays, a: &Analysis, after: &str) -> Table {
    let num = |v: f64| if v.is_finite() { format!("{v:.4}") } else { "—".into() };
    let rows = x
        .entries
        .iter()
        .take(SHOWN)
        .enumerate()
        .map(|(i, e)| {
            vec![
                (i + 1).to_string(),
                candidate(a, e),
                pm(e.rmse, 4),
                e.behind.map_or("best".into(), |m| {
                    format!("+{:.1} % ± {:.1} %", 100.0 * m.relative(), 100.0 * m.relative_se())
                }),
                if e.near_tie { "yes".into() } else { String::new() },
                num(e.flip.value),
                num(e.flicker),
                num(e.split.bias_rmse),
                num(e.split.noise_rmse),
                ms(e.time_s),
                format!("{:.1}", a.sampler_ns(e.row, x.rays)),
            ]
        })
        .collect();
    Table {
        title: format!(
            "At {} per pixel per frame, {}, {after}: {} candidates ranked by RMSE",
            if x.rays == 1 { "1 ray".to_string() } else { format!("{} rays", x.rays) },
            camera(&x.camera),
            x.entries.len()
        ),
        header: [
            "#",
            "configuration",
            "RMSE",
            "MSE above the best's (paired)",
            "near-tie",
            "FLIP",
            "flicker",
            "bias",
            "noise",
            "time per frame (ms)",
            "sampler (ns per point)",
        ]
        .map(String::from)
        .to_vec(),
        rows,
    }
}

fn summary_table(a: &Analysis) -> Table {
    let rows = a
        .answers
        .iter()
        .map(|x| {
            let b = ms(x.budget_s);
            let Some(best) = x.recommended() else {
                let mut row = vec![b, status(&x.ranking).into()];
                row.resize(8, String::new());
                return row;
            };
            let sc = x.score(best);
            let gain = sc.gain.map_or("—".into(), |g| pm(g.estimate(), 2));
            let second = x.runner_up().map_or(String::new(), |r| {
                format!("{} ({:.1} σ)", label(r.row), x.score(r).behind.unwrap_or(f64::NAN))
            });
            vec![
                b,
                label(best.row),
                best.rays.to_string(),
                if x.measured { pm(sc.time_ms, 2) } else { "not measured".into() },
                pm(sc.rmse, 4),
                gain,
                second,
                x.best_lowpass().map_or(String::new(), |l| label(l.row)),
            ]
        })
        .collect();
    Table {
        title: "Advice per budget (measured at the ray count shipped)".into(),
        header: [
            "budget (ms)",
            "ship",
            "rays",
            "time (ms)",
            "RMSE",
            "MSE gain vs paper default",
            "runner-up (σ behind)",
            "least low-pass RMSE",
        ]
        .map(String::from)
        .to_vec(),
        rows,
    }
}

fn finalists_table(x: &Answer, per: &str) -> Table {
    let best = x.recommended().map(|b| b.row);
    let rows = x
        .finalists
        .iter()
        .zip(&x.scores)
        .map(|(c, sc)| {
            vec![
                format!("{}{}", label(c.row), if Some(c.row) == best { " ← ship" } else { "" }),
                c.rays.to_string(),
                if c.measured { pm(sc.time_ms, 2) } else { "—".into() },
                pm(sc.rmse, 4),
                pm(sc.lowpass_rmse, 4),
                format!("{:.1}{}", c.structure_mean(), if c.structured() { " (structured)" } else { "" }),
                sc.gain.map_or("—".into(), |g| pm(g.estimate(), 2)),
                if Some(c.row) == best {
                    String::new()
                } else {
                    format!("{:.1}", sc.behind.unwrap_or(f64::NAN))
                },
            ]
        })
        .collect();
    Table {
        title: format!(
            "At {} ms per {per}: the finalists {}",
            ms(x.budget_s),
            if x.measured {
                "measured at the ray count that fits the budget".to_string()
            } else {
                "(not measured: interpolated from the sweep)".to_string()
            }
        ),
        header: [
            "configuration",
            "rays",
            "time (ms)",
            "RMSE",
            "low-pass RMSE",
            structure::MEASURE,
            "MSE gain vs paper default",
            "σ behind the shipped",
        ]
        .map(String::from)
        .to_vec(),
        rows,
    }
}

fn ranking_table(r: &Ranking, scores: &[RankScored], per: &str) -> Table {
    let mut shown: Vec<usize> = (0..r.ranked.len().min(SHOWN)).collect();
    if let Some(i) = r.ranked.iter().position(|a| a.row == PAPER_DEFAULT).filter(|&i| i >= SHOWN) {
        shown.push(i);
    }
    let rows = shown
        .into_iter()
        .map(|i| {
            let (a, sc) = (&r.ranked[i], &scores[i]);
            vec![
                (i + 1).to_string(),
                label(a.row),
                format!("{:.1}", a.rays),
                pm(sc.rmse, 4),
                pm(sc.lowpass_rmse, 4),
                sc.gain.map_or("—".into(), |g| pm(g.estimate(), 2)),
                sc.behind_best.map_or(String::new(), |z| format!("{z:.1}")),
            ]
        })
        .collect();
    Table {
        title: format!(
            "At {} ms per {per}, interpolated from the sweep: {} configurations ranked by RMSE{}",
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
            "MSE gain vs paper default",
            "σ behind #1",
        ]
        .map(String::from)
        .to_vec(),
        rows,
    }
}

fn ladder_table(a: &Analysis, per: &str) -> Table {
    let mut rows = Vec::new();
    for c in &a.curves {
        for p in &c.points {
            let (t, e, l) = (p.time_ms(), p.rmse(Metric::Rmse), p.rmse(Metric::Lowpass));
            rows.push(vec![label(c.row), p.rays.to_string(), pm(t, 3), pm(e, 4), pm(l, 4)]);
        }
    }
    Table {
        title: "Every point of the sweep (time: median ± σ; errors ± σ over the replicates)".into(),
        header: [
            "configuration".into(),
            "rays".into(),
            format!("time per {per} (ms)"),
            "RMSE".into(),
            "low-pass RMSE".into(),
        ]
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
