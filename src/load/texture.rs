//! Reading a noise texture the user names into `sampling::texture`'s table.
//!
//! - **Files**: one PNG (8 or 16 bit; grey, grey + alpha, RGB, RGBA) or EXR per slice. A path with
//!   `%d` (or `%0Nd`, zero-padded to N digits, or `%Nd`, space-padded as printf pads; N up to 9) is a
//!   numbered pattern: slices 0, 1, 2, … (or from 1, when no slice 0 exists) up to the first number
//!   with no file. Without one it is a single slice.
//! - **Channels**: a PNG's in order (grey; grey, alpha; R, G, B(, A)); an EXR's R, G, B when it has
//!   them, else its one channel (Y or any). `offset` reads channels 0 and 1 (one channel: read at
//!   two independent shifts), `rotation` channel 0, `vector` channels 0–2 (three needed).
//! - **Name**: `texture:PATH:USE#hash8`, PATH as the spec or command line wrote it and hash8 the
//!   first 8 hex digits of the FNV-1a 128 content hash of every slice's bytes in order, so that an
//!   edited texture is a new seed mode and never resumes the old one's results.
//!
//! Every problem is one message naming the file and the reason (missing, not an image, the wrong
//! channel count, a size that differs between slices, a bad texel); a texture whose slices do not
//! give exactly uniform offsets loads with one warning giving the measured distance.

use crate::image::decode_exr;
use crate::io;
use crate::sampling::SeedMode;
use crate::sampling::texture::{self, Layout, Samples, TextureMask, TextureUse};
use std::path::{Path, PathBuf};

/// Slices a numbered pattern may have (more is a typo, e.g. a pattern matching unrelated files).
pub const MAX_SLICES: usize = 4096;

/// Loads the texture `written` (relative to `base`, the spec's directory or the current one) for
/// `use_`, registers it and returns its seed mode; the message names the file and what is wrong.
pub fn texture(base: &Path, written: &str, use_: TextureUse) -> Result<SeedMode, String> {
    let files = slice_files(base, written)?;
    let mut bytes_all: Vec<Vec<u8>> = Vec::with_capacity(files.len());
    let mut layout: Option<(Layout, PathBuf)> = None;
    let mut ints: Vec<u16> = Vec::new();
    let mut floats: Vec<f32> = Vec::new();
    let mut bits_seen: Option<u32> = None;
    for file in &files {
        let shown = file.display();
        let bytes = io::read_bytes(file).map_err(|e| e.to_string())?;
        let (l, samples) = crate::scene::guard::contained("image", || decode(file, &bytes))
            .map_err(|e| if e.starts_with("texture") { e } else { format!("texture {shown}: {e}") })?;
        match &layout {
            None => layout = Some((l, file.clone())),
            Some((first, from))
                if (first.width, first.height, first.channels) != (l.width, l.height, l.channels) =>
            {
                return Err(format!(
                    "texture slice {shown} is {}x{} with {} channel(s), but {} is {}x{} with {}; every slice must \
                     match",
                    l.width,
                    l.height,
                    l.channels,
                    from.display(),
                    first.width,
                    first.height,
                    first.channels
                ));
            }
            Some(_) => {}
        }
        match samples {
            Samples::Int { bits, data } => {
                if bits_seen.is_some_and(|b| b != bits) || !floats.is_empty() {
                    return Err(format!(
                        "texture slice {shown} has another bit depth or format than slice 0"
                    ));
                }
                bits_seen = Some(bits);
                ints.extend(data);
            }
            Samples::Float(data) => {
                if bits_seen.is_some() {
                    return Err(format!(
                        "texture slice {shown} is an EXR, slice 0 a PNG; every slice must match"
                    ));
                }
                floats.extend(data);
            }
        }
        bytes_all.push(bytes);
    }
    let (mut layout, first) = layout.expect("at least one slice file");
    layout.depth = files.len() as u32;
    if use_ == TextureUse::Vector && layout.channels < 3 {
        return Err(format!(
            "texture {} has {} channel(s); a `vector` texture needs 3 (R, G, B: the direction)",
            first.display(),
            layout.channels
        ));
    }
    let samples = match bits_seen {
        Some(bits) => Samples::Int { bits, data: ints },
        None => Samples::Float(floats),
    };
    let parts: Vec<&[u8]> = bytes_all.iter().map(Vec::as_slice).collect();
    let hash8 = crate::scene::content_hash(&parts)[..8].to_string();
    let name = format!("texture:{written}:{}#{hash8}", use_.name());
    let label = format!("texture {written} ({})", use_.name());
    let mask = TextureMask::new(name, label, use_, layout, &samples).map_err(|e| {
        format!("texture {}: texel ({}, {}): {}", files[e.slice as usize].display(), e.x, e.y, e.what)
    })?;
    let deviation = mask.deviation();
    let uniform = mask.uniform();
    let texels = (layout.width * layout.height) as usize;
    let (id, new) = texture::register(mask)?;
    if new && (deviation.distance > deviation.tolerance) {
        eprintln!("{}", warning(written, use_, &files, texels, uniform, deviation));
    }
    Ok(SeedMode::Texture(id))
}

