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
