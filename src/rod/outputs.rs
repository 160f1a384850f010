//! What a rod state shows: the tip's rotation, the spatial force and
//! moment at a node, the node positions.

use super::kinematics::{mat_vec, rotation};
use super::model::Rod;

impl Rod {
    /// The angle between the tip tangent d3(L) and e3 (radians, 0…π).
    pub fn tip_rotation(&self, x: &[f64]) -> f64 {
        let y = self.node_state(x, self.elements);
        let n2 = y[3] * y[3] + y[4] * y[4] + y[5] * y[5] + y[6] * y[6];
        let d3z = (y[3] * y[3] - y[4] * y[4] - y[5] * y[5] + y[6] * y[6]) / n2;
        d3z.clamp(-1.0, 1.0).acos()
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
        let h = self.element_length();
        let tab = self.tableau();
        let stages = self.scheme.stages();
        let r = self.stage_offsets().into_iter().map(|o| [x[o], x[o + 1], x[o + 2]]).collect();
        let c = &tab.c;
        let s = (0..self.elements).flat_map(|e| (0..stages).map(move |j| (e as f64 + c[j]) * h)).collect();
        (r, s)
    }
}
