//! Tiles chosen where the content is (`plan::tiles`, `jobs::tiles`): the choice on the kitchen is
//! pinned, deterministic for any thread count, covered, half a tile apart, and its apron is the
//! pipeline's reach plus the camera's motion; the mosaic lays the interiors side by side; bad
//! `[tiles]` values are refused naming the line and key.

use hemilab::denoise::Pipeline;
use hemilab::jobs::tiles::{self, GAP, TileSet};
use hemilab::load::load_scene;
use hemilab::plan::tiles::TileSpec;
use hemilab::plan::{CameraId, CameraRun};
use hemilab::render::Window;
use hemilab::scene::camera_path::CameraPath;
use hemilab::spec::parse_spec;
use std::path::Path;

const FULL: [u32; 2] = [320, 180];

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}
const SPEC: TileSpec = TileSpec { count: 4, size: 48 };

fn kitchen_tiles(pipelines: &[Pipeline], cameras: &[CameraId]) -> TileSet {
    let scene = load_scene(&root().join("scenes/kitchen.toml")).unwrap();
    tiles::of(&scene, FULL, SPEC, pipelines, cameras)
}

#[test]
fn the_kitchens_tiles_are_pinned_covered_and_apart() {
    let svgf: Pipeline = "svgf".parse().unwrap();
    let t = kitchen_tiles(&[svgf], &[]);
    let at: Vec<(u32, u32)> = t.interiors.iter().map(|w| (w.x, w.y)).collect();
    eprintln!("{}", t.canonical());
    assert_eq!(at, PINNED, "{}", t.canonical());
    // SVGF at 320x180: 2 à-trous passes (13 px footprint, 6 either side) and its 3 px variance
    // window; no camera motion.
    assert_eq!(t.apron, 9);
    for (i, w) in t.interiors.iter().enumerate() {
        assert_eq!((w.width, w.height), (48, 48));
        assert!(t.windows[i].covers(w) && t.windows[i].width <= 48 + 18);
        for o in &t.interiors[..i] {
            assert!(!o.grown(24).overlaps(w), "{w:?} is within half a tile of {o:?}");
        }
    }
    assert!(t.covered_share > 0.0 && t.covered_share < 1.0, "{}", t.covered_share);
    // The same choice on one thread (the probe is a render: deterministic for any thread count).
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    assert_eq!(pool.install(|| kitchen_tiles(&[svgf], &[])), t);
}

/// Where the kitchen's 4 tiles of 48 px at 320x180 are (top-left corners, best first).
const PINNED: [(u32, u32); 4] = [(72, 72), (204, 108), (36, 0), (144, 36)];

#[test]
fn a_moving_camera_widens_the_apron_and_not_the_choice() {
    let ema: Pipeline = "ema0.1".parse().unwrap();
    let still = kitchen_tiles(&[ema], &[]);
    assert_eq!(still.apron, 0, "an EMA reads no neighbour");
    let orbit = CameraId::intern(CameraRun {
        name: "orbit-tiles".into(),
        path: CameraPath::Orbit { degrees: 6.0 },
        jitter: false,
        frames: 16,
    });
    let moving = kitchen_tiles(&[ema], &[orbit]);
    assert_eq!(moving.interiors, still.interiors);
    // 6° over 15 steps is 0.4° a frame: at 320 px across a 60-odd degree view, a few pixels a
    // frame for the nearest points, times the 8 frames a history holds.
    assert!(moving.apron >= 8 && moving.apron < 120, "apron {}", moving.apron);
}

#[test]
fn the_mosaic_lays_the_interiors_side_by_side() {
    let full = [40, 20];
    let interiors = vec![Window::new(full, 2, 3, 4, 4), Window::new(full, 30, 10, 4, 4)];
    let windows: Vec<Window> = interiors.iter().map(|w| w.grown(2)).collect();
    let t =
        TileSet { spec: TileSpec { count: 2, size: 4 }, apron: 2, interiors, windows, covered_share: 1.0 };
    assert_eq!(t.mosaic_size(), [4 + GAP + 4, 4]);
    let parts: Vec<hemilab::image::Image> = t
        .windows
        .iter()
        .map(|w| {
            let data = (0..w.pixels())
                .map(|i| (w.x + (i as u32 % w.width)) as f32 * 100.0 + (w.y + i as u32 / w.width) as f32)
                .collect();
            hemilab::image::Image::from_vec(w.width, w.height, data)
        })
        .collect();
    let m = t.mosaic_of_windows(&parts, -1.0);
    let at = |x: u32, y: u32| m.data[(y * m.width + x) as usize];
    assert_eq!(at(0, 0), 203.0, "interior 0's corner (2, 3)");
    assert_eq!(at(3, 3), 506.0);
    assert_eq!(at(4, 0), -1.0, "the gap");
    assert_eq!(at(4 + GAP, 0), 3010.0, "interior 1's corner (30, 10)");
}

const BASE: &str = r#"name = "t"
scenes = ["../scenes/cornell-box.toml"]
resolution = [64, 48]
@TILES@
[[table]]
name = "t2"
rays = [1]
distributions = ["sine-cosine"]
sequences = ["random"]
"#;

fn error(tiles: &str) -> String {
    let text = BASE.replace("@TILES@", tiles);
    parse_spec(&text, Path::new("experiments/bad.toml")).expect_err("refused").to_string()
}

#[test]
fn bad_tiles_are_refused_naming_the_line_and_key() {
    let ok = parse_spec(&BASE.replace("@TILES@", "[tiles]\ncount = 2\nsize = 16\n"), Path::new("e/t.toml"));
    assert_eq!(ok.unwrap().tiles, Some(TileSpec { count: 2, size: 16 }));
    let e = error("[tiles]\ncount = 0\n");
    assert!(e.contains("line 5") && e.contains("tiles.count") && e.contains("1..=64"), "{e}");
    let e = error("[tiles]\nsize = 60\n");
    assert!(e.contains("tiles.size") && e.contains("does not fit the 64x48 image"), "{e}");
    let e = error("[tiles]\ncount = 12\nsize = 16\n");
    assert!(e.contains("key `tiles`") && e.contains("cover the whole 64x48 image"), "{e}");
    let e = error("[tiles]\ncuont = 2\n");
    assert!(e.contains("did you mean `count`"), "{e}");
}

#[test]
fn each_tiles_apron_holds_the_motion_of_its_own_content() {
    let svgf: Pipeline = "svgf".parse().unwrap();
    let still = kitchen_tiles(&[svgf], &[]);
    let orbit = CameraId::intern(CameraRun {
        name: "orbit-tiles-10".into(),
        path: CameraPath::Orbit { degrees: 10.0 },
        jitter: true,
        frames: 64,
    });
    let moving = kitchen_tiles(&[svgf], &[orbit]);
    assert_eq!(moving.interiors, still.interiors);
    // Each window is its interior grown by an apron of its own: the filter's reach (9 px here)
    // plus 8 frames of the most its own content (and the reach around it) moves.
    let aprons: Vec<u32> = moving
        .interiors
        .iter()
        .zip(&moving.windows)
        .map(|(i, w)| (0..=400).find(|&a| i.grown(a) == *w).expect("a grown interior"))
        .collect();
    eprintln!("aprons {aprons:?}");
    assert!(aprons.iter().all(|&a| a > 9), "{aprons:?}");
    assert_eq!(aprons.iter().max(), Some(&moving.apron));
    assert!(aprons.iter().min() < aprons.iter().max(), "the near content moves more: {aprons:?}");
    assert!(still.windows.iter().zip(&still.interiors).all(|(w, i)| *w == i.grown(9)));
}
