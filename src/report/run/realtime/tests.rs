//! Unit tests of the real-time tables and sentences on hand-made records.

use super::*;
use crate::sampling::{Distribution as D, SeedMode as M, Sequence as S};
use crate::spec::Row;

/// Two replicates of a configuration at `rmse` ± `d`.
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
fn verdicts_read_the_last_frame_and_say_the_margin_with_its_error() {
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
    let t = paper_table(&rs).unwrap();
    assert_eq!(t.rows.len(), 2, "{:?}", t.rows);
    assert_eq!(t.rows[0][P_PIPELINE], "ema0.1+atrous (frame 16)");
    assert_eq!(t.rows[0][2], "static");
    // Best other: stbn at 0.015 against 0.02; the paired differences are exactly −0.005 twice.
    assert_eq!(t.rows[0][5], "0.0200 ± 0.0010");
    assert_eq!(
        (t.rows[0][P_MARGIN].as_str(), t.rows[0][P_VERDICT].as_str()),
        ("-25.0 ± 0.0 %", "best other wins")
    );
    assert_eq!(t.rows[0][8], "0.0000 / 0.0200", "the paper's bias / noise (no standard error)");
    assert_eq!(t.rows[0][P_NOISE_VERDICT], "best other wins", "noise RMSE: the same halves");
    assert_eq!(
        (t.rows[1][P_MARGIN].as_str(), t.rows[1][P_VERDICT].as_str()),
        ("+20.0 ± 0.0 %", "paper wins")
    );
    let s = stbn_table(&rs).unwrap();
    assert_eq!(s.rows.len(), 1);
    // stbn − blue noise: −0.016 and −0.014 → −50 % ± 3.3 % of 0.03: beyond t(1 dof) = 12.7 SE.
    assert_eq!((s.rows[0][8].as_str(), s.rows[0][S_VERDICT].as_str()), ("-50.0 ± 3.3 %", "stbn wins"));
    let sum = summary_table(&rs).unwrap();
    assert_eq!(sum.rows.len(), 2);
    assert_eq!(
        sum.rows[0][..7],
        ["ema0.1+atrous (frame 16)", "2", "static", "1", "—", "0 / 0 / 1 / 0 / 0", "-25.0 %"]
            .map(String::from)
    );
    // A floor above both means: the verdict is withheld.
    let mut floored = rs.clone();
    floored.iter_mut().filter(|r| r.frame == 16).for_each(|r| r.floor = Some(0.05));
    let t = paper_table(&floored).unwrap();
    assert_eq!((t.rows[0][4].as_str(), t.rows[0][P_VERDICT].as_str()), ("0.0500", "below floor"));
    let seeds = seeds_table(&rs);
    assert!(seeds.is_none(), "no rotation/blue-noise/stbn triple at the fewest rays");
    assert!(paper_table(&rs[..4]).is_none(), "single frames only: no section");
}

#[test]
fn flip_verdicts_are_dashes_without_the_column_and_disagreements_are_named() {
    let mut rs: Vec<JobResult> = [
        recs(S::Fibonacci, M::BlueNoise, "ema0.1+atrous", 16, 0.050, 0.001),
        recs(S::Fibonacci, M::Stbn, "ema0.1+atrous", 16, 0.040, 0.001),
    ]
    .concat();
    let s = stbn_table(&rs).unwrap();
    assert_eq!((s.rows[0][S_VERDICT].as_str(), s.rows[0][S_FLIP_VERDICT].as_str()), ("stbn wins", "—"));
    assert_eq!(s.rows[0][12], "—");
    let said = text(&rs);
    assert!(said[1].contains("on FLIP it has less in 0, ties in 0 and has more in 0"), "{}", said[1]);
    assert!(said[2].contains("FLIP was not measured"), "{}", said[2]);
    // RMSE says stbn wins; FLIP (mask 0.10, stbn 0.11 in both replicates) says the mask wins.
    for r in &mut rs {
        r.flip = if r.seed_mode == "stbn" { 0.11 } else { 0.10 } + 0.001 * r.replicate as f64;
    }
    let s = stbn_table(&rs).unwrap();
    assert_eq!(
        (s.rows[0][12].as_str(), s.rows[0][S_FLIP_VERDICT].as_str()),
        ("+10.0 ± 0.0 %", "blue noise wins")
    );
    let said = text(&rs);
    assert!(said[1].contains("on FLIP it has less in 0, ties in 0 and has more in 1"), "{}", said[1]);
    assert_eq!(
        said[2],
        "Spatiotemporal blue noise against the 2-D mask: RMSE and FLIP disagree in 1 of 1 cells with FLIP \
         (k, 2 rays, static camera, ema0.1+atrous (frame 16), sine-cosine/fibonacci: RMSE stbn wins, FLIP blue noise wins)."
    );
}

