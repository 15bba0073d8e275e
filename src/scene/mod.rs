//! A scene: mesh, camera, default resolution, AO distance d, and the BVH built once from the mesh.
//! No IO here: `app` reads the files and hands over their bytes.

pub mod accel;
pub mod alpha;
pub mod camera;
pub mod camera_path;
mod cluster;
pub mod dds;
mod effort;
pub mod file;
#[cfg(any(test, feature = "testing"))]
pub mod foliage;
#[cfg(any(test, feature = "testing"))]
pub mod generate;
pub mod gltf_accessor;
pub mod gltf_check;
pub mod gltf_ext;
pub mod gltf_mesh;
pub mod gltf_meshopt;
#[cfg(any(test, feature = "testing"))]
pub mod gltf_write;
pub mod guard;
pub mod mesh;
pub mod mtl;
pub(crate) mod near;
mod node;
mod obj;
mod obj_masks;
pub mod packet;
#[cfg(any(test, feature = "testing"))]
pub mod procedural;
mod repeats;
#[cfg(any(test, feature = "testing"))]
pub mod tree;

pub use accel::{Accel, Effort};
pub use camera::{Camera, WorldCamera};
pub use camera_path::{CameraPath, Keyframe, halton_jitter};
pub use mesh::Mesh;

use glam::{DVec3, Vec3};
use rayon::prelude::*;

/// The largest coordinate (of a mesh vertex or a camera position) a scene may have, in magnitude:
/// the renderer works in f32 relative to the camera, and a triangle's edge cross product (up to
/// about 12 × this squared between two points at ±this) stays below f32's 3.4e38 only up to here.
pub const MAX_COORDINATE: f64 = 1e18;

/// How `Scene::new`'s error starts when no triangle survives rounding to f32 (a fault of the mesh
/// file, not of the scene file, so the loader names the mesh).
pub const EMPTY_MESH: &str = "empty mesh";

/// A scene ready to render. Everything the renderer sees is relative to `origin`, the camera's eye:
/// the world coordinates (f64) have the eye subtracted before they are rounded to f32, as large-world
/// game engines do. A scene 1 km (or 10 km) from the world origin then renders exactly like the same
/// scene at the origin, and every f32 coordinate is as fine as the scene is near the camera.
pub struct Scene {
    pub name: String,
    /// The camera as the scene places it (world coordinates).
    pub view: WorldCamera,
    /// World position of the renderer's origin: the eye.
    pub origin: DVec3,
    /// The camera relative to `origin` (its eye is at 0).
    pub camera: Camera,
    pub resolution: (u32, u32),
    /// The paper's d; `f32::INFINITY` means unbounded.
    pub ao_distance: f32,
    /// Hex hash of what determines the scene's images (scene TOML bytes + mesh bytes).
    pub content_hash: String,
    pub triangle_count: usize,
    /// Materials with an alpha mask (each `alpha::Cutout` some kept triangle uses), and the kept
    /// triangles they cut: for the scene summary (`load::summary`).
    pub masked_materials: usize,
    pub masked_triangles: usize,
    /// Triangles dropped at load (zero area or non-finite), for one warning.
    pub dropped_triangles: usize,
    /// Triangles that repeat an earlier one exactly, counted in `triangle_count` but given to the
    /// BVH once (`repeats`: the image is the same).
    pub repeated_triangles: usize,
    /// Mesh elements skipped because they are not faces (`Mesh::skipped_description`), for one
    /// warning.
    pub skipped_elements: Option<String>,
    /// The mesh's other load warnings (`Mesh::notes`), one sentence each.
    pub notes: Vec<String>,
    /// The scene file's own camera paths (`[cameras.NAME]`), in name order: (name, path, jitter).
    pub paths: Vec<(String, camera_path::CameraPath, bool)>,
    /// Core BVH build time (obvhs's own measure, without input conversion).
    pub bvh_build_s: f64,
    pub accel: Accel,
}

