//! Comparing two supercoiling paths that solve the same equations to the
//! same residual tolerance and differ only by rounding in their
//! factorisations (tests/supercoil_lu.rs, tests/supercoil_overlap.rs).

use rodkit::charged::dna::SupercoilRun;

/// As many points, and at each the turns, extension, torque and writhe
/// within `tol` of their scales (1 turn, L = `length` nm, 10 pN nm).
pub fn assert_same_points(a: &SupercoilRun, b: &SupercoilRun, length: f64, tol: f64) {
    assert_eq!(a.points.len(), b.points.len(), "different numbers of points");
    for (k, (p, q)) in a.points.iter().zip(&b.points).enumerate() {
        let (o, f) = (&p.observables, &q.observables);
        for (name, x, y, scale) in [
            ("turns", o.turns, f.turns, 1.0),
            ("extension", o.extension, f.extension, length),
            ("torque", o.torque, f.torque, 10.0),
            ("writhe", o.writhe, f.writhe, 1.0),
        ] {
            assert!((x - y).abs() < tol * scale, "point {k}: {name} {x} vs {y}");
        }
    }
}
