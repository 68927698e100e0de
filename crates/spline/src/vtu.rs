//! VTU output: every Bézier element of every patch as one
//! `VTK_BEZIER_QUADRILATERAL` (cell type 77) with its `(p+1)(q+1)` control
//! points, the degrees in the `HigherOrderDegrees` cell data, and the
//! weights (all 1) as the `RationalWeights` point data.
//!
//! Node order (the VTK convention for Lagrange/Bézier quadrilaterals): the
//! corners (0,0), (1,0), (1,1), (0,1); then the edge nodes bottom (+s),
//! right (+t), top (+s), left (+t); then the interior row by row (s fastest).

use crate::atomic::write_atomically;
use crate::bezier::extract_bezier;
use crate::error::Result;
use crate::multipatch::Multipatch;
use std::fmt::Write as _;
use std::path::Path;

/// The VTK cell type of a Bézier quadrilateral.
pub const VTK_BEZIER_QUADRILATERAL: u8 = 77;

/// The local (a, b) node positions of a degree (p, q) element in VTK order.
pub fn vtk_node_order(p: usize, q: usize) -> Vec<(usize, usize)> {
    let mut out = vec![(0, 0), (p, 0), (p, q), (0, q)];
    out.extend((1..p).map(|a| (a, 0)));
    out.extend((1..q).map(|b| (p, b)));
    out.extend((1..p).map(|a| (a, q)));
    out.extend((1..q).map(|b| (0, b)));
    for b in 1..q {
        out.extend((1..p).map(|a| (a, b)));
    }
    out
}

/// The multipatch as VTU (ASCII) text: one cell per Bézier element, points
/// not shared between cells. A `Patch` cell array names each cell's patch.
pub fn to_vtu_string(mp: &Multipatch) -> Result<String> {
    let mut points: Vec<[f64; 3]> = Vec::new();
    let mut conn: Vec<usize> = Vec::new();
    let mut offsets: Vec<usize> = Vec::new();
    let mut degrees: Vec<(usize, usize)> = Vec::new();
    let mut patch_of: Vec<usize> = Vec::new();
    for k in 0..mp.patches().len() {
        for el in extract_bezier(&mp.patch(k)?)? {
            let (p, q) = el.degree;
            for (a, b) in vtk_node_order(p, q) {
                conn.push(points.len());
                points.push(el.control[b * (p + 1) + a]);
            }
            offsets.push(conn.len());
            degrees.push((p, q));
            patch_of.push(k);
        }
    }
    let mut s = String::new();
    let w = &mut s;
    // Writing to a String cannot fail.
    let _ = writeln!(w, "<?xml version=\"1.0\"?>");
    let _ = writeln!(
        w,
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\">"
    );
    let _ = writeln!(w, "<UnstructuredGrid>");
    let _ = writeln!(
        w,
        "<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">",
        points.len(),
        offsets.len()
    );
    let _ = writeln!(w, "<PointData RationalWeights=\"RationalWeights\">");
    let _ = writeln!(
        w,
        "<DataArray type=\"Float64\" Name=\"RationalWeights\" format=\"ascii\">"
    );
    for _ in &points {
        let _ = write!(w, "1 ");
    }
    let _ = writeln!(w, "\n</DataArray>\n</PointData>");
    let _ = writeln!(w, "<CellData HigherOrderDegrees=\"HigherOrderDegrees\">");
    let _ = writeln!(w, "<DataArray type=\"Float64\" Name=\"HigherOrderDegrees\" NumberOfComponents=\"3\" format=\"ascii\">");
    for (p, q) in &degrees {
        let _ = write!(w, "{p} {q} 0 ");
    }
    let _ = writeln!(w, "\n</DataArray>");
    let _ = writeln!(
        w,
        "<DataArray type=\"Int32\" Name=\"Patch\" format=\"ascii\">"
    );
    for k in &patch_of {
        let _ = write!(w, "{k} ");
    }
    let _ = writeln!(w, "\n</DataArray>\n</CellData>");
    let _ = writeln!(
        w,
        "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">"
    );
    for p in &points {
        let _ = writeln!(w, "{} {} {}", p[0], p[1], p[2]);
    }
    let _ = writeln!(w, "</DataArray>\n</Points>\n<Cells>");
    let _ = writeln!(
        w,
        "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">"
    );
    for c in &conn {
        let _ = write!(w, "{c} ");
    }
    let _ = writeln!(
        w,
        "\n</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">"
    );
    for o in &offsets {
        let _ = write!(w, "{o} ");
    }
    let _ = writeln!(
        w,
        "\n</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">"
    );
    for _ in &offsets {
        let _ = write!(w, "{VTK_BEZIER_QUADRILATERAL} ");
    }
    let _ = writeln!(
        w,
        "\n</DataArray>\n</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>"
    );
    Ok(s)
}

/// Writes the multipatch to `path` as VTU (atomically).
pub fn write_vtu(path: &Path, mp: &Multipatch) -> Result<()> {
    let text = to_vtu_string(mp)?;
    Ok(write_atomically(path, text.as_bytes())?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cubic_node_order_is_vtk() {
        let o = vtk_node_order(3, 3);
        assert_eq!(o.len(), 16);
        assert_eq!(&o[..4], &[(0, 0), (3, 0), (3, 3), (0, 3)]);
        assert_eq!(
            &o[4..12],
            &[
                (1, 0),
                (2, 0),
                (3, 1),
                (3, 2),
                (1, 3),
                (2, 3),
                (0, 1),
                (0, 2)
            ]
        );
        assert_eq!(&o[12..], &[(1, 1), (2, 1), (1, 2), (2, 2)]);
        let mut sorted = o.clone();
        sorted.sort();
        sorted.dedup();
        assert_eq!(sorted.len(), 16);
    }
}
