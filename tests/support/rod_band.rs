//! Banded layout of the rod Jacobian for SUNDIALS' band solver (shared by
//! tests/sundials_rod.rs and benches/rod.rs).

/// Rows ordered by their first column (the end conditions, stored in node
/// 0's rows, move to the bottom) and the band widths of the reordered
/// Jacobian: the rod system is then banded for SUNDIALS' band solver. The
/// pattern's diagonal is skipped: AssembledSystem adds it as a pivot slot
/// even where it is structurally zero (the end conditions' rows).
pub fn band_layout(p: &rodkit::linalg::sparse::Pattern) -> (Vec<usize>, usize, usize) {
    let mut first = vec![usize::MAX; p.n];
    for j in 0..p.n {
        for k in p.col_ptr[j]..p.col_ptr[j + 1] {
            if p.row_idx[k] != j {
                first[p.row_idx[k]] = first[p.row_idx[k]].min(j);
            }
        }
    }
    // A row whose only entry is its diagonal stays where it is.
    for (i, f) in first.iter_mut().enumerate() {
        if *f == usize::MAX {
            *f = i;
        }
    }
    let mut order: Vec<usize> = (0..p.n).collect();
    order.sort_by_key(|&i| (first[i], i));
    let mut position = vec![0; p.n];
    for (new, &old) in order.iter().enumerate() {
        position[old] = new;
    }
    let (mut upper, mut lower) = (0usize, 0usize);
    for j in 0..p.n {
        for k in p.col_ptr[j]..p.col_ptr[j + 1] {
            // The artificial diagonal left of a row's first entry.
            if p.row_idx[k] == j && j < first[j] {
                continue;
            }
            let i = position[p.row_idx[k]];
            if j > i {
                upper = upper.max(j - i);
            } else {
                lower = lower.max(i - j);
            }
        }
    }
    (order, upper, lower)
}
