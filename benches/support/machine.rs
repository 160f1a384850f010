//! What else the machine did while a bench timed: the CPU time all
//! processes spent (/proc/stat) less this process's and its children's own
//! (getrusage), per second of wall time — the cores other jobs took. A
//! ratio of two timings is only reported when that stayed small.

use std::time::Instant;

/// A reading of the machine's and this process's CPU time.
#[derive(Clone, Copy, Debug)]
pub struct Sample {
    at: Instant,
    /// Busy time of all CPUs (user, nice, system, irq, softirq, steal), s.
    busy: f64,
    /// This process's and its waited-for children's CPU time, s.
    own: f64,
}

/// The aggregate "cpu" line of /proc/stat in seconds of busy time (None
/// where there is no /proc).
fn busy_seconds() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/stat").ok()?;
    let line = text.lines().find(|l| l.starts_with("cpu "))?;
    let v: Vec<f64> = line.split_whitespace().skip(1).filter_map(|x| x.parse().ok()).collect();
    // user nice system idle iowait irq softirq steal …
    let busy = v.first()? + v.get(1)? + v.get(2)? + v.get(5)? + v.get(6)? + v.get(7).copied().unwrap_or(0.0);
    // SAFETY: sysconf has no preconditions.
    let tick = unsafe { libc::sysconf(libc::_SC_CLK_TCK) } as f64;
    Some(busy / tick)
}

impl Sample {
    pub fn now() -> Self {
        Sample {
            at: Instant::now(),
            busy: busy_seconds().unwrap_or(f64::NAN),
            own: (crate::timing::cpu_time(false) + crate::timing::cpu_time(true)).as_secs_f64(),
        }
    }

    /// Cores used by other processes between `self` and `later` (NaN
    /// without /proc). The clock tick makes it coarse over short spans.
    pub fn others_since(&self, later: &Sample) -> f64 {
        let wall = later.at.duration_since(self.at).as_secs_f64();
        ((later.busy - self.busy) - (later.own - self.own)) / wall.max(1e-9)
    }
}

/// The number of online CPUs.
pub fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// The one-minute load average (/proc/loadavg), this bench included.
pub fn load_average() -> f64 {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|t| t.split_whitespace().next().and_then(|v| v.parse().ok()))
        .unwrap_or(f64::NAN)
}
