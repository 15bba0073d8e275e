//! `hemilab run` writes every figure its spec asks for, and `index.html` references only files that
//! exist. Real binary, tiny renders of the Cornell box, temporary directories.

use hemilab::report::referenced_files;
use std::path::Path;
use std::process::Command;

use crate::support::common;

/// A fresh directory per test, removed when dropped.
use common::Tmp as TempDir;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn run(spec: &Path, dir: &Path) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_hemilab"))
        .arg("run")
        .arg(spec)
        .arg("--out")
        .arg(dir.join("out"))
        .arg("--reference-dir")
        .arg(dir.join("reference"))
        .arg("--quiet")
        .output()
        .expect("hemilab runs")
}

/// Every file the page links to or embeds exists, and the page links every PNG and SVG written.
fn assert_page_is_whole(out: &Path) {
    let html = std::fs::read_to_string(out.join("index.html")).expect("index.html");
    let refs = referenced_files(&html);
    assert!(!refs.is_empty(), "index.html references nothing");
    for f in &refs {
        assert!(!f.starts_with('/') && !f.contains(".."), "not a relative link inside the output: {f}");
        assert!(out.join(f).is_file(), "index.html references {f}, which does not exist");
    }
    for e in std::fs::read_dir(out).unwrap() {
        let name = e.unwrap().file_name().to_string_lossy().into_owned();
        if name.ends_with(".png") || name.ends_with(".svg") {
            assert!(refs.contains(&name), "{name} is written but not on the page");
        }
    }
    let md = std::fs::read_to_string(out.join("report.md")).expect("report.md");
    for f in refs.iter().filter(|f| f.ends_with(".png")) {
        assert!(md.contains(&format!("]({f})")), "report.md lacks {f}");
    }
}

#[test]
fn smoke_run_page_references_only_existing_files() {
    let dir = TempDir::new("smoke");
    let o = run(&root().join("experiments/smoke.toml"), &dir.0);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = dir.0.join("out");
    for f in ["smoke.png", "smoke_error.png", "banding.png", "banding.svg", "report.md", "index.html"] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    assert!(!out.join("table1.png").exists(), "point figures only when the spec asks");
    assert_page_is_whole(&out);
}

#[test]
fn every_kind_of_figure_is_written_and_on_the_page() {
    let dir = TempDir::new("all");
    let scene = root().join("scenes/cornell-box.toml");
    let spec = format!(
        r#"name = "all"
scenes = ["{}"]
resolution = [12, 10]
replicates = 2
point_figures = true
[reference]
rays = 256
replicates = 2
[[table]]
name = "t"
rays = [2, 4]
rows = [
  {{ distribution = "sine-cosine", sequence = "random" }},
  {{ distribution = "sine-cosine", sequence = "fibonacci", seed_mode = "static" }},
]
[[convergence]]
name = "sweep"
rays = [1, 2, 4, 8]
distributions = ["sine-cosine"]
sequences = ["random", "fibonacci"]
"#,
        scene.display()
    );
    let path = dir.0.join("all.toml");
    std::fs::write(&path, spec).unwrap();
    let o = run(&path, &dir.0);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = dir.0.join("out");
    for f in [
        "table1.png",
        "figure2.png",
        "figure3.png",
        "figure4.png",
        "t.png",
        "t_error.png",
        "sweep_rays.png",
        "sweep_rays.svg",
        "sweep_time.png",
        "sweep_time.svg",
        "sweep_efficiency.png",
        "sweep_efficiency.svg",
        "banding.png",
        "banding.svg",
    ] {
        let bytes = std::fs::read(out.join(f)).unwrap_or_else(|e| panic!("{f}: {e}"));
        let magic: &[u8] = if f.ends_with(".png") { b"\x89PNG" } else { b"<svg" };
        assert!(bytes.starts_with(magic), "{f} is not a {magic:?} file");
    }
    assert_page_is_whole(&out);
    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    for text in [
        "References",
        "noise floor",
        "slope vs rays",
        "slope vs AO time",
        "lowpass RMSE",
        "efficiency",
        "sine-cosine, Fibonacci",
        "Paired comparisons",
        "ns per AO ray",
        hemilab::timing::TIME_INCLUDES,
    ] {
        assert!(html.contains(text), "index.html lacks '{text}'");
    }
    // The answer comes first: before every table and figure.
    let answer = html
        .find("At equal total render time on &#39;cornell-box&#39;")
        .or_else(|| html.find("At equal total render time on 'cornell-box'"));
    let answer = answer.unwrap_or_else(|| panic!("no answer paragraph:\n{html}"));
    assert!(answer < html.find("<table").unwrap() && answer < html.find("<figure").unwrap());
    assert!(html.contains("Equal time (&#39;cornell-box&#39;") || html.contains("Equal time ('cornell-box'"));
    assert!(html.contains("Efficiency at each ray count"));
    assert!(out.join("equal_time.csv").is_file() && out.join("sweep_equal_time.png").is_file());
}

