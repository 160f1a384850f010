//! Whether a pair list still holds every pair that interacts — the
//! criterion for rebuilding it.
//!
//! The list holds the far pairs within r_int + skin of each other where it
//! was built (r_int: the range of the pair potential, r_off of the
//! cutoff's switch or the hard core's 2.5a). A state's residual on the list
//! is the full model's exactly when no pair within r_int is missing.
//! Verlet's rule — rebuild once any stage has moved half the skin — is a
//! sufficient bound for that, and a poor one for a supercoiling rod: the
//! tail slides toward the bead as a whole (~30 nm a turn at 1 kbp, 1 pN,
//! 0.1 M) while the strands keep their partners, so lists lasted ~0.06
//! turns (166 lists along 0 → 12 turns) and capped the ANM's steps there.
//! [`super::ListRule::Coverage`] makes the rule the property itself: the smallest distance of a
//! missing far pair, less r_int (its *gap*), from a cell list of the
//! current stage points. A list is rebuilt while that gap is still half
//! the skin (so no pair is ever missing from a point's residual, and the
//! new list's residual is the old one's); the ANM cuts a step where the
//! gap would reach zero ([`super::ChargedRod::series_reach`]). Measured
//! mixed (faster at 0.1 M, slower at 0.01 M, and one branch lost where
//! Verlet's lists pass: see [`super::ListRule`]), so Verlet's rule stays
//! the default.

use super::{ChargedRod, HARD_CORE_RANGE};
use crate::geometry::proximity::CellList;

/// A copy of a list's pairs and what decides which pairs interact: checks
/// states while the continuation holds the problem.
#[derive(Clone, Debug)]
pub struct ListCoverage {
    offsets: Vec<usize>,
    elements: Vec<usize>,
    /// Each element's near run (first, last): the elements whose pairs
    /// with it are not far ([`super::super::assembly::near_runs`]).
    runs: Vec<(usize, usize)>,
    adj_ptr: Vec<usize>,
    adj: Vec<usize>,
    /// r_int: the potential's range.
    range: f64,
    skin: f64,
}

impl ListCoverage {
    /// The gap at the stage points `r`: min over far pairs missing from the
    /// list of (distance − r_int), capped at the skin (no missing pair
    /// within r_int + skin).
    pub fn gap_at(&self, r: &[[f64; 3]]) -> f64 {
        let reach = self.range + self.skin;
        let cells = CellList::new(r, reach);
        let mut found = Vec::new();
        let mut gap = self.skin;
        for (j, rj) in r.iter().enumerate() {
            cells.neighbours_within(r, rj, reach, &mut found);
            let listed = &self.adj[self.adj_ptr[j]..self.adj_ptr[j + 1]];
            for &k in &found {
                let (first, last) = self.runs[self.elements[j]];
                let far = self.elements[k] < first || self.elements[k] > last;
                if k > j && far && listed.binary_search(&k).is_err() {
                    let d = crate::geometry::vec3::distance(rj, &r[k]);
                    gap = gap.min(d - self.range);
                }
            }
        }
        gap
    }

    /// The gap at the state x.
    pub fn gap(&self, x: &[f64]) -> f64 {
        self.gap_at(&self.points(x))
    }

    fn points(&self, x: &[f64]) -> Vec<[f64; 3]> {
        self.offsets.iter().map(|&o| [x[o], x[o + 1], x[o + 2]]).collect()
    }

    /// The skin the list was built with.
    pub fn skin(&self) -> f64 {
        self.skin
    }
}

impl ChargedRod {
    /// The list's coverage check, None when the list holds every far pair
    /// (no cutoff), is the base-pair model's, or the charge rebuilds its
    /// lists by Verlet's rule ([`super::ListRule`], [`ChargedRod::displacement`]).
    pub fn coverage(&self) -> Option<ListCoverage> {
        if !self.list_local || self.sites.is_some() || self.charge.list_rule != super::ListRule::Coverage {
            return None;
        }
        let a = self.charge.screening.a;
        let hard = if self.charge.hard_core.is_some() { HARD_CORE_RANGE * a } else { 0.0 };
        let range = self.cutoff.map_or(hard, |(_, off)| off.max(hard));
        Some(ListCoverage {
            offsets: self.points.iter().map(|p| p.offset).collect(),
            elements: self.points.iter().map(|p| p.element).collect(),
            runs: self.runs.clone(),
            adj_ptr: self.adj_ptr.clone(),
            adj: self.adj.clone(),
            range,
            skin: self.charge.skin,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::ListCoverage;

    /// Reference: the gap by brute force over every pair of points.
    #[test]
    fn the_gap_is_the_closest_missing_far_pair_less_the_range() {
        let mut seed = 7u64;
        let mut rnd = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let n = 120;
        let r0: Vec<[f64; 3]> = (0..n).map(|_| [30.0 * rnd(), 30.0 * rnd(), 30.0 * rnd()]).collect();
        let (range, skin, near) = (6.0, 3.0, 1);
        let elements: Vec<usize> = (0..n).map(|j| j / 2).collect();
        let far = |j: usize, k: usize| elements[j].abs_diff(elements[k]) > near;
        let d = |a: &[f64; 3], b: &[f64; 3]| crate::geometry::vec3::distance(a, b);
        // The list at r0: far pairs within range + skin.
        let mut adj_ptr = vec![0];
        let mut adj = Vec::new();
        for j in 0..n {
            adj.extend((0..n).filter(|&k| k != j && far(j, k) && d(&r0[j], &r0[k]) < range + skin));
            adj_ptr.push(adj.len());
        }
        let ne = elements[n - 1] + 1;
        let runs = (0..ne).map(|e| (e.saturating_sub(near), (e + near).min(ne - 1))).collect();
        let cover =
            ListCoverage { offsets: vec![], elements: elements.clone(), runs, adj_ptr, adj: adj.clone(), range, skin };
        assert_eq!(cover.gap_at(&r0), skin, "every pair within range + skin is listed where it was built");
        for amplitude in [1.0, 3.0, 6.0] {
            let r: Vec<[f64; 3]> = r0.iter().map(|p| p.map(|v| v + amplitude * (rnd() - 0.5))).collect();
            let mut brute = skin;
            for j in 0..n {
                for k in j + 1..n {
                    let listed = adj[cover.adj_ptr[j]..cover.adj_ptr[j + 1]].contains(&k);
                    if far(j, k) && !listed && d(&r[j], &r[k]) < range + skin {
                        brute = brute.min(d(&r[j], &r[k]) - range);
                    }
                }
            }
            let gap = cover.gap_at(&r);
            assert!((gap - brute).abs() <= 1e-12, "amplitude {amplitude}: {gap} vs {brute}");
        }
    }
}
