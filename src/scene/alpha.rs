//! Alpha masks: triangles whose material cuts holes in them (glTF 2.0 `alphaMode: MASK`, section
//! 3.9.4: "the rendered output is either fully opaque or fully transparent depending on the alpha
//! value and the specified `alphaCutoff`"; leaves, fences, chains). A ray that meets such a
//! triangle where its mask is transparent goes on as if the triangle were not there, for primary
//! and AO rays alike.
//!
//! The test at a hit: the texture coordinates interpolated with the hit's barycentrics (in f32, one
//! formula for every path), the *nearest* texel looked up (texel i covers [i, i+1)/width; no
//! filtering, so the boundary between opaque and transparent lies exactly on texel edges), its
//! coordinates wrapped as the sampler says (repeat when it says nothing), and the texel is opaque
//! iff texture alpha × `baseColorFactor` alpha >= `alphaCutoff` (default 0.5), decided once per
//! texel at load and kept as one bit.
//!
//! Scenes without masks carry none of this (`Accel::alpha` is `None`): their rays cost one
//! predictable check per triangle hit. A leaf: it imports nothing of the crate, so the tree, the
//! packets and the loaders (glTF, and OBJ with `map_d` in its material library) can all use it.

use glam::Vec3;

/// How a texture coordinate outside [0, 1) maps back into the texture (glTF samplers' `wrapS`,
/// `wrapT`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Wrap {
    #[default]
    Repeat,
    Mirror,
    Clamp,
}

impl Wrap {
    /// Texel index `i` (any integer) into 0..n.
    #[inline(always)]
    fn apply(self, i: i64, n: i64) -> usize {
        (match self {
            Wrap::Repeat => i.rem_euclid(n),
            Wrap::Mirror => {
                let m = i.rem_euclid(2 * n);
                if m < n { m } else { 2 * n - 1 - m }
            }
            Wrap::Clamp => i.clamp(0, n - 1),
        }) as usize
    }
}

/// One material's mask: which texels are opaque (one bit each, row by row from the image's first
/// row, which glTF puts at v = 0), and how coordinates wrap.
#[derive(Debug, Clone, PartialEq)]
pub struct Cutout {
    width: u32,
    height: u32,
    bits: Vec<u64>,
    wrap: [Wrap; 2],
}

impl Cutout {
    /// From the texture's alpha values (0..=1, `width` × `height`, first row first), the material's
    /// alpha factor and cutoff: a texel is opaque iff `alpha * factor >= cutoff` (computed in f32).
    pub fn new(width: u32, height: u32, alpha: &[f32], factor: f32, cutoff: f32, wrap: [Wrap; 2]) -> Self {
        assert!(width > 0 && height > 0 && alpha.len() == (width * height) as usize);
        let mut bits = vec![0u64; alpha.len().div_ceil(64)];
        for (i, &a) in alpha.iter().enumerate() {
            if a * factor >= cutoff {
                bits[i / 64] |= 1 << (i % 64);
            }
        }
        Self { width, height, bits, wrap }
    }

    /// A material without a texture: its factor alone decides, everywhere.
    pub fn uniform(factor: f32, cutoff: f32) -> Self {
        Self::new(1, 1, &[1.0], factor, cutoff, [Wrap::Repeat; 2])
    }

    /// Whether the texel nearest to (u, v) is opaque.
    #[inline]
    pub fn opaque_at(&self, u: f32, v: f32) -> bool {
        let (w, h) = (self.width as i64, self.height as i64);
        // `as` saturates (and maps NaN to 0), so any f32 gives some texel.
        let x = self.wrap[0].apply((u * self.width as f32).floor() as i64, w);
        let y = self.wrap[1].apply((v * self.height as f32).floor() as i64, h);
        let i = y * self.width as usize + x;
        (self.bits[i / 64] >> (i % 64)) & 1 != 0
    }
}

/// Which of an image's channels is a mask's value (MTL's `-imfchan`: r, g, b, m for matte = alpha,
/// l for luminance).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Channel {
    Red,
    Green,
    Blue,
    Alpha,
    Luminance,
}

/// Decodes a mask texture (PNG or TGA) to its width, height and one channel's values in 0..=1, row
/// by row from the image's first row. `None`: the alpha channel if the image has one, else its
/// luminance (a grey mask, as Sponza's `map_d` textures are, is its grey value). Images without
/// alpha have alpha 1 everywhere.
/// `name`: the file's name, whose extension tells a TGA (TGA files have no magic number); other
/// images are known by their first bytes.
pub fn decode(bytes: &[u8], channel: Option<Channel>, name: &str) -> Result<(u32, u32, Vec<f32>), String> {
    let tga = name.to_ascii_lowercase().ends_with(".tga");
    let image = if tga {
        image::load_from_memory_with_format(bytes, image::ImageFormat::Tga)
    } else {
        image::load_from_memory(bytes)
    };
    let image = image.map_err(|e| format!("does not decode as PNG or TGA: {e}"))?;
    let channel =
        channel.unwrap_or(if image.color().has_alpha() { Channel::Alpha } else { Channel::Luminance });
    let (w, h) = (image.width(), image.height());
    let values = match channel {
        Channel::Luminance => image.to_luma32f().into_raw(),
        c => {
            let k =
                [Channel::Red, Channel::Green, Channel::Blue, Channel::Alpha].iter().position(|&x| x == c);
            let k = k.expect("a colour channel");
            image.into_rgba32f().pixels().map(|p| p.0[k]).collect()
        }
    };
    Ok((w, h, values))
}

