//! `hemilab run` under `[tiles]` through the real binary: every job of a real-time table (a still
//! and a moving, jittered camera, SVGF and an EMA) is measured on the tiles' interiors — each image
//! the mosaic of the interiors, the tile set named in its provenance — against references of the
//! interiors alone, stored with their window and reused by the next run; `plan` counts the tiles'
//! pixels, not the whole image's.

use crate::support::common::*;

const SPEC: &str = r#"name = "tiles"
scenes = ["@SCENE@"]
resolution = [320, 180]
replicates = 2
seed = 5

[tiles]
count = 2
size = 32

[reference]
rays = 64
replicates = 2

[cameras.orbit]
path = { orbit = { degrees = 1.0 } }
jitter = true

[[table]]
name = "t"
rays = [1]
distributions = ["sine-cosine"]
sequences = ["fibonacci"]
seed_modes = ["rotation", "blue-noise"]
pipelines = ["svgf", "ema0.1"]
cameras = ["static", "orbit"]
frames = 4
"#;

#[test]
fn a_realtime_table_is_measured_on_the_tiles_interiors_against_their_references() {
    let t = Tmp::new("rt-tiles");
    let s = t.spec("tiles.toml", &SPEC.replace("@SCENE@", &scene("kitchen.toml")));
    let plan = t.hemilab(&["plan", "tiles.toml", "--reference-dir", "refs"]);
    assert!(plan.status.success(), "{}", stderr(&plan));
    let text = stdout(&plan);
    let line = text.lines().find(|l| l.contains(" pixels")).expect("the size line");
    let pixels: u64 = line.rsplit(' ').nth(1).unwrap().parse().unwrap();
    // 2 rows x 2 pipelines x 3 reported frames x 2 cameras x 2 replicates = 48 jobs, each at most
    // two windows of (32 + 2 x apron)² px, far fewer than 48 whole images of 320x180.
    assert!(pixels < 48 * 320 * 180 / 4, "{line}");

    t.run_ok(&s, "out", "refs", &[]);
    let rs = records(&t.path("out"));
    assert_eq!(rs.len(), 48);
    for r in &rs {
        assert!(r.rmse.is_finite() && r.rmse > 0.0, "{r:?}");
        assert!(r.covered_pixels > 0 && r.covered_pixels <= 2 * 32 * 32, "{}", r.covered_pixels);
        assert_eq!(r.flicker.is_some(), r.frame > 1);
        let exr = t.path("out").join(&r.image);
        let channels = hemilab::io::read_exr(&exr).unwrap();
        let img = &channels[0].1;
        assert_eq!((img.width, img.height), (32 + hemilab::jobs::tiles::GAP + 32, 32), "the mosaic");
        let bytes = std::fs::read(&exr).unwrap();
        let p = hemilab::image::decode_exr_provenance(&bytes).unwrap().expect("provenance");
        let tiles = p.json["tiles"].as_str().expect("the tile set is named");
        assert!(tiles.starts_with("2x32+") && tiles.contains("/320x180"), "{tiles}");
        assert!(p.summary.contains("measured on tiles 2x32+"), "{}", p.summary);
    }
    // References of the interiors alone: the scene's view and orbit frames 0..=3, two tiles each.
    let refs = |ext: &str| -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(t.path("refs"))
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(ext))
            .collect();
        v.sort();
        v
    };
    let exrs = refs(".exr");
    assert_eq!(exrs.len(), 2 * (1 + 4), "{exrs:?}");
    for name in &exrs {
        assert!(name.contains("-320x180-tile-"), "{name}");
    }
    for json in refs(".json") {
        let m: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(t.path("refs").join(&json)).unwrap()).unwrap();
        let w = m["window"].as_array().expect("the window is in the manifest");
        assert_eq!((w[2].as_u64(), w[3].as_u64()), (Some(32), Some(32)), "{json}");
    }
    // The frame with its tiles outlined.
    let png = image::open(t.path("out/tiles-kitchen.png")).expect("tiles-kitchen.png").to_rgb8();
    assert_eq!(png.dimensions(), (3 * 256, 3 * 144));
    // A second run reuses every reference and every record.
    let again = t.run_ok(&s, "out", "refs", &[]);
    assert!(!stderr(&again).contains("rendering a new one"), "{}", stderr(&again));
    assert_eq!(refs(".exr"), exrs);
    let rs2 = records(&t.path("out"));
    for (a, b) in rs.iter().zip(&rs2) {
        assert_eq!((a.key.as_str(), a.rmse), (b.key.as_str(), b.rmse));
    }
}

/// A tile's reference is the reference of its window: the whole frame's reference (same spec
/// without `[tiles]`) cropped to the window, bit for bit, in mean, standard error and coverage.
#[test]
fn a_tiles_reference_is_the_crop_of_the_whole_frames() {
    let t = Tmp::new("rt-tile-refs");
    let text = |tiles: &str| {
        format!(
            "name = \"r\"\nscenes = [\"{}\"]\nresolution = [96, 72]\n{tiles}\n[reference]\nrays = 16\nreplicates = 2\n\n\
             [[table]]\nname = \"t\"\nrays = [1]\ndistributions = [\"sine-cosine\"]\nsequences = [\"random\"]\n",
            scene("kitchen.toml")
        )
    };
    t.spec("whole.toml", &text(""));
    t.spec("tiled.toml", &text("[tiles]\ncount = 3\nsize = 16\n"));
    for s in ["whole.toml", "tiled.toml"] {
        let o = t.hemilab(&["reference", s, "--reference-dir", "refs", "--quiet"]);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let mut whole = None;
    let mut tiles = Vec::new();
    for e in std::fs::read_dir(t.path("refs")).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_none_or(|x| x != "json") {
            continue;
        }
        let m: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&p).unwrap()).unwrap();
        let channels = hemilab::io::read_exr(&p.with_extension("exr")).unwrap();
        match m["window"].as_array() {
            None => whole = Some(channels),
            Some(w) => {
                tiles.push((w.iter().map(|v| v.as_u64().unwrap() as u32).collect::<Vec<_>>(), channels))
            }
        }
    }
    let whole = whole.expect("the whole frame's reference");
    assert_eq!(tiles.len(), 3);
    let full = hemilab::render::Window::full(96, 72);
    for (w, channels) in &tiles {
        let window = hemilab::render::Window::new([96, 72], w[0], w[1], w[2], w[3]);
        for (name, img) in channels {
            let of_whole = &whole.iter().find(|(n, _)| n == name).expect("same channels").1;
            let crop = full.crop(&of_whole.data, &window);
            let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&img.data), bits(&crop), "channel {name} of {window:?}");
        }
    }
}
