//! Fill-reducing elimination order for the solid: nested dissection of the 27-node lattice, the
//! 3-D form of [`crate::fe::ordering`].
//!
//! No element crosses a lattice plane of even index (an element boundary), so such a plane of
//! nodes separates the block into two halves that never couple. Numbering each half recursively
//! and the separator last is George's nested dissection (George 1973, SIAM J. Numer. Anal. 10;
//! for 3-D grids O(n^2) flops and O(n^4/3) fill, the optimum order of a 3-D grid). Cutting
//! across the longest side keeps the separators small; a thin plate is cut only across its
//! plane, so its factor behaves like the 2-D one with node blocks as deep as the thickness.

use crate::fe::solid::dofs::SolidDofs;
use crate::fe::solid::grid::HexGrid;

/// Blocks of at most this many lattice nodes are numbered directly \[choice\].
const LEAF_NODES: usize = 64;

/// Lattice node indices (`I + nxl (J + nyl K)`) of an `nxl x nyl x nzl` lattice in nested-dissection
/// order; every node once.
pub fn nested_dissection(lattice: [usize; 3]) -> Vec<usize> {
    nested_dissection_between(lattice, &Default::default())
}

/// [`nested_dissection`] cutting only at planes no element crosses: `crossed[d][m]` marks the
/// lattice planes along axis `d` that a merged brick spans ([`HexGrid::merge`]); an empty list
/// crosses none.
pub fn nested_dissection_between(lattice: [usize; 3], crossed: &[Vec<bool>; 3]) -> Vec<usize> {
    let mut out = Vec::with_capacity(lattice.iter().product());
    dissect(
        lattice,
        [(0, lattice[0]), (0, lattice[1]), (0, lattice[2])],
        crossed,
        &mut out,
    );
    out
}

/// The even index nearest the middle of [lo, hi) with nodes on both sides and no element
/// across, if any.
fn cut(lo: usize, hi: usize, crossed: &[bool]) -> Option<usize> {
    let mid = (lo + hi - 1) / 2;
    let ok = |m: usize| {
        m.is_multiple_of(2) && m > lo && m + 1 < hi && !crossed.get(m).copied().unwrap_or(false)
    };
    if crossed.is_empty() {
        return [mid, mid + 1, mid.wrapping_sub(1)]
            .into_iter()
            .find(|&m| ok(m));
    }
    // The nearest clean plane to the middle.
    (0..hi - lo)
        .flat_map(|k| [mid.wrapping_sub(k), mid + k])
        .find(|&m| m < hi && ok(m))
}

/// Lattice planes each merged brick of `grid` spans, by axis.
pub fn crossed_planes(grid: &HexGrid) -> [Vec<bool>; 3] {
    let bricks = grid.merged_bricks();
    if bricks.is_empty() {
        return Default::default();
    }
    let mut out = grid.lattice().map(|n| vec![false; n]);
    for (_, layers) in bricks {
        for d in 0..3 {
            for c in &mut out[d][layers[d][0] + 1..layers[d][2]] {
                *c = true;
            }
        }
    }
    out
}

fn dissect(
    lat: [usize; 3],
    b: [(usize, usize); 3],
    crossed: &[Vec<bool>; 3],
    out: &mut Vec<usize>,
) {
    let size = b.map(|(lo, hi)| hi.saturating_sub(lo));
    if size.contains(&0) {
        return;
    }
    let mut dims = [0, 1, 2];
    dims.sort_by_key(|&d| std::cmp::Reverse(size[d]));
    let split = if size.iter().product::<usize>() <= LEAF_NODES {
        None
    } else {
        dims.iter()
            .find_map(|&d| cut(b[d].0, b[d].1, &crossed[d]).map(|m| (d, m)))
    };
    let Some((d, m)) = split else {
        for k in b[2].0..b[2].1 {
            for j in b[1].0..b[1].1 {
                out.extend((b[0].0..b[0].1).map(|i| i + lat[0] * (j + lat[1] * k)));
            }
        }
        return;
    };
    let mut lo = b;
    lo[d].1 = m;
    let mut hi = b;
    hi[d].0 = m + 1;
    let mut sep = b;
    sep[d] = (m, m + 1);
    dissect(lat, lo, crossed, out);
    dissect(lat, hi, crossed, out);
    // The separator plane: number it row by row (it is eliminated last, as a dense block).
    for k in sep[2].0..sep[2].1 {
        for j in sep[1].0..sep[1].1 {
            out.extend((sep[0].0..sep[0].1).map(|i| i + lat[0] * (j + lat[1] * k)));
        }
    }
}

/// The node order expanded to free dofs: `fwd[new] = old` free index; nodes without free dofs
/// are skipped.
pub fn free_dof_order(dofs: &SolidDofs, grid: &HexGrid) -> Vec<usize> {
    let mut fwd = Vec::with_capacity(dofs.n_free());
    for node in nested_dissection_between(grid.lattice(), &crossed_planes(grid)) {
        fwd.extend(
            (0..3)
                .map(|d| dofs.free_index[3 * node + d])
                .filter(|&f| f < dofs.free_dofs.len()),
        );
    }
    fwd
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_node_once() {
        for lat in [[3, 3, 3], [5, 9, 3], [21, 17, 5], [9, 9, 9], [41, 3, 3]] {
            let mut o = nested_dissection(lat);
            assert_eq!(o.len(), lat.iter().product::<usize>());
            o.sort_unstable();
            assert!(o.iter().enumerate().all(|(k, &n)| k == n), "{lat:?}");
        }
    }

    /// The top-level separator is an even-index plane across the longest side, and every node on
    /// one side of it is numbered before every node on the other.
    #[test]
    fn halves_are_separated() {
        let lat = [21, 9, 5];
        let o = nested_dissection(lat);
        let mut pos = vec![0; o.len()];
        for (k, &n) in o.iter().enumerate() {
            pos[n] = k;
        }
        let plane = lat[1] * lat[2];
        let sep = &o[o.len() - plane..];
        let i_of = |n: usize| n % lat[0];
        let m = i_of(sep[0]);
        assert!(
            m % 2 == 0 && sep.iter().all(|&n| i_of(n) == m),
            "separator at i = {m}"
        );
        let left = (0..o.len()).filter(|&n| i_of(n) < m).map(|n| pos[n]).max();
        let right = (0..o.len()).filter(|&n| i_of(n) > m).map(|n| pos[n]).min();
        assert!(left.unwrap() < right.unwrap());
    }
}
