//! `hemilab advise SCENE.toml`: which configuration to ship for this scene at a time budget.
//!
//! The same stages as `run`, from an in-memory spec instead of a file (`advice::setup`, from the
//! scene and stored references loaded here): every input checked → given budgets checked against a
//! calibrated cheapest render (`jobs::calibrate`; an impossible one is refused in seconds) → the
//! scene's reference (`jobs::reference::obtain`) →
//! the sweep under the timing protocol (`jobs::executor`) → the interpolated rankings → each
//! budget's finalists rendered and timed at the integer ray count that fits it (`advice::answer`)
//! → the answers, the winner maps → advice.json, advice.md, index.html, figures.
//!
//! Output set: built in a hidden sibling of `--out` (`outdir::advise_stage`) that then replaces
//! `--out` in one step, so a reader (or a kill) never sees old and new files mixed. Resume: the
//! records (results.json, rewritten every few seconds) and the finalists' images live there, and a
//! rerun reuses every record `jobs::executor::resumed` accepts — those of `--out`, of a killed
//! run's stage, and of `--from`'s directory. `--from DIR` renders nothing: the sweep must be
//! complete in DIR, and a budget whose finalists DIR lacks is answered by interpolation.

use crate::advice::analysis::{self, Measured};
use crate::advice::pipeline::{as_ranked, still_independent};
use crate::advice::setup::{self, Request, Setup};
use crate::cli::AdviseArgs;
use crate::compare::budget::round_significant;
use crate::error::{Error, Result};
use crate::jobs::calibrate;
use crate::jobs::executor;
use crate::jobs::forecast;
use crate::jobs::runner::JobRunner;
use crate::jobs::sweep;
use crate::load::{dropped_warning, load_scene};
use crate::reference::store::{self as refs, Policy};
use crate::results::JobResult;
use crate::{advice, outdir};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Frames accumulated by a temporal `--pipeline` when `--frames` is not given: steady state, as a
/// game is seen — an EMA of α 0.1 keeps 0.9⁶⁴ ≈ 0.1 % of its first frame by then, and a
/// spatiotemporal blue-noise mask has run its whole cycle of 64 slices.
const DEFAULT_FRAMES: u32 = 64;

