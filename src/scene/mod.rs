//! A scene: mesh, camera, default resolution, AO distance d, and the BVH built once from the mesh.
//! No IO here: `app` reads the files and hands over their bytes.

pub mod accel;
pub mod camera;
pub mod file;
pub mod generate;
pub mod mesh;
pub mod packet;
pub mod procedural;

pub use accel::Accel;
pub use camera::Camera;
pub use mesh::Mesh;

use glam::Vec3;

pub struct Scene {
    pub name: String,
    pub camera: Camera,
    pub resolution: (u32, u32),
    /// The paper's d; `f32::INFINITY` means unbounded.
    pub ao_distance: f32,
    /// Hex hash of what determines the scene's images (scene TOML bytes + mesh bytes).
    pub content_hash: String,
    pub triangle_count: usize,
    /// Triangles dropped at load (zero area or non-finite), for one warning.
    pub dropped_triangles: usize,
    /// Core BVH build time (obvhs's own measure, without input conversion).
    pub bvh_build_s: f64,
    pub accel: Accel,
}

impl Scene {
    /// Checks camera and d, then builds the BVH. The error says which value is wrong.
    pub fn new(
        name: String,
        camera: Camera,
        resolution: (u32, u32),
        ao_distance: f32,
        content_hash: String,
        mesh: Mesh,
    ) -> Result<Scene, String> {
        if let Some(p) = camera.problem() {
            return Err(format!("camera: {p}"));
        }
        if ao_distance.is_nan() || ao_distance <= 0.0 {
            return Err(format!("ao_distance must be positive or \"infinite\", got {ao_distance}"));
        }
        if mesh.triangles.is_empty() {
            return Err("empty mesh: no usable triangles".into());
        }
        let (accel, bvh_build_s) = Accel::build(&mesh.triangles);
        Ok(Scene {
            name,
            camera,
            resolution,
            ao_distance,
            content_hash,
            triangle_count: mesh.triangles.len(),
            dropped_triangles: mesh.dropped,
            bvh_build_s,
            accel,
        })
    }

    /// A scene made in code (tests, validation): unusable triangles are dropped and counted, and the
    /// hash covers the triangles and every parameter.
    pub fn from_triangles(
        name: &str,
        camera: Camera,
        resolution: (u32, u32),
        ao_distance: f32,
        triangles: Vec<[Vec3; 3]>,
    ) -> Result<Scene, String> {
        let mut bytes = format!("{name} {camera:?} {resolution:?} {ao_distance}").into_bytes();
        for v in triangles.iter().flatten() {
            for c in v.to_array() {
                bytes.extend_from_slice(&c.to_le_bytes());
            }
        }
        let hash = content_hash(&[&bytes]);
        let (keep, drop): (Vec<_>, Vec<_>) = triangles.into_iter().partition(mesh::usable);
        let mesh = Mesh { triangles: keep, dropped: drop.len() };
        Scene::new(name.to_string(), camera, resolution, ao_distance, hash, mesh)
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
