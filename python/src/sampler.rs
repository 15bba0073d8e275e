//! A Python callable as a sampler: registered like the Rust extension point
//! (`hemilab::sampling::register`, `examples/external_sampler.rs`), then named by `render`,
//! `points` and the specs `run` reads like any built-in sequence. The renderer's threads call it
//! one at a time (each takes the GIL for its call); the time spent inside it is counted apart
//! (`Sampler.seconds`), since it is Python's cost, not the sampler's.

use crate::error;
use glam::Vec2;
use hemilab::sampling::hash::fix_to_f32;
use hemilab::sampling::{PixelSet as RustSet, PointSequence, SequenceInfo};
use numpy::{PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use std::collections::HashMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, OnceLock, RwLock};
use std::time::Instant;

/// What a registered Python sampler shares with the handle Python holds.
struct Shared {
    name: &'static str,
    callable: RwLock<Py<PyAny>>,
    calls: AtomicU64,
    nanos: AtomicU64,
}

/// The first failure of a Python sampler during a call into hemilab (an exception, a wrong shape,
/// a point outside [0, 1)²): raised as `hemilab.Error` when the call returns.
static FAILURE: Mutex<Option<String>> = Mutex::new(None);

/// The samplers registered from Python, by name: registering a name again replaces the callable
/// (a notebook cell run twice), since the crate's list keeps every sequence for the process.
static REGISTERED: OnceLock<Mutex<HashMap<String, Arc<Shared>>>> = OnceLock::new();

struct PySequence {
    info: SequenceInfo,
    shared: Arc<Shared>,
}

/// One pixel's point set as the sampler sees it (`hemilab::sampling::PixelSet`).
#[pyclass(frozen, module = "hemilab")]
pub struct PixelSet {
    /// Points in the whole set (strata and lattice spacing follow it).
    #[pyo3(get)]
    count: u32,
    /// Points wanted: the first `n` of the `count`-point set.
    #[pyo3(get)]
    n: usize,
    #[pyo3(get)]
    x: u32,
    #[pyo3(get)]
    y: u32,
    /// The pixel's index (y * width + x).
    #[pyo3(get)]
    pixel: u64,
    /// The set's key: fresh per pixel under `shift`, the run's under every other seed mode.
    #[pyo3(get)]
    key: u64,
    /// Offsets in [0, 1)² to add mod 1: the seed mode's (a rotation's, a mask's) with the frame
    /// schedule's; only the schedule's under `shift`.
    #[pyo3(get)]
    offset: (f32, f32),
    #[pyo3(get)]
    seed_mode: &'static str,
}

#[pymethods]
impl PixelSet {
    fn __repr__(&self) -> String {
        format!(
            "PixelSet(count={}, n={}, x={}, y={}, pixel={}, key={}, offset={:?}, seed_mode='{}')",
            self.count, self.n, self.x, self.y, self.pixel, self.key, self.offset, self.seed_mode
        )
    }
}

/// A Python sampler's handle: its name (for specs and `sequence=`) and its measured cost.
#[pyclass(frozen, module = "hemilab")]
pub struct Sampler {
    shared: Arc<Shared>,
}

#[pymethods]
impl Sampler {
    #[getter]
    fn name(&self) -> &'static str {
        self.shared.name
    }

    /// Calls so far (one per pixel and image).
    #[getter]
    fn calls(&self) -> u64 {
        self.shared.calls.load(Ordering::Relaxed)
    }

    /// Seconds spent inside the callable so far (with the GIL held; not the renderer's time).
    #[getter]
    fn seconds(&self) -> f64 {
        self.shared.nanos.load(Ordering::Relaxed) as f64 * 1e-9
    }

    /// Sets `calls` and `seconds` back to 0.
    fn reset(&self) {
        self.shared.calls.store(0, Ordering::Relaxed);
        self.shared.nanos.store(0, Ordering::Relaxed);
    }

    fn __repr__(&self) -> String {
        format!("Sampler('{}', {} calls, {:.3} s)", self.shared.name, self.calls(), self.seconds())
    }
}

impl PointSequence for PySequence {
    fn info(&self) -> &SequenceInfo {
        &self.info
    }

