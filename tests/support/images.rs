//! Small images and G-buffers for the denoise tests: fixed-seed normals, images from a function,
//! synthetic G-buffers (every pixel covered) and the rendered Cornell box's (with background).

use glam::Vec3;
use hemilab::image::Image;
use hemilab::load::load_scene;
use hemilab::render::{GBuffer, gbuffer};
use std::path::Path;

/// SplitMix64-based standard normals (Box–Muller), fixed seeds: the tests cannot flake.
pub fn normals(n: usize, seed: u64) -> Vec<f64> {
    hemilab::stats::normals_from_state(n, seed.wrapping_mul(0x2545_F491_4F6C_DD1D) ^ 0x1234_5678)
}

pub fn image(w: u32, h: u32, f: impl Fn(u32, u32) -> f32) -> Image {
    Image::from_vec(w, h, (0..w * h).map(|i| f(i % w, i / w)).collect())
}

/// An image of iid N(mean, sd²) values (seed `seed`).
pub fn noise(w: u32, h: u32, mean: f32, sd: f32, seed: u64) -> Image {
    let n = normals((w * h) as usize, seed);
    Image::from_vec(w, h, n.iter().map(|&v| mean + sd * v as f32).collect())
}

/// A synthetic G-buffer: every pixel covered, depth and normal by pixel.
pub fn synthetic(
    w: u32,
    h: u32,
    depth: impl Fn(u32, u32) -> f32,
    normal: impl Fn(u32, u32) -> Vec3,
) -> GBuffer {
    GBuffer {
        width: w,
        height: h,
        depth: image(w, h, &depth),
        normal: (0..w * h).map(|i| normal(i % w, i / w)).collect(),
        coverage: image(w, h, |_, _| 1.0),
        primitive: vec![0; (w * h) as usize],
    }
}

/// A fronto-parallel plane at depth 3 filling the image: every edge-stopping weight is 1.
pub fn plane(w: u32, h: u32) -> GBuffer {
    synthetic(w, h, |_, _| 3.0, |_, _| Vec3::Z)
}

/// The rendered Cornell box's G-buffer (its open front shows background).
pub fn cornell(w: u32, h: u32) -> GBuffer {
    let scene = load_scene(&Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell-box.toml")).unwrap();
    gbuffer(&scene, w, h)
}

/// `img` with every background pixel of `g` set to `v`.
pub fn with_background(img: &Image, g: &GBuffer, v: f32) -> Image {
    Image::from_vec(
        img.width,
        img.height,
        (0..img.len()).map(|i| if g.is_covered(i) { img.data[i] } else { v }).collect(),
    )
}

/// The largest |a − b| over all pixels.
pub fn max_diff(a: &Image, b: &Image) -> f64 {
    a.data.iter().zip(&b.data).map(|(x, y)| (*x as f64 - *y as f64).abs()).fold(0.0, f64::max)
}
