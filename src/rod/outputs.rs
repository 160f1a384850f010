//! What a rod state shows: the tip's rotation, the spatial force and
//! moment at a node, the node positions.

use super::kinematics::{mat_vec, rotation};
use super::model::Rod;
use super::scheme::Scheme;
use crate::continuation::stability::Metric;

impl Rod {
    /// The angle between the tip tangent d3(L) and e3 (radians, 0…π), as
    /// atan2(|d3 × e3|, d3 · e3): accurate at small angles, where acos of
    /// the cosine loses half the digits (3 % off at 5e-8 rad).
    pub fn tip_rotation(&self, x: &[f64]) -> f64 {
        let y = self.node_state(x, self.elements);
        let (q0, q1, q2, q3) = (y[3], y[4], y[5], y[6]);
        // d3 = R(q) e3 for q not normalised (divided by |q|² below).
        let d3x = 2.0 * (q1 * q3 + q0 * q2);
        let d3y = 2.0 * (q2 * q3 - q0 * q1);
        let d3z = q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3;
        d3x.hypot(d3y).atan2(d3z)
    }

    /// The rotation vector θ·n of node i's frame (from the lab frame: the
    /// straight rod's), the shortest of the rotations taking one to the
    /// other (θ ∈ [0, π]): its components are signed angles — a planar
    /// cantilever bent towards +e1 turns about +e2 by the second. From
    /// the quaternion q = ±(cos θ/2, sin θ/2 n) (not necessarily unit) as
    /// 2 atan2(|v|, |q0|) v/|v| with v taken on the side q0 ≥ 0: exact at
    /// small angles, where it tends to 2v/q0. A path through θ = π flips
    /// it (n → −n): follow it by continuity there.
    pub fn rotation_vector(&self, x: &[f64], i: usize) -> [f64; 3] {
        let y = self.node_state(x, i);
        let sign = if y[3] < 0.0 { -1.0 } else { 1.0 };
        let (w, v) = (sign * y[3], [sign * y[4], sign * y[5], sign * y[6]]);
        let norm = v[0].hypot(v[1]).hypot(v[2]);
        if norm == 0.0 {
            return [0.0; 3];
        }
        let theta = 2.0 * norm.atan2(w);
        [theta * v[0] / norm, theta * v[1] / norm, theta * v[2] / norm]
    }

    /// Spatial force and moment at node i: R(q) n_b, R(q) m_b.
    pub fn spatial_force_moment(&self, x: &[f64], i: usize) -> ([f64; 3], [f64; 3]) {
        let y = self.node_state(x, i);
        let q = [y[3], y[4], y[5], y[6]];
        let r = rotation(&q);
        let n = mat_vec(&r, &[y[7], y[8], y[9]]);
        let m = mat_vec(&r, &[y[10], y[11], y[12]]);
        (n, m)
    }

    /// Node positions r(s_i), i = 0…N.
    pub fn positions(&self, x: &[f64]) -> Vec<[f64; 3]> {
        (0..=self.elements)
            .map(|i| {
                let y = self.node_state(x, i);
                [y[0], y[1], y[2]]
            })
            .collect()
    }
}

impl Rod {
    /// Offset in the unknowns of the state at stage j of element e (its
    /// position first): the element's stage blocks follow its node's.
    pub fn stage_offset(&self, e: usize, j: usize) -> usize {
        self.node(e) + 13 * (1 + j)
    }

    /// [`Rod::stage_offset`] of every stage point, element by element.
    pub fn stage_offsets(&self) -> Vec<usize> {
        let stages = self.scheme.stages();
        (0..self.elements).flat_map(|e| (0..stages).map(move |j| self.stage_offset(e, j))).collect()
    }

    /// Stage-point positions and their arc lengths in state x.
    pub fn stage_points(&self, x: &[f64]) -> (Vec<[f64; 3]>, Vec<f64>) {
        let tab = self.tableau();
        let stages = self.scheme.stages();
        let r = self.stage_offsets().into_iter().map(|o| [x[o], x[o + 1], x[o + 2]]).collect();
        let c = &tab.c;
        let s = (0..self.elements)
            .flat_map(|e| (0..stages).map(move |j| self.node_position(e) + c[j] * self.element_h(e)))
            .collect();
        (r, s)
    }
}