#[test]
fn point_figures_must_be_a_boolean() {
    let dir = TempDir::new("badkey");
    let path = dir.0.join("bad.toml");
    let text = "scenes = [\"x.toml\"]\npoint_figures = \"yes\"\n[[table]]\nname = \"t\"\nrays = [1]\n\
                distributions = [\"sine\"]\nsequences = [\"random\"]\n";
    std::fs::write(&path, text).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_hemilab")).arg("plan").arg(&path).output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("point_figures") && err.contains("line 2"), "{err}");
}

/// Every file below `dir`, by its path relative to `dir`, with its bytes.
fn files(dir: &Path) -> std::collections::BTreeMap<String, Vec<u8>> {
    let mut out = std::collections::BTreeMap::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                todo.push(p);
            } else {
                let rel = p.strip_prefix(dir).unwrap().to_string_lossy().into_owned();
                out.insert(rel, std::fs::read(&p).unwrap());
            }
        }
    }
    out
}

/// The report is made from the records and `timing.json` alone: run again on a finished output
/// directory whose report files were deleted, reusing every record and rendering nothing, `run`
/// writes every file — the page, quotes.md, equal_time.csv, aggregates.csv, slopes.json and each
/// figure — byte for byte as the first run did. This is what lets a change to the report be held
/// against the code before it: the old binary's output directory, copied and rerun by the new
/// binary, must come out identical (`diff -r`).
#[test]
fn a_rerun_on_the_same_records_writes_the_same_report() {
    let t = common::Tmp::new("same-report");
    let realtime = "\n[[table]]\nname = \"rt\"\nrays = [1]\ndistributions = [\"sine-cosine\"]\n\
                    sequences = [\"random\", \"fibonacci\"]\nseed_modes = [\"rotation\", \"blue-noise\", \"stbn\"]\n\
                    pipelines = [\"raw\", \"ema0.1+atrous\"]\nframes = 2\n";
    let spec = t.spec("tiny.toml", &(common::tiny_spec(16, "") + realtime));
    t.run_ok(&spec, "out", "ref", &[]);
    let out = t.path("out");
    let first = files(&out);
    for name in ["index.html", "report.md", "quotes.md", "equal_time.csv", "c_equal_time.png", "rt_final.png"]
    {
        assert!(first.contains_key(name), "{name} missing: {:?}", first.keys().collect::<Vec<_>>());
    }
    let kept = ["results.json", "timing.json"];
    for name in first.keys().filter(|n| !n.contains('/') && !kept.contains(&n.as_str())) {
        std::fs::remove_file(out.join(name)).unwrap();
    }
    let o = t.run_ok(&spec, "out", "ref", &[]);
    assert!(common::stdout(&o).contains(" 0 rendered, "), "{}", common::stdout(&o));
    let second = files(&out);
    assert_eq!(first.keys().collect::<Vec<_>>(), second.keys().collect::<Vec<_>>());
    for (name, bytes) in &first {
        assert!(second[name] == *bytes, "{name} differs between the run and the rerun on its records");
    }
}