/// The one warning of a texture whose offsets are not exactly uniform.
fn warning(
    written: &str,
    use_: TextureUse,
    files: &[PathBuf],
    texels: usize,
    uniform: bool,
    d: texture::Deviation,
) -> String {
    let slice = files.get(d.slice as usize).map_or(String::new(), |f| format!(" ({})", f.display()));
    if use_ == TextureUse::Vector {
        format!(
            "warning: texture '{written}' (vector): slice {}{slice}: its {} is {:.4} (Kolmogorov–Smirnov / \
             Kuiper distance) from a cosine-weighted hemisphere's, more than {} independent directions would \
             be ({:.4}); its estimates are biased by the difference",
            d.slice, d.channel, d.distance, texels, d.tolerance
        )
    } else {
        let _ = uniform;
        format!(
            "warning: texture '{written}' ({}): slice {}{slice}: its {} offsets are not uniform: Kuiper distance \
             {:.6} from uniform (0 for equally spaced ranks, as a void-and-cluster mask has); each pixel's \
             offsets over runs are off by up to that much, so its estimate is not exactly unbiased",
            use_.name(),
            d.slice,
            d.channel,
            d.distance
        )
    }
}

/// The files of a texture: the numbered slices of a `%d` pattern, or the one file.
fn slice_files(base: &Path, written: &str) -> Result<Vec<PathBuf>, String> {
    let at = |p: &Path| std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf()).display().to_string();
    let Some(Pattern { head, width, pad, tail }) = pattern(written)? else {
        let file = base.join(written);
        if !io::exists(&file) {
            // `t.png:diagonal`: the file exists and the word after it is not a use.
            if let Some((path, use_)) = written.rsplit_once(':')
                && (io::exists(&base.join(path)) || pattern(path).is_ok_and(|p| p.is_some()))
                && let Err(e) = TextureUse::parse(use_)
            {
                return Err(format!("texture '{written}': {e} (after the file name, a `:` names the use)"));
            }
            return Err(format!("texture file '{written}' not found (looked for {})", at(&file)));
        }
        return Ok(vec![file]);
    };
    // printf's `%Nd` pads with spaces, `%0Nd` with zeros.
    let name = |i: usize| {
        let number = if pad == '0' { format!("{i:0width$}") } else { format!("{i:>width$}") };
        base.join(format!("{head}{number}{tail}"))
    };
    let start = if io::exists(&name(0)) { 0 } else { 1 };
    let mut files = Vec::new();
    while io::exists(&name(start + files.len())) {
        if files.len() == MAX_SLICES {
            return Err(format!("texture pattern '{written}' matches more than {MAX_SLICES} slices"));
        }
        files.push(name(start + files.len()));
    }
    if files.is_empty() {
        return Err(format!(
            "texture pattern '{written}' matches no file (looked for {} and {})",
            at(&name(0)),
            at(&name(1))
        ));
    }
    Ok(files)
}

/// The widest number a pattern may pad to: slice numbers have at most 4 digits (`MAX_SLICES`), and
/// a wider field is a typo (`%099999999999d` would ask for a name longer than any file system's).
pub const MAX_PATTERN_WIDTH: usize = 9;

/// A numbered pattern: `head`, the slice number padded to `width` with `pad`, `tail`.
#[derive(Debug, PartialEq)]
struct Pattern<'a> {
    head: &'a str,
    width: usize,
    pad: char,
    tail: &'a str,
}

