//! `Scene` (load, render, G-buffer, stored reference) and `points`: the work of `hemilab render`
//! and `hemilab points`, through the functions those commands call.

use crate::args::{Line, resolution};
use crate::arrays::{Array, image, image_rgb};
use crate::error;
use glam::Vec2;
use hemilab::cli::Command;
use hemilab::jobs::Threads;
use hemilab::load;
use hemilab::reference::store as refs;
use hemilab::render::{self, RenderJob};
use numpy::PyArray2;
use pyo3::prelude::*;
use std::path::PathBuf;
use std::sync::Arc;

/// A scene file loaded once (mesh, camera, BVH), to render, trace a G-buffer of, or find the
/// stored reference of, at any size.
#[pyclass(frozen, module = "hemilab")]
pub struct Scene {
    scene: Arc<hemilab::scene::Scene>,
    path: PathBuf,
}

/// A G-buffer: what each pixel's primary ray hit (`render::GBuffer`), to guide `denoise`.
#[pyclass(frozen, module = "hemilab")]
pub struct GBuffer {
    pub inner: Arc<render::GBuffer>,
}

#[pymethods]
impl Scene {
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let scene = py.detach(|| load::load_scene(&path)).map_err(error)?;
        if let Some(w) = load::dropped_warning(&scene) {
            eprintln!("{w}");
        }
        Ok(Self { scene: Arc::new(scene), path })
    }

    #[getter]
    fn name(&self) -> &str {
        &self.scene.name
    }

    #[getter]
    fn path(&self) -> PathBuf {
        self.path.clone()
    }

    #[getter]
    fn resolution(&self) -> (u32, u32) {
        self.scene.resolution
    }

    #[getter]
    fn ao_distance(&self) -> f32 {
        self.scene.ao_distance
    }

    #[getter]
    fn content_hash(&self) -> &str {
        &self.scene.content_hash
    }

    fn __repr__(&self) -> String {
        let (w, h) = self.scene.resolution;
        format!(
            "Scene('{}', {}, {w}x{h}, d = {})",
            self.scene.name,
            self.path.display(),
            self.scene.ao_distance
        )
    }

    /// `hemilab render SCENE --rays ... ` without the files: (AO, coverage) as float32 (H, W).
    #[pyo3(signature = (rays, distribution=None, sequence=None, seed_mode=None, seed=None, resolution=None, frame=None, schedule=None, integrand=None, threads=None))]
    #[allow(clippy::too_many_arguments)]
    fn render<'py>(
        &self,
        py: Python<'py>,
        rays: i64,
        distribution: Option<String>,
        sequence: Option<String>,
        seed_mode: Option<String>,
        seed: Option<i128>,
        resolution: Option<(u32, u32)>,
        frame: Option<i64>,
        schedule: Option<String>,
        integrand: Option<String>,
        threads: Option<i64>,
    ) -> PyResult<(Array<'py>, Array<'py>)> {
        let line = Line::new("render")
            .flag("rays", rays)
            .opt("distribution", distribution)
            .opt("sequence", sequence)
            .opt("seed-mode", seed_mode)
            .opt("seed", seed)
            .opt("resolution", crate::args::resolution(resolution))
            .opt("frame", frame)
            .opt("schedule", schedule)
            .opt("integrand", integrand)
            .opt("threads", threads)
            .flag("output", "python.exr")
            .arg(self.path.display());
        let Command::Render(args) = line.parse()? else { unreachable!("a render line parses as render") };
        let s = &args.sampling;
        let (_, sampler) = hemilab::app::sampler(
            s.distribution,
            &s.sequence,
            &s.seed_mode,
            s.seed,
            &s.frames,
            args.rays,
            "--rays",
        )
        .map_err(error)?;
        let (width, height) = load::image_size(&self.path, &self.scene, args.resolution).map_err(error)?;
        let job = RenderJob {
            distribution: s.distribution,
            sampler,
            width,
            height,
            ao_distance: self.scene.ao_distance,
        };
        let scene = self.scene.clone();
        let pool = Threads::resolve(args.common.threads).pool().map_err(error)?;
        let integrand = args.integrand;
        // The GIL is released while rendering: other Python threads run, and a Python sampler's
        // calls from the render's threads take it one at a time.
        let out = py.detach(move || {
            job.sampler.prepare();
            pool.install(|| render::render_integrand(&scene, &job, integrand, &|_| {}))
        });
        crate::sampler::check_after(py)?;
        Ok((image(py, &out.ao)?, image(py, &out.coverage)?))
    }

    /// The G-buffer at `resolution` (default: the scene's), as `render` traces it.
    #[pyo3(signature = (resolution=None))]
    fn gbuffer(&self, py: Python<'_>, resolution: Option<(u32, u32)>) -> PyResult<GBuffer> {
        let (width, height) = self.size(resolution)?;
        let scene = self.scene.clone();
        let g = py.detach(move || render::gbuffer(&scene, width, height));
        Ok(GBuffer { inner: Arc::new(g) })
    }

    /// The stored reference of this scene at `resolution` as `hemilab advise` finds it:
    /// (mean, coverage, standard error, manifest JSON).
    #[pyo3(signature = (resolution=None, reference_dir=None))]
    fn reference<'py>(
        &self,
        py: Python<'py>,
        resolution: Option<(u32, u32)>,
        reference_dir: Option<PathBuf>,
    ) -> PyResult<(Array<'py>, Array<'py>, Array<'py>, String)> {
        let (width, height) = self.size(resolution)?;
        let dir = refs::dir_of_scene(reference_dir.as_deref(), &self.path, &self.scene).map_err(error)?;
        let d = hemilab::plan::Geometry::of(None, None, &self.scene).distance.canonical();
        let stored = refs::stored_of_scene(&dir, &self.scene).map_err(error)?;
        // The AO reference of this size and distance with the lowest noise floor.
        let best = stored
            .into_iter()
            .filter(|(m, _)| m.resolution == [width, height] && m.ao_distance == d && m.integrand == "ao")
            .filter(|(m, _)| !m.jitter_average)
            .min_by(|a, b| {
                a.0.noise_floor.unwrap_or(f64::MAX).total_cmp(&b.0.noise_floor.unwrap_or(f64::MAX))
            });
        let Some((manifest, exr)) = best else {
            return Err(error(format!(
                "{}: no stored reference of '{}' at {width}x{height} (d = {d}) in {}; `hemilab advise {}` or \
                 `hemilab reference SPEC` builds one",
                self.path.display(),
                self.scene.name,
                dir.display(),
                self.path.display()
            )));
        };
        let channels = py.detach(|| hemilab::io::read_exr(&exr)).map_err(error)?;
        let get = |name: &str| {
            channels
                .iter()
                .find(|(n, _)| n == name)
                .map(|(_, i)| i.clone())
                .ok_or_else(|| error(format!("{}: no channel '{name}'", exr.display())))
        };
        let (mean, coverage, stderr) = (get("Y")?, get("A")?, get("stderr")?);
        Ok((image(py, &mean)?, image(py, &coverage)?, image(py, &stderr)?, manifest.to_json()))
    }
}

