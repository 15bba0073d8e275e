//! Shared by the integration tests that run the binary: a fresh temporary directory per test, a tiny spec written into it
//! (absolute scene paths, 24x18 pixels, few rays), and the real binary run inside it.

use hemilab::results::JobResult;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A directory of its own under the system temp dir, removed when the test passes.
pub struct Tmp(pub PathBuf);

impl Tmp {
    /// Unique per call, not just per process: tests of several files share one test binary, and
    /// two of them may pick the same `name`.
    pub fn new(name: &str) -> Self {
        static N: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
        let n = N.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!("hemilab-test-{name}-{}-{n}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        Tmp(dir)
    }

    pub fn path(&self, rel: &str) -> PathBuf {
        self.0.join(rel)
    }

    /// Writes a spec file into the directory and returns its path.
    pub fn spec(&self, name: &str, text: &str) -> PathBuf {
        let p = self.0.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }

    /// Runs the binary with the temp dir as working directory.
    pub fn hemilab<S: AsRef<std::ffi::OsStr>>(&self, args: &[S]) -> Output {
        Command::new(env!("CARGO_BIN_EXE_hemilab"))
            .args(args)
            .current_dir(&self.0)
            .output()
            .expect("run hemilab")
    }

    /// `hemilab run SPEC --out OUT --reference-dir REF --quiet [extra]`, asserted to succeed.
    pub fn run_ok(&self, spec: &Path, out: &str, reference: &str, extra: &[&str]) -> Output {
        let o = self.run(spec, out, reference, extra);
        assert!(o.status.success(), "run failed:\n{}", String::from_utf8_lossy(&o.stderr));
        o
    }

    pub fn run(&self, spec: &Path, out: &str, reference: &str, extra: &[&str]) -> Output {
        let mut args: Vec<std::ffi::OsString> = vec!["run".into(), spec.into()];
        for a in ["--out", out, "--reference-dir", reference, "--quiet"] {
            args.push(a.into());
        }
        args.extend(extra.iter().map(Into::into));
        self.hemilab(&args)
    }

    /// Every file below the directory, relative, sorted.
    pub fn listing(&self) -> Vec<String> {
        fn walk(base: &Path, dir: &Path, out: &mut Vec<String>) {
            for e in std::fs::read_dir(dir).unwrap() {
                let p = e.unwrap().path();
                out.push(p.strip_prefix(base).unwrap().to_string_lossy().into_owned());
                if p.is_dir() {
                    walk(base, &p, out);
                }
            }
        }
        let mut v = Vec::new();
        walk(&self.0, &self.0, &mut v);
        v.sort();
        v
    }
}

/// A `Tmp` reads as its directory's path (`dir.join(..)`, `&dir` for a `&Path`).
impl std::ops::Deref for Tmp {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl Drop for Tmp {
    fn drop(&mut self) {
        if !std::thread::panicking() {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}

/// `hemilab ARGS` run in the repository's root, where scene paths read as the README writes them
/// (`scenes/cornell-box.toml`).
pub fn hemilab_in_root<S: AsRef<std::ffi::OsStr>>(args: &[S]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_hemilab"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("run hemilab")
}

/// The arguments of `hemilab render SCENE --rays N --output OUTPUT` followed by `extra`: the one
/// spelling of a render's command line in the tests.
pub fn render_args(scene: &str, rays: u32, output: &Path, extra: &[&str]) -> Vec<std::ffi::OsString> {
    let mut v: Vec<std::ffi::OsString> = vec!["render".into(), scene.into(), "--rays".into()];
    v.push(rays.to_string().into());
    v.push("--output".into());
    v.push(output.into());
    v.extend(extra.iter().map(Into::into));
    v
}

/// `hemilab render` of a committed scene (`scenes/NAME`, from the repository's root).
pub fn render(scene: &str, rays: u32, output: &Path, extra: &[&str]) -> Output {
    hemilab_in_root(&render_args(&format!("scenes/{scene}"), rays, output, extra))
}

/// The names in a directory (not below it), in the order the filesystem gives.
pub fn entries(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect()
}

pub fn scene(file: &str) -> String {
    format!("{}/scenes/{file}", env!("CARGO_MANIFEST_DIR"))
}

/// 16 jobs on the Cornell box at 24x18: a table (2 rows x 2 ray counts x 2 replicates) and a sweep
/// whose static row overlaps the table (merged) and whose shift row does not; `extra_reference` is
/// added to the `[reference]` section.
pub fn tiny_spec(reference_rays: u32, extra_reference: &str) -> String {
    format!(
        r#"name = "tiny"
scenes = ["{}"]
resolution = [24, 18]
replicates = 2
seed = 3

[reference]
rays = {reference_rays}
replicates = 2
{extra_reference}

[[table]]
name = "t"
rays = [2, 4]
rows = [
  {{ distribution = "uniform", sequence = "random" }},
  {{ distribution = "sine-cosine", sequence = "fibonacci", seed_mode = "static" }},
]

[[convergence]]
name = "c"
rays = [1, 2, 4]
distributions = ["sine-cosine"]
sequences = ["fibonacci"]
seed_modes = ["static", "shift"]
"#,
        scene("cornell-box.toml")
    )
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// The records a run in `out` has saved: its `results.json` and the journal of records since.
pub fn records(out: &Path) -> Vec<JobResult> {
    hemilab::outdir::read_results(out, &|e| e).unwrap_or_else(|e| panic!("{}: {e}", out.display()))
}

/// A record with its run-time fields blanked: what must be identical between runs.
pub fn timeless(r: &JobResult) -> JobResult {
    r.without_times()
}

/// Asserts a failed command: exit status 2, one `error: <what>: ...` line first, no panic.
pub fn assert_error(o: &Output, what: &str) -> String {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(2), "expected exit 2, got {:?}:\n{e}", o.status);
    assert!(e.starts_with(&format!("error: {what}: ")), "message must start with `error: {what}: `:\n{e}");
    assert_eq!(e.matches("error:").count(), 1, "the error is printed once:\n{e}");
    assert!(!e.contains("panicked"), "{e}");
    e
}

/// `results.csv` without its run-time columns (`results::TIME_COLUMNS`): as text, so a value that
/// drifted by one ulp through a read-back would show.
pub fn timeless_csv(out: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(out.join("results.csv")).unwrap();
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    let drop: Vec<usize> =
        hemilab::results::TIME_COLUMNS.iter().map(|c| header.iter().position(|h| h == c).unwrap()).collect();
    text.lines()
        .map(|l| {
            let f: Vec<&str> =
                l.split(',').enumerate().filter(|(i, _)| !drop.contains(i)).map(|x| x.1).collect();
            f.join(",")
        })
        .collect()
}

/// Runs a shipped spec (`experiments/<name>.toml`) through the real binary against the committed
/// references, as the claims tests do, and returns its records and the command's output. Panics,
/// naming the spec and how to rebuild its references, when the run fails.
pub fn run_shipped_spec(name: &str) -> (Vec<JobResult>, Output) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = std::env::temp_dir().join(format!("hemilab-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let o = Command::new(env!("CARGO_BIN_EXE_hemilab"))
        .arg("run")
        .arg(root.join(format!("experiments/{name}.toml")))
        .arg("--out")
        .arg(&out)
        .arg("--reference-dir")
        .arg(root.join("reference"))
        .arg("--no-build-reference")
        .arg("--quiet")
        .output()
        .expect("hemilab runs");
    assert!(
        o.status.success(),
        "hemilab run experiments/{name}.toml failed (are its references committed? \
         `hemilab reference experiments/{name}.toml` rebuilds them):\n{}",
        stderr(&o)
    );
    let list = records(&out);
    let _ = std::fs::remove_dir_all(&out);
    (list, o)
}
