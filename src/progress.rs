//! Progress on stderr, never with --quiet. On a terminal, an indicatif bar; elsewhere (a log file,
//! `nohup`, a batch job) a bar would be escape codes or nothing, so a plain line is printed instead
//! every `LINE_EVERY` seconds, or when the work passes a tenth of the way (at most every
//! `LINE_AT_LEAST` seconds): an 84 s run leaves about ten lines, and work of a second or two none.
//!
//! The time left is said only once it means something (`left`): after `ETA_AFTER_S` and a
//! hundredth of the work. indicatif's own estimate starts from the first increments' rate, which
//! before any render has finished (warm-ups, the first slot of every worker) reads as hours.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressState, ProgressStyle};
use std::io::IsTerminal;
use std::time::{Duration, Instant};

/// Seconds between plain lines at most.
const LINE_EVERY: Duration = Duration::from_secs(10);
/// Seconds between plain lines at least (a tenth of the way done sooner waits for this).
const LINE_AT_LEAST: Duration = Duration::from_secs(2);
/// An estimate of the time left needs this much time spent…
const ETA_AFTER_S: f64 = 3.0;
/// …and this fraction of the work done.
const ETA_AFTER_FRACTION: f64 = 0.01;

/// A bar over `total` units labelled `what`: drawn on a terminal, plain lines elsewhere, nothing
/// when `quiet`.
pub fn bar(total: u64, what: &str, quiet: bool) -> ProgressBar {
    let pb = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr());
    let terminal = std::io::stderr().is_terminal();
    if quiet || !terminal {
        pb.set_draw_target(ProgressDrawTarget::hidden());
    }
    let style = ProgressStyle::with_template("{msg:12} [{elapsed_precise}] {wide_bar} {percent:>3}% {left}")
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .with_key("left", |s: &ProgressState, w: &mut dyn std::fmt::Write| {
            let _ = match left(s.fraction() as f64, s.elapsed()) {
                Some(d) => write!(w, "ETA {}", clock(d)),
                None => write!(w, "ETA …"),
            };
        });
    pb.set_style(style);
    pb.set_message(what.to_string());
    if !quiet && !terminal {
        plain_lines(&pb);
    }
    pb
}

/// The time left at `fraction` done after `elapsed`, at the rate so far; `None` while too little
/// is done to say.
pub fn left(fraction: f64, elapsed: Duration) -> Option<Duration> {
    let spent = elapsed.as_secs_f64();
    if spent < ETA_AFTER_S || fraction.is_nan() || fraction < ETA_AFTER_FRACTION {
        return None;
    }
    // Whole seconds, rounded up: "about 0 s left" would say it is done.
    Some(Duration::from_secs_f64((spent * (1.0 - fraction.min(1.0)) / fraction).ceil()))
}

/// "42 s", "3:07", "1:02:03".
fn clock(d: Duration) -> String {
    let s = d.as_secs();
    match s {
        0..60 => format!("{s} s"),
        60..3600 => format!("{}:{:02}", s / 60, s % 60),
        _ => format!("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60),
    }
}

/// One line of progress: "jobs: 40 % after 1:12, about 1:48 left".
pub fn line(what: &str, fraction: f64, elapsed: Duration) -> String {
    let eta = left(fraction, elapsed).map_or(String::new(), |d| format!(", about {} left", clock(d)));
    format!("{what}: {:.0} % after {}{eta}", 100.0 * fraction, clock(elapsed))
}

/// Watches `pb` from a thread of its own (as long as the bar exists) and prints `line`s.
fn plain_lines(pb: &ProgressBar) {
    let weak = pb.downgrade();
    let watch = move || {
        let mut last = Instant::now();
        let mut last_tenth = u64::MAX;
        loop {
            std::thread::sleep(Duration::from_millis(250));
            let Some(pb) = weak.upgrade() else { return };
            let len = pb.length().unwrap_or(0);
            if pb.is_finished() || len == 0 {
                continue;
            }
            let fraction = pb.position().min(len) as f64 / len as f64;
            let tenth = (fraction * 10.0) as u64;
            let since = last.elapsed();
            if since >= LINE_EVERY || (tenth != last_tenth && since >= LINE_AT_LEAST) {
                eprintln!("{}", line(&pb.message(), fraction, pb.elapsed()));
                (last, last_tenth) = (Instant::now(), tenth);
            }
        }
    };
    // Without the thread there are just no lines; the work goes on.
    let _ = std::thread::Builder::new().name("progress".into()).spawn(watch);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_estimate_before_it_means_something() {
        let s = Duration::from_secs;
        assert_eq!(left(0.5, s(1)), None, "too early");
        assert_eq!(left(0.001, s(60)), None, "too little done");
        assert_eq!(left(0.25, s(30)), Some(s(90)));
        assert_eq!(left(f64::NAN, s(30)), None);
        assert_eq!(line("jobs", 0.25, s(30)), "jobs: 25 % after 30 s, about 1:30 left");
        assert_eq!(line("reference 1/4", 0.0, s(1)), "reference 1/4: 0 % after 1 s");
        assert_eq!(clock(s(3723)), "1:02:03");
    }
}
