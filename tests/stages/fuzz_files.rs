//! Mutated binary and structured inputs, through the library in-process: glTF and GLB files (their
//! JSON mutated as a tree, their bytes and buffers as bytes; plain, quantized, meshopt-compressed,
//! with cameras and a node tree, and the shipped foliage scene), PNG and EXR noise textures (a PNG's
//! chunk checksums recomputed for half the cases, so the mutation reaches the decoder), and `.npy`
//! point sets (their header text and their bytes). Each case is read, or refused with one message
//! (one line, and for glTF found by the checks, not caught as a panic): never a panic, which
//! `catch_unwind` reports with its case, and never a hang, which a watchdog reports by aborting
//! with the case that did not return. (An allocation failure aborts too: the run's output then
//! ends at the case.) The mutations are seeded: a failure names a case that reproduces.

use crate::support::gltf_ext::masked_square;
use crate::support::mutate::{Rng, mutate, mutate_bytes, mutate_json};
use hemilab::render::render;
use hemilab::sampling::texture::TextureUse;
use hemilab::sampling::{Distribution, SamplerConfig, SeedMode, Sequence};
use hemilab::scene::camera::{Camera, WorldCamera};
use hemilab::scene::gltf_mesh::parse_gltf;
use hemilab::scene::gltf_write::{Node, glb, meshopt_compress, quantize};
use hemilab::scene::{Scene, gltf_write};
use serde_json::Value;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// Longer than any case takes on a loaded machine (milliseconds), far shorter than a hang.
const HANG: Duration = Duration::from_secs(60);

/// Aborts the test binary, naming the case, if a case runs longer than `HANG`.
struct Watchdog {
    case: Arc<Mutex<(Instant, String)>>,
    done: Arc<AtomicBool>,
}

impl Watchdog {
    fn new() -> Self {
        let case = Arc::new(Mutex::new((Instant::now(), String::new())));
        let done = Arc::new(AtomicBool::new(false));
        let (c, d) = (case.clone(), done.clone());
        std::thread::spawn(move || {
            while !d.load(Ordering::Relaxed) {
                std::thread::sleep(Duration::from_millis(200));
                let (start, name) = c.lock().unwrap().clone();
                if start.elapsed() > HANG && !d.load(Ordering::Relaxed) {
                    eprintln!("fuzz: case {name} has not returned after {HANG:?}: a hang");
                    std::process::abort();
                }
            }
        });
        Watchdog { case, done }
    }

    fn start(&self, name: String) {
        *self.case.lock().unwrap() = (Instant::now(), name);
    }
}

impl Drop for Watchdog {
    fn drop(&mut self) {
        self.done.store(true, Ordering::Relaxed);
    }
}

/// One case: its number and its bytes; Ok if they were read, else the one message.
type Case<'a> = dyn Fn(u64, &[u8]) -> Result<(), String> + 'a;