/// `a%d.png` → ("a", 0, ".png"); `a%03d.png` → zero-padded to 3; `a%3d.png` → space-padded to 3
/// (as printf pads); None without a `%…d`, an error for a `%…d` this reader does not take (a flag
/// other than `0`, a width over `MAX_PATTERN_WIDTH`).
fn pattern(written: &str) -> Result<Option<Pattern<'_>>, String> {
    let Some(i) = written.find('%') else { return Ok(None) };
    let rest = &written[i + 1..];
    let Some(d) = rest.find(|c: char| !matches!(c, '0'..='9' | '-' | '+' | ' ' | '#' | '\'')) else {
        return Ok(None);
    };
    if !rest[d..].starts_with('d') {
        return Ok(None);
    }
    let spec = &rest[..d];
    let refuse = |why: &str| {
        Err(format!(
            "texture pattern '{written}': '%{spec}d' {why}; a pattern takes %d, %Nd (space-padded, as printf) or \
             %0Nd (zero-padded), N up to {MAX_PATTERN_WIDTH}"
        ))
    };
    let (pad, digits) = match spec.strip_prefix('0') {
        Some(d) => ('0', d),
        None => (' ', spec),
    };
    if !digits.chars().all(|c| c.is_ascii_digit()) {
        return refuse("has a flag this reader does not take");
    }
    let width = match digits.parse::<usize>() {
        _ if digits.is_empty() => 0,
        Ok(w) if w <= MAX_PATTERN_WIDTH => w,
        _ => return refuse("pads wider than any slice number needs"),
    };
    Ok(Some(Pattern { head: &written[..i], width, pad, tail: &rest[d + 1..] }))
}

/// One slice's size, channels and samples, by the file's extension.
fn decode(file: &Path, bytes: &[u8]) -> Result<(Layout, Samples), String> {
    let ext = file.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    let shown = file.display();
    match ext.as_str() {
        "png" => decode_png(bytes).map_err(|e| format!("texture {shown} is not a readable PNG: {e}")),
        "exr" => {
            exr_size(bytes).map_err(|e| format!("texture {shown} is not a readable EXR: {e}"))?;
            let channels =
                decode_exr(bytes).map_err(|e| format!("texture {shown} is not a readable EXR: {e}"))?;
            exr_samples(channels).map_err(|e| format!("texture {shown}: {e}"))
        }
        _ => Err(format!(
            "texture {shown} is not a PNG or an EXR (its extension is '{ext}'; allowed: .png, .exr)"
        )),
    }
}

fn decode_png(bytes: &[u8]) -> Result<(Layout, Samples), String> {
    use ::image::DynamicImage as D;
    let img =
        ::image::load_from_memory_with_format(bytes, ::image::ImageFormat::Png).map_err(|e| e.to_string())?;
    let (width, height) = (img.width(), img.height());
    let layout = |channels: u32| Layout { width, height, depth: 1, channels };
    let wide = |v: &[u8]| v.iter().map(|&b| b as u16).collect::<Vec<u16>>();
    Ok(match img {
        D::ImageLuma8(b) => (layout(1), Samples::Int { bits: 8, data: wide(b.as_raw()) }),
        D::ImageLumaA8(b) => (layout(2), Samples::Int { bits: 8, data: wide(b.as_raw()) }),
        D::ImageRgb8(b) => (layout(3), Samples::Int { bits: 8, data: wide(b.as_raw()) }),
        D::ImageRgba8(b) => (layout(4), Samples::Int { bits: 8, data: wide(b.as_raw()) }),
        D::ImageLuma16(b) => (layout(1), Samples::Int { bits: 16, data: b.into_raw() }),
        D::ImageLumaA16(b) => (layout(2), Samples::Int { bits: 16, data: b.into_raw() }),
        D::ImageRgb16(b) => (layout(3), Samples::Int { bits: 16, data: b.into_raw() }),
        D::ImageRgba16(b) => (layout(4), Samples::Int { bits: 16, data: b.into_raw() }),
        other => return Err(format!("its pixel format {:?} is not 8- or 16-bit integer", other.color())),
    })
}

/// The most texels one slice may have: 2^26 (8192 x 8192), far above any noise texture (64 x 64 to
/// 1024 x 1024) and below what the decoder could allocate without failing.
pub const MAX_TEXELS: u64 = 1 << 26;

/// An EXR's header read first, so that a data window of 2^31 x 2^31 (an allocation failure, which
/// aborts) is refused before its pixels are decoded.
fn exr_size(bytes: &[u8]) -> Result<(), String> {
    let meta = exr::meta::MetaData::read_from_buffered(std::io::Cursor::new(bytes), false)
        .map_err(|e| e.to_string())?;
    for h in &meta.headers {
        let (w, ht) = (h.layer_size.0 as u64, h.layer_size.1 as u64);
        let channels = h.channels.list.len() as u64;
        if w * ht > MAX_TEXELS || channels > 64 {
            return Err(format!(
                "its header declares {w}x{ht} pixels with {channels} channel(s); a texture slice may have at most \
                 {MAX_TEXELS} texels and 64 channels"
            ));
        }
    }
    Ok(())
}

