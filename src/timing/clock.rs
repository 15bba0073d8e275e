//! The clock a render is timed with: the CPU time of the calling thread. A render timed this way
//! on one thread is not charged for the time another process held the core, which on a shared
//! machine is most of the noise of wall time; it still includes what the render itself spends
//! (cache misses, a slower clock).

/// What [`thread_cpu_s`] reads, for the report.
#[cfg(unix)]
pub const NAME: &str = "thread CPU time (clock_gettime CLOCK_THREAD_CPUTIME_ID)";
#[cfg(not(unix))]
pub const NAME: &str = "wall time (no thread CPU clock on this platform)";

/// CPU seconds the calling thread has used so far.
#[cfg(unix)]
pub fn thread_cpu_s() -> f64 {
    let mut ts = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: `ts` is a valid, writable timespec; the call only writes it.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    if rc != 0 {
        return wall_s();
    }
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

/// Without a thread CPU clock, wall time since the first call.
#[cfg(not(unix))]
pub fn thread_cpu_s() -> f64 {
    wall_s()
}

/// Seconds since the first call in this process (a monotonic wall clock).
pub fn wall_s() -> f64 {
    use std::sync::OnceLock;
    use std::time::Instant;
    static START: OnceLock<Instant> = OnceLock::new();
    START.get_or_init(Instant::now).elapsed().as_secs_f64()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thread_clock_advances_with_work_and_not_with_sleep() {
        let t0 = thread_cpu_s();
        let mut x = 0u64;
        for i in 0..5_000_000u64 {
            x = x.wrapping_mul(6364136223846793005).wrapping_add(i);
        }
        std::hint::black_box(x);
        let t1 = thread_cpu_s();
        assert!(t1 > t0, "busy work uses CPU time");
        if cfg!(unix) {
            std::thread::sleep(std::time::Duration::from_millis(30));
            let t2 = thread_cpu_s();
            assert!(t2 - t1 < 0.02, "a sleeping thread uses (almost) no CPU time: {}", t2 - t1);
        }
    }
}