/// Runs `case` on `cases` mutations (`mutate`) of each seed; fails with the cases that panicked,
/// whose message was not one line or was a panic the wall caught (`scene::guard`: a check missed
/// it), or if no mutation was accepted or none refused.
fn fuzz(name: &str, seeds: &[Vec<u8>], cases: u64, mutate: &dyn Fn(&[u8], &mut Rng) -> Vec<u8>, case: &Case) {
    // A longer run by hand: HEMILAB_FUZZ_CASES=100000 cargo test --release --test stages fuzz_files
    let cases = std::env::var("HEMILAB_FUZZ_CASES").ok().and_then(|c| c.parse().ok()).unwrap_or(cases);
    let watchdog = Watchdog::new();
    let (mut failed, mut accepted, mut total) = (Vec::new(), 0, 0);
    let began = Instant::now();
    for (k, seed) in seeds.iter().enumerate() {
        for n in 0..cases {
            let mut rng = Rng::new(0xF17E_0000 ^ ((k as u64) << 32 | n));
            let bytes = mutate(seed, &mut rng);
            watchdog.start(format!("{name} seed {k} case {n}"));
            let why = match catch_unwind(AssertUnwindSafe(|| case(n, &bytes))) {
                Ok(Ok(())) => {
                    accepted += 1;
                    None
                }
                Ok(Err(e)) if e.lines().count() == 1 && !e.contains("reader failed") => None,
                Ok(Err(e)) => Some(e),
                Err(p) => {
                    let what = p
                        .downcast_ref::<String>()
                        .cloned()
                        .or(p.downcast_ref::<&str>().map(|s| s.to_string()));
                    Some(format!("panicked: {}", what.unwrap_or_default()))
                }
            };
            if let Some(why) = why {
                // The input kept beside the message, to open by hand.
                let kept =
                    std::env::temp_dir().join(format!("hemilab-fuzz-{}-{k}-{n}", name.replace(' ', "-")));
                std::fs::write(&kept, &bytes).unwrap();
                failed.push(format!("seed {k} case {n} (input kept as {}): {why}", kept.display()));
            }
            total += 1;
        }
    }
    let took = began.elapsed().as_secs_f64();
    assert!(
        failed.is_empty(),
        "{name}: {} of {total} failed, e.g.\n{}",
        failed.len(),
        failed[..failed.len().min(5)].join("\n")
    );
    eprintln!("{name}: {total} mutated files, {accepted} accepted, none panicked or hung ({took:.1} s)");
    assert!(accepted > 0 && accepted < total, "{name}: {accepted} of {total} accepted");
}

/// A glTF seed: its JSON and binary buffer.
fn gltf_seeds() -> Vec<(Value, Vec<u8>)> {
    let plain = masked_square().encode(None);
    let mut quantized = masked_square().encode(None);
    quantize(&mut quantized.0, &mut quantized.1, "POSITION", 5122, false);
    quantize(&mut quantized.0, &mut quantized.1, "TEXCOORD_0", 5121, true);
    let mut packed = masked_square().encode(None);
    packed.1 = meshopt_compress(&mut packed.0, &packed.1, true);
    // A node tree with transforms and a camera (a child of the square's node).
    let mut tree = masked_square();
    tree.nodes[0].children = vec![2];
    tree.nodes.push(Node { camera: Some(0), translation: Some([0.5, 0.5, 3.0]), ..Node::default() });
    tree.nodes.push(Node { mesh: Some(0), scale: Some([0.5; 3]), children: vec![], ..Node::default() });
    tree.nodes[1].children = vec![3];
    tree.cameras = vec![0.8];
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let foliage: Value = serde_json::from_slice(&std::fs::read(root.join("foliage.gltf")).unwrap()).unwrap();
    let bin = std::fs::read(root.join("foliage.bin")).unwrap();
    vec![plain, quantized, packed, tree.encode(None), (foliage, bin)]
}

/// The glTF and GLB files are read, and what is read becomes a scene that renders (4 x 3 pixels).
#[test]
fn mutated_gltf_files_are_read_or_refused_with_one_message() {
    let seeds = gltf_seeds();
    let leaf = std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/foliage-leaf.png")).unwrap();
    // Seed k as bytes: k then the GLB (the external-buffer seed keeps its JSON text and buffer).
    let files: Vec<Vec<u8>> = (0..seeds.len() as u8).map(|k| vec![k]).collect();
    let mutate_case = |tag: &[u8], rng: &mut Rng| -> Vec<u8> {
        let (doc, bin) = &seeds[tag[0] as usize];
        let (doc, bin) = match rng.below(4) {
            0 | 1 => (mutate_json(doc, rng), bin.clone()),
            2 => (doc.clone(), mutate_bytes(bin, rng)),
            _ => {
                let text = mutate(&serde_json::to_string(doc).unwrap(), rng);
                let mut out = vec![tag[0], 1];
                out.extend(glb_text(&text, bin));
                return out;
            }
        };
        let mut out = vec![tag[0], 0];
        out.extend(glb(&doc, &bin));
        out
    };
    let view = WorldCamera::from(Camera::Perspective {
        eye: glam::DVec3::new(0.5, 0.5, 3.0),
        target: glam::DVec3::new(0.5, 0.5, 0.0),
        up: glam::DVec3::Y,
        fov_y_deg: 45.0,
    });
    fuzz("glTF", &files, 3000, &mutate_case, &|_, bytes| {
        let (k, file) = (bytes[0] as usize, &bytes[2..]);
        let bin = &seeds[k].1;
        // The foliage scene names its buffer and leaf texture by URI; the others use the GLB chunk.
        let mut fetch = |uri: &str| -> Result<Vec<u8>, String> {
            match uri {
                "foliage.bin" => Ok(bin.clone()),
                "foliage-leaf.png" => Ok(leaf.clone()),
                _ => Err(format!("file '{uri}' not found")),
            }
        };
        let g = parse_gltf(file, &mut fetch)?;
        let scene = Scene::new("fuzz".into(), view, (4, 3), 1.0, String::new(), g.mesh, None)?;
        let sampler = SamplerConfig::new(Sequence::Fibonacci, SeedMode::Rotation, 2, 1).unwrap();
        let job = crate::support::jobs::render_job(Distribution::SineCosine, sampler, (4, 3), 1.0);
        let out = render(&scene, &job, &|_| {});
        assert!(out.ao.data.iter().all(|v| v.is_finite()));
        Ok(())
    });
}

