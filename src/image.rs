//! Float images and their encodings (EXR, PNG) as bytes. No filesystem access here.

use std::io::Cursor;

/// One float channel, row-major, `data[y * width + x]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub data: Vec<f32>,
}

impl Image {
    pub fn new(width: u32, height: u32) -> Self {
        Self { width, height, data: vec![0.0; width as usize * height as usize] }
    }

    pub fn from_vec(width: u32, height: u32, data: Vec<f32>) -> Self {
        assert_eq!(data.len(), width as usize * height as usize, "image data does not match its size");
        Self { width, height, data }
    }

    pub fn len(&self) -> usize {
        self.data.len()
    }

    pub fn is_empty(&self) -> bool {
        self.data.is_empty()
    }

    pub fn at(&self, x: u32, y: u32) -> f32 {
        self.data[y as usize * self.width as usize + x as usize]
    }

    /// The `w` × `h` window whose top-left pixel is (x, y), clipped to the image.
    pub fn crop(&self, x: u32, y: u32, w: u32, h: u32) -> Image {
        let (x, y) = (x.min(self.width), y.min(self.height));
        let (w, h) = (w.min(self.width - x), h.min(self.height - y));
        let data =
            (y..y + h).flat_map(|r| (x..x + w).map(move |c| (r, c))).map(|(r, c)| self.at(c, r)).collect();
        Image::from_vec(w, h, data)
    }

    pub fn same_size(&self, other: &Image) -> bool {
        self.width == other.width && self.height == other.height
    }
}

/// A fast key of pixel data (not cryptographic): 32-bit words mixed into four independent lanes
/// (word i into lane i mod 4, restarting with each `mix`), so that hashing a frame costs a small
/// part of the work a cache keyed by it saves. The caches that use it (`denoise::taps`,
/// `jobs::flip_refs`) key tables made from images by it.
#[derive(Debug, Clone, Copy)]
pub struct WordHash {
    lanes: [u64; 4],
}

impl WordHash {
    const K: u64 = 0x9E37_79B9_7F4A_7C15;

    /// Starts from four words of the caller's (sizes, parameters).
    pub fn new(lanes: [u64; 4]) -> Self {
        Self { lanes }
    }

    /// Mixes `words` in.
    pub fn mix(&mut self, words: impl IntoIterator<Item = u32>) {
        for (i, w) in words.into_iter().enumerate() {
            let l = &mut self.lanes[i & 3];
            *l = (*l ^ w as u64).wrapping_mul(Self::K).rotate_left(29);
        }
    }

    /// The key.
    pub fn finish(&self) -> u64 {
        self.lanes.iter().fold(0u64, |h, &l| (h ^ l).wrapping_mul(Self::K).rotate_left(31))
    }
}

/// Coverage masks are 1.0 (a surface) or 0.0 (background); anything above one half counts. (Here,
/// beside `Image`, so that `metrics` and `denoise` read masks by one rule without importing each
/// other.)
pub fn covered(mask: &Image, i: usize) -> bool {
    mask.data[i] > 0.5
}

/// A named channel for an EXR file.
pub struct Channel<'a> {
    pub name: &'a str,
    pub image: &'a Image,
}

/// Where an image came from, for its EXR header: a sentence for people (the standard `comments`
/// attribute, which viewers such as OpenImageIO's `iinfo -v` show) and the same facts as a JSON
/// object for programs (the `hemilab` attribute); `software` names the version. One custom
/// attribute only: the exr crate keeps them in a hash map and writes them in its (random) order,
/// and an image's bytes must not change from one run to the next.
#[derive(Debug, Clone, PartialEq)]
pub struct Provenance {
    pub summary: String,
    pub json: serde_json::Value,
}

/// The name of the JSON attribute.
pub const PROVENANCE_ATTRIBUTE: &str = "hemilab";

/// EXR text attributes hold bytes, not Unicode: JSON with every non-ASCII character escaped
/// (`\u00e9`, surrogate pairs beyond the basic plane), and a summary with `?` in their place.
fn ascii_json(v: &serde_json::Value) -> String {
    let mut out = String::new();
    for c in v.to_string().chars() {
        if c.is_ascii() {
            out.push(c);
        } else {
            for unit in c.encode_utf16(&mut [0; 2]) {
                out.push_str(&format!("\\u{unit:04x}"));
            }
        }
    }
    out
}

/// Encodes single-precision channels losslessly (round trips bit-exactly).
/// Viewers show "Y" as grey and "A" as alpha, so AO goes in Y and coverage in A.
pub fn encode_exr(channels: &[Channel]) -> Result<Vec<u8>, String> {
    encode_exr_with(channels, None)
}

