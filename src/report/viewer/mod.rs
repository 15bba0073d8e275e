//! The run page's comparison viewer: what a reader does with images rather than numbers — two
//! configurations (or one and the reference) under a split, zoomed to single pixels, stepped
//! through a real-time sequence's frames, as AO, signed error or FLIP map.
//!
//! This module makes bytes only: the layers as 8-bit PNGs (`layers`), the manifest of what exists
//! (`manifest.js`, a script because a page opened from disk may load scripts but not fetch JSON),
//! the page's section and the script itself (`viewer.js`, committed beside this file). Which
//! images are exported is `report::run::viewer`'s choice; `outdir` writes the files.

pub mod layers;

use crate::report::colormap::{css_gradient, diverging, grey, magma};
use serde::Serialize;

/// Where the viewer's files go, relative to the page.
pub const DIR: &str = "viewer";
/// The manifest's file name under `DIR`.
pub const MANIFEST_JS: &str = "viewer/manifest.js";
/// The script's file name under `DIR`.
pub const SCRIPT_JS: &str = "viewer/viewer.js";
/// The script: plain JavaScript, no library, no network.
pub const SCRIPT: &str = include_str!("viewer.js");

/// Everything the viewer can show.
#[derive(Debug, Clone, Serialize)]
pub struct Manifest {
    /// Which images were exported, in words (the page says it too).
    pub rule: String,
    /// How the FLIP maps were made (pixels per degree), for the legend.
    pub flip_note: String,
    /// CSS gradients of the three layers' colour maps, so the legend matches the PNGs.
    pub gradients: Gradients,
    pub views: Vec<View>,
}

#[derive(Debug, Clone, Serialize)]
pub struct Gradients {
    pub image: String,
    pub error: String,
    pub flip: String,
}

impl Gradients {
    /// The colour maps the layers are drawn with (`report::colormap`).
    pub fn of_colormaps() -> Self {
        Self {
            image: css_gradient(grey, 0.0, 1.0, 2),
            error: css_gradient(diverging, -1.0, 1.0, 9),
            flip: css_gradient(magma, 0.0, 1.0, 9),
        }
    }
}

/// One view of one scene (a camera at a ray count): the images in it compare pixel for pixel.
#[derive(Debug, Clone, Serialize)]
pub struct View {
    /// Stable name in the URL (`v=`).
    pub id: String,
    pub title: String,
    pub width: u32,
    pub height: u32,
    /// Every frame some series of the view has, ascending.
    pub frames: Vec<u32>,
    /// The reference at each frame that has one of its own (a still camera: frame 1 serves all).
    pub reference: Vec<ReferenceFrame>,
    pub series: Vec<Series>,
}

#[derive(Debug, Clone, Serialize)]
pub struct ReferenceFrame {
    pub frame: u32,
    pub image: String,
}

/// One configuration through one pipeline: its frames.
#[derive(Debug, Clone, Serialize)]
pub struct Series {
    /// Stable name in the URL (`a=`, `b=`).
    pub id: String,
    pub label: String,
    /// The paper's configuration (shown first).
    pub paper: bool,
    pub frames: Vec<Frame>,
}

/// One exported image and its layers.
#[derive(Debug, Clone, Serialize)]
pub struct Frame {
    pub frame: u32,
    pub replicate: u32,
    pub image: String,
    pub error: String,
    /// The signed-error layer's scale: ± this value are the colour map's ends (one scale for every
    /// series of the view at this frame).
    pub error_scale: f32,
    pub flip: Option<String>,
    pub rmse: f64,
    pub flip_mean: Option<f64>,
}

/// The manifest as a script that sets `window.HEMILAB_VIEWER`.
pub fn manifest_js(m: &Manifest) -> String {
    let json = serde_json::to_string(m).expect("a manifest of strings and numbers always serializes");
    // `</script` cannot end a script loaded by src, but keep the text safe to inline anyway.
    format!(
        "// What hemilab's comparison viewer can show (written by the run).\nwindow.HEMILAB_VIEWER = {};\n",
        json.replace("</", "<\\/")
    )
}

/// A name safe in a URL and a file name: letters, digits, `.`, `_` and `-`; anything else `-`.
pub fn slug(text: &str) -> String {
    text.chars().map(|c| if c.is_ascii_alphanumeric() || "._-".contains(c) { c } else { '-' }).collect()
}

const STYLE: &str = "#viewer .controls{display:flex;flex-wrap:wrap;gap:.4em 1.2em;align-items:center;margin:.5em 0}\
#viewer select{max-width:28em}\
#viewer-stage{position:relative;overflow:hidden;width:100%;height:60vh;background:#607080;cursor:ew-resize;touch-action:none;user-select:none}\
#viewer-stage img{position:absolute;max-width:none;border:0;image-rendering:pixelated;image-rendering:crisp-edges}\
#viewer-clip-b{position:absolute;inset:0;background:#607080}\
#viewer-split{position:absolute;top:0;bottom:0;width:2px;background:#ff0}\
#viewer-label-a,#viewer-label-b{position:absolute;top:4px;background:rgba(0,0,0,.6);color:#fff;padding:2px 6px;font-size:13px;max-width:48%}\
#viewer-label-a{left:4px}#viewer-label-b{right:4px;text-align:right}\
#viewer-legend{display:flex;gap:.6em;align-items:center;margin:.4em 0;font-size:90%}\
#viewer-bar{display:inline-block;width:220px;height:14px;border:1px solid #888}\
#viewer-note{color:#a33}\
#viewer.focus{position:fixed;inset:0;z-index:10;background:#fff;overflow:auto;padding:0 1em}\
#viewer.focus .intro{display:none}";

