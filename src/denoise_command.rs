//! The user's own denoiser: a command the spec names, run on a measured frame.
//! hemilab writes the frame and its G-buffer as one EXR, runs the command, reads one EXR back,
//! checks it, and times the command alone (not the render, not the EXR writing and reading).
//!
//! Files go through `io` and `image` (EXR); only the process is spawned here. A command that
//! cannot run, fails, runs too long or writes nothing usable is one clear error
//! (`Error::Refused`, exit status 2) that names the command and what was wrong, with the end of
//! its stderr; `probe` tries the command on a tiny generated image so that this happens before
//! any rendering.
//!
//! The input EXR's channels (32-bit float, the names OpenEXR tools and denoisers' EXR loaders
//! expect):
//!
//! | channel | what |
//! | --- | --- |
//! | `R`, `G`, `B` | the frame's AO, the same value in all three (colour denoisers take RGB) |
//! | `A` | coverage: 1 where the primary ray hit the scene, 0 on background |
//! | `N.X`, `N.Y`, `N.Z` | the hit's unit normal facing the camera, world orientation; 0 on background |
//! | `Z` | depth: distance along the primary ray to the hit, scene units; 0 on background |
//! | `albedo.R`, `albedo.G`, `albedo.B` | 1: AO has no albedo, so all the signal is "lighting" |
//!
//! The output EXR must be the frame's size and have a `Y` channel or `R`, `G` and `B` (its value
//! is `Y`, else the mean of the three), every value finite; other channels are ignored.
//!
//! In a spec (the table the lead's spec puts it in; `denoise_command` here):
//!
//! ```toml
//! [denoise_command]
//! program = "python3"                            # looked up on PATH unless it holds a '/'
//! args = ["../examples/oidn_denoise.py", "{input}", "{output}"]   # files relative to the spec
//! timeout_s = 60                                 # per frame; default 60
//! ```

use crate::error::{Error, Result};
use crate::image::{Channel, Image};
use crate::io;
use crate::render::GBuffer;
use glam::Vec3;
use serde::Deserialize;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};
use wait_timeout::ChildExt;

/// The placeholders an argument may hold: the input EXR's path and where to write the output.
pub const PLACEHOLDERS: [&str; 2] = ["{input}", "{output}"];

/// Side of the image `probe` tries the command on.
pub const PROBE_SIDE: u32 = 8;

/// A denoiser command as a spec names it.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DenoiseCommand {
    /// The program to run: a path (relative to the working directory, or made absolute by the spec
    /// loader with `resolve`) if it holds a '/', otherwise a name looked up on PATH.
    pub program: String,
    /// Its arguments; `{input}` and `{output}` are replaced by the EXR paths (each must appear).
    #[serde(default)]
    pub args: Vec<String>,
    /// Longest a run may take, seconds; past it the command is killed and the run refused.
    #[serde(default = "default_timeout")]
    pub timeout_s: f64,
}

fn default_timeout() -> f64 {
    60.0
}

impl DenoiseCommand {
    /// Checks the command as written; each message names its key (`program`, `args[i]`,
    /// `timeout_s`) and says what is allowed.
    pub fn validate(&self) -> std::result::Result<(), String> {
        if self.program.trim().is_empty() {
            return Err("program must name the denoiser to run (a path, or a name on PATH)".into());
        }
        for (i, a) in self.args.iter().enumerate() {
            if let Some(bad) = unknown_placeholder(a) {
                return Err(format!(
                    "args[{i}] holds the placeholder {bad}; the placeholders are {}",
                    PLACEHOLDERS.join(" and ")
                ));
            }
        }
        for p in PLACEHOLDERS {
            if !self.args.iter().any(|a| a.contains(p)) {
                return Err(format!(
                    "args must contain {p} (where hemilab {} the frame's EXR); got {:?}",
                    if p == "{input}" { "writes" } else { "reads back" },
                    self.args
                ));
            }
        }
        if !(self.timeout_s.is_finite() && self.timeout_s > 0.0 && self.timeout_s <= 86_400.0) {
            return Err(format!(
                "timeout_s must be a number of seconds in (0, 86400], got {}",
                self.timeout_s
            ));
        }
        Ok(())
    }

