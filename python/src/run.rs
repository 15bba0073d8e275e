//! `hemilab run` from Python, and the files a run writes read back (results, EXR images).

use crate::args::Line;
use crate::arrays::image;
use crate::error;
use hemilab::cli::Command;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::{Path, PathBuf};

/// `hemilab run SPEC [--out DIR] ...` through the command's own code (`app::run`), with the GIL
/// released; returns the output directory.
#[pyfunction]
#[pyo3(signature = (spec, out=None, reference_dir=None, force=false, no_build_reference=false, timing_repeats=None, threads=None, quiet=true))]
#[allow(clippy::too_many_arguments)]
pub fn run(
    py: Python<'_>,
    spec: PathBuf,
    out: Option<PathBuf>,
    reference_dir: Option<PathBuf>,
    force: bool,
    no_build_reference: bool,
    timing_repeats: Option<i64>,
    threads: Option<i64>,
    quiet: bool,
) -> PyResult<PathBuf> {
    let line = Line::new("run")
        .opt("out", out.as_ref().map(|p| p.display()))
        .opt("reference-dir", reference_dir.as_ref().map(|p| p.display()))
        .switch("force", force)
        .switch("no-build-reference", no_build_reference)
        .opt("timing-repeats", timing_repeats)
        .opt("threads", threads)
        .switch("quiet", quiet)
        .arg(spec.display());
    let command = line.parse()?;
    let Command::Run(args) = &command else { unreachable!("a run line parses as run") };
    let out = match &args.out {
        Some(o) => o.clone(),
        None => Path::new("out").join(spec_name(&spec)?),
    };
    let cli = hemilab::cli::Cli { command };
    py.detach(|| hemilab::app::run(cli)).map_err(error)?;
    crate::sampler::check_after(py)?;
    Ok(out)
}

/// The spec's `name` (its default output directory's), from the spec as `hemilab run` reads it.
fn spec_name(spec: &Path) -> PyResult<String> {
    let text = hemilab::load::read_named(spec, "spec").map_err(error)?;
    let dir = spec.parent().unwrap_or(Path::new(""));
    let files = hemilab::load::SpecFiles { dir };
    Ok(hemilab::spec::parse_spec_with(&text, spec, &files).map_err(error)?.name)
}

/// A run's records (`results.json`, or `results.csv`, as `merge` and `advise --from` read them)
/// as JSON text.
#[pyfunction]
pub fn results_json(py: Python<'_>, dir: PathBuf) -> PyResult<String> {
    let records = py
        .detach(|| {
            hemilab::outdir::read_results(&dir, &|e| {
                format!("{e}; a `hemilab run` output directory holds results.json")
            })
        })
        .map_err(error)?;
    if records.is_empty() && !hemilab::io::exists(&dir.join("results.json")) {
        return Err(error(format!(
            "{}: no results.json here; `hemilab run SPEC --out DIR` writes one",
            dir.display()
        )));
    }
    Ok(hemilab::results::to_json(&records))
}

/// Every channel of an EXR file hemilab wrote (render's `Y` and `A`, a reference's `stderr`), as
/// (H, W) float32 arrays by name.
#[pyfunction]
pub fn read_exr<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyDict>> {
    let channels = py.detach(|| hemilab::io::read_exr(&path)).map_err(error)?;
    let d = PyDict::new(py);
    for (name, img) in &channels {
        d.set_item(name, image(py, img)?)?;
    }
    Ok(d)
}
