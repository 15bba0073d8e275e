use super::*;
use crate::compare::budget::{Metric, Place, Point, locate, rank};

const SC: Distribution = Distribution::SineCosine;

fn row(s: Sequence, m: SeedMode) -> Row {
    Row::new(SC, s, m)
}

/// A ladder with time = 1 ms + 0.1 ms per ray and MSE = c / rays, replicate r scaled by `noise[r]`.
fn curve(r: Row, c: f64, noise: &[f64]) -> Curve {
    let points = [1u32, 2, 4, 8, 16]
        .iter()
        .map(|&n| Point {
            rays: n,
            time_s: 1e-3 + 1e-4 * n as f64,
            time_sigma_ln: 0.01 * (1.0 + 0.1 * n as f64),
            timings: 15,
            replicates: (0..noise.len() as u32).collect(),
            mse: noise.iter().map(|k| k * c / n as f64).collect(),
            lowpass_mse: noise.iter().map(|k| k * c / (4.0 * n as f64)).collect(),
            structure: noise.iter().map(|_| n as f64).collect(),
        })
        .collect();
    Curve { row: r, points }
}

#[test]
fn the_default_set_is_every_distinct_sensible_estimator() {
    let rows = sensible_rows();
    // The original four sequences: 4 × 4 × 4, less random × shift (= random × rotation), random ×
    // static, and concentric × rotation for the three non-random ones; then the samplers renderers
    // ship, as they ship them (see the last test).
    assert_eq!(rows.len(), 64 - 4 - 4 - 3 + 20);
    assert!(rows.contains(&PAPER_DEFAULT));
    assert!(rows.contains(&Row::new(Distribution::ConcentricCosine, Sequence::Random, SeedMode::Rotation)));
    assert!(rows.contains(&row(Sequence::Random, SeedMode::BlueNoise)));
    for r in &rows {
        assert_eq!(*r, r.canonical());
        assert!(not_sensible(*r).is_none(), "{r:?}");
    }
    assert!(!rows.contains(&row(Sequence::Random, SeedMode::Static)));
    let odd = Row::new(Distribution::ConcentricCosine, Sequence::Fibonacci, SeedMode::Rotation);
    assert!(!rows.contains(&odd) && not_sensible(odd).is_some());
}

#[test]
fn only_patterns_select_and_explain() {
    let p = |s: &str| Pattern::parse(s).unwrap();
    assert_eq!(
        p("sine-cosine/*/shift"),
        Pattern { distribution: Some(SC), sequence: None, seed_mode: Some(SeedMode::Shift) }
    );
    for bad in ["sine-cosine/fibonacci", "a/b/c/d", "cosine/*/*", "*/halton2/*", "*/*/jitter", ""] {
        let e = Pattern::parse(bad).unwrap_err();
        assert!(e.contains(bad) || bad.is_empty(), "{bad}: {e}");
    }
    assert!(Pattern::parse("cosine/*/*").unwrap_err().contains("sine-cosine"), "lists the valid names");

    let all = select(&[]).unwrap();
    assert_eq!(all[0], PAPER_DEFAULT, "the baseline comes first");
    assert_eq!(all.len(), sensible_rows().len());
    let lattice = select(&[p("*/fibonacci/*")]).unwrap();
    assert_eq!(lattice[0], PAPER_DEFAULT, "always run: every gain is against it");
    assert_eq!(lattice.len(), 1 + 4 * 4 - 1);
    // Duplicates merge; random × shift is random × rotation, i.e. the default itself.
    assert_eq!(select(&[p("sine-cosine/random/shift"), p("sine-cosine/random/rotation")]).unwrap().len(), 1);
    // A fully named odd estimator is taken as asked.
    let odd = select(&[p("concentric-cosine/fibonacci/rotation")]).unwrap();
    assert_eq!(odd.len(), 2);
    // stbn is left out of the default set (one frame of it is a 2-D blue-noise mask), taken by name.
    assert!(!all.iter().any(|r| r.seed_mode == SeedMode::Stbn));
    let stbn = select(&[p("sine-cosine/fibonacci/stbn")]).unwrap();
    assert_eq!(stbn[1], row(Sequence::Fibonacci, SeedMode::Stbn));
    assert!(select(&[p("*/*/stbn")]).unwrap_err().contains("stbn"));
    let e = select(&[p("*/random/static")]).unwrap_err();
    assert!(e.contains("*/random/static") && e.contains("matches no configuration"), "{e}");
}

