//! Euler's clamped–free rod of the buckling tests: K_b1 = 2, K_b2 = 1
//! (the buckling plane fixed, a simple point), C = 1/1.3, GA = 1e4,
//! EA = 2.6e4, L = 1, an axial dead tip load −Λ e_z; and the straight
//! branch's options that detect its point (to Λ = 3, residual 1e-10).

use rodkit::continuation::Options;
use rodkit::rod::model::{Rod, Supports};
use rodkit::rod::scheme::Scheme;
use rodkit::rod::{Load, Loads, RodLaw};

pub fn euler_cantilever(elements: usize) -> Rod {
    let k = nalgebra::Matrix6::from_diagonal(&nalgebra::Vector6::new(2.0, 1.0, 1.0 / 1.3, 1e4, 1e4, 2.6e4));
    let law = RodLaw::general(k, nalgebra::Vector3::zeros(), nalgebra::Vector3::new(0.0, 0.0, 1.0)).unwrap();
    let loads = Loads { tip_force: Some(Load::dead([0.0, 0.0, -1.0])), ..Default::default() };
    Rod::new(law, 1.0, loads, Supports::Cantilever, Scheme::Gauss(4), elements).unwrap()
}

pub fn straight_options() -> Options {
    Options {
        target_lambda: Some(3.0),
        residual_tol: 1e-10,
        initial_step: 0.2,
        max_step: 1.0,
        detect_bifurcations: true,
        ..Default::default()
    }
}
