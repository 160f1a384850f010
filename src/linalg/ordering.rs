//! A bandwidth-reducing column ordering: reverse Cuthill–McKee on the
//! graph of A + Aᵀ (E. Cuthill & J. McKee, Proc. 24th ACM Nat. Conf.
//! (1969); reversed as A. George, "Computer implementation of the finite
//! element method" (1971); the start at a pseudo-peripheral node by George
//! & Liu's level-structure search, ACM TOMS 5, 284 (1979)).
//!
//! Why: a charged rod's plectoneme couples the unknowns of its two
//! interwound strands, up to ~n apart in the arc-length order. The natural
//! order's LU fills the whole profile between them (21.7× the matrix's
//! entries at 12 turns of the 1 kbp DNA scene, 854 ms a factorisation, 94 %
//! of a run); ordered by RCM the strands are interleaved and the matrix is
//! a band again, whatever the shape. COLAMD, tried on the same matrices,
//! filled more than the natural order (benches/README.md).
//!
//! Rows or columns with many entries (a continuation's dense border, a
//! phase condition's multiplier) would make every node a neighbour of
//! every other: they are left out of the graph and ordered last.

use super::sparse::Pattern;

/// A node with more neighbours than this is "dense" (ordered last).
fn dense_degree(n: usize) -> usize {
    (10.0 * (n as f64).sqrt()).max(64.0) as usize
}

/// The symmetric adjacency (A + Aᵀ, no diagonal) in compressed form, and
/// which nodes are dense.
fn adjacency(pattern: &Pattern, trailing: usize) -> (Vec<usize>, Vec<usize>, Vec<bool>) {
    let n = pattern.n;
    let mut degree = vec![0usize; n];
    for j in 0..n {
        for &i in &pattern.row_idx[pattern.col_ptr[j]..pattern.col_ptr[j + 1]] {
            if i != j {
                degree[i] += 1;
                degree[j] += 1;
            }
        }
    }
    let limit = dense_degree(n);
    let dense: Vec<bool> = degree.iter().enumerate().map(|(i, &d)| d > limit || i + trailing >= n).collect();
    let mut ptr = vec![0usize; n + 1];
    for j in 0..n {
        for &i in &pattern.row_idx[pattern.col_ptr[j]..pattern.col_ptr[j + 1]] {
            if i != j && !dense[i] && !dense[j] {
                ptr[i + 1] += 1;
                ptr[j + 1] += 1;
            }
        }
    }
    for k in 0..n {
        ptr[k + 1] += ptr[k];
    }
    let mut next = ptr.clone();
    let mut adj = vec![0usize; ptr[n]];
    for j in 0..n {
        for &i in &pattern.row_idx[pattern.col_ptr[j]..pattern.col_ptr[j + 1]] {
            if i != j && !dense[i] && !dense[j] {
                adj[next[i]] = j;
                next[i] += 1;
                adj[next[j]] = i;
                next[j] += 1;
            }
        }
    }
    // Duplicates (an entry and its transpose both present) are harmless to
    // the breadth-first search, but sorted, unique lists keep degrees true.
    let mut out_ptr = vec![0usize; n + 1];
    let mut out = Vec::with_capacity(adj.len());
    for i in 0..n {
        let list = &mut adj[ptr[i]..ptr[i + 1]];
        list.sort_unstable();
        let mut last = usize::MAX;
        for &v in list.iter() {
            if v != last {
                out.push(v);
                last = v;
            }
        }
        out_ptr[i + 1] = out.len();
    }
    (out_ptr, out, dense)
}

/// Breadth-first level structure from `root` over the component: the
/// nodes in BFS order into `order` (neighbours by increasing degree when
/// `sorted`); returns the number of levels and where the last one starts.
fn bfs(
    root: usize,
    ptr: &[usize],
    adj: &[usize],
    stamp: &mut [usize],
    pass: usize,
    sorted: bool,
    order: &mut Vec<usize>,
) -> (usize, usize) {
    order.clear();
    order.push(root);
    stamp[root] = pass;
    let (mut head, mut levels, mut last) = (0, 0, 0);
    while head < order.len() {
        let end = order.len();
        levels += 1;
        last = head;
        while head < end {
            let v = order[head];
            head += 1;
            let start = order.len();
            for &w in &adj[ptr[v]..ptr[v + 1]] {
                if stamp[w] != pass {
                    stamp[w] = pass;
                    order.push(w);
                }
            }
            if sorted {
                order[start..].sort_by_key(|&w| (ptr[w + 1] - ptr[w], w));
            }
        }
    }
    (levels, last)
}

