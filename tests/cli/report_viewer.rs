//! The run page's comparison viewer in a real browser: a tiny real-time run (the kitchen, a still
//! and an orbiting camera, two pipelines, four configurations), its page opened from disk
//! (`file://`) by headless Chromium with two different states in the URL's hash, and the
//! screenshots shown to differ where the viewer is; `--dump-dom` shows which images each state
//! put on the stage, and that a malformed state falls back to the defaults and says so.
//!
//! Chromium must be installed (`.ci/run` installs Debian's `chromium` when it is absent): this test
//! fails rather than skips without it.

use crate::support::common::*;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

const SPEC: &str = r#"name = "viewer"
scenes = ["SCENE"]
resolution = [32, 24]
replicates = 2
seed = 5

[reference]
rays = 64
replicates = 2

[cameras.orbit]
path = { orbit = { degrees = 6.0 } }
jitter = true

[[table]]
name = "t"
rays = [1]
distributions = ["sine-cosine"]
sequences = ["fibonacci", "random"]
seed_modes = ["rotation", "blue-noise"]
pipelines = ["raw", "ema0.1+atrous"]
cameras = ["static", "orbit"]
frames = 4
"#;

/// The browser, found on PATH; a missing one fails the test with how to install it.
fn chromium() -> PathBuf {
    for name in ["chromium", "chromium-browser", "google-chrome"] {
        if let Ok(o) = Command::new("sh").arg("-c").arg(format!("command -v {name}")).output()
            && o.status.success()
        {
            return PathBuf::from(String::from_utf8_lossy(&o.stdout).trim());
        }
    }
    panic!(
        "the viewer test needs a headless Chromium: `apt-get update && apt-get install -y chromium` \
         (.ci/run does this when CI=true)"
    );
}

