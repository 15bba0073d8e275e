//! Noise textures from files: hemilab's own blue-noise and STBN masks written as PNG and
//! EXR and read back as `offset` textures render the built-in modes' images bit for bit; a
//! texture's offsets are uniform over pixels and frames and, in each pixel, over run seeds (so the
//! offset mode is unbiased per pixel); a texture that is not uniform is measured as such and not
//! claimed unbiased; a vector texture's directions are what the renderer traces; every bad file is
//! one error naming it.

use crate::support::common::Tmp;
use crate::support::stats::{chi2_test, sidak_threshold};
use glam::{Vec2, Vec3};
use hemilab::compare::per_pixel_unbiased;
use hemilab::load::load_scene;
use hemilab::load::texture::{Own, own_masks, texture};
use hemilab::render::render;
use hemilab::sampling::seed::PixelSeed;
use hemilab::sampling::texture::TextureUse;
use hemilab::sampling::{Distribution, SamplerConfig, Schedule, SeedMode, Sequence};
use hemilab::spec::Row;
use std::path::Path;

/// Writes `files` into `dir`.
fn write(dir: &Path, files: &[(String, Vec<u8>)]) {
    for (name, bytes) in files {
        std::fs::write(dir.join(name), bytes).unwrap();
    }
}

/// hemilab's own masks as a texture in a fresh directory, loaded as `use_`.
fn own(which: Own, png: bool, use_: TextureUse) -> (Tmp, SeedMode) {
    let dir = Tmp::new("own-masks");
    write(&dir.0, &own_masks(which, png).unwrap());
    let ext = if png { "png" } else { "exr" };
    let file = match which {
        Own::BlueNoise => format!("blue_noise.{ext}"),
        Own::Stbn => format!("stbn_%d.{ext}"),
    };
    let mode = texture(&dir.0, &file, use_).unwrap_or_else(|e| panic!("{e}"));
    (dir, mode)
}

fn bits(v: &[f32]) -> Vec<u32> {
    v.iter().map(|x| x.to_bits()).collect()
}