pub fn run(args: AdviseArgs) -> Result<()> {
    let request = match &args.from {
        Some(dir) => Request::from_json(&outdir::read_advise_request(dir)?)
            .map_err(|e| Error::input(&dir.join(outdir::ADVISE_REQUEST), e))?,
        None => Request {
            scene: args.scene.clone().expect("clap requires a scene without --from"),
            rays: if args.rays.is_empty() { setup::default_rays(args.pipeline) } else { args.rays.clone() },
            only: args.only.clone(),
            replicates: args
                .replicates
                .unwrap_or_else(|| crate::advice::defaults::replicates(args.resolution)),
            resolution: args.resolution,
            reference_dir: args.reference_dir.clone(),
            pipeline: args.pipeline,
            frames: args.frames.unwrap_or(if args.pipeline.is_temporal() { DEFAULT_FRAMES } else { 1 }),
            integrand: args.integrand,
            files: args
                .texture
                .iter()
                .map(|t| format!("texture:{}", t.strip_prefix("texture:").unwrap_or(t)))
                .chain(
                    args.points.iter().map(|p| format!("points:{}", p.strip_prefix("points:").unwrap_or(p))),
                )
                .collect(),
            files_dir: std::env::current_dir().ok(),
            cameras: args.camera_path.clone(),
            denoiser: args.denoiser.clone(),
        },
    };
    let setup = set_up(&request)?;
    // What is measured, and at what size and why, before minutes of work, and again with the answer
    // (once with --from, which renders nothing: with the answer).
    let [w, h] = setup.loaded.spec.resolution.unwrap_or([0, 0]);
    let about = format!("{}\n{}", crate::load::summary(&setup.loaded.scenes[0], w, h), setup.choice);
    if !args.common.quiet && args.from.is_none() {
        eprintln!("{about}");
    }
    // Each pipeline's advice in a folder of its own: `out/advise-room`, `out/advise-room-svgf`.
    let default_out = || outdir::advise_default(&setup.stem, &request.pipeline.to_string());
    let out = args.out.clone().or_else(|| args.from.clone()).unwrap_or_else(default_out);
    outdir::check_advise_out(&out)?;
    if args.from.is_none() {
        refuse_another_question(&request, &out, &default_out())?;
    }
    let stage_at = outdir::advise_stage(&out)?;
    let threads = crate::jobs::Threads::resolve(args.common.threads);
    let workers = threads.workers;
    let spec = &setup.loaded.spec;
    let protocol = threads.protocol(None, spec);

    // Earlier records: --from's directory, the output directory's, a killed run's stage.
    let mut sources: Vec<PathBuf> = Vec::new();
    for dir in [args.from.clone(), Some(out.clone()), Some(stage_at.clone())].into_iter().flatten() {
        if crate::io::exists(&dir) && !sources.contains(&dir) {
            sources.push(dir);
        }
    }
    let mut previous: HashMap<String, JobResult> = HashMap::new();
    for dir in &sources {
        previous.extend(outdir::previous_results(dir)?);
    }
    // What it will cost, before any work: refused over --max-minutes (exit 2, nothing written).
    if args.from.is_none() {
        let todo = forecast::left(&setup.plan, previous.values());
        let finalists = forecast::Finalists {
            replicates: analysis::verify_replicates(spec.replicates),
            frames: request.frames,
            budgets_s: args.budget_ms.iter().map(|b| b * 1e-3).collect(),
            default_budgets: request.pipeline == crate::denoise::Pipeline::RAW,
            sweep_images: keeps_sweep_images(&setup),
        };
        let (f, cal) =
            forecast::advise(&setup.loaded, &setup.plan, &todo, &setup.reference_dir, &finalists, workers)?;
        f.check(args.max_minutes).map_err(|e| Error::Usage(format!("{}\n{e}", f.line("advise"))))?;
        if !args.common.quiet {
            eprintln!("{}", f.line("advise"));
        }
        if !args.budget_ms.is_empty() {
            refuse_impossible(&setup, &cal, &args.budget_ms)?;
        }
    }
    let runner = JobRunner::new(threads, args.common.quiet)?;
    let policy = if args.from.is_some() { Policy::ReuseOnly } else { Policy::ReuseOrBuild };
    let reference = crate::jobs::reference::obtain(
        spec,
        0,
        &setup.loaded.scenes[0],
        &setup.reference_dir,
        policy,
        &runner,
    )?;
    // The moving cameras' frames' references, as `run` obtains them.
    let views = crate::jobs::reference::obtain_views(
        spec,
        &setup.plan,
        &setup.loaded.scenes,
        |_| 0,
        &setup.reference_dir,
        policy,
        &runner,
    )?;

    let stage = outdir::begin_advise_stage(&out, &sources.iter().map(PathBuf::as_path).collect::<Vec<_>>())?;
    outdir::write_advise_request(&stage, &request.to_json())?;
    let store = sweep::Store::new(&stage, &previous);
    // After a signal: the finished jobs are kept in the stage (written out now, not at the next
    // periodic write), and a rerun of the same command resumes from them.
    crate::interrupt::saves_to(&stage);
    let kept = |e: Error| {
        if matches!(e, Error::Interrupted(_)) {
            let _ = store.write(&[], true);
        }
        e
    };

    let (results, mut session) = match &args.from {
        Some(dir) => sweep::stored(&setup.loaded, &setup.plan, &reference, &previous, &stage, dir)?,
        None => {
            // After a real-time pipeline the sweep's images are kept: the bias/noise split of each
            // configuration (`jobs::replicates`) and the page's final frames read them.
            let keep_images = keeps_sweep_images(&setup);
            let keep = |_: usize, job: &crate::plan::Job, o: &crate::render::RenderOutput| {
                if !keep_images {
                    return Ok(String::new());
                }
                let p = executor::provenance(&spec.name, job, &setup.loaded.scenes[0], &reference, o);
                outdir::write_image(&stage, job, o, &p)
            };
            let write = |s: &executor::Saved| store.write(s.new, false);
            let jobs = executor::Jobs {
                loaded: &setup.loaded,
                plan: &setup.plan,
                references: std::slice::from_ref(&reference),
                views: &views,
                previous: &previous,
                out: &stage,
                protocol,
                bar: &runner.bar,
                label: "sweep",
                write: &write,
            };
            let ran = executor::measure_jobs(&jobs, &keep).map_err(kept)?;
            (ran.0, ran.1)
        }
    };
    store.add(&results)?;
    if session.renders == 0 {
        session.overhead = outdir::previous_overhead(sources.first().map_or(&stage, |d| d), spec);
    }
    let stored = results.clone();
    // What advise ranks: the images after the pipeline, at the time of one frame (`as_ranked`).
    let results = as_ranked(&results).map_err(Error::Refused)?;
    let mut analysis = analysis::analyse(&setup, &results, &args.budget_ms);
    if !analysis.per_ray.is_empty() {
        analysis.sampler_ns = crate::jobs::sampler_cost::of_rows(&setup.rows, &setup.rays);
    }
    let replicates = analysis::verify_replicates(spec.replicates);
    let vplan = setup::verify_jobs(spec, &analysis::finalists(&analysis), replicates);
    let (verified, verify_session) = if args.from.is_some() {
        (sweep::present(&setup.loaded, &vplan, &reference, &previous, &stage), None)
    } else {
        let keep = |_: usize, job: &crate::plan::Job, o: &crate::render::RenderOutput| {
            let (_, scene) = setup.loaded.scene_of(job);
            let p = executor::provenance(&setup.loaded.spec.name, job, scene, &reference, o);
            outdir::write_image(&stage, job, o, &p)
        };
        let write = |s: &executor::Saved| store.write(s.new, false);
        let jobs = executor::Jobs {
            loaded: &setup.loaded,
            plan: &vplan,
            references: std::slice::from_ref(&reference),
            views: &Default::default(),
            previous: &previous,
            out: &stage,
            protocol,
            bar: &runner.bar,
            label: "finalists",
            write: &write,
        };
        let (r, s) = executor::measure_jobs(&jobs, &keep).map_err(kept)?;
        (r.into_iter().map(Some).collect(), Some(s))
    };
    runner.bar.finish_and_clear();
    let errors = sweep::error_images(&vplan, &verified, &reference, &stage)?;
    let verified: Vec<JobResult> = verified.into_iter().flatten().collect();
    store.add(&verified)?;
    let verified = still_independent(&as_ranked(&verified).map_err(Error::Refused)?);
    // Rendered: what the sessions rendered; with --from nothing is (the records are all reused).
    let rendered = results.len() - session.reused
        + verify_session.as_ref().map_or(0, |s| verified.len().saturating_sub(s.reused));
    let reused = results.len() + verified.len() - rendered;
    analysis::measure(&mut analysis, &verified, replicates);
    outdir::write_timing(&stage, &session.timing(spec, protocol))?;
    let images = |r: &JobResult| outdir::record_image(&stage, r);
    let tiles = tiles_png(&setup)?;
    let measured = Measured {
        setup: &setup,
        reference: &reference,
        views: &views,
        images: &images,
        stored,
        rendered,
        reused,
        results,
        verified,
        errors,
        replicates,
        session,
        verify_session,
        protocol,
        from: args.from.clone(),
        tiles,
    };
    analysis.maps = analysis::winner_maps(&measured, &analysis);
    let report = crate::report::advise::report(&measured, &analysis, &out)?;
    outdir::write_files(&stage, &report.files, &report.stale)?;
    outdir::commit_advise_stage(&stage, &out)?;
    for w in &report.warnings {
        eprintln!("{w}");
    }
    println!("{about}");
    print!("{}", report.text);
    Ok(())
}

