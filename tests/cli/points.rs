//! `hemilab points` end to end: the real binary in a temporary directory.

use std::process::Command;

use crate::support::common;

/// A fresh directory per test, removed when dropped.
use common::Tmp as TempDir;

fn points(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_hemilab")).arg("points").args(args).output().unwrap()
}

#[test]
fn points_writes_a_png_and_an_svg_panel() {
    let dir = TempDir::new("points-ok");
    let png = dir.0.join("fib.png");
    let out = points(&[
        "--distribution",
        "sine-cosine",
        "--sequence",
        "fibonacci",
        "--count",
        "500",
        "--output",
        png.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // A summary, as `render` prints one.
    let said = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        said.trim_end(),
        format!("500 points, sine-cosine, Fibonacci, static seed, run seed 1 (pixel 0) -> {}", png.display())
    );
    let bytes = std::fs::read(&png).unwrap();
    let img = image::load_from_memory_with_format(&bytes, image::ImageFormat::Png).unwrap();
    assert!(img.width() >= 280 && img.height() >= 280, "{}x{}", img.width(), img.height());

    let svg = dir.0.join("rnd.SVG");
    let out = points(&[
        "--distribution",
        "uniform",
        "--sequence",
        "random",
        "--seed-mode",
        "rotation",
        "--seed",
        "7",
        "--count",
        "100",
        "--output",
        svg.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains("<svg") && text.contains("100 points") && text.contains("uniform"));
    // A per-pixel seed: a grid of 4 pixels x 3 frames, top views (outline + each point).
    assert_eq!(text.matches("<circle").count(), 12 * (1 + 100), "{}", String::from_utf8_lossy(&out.stdout));
    assert!(text.contains("pixel (1, 1)") && text.contains("frame 2"));
    assert!(String::from_utf8_lossy(&out.stdout).contains("(pixels (0..1, 0..1) x frames 0..2)"));
}

#[test]
fn points_with_an_unknown_extension_exits_2_and_writes_nothing() {
    let dir = TempDir::new("points-bad");
    for name in ["p.jpg", "p"] {
        let target = dir.0.join(name);
        let out = points(&[
            "--distribution",
            "sine",
            "--sequence",
            "random",
            "--count",
            "10",
            "--output",
            target.to_str().unwrap(),
        ]);
        assert_eq!(out.status.code(), Some(2));
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(".png or .svg") && err.contains(name), "{err}");
    }
    assert_eq!(std::fs::read_dir(&dir.0).unwrap().count(), 0, "no file, not even a temporary one");
}

#[test]
fn points_rejects_zero_count_and_unknown_distribution() {
    let dir = TempDir::new("points-args");
    let target = dir.0.join("p.png");
    let t = target.to_str().unwrap();
    let zero = points(&["--distribution", "sine", "--sequence", "random", "--count", "0", "--output", t]);
    assert_eq!(zero.status.code(), Some(2));
    let bad = points(&["--distribution", "cosine", "--sequence", "random", "--count", "5", "--output", t]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("sine-cosine"));
    assert!(!target.exists());
}