#[test]
fn own_masks_as_png_and_exr_render_the_built_in_images_bit_for_bit() {
    let scene = load_scene(&Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell-box.toml")).unwrap();
    for (which, built_in) in [(Own::BlueNoise, SeedMode::BlueNoise), (Own::Stbn, SeedMode::Stbn)] {
        for png in [true, false] {
            let (_dir, mode) = own(which, png, TextureUse::Offset);
            assert!(mode.name().starts_with("texture:") && mode.name().contains(":offset#"), "{mode}");
            for seq in [Sequence::Fibonacci, Sequence::Random, Sequence::Sobol, Sequence::R2] {
                for (frame, schedule) in [
                    (0, Schedule::Independent),
                    (5, Schedule::Independent),
                    (5, Schedule::R1),
                    (37, Schedule::R1),
                    (40, Schedule::Independent),
                ] {
                    let job = |m| {
                        crate::support::jobs::render_job(
                            Distribution::SineCosine,
                            SamplerConfig::new(seq, m, 4, 11)
                                .unwrap()
                                .with_frame(frame)
                                .with_schedule(schedule),
                            (32, 24),
                            scene.ao_distance,
                        )
                    };
                    let (a, b) =
                        (render(&scene, &job(mode), &|_| {}), render(&scene, &job(built_in), &|_| {}));
                    assert!(b.occluded_rays > 0);
                    let what = format!("{which:?} png={png} {seq} frame {frame} {schedule}");
                    assert_eq!(bits(&a.ao.data), bits(&b.ao.data), "{what}");
                    assert_eq!(a.occluded_rays, b.occluded_rays, "{what}");
                }
            }
        }
    }
}

#[test]
fn a_texture_offsets_are_stratified_over_pixels_and_frames() {
    // Over one 64 × 64 tile and all 32 frames of the STBN texture, each frame's x and y offsets are
    // 4096 distinct cells of 1/4096 (the ranks, plus one common jitter): χ² over 64 bins is 0.
    let (_dir, mode) = own(Own::Stbn, true, TextureUse::Offset);
    let mut counts = [vec![0.0; 64], vec![0.0; 64]];
    for frame in 0..32 {
        let ps = PixelSeed::new(3, 0);
        let mut cells = [std::collections::HashSet::new(), std::collections::HashSet::new()];
        for y in 0..64 {
            for x in 0..64 {
                let o = ps.offsets_at(mode, x + 7, y + 3, frame);
                for (c, v) in [o.0, o.1].into_iter().enumerate() {
                    counts[c][(v >> 18) as usize] += 1.0;
                    cells[c].insert(v >> 12);
                }
            }
        }
        assert!(
            cells.iter().all(|c| c.len() == 4096),
            "frame {frame}: offsets not a permutation of the cells"
        );
    }
    for c in &counts {
        let t = chi2_test(c, &[2048.0; 64], 5.0).unwrap();
        assert!(t.statistic < 1e-9, "χ² {}", t.statistic);
    }
}

#[test]
fn a_texture_offset_in_each_pixel_is_uniform_over_run_seeds() {
    // 16 × 16 cells of [0, 1)², 65536 seeds, at a frame past the first cycle: what makes the offset
    // mode unbiased per pixel (as for the built-in masks).
    let (_dir, mode) = own(Own::Stbn, false, TextureUse::Offset);
    let pixels = [(0u32, 0u32), (37, 5), (1000, 77)];
    let alpha = sidak_threshold(0.01, pixels.len());
    for (x, y) in pixels {
        let mut counts = vec![0.0; 256];
        for seed in 0..65536u64 {
            let (ox, oy) = PixelSeed::new(seed, 0).offsets_at(mode, x, y, 19);
            counts[(oy >> 20) as usize * 16 + (ox >> 20) as usize] += 1.0;
        }
        let t = chi2_test(&counts, &[256.0; 256], 5.0).unwrap();
        assert!(t.p_value > alpha, "pixel ({x}, {y}): p = {}", t.p_value);
    }
    let row = Row::new(Distribution::SineCosine, Sequence::Fibonacci, mode);
    assert!(per_pixel_unbiased(row), "an exactly uniform texture is unbiased per pixel");
    // A rotation texture moves x alone: as `rotation`, unbiased only for fresh pseudo-random numbers.
    let (_d2, rot) = own(Own::BlueNoise, true, TextureUse::Rotation);
    assert!(!per_pixel_unbiased(Row::new(Distribution::SineCosine, Sequence::Fibonacci, rot)));
    assert!(per_pixel_unbiased(Row::new(Distribution::SineCosine, Sequence::Random, rot)));
    let (x, y) = PixelSeed::new(5, 0).offsets_at(rot, 9, 4, 0);
    let (bx, _) = PixelSeed::new(5, 0).offsets_at(SeedMode::BlueNoise, 9, 4, 0);
    assert_eq!((x, y), (bx, 0), "a rotation texture gives the x offset alone");
}

/// A single-slice 8-bit grey PNG of `side` × `side` from `value(x, y)`.
fn grey8(dir: &Path, name: &str, side: u32, value: impl Fn(u32, u32) -> u8) {
    let img = image::GrayImage::from_fn(side, side, |x, y| image::Luma([value(x, y)]));
    img.save(dir.join(name)).unwrap();
}

#[test]
fn uniformity_is_measured_and_a_skewed_texture_is_not_claimed_unbiased() {
    let dir = Tmp::new("skewed");
    // Quantized ranks, 64 texels per 8-bit level: exactly uniform with the level-wide jitter.
    grey8(&dir.0, "levels.png", 128, |x, y| ((y * 128 + x) * 7919 % 16384 / 64) as u8);
    // Every value in the lower half: far from uniform.
    grey8(&dir.0, "low.png", 16, |x, y| ((y * 16 + x) / 2) as u8);
    let levels = texture(&dir.0, "levels.png", TextureUse::Offset).unwrap();
    let low = texture(&dir.0, "low.png", TextureUse::Offset).unwrap();
    let (l, w) = (levels_mask(levels), levels_mask(low));
    eprintln!("deviation: levels {:?}, low {:?}", l.deviation(), w.deviation());
    assert!(l.uniform() && l.deviation().distance < 1e-9);
    assert!(!w.uniform() && (w.deviation().distance - 0.5).abs() < 0.01);
    let row = |m| Row::new(Distribution::SineCosine, Sequence::Fibonacci, m);
    assert!(per_pixel_unbiased(row(levels)));
    assert!(!per_pixel_unbiased(row(low)), "a skewed texture's offsets are not uniform");
    // The same file read twice is one seed mode; its name holds the content hash.
    assert_eq!(texture(&dir.0, "low.png", TextureUse::Offset).unwrap(), low);
    assert_ne!(texture(&dir.0, "low.png", TextureUse::Rotation).unwrap(), low);
    grey8(&dir.0, "low.png", 16, |x, y| ((y * 16 + x) / 2 + 1) as u8);
    let edited = texture(&dir.0, "low.png", TextureUse::Offset).unwrap();
    assert_ne!(edited, low);
    assert_eq!(edited.name().split('#').next(), low.name().split('#').next(), "same path and use");
}

fn levels_mask(m: SeedMode) -> &'static hemilab::sampling::texture::TextureMask {
    match m {
        SeedMode::Texture(t) => t.get(),
        _ => panic!("not a texture"),
    }
}