/// The page's viewer section (`intro`: how to use it and what was exported, plain text): the controls,
/// the stage and the two scripts.
pub fn section_html(intro: &str) -> String {
    let layer = |v: &str, text: &str| {
        format!("<label><input type=\"radio\" name=\"viewer-layer\" value=\"{v}\"> {text}</label>")
    };
    format!(
        "<section id=\"viewer\">\n<style>{STYLE}</style>\n<h2>Compare the images</h2>\n<p class=\"intro\">{}</p>\n\
<div class=\"controls\">\n<label>view <select id=\"viewer-view\"></select></label>\n\
<label>left <select id=\"viewer-a\"></select></label>\n<label>right <select id=\"viewer-b\"></select></label>\n\
</div>\n<div class=\"controls\">\n<span><button id=\"viewer-prev\" type=\"button\">◀</button> \
<span id=\"viewer-frame\"></span> <button id=\"viewer-next\" type=\"button\">▶</button></span>\n\
<span>layer: {} {} {}</span>\n<span>zoom <button id=\"viewer-zoom-out\" type=\"button\">−</button> \
<button id=\"viewer-zoom-fit\" type=\"button\">fit</button> <button id=\"viewer-zoom-in\" type=\"button\">+</button> \
<span id=\"viewer-zoom\"></span></span>\n<span id=\"viewer-pixel\"></span>\n\
<a id=\"viewer-link\" href=\"#\">link to this view</a>\n\
<button id=\"viewer-focus\" type=\"button\">whole window</button>\n</div>\n\
<div id=\"viewer-stage\">\n<img id=\"viewer-img-a\" alt=\"\">\n<div id=\"viewer-clip-b\"><img id=\"viewer-img-b\" alt=\"\"></div>\n\
<div id=\"viewer-split\"></div>\n<span id=\"viewer-label-a\"></span><span id=\"viewer-label-b\"></span>\n</div>\n\
<div id=\"viewer-legend\"><span id=\"viewer-lo\"></span><span id=\"viewer-bar\"></span><span id=\"viewer-hi\"></span> \
<span id=\"viewer-legend-text\"></span></div>\n<p id=\"viewer-note\"></p>\n\
<noscript><p>The viewer needs JavaScript; every image it shows is a PNG under {DIR}/.</p></noscript>\n\
<script src=\"{MANIFEST_JS}\"></script>\n<script src=\"{SCRIPT_JS}\"></script>\n</section>\n",
        esc(intro),
        layer("image", "image"),
        layer("error", "signed error"),
        layer("flip", "FLIP"),
    )
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn manifest() -> Manifest {
        Manifest {
            rule: "all".into(),
            flip_note: "67 ppd".into(),
            gradients: Gradients::of_colormaps(),
            views: vec![View {
                id: "k.static.1".into(),
                title: "k </script>".into(),
                width: 4,
                height: 3,
                frames: vec![1, 2],
                reference: vec![ReferenceFrame { frame: 1, image: "viewer/r.png".into() }],
                series: vec![Series {
                    id: "s".into(),
                    label: "paper".into(),
                    paper: true,
                    frames: vec![Frame {
                        frame: 1,
                        replicate: 0,
                        image: "viewer/a.png".into(),
                        error: "viewer/e.png".into(),
                        error_scale: 0.25,
                        flip: None,
                        rmse: f64::NAN,
                        flip_mean: None,
                    }],
                }],
            }],
        }
    }

    #[test]
    fn the_manifest_is_a_script_setting_one_global() {
        let js = manifest_js(&manifest());
        let json = js.split_once("window.HEMILAB_VIEWER = ").unwrap().1.trim_end().trim_end_matches(';');
        let v: serde_json::Value = serde_json::from_str(json).unwrap();
        assert_eq!(v["views"][0]["series"][0]["frames"][0]["error_scale"], 0.25);
        assert!(v["views"][0]["series"][0]["frames"][0]["rmse"].is_null(), "NaN is null, not invalid JSON");
        assert!(!js.contains("</script"), "{js}");
    }

    #[test]
    fn the_section_loads_the_manifest_before_the_script_and_names_every_control() {
        let html = section_html("Rule & <more>");
        let files = crate::report::referenced_files(&html);
        assert_eq!(files, [MANIFEST_JS, SCRIPT_JS]);
        assert!(html.contains("Rule &amp; &lt;more&gt;"));
        for id in [
            "viewer-view",
            "viewer-a",
            "viewer-b",
            "viewer-stage",
            "viewer-img-a",
            "viewer-img-b",
            "viewer-note",
        ] {
            assert!(html.contains(&format!("id=\"{id}\"")), "{id}");
            assert!(SCRIPT.contains(&format!("\"{id}\"")), "the script uses {id}");
        }
        assert_eq!(
            slug("sine-cosine × Fibonacci / ema0.1+atrous"),
            "sine-cosine---Fibonacci---ema0.1-atrous"
        );
    }
}
