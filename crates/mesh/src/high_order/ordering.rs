//! Node orders of Lagrange quads and lines in the file formats, written from
//! the formats' documentation.
//!
//! Each ordering is a list `perm` with `perm[k]` = the tensor index
//! (`i + (N + 1) j`, see [`super::HighOrderQuadMesh`]) of the format's node
//! `k`: a writer emits `tensor[perm[k]]` for `k = 0, 1, …`, a reader puts the
//! file's node `k` at `tensor[perm[k]]`.
//!
//! - **Gmsh** (MSH quads of types 3, 10, 36, 37, 38, 47–51): the 4 corners
//!   counter-clockwise from `(0, 0)`, then the nodes inside each edge, edges
//!   0→1, 1→2, 2→3, 3→0 each walked in that direction, then the interior
//!   nodes as an order-(N − 2) quad in the same convention, recursively (an
//!   order-0 quad is its single centre node). Lines (types 1, 8, 26, 27, 28,
//!   62–66): the two ends, then the inner nodes from the first end.
//! - **VTK** (`VTK_LAGRANGE_QUADRILATERAL` = 70): the 4 corners, then the
//!   edges (0,1), (1,2), (3,2), (0,3), each in increasing parameter (so the
//!   last two run opposite to Gmsh's), then the interior row by row, `i`
//!   fastest.
//!
//! The two first differ at N = 3.

use super::{check_order, HighOrderError, MAX_ORDER};

/// VTK's cell type of an arbitrary-order Lagrange quadrilateral.
pub const VTK_LAGRANGE_QUADRILATERAL: u8 = 70;

/// MSH element types of the Lagrange quads of order 1..=10 (complete, with interior nodes).
const GMSH_QUAD_TYPES: [i32; MAX_ORDER] = [3, 10, 36, 37, 38, 47, 48, 49, 50, 51];
/// MSH element types of the Lagrange lines of order 1..=10.
const GMSH_LINE_TYPES: [i32; MAX_ORDER] = [1, 8, 26, 27, 28, 62, 63, 64, 65, 66];

/// The MSH element type of a Lagrange quad of `order` (3 for order 1, 10 for 2, …).
pub fn gmsh_quad_type(order: usize) -> Result<i32, HighOrderError> {
    check_order(order)?;
    Ok(GMSH_QUAD_TYPES[order - 1])
}

/// The MSH element type of a Lagrange line of `order` (1 for order 1, 8 for 2, …).
pub fn gmsh_line_type(order: usize) -> Result<i32, HighOrderError> {
    check_order(order)?;
    Ok(GMSH_LINE_TYPES[order - 1])
}

/// The order of MSH quad type `ty`, `None` when it is not a complete Lagrange quad.
pub fn order_of_gmsh_quad(ty: i32) -> Option<usize> {
    GMSH_QUAD_TYPES.iter().position(|&t| t == ty).map(|k| k + 1)
}

/// The order of MSH line type `ty`, `None` when it is not a Lagrange line.
pub fn order_of_gmsh_line(ty: i32) -> Option<usize> {
    GMSH_LINE_TYPES.iter().position(|&t| t == ty).map(|k| k + 1)
}

/// Gmsh's quad node order for `order`: `perm[k]` is the tensor index of
/// Gmsh's node `k` (see the module docs).
pub fn gmsh_quad_ordering(order: usize) -> Result<Vec<usize>, HighOrderError> {
    check_order(order)?;
    let mut perm = Vec::with_capacity((order + 1) * (order + 1));
    // rings from the outside in: the ring of `lo..=hi` is itself a quad of
    // order hi − lo, laid out corners first, then its edges
    let (mut lo, mut hi) = (0usize, order);
    let index = |i: usize, j: usize| i + (order + 1) * j;
    while lo <= hi {
        if lo == hi {
            perm.push(index(lo, lo));
            break;
        }
        perm.extend([index(lo, lo), index(hi, lo), index(hi, hi), index(lo, hi)]);
        let inner = lo + 1..hi;
        perm.extend(inner.clone().map(|i| index(i, lo))); // 0 → 1
        perm.extend(inner.clone().map(|j| index(hi, j))); // 1 → 2
        perm.extend(inner.clone().rev().map(|i| index(i, hi))); // 2 → 3
        perm.extend(inner.rev().map(|j| index(lo, j))); // 3 → 0
        lo += 1;
        hi -= 1;
    }
    Ok(perm)
}

/// Gmsh's line node order for `order`: `perm[k]` is the position along the
/// line (0 = first end, `order` = last end) of Gmsh's node `k`.
pub fn gmsh_line_ordering(order: usize) -> Result<Vec<usize>, HighOrderError> {
    check_order(order)?;
    let mut perm = vec![0, order];
    perm.extend(1..order);
    Ok(perm)
}

