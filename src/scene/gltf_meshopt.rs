//! `EXT_meshopt_compression` (Khronos, ratified vendor extension): a buffer view's bytes stored
//! compressed in another buffer, decoded here before anything reads the view. The compressed stream
//! is meshoptimizer's vertex codec (`ATTRIBUTES`, byte-wise deltas in blocks), index codec
//! (`TRIANGLES`, edge and vertex FIFOs) or index-sequence codec (`INDICES`), optionally followed by
//! a filter (`OCTAHEDRAL` normals, `QUATERNION` rotations, `EXPONENTIAL` floats); the decoders are
//! the pure-Rust port of meshoptimizer (`meshopt-rs`, at the bitstream versions the extension
//! fixes: vertex 0, index 0 and 1). The decoded bytes go where the view says (its buffer, offset
//! and length), so every reader downstream sees an ordinary buffer; a buffer marked
//! `fallback: true` has no data of its own and starts as zeros.

use meshopt_rs::index::{buffer::decode_index_buffer, sequence::decode_index_sequence};
use meshopt_rs::vertex::buffer::decode_vertex_buffer;
use meshopt_rs::vertex::filter::{
    decode_filter_exp, decode_filter_oct_8, decode_filter_oct_16, decode_filter_quat,
};
use serde_json::Value;

/// Whether buffer `i` is an `EXT_meshopt_compression` fallback buffer (no data of its own).
pub fn is_fallback(json: &Value, i: usize) -> bool {
    json["buffers"][i]["extensions"]["EXT_meshopt_compression"]["fallback"].as_bool() == Some(true)
}

/// Decodes every compressed buffer view of `json` into `buffers`.
pub fn decode_views(json: &Value, buffers: &mut [Vec<u8>]) -> Result<(), String> {
    let views = json.get("bufferViews").and_then(Value::as_array).map_or(&[][..], |v| &v[..]);
    for (i, view) in views.iter().enumerate() {
        let Some(ext) = view.get("extensions").and_then(|e| e.get("EXT_meshopt_compression")) else {
            continue;
        };
        decode_view(view, ext, buffers)
            .map_err(|e| format!("bufferView {i}: EXT_meshopt_compression: {e}"))?;
    }
    Ok(())
}

fn decode_view(view: &Value, ext: &Value, buffers: &mut [Vec<u8>]) -> Result<(), String> {
    let num = |v: &Value, k: &str, default: Option<u64>| {
        v.get(k)
            .map_or(default, Value::as_u64)
            .map(|n| n as usize)
            .ok_or_else(|| format!("`{k}` missing or not a count"))
    };
    let (src, offset, len) =
        (num(ext, "buffer", None)?, num(ext, "byteOffset", Some(0))?, num(ext, "byteLength", None)?);
    let (stride, count) = (num(ext, "byteStride", None)?, num(ext, "count", None)?);
    let mode = ext.get("mode").and_then(Value::as_str).unwrap_or("");
    let filter = ext.get("filter").and_then(Value::as_str).unwrap_or("NONE");
    let data = buffers
        .get(src)
        .and_then(|b| b.get(offset..offset.checked_add(len)?))
        .ok_or_else(|| format!("its data (buffer {src}, bytes {offset}..+{len}) lies outside the buffer"))?;
    let (dst, at, room) =
        (num(view, "buffer", None)?, num(view, "byteOffset", Some(0))?, num(view, "byteLength", None)?);
    // Before decoding: the decoder allocates count x stride bytes, which must fit in the view (a
    // count of 2^31 would otherwise ask the allocator for gigabytes, and an allocation failure aborts).
    if count.checked_mul(stride).is_none_or(|n| n > room) {
        return Err(format!("decodes to {count} x {stride} bytes, the view holds {room}"));
    }
    let mut out = decode(mode, stride, count, data)?;
    apply_filter(filter, mode, stride, &mut out)?;
    let target = buffers
        .get_mut(dst)
        .and_then(|b| b.get_mut(at..at.checked_add(out.len())?))
        .ok_or_else(|| format!("the view (buffer {dst}, bytes {at}..+{room}) lies outside its buffer"))?;
    target.copy_from_slice(&out);
    Ok(())
}