impl Rod {
    /// The stability metric of state x ([`Metric`]): the stage positions,
    /// their weights h_e b_j (the stage quadrature of ∫|δr|² ds), and the
    /// rows a dead force density p_j at stage j enters — its element's n
    /// rows, h_e a_ij R(q_j)ᵀ p_j in stage row i and h_e b_j R(q_j)ᵀ p_j in
    /// the update, as the right-hand side n_b' = … − R(q)ᵀp does through
    /// the residual Y_i − y_0 − h Σ_j a_ij f(Y_j). With `phase` (the
    /// system with a phase condition and its unfolding μ, one more
    /// unknown), the rotation about e3 is the zero mode. None for the
    /// midpoint scheme (no stage unknowns).
    pub fn stage_metric(&self, x: &[f64], phase: bool) -> Option<Metric> {
        let Scheme::Gauss(s) = self.scheme else { return None };
        let tab = self.tableau();
        let points = self.elements * s;
        let (scale, tension) = self.sigma_scale(x);
        let mut metric = Metric {
            dim: self.unknowns() + phase as usize,
            coords: Vec::with_capacity(points),
            weights: Vec::with_capacity(points),
            rows_per_point: s + 1,
            rows: Vec::with_capacity(points * (s + 1)),
            coefs: Vec::with_capacity(points * (s + 1)),
            rotations: Vec::with_capacity(points),
            zero_modes: Vec::new(),
            unfolding: phase.then(|| self.unknowns()),
            scale,
            neutral_scale: if self.localised(x) { tension } else { 0.0 },
        };
        for e in 0..self.elements {
            let h = self.element_h(e);
            for j in 0..s {
                let o = self.stage_offset(e, j);
                metric.coords.push(o);
                metric.weights.push(h * tab.b[j]);
                for (i, a) in tab.a.iter().enumerate() {
                    metric.rows.push(self.stage_offset(e, i) + 7);
                    metric.coefs.push(h * a[j]);
                }
                metric.rows.push(self.node(e + 1) + 7);
                metric.coefs.push(h * tab.b[j]);
                metric.rotations.push(rotation(&[x[o + 3], x[o + 4], x[o + 5], x[o + 6]]));
            }
        }
        if phase {
            let r: Vec<[f64; 3]> = metric.coords.iter().map(|&o| [x[o], x[o + 1], x[o + 2]]).collect();
            metric.zero_modes.extend(metric.axial_rotation_mode(&r, self.length));
        }
        Some(metric)
    }

    /// Whether the state carries a localised structure on straight tails:
    /// some stage point lies off the axis by more than the tension length
    /// ξ = √(K_b/F) (F the larger end force). Next to the straight rod's
    /// bifurcation the buckled state is an extended helix of small
    /// amplitude with no such structure, and its σ near zero are the
    /// bifurcation's own modes, never neutral.
    pub fn localised(&self, x: &[f64]) -> bool {
        let Scheme::Gauss(s) = self.scheme else { return false };
        let kb = self.law.stiffness[(0, 0)].min(self.law.stiffness[(1, 1)]);
        let force = [self.node(0), self.node(self.elements)]
            .iter()
            .map(|&o| x[o + 7..o + 10].iter().map(|a| a * a).sum::<f64>().sqrt())
            .fold(0.0, f64::max);
        if !(force > 0.0) {
            return false;
        }
        let xi = (kb / force).sqrt();
        (0..self.elements).flat_map(|e| (0..s).map(move |j| (e, j))).any(|(e, j)| {
            let o = self.stage_offset(e, j);
            x[o].hypot(x[o + 1]) > xi
        })
    }

    /// The units of σ at state x ([`Metric::scale`], and
    /// [`Metric::neutral_scale`] without the moment): max(K_b/L⁴, F²/K_b,
    /// M⁴/K_b³) with K_b the smaller bending stiffness and F, M the
    /// largest force and moment at the two ends (n_b, m_b of the end
    /// nodes: the load the rod carries, not the bending moment of a loop
    /// inside it).
    pub fn sigma_scale(&self, x: &[f64]) -> (f64, f64) {
        let kb = self.law.stiffness[(0, 0)].min(self.law.stiffness[(1, 1)]);
        let norm = |v: &[f64]| v.iter().map(|a| a * a).sum::<f64>().sqrt();
        let (mut f, mut m) = (0.0f64, 0.0f64);
        for o in [self.node(0), self.node(self.elements)] {
            f = f.max(norm(&x[o + 7..o + 10]));
            m = m.max(norm(&x[o + 10..o + 13]));
        }
        let tension = (kb / self.length.powi(4)).max(f * f / kb);
        (tension.max(m.powi(4) / kb.powi(3)), tension)
    }
}

