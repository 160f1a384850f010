//! Writhe by the Gauss double integral (physics.md §3.4) against values
//! from an independent formula: Fuller's (1978) theorem, Wr(C1) − Wr(C0) =
//! (1/2π) ∫ (T0 × T1)·(T0' + T1')/(1 + T0·T1) dσ, for a curve C1 deformed
//! from C0 without antipodal tangents — a single integral along a common
//! parameter, evaluated here by composite Gauss–Legendre. C0 is a circle
//! (planar: Wr = 0), or for open rods closed by rays along the clamp axis a
//! straight segment (collinear with its rays: Wr = 0; the rays' tangents
//! are the same for C1, so they add nothing to Fuller's integral).

use rodkit::electrostatics::Centerline;
use rodkit::geometry::writhe::writhe;
use std::f64::consts::PI;

/// A curve r(σ) given with r'(σ), r''(σ) for its own parameter σ ∈ [0, P].
struct Param<F: Fn(f64) -> ([f64; 3], [f64; 3], [f64; 3])> {
    f: F,
    period: f64,
    closed: bool,
    panels: usize,
}

impl<F: Fn(f64) -> ([f64; 3], [f64; 3], [f64; 3])> Centerline for Param<F> {
    fn length(&self) -> f64 {
        self.period
    }
    fn closed(&self) -> bool {
        self.closed
    }
    fn eval(&self, s: f64) -> ([f64; 3], [f64; 3], [f64; 3]) {
        (self.f)(s)
    }
    fn breakpoints(&self) -> Vec<f64> {
        (1..self.panels).map(|k| self.period * k as f64 / self.panels as f64).collect()
    }
}

fn unit_and_derivative(d1: [f64; 3], d2: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let n = (d1[0] * d1[0] + d1[1] * d1[1] + d1[2] * d1[2]).sqrt();
    let t = [d1[0] / n, d1[1] / n, d1[2] / n];
    let td2 = t[0] * d2[0] + t[1] * d2[1] + t[2] * d2[2];
    (t, [(d2[0] - t[0] * td2) / n, (d2[1] - t[1] * td2) / n, (d2[2] - t[2] * td2) / n])
}

/// Fuller's integral between the unit tangents of two parametrised curves.
fn fuller(
    c0: &dyn Fn(f64) -> ([f64; 3], [f64; 3], [f64; 3]),
    c1: &dyn Fn(f64) -> ([f64; 3], [f64; 3], [f64; 3]),
    period: f64,
) -> f64 {
    let (g, w) = (
        [-0.906179845938664, -0.5384693101056831, 0.0, 0.5384693101056831, 0.906179845938664],
        [0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665, 0.2369268850561891],
    );
    let m = 4000;
    let mut sum = 0.0;
    for k in 0..m {
        let (a, b) = (period * k as f64 / m as f64, period * (k + 1) as f64 / m as f64);
        for (gi, wi) in g.iter().zip(&w) {
            let s = 0.5 * (a + b) + 0.5 * (b - a) * gi;
            let (_, a1, a2) = c0(s);
            let (_, b1, b2) = c1(s);
            let (t0, dt0) = unit_and_derivative(a1, a2);
            let (t1, dt1) = unit_and_derivative(b1, b2);
            let x = [t0[1] * t1[2] - t0[2] * t1[1], t0[2] * t1[0] - t0[0] * t1[2], t0[0] * t1[1] - t0[1] * t1[0]];
            let num = x[0] * (dt0[0] + dt1[0]) + x[1] * (dt0[1] + dt1[1]) + x[2] * (dt0[2] + dt1[2]);
            let den = 1.0 + t0[0] * t1[0] + t0[1] * t1[1] + t0[2] * t1[2];
            sum += 0.5 * (b - a) * wi * num / den;
        }
    }
    sum / (2.0 * PI)
}

fn circle(s: f64) -> ([f64; 3], [f64; 3], [f64; 3]) {
    let (sn, cs) = s.sin_cos();
    ([cs, sn, 0.0], [-sn, cs, 0.0], [-cs, -sn, 0.0])
}

/// A toroidal helix winding n times round the unit circle at amplitude ε.
fn toroidal(n: f64, eps: f64) -> impl Fn(f64) -> ([f64; 3], [f64; 3], [f64; 3]) {
    move |p: f64| {
        let (sp, cp) = p.sin_cos();
        let (sn, cn) = (n * p).sin_cos();
        let rho = 1.0 + eps * cn;
        let drho = -eps * n * sn;
        let ddrho = -eps * n * n * cn;
        (
            [rho * cp, rho * sp, eps * sn],
            [drho * cp - rho * sp, drho * sp + rho * cp, eps * n * cn],
            [ddrho * cp - 2.0 * drho * sp - rho * cp, ddrho * sp + 2.0 * drho * cp - rho * sp, -eps * n * n * sn],
        )
    }
}

#[test]
fn writhe_of_a_circle_is_zero() {
    let c = Param { f: circle, period: 2.0 * PI, closed: true, panels: 16 };
    let wr = writhe(&c, 10).unwrap();
    assert!(wr.abs() < 1e-12, "{wr:e}");
}

/// Toroidal helices (closed, 3 and 10 windings) against Fuller from the circle.
#[test]
fn writhe_of_closed_toroidal_helices_matches_fuller() {
    for (n, eps) in [(3.0, 0.2), (10.0, 0.1), (10.0, 0.05)] {
        let f = toroidal(n, eps);
        let reference = fuller(&circle, &f, 2.0 * PI);
        let c = Param { f: toroidal(n, eps), period: 2.0 * PI, closed: true, panels: 8 * n as usize };
        let wr = writhe(&c, 12).unwrap();
        println!("n {n}, ε {eps}: Gauss {wr}, Fuller {reference}");
        assert!((wr - reference).abs() < 1e-8, "n {n} ε {eps}: {wr} vs {reference}");
    }
}

/// An open rod along z with a helical bump, r(σ) = (ε f cos mσ, ε f sin mσ, σ),
/// f = sin²(πσ/L) (end tangents along z, the clamp axis), closed by rays:
/// Fuller from the straight segment.
#[test]
fn writhe_of_an_open_rod_closed_by_rays_matches_fuller() {
    let l = 10.0;
    for (m, eps) in [(2.0, 0.5), (5.0, 0.3)] {
        let bump = move |s: f64| {
            let k = PI / l;
            let (f, df, ddf) = ((k * s).sin().powi(2), k * (2.0 * k * s).sin(), 2.0 * k * k * (2.0 * k * s).cos());
            let (sm, cm) = (m * s).sin_cos();
            (
                [eps * f * cm, eps * f * sm, s],
                [eps * (df * cm - f * m * sm), eps * (df * sm + f * m * cm), 1.0],
                [
                    eps * (ddf * cm - 2.0 * df * m * sm - f * m * m * cm),
                    eps * (ddf * sm + 2.0 * df * m * cm - f * m * m * sm),
                    0.0,
                ],
            )
        };
        let straight = |s: f64| ([0.0, 0.0, s], [0.0, 0.0, 1.0], [0.0; 3]);
        let reference = fuller(&straight, &bump, l);
        let c = Param { f: bump, period: l, closed: false, panels: 40 };
        let wr = writhe(&c, 12).unwrap();
        println!("m {m}, ε {eps}: Gauss with rays {wr}, Fuller {reference}");
        assert!((wr - reference).abs() < 1e-7, "m {m}: {wr} vs {reference}");
        assert!(reference.abs() > 0.05, "a test that could not tell");
    }
}