#[test]
fn finalists_are_measured_where_the_budget_fits_and_answer_from_measurements() {
    use crate::advice::answer::{Answer, FINALISTS, counts, finalists, rays_for};
    use crate::results::JobResult;
    let noise = [0.9, 1.0, 1.1, 1.05];
    let mut curves = vec![curve(PAPER_DEFAULT, 1.0, &noise)];
    for (i, s) in [Sequence::Fibonacci, Sequence::Sobol, Sequence::Stratified].into_iter().enumerate() {
        for (j, m) in [SeedMode::Shift, SeedMode::BlueNoise, SeedMode::Static].into_iter().enumerate() {
            curves.push(curve(row(s, m), 0.2 + 0.01 * (3 * i + j) as f64, &noise));
        }
    }
    let budget = 2.0e-3; // between 8 and 16 rays on every ladder: 9.76 interpolated
    let (r, low) = (rank(&curves, budget, Metric::Rmse), rank(&curves, budget, Metric::Lowpass));
    let f = finalists(&r, &low);
    assert_eq!(f.len(), FINALISTS + 1, "the six best, and the default");
    assert!(f.iter().any(|a| a.row == PAPER_DEFAULT));
    assert_eq!(counts(f[0]), [9, 8], "the interpolated count and the sweep's below");
    let mut wide = f[0].clone();
    (wide.rays, wide.lo_rays) = (41.7, 32);
    assert_eq!(counts(&wide), [41, 32], "above 32 rays the packet multiple is the ladder's here");
    (wide.rays, wide.lo_rays) = (70.2, 64);
    assert_eq!(counts(&wide), [70, 64]);
    (wide.rays, wide.lo_rays) = (100.0, 64);
    assert_eq!(counts(&wide), [100, 96, 64]);

    // Measurements: the best-ranked is structured (z 10 > 5) and 20 % better measured; the
    // second is measured at 9 rays over the budget (by 10 %, more than 2 σ of the session
    // factor) and so shipped at 8; every time is proportional to the rays, 9 rays at the budget.
    let interpolated = Answer::interpolated(r.clone(), low.clone());
    assert!(!interpolated.measured && interpolated.finalists.len() == f.len());
    let mut records: Vec<JobResult> = Vec::new();
    for a in &f {
        for n in counts(a) {
            for rep in 0..4u32 {
                let mse = a.mse[rep as usize] * 10.0 / n as f64;
                let z = if a.row == r.ranked[0].row { 10.0 } else { 1.0 };
                let mut rec = JobResult::for_test("s", a.row, n, rep, mse.sqrt(), z);
                let slow = if a.row == r.ranked[1].row && n == 9 { 1.1 } else { 1.0 };
                rec.add_time(budget * slow * n as f64 / rays_for(a) as f64, 0.0);
                records.push(rec);
            }
        }
    }
    let by = |row: Row, n: u32| records.iter().filter(|x| x.rays == n && x.is_row(row)).collect::<Vec<_>>();
    let ans = interpolated.clone().measure(&by, 4, 1.0);
    assert!(ans.measured);
    let best = ans.recommended().unwrap();
    assert_ne!(best.row, r.ranked[0].row, "structured: never recommended while another is measured");
    assert_eq!(ans.least_structured().unwrap().row, r.ranked[0].row);
    let second = ans.finalists.iter().find(|c| c.row == r.ranked[1].row).unwrap();
    assert_eq!((second.rays, second.others[0].0), (8, 9), "9 rays measured over the budget: 8 shipped");
    assert!(ans.fits(second) && ans.finalists.iter().all(|c| c.measured && ans.fits(c)));
    // Put on the sweep's scale, a session 10 % slower throughout fits again.
    let slow = interpolated.clone().measure(&by, 4, 1.1);
    assert_eq!(slow.finalists.iter().find(|c| c.row == r.ranked[1].row).unwrap().rays, 9);
    // Every time 4 % over the budget: within 2 σ of the session factor, so it fits, and the answer
    // says why a time above the budget is shipped (it once read as a mistake).
    let mut over: Vec<JobResult> = Vec::new();
    for a in &f {
        for n in counts(a) {
            for rep in 0..4u32 {
                let mse = a.mse[rep as usize] * 10.0 / n as f64;
                let z = if a.row == r.ranked[0].row { 10.0 } else { 1.0 };
                let mut rec = JobResult::for_test("s", a.row, n, rep, mse.sqrt(), z);
                rec.add_time(budget * 1.04 * n as f64 / rays_for(a) as f64, 0.0);
                over.push(rec);
            }
        }
    }
    let by_over = |row: Row, n: u32| over.iter().filter(|x| x.rays == n && x.is_row(row)).collect::<Vec<_>>();
    let ans_over = interpolated.clone().measure(&by_over, 4, 1.0);
    assert!(ans_over.fits(ans_over.recommended().unwrap()));
    let line = crate::report::advise::text::advice_line(&ans_over, "image");
    assert!(line.contains("its measured time is 4 % over the budget, which is within this machine's timing noise (its speed moves by about 3 % from one session to the next, and up to 2 times that counts as fitting), so it ships"), "{line}");
    assert!(
        !crate::report::advise::text::advice_line(&ans, "image").contains("over the budget"),
        "at the budget: no note"
    );
    let frame = crate::report::advise::text::advice_line(&ans_over, "frame");
    assert!(
        frame.contains("ms per frame: ship") && frame.contains("per pixel per frame (measured there"),
        "{frame}"
    );
    // A missing replicate: the budget stays interpolated.
    assert!(!interpolated.measure(&by, 5, 1.0).measured);
    // Measured MSE carries the replicates' σ only; the gain the model's.
    let d = ans.paper_default().unwrap();
    let g = ans.score(best).gain.unwrap();
    assert!((g.value - d.mean_mse(Metric::Rmse).value / best.mean_mse(Metric::Rmse).value).abs() < 1e-9);
    assert!(g.se_timing > 0.0 && g.se >= g.se_replicates);
}

