//! `hemilab run` and `hemilab plan` end to end through the real binary: the promised results columns,
//! resuming an interrupted run, bit-identical reruns for any thread count, and a plan that renders
//! and writes nothing.

use crate::support::common;

use common::*;
use hemilab::results::JobResult;
use std::path::Path;

const PROMISED: [&str; 14] = [
    "scene",
    "distribution",
    "sequence",
    "seed_mode",
    "rays",
    "replicate",
    "seed",
    "rmse",
    "bias",
    "autocorr_x",
    "autocorr_y",
    "lowpass_rmse",
    "time_s",
    "rays_per_s",
];

/// The pinned job order of `tiny_spec`: scene, then groups in file order, then row, rays, replicate;
/// a job an earlier group already needs is not repeated.
const TINY_ORDER: [(&str, &str, &str, u32, u32); 16] = [
    ("uniform", "random", "rotation", 2, 0),
    ("uniform", "random", "rotation", 2, 1),
    ("uniform", "random", "rotation", 4, 0),
    ("uniform", "random", "rotation", 4, 1),
    ("sine-cosine", "fibonacci", "static", 2, 0),
    ("sine-cosine", "fibonacci", "static", 2, 1),
    ("sine-cosine", "fibonacci", "static", 4, 0),
    ("sine-cosine", "fibonacci", "static", 4, 1),
    ("sine-cosine", "fibonacci", "static", 1, 0),
    ("sine-cosine", "fibonacci", "static", 1, 1),
    ("sine-cosine", "fibonacci", "shift", 1, 0),
    ("sine-cosine", "fibonacci", "shift", 1, 1),
    ("sine-cosine", "fibonacci", "shift", 2, 0),
    ("sine-cosine", "fibonacci", "shift", 2, 1),
    ("sine-cosine", "fibonacci", "shift", 4, 0),
    ("sine-cosine", "fibonacci", "shift", 4, 1),
];

fn config(r: &JobResult) -> (&str, &str, &str, u32, u32) {
    (&r.distribution, &r.sequence, &r.seed_mode, r.rays, r.replicate)
}

fn image_bytes(out: &Path, r: &JobResult) -> Vec<u8> {
    std::fs::read(out.join(&r.image)).unwrap_or_else(|e| panic!("{}: {e}", r.image))
}

#[test]
fn smoke_run_writes_results_with_the_required_columns() {
    let t = Tmp::new("smoke");
    let spec = Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments/smoke.toml");
    t.run_ok(&spec, "out", "ref", &[]);
    let out = t.path("out");

    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(&header[..PROMISED.len()], &PROMISED, "promised columns, in this order");
    assert_eq!(header, hemilab::results::CSV_COLUMNS, "later columns appended, in their order");
    assert_eq!(header.last(), Some(&"bias_se"), "the newest column is last");
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();

    let text = std::fs::read_to_string(&spec).unwrap();
    let plan = hemilab::plan::plan(&hemilab::spec::parse_spec(&text, &spec).unwrap());
    assert_eq!(rows.len(), plan.jobs.len(), "one record per planned job");
    let records = records(&out);
    assert_eq!(records.len(), plan.jobs.len());
    for ((job, rec), row) in plan.jobs.iter().zip(&records).zip(&rows) {
        assert_eq!(row.len(), header.len());
        assert_eq!(
            (rec.scene.as_str(), config(rec), rec.seed),
            (
                job.scene_name.as_str(),
                (job.distribution.name(), job.sequence.name(), job.seed_mode.name(), job.rays, job.replicate),
                job.seed
            ),
            "records follow the plan"
        );
        assert_eq!(row[0], rec.scene);
        assert_eq!(row[7].parse::<f64>().unwrap(), rec.rmse, "CSV and JSON agree");
        assert!(rec.rmse > 0.0 && rec.rmse < 1.0 && rec.time_s > 0.0 && rec.rays_per_s > 0.0, "{rec:?}");
        let channels = hemilab::io::read_exr(&out.join(&rec.image)).unwrap();
        assert!(channels.iter().any(|(n, img)| n == "Y" && (img.width, img.height) == (32, 32)));
    }
}