/// No mask: the triangle is solid (a material index no cutout has).
pub const SOLID: u32 = u32::MAX;

/// A mesh's masks as the loader finds them: the cutouts, and per triangle (mesh order) its cutout
/// (or `SOLID`) and its corners' texture coordinates.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Source {
    pub cutouts: Vec<Cutout>,
    pub cutout: Vec<u32>,
    pub uv: Vec<[[f32; 2]; 3]>,
}

impl Source {
    /// Records the next triangle of the mesh.
    pub fn push(&mut self, cutout: u32, uv: [[f32; 2]; 3]) {
        self.cutout.push(cutout);
        self.uv.push(uv);
    }

    /// Keeps the triangles where `keep` is true (what `Scene::new` keeps of the mesh).
    pub fn retain(&mut self, keep: &[bool]) {
        assert_eq!(keep.len(), self.cutout.len());
        let mut k = keep.iter();
        self.cutout.retain(|_| *k.next().unwrap());
        let mut k = keep.iter();
        self.uv.retain(|_| *k.next().unwrap());
    }

    /// Whether any triangle has a cutout (else the scene needs no masks at all).
    pub fn any(&self) -> bool {
        self.cutout.iter().any(|&c| c != SOLID)
    }
}

/// The masks per BVH slot: the cutout and the corners' coordinates in the order of the slot's
/// vertices (the tree sorts each triangle's vertices, and a hit's barycentrics refer to that order).
#[derive(Debug, Clone)]
pub struct Mask {
    cutouts: Vec<Cutout>,
    cutout: Vec<u32>,
    uv: Vec<[[f32; 2]; 3]>,
}

impl Mask {
    /// `source`: per input triangle (the tree's input order), `input` those triangles' vertices as
    /// given, `slots` per BVH slot its input triangle and its vertices as the tree stores them (a
    /// permutation of the input's: the three are distinct, as the triangle has an area).
    pub fn for_slots(
        source: Source,
        input: &[[Vec3; 3]],
        slots: impl Iterator<Item = (u32, [Vec3; 3])>,
    ) -> Self {
        assert_eq!(source.cutout.len(), input.len());
        let (mut cutout, mut uv) = (Vec::new(), Vec::new());
        for (i, sorted) in slots {
            let (i, given) = (i as usize, &input[i as usize]);
            cutout.push(source.cutout[i]);
            uv.push(sorted.map(|v| {
                let k = given.iter().position(|g| *g == v).expect("a slot's vertices are its triangle's");
                source.uv[i][k]
            }));
        }
        Self { cutouts: source.cutouts, cutout, uv }
    }

    /// Whether the hit on slot `prim` at barycentrics (1 - b - c, b, c) counts: its triangle is
    /// solid, or the texel there is opaque.
    #[inline]
    pub fn keeps(&self, prim: u32, b: f32, c: f32) -> bool {
        let m = self.cutout[prim as usize];
        if m == SOLID {
            return true;
        }
        let [p, q, r] = self.uv[prim as usize];
        let a = 1.0 - b - c;
        let u = (a * p[0] + b * q[0]) + c * r[0];
        let v = (a * p[1] + b * q[1]) + c * r[1];
        self.cutouts[m as usize].opaque_at(u, v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_texel_with_each_wrap() {
        // 2 × 1: left texel opaque, right transparent.
        let c = Cutout::new(2, 1, &[1.0, 0.0], 1.0, 0.5, [Wrap::Repeat; 2]);
        assert!(c.opaque_at(0.0, 0.5) && c.opaque_at(0.4999, 0.5) && !c.opaque_at(0.5, 0.5));
        assert!(c.opaque_at(1.2, 7.0) && !c.opaque_at(-0.2, 0.0));
        let m = Cutout::new(2, 1, &[1.0, 0.0], 1.0, 0.5, [Wrap::Mirror; 2]);
        assert!(!m.opaque_at(1.2, 0.0) && m.opaque_at(1.7, 0.0) && m.opaque_at(-0.2, 0.0));
        let k = Cutout::new(2, 1, &[1.0, 0.0], 1.0, 0.5, [Wrap::Clamp; 2]);
        assert!(!k.opaque_at(3.0, 0.0) && k.opaque_at(-3.0, 0.0) && k.opaque_at(f32::NAN, 0.0));
    }

    #[test]
    fn factor_times_alpha_against_the_cutoff() {
        let c = Cutout::new(3, 1, &[1.0, 0.5, 0.2], 0.5, 0.25, [Wrap::Clamp; 2]);
        assert!(c.opaque_at(0.1, 0.0) && c.opaque_at(0.5, 0.0) && !c.opaque_at(0.9, 0.0));
        assert!(
            Cutout::uniform(1.0, 0.5).opaque_at(3.0, -2.0) && !Cutout::uniform(0.4, 0.5).opaque_at(0.0, 0.0)
        );
    }
}
