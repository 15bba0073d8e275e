//! The error measures of `metrics` and the frame filters of `denoise`, on numpy arrays.

use crate::arrays::{image, to_image};
use crate::error;
use crate::scene::GBuffer;
use hemilab::denoise::Pipeline;
use hemilab::denoise::motion::Motion;
use numpy::{PyArray2, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Every error statistic `hemilab run` records for an image (`metrics::measure`, and the mean
/// LDR-FLIP at 67 pixels per degree, `metrics::flip`), as a dict.
#[pyfunction]
pub fn metrics<'py>(
    py: Python<'py>,
    image: PyReadonlyArray2<'py, f32>,
    reference: PyReadonlyArray2<'py, f32>,
    coverage: PyReadonlyArray2<'py, f32>,
) -> PyResult<Bound<'py, PyDict>> {
    let (img, reference, coverage) =
        (to_image(&image, "image")?, to_image(&reference, "reference")?, to_image(&coverage, "coverage")?);
    let (s, flip) = py
        .detach(|| {
            let s = hemilab::metrics::measure(&img, &reference, &coverage)?;
            let map =
                hemilab::metrics::flip::ldr_flip_map(&reference, &img, hemilab::metrics::flip::DEFAULT_PPD);
            Ok::<_, hemilab::metrics::MetricsError>((s, hemilab::metrics::flip::mean_flip(&map, &coverage)))
        })
        .map_err(error)?;
    let d = PyDict::new(py);
    d.set_item("covered", s.covered)?;
    d.set_item("rmse", s.rmse)?;
    d.set_item("bias", s.bias)?;
    d.set_item("autocorr_x", s.autocorr_x)?;
    d.set_item("autocorr_y", s.autocorr_y)?;
    d.set_item("lowpass_rmse", s.lowpass_rmse)?;
    d.set_item("whiteness_z", s.whiteness_z)?;
    d.set_item("lowfreq_ratio", s.lowfreq_ratio)?;
    d.set_item("flip", flip)?;
    Ok(d)
}

/// A still camera's frames through `pipeline` (`Pipeline::start`, as a run pushes them): the
/// output after each frame.
#[pyfunction]
pub fn denoise<'py>(
    py: Python<'py>,
    frames: Vec<PyReadonlyArray2<'py, f32>>,
    pipeline: &str,
    gbuffer: &GBuffer,
) -> PyResult<Vec<Bound<'py, PyArray2<f32>>>> {
    let pipeline: Pipeline = hemilab::cli::parse_pipeline(pipeline).map_err(error)?;
    let g = gbuffer.inner.clone();
    let frames = frames
        .iter()
        .enumerate()
        .map(|(i, f)| {
            let img = to_image(f, &format!("frames[{i}]"))?;
            if (img.width, img.height) != (g.width, g.height) {
                return Err(error(format!(
                    "frames[{i}] is {}x{} but the G-buffer is {}x{}; every frame must be the G-buffer's size",
                    img.width, img.height, g.width, g.height
                )));
            }
            Ok(img)
        })
        .collect::<PyResult<Vec<_>>>()?;
    let out = py.detach(move || {
        let motion = Motion::identity(g.width, g.height);
        let mut run = pipeline.start(g.width, g.height);
        frames.iter().map(|f| run.push(f, &g, &motion)).collect::<Vec<_>>()
    });
    out.iter().map(|i| image(py, i)).collect()
}