/// The stream decoded: `count` elements of `stride` bytes.
fn decode(mode: &str, stride: usize, count: usize, data: &[u8]) -> Result<Vec<u8>, String> {
    let failed = |e: &dyn std::fmt::Debug| format!("the {mode} stream does not decode ({e:?})");
    match mode {
        "ATTRIBUTES" => {
            if stride == 0 || stride > 256 || !stride.is_multiple_of(4) {
                return Err(format!("byteStride {stride}: ATTRIBUTES need a multiple of 4 up to 256"));
            }
            attributes(stride, count, data).map_err(|e| failed(&e))
        }
        "TRIANGLES" | "INDICES" => {
            if stride != 2 && stride != 4 {
                return Err(format!("byteStride {stride}: {mode} need 2 or 4"));
            }
            if mode == "TRIANGLES" && !count.is_multiple_of(3) {
                return Err(format!("count {count}: TRIANGLES need a multiple of 3"));
            }
            let mut ix = vec![0u32; count];
            if mode == "TRIANGLES" {
                decode_index_buffer(&mut ix, data).map_err(|e| failed(&e))?;
            } else {
                decode_index_sequence(&mut ix, data).map_err(|e| failed(&e))?;
            }
            // 16-bit indices were encoded from 16-bit values, so the low half is the whole value.
            Ok(if stride == 2 {
                ix.iter().flat_map(|&i| (i as u16).to_le_bytes()).collect()
            } else {
                ix.iter().flat_map(|&i| i.to_le_bytes()).collect()
            })
        }
        _ => Err(format!("mode '{mode}' is not ATTRIBUTES, TRIANGLES or INDICES")),
    }
}

/// The vertex codec at a stride known at run time: the decoder is generic over the vertex type, so
/// each stride the extension allows (4..=256 in steps of 4) gets its own `[u8; N]`.
fn attributes(stride: usize, count: usize, data: &[u8]) -> Result<Vec<u8>, meshopt_rs::vertex::DecodeError> {
    fn at<const N: usize>(count: usize, data: &[u8]) -> Result<Vec<u8>, meshopt_rs::vertex::DecodeError> {
        let mut v = vec![[0u8; N]; count];
        decode_vertex_buffer(&mut v, data)?;
        Ok(v.into_iter().flatten().collect())
    }
    macro_rules! strides {
        ($($n:literal)*) => {
            match stride {
                $($n => at::<$n>(count, data),)*
                _ => unreachable!("checked: a multiple of 4 up to 256"),
            }
        };
    }
    strides!(4 8 12 16 20 24 28 32 36 40 44 48 52 56 60 64 68 72 76 80 84 88 92 96 100 104 108 112 116
        120 124 128 132 136 140 144 148 152 156 160 164 168 172 176 180 184 188 192 196 200 204 208 212 216
        220 224 228 232 236 240 244 248 252 256)
}