#[cfg(test)]
mod tests {
    use crate::rod::model::{Rod, Supports};
    use crate::rod::scheme::Scheme;
    use crate::rod::{Loads, RodLaw};

    /// A tip frame turned by ε about e1 (q = (cos ε/2, sin ε/2, 0, 0),
    /// scaled by 3: the angle does not depend on |q|) tilts d3 by exactly ε
    /// from e3: tip_rotation returns ε to 1e-15 relative, also at 5e-8 rad
    /// where acos of the cosine was 3 % off.
    #[test]
    fn tip_rotation_is_accurate_at_small_angles() {
        let law = RodLaw::kirchhoff(1.0, 1.0, 1.0).unwrap();
        let rod = Rod::new(law, 1.0, Loads::default(), Supports::Cantilever, Scheme::Gauss(2), 2).unwrap();
        let mut x = rod.straight_state();
        let tip = rod.node(rod.elements);
        for eps in [5e-8f64, 1e-3, 2.0, 3.0] {
            let (c, s) = ((0.5 * eps).cos(), (0.5 * eps).sin());
            x[tip + 3..tip + 7].copy_from_slice(&[3.0 * c, 3.0 * s, 0.0, 0.0]);
            let got = rod.tip_rotation(&x);
            assert!((got - eps).abs() <= 1e-15 * eps, "ε {eps}: {got}");
        }
    }

    /// The metric's injection M′ is the rows' own derivative with respect
    /// to a dead distributed force: a rod loaded by Λ·w (w dead, spatial)
    /// has ∂R/∂Λ = M′(w, w, …, w) exactly, whatever the state (a
    /// cantilever: no Λ in its boundary rows). Reference:
    /// the assembled system's Jacobian column (its tapes differentiate the
    /// kinematics' −R(q)ᵀΛw independently of the metric's bookkeeping), at
    /// a perturbed state whose stage quaternions are not unit, on a graded
    /// mesh (h per element), Gauss(3): to 1e-15 of the column's size.
    /// With a phase condition the zero mode is e3 × r_j, W-normalised.
    #[test]
    fn metric_injects_as_a_dead_distributed_force() {
        use crate::continuation::Problem;
        use crate::rod::Load;
        let law = RodLaw::kirchhoff(1.0, 1.0, 1.3).unwrap();
        let w = [0.3, -0.7, 0.5];
        let loads = Loads { distributed_force: Some(Load::dead(w)), ..Default::default() };
        let rod = Rod::new(law, 1.7, loads, Supports::Cantilever, Scheme::Gauss(3), 5)
            .unwrap()
            .graded(&[0.0, 0.1, 0.3, 0.55, 0.8, 1.0])
            .unwrap();
        let mut x = rod.straight_state();
        for (k, v) in x.iter_mut().enumerate() {
            *v += 0.05 * ((k as f64) * 0.713).sin();
        }
        let mut sys = rod.system().unwrap();
        let n = sys.dim();
        let (mut jx, mut jl) = (vec![0.0; sys.pattern().nnz()], vec![0.0; n]);
        sys.jacobian(&x, 0.2, &mut jx, &mut jl);
        let metric = rod.stage_metric(&x, false).unwrap();
        assert_eq!(metric.points(), 15);
        let force: Vec<f64> = (0..metric.points()).flat_map(|_| w).collect();
        let mut injected = vec![0.0; n];
        metric.inject(&force, &mut injected);
        let scale = jl.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let err = jl.iter().zip(&injected).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(scale > 0.01 && err <= 1e-15 * scale, "∂R/∂Λ vs M′w: {err:e} of {scale:e}");
        let metric = rod.stage_metric(&x, true).unwrap();
        assert_eq!((metric.dim, metric.zero_modes.len()), (n + 1, 1));
        // μ is the unknown after the rod's own (Rod::system_with_phase).
        assert_eq!((rod.stage_metric(&x, false).unwrap().unfolding, metric.unfolding), (None, Some(n)));
        let z = &metric.zero_modes[0];
        assert!((metric.dot(z, z) - 1.0).abs() < 1e-14);
        for (p, &o) in metric.coords.iter().enumerate() {
            let ratio = z[3 * p] / -x[o + 1];
            assert!((z[3 * p + 1] - ratio * x[o]).abs() < 1e-14 && z[3 * p + 2] == 0.0);
        }
        let straight = rod.straight_state();
        assert!(rod.stage_metric(&straight, true).unwrap().zero_modes.is_empty());
    }
}
