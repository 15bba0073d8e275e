//! hemilab's images to and from numpy arrays (row-major, float32, as `Image` holds them).

use hemilab::image::Image;
use numpy::{PyArray1, PyArray2, PyArray3, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;

/// A float32 (H, W) image or (n, k) matrix, as the module returns them.
pub type Array<'py> = Bound<'py, PyArray2<f32>>;

/// An (rows, cols) float32 array of `data` (row-major).
pub fn matrix<'py>(
    py: Python<'py>,
    rows: usize,
    cols: usize,
    data: Vec<f32>,
) -> PyResult<Bound<'py, PyArray2<f32>>> {
    PyArray1::from_vec(py, data).reshape([rows, cols])
}

/// An image as an (H, W) float32 array.
pub fn image<'py>(py: Python<'py>, img: &Image) -> PyResult<Bound<'py, PyArray2<f32>>> {
    matrix(py, img.height as usize, img.width as usize, img.data.clone())
}

/// Per-pixel vectors as an (H, W, 3) float32 array.
pub fn image_rgb<'py>(
    py: Python<'py>,
    width: u32,
    height: u32,
    v: &[glam::Vec3],
) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let data: Vec<f32> = v.iter().flat_map(|p| [p.x, p.y, p.z]).collect();
    PyArray1::from_vec(py, data).reshape([height as usize, width as usize, 3])
}

/// A C-contiguous (H, W) float32 array as an image (`hemilab/__init__.py` makes it so).
pub fn to_image(a: &PyReadonlyArray2<'_, f32>, what: &str) -> PyResult<Image> {
    let shape = a.shape();
    let (h, w) = (shape[0], shape[1]);
    let data = a.as_slice().map_err(|e| crate::error(format!("{what}: {e}")))?.to_vec();
    let (Ok(w), Ok(h)) = (u32::try_from(w), u32::try_from(h)) else {
        return Err(crate::error(format!("{what}: {h}x{w} is too large")));
    };
    Ok(Image::from_vec(w, h, data))
}