/// The reverse Cuthill–McKee order of `pattern`'s columns: `perm[k]` is
/// the column placed k-th. The last `trailing` unknowns (a continuation's
/// parameter, a phase condition's multiplier: their equations reach the
/// whole system, as a μ coupled to 362 unknowns spread over a 300 bp
/// plectoneme's 1575) and other dense rows/columns (see [`dense_degree`])
/// last, in their natural order; each connected component from a
/// pseudo-peripheral node.
pub fn reverse_cuthill_mckee(pattern: &Pattern, trailing: usize) -> Vec<usize> {
    let n = pattern.n;
    let (ptr, adj, dense) = adjacency(pattern, trailing);
    let degree = |v: usize| ptr[v + 1] - ptr[v];
    // stamp[v] == pass: v seen in the current search; done: placed.
    let mut stamp = vec![0usize; n];
    let mut done = vec![false; n];
    let mut pass = 0;
    let mut order = Vec::with_capacity(n);
    let mut perm = Vec::with_capacity(n);
    for seed in 0..n {
        if done[seed] || dense[seed] {
            continue;
        }
        // George–Liu: from a node of the last level of the current root's
        // structure, of least degree, while the depth grows.
        let mut root = seed;
        pass += 1;
        let (mut levels, mut last) = bfs(root, &ptr, &adj, &mut stamp, pass, false, &mut order);
        for _ in 0..8 {
            let candidate = *order[last..].iter().min_by_key(|&&v| (degree(v), v)).expect("non-empty");
            pass += 1;
            let (depth, next_last) = bfs(candidate, &ptr, &adj, &mut stamp, pass, false, &mut order);
            if depth <= levels {
                break;
            }
            (root, levels, last) = (candidate, depth, next_last);
        }
        pass += 1;
        bfs(root, &ptr, &adj, &mut stamp, pass, true, &mut order);
        for &v in &order {
            done[v] = true;
        }
        perm.extend(order.iter().rev());
    }
    perm.extend((0..n).filter(|&v| dense[v]));
    debug_assert_eq!(perm.len(), n);
    perm
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The half-bandwidth of `pattern` (off the dense rows/columns) with its
    /// columns and rows both ordered by `perm` (None: natural), the last
    /// `trailing` left out.
    fn half_bandwidth(pattern: &Pattern, perm: Option<&[usize]>, trailing: usize) -> usize {
        let n = pattern.n;
        let (_, _, dense) = adjacency(pattern, trailing);
        let mut pos: Vec<usize> = (0..n).collect();
        if let Some(p) = perm {
            for (k, &j) in p.iter().enumerate() {
                pos[j] = k;
            }
        }
        let mut b = 0;
        for j in 0..n {
            for &i in &pattern.row_idx[pattern.col_ptr[j]..pattern.col_ptr[j + 1]] {
                if !dense[i] && !dense[j] {
                    b = b.max(pos[i].abs_diff(pos[j]));
                }
            }
        }
        b
    }

    /// A "ladder" of two chains of m nodes, chain A in natural order
    /// 0..m, chain B in m..2m with node m + k coupled to A's node m − 1 − k
    /// (two strands of a hairpin, folded back): in natural order the
    /// half-bandwidth is 2m − 1; interleaved by RCM it is ≤ 3 (each level
    /// holds one node of each strand). Plus a dense last row and column
    /// (a border), which must be ordered last.
    #[test]
    fn rcm_interleaves_a_folded_chain_and_puts_the_border_last() {
        let m = 200;
        let n = 2 * m + 1;
        let mut e = Vec::new();
        for i in 0..2 * m {
            e.push((i, i));
            if i + 1 < 2 * m {
                e.push((i, i + 1));
                e.push((i + 1, i));
            }
        }
        for k in 0..m {
            e.push((m + k, m - 1 - k));
            e.push((m - 1 - k, m + k));
        }
        for i in 0..n {
            e.push((i, n - 1));
            e.push((n - 1, i));
        }
        let p = Pattern::from_entries(n, e);
        let perm = reverse_cuthill_mckee(&p, 0);
        let mut sorted = perm.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..n).collect::<Vec<_>>(), "a permutation");
        assert_eq!(perm[n - 1], n - 1, "the dense border last");
        assert_eq!(half_bandwidth(&p, None, 0), 2 * m - 1);
        assert!(half_bandwidth(&p, Some(&perm), 0) <= 3, "RCM band {}", half_bandwidth(&p, Some(&perm), 0));
    }
}