impl Scene {
    /// Re-centres camera and mesh on the eye (in f64, then rounded to f32), checks camera and d,
    /// then builds the BVH for `rays` rays (`Effort::for_work`; None: a paper run's). Triangles
    /// that lose their area in f32 are dropped and counted. The error says which value is wrong.
    pub fn new(
        name: String,
        view: WorldCamera,
        resolution: (u32, u32),
        ao_distance: f32,
        content_hash: String,
        mesh: Mesh,
        rays: Option<u64>,
    ) -> Result<Scene, String> {
        let origin = view.eye();
        let camera = view.relative_to(origin);
        if !origin.is_finite() {
            return Err("camera: eye, target and up must be finite".into());
        }
        if let Some(p) = camera.problem() {
            return Err(format!("camera: {p}"));
        }
        if ao_distance.is_nan() || ao_distance <= 0.0 {
            return Err(format!("ao_distance must be positive or \"infinite\", got {ao_distance}"));
        }
        let local = |v: DVec3| (v - origin).as_vec3();
        let skipped_elements = mesh.skipped_description();
        let Mesh { positions, mut indices, dropped, notes, alpha, .. } = mesh;
        // Each position shifted once (as each of its triangles would shift it: the same bits), and
        // the f64 copy freed before the BVH build's peak.
        let positions: Vec<Vec3> = positions.into_iter().map(local).collect();
        // In parallel: a gather through the indices, slow for a large shuffled mesh.
        let keep: Vec<bool> = indices.par_iter().map(|t| usable(&t.map(|i| positions[i as usize]))).collect();
        let before = indices.len();
        let mut kept = keep.iter();
        indices.retain(|_| *kept.next().expect("one flag a triangle"));
        let dropped = dropped + (before - indices.len());
        // The alpha masks of the kept triangles (only scenes with masks have any).
        let mut alpha = alpha.filter(alpha::Source::any).map(|mut source| {
            source.retain(&keep);
            source
        });
        if indices.is_empty() {
            return Err(format!(
                "{EMPTY_MESH}: all {dropped} triangles lose their area when moved next to the camera and \
                 rounded to f32 (the renderer's precision): they are too small for their distance from \
                 the eye, or too large for f32"
            ));
        }
        let (masked_materials, masked_triangles) = alpha.as_ref().map_or((0, 0), |a| {
            let mut used: Vec<u32> = a.cutout.iter().copied().filter(|&c| c != alpha::SOLID).collect();
            let triangles = used.len();
            used.sort_unstable();
            used.dedup();
            (used.len(), triangles)
        });
        let triangle_count = indices.len();
        // Exact repeats are drawn once (`repeats`): the same image, without the build's quadratic
        // time over thousands of identical boxes. They still count as the mesh's triangles.
        let once = repeats::kept_copies(&positions, &indices, alpha.as_ref());
        let repeated_triangles = once.iter().filter(|&&f| !f).count();
        if repeated_triangles > 0 {
            let mut k = once.iter();
            indices.retain(|_| *k.next().expect("one flag a triangle"));
            if let Some(a) = alpha.as_mut() {
                a.retain(&once);
            }
        }
        drop(once);
        let effort = Effort::for_work(rays, indices.len());
        // The masks need the input triangles in input order; the build takes the indices.
        let alpha = alpha.map(|source| (source, indices.clone()));
        let (mut accel, bvh_build_s) = Accel::build_indexed(&positions, indices, effort);
        if let Some((source, indices)) = alpha {
            let input: Vec<[Vec3; 3]> = indices.iter().map(|t| t.map(|i| positions[i as usize])).collect();
            let slots = (0..accel.len() as u32).map(|p| (accel.source_index(p), accel.triangle(p)));
            let mask = alpha::Mask::for_slots(source, &input, slots);
            accel.set_alpha(mask);
        }
        drop(positions);
        Ok(Scene {
            name,
            view,
            origin,
            camera,
            resolution,
            ao_distance,
            content_hash,
            triangle_count,
            masked_materials,
            masked_triangles,
            dropped_triangles: dropped,
            repeated_triangles,
            skipped_elements,
            notes,
            paths: Vec::new(),
            bvh_build_s,
            accel,
        })
    }

    /// The camera as reference manifests record it: the world placement, as the scene gives it.
    pub fn camera_description(&self) -> String {
        self.view.canonical()
    }

    /// A scene made in code (tests, validation), in world coordinates: unusable triangles are
    /// dropped and counted, and the hash covers the triangles and every parameter.
    pub fn from_triangles(
        name: &str,
        view: WorldCamera,
        resolution: (u32, u32),
        ao_distance: f32,
        triangles: Vec<[DVec3; 3]>,
    ) -> Result<Scene, String> {
        let (w, h) = resolution;
        let mut bytes = format!("{name} {} ({w}, {h}) {ao_distance}", view.canonical()).into_bytes();
        for v in triangles.iter().flatten() {
            for c in v.to_array() {
                bytes.extend_from_slice(&c.to_le_bytes());
            }
        }
        let hash = content_hash(&[&bytes]);
        let (keep, drop): (Vec<_>, Vec<_>) = triangles.into_iter().partition(mesh::usable);
        let mesh = Mesh { dropped: drop.len(), ..Mesh::from_soup(keep) };
        Scene::new(name.to_string(), view, resolution, ao_distance, hash, mesh, None)
    }
}

/// A triangle the renderer can use: finite f32 vertices and a normal that normalizes (then the
/// geometric normal is always a unit vector).
pub fn usable(t: &[Vec3; 3]) -> bool {
    t.iter().all(|v| v.is_finite()) && {
        let n = (t[1] - t[0]).cross(t[2] - t[0]);
        n.is_finite() && n.length_squared() > 0.0 && n.normalize().is_finite()
    }
}

/// FNV-1a, 128-bit (Fowler, Noll, Vo; IETF draft-eastlake-fnv), over each part preceded by its
/// length so that part boundaries count. Not cryptographic: it names content, it does not guard it.
pub fn content_hash(parts: &[&[u8]]) -> String {
    const OFFSET: u128 = 0x6c62272e07bb014262b821756295c58d;
    const PRIME: u128 = 0x0000000001000000000000000000013B;
    let mut h = OFFSET;
    for part in parts {
        for &b in (part.len() as u64).to_le_bytes().iter().chain(part.iter()) {
            h ^= b as u128;
            h = h.wrapping_mul(PRIME);
        }
    }
    format!("{h:032x}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hash_separates_parts() {
        assert_ne!(content_hash(&[b"ab", b"c"]), content_hash(&[b"a", b"bc"]));
        assert_eq!(content_hash(&[b"x"]).len(), 32);
    }
}
