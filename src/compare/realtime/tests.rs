//! Unit tests of the real-time verdicts on hand-made records.

use super::*;
use crate::sampling::{Distribution as D, SeedMode as M, Sequence as S};
use crate::spec::Row;

/// Two replicates of a configuration at `rmse` ± `d`, noise RMSE half of it.
fn recs(seq: S, mode: M, pipeline: &str, frame: u32, rmse: f64, d: f64) -> Vec<JobResult> {
    (0..2)
        .map(|rep| {
            let v = rmse + if rep == 0 { -d } else { d };
            let mut r = JobResult::for_test("k", Row::new(D::SineCosine, seq, mode), 2, rep, v, 1.0);
            r.pipeline = pipeline.into();
            r.frame = frame;
            r.bias_rmse = 0.0;
            r.noise_rmse = rmse;
            r
        })
        .collect()
}

#[test]
fn cells_are_read_at_the_last_frame_with_paired_margins() {
    let rs: Vec<JobResult> = [
        recs(S::Fibonacci, M::Rotation, "raw", 1, 0.10, 0.001),
        recs(S::Random, M::Rotation, "raw", 1, 0.12, 0.001),
        recs(S::Fibonacci, M::Rotation, "ema0.1+atrous", 1, 0.05, 0.001),
        recs(S::Random, M::BlueNoise, "ema0.1+atrous", 1, 0.01, 0.001),
        recs(S::Fibonacci, M::Rotation, "ema0.1+atrous", 16, 0.02, 0.001),
        recs(S::Random, M::BlueNoise, "ema0.1+atrous", 16, 0.03, 0.002),
        recs(S::Random, M::Stbn, "ema0.1+atrous", 16, 0.015, 0.001),
    ]
    .concat();
    let paper = paper_cells(&rs).unwrap();
    assert_eq!(paper.len(), 2);
    assert_eq!((paper[0].place.pipeline.as_str(), paper[0].place.frame), ("ema0.1+atrous", 16));
    // Best other: stbn at 0.015 against 0.02; the paired differences are exactly −0.005 twice.
    assert_eq!(paper[0].best.to_string(), "sine-cosine/random/stbn/independent");
    let m = paper[0].rmse.margin;
    assert!((m.relative() + 0.25).abs() < 1e-9 && m.n == 2, "{m:?}");
    assert_eq!((paper[0].rmse.sign, paper[0].noise.sign), (-1, -1));
    assert_eq!(paper[1].rmse.sign, 1, "raw: the paper's 0.10 against 0.12");
    let stbn = stbn_cells(&rs);
    assert_eq!(stbn.len(), 1);
    // stbn − blue noise: −0.016 and −0.014 → −50 % ± 3.3 % of 0.03: beyond t(1 dof) = 12.7 SE.
    let m = stbn[0].rmse.margin;
    assert!((m.relative() + 0.5).abs() < 1e-9 && (m.relative_se() - 0.1 / 3.0).abs() < 1e-9, "{m:?}");
    assert_eq!(stbn[0].rmse.sign, -1);
    assert_eq!(seeds_cells(&rs).map(|s| s.1.len()), Some(0), "no rotation/blue-noise/stbn triple");
    assert!(paper_cells(&rs[..4]).is_none(), "single frames only: nothing real-time");
}

#[test]
fn engine_cells_set_the_best_engine_pattern_against_the_best_other_seed_mode() {
    let rs: Vec<JobResult> = [
        recs(S::Fibonacci, M::Rotation, "ema0.1+atrous", 16, 0.030, 0.001),
        recs(S::Random, M::BlueNoise, "ema0.1+atrous", 16, 0.020, 0.001),
        recs(S::Random, M::Ign, "ema0.1+atrous", 16, 0.025, 0.001),
        recs(S::Fibonacci, M::Bayer, "ema0.1+atrous", 16, 0.040, 0.001),
        recs(S::Random, M::Ign, "ema0.1+atrous", 1, 0.001, 0.0001),
        recs(S::Fibonacci, M::Rotation, "raw", 1, 0.10, 0.001),
        recs(S::Fibonacci, M::MagicSquare, "raw", 1, 0.08, 0.001),
    ]
    .concat();
    let c = engine_cells(&rs);
    assert_eq!(c.len(), 2, "{c:?}");
    assert_eq!(
        (c[0].place.pipeline.as_str(), c[0].place.frame),
        ("ema0.1+atrous", 16),
        "the last frame only"
    );
    assert_eq!(c[0].engine.to_string(), "sine-cosine/random/ign/independent");
    assert_eq!(c[0].other.to_string(), "sine-cosine/random/blue-noise/independent");
    // Blue noise − IGN: exactly −0.005 twice → −20 % of 0.025, a verdict however few pairs.
    assert!((c[0].rmse.margin.relative() + 0.2).abs() < 1e-12, "{:?}", c[0].rmse.margin);
    assert_eq!((c[0].rmse.sign, c[0].noise.sign), (-1, -1), "the other wins");
    assert_eq!(c[1].engine.to_string(), "sine-cosine/fibonacci/magic-square/independent");
    assert_eq!(c[1].rmse.sign, 1, "raw: the magic square's 0.08 against the paper's 0.10");
    assert!(engine_cells(&rs[..4]).is_empty(), "no engine pattern measured: no cell");
}

