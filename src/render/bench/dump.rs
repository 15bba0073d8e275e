//! The bench's ray set as bytes in the HLRAYS1 format, so that other ray tracers (Embree, tinybvh:
//! the peer programs docs/performance.md describes) can trace exactly the rays hemilab traces and
//! their occluded counts can be set beside hemilab's. Pure: bytes out, the file is `io`'s.
//!
//! Layout, all little-endian: the 8 bytes `HLRAYS1\0`; u32 T; T triangles of 3 vertices of 3 f32;
//! u32 P (pixels); u32 N (rays a pixel); P origins (3 f32); P normals (3 f32); P × N directions
//! (3 f32; pixel p's rays are p·N .. p·N + N − 1). The coordinates are the scene's as hemilab
//! traces it (moved next to the camera at load), origins already offset off the surface, so a
//! reader uses them as given: a ray is occluded if any triangle, either face, is hit at 0 < t < d.

use super::RaySet;
use glam::Vec3;

/// The first 8 bytes of a dump.
pub const MAGIC: &[u8; 8] = b"HLRAYS1\0";

/// Why a ray set cannot be written in the format (its counts are u32).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TooLarge(pub String);

/// `set` over `triangles` as an HLRAYS1 dump.
pub fn hlrays1(triangles: &[[Vec3; 3]], set: &RaySet) -> Result<Vec<u8>, TooLarge> {
    let count = |what: &str, n: usize| {
        u32::try_from(n).map_err(|_| TooLarge(format!("{n} {what} (the format's counts are 32-bit)")))
    };
    let t = count("triangles", triangles.len())?;
    let p = count("pixels", set.origins.len())?;
    let n = count("rays a pixel", set.n)?;
    let floats = 9 * triangles.len() + 6 * set.origins.len() + 3 * set.dirs.len();
    let mut out = Vec::with_capacity(MAGIC.len() + 12 + 4 * floats);
    out.extend_from_slice(MAGIC);
    let vec3 = |out: &mut Vec<u8>, v: &Vec3| {
        for x in v.to_array() {
            out.extend_from_slice(&x.to_le_bytes());
        }
    };
    out.extend_from_slice(&t.to_le_bytes());
    for v in triangles.iter().flatten() {
        vec3(&mut out, v);
    }
    out.extend_from_slice(&p.to_le_bytes());
    out.extend_from_slice(&n.to_le_bytes());
    for v in set.origins.iter().chain(&set.normals).chain(&set.dirs) {
        vec3(&mut out, v);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dump_is_laid_out_as_documented() {
        let set = RaySet {
            n: 2,
            origins: vec![Vec3::new(1.0, 2.0, 3.0)],
            normals: vec![Vec3::Y],
            dirs: vec![Vec3::X, Vec3::new(0.0, -0.0, 1.0)],
            x: vec![1.0, 0.0],
            y: vec![0.0, -0.0],
            z: vec![0.0, 1.0],
        };
        let tri = [Vec3::ZERO, Vec3::X, Vec3::Z];
        let b = hlrays1(&[tri], &set).unwrap();
        assert_eq!(b.len(), 8 + 4 + 36 + 8 + 12 + 12 + 24);
        assert_eq!(&b[..8], MAGIC);
        let u = |at: usize| u32::from_le_bytes(b[at..at + 4].try_into().unwrap());
        let f = |at: usize| f32::from_le_bytes(b[at..at + 4].try_into().unwrap());
        assert_eq!(u(8), 1);
        assert_eq!(f(12 + 12), 1.0); // the second vertex's x
        assert_eq!((u(48), u(52)), (1, 2));
        assert_eq!((f(56), f(60), f(64)), (1.0, 2.0, 3.0));
        assert_eq!(f(72), 1.0); // the normal's y
        // Directions exactly as traced, -0.0 included.
        assert_eq!(f(80), 1.0);
        assert_eq!(f(96).to_bits(), (-0.0f32).to_bits());
    }
}