    fn fill(&self, set: &RustSet, out: &mut [Vec2]) {
        let result = Python::attach(|py| {
            let callable = self.shared.callable.read().unwrap_or_else(|e| e.into_inner()).clone_ref(py);
            let (key, dx, dy) = set.keyed();
            let arg = PixelSet {
                count: set.count,
                n: out.len(),
                x: set.x,
                y: set.y,
                pixel: set.pixel,
                key,
                offset: (fix_to_f32(dx), fix_to_f32(dy)),
                seed_mode: set.seed_mode.name(),
            };
            let start = Instant::now();
            let r = call(py, &callable, arg, out);
            self.shared.nanos.fetch_add(start.elapsed().as_nanos() as u64, Ordering::Relaxed);
            self.shared.calls.fetch_add(1, Ordering::Relaxed);
            r
        });
        if let Err(e) = result {
            // Keep going with a neutral point (the image is refused after the call), first error kept.
            out.fill(Vec2::splat(0.5));
            let mut f = FAILURE.lock().unwrap_or_else(|e| e.into_inner());
            if f.is_none() {
                *f = Some(format!("sampler '{}' at pixel ({}, {}): {e}", self.shared.name, set.x, set.y));
            }
        }
    }
}

/// Calls the sampler and writes its first `out.len()` points, refusing a wrong shape or a point
/// outside [0, 1)².
fn call(py: Python<'_>, f: &Py<PyAny>, arg: PixelSet, out: &mut [Vec2]) -> Result<(), String> {
    let n = out.len();
    let value = f.call1(py, (arg,)).map_err(|e| e.to_string())?;
    let value = value.bind(py);
    let shape = |s: &[usize]| -> Result<(), String> {
        if s.len() == 2 && s[1] == 2 {
            Ok(())
        } else {
            Err(format!("returned an array of shape {s:?}; (n, 2) wanted"))
        }
    };
    let points: Vec<[f64; 2]> = if let Ok(a) = value.extract::<PyReadonlyArray2<'_, f64>>() {
        shape(a.shape())?;
        a.as_array().rows().into_iter().map(|r| [r[0], r[1]]).collect()
    } else if let Ok(a) = value.extract::<PyReadonlyArray2<'_, f32>>() {
        shape(a.shape())?;
        a.as_array().rows().into_iter().map(|r| [r[0] as f64, r[1] as f64]).collect()
    } else {
        value
            .extract::<Vec<[f64; 2]>>()
            .map_err(|_| format!("returned {}, not an (n, 2) array of points", type_name(value)))?
    };
    if points.len() < n {
        return Err(format!("returned {} points; {n} wanted (an (n, 2) array)", points.len()));
    }
    for (o, p) in out.iter_mut().zip(&points) {
        let ok = p.iter().all(|v| (0.0..1.0).contains(v));
        if !ok {
            return Err(format!("returned the point ({}, {}), outside [0, 1)²", p[0], p[1]));
        }
        *o = Vec2::new(p[0] as f32, p[1] as f32).min(Vec2::splat(1.0 - f32::EPSILON / 2.0));
    }
    Ok(())
}

fn type_name(v: &Bound<'_, PyAny>) -> String {
    v.get_type().name().map(|n| n.to_string()).unwrap_or_else(|_| "an object".into())
}

/// Raises the first failure of a Python sampler since the last check, if any.
pub fn check_after(_py: Python<'_>) -> PyResult<()> {
    match FAILURE.lock().unwrap_or_else(|e| e.into_inner()).take() {
        Some(e) => Err(error(e)),
        None => Ok(()),
    }
}

/// Registers `fill` as the sequence `name` (lower-case letters, digits and '-'), as
/// `hemilab::sampling::register` does a Rust one; the same name again replaces the callable.
#[pyfunction]
#[pyo3(signature = (name, fill, label=None))]
pub fn register_sampler(
    py: Python<'_>,
    name: &str,
    fill: Py<PyAny>,
    label: Option<&str>,
) -> PyResult<Sampler> {
    if !fill.bind(py).is_callable() {
        return Err(error(format!(
            "register_sampler('{name}', ...): fill must be callable (PixelSet -> (n, 2) points)"
        )));
    }
    let mut map = REGISTERED.get_or_init(Default::default).lock().unwrap_or_else(|e| e.into_inner());
    if let Some(shared) = map.get(name) {
        *shared.callable.write().unwrap_or_else(|e| e.into_inner()) = fill;
        shared.calls.store(0, Ordering::Relaxed);
        shared.nanos.store(0, Ordering::Relaxed);
        return Ok(Sampler { shared: shared.clone() });
    }
    let name: &'static str = Box::leak(name.to_string().into_boxed_str());
    let label: &'static str = Box::leak(label.unwrap_or(name).to_string().into_boxed_str());
    let shared = Arc::new(Shared {
        name,
        callable: RwLock::new(fill),
        calls: AtomicU64::new(0),
        nanos: AtomicU64::new(0),
    });
    let info = SequenceInfo { name, label, words: &[], fresh_per_pixel: false, shipped: None };
    hemilab::sampling::register(Box::new(PySequence { info, shared: shared.clone() })).map_err(error)?;
    map.insert(name.to_string(), shared.clone());
    Ok(Sampler { shared })
}
