//! The real-time verdicts (issue 26): the records of a spec's `frames`/`pipelines`/`schedules`
//! groups (`JobResult::is_single_frame` false, plus the raw frame-1 records beside them) read as
//! two questions, with measured margins (mean RMSE over the replicates, against the reference:
//! what the user sees). (1) After each pipeline, at its last measured frame, does the paper's
//! sine-cosine × Fibonacci × per-pixel seed (independent schedule) still have the least error of
//! every configuration measured with it? (2) Under the EMA pipelines, does spatiotemporal blue
//! noise (Wolfe, Morrical & Ramamoorthi 2022) beat the 2-D blue-noise mask drawn afresh each
//! frame (the same sequence, the independent schedule), as its paper reports for AO?
//! The RMSE after a spatial filter includes the filter's bias (`noise_rmse` in results.csv leaves
//! it out), so small margins there say the filter, not the sampler, sets the error.

use crate::report::Table;
use crate::results::JobResult;
use std::collections::BTreeMap;

/// (scene, rays, pipeline, frame) → configuration label (`distribution/sequence/seed_mode/schedule`)
/// → RMSE of each replicate.
type Cells<'a> = BTreeMap<(&'a str, u32, &'a str, u32), BTreeMap<String, Vec<f64>>>;

fn cells(results: &[JobResult]) -> Cells<'_> {
    let mut out: Cells = BTreeMap::new();
    for r in results {
        let label = format!("{}/{}/{}/{}", r.distribution, r.sequence, r.seed_mode, r.schedule);
        out.entry((&r.scene, r.rays, &r.pipeline, r.frame))
            .or_default()
            .entry(label)
            .or_default()
            .push(r.rmse);
    }
    out
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

/// The paper's configuration, as `cells` labels it.
pub const PAPER: &str = "sine-cosine/fibonacci/rotation/independent";

/// Whether the spec measured anything real-time (more than one frame, schedule or pipeline).
pub fn any(results: &[JobResult]) -> bool {
    results.iter().any(|r| !r.is_single_frame())
}

/// Question (1): one row per (scene, rays, pipeline at its last frame): the paper's RMSE, the best
/// configuration and its RMSE, and the margin (best other / paper − 1; positive: the paper's wins).
pub fn paper_table(results: &[JobResult]) -> Option<Table> {
    if !any(results) {
        return None;
    }
    let cells = cells(results);
    let last = |scene: &str, rays: u32, p: &str| {
        cells.keys().filter(|k| k.0 == scene && k.1 == rays && k.2 == p).map(|k| k.3).max()
    };
    let mut rows = Vec::new();
    for (&(scene, rays, pipeline, frame), configs) in &cells {
        if Some(frame) != last(scene, rays, pipeline) {
            continue;
        }
        let Some(paper) = configs.get(PAPER).map(|v| mean(v)) else { continue };
        // Other estimators only: the paper's under another schedule is still the paper's (and at
        // frame 1 the very same image).
        let estimator = |l: &str| l.rsplit_once('/').map_or("", |x| x.0).to_string();
        let others =
            configs.iter().filter(|(l, _)| estimator(l) != estimator(PAPER)).map(|(l, v)| (l, mean(v)));
        let Some((best, best_rmse)) = others.min_by(|a, b| a.1.total_cmp(&b.1)) else { continue };
        let margin = best_rmse / paper - 1.0;
        rows.push(vec![
            scene.to_string(),
            rays.to_string(),
            format!("{pipeline} (frame {frame})"),
            format!("{paper:.4}"),
            best.clone(),
            format!("{best_rmse:.4}"),
            format!("{:+.1} %", 100.0 * margin),
            if margin > 0.0 { "yes" } else { "no" }.into(),
        ]);
    }
    Some(Table {
        title: "Real-time: does sine-cosine × Fibonacci × per-pixel seed still win after the pipeline?"
            .into(),
        header: [
            "scene",
            "rays/frame",
            "pipeline",
            "paper's RMSE",
            "best other",
            "its RMSE",
            "margin",
            "paper wins",
        ]
        .map(String::from)
        .to_vec(),
        rows,
    })
}