    /// The command with its paths taken from `base` (the spec's directory), as every other path
    /// in a spec is, never from the directory hemilab happens to run in: a relative program path
    /// (one holding a '/'; a bare name stays a PATH look-up), and every argument that, read
    /// against `base`, names a file or directory there (a script, a weights file: `args =
    /// ["oidn_denoise.py", "{input}", "{output}"]` beside the spec). Other arguments (options,
    /// numbers, the placeholders) are passed as written.
    pub fn resolve(mut self, base: &Path) -> Self {
        let p = Path::new(&self.program);
        if p.is_relative() && self.program.contains('/') {
            self.program = base.join(p).to_string_lossy().into_owned();
        }
        for a in &mut self.args {
            let path = Path::new(a.as_str());
            let plain = !a.is_empty() && !a.starts_with('-') && !a.contains('{');
            if plain && path.is_relative() && io::exists(&base.join(path)) {
                *a = base.join(path).to_string_lossy().into_owned();
            }
        }
        self
    }

    /// Runs the command once on a `PROBE_SIDE`² generated frame in `dir` and checks what it
    /// writes, so that a broken command is refused before any rendering.
    /// Its files are removed whatever the outcome (a failed probe once left a folder with 20 MB of
    /// stderr in the temporary directory): the message keeps the end of the stderr.
    pub fn probe(&self, dir: &Path) -> Result<()> {
        let (frame, gbuffer) = probe_frame();
        let tried = self.denoise(dir, &frame, &gbuffer, "on a tiny test image, before any rendering");
        if tried.is_err() {
            let files = Files::in_dir(dir);
            for f in [&files.input, &files.output, &files.stdout, &files.stderr] {
                io::remove_file_if_exists(f)?;
            }
        }
        tried.map(|_| ())
    }

    /// Denoises `frame` (AO per pixel) guided by `gbuffer` (the same frame's): writes the input
    /// EXR into `dir`, runs the command, reads and checks the output. Returns the denoised image and
    /// the command's own wall-clock time (spawn to exit: neither the render, nor the EXR writing
    /// or reading). The files are removed after a success and kept after a failure (the message
    /// names them), so the failing input can be tried by hand.
    pub fn run(&self, dir: &Path, frame: &Image, gbuffer: &GBuffer) -> Result<(Image, Duration)> {
        self.denoise(dir, frame, gbuffer, "")
    }

    fn denoise(&self, dir: &Path, frame: &Image, g: &GBuffer, when: &str) -> Result<(Image, Duration)> {
        assert!(
            frame.width == g.width && frame.height == g.height,
            "denoise_command: a {}x{} frame with a {}x{} G-buffer",
            frame.width,
            frame.height,
            g.width,
            g.height
        );
        io::create_dir_all(dir)?;
        let files = Files::in_dir(dir);
        io::remove_file_if_exists(&files.output)?;
        write_input(&files.input, frame, g)?;
        let line = self.command_line(&files);
        let fail = |what: String| {
            let tail = stderr_tail(&files.stderr);
            // A probe's test frame is removed (`probe`); a frame of the run is kept to try by hand.
            let kept = if when.is_empty() {
                format!(" (input kept at {})", files.input.display())
            } else {
                String::new()
            };
            Error::Refused(format!(
                "denoise_command `{line}`{}{}: {what}{kept}{tail}",
                if when.is_empty() { "" } else { " " },
                when,
            ))
        };
        let elapsed = self.spawn_and_wait(&files).map_err(&fail)?;
        if !io::exists(&files.output) {
            return Err(fail(format!(
                "it exited successfully but wrote nothing at {}",
                files.output.display()
            )));
        }
        let channels = io::read_exr(&files.output).map_err(|e| fail(e.to_string()))?;
        let image = value_of(&channels, frame.width, frame.height).map_err(&fail)?;
        for f in [&files.input, &files.output, &files.stdout, &files.stderr] {
            io::remove_file_if_exists(f)?;
        }
        Ok((image, elapsed))
    }

    /// The command as it runs, placeholders replaced (for messages).
    fn command_line(&self, files: &Files) -> String {
        std::iter::once(self.program.clone())
            .chain(self.args(files))
            .map(|a| quoted(&a))
            .collect::<Vec<_>>()
            .join(" ")
    }

    fn args(&self, files: &Files) -> Vec<String> {
        let (input, output) = (files.input.to_string_lossy(), files.output.to_string_lossy());
        self.args.iter().map(|a| a.replace("{input}", &input).replace("{output}", &output)).collect()
    }

