//! The native half of the `hemilab` Python package (`python/hemilab/__init__.py` re-exports it
//! with docstrings and type hints). Every function here calls the library function the command
//! line calls for the same work, so a Python render is a `hemilab render` bit for bit, and every
//! setting is read by the command line's own parser (`args`), so that it means what the flag
//! means and is refused with the flag's message.

mod args;
mod arrays;
mod filters;
mod run;
mod sampler;
mod scene;

use pyo3::prelude::*;

pyo3::create_exception!(
    hemilab,
    Error,
    pyo3::exceptions::PyException,
    "A bad input or an unusable environment: the message is the command line's for the same input."
);

/// A hemilab error as the Python exception, with the command line's message.
pub(crate) fn error(e: impl std::fmt::Display) -> PyErr {
    Error::new_err(e.to_string())
}

#[pymodule]
fn _hemilab(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("Error", m.py().get_type::<Error>())?;
    m.add_class::<scene::Scene>()?;
    m.add_class::<scene::GBuffer>()?;
    m.add_class::<sampler::Sampler>()?;
    m.add_class::<sampler::PixelSet>()?;
    m.add_function(wrap_pyfunction!(scene::points, m)?)?;
    m.add_function(wrap_pyfunction!(scene::sequences, m)?)?;
    m.add_function(wrap_pyfunction!(filters::metrics, m)?)?;
    m.add_function(wrap_pyfunction!(filters::denoise, m)?)?;
    m.add_function(wrap_pyfunction!(run::run, m)?)?;
    m.add_function(wrap_pyfunction!(run::results_json, m)?)?;
    m.add_function(wrap_pyfunction!(run::read_exr, m)?)?;
    m.add_function(wrap_pyfunction!(sampler::register_sampler, m)?)?;
    Ok(())
}
