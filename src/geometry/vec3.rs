//! 3-vectors stored as `[f64; 3]`, the layout of every position and
//! tangent in rodkit's APIs (and of the C arrays behind them). The few
//! operations the curve and pair loops need, in one place; the rod's
//! frames and stiffness algebra use nalgebra's fixed-size types.

#[inline]
pub fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline]
pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline]
pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

/// |a − b|² (written out: the pair loops' hottest expression).
#[inline]
pub fn distance2(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)
}

/// |a − b|.
#[inline]
pub fn distance(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    distance2(a, b).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn products_and_distances_by_hand() {
        // e1 × e2 = e3; (1,2,2) has length 3 (hand values).
        assert_eq!(cross([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]), [0.0, 0.0, 1.0]);
        assert_eq!(dot([1.0, 2.0, 3.0], [4.0, -5.0, 6.0]), 12.0);
        assert_eq!(distance(&[1.0, 2.0, 2.0], &[0.0; 3]), 3.0);
        assert_eq!(sub([1.0, 2.0, 3.0], [1.0, 1.0, 1.0]), [0.0, 1.0, 2.0]);
    }
}