#[test]
fn default_budgets_lie_inside_the_baseline_range() {
    let c = curve(PAPER_DEFAULT, 1.0, &[1.0]);
    let b = default_budgets(&c);
    assert_eq!(b.len(), 3);
    assert!(b.windows(2).all(|w| w[0] < w[1]), "{b:?}");
    for t in &b {
        assert!(matches!(locate(&c, *t), Place::Inside { .. }), "{t}");
        assert_eq!(*t, round_significant(*t, 2));
    }
    // A narrow range (times within 10 %): still three distinct budgets, with a third digit.
    let mut narrow = c.clone();
    for p in &mut narrow.points {
        p.time_s = 1e-3 + 1e-6 * p.rays as f64; // 1.001 to 1.016 ms
    }
    let b = default_budgets(&narrow);
    assert_eq!(b.len(), 3, "{b:?}");
    assert!(b.windows(2).all(|w| w[0] < w[1]), "{b:?}");
    assert_eq!(round_significant(0.012345, 2), 0.012);
    assert_eq!(round_significant(987.0, 2), 990.0);
    assert_eq!(round_significant(0.0, 2), 0.0);
    assert_eq!(round_significant(5.0999, 2), 5.1);
    assert_eq!(round_significant(0.0051, 1).to_string(), "0.005");
}

#[test]
fn the_default_set_holds_the_four_samplers_renderers_ship() {
    // 53 before halton, pmj02bn, zsobol and r2, which run as they ship: `shift` (and ZSobol's
    // `static` too) for each of the 4 distributions: 4 × (1 + 1 + 2 + 1) = 20 more.
    let rows = sensible_rows();
    assert_eq!(rows.len(), 73);
    for (s, n) in [(Sequence::Halton, 4), (Sequence::Pmj02bn, 4), (Sequence::ZSobol, 8), (Sequence::R2, 4)] {
        assert_eq!(rows.iter().filter(|r| r.sequence == s).count(), n, "{s}");
    }
}