#[test]
fn resume_after_interruption_gives_identical_results() {
    let t = Tmp::new("resume");
    let spec = t.spec("tiny.toml", &tiny_spec(64, ""));
    t.run_ok(&spec, "out", "ref", &[]);
    let out = t.path("out");
    let full = records(&out);
    assert_eq!(full.len(), 16);
    let full_csv = timeless_csv(&out);
    let images: Vec<Vec<u8>> = full.iter().map(|r| image_bytes(&out, r)).collect();

    // Interrupted after 6 jobs: results.json holds those (their first time sample marked by an
    // impossible value so a skip is visible; a kept record may still get timing-only re-renders),
    // the later images never got written, and job 1's image was lost too.
    const SENTINEL: f64 = 1234.5;
    let kept: Vec<JobResult> = full[..6]
        .iter()
        .map(|r| JobResult { time_s: SENTINEL, times: vec![SENTINEL], walls: vec![SENTINEL], ..r.clone() })
        .collect();
    std::fs::write(out.join("results.json"), hemilab::results::to_json(&kept)).unwrap();
    std::fs::write(out.join("results.csv"), hemilab::results::to_csv(&kept)).unwrap();
    for r in &full[6..] {
        std::fs::remove_file(out.join(&r.image)).unwrap();
    }
    std::fs::remove_file(out.join(&full[1].image)).unwrap();

    t.run_ok(&spec, "out", "ref", &[]);
    let resumed = records(&out);
    assert_eq!(resumed.len(), 16);
    for (i, r) in resumed.iter().enumerate() {
        let skipped = r.times.first() == Some(&SENTINEL);
        assert_eq!(
            skipped,
            i < 6 && i != 1,
            "job {i}: finished jobs with their image are skipped, others redone"
        );
        assert_eq!(timeless(r), timeless(&full[i]), "job {i}: identical results");
        assert_eq!(image_bytes(&out, r), images[i], "job {i}: identical image");
    }
    assert_eq!(timeless_csv(&out), full_csv, "results.csv identical but for run times");

    t.run_ok(&spec, "out", "ref", &["--force"]);
    let forced = records(&out);
    assert!(forced.iter().all(|r| !r.times.contains(&SENTINEL)), "--force redoes every job");
    let a: Vec<JobResult> = full.iter().map(timeless).collect();
    assert_eq!(forced.iter().map(timeless).collect::<Vec<_>>(), a);
    assert_eq!(timeless_csv(&out), full_csv);
}

#[test]
fn rerun_is_bit_identical_for_any_thread_count() {
    let t = Tmp::new("threads");
    let spec = t.spec("tiny.toml", &tiny_spec(64, ""));
    t.run_ok(&spec, "one", "ref1", &["--threads", "1"]);
    t.run_ok(&spec, "two", "ref2", &["--threads", "2"]);
    let (one, two) = (records(&t.path("one")), records(&t.path("two")));
    assert_eq!(timeless_csv(&t.path("one")), timeless_csv(&t.path("two")));
    assert_eq!(one.len(), 16);
    for (a, b) in one.iter().zip(&two) {
        assert_eq!(image_bytes(&t.path("one"), a), image_bytes(&t.path("two"), b), "{}", a.image);
        let metrics = |r: &JobResult| {
            [r.rmse, r.bias, r.autocorr_x, r.autocorr_y, r.lowpass_rmse, r.whiteness_z, r.lowfreq_ratio]
        };
        assert_eq!(metrics(a).map(f64::to_bits), metrics(b).map(f64::to_bits), "{}", a.image);
        assert_eq!(timeless(a), timeless(b));
    }
    let refs = |d: &str| {
        let mut v: Vec<_> = std::fs::read_dir(t.path(d)).unwrap().map(|e| e.unwrap().path()).collect();
        v.sort();
        v.iter().filter(|p| p.extension().is_some_and(|e| e == "exr")).map(std::fs::read).collect::<Vec<_>>()
    };
    let (r1, r2) = (refs("ref1"), refs("ref2"));
    assert_eq!(r1.len(), 1);
    assert!(r1[0].as_ref().unwrap() == r2[0].as_ref().unwrap(), "reference images are identical too");
}