/// The extension's filters, in place on the decoded little-endian bytes.
fn apply_filter(filter: &str, mode: &str, stride: usize, out: &mut [u8]) -> Result<(), String> {
    if filter != "NONE" && mode != "ATTRIBUTES" {
        return Err(format!("filter {filter} applies to ATTRIBUTES only, not {mode}"));
    }
    match (filter, stride) {
        ("NONE", _) => {}
        ("OCTAHEDRAL", 4) => {
            let mut v: Vec<[u8; 4]> = out.chunks_exact(4).map(|c| [c[0], c[1], c[2], c[3]]).collect();
            decode_filter_oct_8(&mut v);
            out.copy_from_slice(&v.concat());
        }
        ("OCTAHEDRAL", 8) | ("QUATERNION", 8) => {
            let mut v: Vec<[u16; 4]> = out
                .chunks_exact(8)
                .map(|c| std::array::from_fn(|k| u16::from_le_bytes([c[2 * k], c[2 * k + 1]])))
                .collect();
            if filter == "OCTAHEDRAL" {
                decode_filter_oct_16(&mut v);
            } else {
                decode_filter_quat(&mut v);
            }
            let bytes: Vec<u8> = v.iter().flatten().flat_map(|x| x.to_le_bytes()).collect();
            out.copy_from_slice(&bytes);
        }
        ("EXPONENTIAL", _) => {
            let mut v: Vec<u32> =
                out.chunks_exact(4).map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect();
            decode_filter_exp(&mut v);
            let bytes: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
            out.copy_from_slice(&bytes);
        }
        ("OCTAHEDRAL" | "QUATERNION", _) => {
            return Err(format!(
                "filter {filter} with byteStride {stride} (OCTAHEDRAL needs 4 or 8, QUATERNION 8)"
            ));
        }
        _ => return Err(format!("filter '{filter}' is not NONE, OCTAHEDRAL, QUATERNION or EXPONENTIAL")),
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    // Streams written by meshoptimizer's own C++ encoder (the PyPI wrapper `meshoptimizer`
    // 0.2.30a0; vertex codec version 0, index codecs version 1, as the extension fixes), so the
    // pure-Rust decoder is checked against the reference implementation, not against its own encoder.
    const VERTICES: [u8; 79] = [
        160, 0, 0, 3, 0, 255, 255, 128, 127, 255, 255, 128, 127, 255, 255, 128, 127, 255, 255, 128, 1, 56,
        248, 248, 248, 124, 125, 124, 125, 124, 125, 124, 0, 0, 1, 0, 0, 192, 192, 255, 128, 1, 0, 192, 0, 0,
        126, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
    ];
    const TRIANGLES: [u8; 27] = [
        225, 254, 30, 16, 14, 78, 30, 18, 14, 15, 6, 0, 118, 135, 86, 103, 120, 169, 134, 101, 137, 104, 152,
        1, 105, 0, 0,
    ];
    const SEQUENCE: [u8; 17] = [209, 0, 4, 4, 4, 2, 2, 16, 12, 14, 0, 12, 2, 0, 0, 0, 0];

    fn u32s(b: &[u8]) -> Vec<u32> {
        b.chunks_exact(4).map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect()
    }

    #[test]
    fn streams_of_the_reference_encoder_decode_to_what_it_encoded() {
        // A 4 x 4 grid of (x/4, y/2) as f32 pairs, 8 bytes a vertex.
        let want: Vec<u8> = (0..16)
            .flat_map(|i| [(i % 4) as f32 * 0.25, (i / 4) as f32 * 0.5])
            .flat_map(f32::to_le_bytes)
            .collect();
        assert_eq!(decode("ATTRIBUTES", 8, 16, &VERTICES).unwrap(), want);
        // Eight triangles of a 3 x 3 grid; the codec may start a triangle at another corner (same
        // winding), so each is compared up to rotation.
        let tris = [0, 1, 3, 1, 4, 3, 1, 2, 4, 2, 5, 4, 3, 4, 6, 4, 7, 6, 4, 5, 7, 5, 8, 7];
        let got = u32s(&decode("TRIANGLES", 4, 24, &TRIANGLES).unwrap());
        let turn = |t: &[u32]| {
            let k = (0..3).min_by_key(|&k| t[k]).unwrap();
            [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
        };
        assert!(got.chunks(3).zip(tris.chunks(3)).all(|(a, b)| turn(a) == turn(b)), "{got:?}");
        // 16-bit indices are the same values, two bytes each.
        let short = decode("TRIANGLES", 2, 24, &TRIANGLES).unwrap();
        assert_eq!(short.chunks(2).map(|c| u16::from_le_bytes([c[0], c[1]]) as u32).collect::<Vec<_>>(), got);
        let seq = [0, 1, 2, 3, 2, 1, 5, 8, 4, 4, 7, 6];
        assert_eq!(u32s(&decode("INDICES", 4, 12, &SEQUENCE).unwrap()), seq);
        assert!(decode("ATTRIBUTES", 6, 16, &VERTICES).unwrap_err().contains("multiple of 4"));
        assert!(decode("ATTRIBUTES", 8, 16, &VERTICES[..20]).unwrap_err().contains("does not decode"));
    }

    #[test]
    fn the_exponential_filter_gives_m_times_two_to_the_e() {
        // 3 · 2^-2 = 0.75 and -5 · 2^3 = -40: exponent in the top byte, 24-bit signed mantissa.
        let enc = |m: i32, e: i8| (((e as u8 as u32) << 24) | (m as u32 & 0x00FF_FFFF)).to_le_bytes();
        let mut b: Vec<u8> = [enc(3, -2), enc(-5, 3)].concat();
        apply_filter("EXPONENTIAL", "ATTRIBUTES", 8, &mut b).unwrap();
        let f: Vec<f32> = u32s(&b).into_iter().map(f32::from_bits).collect();
        assert_eq!(f, [0.75, -40.0]);
        assert!(apply_filter("EXPONENTIAL", "TRIANGLES", 4, &mut b).is_err());
        assert!(apply_filter("QUATERNION", "ATTRIBUTES", 4, &mut b).unwrap_err().contains("QUATERNION 8"));
    }
}
