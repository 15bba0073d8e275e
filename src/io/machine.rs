//! What `/proc` says about this machine: its name and CPU, for records and reports, and how busy
//! it is, for forecasts (`jobs::calibrate`).

use std::fs;

/// This machine's host name (`/proc/sys/kernel/hostname`, else `$HOSTNAME`), or "unknown".
pub fn hostname() -> String {
    fs::read_to_string("/proc/sys/kernel/hostname")
        .ok()
        .or_else(|| std::env::var("HOSTNAME").ok())
        .map(|h| h.trim().to_string())
        .filter(|h| !h.is_empty())
        .unwrap_or_else(|| "unknown".into())
}

/// The host name with only letters, digits, '-' and '.', for file names.
pub fn host_tag() -> String {
    hostname()
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '.' { c } else { '_' })
        .collect()
}

/// The CPU model (`model name` in `/proc/cpuinfo`) and its logical CPU count, e.g.
/// "AMD EPYC 7B13 (2 CPUs)"; the architecture where `/proc` has no model name.
pub fn cpu_model() -> String {
    let cpus = crate::timing::cores();
    let model = fs::read_to_string("/proc/cpuinfo").ok().and_then(|t| {
        t.lines()
            .find(|l| l.starts_with("model name"))
            .and_then(|l| l.split_once(':'))
            .map(|(_, m)| m.split_whitespace().collect::<Vec<_>>().join(" "))
    });
    format!("{} ({cpus} CPUs)", model.unwrap_or_else(|| std::env::consts::ARCH.to_string()))
}

/// The 1-minute load average and the number of CPUs the kernel has online (`/proc/loadavg`,
/// `/proc/cpuinfo`): how many threads want a core, machine-wide, and how many cores there are.
pub fn load_average() -> Option<(f64, usize)> {
    let load = fs::read_to_string("/proc/loadavg").ok()?.split_whitespace().next()?.parse().ok()?;
    let cpus =
        fs::read_to_string("/proc/cpuinfo").ok()?.lines().filter(|l| l.starts_with("processor")).count();
    (cpus > 0).then_some((load, cpus))
}

/// How many threads of *other* processes want a core, sampled while this process works
/// (`/proc/stat`'s `procs_running`, less this process's own threads in state R). Unlike the load
/// average it does not remember the last minute: a forecast asked right after a long run saw that
/// run's own 1.9 in the load average and forecast a quiet machine 1.4x slow (2026-12-07).
#[derive(Debug, Default)]
pub struct Runnable {
    sum: f64,
    samples: u32,
}

impl Runnable {
    /// One sample; false where `/proc` cannot say (then `mean` stays `None`).
    pub fn sample(&mut self) -> bool {
        let Some(all) = procs_running() else { return false };
        let mine = own_running().unwrap_or(1);
        self.sum += all.saturating_sub(mine) as f64;
        self.samples += 1;
        true
    }

    /// Mean runnable threads of other processes over the samples.
    pub fn mean(&self) -> Option<f64> {
        (self.samples > 0).then(|| self.sum / self.samples as f64)
    }
}

fn procs_running() -> Option<usize> {
    let stat = fs::read_to_string("/proc/stat").ok()?;
    stat.lines().find_map(|l| l.strip_prefix("procs_running")).and_then(|n| n.trim().parse().ok())
}

/// This process's threads that are running or runnable (state R in `/proc/self/task/*/stat`).
fn own_running() -> Option<usize> {
    let tasks = fs::read_dir("/proc/self/task").ok()?;
    let running = tasks
        .flatten()
        .filter_map(|t| fs::read_to_string(t.path().join("stat")).ok())
        // The state follows the command name's closing parenthesis (which may itself hold spaces).
        .filter(|s| s.rsplit_once(')').is_some_and(|(_, rest)| rest.trim_start().starts_with('R')))
        .count();
    Some(running)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sampling_thread_does_not_count_itself() {
        let mut r = Runnable::default();
        assert!(r.sample(), "Linux's /proc/stat says procs_running");
        // This thread is running while it reads, and is subtracted: others only.
        assert!(r.mean().is_some_and(|m| m >= 0.0));
        assert!(own_running().is_some_and(|n| n >= 1), "the reading thread is running");
    }
}