#[test]
fn a_real_time_pipeline_sweeps_the_engine_patterns_as_engines_ship_them() {
    let engine = engine_rows();
    let modes = [SeedMode::Ign, SeedMode::Bayer, SeedMode::MagicSquare, SeedMode::R2Dither];
    let want: Vec<Row> =
        modes.iter().flat_map(|&m| [row(Sequence::Random, m), row(Sequence::Fibonacci, m)]).collect();
    assert_eq!(engine, want);
    let raw = sensible_rows();
    for r in &engine {
        assert!(!raw.contains(r) && not_sensible(*r).is_some(), "not in a raw frame's sweep: {r:?}");
        assert!(r.invalid().is_none(), "{r:?}");
    }
    let swept = select_with(&[], &engine).unwrap();
    assert_eq!(swept[0], PAPER_DEFAULT);
    assert_eq!(swept.len(), raw.len() + engine.len(), "the default set and the engines' rows");
    assert!(engine.iter().all(|r| swept.contains(r)));
    // With them in the pool, a pattern selects them as it selects the built-ins' rows.
    let ign = select_with(&[Pattern::parse("*/*/ign").unwrap()], &engine).unwrap();
    assert_eq!(
        ign,
        vec![PAPER_DEFAULT, row(Sequence::Random, SeedMode::Ign), row(Sequence::Fibonacci, SeedMode::Ign)]
    );
    assert!(select(&[Pattern::parse("*/*/ign").unwrap()]).is_err(), "a raw frame's pool has none");

    let request = |pipeline: &str| setup::Request {
        scene: "scenes/cornell-box.toml".into(),
        rays: vec![1, 2],
        only: Vec::new(),
        replicates: 2,
        resolution: None,
        reference_dir: None,
        pipeline: pipeline.parse().unwrap(),
        frames: 1,
        integrand: crate::sampling::Integrand::Ao,
        files: Vec::new(),
        files_dir: None,
        cameras: Vec::new(),
        denoiser: None,
    };
    let rows = |p: &str| setup::check(&request(p)).unwrap().rows;
    assert_eq!(rows("raw"), select(&[]).unwrap(), "raw: the default set alone");
    for p in ["atrous", "ema0.1+atrous", "svgf"] {
        // After a pipeline: the seed modes an engine chooses from, through the kernels it uses.
        let rs = rows(p);
        assert_eq!(rs, realtime_rows(&[]), "{p}");
        assert!(engine.iter().all(|r| rs.contains(r)), "{p}: the engines' patterns are swept");
        assert_eq!(rs.len(), 2 * REALTIME_MODES.len(), "{p}");
        assert!(rs.iter().all(|r| r.seed_mode != SeedMode::Static), "{p}");
        for m in REALTIME_MODES {
            assert!(rs.iter().any(|r| r.seed_mode == m), "{p}: {m:?}");
        }
        // --only picks from the whole sensible set too.
        let only =
            setup::Request { only: vec![Pattern::parse("uniform/sobol/shift").unwrap()], ..request(p) };
        assert_eq!(setup::check(&only).unwrap().rows, vec![PAPER_DEFAULT, row_of("uniform/sobol/shift")]);
    }
    // Cameras: the still one alone unless frames accumulate; then the default path, jittered, and
    // each --camera-path (a path equal to one already there is not measured twice).
    assert_eq!(setup::check(&request("svgf")).unwrap().cameras, vec![crate::plan::CameraId::STATIC]);
    let moving = setup::Request {
        frames: 8,
        cameras: vec!["pan:5".into(), "orbit:10".into()],
        ..request("ema0.1+atrous")
    };
    let cams = setup::check(&moving).unwrap().cameras;
    assert_eq!(cams.len(), 3, "still, the default orbit, pan:5");
    assert_eq!(cams[0], crate::plan::CameraId::STATIC);
    let runs: Vec<_> = cams[1..].iter().map(|c| c.run().unwrap()).collect();
    assert_eq!(runs[0].path, setup::default_path());
    assert!(runs.iter().all(|r| r.jitter && r.frames == 8));
    assert_eq!(runs[1].path, crate::scene::camera_path::CameraPath::Pan { degrees: 5.0 });
    let bad = setup::Request { cameras: vec!["spin:4".into()], ..moving.clone() };
    assert!(
        matches!(setup::check(&bad), Err(crate::error::Error::Usage(m)) if m.contains("--camera-path spin:4"))
    );
    let still = setup::Request { cameras: vec!["pan:5".into()], ..request("svgf") };
    assert!(setup::check(&still).is_err(), "a camera path needs accumulated frames");
    // The denoiser: NAME=PROGRAM ARGS, with both placeholders, only after a pipeline.
    let d = setup::Request { denoiser: Some("box=denoise {input} {output}".into()), ..moving.clone() };
    let id = setup::check(&d).unwrap().denoiser;
    let got = id.get().unwrap();
    assert_eq!((got.name.as_str(), got.command.program.as_str()), ("box", "denoise"));
    assert_eq!(got.command.args, ["{input}", "{output}"]);
    for wrong in ["box", "box=denoise {input}", "b x=denoise {input} {output}"] {
        let r = setup::Request { denoiser: Some(wrong.into()), ..moving.clone() };
        assert!(
            matches!(setup::check(&r), Err(crate::error::Error::Usage(m)) if m.starts_with("--denoiser")),
            "{wrong}"
        );
    }
    let raw_d = setup::Request { denoiser: Some("box=denoise {input} {output}".into()), ..request("raw") };
    assert!(setup::check(&raw_d).is_err());
}

fn row_of(text: &str) -> Row {
    let p = Pattern::parse(text).unwrap();
    Row::new(p.distribution.unwrap(), p.sequence.unwrap(), p.seed_mode.unwrap()).canonical()
}