#[test]
fn plan_prints_jobs_and_estimate_without_rendering() {
    let t = Tmp::new("plan");
    let spec = t.spec("tiny.toml", &tiny_spec(64, ""));
    let before = t.listing();
    let o = t.hemilab(&["plan", "tiny.toml", "--jobs", "--reference-dir", "ref"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(t.listing(), before, "plan writes nothing");
    let text = stdout(&o);
    let jobs: Vec<Vec<&str>> = text
        .lines()
        .map(|l| l.split_whitespace().collect::<Vec<_>>())
        .filter(|f| f.len() == 8 && f[0].parse::<usize>().is_ok())
        .collect();
    assert_eq!(jobs.len(), TINY_ORDER.len(), "{text}");
    for (i, (f, want)) in jobs.iter().zip(TINY_ORDER).enumerate() {
        assert_eq!(f[0], (i + 1).to_string());
        assert_eq!(f[1], "cornell-box");
        let got = (f[2], f[3], f[4], f[5].parse::<u32>().unwrap(), f[6].parse::<u32>().unwrap());
        assert_eq!(got, want, "job {}", i + 1);
    }
    // The summary first: an upper bound of the rays (every one of the 24x18 pixels of every job at
    // the job's ray count) and a time estimate; the job list after it.
    let rays: u32 = TINY_ORDER.iter().map(|j| j.3).sum();
    let total = (24 * 18 * rays).to_string();
    let first = text.lines().next().unwrap();
    assert!(first.contains(": 16 jobs in 8 configurations"), "{first}");
    assert!(first.contains(&format!("at most {total} AO rays")), "{first}");
    let estimate = text.lines().position(|l| l.starts_with("estimate: ≈ ")).expect("a time estimate");
    assert!(estimate < text.lines().position(|l| l.starts_with("jobs, in run order")).unwrap());

    // The run renders exactly these jobs, in this order.
    t.run_ok(&spec, "out", "ref", &[]);
    let recs = records(&t.path("out"));
    assert_eq!(recs.iter().map(config).collect::<Vec<_>>(), TINY_ORDER.to_vec());
    // Slopes: per sweep row, over the sweep's ray counts only (not the table's uniform row).
    let slopes: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(t.path("out/slopes.json")).unwrap()).unwrap();
    let sweep = &slopes.as_array().unwrap()[0];
    assert_eq!(sweep["group"], "c");
    let rows = sweep["slopes"].as_array().unwrap();
    assert_eq!(rows.len(), 2, "{slopes}");
    assert!(
        rows.iter().all(|r| r["points"] == 3 && r["vs_rays"]["value"].as_f64().unwrap() < 0.0),
        "{slopes}"
    );
    assert!(rows.iter().all(|r| r["vs_rays"]["ci95"].as_array().is_some_and(|c| c.len() == 2)), "{slopes}");
}

#[test]
fn default_output_directory_is_out_slash_spec_name() {
    let t = Tmp::new("default-out");
    let spec =
        tiny_spec(16, "").replace("rays = [2, 4]", "rays = [1]").replace("rays = [1, 2, 4]", "rays = [1]");
    t.spec("tiny.toml", &spec);
    let o = t.hemilab(&["run", "tiny.toml", "--reference-dir", "ref", "--quiet"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(records(&t.path("out/tiny")).len(), 6);
    let closing = |o: &std::process::Output| stdout(o).lines().last().unwrap_or_default().to_string();
    assert_eq!(closing(&o), "6 jobs: 6 rendered, 0 reused; report: out/tiny/index.html", "{}", stdout(&o));
    // A rerun reuses every result and says so, last.
    let o = t.hemilab(&["run", "tiny.toml", "--reference-dir", "ref", "--quiet"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(closing(&o), "6 jobs: 0 rendered, 6 reused; report: out/tiny/index.html", "{}", stdout(&o));
    // Without --quiet it says so before any work, too.
    let o = t.hemilab(&["run", "tiny.toml", "--reference-dir", "ref"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o)
            .lines()
            .any(|l| l.starts_with("resuming from out/tiny: 6 of 6 jobs have their records there")),
        "{}",
        stderr(&o)
    );
}

#[test]
fn noise_floor_warning_says_how_many_rays_are_needed() {
    let t = Tmp::new("floor");
    // A scene file whose own `name` differs from its file stem (the results' `scene` column).
    let box_toml = std::fs::read_to_string(scene("cornell-box.toml")).unwrap();
    let box_toml =
        box_toml.replace("mesh = \"cornell-box.obj\"", &format!("mesh = \"{}\"", scene("cornell-box.obj")));
    std::fs::write(t.path("box.toml"), format!("name = \"named-box\"\n{box_toml}")).unwrap();
    let spec = tiny_spec(1, "").replace(&scene("cornell-box.toml"), "box.toml");
    let spec = t.spec("tiny.toml", &spec);
    let o = t.run_ok(&spec, "out", "ref", &[]);
    let (out, err) = (stdout(&o), stderr(&o));
    assert!(records(&t.path("out")).iter().all(|r| r.scene == "box"));
    assert!(out.contains("reference 'box': noise floor"), "{out}");
    assert!(!out.contains("smallest RMSE inf"), "{out}");
    assert!(
        err.contains("warning: reference noise floor") && err.contains("rays per replicate are needed"),
        "a 1-ray reference is far too noisy and the run says so:\n{err}"
    );
}

#[test]
fn timing_columns_follow_the_protocol() {
    let t = Tmp::new("timing");
    let spec = t.spec("tiny.toml", &tiny_spec(64, ""));
    // Two replicates, five timed renders per configuration: three timing-only re-renders each.
    t.run_ok(&spec, "out", "ref", &["--timing-repeats", "5", "--threads", "2"]);
    let recs = records(&t.path("out"));
    let timing: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(t.path("out/timing.json")).unwrap()).unwrap();
    assert_eq!(timing["protocol"]["repeats"], 5);
    assert_eq!(timing["protocol"]["workers"], 2);
    assert_eq!(timing["protocol"]["threads_per_render"], 1);
    let overhead = &timing["overhead"][0]["overhead_s"];
    let over_n = overhead["n"].as_u64().unwrap();
    assert!((7..=15).contains(&over_n), "{timing}");
    let over = overhead["median"].as_f64().unwrap();
    assert!(over > 0.0);
    let mut renders = over_n;
    for r in &recs {
        let same: Vec<&JobResult> = recs.iter().filter(|o| o.config() == r.config()).collect();
        let samples: Vec<f64> = same.iter().flat_map(|o| o.times.iter().copied()).collect();
        // At least the 5 asked for; these 24x18 renders are cheap, so the second round adds more,
        // up to 15 in all.
        assert!((5..=15).contains(&samples.len()), "{:?}: {} samples", r.config(), samples.len());
        assert_eq!(r.timings, samples.len());
        if r.replicate == 0 {
            renders += samples.len() as u64;
        }
        assert!(!r.times.is_empty() && r.times.len() == r.walls.len());
        assert_eq!(
            r.time_s,
            hemilab::stats::median(&r.times),
            "a job's own time is the median of its renders"
        );
        assert_eq!(r.time_median_s, hemilab::stats::median(&samples));
        let min = samples.iter().copied().fold(f64::INFINITY, f64::min);
        let max = samples.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        assert_eq!((r.time_min_s, r.time_max_s), (min, max));
        assert_eq!(r.overhead_s, over, "one overhead per scene");
        assert_eq!(r.timing_threads, 1);
        if r.time_median_s > over {
            assert_eq!(r.ao_time_s, r.time_median_s - over);
            assert!((r.ns_per_ray - 1e9 * r.ao_time_s / r.rays_cast as f64).abs() < 1e-9 * r.ns_per_ray);
            let e = r.efficiency.unwrap();
            assert!((e - 1.0 / (r.rmse * r.rmse * r.ao_time_s)).abs() < 1e-9 * e);
        } else {
            assert!(r.ao_time_s.is_nan() && r.efficiency.is_none(), "no split below the overhead: {r:?}");
        }
    }
    assert_eq!(timing["session"]["timed_renders"], renders, "{timing}");
    // The CSV carries the same numbers, undefined ones as empty fields.
    let csv = std::fs::read_to_string(t.path("out/results.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    for (line, r) in csv.lines().skip(1).zip(&recs) {
        let f: Vec<&str> = line.split(',').collect();
        assert_eq!(f[col("time_median_s")].parse::<f64>().unwrap(), r.time_median_s);
        assert_eq!(f[col("timings")], r.timings.to_string());
        assert_eq!(f[col("overhead_s")].parse::<f64>().unwrap(), r.overhead_s);
        assert_eq!(
            f[col("ao_time_s")].parse::<f64>().ok().unwrap_or(f64::NAN).to_bits(),
            r.ao_time_s.to_bits()
        );
    }
    let aggs = std::fs::read_to_string(t.path("out/aggregates.csv")).unwrap();
    for c in [
        "time_median_s",
        "time_min_s",
        "time_max_s",
        "overhead_s",
        "ns_per_ray",
        "efficiency_spread",
        "lowfreq_ratio_mean",
        "lowfreq_ratio_sd",
    ] {
        assert!(aggs.lines().next().unwrap().split(',').any(|h| h == c), "aggregates.csv lacks {c}");
    }
    // Killed after its last job but before the timing columns were filled: every record is there,
    // none split. The rerun renders no job again, only what the timing still needs.
    let unsplit: Vec<JobResult> = recs
        .iter()
        .map(|r| JobResult {
            time_median_s: f64::NAN,
            time_min_s: f64::NAN,
            time_max_s: f64::NAN,
            timings: 0,
            overhead_s: f64::NAN,
            ao_time_s: f64::NAN,
            ns_per_ray: f64::NAN,
            efficiency: None,
            ..r.clone()
        })
        .collect();
    std::fs::write(t.path("out/results.json"), hemilab::results::to_json(&unsplit)).unwrap();
    std::fs::remove_file(t.path("out/timing.json")).unwrap();
    t.run_ok(&spec, "out", "ref", &["--timing-repeats", "5"]);
    let refilled = records(&t.path("out"));
    for (a, b) in refilled.iter().zip(&recs) {
        assert_eq!(timeless(a), timeless(b));
        assert!(a.timings >= 5 && a.overhead_s > 0.0 && a.time_median_s > 0.0, "{a:?}");
        assert_eq!(a.times[..b.times.len()], b.times[..], "kept samples stay");
    }
    let recs = refilled;
    let timing: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(t.path("out/timing.json")).unwrap()).unwrap();
    // A rerun with nothing to do renders nothing and keeps every time.
    t.run_ok(&spec, "out", "ref", &["--timing-repeats", "5"]);
    assert_eq!(records(&t.path("out")), recs);
    let again: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(t.path("out/timing.json")).unwrap()).unwrap();
    assert_eq!(
        again["session"], timing["session"],
        "the session that made the times, not the one that reused them"
    );
    assert!(timing["session"]["timed_renders"].as_u64().unwrap() > 0);
    assert_eq!(again["overhead"], timing["overhead"], "the overhead of the session that made the times");
}

#[test]
fn a_run_over_two_scenes_times_each_with_its_own_overhead() {
    // The kitchen first, then the 30-triangle Cornell box: each worker thread renders both,
    // interleaved, so nothing it keeps from one scene may be used on the other.
    let t = Tmp::new("two-scenes");
    let spec = format!(
        r#"name = "two"
scenes = ["{}", "{}"]
resolution = [24, 18]
replicates = 2
[reference]
rays = 16
replicates = 2
[[convergence]]
name = "c"
rays = [1, 4, 16]
distributions = ["sine-cosine"]
sequences = ["fibonacci"]
seed_modes = ["shift"]
"#,
        scene("kitchen.toml"),
        scene("cornell-box.toml")
    );
    let spec = t.spec("two.toml", &spec);
    t.run_ok(&spec, "out", "ref", &["--threads", "2"]);
    let recs = records(&t.path("out"));
    assert_eq!(recs.len(), 12);
    let timing: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(t.path("out/timing.json")).unwrap()).unwrap();
    let over: Vec<(String, f64)> = timing["overhead"]
        .as_array()
        .unwrap()
        .iter()
        .map(|o| (o["scene"].as_str().unwrap().to_string(), o["overhead_s"]["median"].as_f64().unwrap()))
        .collect();
    assert_eq!(over.iter().map(|o| o.0.as_str()).collect::<Vec<_>>(), ["kitchen", "cornell-box"]);
    for r in &recs {
        let own = over.iter().find(|o| o.0 == r.scene).unwrap().1;
        assert_eq!(r.overhead_s, own, "{} takes its own scene's overhead", r.scene);
    }
    // The same images whichever way the renders were spread over threads.
    t.run_ok(&spec, "one", "ref", &["--threads", "1"]);
    let a: Vec<JobResult> = recs.iter().map(timeless).collect();
    assert_eq!(records(&t.path("one")).iter().map(timeless).collect::<Vec<_>>(), a);
}

/// The journal beside results.json: records are saved as they are made, a later line replaces an
/// earlier record of its key, a cut-off last line (a kill mid-write) is dropped, and writing
/// results.json whole empties the journal.
#[test]
fn the_journal_keeps_every_record_a_killed_run_made() {
    let t = Tmp::new("journal");
    t.spec("s.toml", &tiny_spec(64, ""));
    let o = t.run_ok(&t.path("s.toml"), "out", "ref", &[]);
    assert!(o.status.success());
    let out = t.path("out");
    let all = records(&out);
    assert!(
        all.len() >= 2 && !out.join(hemilab::outdir::RESULTS_JOURNAL).exists(),
        "a finished run has none"
    );
    // A run killed after saving two records whole and one in its journal, mid-way through a fourth.
    hemilab::outdir::write_results(&out, &all[..2]).unwrap();
    let mut changed = all[0].clone();
    changed.rmse = 0.5;
    hemilab::outdir::append_results(&out, &[all[2].clone(), changed]).unwrap();
    let cut = serde_json::to_string(&all[3 % all.len()]).unwrap();
    hemilab::io::append(&out.join(hemilab::outdir::RESULTS_JOURNAL), &cut.as_bytes()[..cut.len() / 2])
        .unwrap();
    let read = records(&out);
    assert_eq!(read.len(), 3, "two whole, one journalled, the cut-off line dropped");
    assert_eq!((read[0].rmse, &read[1], &read[2]), (0.5, &all[1], &all[2]));
    // A rerun resumes from them and writes results.json whole again.
    let o = t.run_ok(&t.path("s.toml"), "out", "ref", &[]);
    assert!(stdout(&o).contains("reused"), "{}", stdout(&o));
    assert!(!out.join(hemilab::outdir::RESULTS_JOURNAL).exists());
    assert_eq!(records(&out).len(), all.len());
}