/// The request checked on its own, then with what it names loaded here, where files are read: the
/// scene (its warnings printed) and the references stored for it (`reference::store`).
fn set_up(request: &Request) -> Result<Setup> {
    let checked = setup::check(request)?;
    let scene = load_scene(&request.scene)?;
    if let Some(w) = dropped_warning(&scene) {
        eprintln!("{w}");
    }
    let reference_dir = refs::dir_of_scene(request.reference_dir.as_deref(), &request.scene, &scene)?;
    let stored = refs::stored_of_scene(&reference_dir, &scene)?;
    let setup = setup::setup(request, checked, setup::Inputs { scene, reference_dir, stored })?;
    // A camera path that leaves the scene's view, a denoiser that cannot run: refused now.
    crate::load::check_realtime(&setup.loaded.spec, &setup.loaded.scenes)?;
    Ok(setup)
}

/// Under tiles, the scene's frame with its tiles outlined (`tiles.png`), as `run` draws it.
fn tiles_png(setup: &Setup) -> Result<Option<outdir::File>> {
    let (spec, scene) = (&setup.loaded.spec, &setup.loaded.scenes[0]);
    let Some(t) = crate::jobs::tiles::of_spec(spec, 0, scene) else { return Ok(None) };
    let p = crate::jobs::tiles::preview(spec, scene);
    let png = crate::report::tiles::tiles_png(&p.ao, &p.coverage, &t.interiors, &t.windows)
        .map_err(Error::Refused)?;
    Ok(Some(outdir::File::new("tiles.png", png)))
}