    /// Spawns the command (stdin closed, stdout and stderr to files) and waits for it, at most
    /// `timeout_s`; its wall time, or why it failed.
    ///
    /// The command runs in a process group of its own, and the whole group is killed when it is
    /// done or stopped: a command past its timeout once was killed while its own children (a
    /// shell's, a Python pool's) kept running and holding cores the next timed renders needed.
    fn spawn_and_wait(&self, files: &Files) -> std::result::Result<Duration, String> {
        use std::os::unix::process::CommandExt;
        let out = io::create_file(&files.stdout).map_err(|e| e.to_string())?;
        let err = io::create_file(&files.stderr).map_err(|e| e.to_string())?;
        let mut command = Command::new(&self.program);
        command.args(self.args(files)).stdin(Stdio::null()).stdout(out).stderr(err).process_group(0);
        let start = Instant::now();
        let mut child = command.spawn().map_err(|e| format!("cannot start {}: {e}", self.program))?;
        let group = Group::of(&child);
        let status =
            child.wait_timeout(Duration::from_secs_f64(self.timeout_s)).map_err(|e| e.to_string())?;
        let elapsed = start.elapsed();
        let Some(status) = status else {
            // The group first (the command and whatever it started), then our own child, reaped.
            drop(group);
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!(
                "it did not finish within timeout_s = {} s and was stopped (with every process it started)",
                self.timeout_s
            ));
        };
        drop(group);
        if !status.success() {
            return Err(format!("it failed ({status})"));
        }
        Ok(elapsed)
    }
}

/// The process group of a running command (its id is the command's process id), killed whole
/// when dropped: after the command exits, is stopped, or the run ends by a second signal
/// (`kill_running`), no process it started outlives it.
struct Group(i32);

/// The groups of the commands running now, for `kill_running`.
static RUNNING: std::sync::Mutex<Vec<i32>> = std::sync::Mutex::new(Vec::new());

impl Group {
    fn of(child: &std::process::Child) -> Self {
        let id = child.id() as i32;
        RUNNING.lock().unwrap_or_else(|e| e.into_inner()).push(id);
        Group(id)
    }
}

impl Drop for Group {
    fn drop(&mut self) {
        RUNNING.lock().unwrap_or_else(|e| e.into_inner()).retain(|&g| g != self.0);
        kill_group(self.0);
    }
}

fn kill_group(id: i32) {
    if id > 1 {
        // SAFETY: a plain signal to a process group this module created. While any process of it
        // lives the id stays its own; once all are gone the call is ESRCH (ignored), and only a new
        // group taking the same id in between (pids are handed out in turn up to pid_max) could
        // be hit.
        unsafe { libc::kill(-id, libc::SIGKILL) };
    }
}

/// Kills every user's command running now with all it started: the way out of a command that
/// exits at once (`interrupt`'s second signal), where no `Drop` runs.
pub fn kill_running() {
    let ids = RUNNING.lock().map(|v| v.clone()).unwrap_or_default();
    ids.into_iter().for_each(kill_group);
}

/// `arg` as a POSIX shell would need it written (single quotes when it holds anything but plain
/// characters), so a message's command line can be pasted into a shell.
fn quoted(arg: &str) -> String {
    let plain = |c: char| c.is_ascii_alphanumeric() || "-_./=:,+@%".contains(c);
    if !arg.is_empty() && arg.chars().all(plain) {
        arg.to_string()
    } else {
        format!("'{}'", arg.replace('\'', "'\\''"))
    }
}

/// The first `{name}` in `arg` that is not a placeholder, if any.
fn unknown_placeholder(arg: &str) -> Option<String> {
    let mut rest = arg;
    while let Some(open) = rest.find('{') {
        let after = &rest[open + 1..];
        let Some(close) = after.find('}') else { break };
        let name = &after[..close];
        if !name.is_empty() && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-') {
            let token = format!("{{{name}}}");
            if !PLACEHOLDERS.contains(&token.as_str()) {
                return Some(token);
            }
        }
        rest = &after[close + 1..];
    }
    None
}

/// The files of one run, in the run's directory.
struct Files {
    input: PathBuf,
    output: PathBuf,
    stdout: PathBuf,
    stderr: PathBuf,
}

impl Files {
    fn in_dir(dir: &Path) -> Self {
        let f = |name: &str| dir.join(name);
        Files {
            input: f("denoise-input.exr"),
            output: f("denoise-output.exr"),
            stdout: f("denoise-stdout.txt"),
            stderr: f("denoise-stderr.txt"),
        }
    }
}

