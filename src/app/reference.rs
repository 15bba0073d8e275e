//! Reference images: reuse a stored one only when its manifest matches what the run needs,
//! otherwise render it (unless told not to). A reference is the mean of independent renders with
//! an unbiased estimator; their spread gives the per-pixel standard error and so the noise floor.

use super::jobs::{Geometry, JobRunner};
use crate::error::{Error, Result};
use crate::image::{Channel, Image};
use crate::io;
use crate::plan;
use crate::reference::{self, Manifest};
use crate::scene::Scene;
use crate::spec::{ReferenceRays, Spec};
use std::path::{Path, PathBuf};
use std::time::Instant;

pub struct Reference {
    pub mean: Image,
    pub stderr: Image,
    pub coverage: Image,
    pub manifest: Manifest,
    pub exr: PathBuf,
}

impl Reference {
    pub fn noise_floor(&self) -> f64 {
        reference::noise_floor(&self.stderr, &self.coverage)
    }
}

/// What to do when the stored reference is missing or does not match.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Policy {
    /// Reuse a matching one, else render.
    ReuseOrBuild,
    /// Reuse a matching one, else stop with an error.
    ReuseOnly,
    /// Always render.
    Rebuild,
}

/// Rays per reference replicate for `rays = "auto"`. The smallest RMSE a spec measures is about the
/// single-render error of the best estimator at the largest ray count N; the floor of K replicates
/// at R rays is about err(R)/√K, and err falls at least as 1/√rays, so R = 100·N/K puts the floor at
/// or below a tenth of it. The run checks the claim against the measured RMSEs afterwards.
pub fn auto_rays(spec: &Spec, scene: usize) -> u32 {
    let n = spec.groups.iter().filter(|g| g.scenes.contains(&scene)).flat_map(|g| g.rays.iter()).max();
    let n = *n.unwrap_or(&64) as u64;
    let r = (100 * n).div_ceil(spec.reference.replicates.max(1) as u64);
    r.next_power_of_two().min(1 << 22) as u32
}

pub fn wanted_manifest(spec: &Spec, si: usize, scene: &Scene, geometry: Geometry) -> Manifest {
    let rays = match spec.reference.rays {
        ReferenceRays::Fixed(r) => r,
        ReferenceRays::Auto => auto_rays(spec, si),
    };
    Manifest::wanted(
        &spec.scenes[si],
        &scene.content_hash,
        &format!("{:?}", scene.view),
        [geometry.width, geometry.height],
        geometry.distance,
        spec.reference.estimator,
        rays,
        spec.reference.replicates,
        spec.reference.seed,
    )
}

fn paths(dir: &Path, manifest: &Manifest) -> (PathBuf, PathBuf) {
    let stem = manifest.file_stem();
    (dir.join(format!("{stem}.exr")), dir.join(format!("{stem}.json")))
}

/// The reference of scene `si`, from `dir` or freshly rendered into it.
pub fn obtain(
    spec: &Spec,
    si: usize,
    scene: &Scene,
    dir: &Path,
    policy: Policy,
    runner: &JobRunner,
) -> Result<Reference> {
    let geometry = Geometry::of(spec.resolution, spec.ao_distance, scene);
    let wanted = wanted_manifest(spec, si, scene, geometry);
    let (exr, json) = paths(dir, &wanted);
    if policy != Policy::Rebuild {
        match load_if_matching(spec, &wanted, &exr, &json)? {
            Ok(r) => return Ok(r),
            Err((file, why)) if policy == Policy::ReuseOnly => {
                return Err(Error::input(
                    &file,
                    format!(
                        "{why}: no usable reference for scene '{}'; run `hemilab reference {}` or drop \
                         --no-build-reference",
                        scene.name,
                        spec.path.display()
                    ),
                ));
            }
            Err((file, why)) => {
                // Fail before the (long) reference render, not after it, if it could not be saved.
                io::ensure_writable_dir(dir)?;
                eprintln!("reference for '{}': {}: {why}; rendering a new one", scene.name, file.display())
            }
        }
    }
    io::ensure_writable_dir(dir)?;
    build(spec, si, scene, wanted, &exr, &json, runner)
}

