//! Pure: what a command is about to do, said before it does it — the references it builds, the
//! images it renders, the CPU and wall time they take on this machine (from `jobs::forecast`'s
//! calibration) and the bytes it writes — and the one rule that stops it: a forecast longer than
//! `--max-minutes` is refused (exit status 2) unless the user raises the limit, so that a mistyped
//! `--rays 1048576 --resolution 8192x8192` never starts days of work without a word.

use super::{format_bytes, format_duration};

/// Minutes of wall time a command may be forecast to take before it must be asked for
/// (`--max-minutes`).
pub const DEFAULT_MAX_MINUTES: f64 = 30.0;

/// A command's forecast.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Forecast {
    /// References it must build (0 when they are stored); `None`: it reads none (`render`).
    pub references: Option<usize>,
    /// Images it measures (jobs), or renders (`render`: 1).
    pub jobs: usize,
    /// What the jobs are, e.g. "sweep 2,044 jobs, finalists about 1,440" (empty: nothing to add).
    pub detail: String,
    /// CPU seconds of all the rendering.
    pub cpu_s: f64,
    /// Wall seconds on `threads` threads at the machine's measured load.
    pub wall_s: f64,
    pub threads: usize,
    /// Bytes of every file it writes.
    pub bytes: f64,
}

impl Forecast {
    /// One line: "plan: 1 reference to build, 2044 jobs (…): ≈ 3 min 10 s on 2 threads here
    /// (5 min 40 s of CPU time), ≈ 12 MB written".
    pub fn line(&self, command: &str) -> String {
        let refs = match self.references {
            None => String::new(),
            Some(0) => "its reference stored, ".to_string(),
            Some(1) => "1 reference to build, ".to_string(),
            Some(n) => format!("{n} references to build, "),
        };
        let detail = if self.detail.is_empty() { String::new() } else { format!(" ({})", self.detail) };
        format!(
            "{command} plan: {refs}{} image{}{detail}: ≈ {} on {} thread{} here ({} of CPU time), ≈ {} written",
            self.jobs,
            if self.jobs == 1 { "" } else { "s" },
            format_duration(self.wall_s),
            self.threads,
            if self.threads == 1 { "" } else { "s" },
            format_duration(self.cpu_s),
            format_bytes(self.bytes)
        )
    }

    /// `Err` (the message for exit status 2) when the forecast wall time exceeds `max_minutes`.
    pub fn check(&self, max_minutes: f64) -> Result<(), String> {
        if self.wall_s <= max_minutes * 60.0 {
            return Ok(());
        }
        let need = (self.wall_s / 60.0).ceil();
        Err(format!(
            "--max-minutes {}: this would take about {} on this machine, over the limit; nothing was \
             started. Ask for less (fewer rays, a smaller --resolution) or allow it with --max-minutes {need}",
            trim(max_minutes),
            format_duration(self.wall_s)
        ))
    }
}

/// 30 → "30", 2.5 → "2.5".
fn trim(x: f64) -> String {
    if x.fract() == 0.0 { format!("{x:.0}") } else { format!("{x}") }
}

/// Positive minutes, finite: what `--max-minutes` accepts.
pub fn parse_max_minutes(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(m) if m > 0.0 && m.is_finite() => Ok(m),
        _ => Err(format!("'{s}' must be a number of minutes > 0 (e.g. 30, or 600 for ten hours)")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_forecast_over_the_limit_is_refused_and_says_what_to_raise_it_to() {
        let f = Forecast {
            references: Some(12),
            jobs: 2044,
            detail: String::new(),
            cpu_s: 3.0 * 3600.0,
            wall_s: 1.5 * 3600.0 + 1.0,
            threads: 2,
            bytes: 504e6,
        };
        let line = f.line("advise");
        assert!(
            line.starts_with("advise plan: 12 references to build, 2044 images: ≈ 1 h 30 min on 2 threads")
        );
        assert!(line.ends_with("(3 h 00 min of CPU time), ≈ 504 MB written"), "{line}");
        let e = f.check(30.0).unwrap_err();
        assert!(e.starts_with("--max-minutes 30: this would take about 1 h 30 min"), "{e}");
        assert!(e.ends_with("--max-minutes 91"), "{e}");
        assert!(f.check(91.0).is_ok());
        let render = Forecast { references: None, jobs: 1, ..f.clone() }.line("render");
        assert!(render.starts_with("render plan: 1 image: ≈ 1 h 30 min on 2 threads"), "{render}");
        assert!(Forecast { wall_s: 1800.0, ..f }.check(30.0).is_ok(), "at the limit it runs");
        assert_eq!(parse_max_minutes("2.5"), Ok(2.5));
        assert!(parse_max_minutes("0").is_err() && parse_max_minutes("inf").is_err());
    }
}
