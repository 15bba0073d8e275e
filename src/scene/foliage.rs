//! The foliage scene of `scenes/` as a glTF document: leaf cards (quads whose alpha-masked PNG cuts
//! out a leaf) hanging in two bushes above a floor, the geometry real scenes draw plants with and the
//! stiffest AO case there is (occluders with holes at texel scale, lit through the gaps). Pure:
//! `examples/write_scenes.rs` writes the files; `tests/stages/scene_alpha.rs` checks that the
//! committed ones are exactly what this code makes.

use super::gltf_write::{Doc, Material, Node, Prim};

/// The leaf texture's file, beside the glTF file.
pub const LEAF_PNG: &str = "foliage-leaf.png";

/// The leaf texture's side, in texels.
pub const LEAF_SIDE: u32 = 64;

/// Whether texel (x, y) of the leaf texture is opaque: an ellipse pointed at both ends (a leaf
/// along the texture's diagonal), minus a midrib slit and a few insect holes, so light comes
/// through the cards in places no solid quad would let it.
pub fn leaf_opaque(x: u32, y: u32) -> bool {
    let n = LEAF_SIDE as f64;
    // Texel centre in [-1, 1]², rotated 45° so the leaf runs corner to corner.
    let (px, py) = ((x as f64 + 0.5) / n * 2.0 - 1.0, (y as f64 + 0.5) / n * 2.0 - 1.0);
    let (a, b) = ((px + py) / std::f64::consts::SQRT_2, (py - px) / std::f64::consts::SQRT_2);
    let half_width = 0.38 * (1.0 - a * a).max(0.0).powf(0.8);
    let inside = a.abs() < 0.95 && b.abs() < half_width;
    let midrib = b.abs() < 0.02 && a.abs() < 0.7;
    let holes = [(0.3, 0.12, 0.07), (-0.35, -0.1, 0.06), (0.55, -0.05, 0.05)];
    let holed = holes.iter().any(|&(ha, hb, r)| (a - ha).powi(2) + (b - hb).powi(2) < r * r);
    inside && !midrib && !holed
}

/// The leaf texture as a PNG: white, alpha 255 where `leaf_opaque`, 0 elsewhere.
pub fn leaf_png() -> Vec<u8> {
    let img = image::RgbaImage::from_fn(LEAF_SIDE, LEAF_SIDE, |x, y| {
        image::Rgba([60, 140, 50, if leaf_opaque(x, y) { 255 } else { 0 }])
    });
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).expect("PNG encoding to memory");
    out.into_inner()
}

/// A small linear congruential generator (Knuth's MMIX constants): the same cards on every machine.
struct Lcg(u64);

impl Lcg {
    /// Uniform in [0, 1), from the top 53 bits.
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Cards per bush.
const CARDS: usize = 90;

/// The scene: a 6 m × 6 m floor at y = 0 (solid), and two bushes of `CARDS` leaf cards each (0.2 m
/// squares, randomly turned and tilted, 0.15 to 1.0 m above the floor), every card textured with the
/// whole leaf (texture coordinates 0..1 across it). Y up, metres.
pub fn foliage() -> Doc {
    let floor = Prim {
        positions: vec![[-3.0, 0.0, -3.0], [3.0, 0.0, -3.0], [3.0, 0.0, 3.0], [-3.0, 0.0, 3.0]],
        indices: Some(vec![0, 2, 1, 0, 3, 2]),
        mode: 4,
        ..Prim::default()
    };
    let mut rng = Lcg(29);
    let (mut positions, mut uvs, mut indices) = (Vec::new(), Vec::new(), Vec::new());
    for centre in [[-0.6, 0.0], [0.7, -0.4]] {
        for _ in 0..CARDS {
            // A point in the bush's ellipsoid (rejection sampling), the card's centre.
            let c = loop {
                let p = [rng.next() * 2.0 - 1.0, rng.next() * 2.0 - 1.0, rng.next() * 2.0 - 1.0];
                if p[0] * p[0] + p[1] * p[1] + p[2] * p[2] <= 1.0 {
                    break [centre[0] + 0.55 * p[0], 0.575 + 0.425 * p[1], centre[1] + 0.55 * p[2]];
                }
            };
            // Orientation: a yaw, and a tilt of the card's plane from horizontal (0 to 70 degrees).
            let (yaw, tilt) = (rng.next() * std::f64::consts::TAU, rng.next() * 70f64.to_radians());
            let u = [yaw.cos(), 0.0, yaw.sin()];
            let v = [-yaw.sin() * tilt.cos(), tilt.sin(), yaw.cos() * tilt.cos()];
            let h = 0.1;
            let base = positions.len() as u32;
            for (su, sv, uv) in [
                (-1.0, -1.0, [0.0, 1.0]),
                (1.0, -1.0, [1.0, 1.0]),
                (1.0, 1.0, [1.0, 0.0]),
                (-1.0, 1.0, [0.0, 0.0]),
            ] {
                positions.push(std::array::from_fn(|k| (c[k] + h * (su * u[k] + sv * v[k])) as f32));
                uvs.push(uv);
            }
            indices.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
        }
    }
    let leaves = Prim { positions, indices: Some(indices), mode: 4, uvs: Some(uvs), material: Some(0) };
    Doc {
        meshes: vec![vec![floor, leaves]],
        nodes: vec![Node { mesh: Some(0), ..Node::default() }],
        roots: vec![0],
        materials: vec![Material { base_color_factor: [1.0; 4], texture: Some(0), alpha_cutoff: Some(0.5) }],
        images: vec![leaf_png()],
        image_uris: vec![LEAF_PNG.into()],
        ..Doc::default()
    }
}
