//! What every bench binary measures with: the median of repeated wall
//! times, milliseconds, and the largest distance between two lists of
//! tip positions.

use std::time::Duration;

/// The median of `v` (the upper one for an even count).
pub fn median(mut v: Vec<Duration>) -> Duration {
    v.sort();
    v[v.len() / 2]
}

pub fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

/// max_k |a_k − b_k| over paired 3-vectors (tips against their reference).
#[allow(dead_code)] // not every bench compares tips
pub fn max_distance(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt())
        .fold(0.0, f64::max)
}

/// CPU time (user + system) of this process (`children` false) or of its
/// terminated, waited-for children so far (true): getrusage.
#[allow(dead_code)] // the benches that run no peer process
pub fn cpu_time(children: bool) -> Duration {
    let who = if children { libc::RUSAGE_CHILDREN } else { libc::RUSAGE_SELF };
    let mut u = std::mem::MaybeUninit::<libc::rusage>::zeroed();
    // SAFETY: getrusage writes the struct it is given; `who` is valid.
    let u = unsafe {
        libc::getrusage(who, u.as_mut_ptr());
        u.assume_init()
    };
    let tv = |t: libc::timeval| Duration::new(t.tv_sec as u64, t.tv_usec as u32 * 1000);
    tv(u.ru_utime) + tv(u.ru_stime)
}
