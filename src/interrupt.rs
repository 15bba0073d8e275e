//! Ctrl-C and `kill` (SIGINT, SIGTERM): say what was saved and how to go on, then exit with 128 +
//! the signal's number (130 for SIGINT, 143 for SIGTERM, as a shell reports a killed command).
//!
//! No code of ours runs in a signal handler, where almost nothing is safe (no locks, no
//! allocation, no printing). Instead `install`, first thing in `main`, blocks both signals in the
//! main thread before any other thread exists, so every thread inherits the mask, and one thread of
//! its own takes them with `sigwait`: an ordinary thread, which may lock, print and exit.
//!
//! While the executor runs jobs (`jobs_phase`), the first signal only asks it to stop
//! (`requested`): it hands out no new job, the renders in progress finish and are saved, and the
//! command ends with `Error::Interrupted`, whose message says how many jobs are saved and how to
//! resume. Anywhere else, and at a second signal, the thread prints what is known and exits at
//! once: every file hemilab writes is written whole or not at all (`io::write_atomic`), and the
//! temporary files such an exit (or `kill -9`) leaves are removed by the next run
//! (`io::remove_stale_temp_files`).

use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};

/// The first signal received, 0 for none.
static SIGNAL: AtomicI32 = AtomicI32::new(0);
/// Whether the executor is running jobs (it then stops by itself at the first signal).
static IN_JOBS: AtomicBool = AtomicBool::new(false);
static STATUS: Mutex<Status> =
    Mutex::new(Status { done: 0, total: 0, saved_in: None, started: false, one_image: None });

/// What the executor has done so far, for the message.
struct Status {
    done: usize,
    total: usize,
    /// Where finished jobs are saved for a rerun to resume (`run`); `None`: they are kept in
    /// memory only (`advise`, which writes its outputs at the end).
    saved_in: Option<PathBuf>,
    started: bool,
    /// `render`: when its one image started, and the file it writes at the end.
    one_image: Option<(std::time::Instant, PathBuf)>,
}

/// Takes SIGINT and SIGTERM on a thread of their own. Call it before any thread is started.
pub fn install() {
    // SAFETY: plain libc calls on a local, initialized signal set; pthread_sigmask affects only
    // the calling (main) thread, which has not started any other.
    let set = unsafe {
        let mut set: libc::sigset_t = std::mem::zeroed();
        libc::sigemptyset(&mut set);
        libc::sigaddset(&mut set, libc::SIGINT);
        libc::sigaddset(&mut set, libc::SIGTERM);
        if libc::pthread_sigmask(libc::SIG_BLOCK, &set, std::ptr::null_mut()) != 0 {
            return; // Signals keep their default action: the command just ends, as before.
        }
        set
    };
    let watcher = std::thread::Builder::new().name("signals".into()).spawn(move || {
        loop {
            let mut sig = 0;
            // SAFETY: `set` is initialized and holds signals this thread has blocked.
            if unsafe { libc::sigwait(&set, &mut sig) } != 0 {
                continue;
            }
            let first = SIGNAL.compare_exchange(0, sig, Ordering::SeqCst, Ordering::SeqCst).is_ok();
            if first && IN_JOBS.load(Ordering::SeqCst) {
                eprintln!(
                    "\n{}: stopping after the renders in progress, which are kept; press Ctrl-C again to stop \
                     at once",
                    name(sig)
                );
                continue;
            }
            eprintln!("\n{}", message_now(sig));
            // No `Drop` runs on this exit: the lock files go here (the locks go with the process).
            crate::io::remove_held_locks();
            // Nor would a user's denoiser and what it started stop with us (their own group).
            crate::denoise_command::kill_running();
            std::process::exit(128 + sig);
        }
    });
    if watcher.is_err() {
        // No thread, no way to take the signals: give them back their default action.
        // SAFETY: as above.
        unsafe { libc::pthread_sigmask(libc::SIG_UNBLOCK, &set, std::ptr::null_mut()) };
    }
}