/// A GLB of JSON `text` (which may no longer be JSON) and `bin`.
fn glb_text(text: &str, bin: &[u8]) -> Vec<u8> {
    let doc = gltf_write::glb(&Value::Null, bin);
    // The GLB of `null`, with its JSON chunk replaced by `text` (padded) and the lengths fixed.
    let mut json = text.as_bytes().to_vec();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let old = u32::from_le_bytes(doc[12..16].try_into().unwrap()) as usize;
    let mut out = doc[..12].to_vec();
    out.extend((json.len() as u32).to_le_bytes());
    out.extend(&doc[16..20]);
    out.extend(&json);
    out.extend(&doc[20 + old..]);
    let total = out.len() as u32;
    out[8..12].copy_from_slice(&total.to_le_bytes());
    out
}

/// CRC-32 (ISO 3309, as PNG's chunks use it).
fn crc32(bytes: &[u8]) -> u32 {
    let mut c = !0u32;
    for &b in bytes {
        c ^= b as u32;
        for _ in 0..8 {
            c = if c & 1 != 0 { 0xEDB8_8320 ^ (c >> 1) } else { c >> 1 };
        }
    }
    !c
}

/// A PNG with every whole chunk's checksum recomputed (a mutated file then reaches the decoder).
fn fix_crcs(png: &mut [u8]) {
    let mut at = 8;
    while at + 12 <= png.len() {
        let len = u32::from_be_bytes(png[at..at + 4].try_into().unwrap()) as usize;
        let Some(end) = (at + 8).checked_add(len).filter(|&e| e + 4 <= png.len()) else { break };
        let crc = crc32(&png[at + 4..end]);
        png[end..end + 4].copy_from_slice(&crc.to_be_bytes());
        at = end + 4;
    }
}

fn png(img: image::DynamicImage) -> Vec<u8> {
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}