/// VTK's Lagrange quadrilateral node order for `order`: `perm[k]` is the
/// tensor index of VTK's point `k` (see the module docs).
pub fn vtk_quad_ordering(order: usize) -> Result<Vec<usize>, HighOrderError> {
    check_order(order)?;
    let n = order;
    let index = |i: usize, j: usize| i + (n + 1) * j;
    let mut perm = vec![index(0, 0), index(n, 0), index(n, n), index(0, n)];
    perm.extend((1..n).map(|i| index(i, 0))); // (0,1)
    perm.extend((1..n).map(|j| index(n, j))); // (1,2)
    perm.extend((1..n).map(|i| index(i, n))); // (3,2)
    perm.extend((1..n).map(|j| index(0, j))); // (0,3)
    for j in 1..n {
        perm.extend((1..n).map(|i| index(i, j)));
    }
    Ok(perm)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn is_permutation(perm: &[usize], len: usize) -> bool {
        let mut seen = vec![false; len];
        perm.len() == len
            && perm
                .iter()
                .all(|&k| k < len && !std::mem::replace(&mut seen[k], true))
    }

    #[test]
    fn every_ordering_is_a_permutation_for_orders_1_to_10() {
        for n in 1..=MAX_ORDER {
            let k = (n + 1) * (n + 1);
            assert!(
                is_permutation(&gmsh_quad_ordering(n).unwrap(), k),
                "gmsh quad {n}"
            );
            assert!(
                is_permutation(&vtk_quad_ordering(n).unwrap(), k),
                "vtk quad {n}"
            );
            assert!(
                is_permutation(&gmsh_line_ordering(n).unwrap(), n + 1),
                "line {n}"
            );
            // both start with the four corners, counter-clockwise from (0, 0)
            let corners = [0, n, k - 1, k - 1 - n];
            assert_eq!(gmsh_quad_ordering(n).unwrap()[..4], corners);
            assert_eq!(vtk_quad_ordering(n).unwrap()[..4], corners);
        }
    }

    #[test]
    fn order_3_matches_the_hand_tables() {
        // tensor index i + 4 j:
        //  12 13 14 15
        //   8  9 10 11
        //   4  5  6  7
        //   0  1  2  3
        // Gmsh: corners, 0→1, 1→2, 2→3 (i falling), 3→0 (j falling), inner quad
        let gmsh = [0, 3, 15, 12, 1, 2, 7, 11, 14, 13, 8, 4, 5, 6, 10, 9];
        // VTK: corners, (0,1), (1,2), (3,2) (i rising), (0,3) (j rising), rows
        let vtk = [0, 3, 15, 12, 1, 2, 7, 11, 13, 14, 4, 8, 5, 6, 9, 10];
        assert_eq!(gmsh_quad_ordering(3).unwrap(), gmsh);
        assert_eq!(vtk_quad_ordering(3).unwrap(), vtk);
        assert_eq!(gmsh_line_ordering(3).unwrap(), [0, 3, 1, 2]);
    }

    #[test]
    fn low_and_recursive_orders_match_hand_tables() {
        assert_eq!(gmsh_quad_ordering(1).unwrap(), [0, 1, 3, 2]);
        assert_eq!(vtk_quad_ordering(1).unwrap(), [0, 1, 3, 2]);
        // order 2 (3×3): the centre last; VTK and Gmsh agree
        let two = [0, 2, 8, 6, 1, 5, 7, 3, 4];
        assert_eq!(gmsh_quad_ordering(2).unwrap(), two);
        assert_eq!(vtk_quad_ordering(2).unwrap(), two);
        // order 4 (5×5): the inner ring is an order-2 quad, its centre last
        let g4 = gmsh_quad_ordering(4).unwrap();
        assert_eq!(g4[4..16], [1, 2, 3, 9, 14, 19, 23, 22, 21, 15, 10, 5]);
        assert_eq!(g4[16..], [6, 8, 18, 16, 7, 13, 17, 11, 12]);
        let v4 = vtk_quad_ordering(4).unwrap();
        assert_eq!(v4[10..16], [21, 22, 23, 5, 10, 15]);
        assert_eq!(v4[16..], [6, 7, 8, 11, 12, 13, 16, 17, 18]);
        assert_eq!(gmsh_line_ordering(1).unwrap(), [0, 1]);
        assert_eq!(gmsh_line_ordering(5).unwrap(), [0, 5, 1, 2, 3, 4]);
    }

    #[test]
    fn types_and_orders_map_both_ways() {
        for n in 1..=MAX_ORDER {
            assert_eq!(order_of_gmsh_quad(gmsh_quad_type(n).unwrap()), Some(n));
            assert_eq!(order_of_gmsh_line(gmsh_line_type(n).unwrap()), Some(n));
            // the MSH node counts agree with the orders
            let quad = crate::msh::nodes_per_element(gmsh_quad_type(n).unwrap());
            assert_eq!(quad, Some((n + 1) * (n + 1)));
            let line = crate::msh::nodes_per_element(gmsh_line_type(n).unwrap());
            assert_eq!(line, Some(n + 1));
        }
        assert_eq!(gmsh_quad_type(5), Ok(38));
        assert_eq!(gmsh_line_type(10), Ok(66));
        assert_eq!(order_of_gmsh_quad(2), None);
        assert_eq!(order_of_gmsh_line(15), None);
        for bad in [0, 11] {
            assert_eq!(gmsh_quad_ordering(bad), Err(HighOrderError::BadOrder(bad)));
            assert_eq!(vtk_quad_ordering(bad), Err(HighOrderError::BadOrder(bad)));
            assert_eq!(gmsh_line_ordering(bad), Err(HighOrderError::BadOrder(bad)));
            assert_eq!(gmsh_quad_type(bad), Err(HighOrderError::BadOrder(bad)));
            assert_eq!(gmsh_line_type(bad), Err(HighOrderError::BadOrder(bad)));
        }
    }
}