/// `encode_exr`, with the image's provenance in its header.
pub fn encode_exr_with(channels: &[Channel], provenance: Option<&Provenance>) -> Result<Vec<u8>, String> {
    use exr::prelude::*;
    let first = channels.first().ok_or("an EXR needs at least one channel")?;
    let (w, h) = (first.image.width as usize, first.image.height as usize);
    let list: SmallVec<[AnyChannel<FlatSamples>; 4]> =
        channels.iter().map(|c| AnyChannel::new(c.name, FlatSamples::F32(c.image.data.clone()))).collect();
    if channels.iter().any(|c| c.image.width as usize != w || c.image.height as usize != h) {
        return Err("EXR channels differ in size".into());
    }
    let mut attributes = LayerAttributes::named("hemilab");
    if let Some(p) = provenance {
        let summary: String = p.summary.chars().map(|c| if c.is_ascii() { c } else { '?' }).collect();
        attributes.comments = Some(Text::from(summary.as_str()));
        attributes.software_name = Some(Text::from(concat!("hemilab ", env!("CARGO_PKG_VERSION"))));
        attributes.other.insert(
            Text::from(PROVENANCE_ATTRIBUTE),
            AttributeValue::Text(Text::from(ascii_json(&p.json).as_str())),
        );
    }
    let layer = Layer::new((w, h), attributes, Encoding::SMALL_LOSSLESS, AnyChannels::sort(list));
    let mut bytes = Cursor::new(Vec::new());
    // On the calling thread: exr's parallel compression sends a small image's blocks to rayon's
    // global pool, whose idle threads then spin beside the run's timing workers (the integrands
    // spec's 2,544 small images: a third of both cores' time went to yielding threads).
    exr::prelude::Image::from_layer(layer)
        .write()
        .non_parallel()
        .to_buffered(&mut bytes)
        .map_err(|e| e.to_string())?;
    Ok(bytes.into_inner())
}

/// Decodes every channel of the first layer as f32, by name.
pub fn decode_exr(bytes: &[u8]) -> Result<Vec<(String, Image)>, String> {
    use exr::prelude::*;
    // On the calling thread, as `encode_exr_with` writes: exr's parallel reader builds a thread
    // pool per image (4,029 of them in a run of the integrands spec).
    let img = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .non_parallel()
        .from_buffered(Cursor::new(bytes))
        .map_err(|e| e.to_string())?;
    let size = img.layer_data.size;
    Ok(img
        .layer_data
        .channel_data
        .list
        .iter()
        .map(|c| {
            let data: Vec<f32> = c.sample_data.values_as_f32().collect();
            (c.name.to_string(), crate::image::Image::from_vec(size.0 as u32, size.1 as u32, data))
        })
        .collect())
}

/// The provenance an EXR's header holds (`encode_exr_with`): its summary and its JSON, if it has
/// them.
pub fn decode_exr_provenance(bytes: &[u8]) -> Result<Option<Provenance>, String> {
    use exr::meta::attribute::AttributeValue;
    let meta =
        exr::meta::MetaData::read_from_buffered(Cursor::new(bytes), false).map_err(|e| e.to_string())?;
    let Some(header) = meta.headers.first() else { return Ok(None) };
    let a = &header.own_attributes;
    let json = match a.other.get(&exr::meta::attribute::Text::from(PROVENANCE_ATTRIBUTE)) {
        Some(AttributeValue::Text(t)) => serde_json::from_str(&t.to_string()).map_err(|e| e.to_string())?,
        _ => return Ok(None),
    };
    let summary = a.comments.as_ref().map(|t| t.to_string()).unwrap_or_default();
    Ok(Some(Provenance { summary, json }))
}

/// 8-bit grey PNG of values in \[0, 1\] (clamped), for previews.
pub fn encode_png_gray(image: &Image) -> Result<Vec<u8>, String> {
    let pixels: Vec<u8> = image.data.iter().map(|&v| to_u8(v)).collect();
    encode_png(image.width, image.height, ::image::ExtendedColorType::L8, &pixels)
}

/// 8-bit RGB PNG from interleaved bytes.
pub fn encode_png_rgb(width: u32, height: u32, rgb: &[u8]) -> Result<Vec<u8>, String> {
    encode_png(width, height, ::image::ExtendedColorType::Rgb8, rgb)
}

/// 8-bit grey + alpha PNG from interleaved (grey, alpha) bytes: a preview whose pixels without a
/// surface are transparent.
pub fn encode_png_grey_alpha(width: u32, height: u32, grey_alpha: &[u8]) -> Result<Vec<u8>, String> {
    encode_png(width, height, ::image::ExtendedColorType::La8, grey_alpha)
}

