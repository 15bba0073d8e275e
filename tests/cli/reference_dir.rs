//! Where references are looked up and written: relative to the spec (its `[reference] dir`, else
//! `reference/` beside it), never to the current directory, so committed references are found from
//! anywhere and a user's own spec never writes into the project's `reference/`.

use crate::support::common;

use common::*;
use std::path::{Path, PathBuf};

fn repo(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)
}

fn files(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .map(|d| d.map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect())
        .unwrap_or_default();
    v.sort();
    v
}

/// The acceptance point: the shipped smoke spec, run from another directory, finds its committed
/// reference (`dir = "../reference"`) and ends with the report's path and what it rendered.
#[test]
fn shipped_spec_finds_its_committed_reference_from_another_directory() {
    let t = Tmp::new("refdir-shipped");
    let spec = repo("experiments/smoke.toml");
    let o = t.hemilab(&["run", spec.to_str().unwrap(), "--no-build-reference", "--quiet"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!t.path("reference").exists(), "nothing is written into the current directory's reference/");
    let last = stdout(&o).lines().last().unwrap_or_default().to_string();
    assert_eq!(last, "16 jobs: 16 rendered, 0 reused; report: out/smoke/index.html");
    assert!(t.path("out/smoke/index.html").is_file());
}

/// A spec without `[reference] dir` keeps its references beside itself, wherever it is run from.
#[test]
fn own_spec_writes_references_beside_itself() {
    let t = Tmp::new("refdir-own");
    std::fs::create_dir_all(t.path("exp")).unwrap();
    std::fs::create_dir_all(t.path("elsewhere")).unwrap();
    let spec = t.spec("exp/tiny.toml", &tiny_spec(16, ""));
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_hemilab"))
        .args(["run", spec.to_str().unwrap(), "--quiet"])
        .current_dir(t.path("elsewhere"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let refs = files(&t.path("exp/reference"));
    assert!(
        refs.iter().any(|f| f.ends_with(".exr")) && refs.iter().any(|f| f.ends_with(".json")),
        "{refs:?}"
    );
    assert!(!t.path("elsewhere/reference").exists());
    assert!(t.path("elsewhere/out/tiny/index.html").is_file());
}

/// `[reference] dir` is relative to the spec file; `--reference-dir` overrides it; the error for a
/// missing reference names the directory and the flag.
#[test]
fn reference_dir_key_and_flag() {
    let t = Tmp::new("refdir-key");
    std::fs::create_dir_all(t.path("exp")).unwrap();
    let spec = t.spec("exp/tiny.toml", &tiny_spec(16, "dir = \"../refs\""));
    let o = t.hemilab(&["reference", spec.to_str().unwrap(), "--quiet"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(files(&t.path("refs")).iter().any(|f| f.ends_with(".exr")));
    assert!(!t.path("exp/reference").exists());
    let o = t.hemilab(&["plan", spec.to_str().unwrap()]);
    assert!(stdout(&o).contains("reused"), "plan finds it too:\n{}", stdout(&o));

    let o = t.run(&spec, "out", "nowhere", &["--no-build-reference"]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(e.contains("in nowhere") && e.contains("--reference-dir"), "{e}");
    assert!(!t.path("nowhere").exists(), "a refused run writes nothing");
}

/// `hemilab reference` keeps a stored reference that serves the spec: a smaller spec sharing a
/// larger spec's `rays = "auto"` reference (as experiments/blue_noise.toml shares the paper's) does
/// not replace it with a coarser one. `--force` builds the smaller spec's own, under a name of its
/// own: the richer one is never overwritten by a different one.
#[test]
fn reference_keeps_a_richer_auto_reference() {
    let t = Tmp::new("refdir-keep");
    let auto = tiny_spec(16, "dir = \"refs\"").replace("rays = 16", "rays = \"auto\"");
    let big = t.spec("big.toml", &auto.replace("rays = [2, 4]", "rays = [2, 16]"));
    let small = t.spec("small.toml", &auto);
    let o = t.hemilab(&["reference", big.to_str().unwrap(), "--quiet"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let exr = files(&t.path("refs")).into_iter().find(|f| f.ends_with(".exr")).unwrap();
    let stored = std::fs::read(t.path("refs").join(&exr)).unwrap();

    let o = t.hemilab(&["reference", small.to_str().unwrap(), "--quiet"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("kept"), "{}", stdout(&o));
    assert_eq!(std::fs::read(t.path("refs").join(&exr)).unwrap(), stored, "the richer reference is kept");

    let o = t.hemilab(&["reference", small.to_str().unwrap(), "--quiet", "--force"]);
    assert!(o.status.success() && !stdout(&o).contains("kept"), "{}", stdout(&o));
    assert_eq!(std::fs::read(t.path("refs").join(&exr)).unwrap(), stored, "the richer one is kept");
    let images: Vec<String> = files(&t.path("refs")).into_iter().filter(|f| f.ends_with(".exr")).collect();
    assert_eq!(images.len(), 2, "--force built the smaller spec's own: {images:?}");
}