impl Scene {
    fn size(&self, r: Option<(u32, u32)>) -> PyResult<(u32, u32)> {
        // The resolution through `--resolution`'s own parser, then the loader's size rule.
        let r = match r {
            Some(_) => {
                Some(hemilab::cli::parse_resolution(&resolution(r).unwrap_or_default()).map_err(error)?)
            }
            None => None,
        };
        load::image_size(&self.path, &self.scene, r).map_err(error)
    }
}

#[pymethods]
impl GBuffer {
    #[getter]
    fn width(&self) -> u32 {
        self.inner.width
    }

    #[getter]
    fn height(&self) -> u32 {
        self.inner.height
    }

    #[getter]
    fn depth<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        image(py, &self.inner.depth)
    }

    #[getter]
    fn coverage<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        image(py, &self.inner.coverage)
    }

    #[getter]
    fn normal<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray3<f32>>> {
        image_rgb(py, self.inner.width, self.inner.height, &self.inner.normal)
    }

    fn __repr__(&self) -> String {
        format!("GBuffer({}x{})", self.inner.width, self.inner.height)
    }
}

/// `hemilab points` without the picture: pixel (x, y)'s points (n, 2) and directions (n, 3).
#[pyfunction]
#[pyo3(signature = (distribution, sequence, seed_mode=None, n=64, pixel=(0, 0), width=None, frame=None, schedule=None, seed=None))]
#[allow(clippy::too_many_arguments)]
pub fn points<'py>(
    py: Python<'py>,
    distribution: String,
    sequence: String,
    seed_mode: Option<String>,
    n: i64,
    pixel: (u32, u32),
    width: Option<u32>,
    frame: Option<i64>,
    schedule: Option<String>,
    seed: Option<i128>,
) -> PyResult<(Array<'py>, Array<'py>)> {
    let line = Line::new("points")
        .flag("distribution", distribution)
        .flag("sequence", sequence)
        .opt("seed-mode", seed_mode)
        .flag("count", n)
        .opt("frame", frame)
        .opt("schedule", schedule)
        .opt("seed", seed)
        .flag("output", "python.png");
    let Command::Points(args) = line.parse()? else { unreachable!("a points line parses as points") };
    let (_, config) = hemilab::app::sampler(
        args.distribution,
        &args.sequence,
        &args.seed_mode,
        args.seed,
        &args.frames,
        args.count,
        "--count",
    )
    .map_err(error)?;
    let (x, y) = pixel;
    let index = match width {
        Some(w) if x >= w => {
            return Err(error(format!("pixel ({x}, {y}) is outside an image {w} pixels wide")));
        }
        Some(w) => y as u64 * w as u64 + x as u64,
        None if y == 0 => x as u64,
        None => {
            return Err(error(format!(
                "pixel ({x}, {y}): a pixel below the first row needs width= (its index is y * width + x)"
            )));
        }
    };
    let distribution = args.distribution;
    let (pts, dirs) = py.detach(move || {
        config.prepare();
        let mut pts = vec![Vec2::ZERO; config.count as usize];
        config.fill_pixel(x, y, index, &mut pts);
        let dirs: Vec<glam::Vec3> = pts.iter().map(|&u| distribution.sample(u).dir).collect();
        (pts, dirs)
    });
    crate::sampler::check_after(py)?;
    let n = pts.len();
    let flat_p: Vec<f32> = pts.iter().flat_map(|p| [p.x, p.y]).collect();
    let flat_d: Vec<f32> = dirs.iter().flat_map(|d| [d.x, d.y, d.z]).collect();
    Ok((crate::arrays::matrix(py, n, 2, flat_p)?, crate::arrays::matrix(py, n, 3, flat_d)?))
}

/// Every sequence name specs and flags accept (built-in, then registered).
#[pyfunction]
pub fn sequences() -> Vec<&'static str> {
    hemilab::sampling::Sequence::names()
}