#[test]
fn svgf_iteration_counts_are_paired_by_type_and_changed_verdicts_named() {
    // Under `svgf` the paper's loses to stbn; under `svgf:5` it wins. `svgf:5:id` has another
    // option, so it pairs with neither.
    let rs: Vec<JobResult> = [
        recs(S::Fibonacci, M::Rotation, "svgf", 64, 0.020, 0.001),
        recs(S::Fibonacci, M::BlueNoise, "svgf", 64, 0.030, 0.001),
        recs(S::Fibonacci, M::Stbn, "svgf", 64, 0.015, 0.001),
        recs(S::Fibonacci, M::Rotation, "svgf:5", 64, 0.010, 0.001),
        recs(S::Fibonacci, M::BlueNoise, "svgf:5", 64, 0.030, 0.001),
        recs(S::Fibonacci, M::Stbn, "svgf:5", 64, 0.015, 0.001),
        recs(S::Fibonacci, M::Rotation, "svgf:5:id", 64, 0.010, 0.001),
        recs(S::Fibonacci, M::Stbn, "svgf:5:id", 64, 0.015, 0.001),
    ]
    .concat();
    let pairs = crate::compare::realtime::iterations_pairs(&rs);
    assert_eq!(pairs.len(), 2, "{pairs:?}");
    assert_eq!(
        (pairs[0].places[0].pipeline.as_str(), pairs[0].places[1].pipeline.as_str()),
        ("svgf", "svgf:5")
    );
    let said = iterations_text(&rs);
    assert_eq!(said.len(), 2, "{said:?}");
    assert!(said[0].contains("the RMSE verdict changes in 1 of 1 cells (k, 2 rays, static camera, svgf (frame 64): best other wins → paper wins)"), "{}", said[0]);
    assert!(
        said[1].contains("STBN against the 2-D mask: the RMSE verdict changes in 0 of 1 cells;"),
        "{}",
        said[1]
    );
    let sum = stbn_summary_table(&rs).unwrap();
    assert_eq!(
        sum.rows[0][..5],
        ["svgf (frame 64)", "static", "2", "1", "1 / 0 / 0 / 0 / 0"].map(String::from)
    );
    // The compact forms: pipeline × camera by rays per frame, RMSE and FLIP (not in these records).
    let paper = paper_compact_table(&rs).unwrap();
    assert_eq!(paper.header, ["pipeline", "camera", "2 rays/frame"].map(String::from));
    assert_eq!(paper.rows.len(), 3, "svgf, svgf:5, svgf:5:id: {:?}", paper.rows);
    assert_eq!(paper.rows[0], ["svgf (frame 64)", "static", "RMSE 0/0/1 · FLIP —"].map(String::from));
    assert_eq!(paper.rows[1][2], "RMSE 1/0/0 · FLIP —");
    let stbn = stbn_compact_table(&rs).unwrap();
    assert_eq!(stbn.rows[0][2], "RMSE 1/0/0 · FLIP —", "stbn wins under svgf");
}