/// An EXR's channels in the texture's order: R, G, B where present, else its single channel.
fn exr_samples(channels: Vec<(String, crate::image::Image)>) -> Result<(Layout, Samples), String> {
    let by = |n: &str| channels.iter().find(|(c, _)| c == n).map(|(_, i)| i);
    let mut picked: Vec<&crate::image::Image> = Vec::new();
    for n in ["R", "G", "B"] {
        match by(n) {
            Some(i) => picked.push(i),
            None => break,
        }
    }
    if picked.is_empty() {
        match &channels[..] {
            [(_, only)] => picked.push(only),
            _ => {
                let names: Vec<&str> = channels.iter().map(|(c, _)| c.as_str()).collect();
                return Err(format!(
                    "its channels are {}; a texture's EXR has R (and G, B) or a single channel such as Y",
                    names.join(", ")
                ));
            }
        }
    }
    let (width, height) = (picked[0].width, picked[0].height);
    let n = (width * height) as usize;
    let mut data = Vec::with_capacity(n * picked.len());
    for i in 0..n {
        data.extend(picked.iter().map(|c| c.data[i]));
    }
    Ok((Layout { width, height, depth: 1, channels: picked.len() as u32 }, Samples::Float(data)))
}

/// Which of hemilab's own masks `own_masks` writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Own {
    /// The `blue-noise` mode's x and y masks as one two-channel slice.
    BlueNoise,
    /// The `stbn` mode's x and y volumes as numbered two-channel slices.
    Stbn,
}

/// hemilab's own masks as texture files (name, bytes), for the round trip (reading them back as
/// `offset` textures renders the built-in modes' images bit for bit) and for the hand check against
/// published textures: `png` 16-bit grey + alpha with rank · 2^16 / N (exact), else EXR with
/// R, G = rank / N (exact in f32). Names: `blue_noise.png`, `stbn_0.png` … `stbn_31.png`.
pub fn own_masks(which: Own, png: bool) -> Result<Vec<(String, Vec<u8>)>, String> {
    use crate::image::{Channel, Image, encode_exr, encode_png16};
    use crate::sampling::{blue_noise, stbn};
    let (size, slices, ranks): (u32, u32, [&[u32]; 2]) = match which {
        Own::BlueNoise => {
            let m = blue_noise::masks();
            (blue_noise::MASK_SIZE, 1, [m[0].ranks(), m[1].ranks()])
        }
        Own::Stbn => {
            let m = stbn::stbn_masks();
            (stbn::STBN_SIZE, stbn::STBN_DEPTH, [m[0].ranks(), m[1].ranks()])
        }
    };
    let n = (size * size) as usize;
    let stem = if which == Own::BlueNoise { "blue_noise".to_string() } else { "stbn_".to_string() };
    let mut out = Vec::new();
    for t in 0..slices as usize {
        let part = |c: usize| &ranks[c][t * n..(t + 1) * n];
        let name = |ext: &str| match which {
            Own::BlueNoise => format!("{stem}.{ext}"),
            Own::Stbn => format!("{stem}{t}.{ext}"),
        };
        let bytes = if png {
            let step = (1u32 << 16) / n as u32;
            let samples: Vec<u16> =
                (0..n).flat_map(|i| [(part(0)[i] * step) as u16, (part(1)[i] * step) as u16]).collect();
            (name("png"), encode_png16(size, size, 2, &samples)?)
        } else {
            let img = |c: usize| {
                Image::from_vec(size, size, part(c).iter().map(|&r| r as f32 / n as f32).collect())
            };
            let (r, g) = (img(0), img(1));
            (name("exr"), encode_exr(&[Channel { name: "R", image: &r }, Channel { name: "G", image: &g }])?)
        };
        out.push(bytes);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn patterns_take_plain_and_padded_numbers() {
        let p = |head, width, pad, tail| Ok(Some(Pattern { head, width, pad, tail }));
        assert_eq!(pattern("m/stbn_%d.png"), p("m/stbn_", 0, ' ', ".png"));
        assert_eq!(pattern("m/x%03d.exr"), p("m/x", 3, '0', ".exr"));
        assert_eq!(pattern("m/x%5d.exr"), p("m/x", 5, ' ', ".exr"));
        assert_eq!(pattern("m/x.png"), Ok(None));
        assert_eq!(pattern("m/100%.png"), Ok(None));
        assert!(pattern("s_%099999999999d.png").unwrap_err().contains("N up to 9"));
        assert!(pattern("s_%-5d.png").unwrap_err().contains("flag"));
    }
}
