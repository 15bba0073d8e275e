//! LDR-FLIP (`metrics::flip`) against NVIDIA's flip-evaluator 1.7 on committed images
//! (tests/data/flip/, made once by its make_expected.py, whose header has the command), and
//! against closed forms: identical images give 0 everywhere, the two images can be swapped, and a
//! larger constant offset is never less visible.

use crate::support::images::{image, noise};
use hemilab::image::Image;
use hemilab::metrics::flip::{DEFAULT_PPD, ldr_flip_map, mean_flip};
use std::path::PathBuf;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/flip").join(name)
}

fn read_f32(name: &str, w: u32, h: u32) -> Image {
    let bytes = std::fs::read(data(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
    let v: Vec<f32> = bytes.chunks_exact(4).map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]])).collect();
    Image::from_vec(w, h, v)
}

#[test]
fn agrees_with_flip_evaluator_on_the_committed_images() {
    let text = std::fs::read_to_string(data("expected.json")).unwrap();
    let expected: serde_json::Value = serde_json::from_str(&text).unwrap();
    let (w, h) = (expected["width"].as_u64().unwrap() as u32, expected["height"].as_u64().unwrap() as u32);
    let all = image(w, h, |_, _| 1.0);
    let cases = expected["cases"].as_array().unwrap();
    assert_eq!(cases.len(), 5, "the committed cases");
    for case in cases {
        let name = case["name"].as_str().unwrap();
        let reference = read_f32(&format!("{name}_ref.f32"), w, h);
        let test = read_f32(&format!("{name}_test.f32"), w, h);
        let map = ldr_flip_map(&reference, &test, case["ppd"].as_f64().unwrap());
        let mean = mean_flip(&map, &all);
        let want = case["mean"].as_f64().unwrap();
        assert!((mean - want).abs() < 1e-4, "{name}: mean FLIP {mean} but flip-evaluator says {want}");
        for s in case["samples"].as_array().unwrap() {
            let (x, y, want) =
                (s[0].as_u64().unwrap() as u32, s[1].as_u64().unwrap() as u32, s[2].as_f64().unwrap());
            let got = map.at(x, y) as f64;
            assert!(
                (got - want).abs() < 1e-4,
                "{name}: FLIP at ({x}, {y}) is {got} but flip-evaluator says {want}"
            );
        }
    }
}

#[test]
fn identical_images_differ_nowhere() {
    let a = noise(40, 30, 0.5, 0.3, 11);
    let map = ldr_flip_map(&a, &a, DEFAULT_PPD);
    assert!(map.data.iter().all(|&v| v == 0.0));
    assert_eq!(mean_flip(&map, &image(40, 30, |_, _| 1.0)), 0.0);
}

#[test]
fn swapping_the_images_changes_nothing() {
    let (a, b) = (noise(40, 30, 0.5, 0.2, 12), noise(40, 30, 0.4, 0.3, 13));
    let ab = ldr_flip_map(&a, &b, DEFAULT_PPD);
    let ba = ldr_flip_map(&b, &a, DEFAULT_PPD);
    assert_eq!(ab, ba);
    assert!(ab.data.iter().all(|v| (0.0..=1.0).contains(v)));
}

#[test]
fn a_larger_constant_offset_is_more_visible() {
    let base = image(48, 32, |x, y| 0.2 + 0.5 * (x as f32 / 47.0) * (0.5 + 0.5 * (y as f32 / 31.0)));
    let all = image(48, 32, |_, _| 1.0);
    let mut last = 0.0;
    for c in [0.01f32, 0.02, 0.05, 0.1, 0.2] {
        let shifted = Image::from_vec(48, 32, base.data.iter().map(|v| v + c).collect());
        let m = mean_flip(&ldr_flip_map(&base, &shifted, DEFAULT_PPD), &all);
        assert!(m > last, "offset {c}: mean FLIP {m} not above {last}");
        last = m;
    }
}

#[test]
fn the_mean_counts_covered_pixels_only() {
    let map = image(4, 2, |x, _| x as f32 / 4.0);
    let left = image(4, 2, |x, _| if x < 2 { 1.0 } else { 0.0 });
    assert!((mean_flip(&map, &left) - 0.125).abs() < 1e-12);
    assert!(mean_flip(&map, &image(4, 2, |_, _| 0.0)).is_nan());
}
