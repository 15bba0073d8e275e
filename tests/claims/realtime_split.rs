//! The committed real-time run (`experiments/outputs/realtime/results.json`),
//! asserted on its records (issue 45's acceptance): every pipeline's bias² + noise² is its mean MSE
//! over the replicates, and the floor a verdict is held against — the filter's bias measured on
//! per-pixel-unbiased input — is SVGF's and TAA's bias on the kitchen at one ray, not the
//! RMSE(F(reference), reference) that read 0 for SVGF. Re-running the spec takes about 20 minutes
//! on this 2-core machine, so the test reads the committed records.

use hemilab::results::JobResult;
use std::collections::BTreeMap;
use std::path::Path;

fn records() -> Vec<JobResult> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments/outputs/realtime/results.json");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    hemilab::results::from_json(&text).unwrap()
}

/// A configuration at one place: everything but the replicate.
fn configurations(rs: &[JobResult]) -> BTreeMap<String, Vec<&JobResult>> {
    let mut by: BTreeMap<String, Vec<&JobResult>> = BTreeMap::new();
    for r in rs {
        let k = format!(
            "{}|{}|{}|{}|{}|{}|{}|{}|{}",
            r.scene,
            r.distribution,
            r.sequence,
            r.seed_mode,
            r.schedule,
            r.rays,
            r.pipeline,
            r.frame,
            r.camera
        );
        by.entry(k).or_default().push(r);
    }
    by
}

#[test]
fn bias_squared_plus_noise_squared_is_the_mean_mse_for_every_pipeline() {
    let rs = records();
    let mut checked = BTreeMap::<String, usize>::new();
    for (k, v) in configurations(&rs) {
        let r0 = v[0];
        assert!(v.len() >= 2, "{k}: one replicate");
        assert!(r0.bias_rmse.is_finite() && r0.noise_rmse.is_finite(), "{k}: no split in the committed run");
        let mse = v.iter().map(|r| r.rmse * r.rmse).sum::<f64>() / v.len() as f64;
        let parts = r0.bias_rmse.powi(2) + r0.noise_rmse.powi(2);
        // bias² is clamped at 0 where the estimate is negative (a configuration with no bias to
        // speak of); there bias² + noise² exceeds the MSE by that clamp alone, within 2 %.
        assert!((parts - mse).abs() <= 0.02 * mse, "{k}: bias² + noise² = {parts:.6e}, mean MSE {mse:.6e}");
        *checked.entry(r0.pipeline.clone()).or_default() += 1;
    }
    for p in ["raw", "svgf", "svgf:5", "taa0.1", "ema0.1+atrous"] {
        assert!(checked.get(p).copied().unwrap_or(0) > 0, "no {p} configuration checked: {checked:?}");
    }
}

#[test]
fn svgf_and_taa_floors_on_the_kitchen_at_one_ray_are_their_measured_bias() {
    let rs = records();
    let mut seen = 0;
    for pipeline in ["svgf", "taa0.1"] {
        for camera in ["static", "orbit"] {
            let at: Vec<&JobResult> = rs
                .iter()
                .filter(|r| {
                    r.scene == "kitchen"
                        && r.rays == 1
                        && r.pipeline == pipeline
                        && r.camera == camera
                        && r.frame == 64
                        && r.schedule == "independent"
                })
                .collect();
            let floor = at[0].floor.unwrap_or(f64::NAN);
            assert!(floor > 0.005, "{pipeline}, {camera}: the floor is the filter's bias, not 0: {floor}");
            // The per-pixel-unbiased configurations measured there: the 2-D mask and STBN offsets.
            for mode in ["blue-noise", "stbn"] {
                let r = at
                    .iter()
                    .find(|r| r.seed_mode == mode && r.distribution == "sine-cosine")
                    .unwrap_or_else(|| panic!("{pipeline}, {camera}: no {mode}"));
                assert!(at.iter().all(|x| x.floor == Some(floor)), "one floor per place");
                assert!(
                    (floor - r.bias_rmse).abs() <= 0.10 * r.bias_rmse,
                    "{pipeline}, {camera}, {mode}: floor {floor:.4} against its bias {:.4}",
                    r.bias_rmse
                );
                seen += 1;
            }
        }
    }
    assert_eq!(seen, 8);
}

/// What the README's real-time section says in words about the compact tables, held against the
/// committed run's cells (`compare::realtime`), so the words cannot outlive the numbers.
#[test]
fn the_readme_real_time_conclusions_hold_on_the_committed_run() {
    use hemilab::compare::realtime::{paper_cells, stbn_cells};
    let rs = records();
    let paper = paper_cells(&rs).unwrap();
    let withheld = |below: bool, bias: bool| below || bias;
    for c in &paper {
        let p = &c.place;
        let rmse = if withheld(c.below_floor, c.bias_interaction) { 0 } else { c.rmse.sign };
        if p.pipeline != "raw" && p.rays <= 2 {
            // After every accumulating pipeline at 1 and 2 rays the paper's wins nowhere, either metric.
            assert!(rmse != 1 && c.flip.sign != 1, "{p:?}: {c:?}");
        }
        if p.pipeline == "raw" {
            // Raw: RMSE never for the best other, FLIP always for it (the blue-noise offsets).
            assert!(rmse != -1 && c.flip.sign == -1, "{p:?}: {c:?}");
            assert!(
                matches!(
                    c.best.seed_mode,
                    hemilab::sampling::SeedMode::BlueNoise | hemilab::sampling::SeedMode::Stbn
                ),
                "{p:?}: {}",
                c.best
            );
        }
    }
    let stbn = stbn_cells(&rs);
    let (mut still, mut still_wins) = (0, 0);
    for c in &stbn {
        let p = &c.place;
        let rmse = if withheld(c.below_floor, c.bias_interaction) { 0 } else { c.rmse.sign };
        if p.camera == "orbit" {
            // Moving camera: STBN wins no cell on RMSE; FLIP ties or favours the mask.
            assert!(rmse != -1 && c.flip.sign != -1, "{p:?}: {c:?}");
        } else {
            still += 1;
            still_wins += usize::from(rmse == -1);
        }
    }
    // Still camera: STBN wins on RMSE in most cells, under TAA in every one, where FLIP mostly
    // calls for the mask or a tie.
    assert!(2 * still_wins > still, "{still_wins} of {still}");
    let taa: Vec<_> =
        stbn.iter().filter(|c| c.place.camera == "static" && c.place.pipeline == "taa0.1").collect();
    assert!(
        !taa.is_empty() && taa.iter().all(|c| c.rmse.sign == -1 && !c.below_floor && !c.bias_interaction)
    );
    let flip_stbn = taa.iter().filter(|c| c.flip.sign == -1).count();
    assert!(2 * flip_stbn < taa.len(), "FLIP for stbn in {flip_stbn} of {} TAA cells", taa.len());
}