/// Chromium on `url` with `what` (`--screenshot=FILE` or `--dump-dom`), its stdout.
fn browse(tmp: &Tmp, url: &str, what: &str) -> String {
    let profile = tmp.path(&format!("profile-{}", url.len() + what.len()));
    let o = Command::new(chromium())
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--no-first-run",
            "--hide-scrollbars",
            "--virtual-time-budget=5000",
            "--window-size=1200,900",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(what)
        .arg(url)
        .output()
        .expect("chromium starts");
    assert!(o.status.success(), "chromium failed on {url}: {}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn screenshot(tmp: &Tmp, url: &str, name: &str) -> image::RgbImage {
    let file = tmp.path(name);
    browse(tmp, url, &format!("--screenshot={}", file.display()));
    image::open(&file).expect("chromium wrote a PNG").to_rgb8()
}

/// The `src` of the element with `id` in a dumped DOM.
fn src_of(dom: &str, id: &str) -> String {
    let at = dom.find(&format!("id=\"{id}\"")).unwrap_or_else(|| panic!("no #{id} in the DOM"));
    let tag_start = dom[..at].rfind('<').unwrap();
    let tag = &dom[tag_start..tag_start + dom[tag_start..].find('>').unwrap()];
    let s = tag.split("src=\"").nth(1).unwrap_or_else(|| panic!("#{id} has no src: {tag}"));
    s[..s.find('"').unwrap()].replace("&amp;", "&")
}

fn text_of(dom: &str, id: &str) -> String {
    let at = dom.find(&format!("id=\"{id}\"")).unwrap_or_else(|| panic!("no #{id} in the DOM"));
    let from = at + dom[at..].find('>').unwrap() + 1;
    dom[from..from + dom[from..].find('<').unwrap()].to_string()
}

fn manifest(out: &Path) -> Value {
    let js = std::fs::read_to_string(out.join("viewer/manifest.js")).expect("viewer/manifest.js");
    let json = js.split_once("window.HEMILAB_VIEWER = ").expect("the manifest sets its global").1;
    serde_json::from_str(json.trim_end().trim_end_matches(';')).expect("the manifest is JSON")
}

#[test]
fn the_viewer_shows_what_the_url_says_in_a_real_browser() {
    let t = Tmp::new("viewer");
    let spec = t.spec("viewer.toml", &SPEC.replace("SCENE", &scene("kitchen.toml")));
    t.run_ok(&spec, "out", "refs", &[]);
    let out = t.path("out");
    let m = manifest(&out);
    let views = m["views"].as_array().unwrap();
    // Both cameras, each with its own frames and every file the manifest names on disk.
    let ids: Vec<&str> = views.iter().map(|v| v["id"].as_str().unwrap()).collect();
    assert_eq!(ids, ["kitchen.static.1r", "kitchen.orbit.1r"]);
    let mut files = 0;
    for v in views {
        assert_eq!(v["frames"], serde_json::json!([1, 2, 4]));
        for r in v["reference"].as_array().unwrap() {
            assert!(out.join(r["image"].as_str().unwrap()).is_file());
            files += 1;
        }
        let series = v["series"].as_array().unwrap();
        assert!(series[0]["paper"].as_bool().unwrap(), "the paper's configuration comes first");
        // Per pipeline: the 2 best of 4 configurations and the paper's; raw has one frame.
        assert!(series.len() >= 4 && series.len() <= 6, "{}", series.len());
        for s in series {
            for f in s["frames"].as_array().unwrap() {
                for layer in ["image", "error", "flip"] {
                    assert!(out.join(f[layer].as_str().unwrap()).is_file(), "{}", f[layer]);
                    files += 1;
                }
                assert!(f["error_scale"].as_f64().unwrap() > 0.0);
                let flip = f["flip_mean"].as_f64().unwrap();
                assert!(flip > 0.0 && flip < 1.0, "mean FLIP {flip}");
            }
        }
    }
    let orbit = &views[1];
    assert_eq!(orbit["reference"].as_array().unwrap().len(), 3, "a moving camera: a reference per frame");
    assert!(m["rule"].as_str().unwrap().contains(&format!("{files} PNG files")), "{}", m["rule"]);
    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    assert!(html.contains("<section id=\"viewer\">"));

    let page = format!("file://{}", std::fs::canonicalize(out.join("index.html")).unwrap().display());
    let series = |v: usize, i: usize| views[v]["series"][i]["id"].as_str().unwrap().to_string();
    let frame_file = |v: usize, i: usize, f: u64, layer: &str| {
        let fr = views[v]["series"][i]["frames"].as_array().unwrap();
        let fr = fr.iter().rev().find(|x| x["frame"].as_u64().unwrap() <= f).unwrap_or(&fr[0]);
        fr[layer].as_str().unwrap().to_string()
    };
    // The ema series of the moving camera (frames 1, 2, 4).
    let ema = (0..views[1]["series"].as_array().unwrap().len())
        .find(|&i| series(1, i).starts_with("ema"))
        .expect("an accumulating series");
    let other = (0..views[1]["series"].as_array().unwrap().len()).find(|&i| i != ema).unwrap();
    let one = format!("{page}#v=kitchen.static.1r&a={}&b=ref&f=1&l=image&z=fit&s=0.5", series(0, 0));
    let two = format!(
        "{page}#v=kitchen.orbit.1r&a={}&b={}&f=4&l=error&z=40&x=12&y=10&s=0.3",
        series(1, ema),
        series(1, other)
    );
    let dom = browse(&t, &one, "--dump-dom");
    assert_eq!(src_of(&dom, "viewer-img-a"), frame_file(0, 0, 1, "image"));
    assert_eq!(src_of(&dom, "viewer-img-b"), views[0]["reference"][0]["image"].as_str().unwrap());
    assert_eq!(text_of(&dom, "viewer-note"), "", "a valid state needs no note");
    let dom = browse(&t, &two, "--dump-dom");
    assert_eq!(src_of(&dom, "viewer-img-a"), frame_file(1, ema, 4, "error"));
    assert_eq!(src_of(&dom, "viewer-img-b"), frame_file(1, other, 4, "error"));
    assert!(
        text_of(&dom, "viewer-frame").starts_with("frame 4 (3 of 3)"),
        "{}",
        text_of(&dom, "viewer-frame")
    );

    // The two states look different where the viewer is.
    let (a, b) = (screenshot(&t, &one, "one.png"), screenshot(&t, &two, "two.png"));
    assert_eq!(a.dimensions(), b.dimensions());
    let (w, h) = a.dimensions();
    let differing = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| a.get_pixel(x, y) != b.get_pixel(x, y))
        .count();
    assert!(differing > (w * h / 20) as usize, "only {differing} of {} pixels differ", w * h);
    // A link opens the viewer over the whole window: the split's yellow line is on screen.
    let yellow = |img: &image::RgbImage| img.pixels().filter(|p| p.0 == [255, 255, 0]).count();
    assert!(
        yellow(&a) > 100 && yellow(&b) > 100,
        "the split line is on screen: {} {}",
        yellow(&a),
        yellow(&b)
    );

    // A malformed state: every field that names nothing falls back, and the page says which.
    let bad = format!("{page}#v=nowhere&a=nothing&b=zzz&f=banana&l=sepia&z=-3&s=7");
    let dom = browse(&t, &bad, "--dump-dom");
    let last = views[0]["frames"].as_array().unwrap().last().unwrap().as_u64().unwrap();
    assert_eq!(
        src_of(&dom, "viewer-img-a"),
        frame_file(0, 0, last, "image"),
        "the first view's paper series"
    );
    let note = text_of(&dom, "viewer-note");
    assert!(note.contains("v, a, b, f, l, z, s did not name anything"), "{note}");
    assert!(yellow(&screenshot(&t, &bad, "bad.png")) > 100, "the fallback still shows the viewer");
}