/// `Ok(Err((file, why)))` when there is nothing reusable; `Err` only for a stored file that cannot
/// be read.
fn load_if_matching(
    spec: &Spec,
    wanted: &Manifest,
    exr: &Path,
    json: &Path,
) -> Result<std::result::Result<Reference, (PathBuf, String)>> {
    for file in [json, exr] {
        if !io::exists(file) {
            return Ok(Err((file.to_path_buf(), "not found".into())));
        }
    }
    let stored = Manifest::from_json(&io::read_string(json)?)
        .map_err(|e| Error::input(json, format!("not a reference manifest: {e}")))?;
    let check = match spec.reference.rays {
        ReferenceRays::Fixed(_) => stored.matches(wanted),
        // The floor the run needs is known only after it; a reference with at least the rays `auto`
        // would spend now is as good as a new one, one with fewer (the spec grew) is not.
        ReferenceRays::Auto => stored.matches_auto(wanted, f64::INFINITY).and_then(|()| {
            let total = |m: &Manifest| m.rays as u64 * m.replicates as u64;
            if total(&stored) >= total(wanted) {
                return Ok(());
            }
            Err(vec![format!(
                "rays: stored {} x {}, wanted at least {} x {} for rays = \"auto\"",
                stored.replicates, stored.rays, wanted.replicates, wanted.rays
            )])
        }),
    };
    if let Err(diffs) = check {
        return Ok(Err((json.to_path_buf(), format!("does not match ({})", diffs.join("; ")))));
    }
    let channels = io::read_exr(exr)?;
    let take = |name: &str| {
        channels
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, img)| img.clone())
            .ok_or_else(|| Error::input(exr, format!("reference lacks channel '{name}'")))
    };
    let (mean, stderr, coverage) = (take("Y")?, take("stderr")?, take("A")?);
    if mean.width != wanted.resolution[0] || mean.height != wanted.resolution[1] {
        return Ok(Err((exr.to_path_buf(), "has the wrong size".into())));
    }
    Ok(Ok(Reference { mean, stderr, coverage, manifest: stored, exr: exr.to_path_buf() }))
}

fn build(
    spec: &Spec,
    si: usize,
    scene: &Scene,
    mut manifest: Manifest,
    exr: &Path,
    json: &Path,
    runner: &JobRunner,
) -> Result<Reference> {
    let jobs = plan::reference_jobs(spec, si, manifest.rays);
    let start = Instant::now();
    let mut images = Vec::with_capacity(jobs.len());
    let mut coverage = None;
    for (i, job) in jobs.iter().enumerate() {
        let label = format!("reference {}/{}", i + 1, jobs.len());
        let done = runner.render(job, scene, &label)?;
        coverage.get_or_insert(done.output.coverage);
        images.push(done.output.ao);
    }
    let coverage =
        coverage.ok_or_else(|| Error::Refused("a reference needs at least one replicate".into()))?;
    let (mean, stderr) = reference::mean_and_stderr(&images).map_err(Error::Refused)?;
    manifest.noise_floor = Some(reference::noise_floor(&stderr, &coverage));
    manifest.time_s = Some(start.elapsed().as_secs_f64());
    // Image first, manifest last: a crash in between leaves no manifest, so nothing stale is reused.
    io::write_exr(
        exr,
        &[
            Channel { name: "Y", image: &mean },
            Channel { name: "stderr", image: &stderr },
            Channel { name: "A", image: &coverage },
        ],
    )?;
    io::write_atomic(json, manifest.to_json().as_bytes())?;
    eprintln!(
        "reference for '{}': {} x {} rays, noise floor {:.2e}, {:.1} s → {}",
        scene.name,
        manifest.replicates,
        manifest.rays,
        manifest.noise_floor.unwrap_or(0.0),
        manifest.time_s.unwrap_or(0.0),
        exr.display()
    );
    Ok(Reference { mean, stderr, coverage, manifest, exr: exr.to_path_buf() })
}