/// Cosine-weighted directions of a `side` × `side` × `slices` texture: stratified (u, v) through the
/// sine-cosine warp, shuffled, encoded as NVIDIA's UNORM RGB8 ((d + 1) / 2 · 255).
fn cosine_texture(dir: &Path, side: u32, slices: u32) -> Vec<Vec<Vec3>> {
    let n = side * side;
    let mut all = Vec::new();
    for t in 0..slices {
        let dirs: Vec<Vec3> = (0..n)
            .map(|i| {
                let j = (i * 389 + t * 97) % n;
                let u = Vec2::new(
                    ((j % side) as f32 + 0.5) / side as f32,
                    ((j / side) as f32 + 0.5) / side as f32,
                );
                Distribution::SineCosine.sample(u).dir
            })
            .collect();
        let enc = |c: f32| ((c + 1.0) * 0.5 * 255.0).round() as u8;
        let img = image::RgbImage::from_fn(side, side, |x, y| {
            let d = dirs[(y * side + x) as usize];
            image::Rgb([enc(d.x), enc(d.y), enc(d.z)])
        });
        img.save(dir.join(format!("vec_{t:02}.png"))).unwrap();
        // What the file holds, decoded as the loader decodes it.
        let dec = |c: u8| 2.0 * c as f32 / 255.0 - 1.0;
        all.push(
            dirs.iter().map(|d| Vec3::new(dec(enc(d.x)), dec(enc(d.y)), dec(enc(d.z))).normalize()).collect(),
        );
    }
    all
}

#[test]
fn a_vector_texture_gives_its_directions_and_needs_sine_cosine() {
    let dir = Tmp::new("vector");
    let want = cosine_texture(&dir.0, 32, 4);
    let mode = texture(&dir.0, "vec_%02d.png", TextureUse::Vector).unwrap();
    let mask = levels_mask(mode);
    assert_eq!(mask.size(), (32, 32, 4));
    eprintln!("vector deviation {:?}", mask.deviation());
    assert!(mask.deviation().distance <= mask.deviation().tolerance);
    assert!(!per_pixel_unbiased(Row::new(Distribution::SineCosine, Sequence::Random, mode)));
    assert!(Row::new(Distribution::Uniform, Sequence::Random, mode).invalid().is_some());
    assert!(Row::new(Distribution::SineCosine, Sequence::Random, mode).invalid().is_none());
    assert_eq!(
        Row::new(Distribution::SineCosine, Sequence::Sobol, mode).canonical().sequence,
        Sequence::Random
    );
    // Frame f: the first rays of a 32 × 32 window are slice f mod 4's directions, each once (the
    // run's toroidal shift is a bijection); the renderer's warp hands the texture's direction on.
    for frame in [0u32, 1, 6] {
        let cfg = SamplerConfig::new(Sequence::Fibonacci, mode, 3, 21).unwrap().with_frame(frame);
        let slice = &want[(frame % 4) as usize];
        let mut used = vec![false; slice.len()];
        let mut pts = vec![Vec2::ZERO; 3];
        for y in 0..32u32 {
            for x in 0..32u32 {
                cfg.fill_pixel(x + 5, y + 40, 0, &mut pts);
                let got = Distribution::SineCosine.sample(pts[0]).dir;
                let (best, dot) = slice
                    .iter()
                    .enumerate()
                    .map(|(i, d)| (i, d.dot(got)))
                    .fold((0, -2.0f32), |a, b| if b.1 > a.1 { b } else { a });
                assert!(dot > 1.0 - 1e-5, "frame {frame} ({x}, {y}): {got} is no texel's direction ({dot})");
                assert!(!std::mem::replace(&mut used[best], true), "frame {frame}: a direction twice");
                assert!(pts[1] != pts[0] && pts[2] != pts[1], "the rays of a pixel read different texels");
            }
        }
    }
}

#[test]
fn bad_texture_files_are_one_error_naming_the_file() {
    let dir = Tmp::new("bad-textures");
    std::fs::write(dir.path("junk.png"), b"not a png").unwrap();
    std::fs::write(dir.path("mask.tga"), b"x").unwrap();
    grey8(&dir.0, "grey.png", 8, |x, y| (x * 8 + y) as u8);
    grey8(&dir.0, "s_0.png", 8, |x, _| x as u8);
    grey8(&dir.0, "s_1.png", 4, |x, _| x as u8);
    let img = hemilab::image::Image::from_vec(2, 1, vec![0.25, 1.5]);
    hemilab::io::write_exr(&dir.path("big.exr"), &[hemilab::image::Channel { name: "Y", image: &img }])
        .unwrap();
    for (file, use_, want) in [
        ("missing.png", TextureUse::Offset, "texture file 'missing.png' not found"),
        ("none_%d.png", TextureUse::Offset, "matches no file"),
        ("junk.png", TextureUse::Offset, "junk.png is not a readable PNG"),
        ("mask.tga", TextureUse::Offset, "is not a PNG or an EXR"),
        ("grey.png", TextureUse::Vector, "has 1 channel(s); a `vector` texture needs 3"),
        ("s_%d.png", TextureUse::Offset, "s_1.png is 4x4 with 1 channel(s), but"),
        ("big.exr", TextureUse::Offset, "texel (1, 0): value 1.5 outside [0, 1]"),
    ] {
        let e = texture(&dir.0, file, use_).expect_err(file);
        assert!(e.contains(want), "{file}: {e}");
        assert_eq!(e.lines().count(), 1, "{file}: one line: {e}");
    }
}