/// Question (2): under every accumulating pipeline at its last frame, per (scene, rays, sequence,
/// distribution): RMSE with `stbn` over RMSE with per-frame-independent `blue-noise`.
pub fn stbn_table(results: &[JobResult]) -> Option<Table> {
    let cells = cells(results);
    let mut rows = Vec::new();
    for (&(scene, rays, pipeline, frame), configs) in &cells {
        if !pipeline.starts_with("ema") && !pipeline.starts_with("mean") {
            continue;
        }
        if cells.keys().any(|k| k.0 == scene && k.1 == rays && k.2 == pipeline && k.3 > frame) {
            continue;
        }
        for (label, v) in configs {
            let Some(prefix) = label.strip_suffix("/blue-noise/independent") else { continue };
            let Some(st) = configs.get(&format!("{prefix}/stbn/independent")) else { continue };
            let (bn, st) = (mean(v), mean(st));
            rows.push(vec![
                scene.to_string(),
                rays.to_string(),
                format!("{pipeline} (frame {frame})"),
                prefix.to_string(),
                format!("{bn:.4}"),
                format!("{st:.4}"),
                format!("{:.3}", st / bn),
                if st < bn { "yes" } else { "no" }.into(),
            ]);
        }
    }
    (!rows.is_empty()).then(|| Table {
        title: "Real-time: does spatiotemporal blue noise beat per-frame-independent blue noise under EMA?"
            .into(),
        header: [
            "scene",
            "rays/frame",
            "pipeline",
            "distribution/sequence",
            "blue-noise RMSE",
            "stbn RMSE",
            "stbn / blue-noise",
            "stbn wins",
        ]
        .map(String::from)
        .to_vec(),
        rows,
    })
}

/// One sentence per question: in how many cells the answer is yes.
pub fn text(results: &[JobResult]) -> Vec<String> {
    let count = |t: &Option<Table>| {
        t.as_ref()
            .map(|t| (t.rows.iter().filter(|r| r.last().is_some_and(|c| c == "yes")).count(), t.rows.len()))
    };
    let mut out = Vec::new();
    if let Some((yes, n)) = count(&paper_table(results)) {
        out.push(format!(
            "Real-time: sine-cosine × Fibonacci × per-pixel seed has the least RMSE after the pipeline in {yes} \
             of {n} cells (scene × rays per frame × pipeline at its last frame)."
        ));
    }
    if let Some((yes, n)) = count(&stbn_table(results)) {
        out.push(format!(
            "Under EMA, spatiotemporal blue noise has less RMSE than per-frame-independent blue noise in {yes} \
             of {n} cells."
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{Distribution as D, SeedMode as M, Sequence as S};
    use crate::spec::Row;

    fn rec(seq: S, mode: M, pipeline: &str, frame: u32, rmse: f64) -> JobResult {
        let mut r = JobResult::for_test("k", Row::new(D::SineCosine, seq, mode), 2, 0, rmse, 1.0);
        r.pipeline = pipeline.into();
        r.frame = frame;
        r
    }

    #[test]
    fn verdicts_read_the_last_frame_and_say_the_margin() {
        let rs = vec![
            rec(S::Fibonacci, M::Rotation, "raw", 1, 0.10),
            rec(S::Random, M::Rotation, "raw", 1, 0.12),
            rec(S::Fibonacci, M::Rotation, "ema0.1+atrous", 1, 0.05),
            rec(S::Random, M::BlueNoise, "ema0.1+atrous", 1, 0.01),
            rec(S::Fibonacci, M::Rotation, "ema0.1+atrous", 16, 0.02),
            rec(S::Random, M::BlueNoise, "ema0.1+atrous", 16, 0.03),
            rec(S::Random, M::Stbn, "ema0.1+atrous", 16, 0.015),
        ];
        let t = paper_table(&rs).unwrap();
        assert_eq!(t.rows.len(), 2, "{:?}", t.rows);
        assert_eq!(t.rows[0][2], "ema0.1+atrous (frame 16)");
        assert_eq!((t.rows[0][6].as_str(), t.rows[0][7].as_str()), ("-25.0 %", "no"));
        assert_eq!((t.rows[1][6].as_str(), t.rows[1][7].as_str()), ("+20.0 %", "yes"));
        let s = stbn_table(&rs).unwrap();
        assert_eq!(s.rows.len(), 1);
        assert_eq!((s.rows[0][6].as_str(), s.rows[0][7].as_str()), ("0.500", "yes"));
        assert!(paper_table(&rs[..2]).is_none(), "single frames only: no section");
    }
}
