//! Which points of a curve are near each other in space: cell lists
//! (uniform cubes, deterministic order) and the closest non-neighbouring
//! pair — the pair searches of the electrostatic cutoff, a charged rod's
//! pair list, strand-crossing and self-contact tests.

use super::vec3::distance2;

/// Points binned in cubes of side `size` (deterministic: each cell lists
/// its points in index order).
pub struct CellList {
    size: f64,
    cells: std::collections::HashMap<(i64, i64, i64), Vec<usize>>,
}

impl CellList {
    pub fn new(r: &[[f64; 3]], size: f64) -> Self {
        let mut cells: std::collections::HashMap<(i64, i64, i64), Vec<usize>> = std::collections::HashMap::new();
        for (i, p) in r.iter().enumerate() {
            cells.entry(Self::key(p, size)).or_default().push(i);
        }
        CellList { size, cells }
    }

    fn key(p: &[f64; 3], size: f64) -> (i64, i64, i64) {
        ((p[0] / size).floor() as i64, (p[1] / size).floor() as i64, (p[2] / size).floor() as i64)
    }

    /// Every point in the 27 cells around `p` (its own and the neighbours,
    /// cell by cell, each cell's points in index order).
    fn visit_near(&self, p: &[f64; 3], mut visit: impl FnMut(usize)) {
        let (cx, cy, cz) = Self::key(p, self.size);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    if let Some(list) = self.cells.get(&(cx + dx, cy + dy, cz + dz)) {
                        list.iter().for_each(|&j| visit(j));
                    }
                }
            }
        }
    }

    /// Indices of the points within `radius` (≤ the cell size) of `p`,
    /// ascending.
    pub fn neighbours_within(&self, r: &[[f64; 3]], p: &[f64; 3], radius: f64, out: &mut Vec<usize>) {
        out.clear();
        self.visit_near(p, |j| {
            if distance2(p, &r[j]) < radius * radius {
                out.push(j);
            }
        });
        out.sort_unstable();
    }

    /// Indices j > i of points within `radius` (≤ the cell size) of point
    /// i, ascending.
    pub fn neighbours_after(&self, r: &[[f64; 3]], i: usize, radius: f64, out: &mut Vec<usize>) {
        out.clear();
        self.visit_near(&r[i], |j| {
            if j > i && distance2(&r[i], &r[j]) < radius * radius {
                out.push(j);
            }
        });
        out.sort_unstable();
    }
}

/// The closest pair (distance, i, j) among points closer than `radius` in
/// space whose arc lengths differ by more than `gap` (non-neighbours along
/// the strand), by cell lists: O(N). None when no such pair exists — a
/// strand crossing test with radius 2a (physics.md §3.2), or self-contact
/// with the rod's diameter.
pub fn closest_pair_within(r: &[[f64; 3]], s: &[f64], radius: f64, gap: f64) -> Option<(f64, usize, usize)> {
    if !(radius > 0.0 && radius.is_finite()) || r.len() < 2 {
        return None;
    }
    let cells = CellList::new(r, radius);
    let mut nb = Vec::new();
    let mut best: Option<(f64, usize, usize)> = None;
    for i in 0..r.len() {
        cells.neighbours_after(r, i, radius, &mut nb);
        for &j in &nb {
            if (s[j] - s[i]).abs() <= gap {
                continue;
            }
            let d = distance2(&r[i], &r[j]).sqrt();
            if best.is_none_or(|(bd, _, _)| d < bd) {
                best = Some((d, i, j));
            }
        }
    }
    best
}