/// The input EXR (channels in the module doc).
fn write_input(path: &Path, frame: &Image, g: &GBuffer) -> Result<()> {
    let (w, h) = (frame.width, frame.height);
    let normal = |k: fn(&Vec3) -> f32| Image::from_vec(w, h, g.normal.iter().map(k).collect());
    let (nx, ny, nz) = (normal(|n| n.x), normal(|n| n.y), normal(|n| n.z));
    let one = Image::from_vec(w, h, vec![1.0; w as usize * h as usize]);
    let c = |name, image| Channel { name, image };
    let channels = [
        c("R", frame),
        c("G", frame),
        c("B", frame),
        c("A", &g.coverage),
        c("N.X", &nx),
        c("N.Y", &ny),
        c("N.Z", &nz),
        c("Z", &g.depth),
        c("albedo.R", &one),
        c("albedo.G", &one),
        c("albedo.B", &one),
    ];
    io::write_exr(path, &channels)
}

/// The output's value (`Y`, else the mean of `R`, `G`, `B`), checked for size and finiteness.
fn value_of(channels: &[(String, Image)], w: u32, h: u32) -> std::result::Result<Image, String> {
    let get = |name: &str| channels.iter().find(|(n, _)| n == name).map(|(_, i)| i);
    let names = || channels.iter().map(|(n, _)| n.as_str()).collect::<Vec<_>>().join(", ");
    let image = match (get("Y"), get("R"), get("G"), get("B")) {
        (Some(y), ..) => y.clone(),
        (None, Some(r), Some(g), Some(b)) if r.same_size(g) && r.same_size(b) => Image::from_vec(
            r.width,
            r.height,
            r.data.iter().zip(&g.data).zip(&b.data).map(|((r, g), b)| (r + g + b) / 3.0).collect(),
        ),
        _ => return Err(format!("its output has channels [{}]; hemilab reads Y, or R, G and B", names())),
    };
    if (image.width, image.height) != (w, h) {
        return Err(format!("its output is {}x{}, the frame {w}x{h}", image.width, image.height));
    }
    if let Some(i) = image.data.iter().position(|v| !v.is_finite()) {
        let (x, y) = (i as u32 % w, i as u32 / w);
        return Err(format!("its output is not finite at pixel ({x}, {y}): {}", image.data[i]));
    }
    Ok(image)
}

/// The last lines of the command's stderr, as a suffix for a message ("" if it wrote none).
fn stderr_tail(path: &Path) -> String {
    let text = io::read_string(path).unwrap_or_default();
    let lines: Vec<&str> = text.lines().filter(|l| !l.trim().is_empty()).collect();
    if lines.is_empty() {
        return String::new();
    }
    let tail = lines[lines.len().saturating_sub(8)..].join("\n  ");
    let tail: String = tail.chars().rev().take(2000).collect::<Vec<_>>().into_iter().rev().collect();
    format!("; its stderr ended:\n  {tail}")
}

/// `probe`'s frame and G-buffer: a smooth AO ramp with a faint checker, normals of two faces at a
/// right angle (so an edge-aware filter has an edge), one background pixel.
fn probe_frame() -> (Image, GBuffer) {
    let s = PROBE_SIDE;
    let n = (s * s) as usize;
    let xy = |i: usize| ((i as u32 % s) as f32, (i as u32 / s) as f32);
    let ao: Vec<f32> = (0..n)
        .map(|i| {
            let (x, y) = xy(i);
            0.3 + 0.05 * (x + y) + if (x as u32 + y as u32).is_multiple_of(2) { 0.04 } else { -0.04 }
        })
        .collect();
    let mut coverage = vec![1.0; n];
    coverage[0] = 0.0;
    let normal: Vec<Vec3> = (0..n)
        .map(|i| {
            if coverage[i] == 0.0 {
                Vec3::ZERO
            } else if xy(i).0 < 4.0 {
                Vec3::Z
            } else {
                Vec3::X
            }
        })
        .collect();
    let depth: Vec<f32> =
        (0..n).map(|i| if coverage[i] == 0.0 { 0.0 } else { 1.0 + 0.1 * xy(i).1 }).collect();
    let mut frame = Image::from_vec(s, s, ao);
    frame.data[0] = 1.0;
    let gbuffer = GBuffer {
        width: s,
        height: s,
        depth: Image::from_vec(s, s, depth),
        normal,
        coverage: Image::from_vec(s, s, coverage),
        primitive: Vec::new(),
    };
    (frame, gbuffer)
}

#[cfg(test)]
mod tests;