#[test]
fn a_margin_within_the_biases_with_the_noise_ranked_the_other_way_is_a_bias_interaction() {
    // The paper's: RMSE 0.050 ± 0.0005, bias 0.040 (noise 0.030); the other: RMSE 0.048, bias
    // 0.010 (noise 0.047). The other wins on RMSE by 0.002, within the biases' 0.030, while its
    // noise is the larger: the biases decide, not the samplers' noise.
    let set = |v: &mut Vec<JobResult>, bias: f64| {
        v.iter_mut().for_each(|r| {
            r.bias_rmse = bias;
            r.noise_rmse = (0.05f64.powi(2) - bias * bias).sqrt();
        })
    };
    let mut paper = recs(S::Fibonacci, M::Rotation, "svgf", 16, 0.050, 0.0005);
    let mut other = recs(S::Fibonacci, M::BlueNoise, "svgf", 16, 0.048, 0.0005);
    set(&mut paper, 0.040);
    set(&mut other, 0.010);
    let rs = [paper.clone(), other.clone()].concat();
    let c = &paper_cells(&rs).unwrap()[0];
    assert_eq!((c.rmse.sign, c.noise.sign), (-1, 1), "{c:?}");
    assert!(c.bias_interaction);
    assert_eq!(c.paper_parts.bias.value, 0.040);
    // The same margin with equal biases is a win.
    set(&mut other, 0.040);
    let c = &paper_cells(&[paper, other].concat()).unwrap()[0];
    assert!(c.rmse.sign == -1 && !c.bias_interaction, "{c:?}");
}

#[test]
fn flip_is_a_third_verdict_that_can_disagree_with_rmse_and_is_unmeasured_without_the_column() {
    // STBN has 20 % less RMSE than the 2-D mask in both replicates, but 10 % more FLIP.
    let flip = |v: &mut Vec<JobResult>, f: f64| {
        v.iter_mut().enumerate().for_each(|(i, r)| r.flip = f + 0.001 * i as f64)
    };
    let mut bn = recs(S::Fibonacci, M::BlueNoise, "ema0.1+atrous", 16, 0.050, 0.001);
    let mut st = recs(S::Fibonacci, M::Stbn, "ema0.1+atrous", 16, 0.040, 0.001);
    flip(&mut bn, 0.10);
    flip(&mut st, 0.11);
    let c = &stbn_cells(&[bn.clone(), st.clone()].concat())[0];
    assert_eq!((c.rmse.sign, c.flip.sign), (-1, 1), "{c:?}");
    assert!((c.flip.margin.relative() - 0.01 / 0.1005).abs() < 1e-9, "{:?}", c.flip.margin);
    assert!(c.flip.measured() && c.rmse_flip_disagree());
    // The same FLIP on both sides: a tie, still a disagreement with RMSE's win.
    flip(&mut st, 0.10);
    let c = &stbn_cells(&[bn.clone(), st.clone()].concat())[0];
    assert_eq!(c.flip.sign, 0);
    assert!(c.rmse_flip_disagree());
    // FLIP agreeing: no disagreement.
    flip(&mut st, 0.08);
    assert!(!stbn_cells(&[bn.clone(), st.clone()].concat())[0].rmse_flip_disagree());
    // Records made before the column (NaN): no FLIP verdict, never a disagreement.
    st.iter_mut().for_each(|r| r.flip = f64::NAN);
    let c = &stbn_cells(&[bn, st].concat())[0];
    assert!(!c.flip.measured() && c.flip.sign == 0 && !c.rmse_flip_disagree(), "{c:?}");
}
