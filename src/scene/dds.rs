//! A DDS image's alpha, for an alpha mask whose only texture is DDS (`MSFT_texture_dds`, as the
//! AMD Capsaicin assets ship their roughness maps). The container is read by `ddsfile`; the first
//! surface of the first mip level is decoded by `bcdec_rs` (a pure-Rust port of bcdec) for the
//! block-compressed formats that carry alpha — BC1 (one-bit "punch-through" alpha), BC2, BC3 and
//! BC7 (Microsoft, "Texture Block Compression in Direct3D 11") — or read directly for 8-bit RGBA
//! and BGRA. A format without alpha has nothing to cut with; every other format is refused, naming
//! it, rather than guessed at.

use ddsfile::{D3DFormat, Dds, DxgiFormat};

/// How the first level's bytes are laid out.
#[derive(Clone, Copy, PartialEq)]
enum Layout {
    Bc1,
    Bc2,
    Bc3,
    Bc7,
    /// Four bytes a pixel, alpha the last (RGBA, BGRA and D3D's A8R8G8B8 alike).
    Bytes,
}

/// Width, height and alpha (0..=1, row by row from the first row) of a DDS file's main image.
pub fn alpha(bytes: &[u8]) -> Result<(u32, u32, Vec<f32>), String> {
    let dds = Dds::read(bytes).map_err(|e| format!("does not read as DDS: {e}"))?;
    let layout = match (dds.get_dxgi_format(), dds.get_d3d_format()) {
        (Some(f), _) => match f {
            DxgiFormat::BC1_UNorm | DxgiFormat::BC1_UNorm_sRGB | DxgiFormat::BC1_Typeless => {
                Some(Layout::Bc1)
            }
            DxgiFormat::BC2_UNorm | DxgiFormat::BC2_UNorm_sRGB | DxgiFormat::BC2_Typeless => {
                Some(Layout::Bc2)
            }
            DxgiFormat::BC3_UNorm | DxgiFormat::BC3_UNorm_sRGB | DxgiFormat::BC3_Typeless => {
                Some(Layout::Bc3)
            }
            DxgiFormat::BC7_UNorm | DxgiFormat::BC7_UNorm_sRGB | DxgiFormat::BC7_Typeless => {
                Some(Layout::Bc7)
            }
            DxgiFormat::R8G8B8A8_UNorm
            | DxgiFormat::R8G8B8A8_UNorm_sRGB
            | DxgiFormat::B8G8R8A8_UNorm
            | DxgiFormat::B8G8R8A8_UNorm_sRGB => Some(Layout::Bytes),
            _ => None,
        }
        .ok_or_else(|| format!("DXGI format {f:?}")),
        (None, Some(f)) => match f {
            D3DFormat::DXT1 => Some(Layout::Bc1),
            D3DFormat::DXT2 | D3DFormat::DXT3 => Some(Layout::Bc2),
            D3DFormat::DXT4 | D3DFormat::DXT5 => Some(Layout::Bc3),
            D3DFormat::A8R8G8B8 | D3DFormat::A8B8G8R8 => Some(Layout::Bytes),
            _ => None,
        }
        .ok_or_else(|| format!("D3D format {f:?}")),
        (None, None) => Err("a pixel format ddsfile does not know".to_string()),
    }
    .map_err(|f| {
        format!("DDS with {f}: an alpha mask reads BC1, BC2, BC3, BC7 or 8-bit RGBA/BGRA DDS images")
    })?;
    let (w, h) = (dds.get_width(), dds.get_height());
    if w == 0 || h == 0 || dds.get_depth() > 1 {
        return Err(format!("DDS of {w} x {h} x {}: an alpha mask needs a 2D image", dds.get_depth()));
    }
    let data = dds.get_data(0).map_err(|e| format!("DDS data: {e}"))?;
    let (bw, bh) = (w.div_ceil(4) as usize, h.div_ceil(4) as usize);
    let (w, h) = (w as usize, h as usize);
    let short = |need: usize| format!("DDS data: {} bytes, its first level needs {need}", data.len());
    let rgba: Vec<u8> = match layout {
        Layout::Bytes => data.get(..w * h * 4).ok_or_else(|| short(w * h * 4))?.to_vec(),
        block => {
            let size = if block == Layout::Bc1 { 8 } else { 16 };
            let blocks = data.get(..bw * bh * size).ok_or_else(|| short(bw * bh * size))?;
            // Decoded into whole blocks, four rows of `bw` blocks at a time, then cropped.
            let pitch = bw * 4 * 4;
            let mut padded = vec![0u8; pitch * bh * 4];
            for (k, b) in blocks.chunks_exact(size).enumerate() {
                let (bx, by) = (k % bw, k / bw);
                let out = &mut padded[by * 4 * pitch + bx * 16..];
                match block {
                    Layout::Bc1 => bcdec_rs::bc1(b, out, pitch),
                    Layout::Bc2 => bcdec_rs::bc2(b, out, pitch),
                    Layout::Bc3 => bcdec_rs::bc3(b, out, pitch),
                    _ => bcdec_rs::bc7(b, out, pitch),
                }
            }
            (0..h).flat_map(|y| padded[y * pitch..y * pitch + w * 4].to_vec()).collect()
        }
    };
    Ok((w as u32, h as u32, rgba.chunks_exact(4).map(|p| p[3] as f32 / 255.0).collect()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A DDS file of `format` holding `data` as its one level.
    fn dds(w: u32, h: u32, format: DxgiFormat, data: &[u8]) -> Vec<u8> {
        let mut d = Dds::new_dxgi(ddsfile::NewDxgiParams {
            height: h,
            width: w,
            depth: None,
            format,
            mipmap_levels: None,
            array_layers: None,
            caps2: None,
            is_cubemap: false,
            resource_dimension: ddsfile::D3D10ResourceDimension::Texture2D,
            alpha_mode: ddsfile::AlphaMode::Straight,
        })
        .unwrap();
        d.get_mut_data(0).unwrap().copy_from_slice(data);
        let mut out = Vec::new();
        d.write(&mut out).unwrap();
        out
    }

    #[test]
    fn bc3_and_rgba_alpha_decode_to_the_values_encoded() {
        // BC3 alpha block: endpoints 255 and 0; 3-bit index 0 picks 255, index 1 picks 0. The 16
        // indices, texel 0 first, as 48 little-endian bits: left two columns 0, right two 1.
        let mut bits = 0u64;
        for t in 0..16 {
            if t % 4 >= 2 {
                bits |= 1 << (3 * t);
            }
        }
        let mut block = vec![255u8, 0];
        block.extend_from_slice(&bits.to_le_bytes()[..6]);
        block.extend_from_slice(&[0; 8]); // the colour half: black
        let (w, h, a) = alpha(&dds(4, 4, DxgiFormat::BC3_UNorm, &block)).unwrap();
        assert_eq!((w, h), (4, 4));
        for (t, v) in a.iter().enumerate() {
            assert_eq!(*v, if t % 4 >= 2 { 0.0 } else { 1.0 }, "texel {t}");
        }
        // A 3 x 1 image inside one 4 x 4 block is cropped to its own texels.
        let (w, h, a) = alpha(&dds(3, 1, DxgiFormat::BC3_UNorm, &block)).unwrap();
        assert_eq!((w, h, a), (3, 1, vec![1.0, 1.0, 0.0]));
        let px = [9, 9, 9, 255, 9, 9, 9, 0, 9, 9, 9, 51, 9, 9, 9, 102];
        let (_, _, a) = alpha(&dds(2, 2, DxgiFormat::R8G8B8A8_UNorm, &px)).unwrap();
        assert_eq!(a, vec![1.0, 0.0, 0.2, 0.4]);
        let e = alpha(&dds(4, 4, DxgiFormat::BC4_UNorm, &[0; 8])).unwrap_err();
        assert!(e.contains("BC4_UNorm") && e.contains("BC1, BC2, BC3, BC7"), "{e}");
        assert!(alpha(b"DDS nope").unwrap_err().contains("does not read as DDS"));
    }
}