/// PNG and EXR textures, each read for one of the three uses.
#[test]
fn mutated_textures_are_read_or_refused_with_one_message() {
    use hemilab::image::{Channel, Image, encode_exr};
    let t = crate::support::common::Tmp::new("fuzz-textures");
    let ramp =
        |c: u32| Image::from_vec(8, 8, (0..64).map(|i| ((i * 7 + c * 13) % 64) as f32 / 64.0).collect());
    let (r, g, b) = (ramp(0), ramp(1), ramp(2));
    let seeds: Vec<Vec<u8>> = vec![
        png(image::DynamicImage::ImageLuma8(image::GrayImage::from_fn(8, 8, |x, y| {
            image::Luma([(x * 32 + y * 4) as u8])
        }))),
        png(image::DynamicImage::ImageLumaA16(image::ImageBuffer::from_fn(8, 8, |x, y| {
            image::LumaA([(x * 8192) as u16, (y * 8192) as u16])
        }))),
        png(image::DynamicImage::ImageRgb8(image::RgbImage::from_fn(8, 8, |x, y| {
            image::Rgb([x as u8 * 16, y as u8 * 16, 240])
        }))),
        encode_exr(&[Channel { name: "Y", image: &r }]).unwrap(),
        encode_exr(&[
            Channel { name: "R", image: &r },
            Channel { name: "G", image: &g },
            Channel { name: "B", image: &b },
        ])
        .unwrap(),
    ];
    let mutate_case = |seed: &[u8], rng: &mut Rng| {
        let mut b = mutate_bytes(seed, rng);
        if seed.starts_with(b"\x89PNG") && rng.below(2) == 0 {
            fix_crcs(&mut b);
        }
        b
    };
    fuzz("textures", &seeds, 1000, &mutate_case, &|n, bytes| {
        let ext = if bytes.starts_with(b"\x89PNG") || n % 2 == 0 { "png" } else { "exr" };
        let name = format!("c{n}.{ext}");
        std::fs::write(t.path(&name), bytes).unwrap();
        let use_ = TextureUse::ALL[n as usize % 3];
        let got = hemilab::load::texture::texture(&t, &name, use_);
        std::fs::remove_file(t.path(&name)).unwrap();
        got.map(|_| ()).map_err(|e| if e.contains(&name) { e } else { format!("{e} (names no file)\n") })
    });
}

/// An `.npy` of `n` points (x, y) in float64 or float32, C or Fortran order, little or big endian.
fn npy(sets: usize, n: usize, f8: bool, fortran: bool, big: bool) -> Vec<u8> {
    let descr = format!("{}f{}", if big { '>' } else { '<' }, if f8 { 8 } else { 4 });
    let shape = if sets == 1 { format!("({n}, 2)") } else { format!("({sets}, {n}, 2)") };
    let mut header = format!(
        "{{'descr': '{descr}', 'fortran_order': {}, 'shape': {shape}, }}",
        if fortran { "True" } else { "False" }
    );
    while (10 + header.len() + 1) % 64 != 0 {
        header.push(' ');
    }
    header.push('\n');
    let mut b = b"\x93NUMPY\x01\x00".to_vec();
    b.extend((header.len() as u16).to_le_bytes());
    b.extend(header.as_bytes());
    for k in 0..sets * n * 2 {
        let v = ((k * 37) % 101) as f64 / 101.0;
        match (f8, big) {
            (true, false) => b.extend(v.to_le_bytes()),
            (true, true) => b.extend(v.to_be_bytes()),
            (false, false) => b.extend((v as f32).to_le_bytes()),
            (false, true) => b.extend((v as f32).to_be_bytes()),
        }
    }
    b
}

/// `.npy` point sets: their header as text (its length field kept right) or their bytes.
#[test]
fn mutated_point_sets_are_read_or_refused_with_one_message() {
    let t = crate::support::common::Tmp::new("fuzz-points");
    let seeds =
        vec![npy(1, 16, true, false, false), npy(3, 8, false, true, false), npy(2, 8, true, false, true)];
    let mutate_case = |seed: &[u8], rng: &mut Rng| {
        if rng.below(2) == 0 {
            return mutate_bytes(seed, rng);
        }
        let len = u16::from_le_bytes([seed[8], seed[9]]) as usize;
        let header = mutate(std::str::from_utf8(&seed[10..10 + len]).unwrap(), rng);
        let mut b = seed[..8].to_vec();
        b.extend((header.len().min(65_535) as u16).to_le_bytes());
        b.extend(header.as_bytes());
        b.extend(&seed[10 + len..]);
        b
    };
    fuzz("point sets", &seeds, 1000, &mutate_case, &|n, bytes| {
        let name = format!("p{n}.npy");
        std::fs::write(t.path(&name), bytes).unwrap();
        let got = hemilab::load::points::points(&t, &name);
        std::fs::remove_file(t.path(&name)).unwrap();
        got.map(|_| ()).map_err(|e| if e.contains(&name) { e } else { format!("{e} (names no file)\n") })
    });
}