/// Whether a signal asked the command to stop.
pub fn requested() -> bool {
    SIGNAL.load(Ordering::SeqCst) != 0
}

/// The exit status after a signal: 128 + its number (130 when none was received, as for SIGINT).
pub fn exit_code() -> i32 {
    128 + match SIGNAL.load(Ordering::SeqCst) {
        0 => libc::SIGINT,
        s => s,
    }
}

/// Marks the executor's run of `total` jobs, `done` of them already finished (resumed), until
/// dropped: a signal then lets the renders in progress finish.
pub fn jobs_phase(done: usize, total: usize) -> JobsPhase {
    if let Ok(mut s) = STATUS.lock() {
        (s.done, s.total, s.started) = (done, total, true);
    }
    IN_JOBS.store(true, Ordering::SeqCst);
    JobsPhase
}

/// While alive, the executor is running jobs (`jobs_phase`).
pub struct JobsPhase;

impl Drop for JobsPhase {
    fn drop(&mut self) {
        IN_JOBS.store(false, Ordering::SeqCst);
    }
}

/// `done` jobs are finished (and saved, where they are saved).
pub fn jobs_done(done: usize) {
    if let Ok(mut s) = STATUS.lock() {
        s.done = done;
    }
}

/// Finished jobs are saved in `out`, and a rerun resumes from them (`run`).
pub fn saves_to(out: &Path) {
    if let Ok(mut s) = STATUS.lock() {
        s.saved_in = Some(out.to_path_buf());
    }
}

/// `render` has started its one image, which it writes to `output` only when it is finished: a
/// signal then says how long it had run and that nothing is kept (a render does not resume).
pub fn renders_one_image(output: &Path) {
    if let Ok(mut s) = STATUS.lock() {
        s.one_image = Some((std::time::Instant::now(), output.to_path_buf()));
    }
}

/// What to say after a signal, from what the executor reported.
pub fn message() -> String {
    message_now(match SIGNAL.load(Ordering::SeqCst) {
        0 => libc::SIGINT,
        s => s,
    })
}

fn message_now(sig: i32) -> String {
    let rerun = command_line();
    let Ok(s) = STATUS.lock() else { return format!("{}: stopped; rerun `{rerun}` to go on", name(sig)) };
    if let Some((since, output)) = &s.one_image {
        return format!(
            "{}: stopped after {} of rendering; the image was not finished and nothing was written ({} is \
             written only when it is; a render does not resume): rerun `{rerun}` to render it from the start",
            name(sig),
            crate::plan::format_duration(since.elapsed().as_secs_f64()),
            output.display()
        );
    }
    match (&s.saved_in, s.started) {
        (Some(out), true) => format!(
            "{}: stopped; {} of {} jobs are saved in {}; rerun `{rerun}` to resume from them",
            name(sig),
            s.done,
            s.total,
            out.display()
        ),
        (None, true) => format!(
            "{}: stopped after {} of {} jobs; nothing is saved, as this command writes its outputs only when \
             every job is done; rerun `{rerun}` to start again",
            name(sig),
            s.done,
            s.total
        ),
        (_, false) => format!(
            "{}: stopped before any job ran; nothing was left half-written (every file is written whole or \
             not at all, and references already built are kept); rerun `{rerun}` to go on",
            name(sig)
        ),
    }
}

fn name(sig: i32) -> &'static str {
    if sig == libc::SIGTERM { "terminated (SIGTERM)" } else { "interrupted (SIGINT)" }
}

/// The command as it was run, quoted for a POSIX shell where needed.
fn command_line() -> String {
    let quote = |a: String| {
        let plain = !a.is_empty() && a.chars().all(|c| c.is_ascii_alphanumeric() || "_./=:,@%+-".contains(c));
        if plain { a } else { format!("'{}'", a.replace('\'', "'\\''")) }
    };
    std::env::args().map(quote).collect::<Vec<_>>().join(" ")
}