/// Whether the sweep keeps its images: after a real-time pipeline (the bias/noise split and the
/// page's final frames read them), not for the paper's raw sweep of thousands of images.
fn keeps_sweep_images(setup: &Setup) -> bool {
    setup.pipeline != crate::denoise::Pipeline::RAW
}

/// Refuses (exit 2, in seconds) budgets no configuration can render an image in, naming the
/// cheapest render: a calibration of a fraction of a second instead of a sweep that would only
/// find out at its end.
fn refuse_impossible(setup: &Setup, cal: &calibrate::Calibrated, budgets_ms: &[f64]) -> Result<()> {
    let (cheapest_s, job) = calibrate::cheapest(&setup.loaded, &setup.plan, cal)?;
    let budgets_s: Vec<f64> = budgets_ms.iter().map(|b| b * 1e-3).collect();
    let low = advice::impossible(&budgets_s, cheapest_s);
    if low.is_empty() {
        return Ok(());
    }
    let [w, h] = setup.loaded.spec.resolution.unwrap_or([0, 0]);
    let ms = |s: f64| round_significant(s * 1e3, 2);
    Err(Error::Usage(format!(
        "--budget-ms {}: below the cheapest render here — {} at {} ray{} per pixel takes about {} ms per \
         image at {w}x{h} (a calibration on this machine, now, which tends to over-predict by up to a \
         third); advise can answer budgets from about {} ms (or ask for a smaller --resolution)",
        low.iter().map(|&b| ms(b).to_string()).collect::<Vec<_>>().join(","),
        job.row().label(),
        job.rays,
        if job.rays == 1 { "" } else { "s" },
        ms(cheapest_s),
        ms(cheapest_s),
    )))
}

/// Refuses an `out` that holds the advice to another question (another scene, pipeline, frame or
/// integrand): advise replaces its output directory whole, and nothing the user asked to keep is
/// lost. The same question asked again (other budgets, rays) resumes there.
fn refuse_another_question(request: &Request, out: &Path, default: &Path) -> Result<()> {
    let Ok(text) = outdir::read_advise_request(out) else { return Ok(()) };
    let Ok(earlier) = Request::from_json(&text) else { return Ok(()) };
    match request.differs_from(&earlier) {
        None => Ok(()),
        Some(what) => Err(Error::input(
            out,
            format!(
                "holds advise's answer for {what}; advise replaces its output directory whole, so give \
                 this one another --out (its default is {})",
                default.display()
            ),
        )),
    }
}