/// 8-bit indexed-colour PNG: one palette index a pixel, at most 256 colours. A colour-mapped image
/// (a diverging or magma map) takes a third of the bytes of its RGB form.
pub fn encode_png_indexed(
    width: u32,
    height: u32,
    palette: &[[u8; 3]],
    indices: &[u8],
) -> Result<Vec<u8>, String> {
    if palette.is_empty() || palette.len() > 256 {
        return Err(format!("a PNG palette has 1 to 256 colours, not {}", palette.len()));
    }
    if indices.len() != width as usize * height as usize
        || indices.iter().any(|&i| i as usize >= palette.len())
    {
        return Err(format!(
            "{} indices into {} colours are not a {width}x{height} image",
            indices.len(),
            palette.len()
        ));
    }
    let mut out = Vec::new();
    let mut enc = png::Encoder::new(&mut out, width, height);
    enc.set_color(png::ColorType::Indexed);
    enc.set_depth(png::BitDepth::Eight);
    enc.set_palette(palette.iter().flatten().copied().collect::<Vec<u8>>());
    let mut w = enc.write_header().map_err(|e| e.to_string())?;
    w.write_image_data(indices).map_err(|e| e.to_string())?;
    w.finish().map_err(|e| e.to_string())?;
    Ok(out)
}

/// 16-bit PNG of interleaved samples with `channels` per pixel (1 grey, 2 grey + alpha, 3 RGB,
/// 4 RGBA): how hemilab's own masks are written as noise textures (examples/write_masks.rs).
pub fn encode_png16(width: u32, height: u32, channels: u32, samples: &[u16]) -> Result<Vec<u8>, String> {
    use ::image::{DynamicImage as D, ImageBuffer};
    let raw = samples.to_vec();
    let bad = || format!("{} samples are not {width}x{height}x{channels}", samples.len());
    let img = match channels {
        1 => D::ImageLuma16(ImageBuffer::from_raw(width, height, raw).ok_or_else(bad)?),
        2 => D::ImageLumaA16(ImageBuffer::from_raw(width, height, raw).ok_or_else(bad)?),
        3 => D::ImageRgb16(ImageBuffer::from_raw(width, height, raw).ok_or_else(bad)?),
        4 => D::ImageRgba16(ImageBuffer::from_raw(width, height, raw).ok_or_else(bad)?),
        _ => return Err(format!("a PNG has 1 to 4 channels, not {channels}")),
    };
    let mut out = Cursor::new(Vec::new());
    img.write_to(&mut out, ::image::ImageFormat::Png).map_err(|e| e.to_string())?;
    Ok(out.into_inner())
}

fn encode_png(
    width: u32,
    height: u32,
    color: ::image::ExtendedColorType,
    pixels: &[u8],
) -> Result<Vec<u8>, String> {
    use ::image::ImageEncoder;
    let mut out = Vec::new();
    ::image::codecs::png::PngEncoder::new(&mut out)
        .write_image(pixels, width, height, color)
        .map_err(|e| e.to_string())?;
    Ok(out)
}

/// Quantizes \[0, 1\] to 0..=255, treating NaN as 0.
pub fn to_u8(v: f32) -> u8 {
    if v.is_nan() { 0 } else { (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exr_round_trip_is_bit_exact() {
        let a = Image::from_vec(3, 2, vec![0.0, 1.0, 0.25, f32::MIN_POSITIVE, 0.1, 1e-30]);
        let m = Image::from_vec(3, 2, vec![1.0, 0.0, 1.0, 1.0, 0.0, 1.0]);
        let bytes =
            encode_exr(&[Channel { name: "Y", image: &a }, Channel { name: "A", image: &m }]).unwrap();
        let back = decode_exr(&bytes).unwrap();
        let y = &back.iter().find(|(n, _)| n == "Y").unwrap().1;
        let al = &back.iter().find(|(n, _)| n == "A").unwrap().1;
        assert_eq!(
            y.data.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
            a.data.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
        );
        assert_eq!(al, &m);
    }

    #[test]
    fn provenance_is_in_the_header_and_leaves_the_pixels_alone() {
        let a = Image::from_vec(2, 1, vec![0.5, 1.0]);
        let p = Provenance {
            summary: "hemilab: 4 rays, scene 'café'".into(),
            json: serde_json::json!({ "rays": 4, "scene": "café", "far": "𝄞" }),
        };
        let plain = encode_exr(&[Channel { name: "Y", image: &a }]).unwrap();
        let tagged = encode_exr_with(&[Channel { name: "Y", image: &a }], Some(&p)).unwrap();
        assert_eq!(decode_exr(&plain).unwrap(), decode_exr(&tagged).unwrap());
        let back = decode_exr_provenance(&tagged).unwrap().unwrap();
        assert_eq!(back.json, p.json, "non-ASCII survives as JSON escapes");
        assert_eq!(back.summary, "hemilab: 4 rays, scene 'caf?'");
        assert_eq!(decode_exr_provenance(&plain).unwrap(), None);
        let again = encode_exr_with(&[Channel { name: "Y", image: &a }], Some(&p)).unwrap();
        assert_eq!(tagged, again, "the same bytes every time");
    }

    #[test]
    fn png_starts_with_signature() {
        let png = encode_png_gray(&Image::from_vec(2, 1, vec![0.0, 1.0])).unwrap();
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    }
}
