//! VTK XML UnstructuredGrid (`.vtu`) writer, ASCII, readable by ParaView,
//! VisIt and meshio.
//!
//! Cells are the quads (`VTK_QUAD` = 9) followed by the triangles
//! (`VTK_TRIANGLE` = 5), in mesh order. Arrays written:
//! - point data `class_dim` (Int32): dimension of the model entity the node
//!   lies on (0 corner, 1 curve, 2 face, −1 unclassified);
//! - point data `class_tag` (Int32): that entity's id + 1 (the tag MSH files
//!   use), 0 when unclassified;
//! - point data `valence` (Int32): number of quads at the node;
//! - cell data `cad_face` (Int32): the CAD face id + 1;
//! - cell data `SICN` (Float64), when given: the quad's value; triangles and
//!   non-finite values get [`NO_VALUE`] (VTK's ASCII reader cannot read NaN).
//!
//! [`write_field_vtu`] writes a cross field on its background triangulation
//! ([`CrossFieldMesh`]) with the same XML helpers, in one piece: the
//! triangles (`VTK_TRIANGLE`), then one `VTK_VERTEX` cell per singularity
//! (its point appended after the triangles' nodes). Cell data:
//! - `cad_face` (Int32): the CAD face id + 1;
//! - `cross` (Float64, 3 components): one unit branch of the cross of each
//!   triangle (for glyphs; the other branch is its rotation by 90° about the
//!   normal), zero where the field vanishes and on singularity cells;
//! - `size` (Float64), when the field has one: the size map, [`NO_VALUE`] on
//!   singularity cells and where unknown;
//! - `singularity_index` (Int32): 0 on triangles, the index (±1) on
//!   singularity cells (a Threshold on it isolates the singularities).
//!
//! [`write_high_order_vtu`] writes a [`HighOrderQuadMesh`] as Lagrange
//! quadrilaterals (`VTK_LAGRANGE_QUADRILATERAL` = 70) with point data
//! `class_dim`, `class_tag` and cell data `cad_face`, `jacobian_ratio`.
//!
//! One piece, not two, because meshio 5.3 keeps only the cells of the last piece.

use std::io::{self, Write};
use std::path::{Path, PathBuf};

use geometry::vec3::Vec3;

use crate::atomic::write_atomically;
use crate::field::CrossFieldMesh;
use crate::high_order::{
    vtk_quad_ordering, HighOrderError, HighOrderQuadMesh, VTK_LAGRANGE_QUADRILATERAL,
};
use crate::quadmesh::{NodeClass, QuadMesh};

/// The VTK cell type of a linear quad.
pub const VTK_QUAD: u8 = 9;
/// The VTK cell type of a linear triangle.
pub const VTK_TRIANGLE: u8 = 5;
/// The VTK cell type of a single point.
pub const VTK_VERTEX: u8 = 1;
/// The `SICN` value written for cells without one (triangles, non-finite input).
pub const NO_VALUE: f64 = -2.0;

/// Why a `.vtu` file could not be written.
#[derive(Debug, thiserror::Error)]
pub enum VtuError {
    /// The mesh or the values are inconsistent; nothing was written.
    #[error("cannot write {}: {reason}", path.display())]
    Invalid {
        /// The file that was to be written.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// Writing failed; nothing was left at `path`.
    #[error("cannot write {}: {source}", path.display())]
    Io {
        /// The file that could not be written.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: io::Error,
    },
}

/// Checks what every writer and the renderer rely on: per-node and
/// per-element arrays of matching lengths, element indices in range, finite
/// coordinates. Returns a description of the first problem.
pub(crate) fn check_mesh(mesh: &QuadMesh) -> Result<(), String> {
    let n = mesh.nodes.len();
    if mesh.node_class.len() != n {
        return Err(format!(
            "{} node classifications for {} nodes",
            mesh.node_class.len(),
            n
        ));
    }
    if mesh.quad_face.len() != mesh.quads.len() {
        return Err(format!(
            "{} quad faces for {} quads",
            mesh.quad_face.len(),
            mesh.quads.len()
        ));
    }
    if mesh.triangle_face.len() != mesh.triangles.len() {
        return Err(format!(
            "{} triangle faces for {} triangles",
            mesh.triangle_face.len(),
            mesh.triangles.len()
        ));
    }
    if let Some(i) = mesh
        .nodes
        .iter()
        .position(|p| !p.iter().all(|c| c.is_finite()))
    {
        return Err(format!(
            "node {i} has non-finite coordinates {:?}",
            mesh.nodes[i]
        ));
    }
    if let Some(i) = mesh
        .quads
        .iter()
        .position(|q| q.iter().any(|&v| v as usize >= n))
    {
        return Err(format!(
            "quad {i} {:?} refers to a node beyond the {n} nodes",
            mesh.quads[i]
        ));
    }
    if let Some(i) = mesh
        .triangles
        .iter()
        .position(|t| t.iter().any(|&v| v as usize >= n))
    {
        return Err(format!(
            "triangle {i} {:?} refers to a node beyond the {n} nodes",
            mesh.triangles[i]
        ));
    }
    Ok(())
}

/// Classification of a node as `(dimension, tag)`: see the module docs.
fn class_dim_tag(c: &NodeClass) -> (i32, i64) {
    match c {
        NodeClass::Corner(id) => (0, id.0 as i64 + 1),
        NodeClass::Curve(id, _) => (1, id.0 as i64 + 1),
        NodeClass::Face(id, _) => (2, id.0 as i64 + 1),
        NodeClass::Unclassified => (-1, 0),
    }
}

/// Writes `mesh` to `path` as an ASCII VTK UnstructuredGrid. `sicn`, when
/// given, must hold one value per quad. The file is written atomically.
pub fn write_vtu(mesh: &QuadMesh, sicn: Option<&[f64]>, path: &Path) -> Result<(), VtuError> {
    let invalid = |reason: String| VtuError::Invalid {
        path: path.to_path_buf(),
        reason,
    };
    check_mesh(mesh).map_err(invalid)?;
    if let Some(v) = sicn {
        if v.len() != mesh.quads.len() {
            return Err(invalid(format!(
                "{} SICN values for {} quads",
                v.len(),
                mesh.quads.len()
            )));
        }
    }
    write_atomically(path, |w| write_body(mesh, sicn, w)).map_err(|source| VtuError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Writes values `per_line` to a line, each line indented.
fn write_values<W: Write, T: std::fmt::Display>(
    w: &mut W,
    values: impl Iterator<Item = T>,
    per_line: usize,
) -> io::Result<()> {
    let mut k = 0;
    for v in values {
        if k == 0 {
            w.write_all(b"         ")?;
        } else {
            w.write_all(b" ")?;
        }
        write!(w, "{v}")?;
        k += 1;
        if k == per_line {
            w.write_all(b"\n")?;
            k = 0;
        }
    }
    if k != 0 {
        w.write_all(b"\n")?;
    }
    Ok(())
}

/// Opens a `DataArray` element.
fn open_array<W: Write>(w: &mut W, ty: &str, name: &str, components: usize) -> io::Result<()> {
    writeln!(w, "        <DataArray type=\"{ty}\" Name=\"{name}\" NumberOfComponents=\"{components}\" format=\"ascii\">")
}

/// Closes a `DataArray` element.
fn close_array<W: Write>(w: &mut W) -> io::Result<()> {
    writeln!(w, "        </DataArray>")
}

/// The XML prologue up to the opening `UnstructuredGrid` tag.
fn write_header<W: Write>(w: &mut W) -> io::Result<()> {
    writeln!(w, "<?xml version=\"1.0\"?>")?;
    writeln!(w, "<!-- written by Quadrille -->")?;
    writeln!(w, "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">")?;
    writeln!(w, "  <UnstructuredGrid>")
}

/// Closes what [`write_header`] opened.
fn write_footer<W: Write>(w: &mut W) -> io::Result<()> {
    writeln!(w, "  </UnstructuredGrid>")?;
    writeln!(w, "</VTKFile>")
}

/// Opens a `Piece` element.
fn open_piece<W: Write>(w: &mut W, points: usize, cells: usize) -> io::Result<()> {
    writeln!(
        w,
        "    <Piece NumberOfPoints=\"{points}\" NumberOfCells=\"{cells}\">"
    )
}

/// The `Points` element.
fn write_points<'a, W: Write>(w: &mut W, points: impl Iterator<Item = &'a Vec3>) -> io::Result<()> {
    writeln!(w, "      <Points>")?;
    open_array(w, "Float64", "Points", 3)?;
    write_values(w, points.flat_map(|p| p.iter().copied()), 6)?;
    close_array(w)?;
    writeln!(w, "      </Points>")
}

/// The `Cells` element and the end of the piece: connectivity, end offsets
/// and VTK cell types.
fn write_cells_and_close_piece<W: Write>(
    w: &mut W,
    connectivity: impl Iterator<Item = u32>,
    offsets: impl Iterator<Item = usize>,
    types: impl Iterator<Item = u8>,
) -> io::Result<()> {
    writeln!(w, "      <Cells>")?;
    open_array(w, "Int64", "connectivity", 1)?;
    write_values(w, connectivity, 12)?;
    close_array(w)?;
    open_array(w, "Int64", "offsets", 1)?;
    write_values(w, offsets, 12)?;
    close_array(w)?;
    open_array(w, "UInt8", "types", 1)?;
    write_values(w, types, 30)?;
    close_array(w)?;
    writeln!(w, "      </Cells>")?;
    writeln!(w, "    </Piece>")
}

/// The XML document.
fn write_body<W: Write>(mesh: &QuadMesh, sicn: Option<&[f64]>, w: &mut W) -> io::Result<()> {
    let ncells = mesh.quads.len() + mesh.triangles.len();
    write_header(w)?;
    open_piece(w, mesh.nodes.len(), ncells)?;

    writeln!(w, "      <PointData Scalars=\"valence\">")?;
    open_array(w, "Int32", "class_dim", 1)?;
    write_values(w, mesh.node_class.iter().map(|c| class_dim_tag(c).0), 20)?;
    close_array(w)?;
    open_array(w, "Int32", "class_tag", 1)?;
    write_values(w, mesh.node_class.iter().map(|c| class_dim_tag(c).1), 20)?;
    close_array(w)?;
    open_array(w, "Int32", "valence", 1)?;
    write_values(w, mesh.node_valences().into_iter(), 20)?;
    close_array(w)?;
    writeln!(w, "      </PointData>")?;

    writeln!(
        w,
        "      <CellData{}>",
        if sicn.is_some() {
            " Scalars=\"SICN\""
        } else {
            ""
        }
    )?;
    open_array(w, "Int32", "cad_face", 1)?;
    write_values(
        w,
        mesh.quad_face
            .iter()
            .chain(&mesh.triangle_face)
            .map(|f| f.0 as i64 + 1),
        20,
    )?;
    close_array(w)?;
    if let Some(v) = sicn {
        open_array(w, "Float64", "SICN", 1)?;
        let vals = v
            .iter()
            .map(|x| if x.is_finite() { *x } else { NO_VALUE })
            .chain(mesh.triangles.iter().map(|_| NO_VALUE));
        write_values(w, vals, 6)?;
        close_array(w)?;
    }
    writeln!(w, "      </CellData>")?;

    write_points(w, mesh.nodes.iter())?;
    let conn = mesh
        .quads
        .iter()
        .flat_map(|q| q.iter().copied())
        .chain(mesh.triangles.iter().flat_map(|t| t.iter().copied()));
    let offsets = (1..=mesh.quads.len())
        .map(|i| 4 * i)
        .chain((1..=mesh.triangles.len()).map(|i| 4 * mesh.quads.len() + 3 * i));
    let types = mesh
        .quads
        .iter()
        .map(|_| VTK_QUAD)
        .chain(mesh.triangles.iter().map(|_| VTK_TRIANGLE));
    write_cells_and_close_piece(w, conn, offsets, types)?;
    write_footer(w)
}

/// Writes a cross field on its background triangulation to `path` (see the
/// module documentation for the pieces and arrays). The file is written
/// atomically; an inconsistent `field` is refused before anything is written.
pub fn write_field_vtu(field: &CrossFieldMesh, path: &Path) -> Result<(), VtuError> {
    field.check().map_err(|reason| VtuError::Invalid {
        path: path.to_path_buf(),
        reason,
    })?;
    write_atomically(path, |w| write_field_body(field, w)).map_err(|source| VtuError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// The XML document of [`write_field_vtu`]: one piece, triangles then one
/// vertex cell per singularity (whose points follow the triangles' nodes).
fn write_field_body<W: Write>(field: &CrossFieldMesh, w: &mut W) -> io::Result<()> {
    let (nn, nt, ns) = (
        field.nodes.len(),
        field.triangles.len(),
        field.singularities.len(),
    );
    write_header(w)?;
    open_piece(w, nn + ns, nt + ns)?;

    writeln!(
        w,
        "      <CellData Scalars=\"singularity_index\" Vectors=\"cross\">"
    )?;
    open_array(w, "Int32", "cad_face", 1)?;
    let faces = field
        .triangle_face
        .iter()
        .chain(field.singularities.iter().map(|s| &s.face));
    write_values(w, faces.map(|f| f.0 as i64 + 1), 20)?;
    close_array(w)?;
    open_array(w, "Float64", "cross", 3)?;
    let cross = field
        .cross
        .iter()
        .map(|c| c.unwrap_or([0.0; 3]))
        .chain((0..ns).map(|_| [0.0; 3]));
    write_values(w, cross.flat_map(|d| d.into_iter()), 6)?;
    close_array(w)?;
    if let Some(size) = &field.size {
        open_array(w, "Float64", "size", 1)?;
        let size = size
            .iter()
            .map(|&x| if x.is_finite() { x } else { NO_VALUE })
            .chain((0..ns).map(|_| NO_VALUE));
        write_values(w, size, 6)?;
        close_array(w)?;
    }
    open_array(w, "Int32", "singularity_index", 1)?;
    write_values(
        w,
        (0..nt)
            .map(|_| 0)
            .chain(field.singularities.iter().map(|s| s.index)),
        20,
    )?;
    close_array(w)?;
    writeln!(w, "      </CellData>")?;

    write_points(
        w,
        field
            .nodes
            .iter()
            .chain(field.singularities.iter().map(|s| &s.position)),
    )?;
    let conn = field
        .triangles
        .iter()
        .flatten()
        .copied()
        .chain(nn as u32..(nn + ns) as u32);
    let offsets = (1..=nt).map(|i| 3 * i).chain((1..=ns).map(|i| 3 * nt + i));
    let types = (0..nt)
        .map(|_| VTK_TRIANGLE)
        .chain((0..ns).map(|_| VTK_VERTEX));
    write_cells_and_close_piece(w, conn, offsets, types)?;
    write_footer(w)
}

/// Writes a high-order quad mesh to `path` as an ASCII VTK UnstructuredGrid
/// of `VTK_LAGRANGE_QUADRILATERAL` cells (type 70), each element's
/// `(N + 1)²` points in VTK's order ([`crate::high_order::vtk_quad_ordering`]).
/// Point data `class_dim`, `class_tag` (as in [`write_vtu`]); cell data
/// `cad_face` (the CAD face id + 1) and `jacobian_ratio` (the element's
/// [`crate::high_order::ElementJacobian::ratio`] against its own normal,
/// [`NO_VALUE`] if not finite). An inconsistent mesh is refused before
/// anything is written; the file is written atomically.
pub fn write_high_order_vtu(mesh: &HighOrderQuadMesh, path: &Path) -> Result<(), VtuError> {
    let invalid = |e: HighOrderError| VtuError::Invalid {
        path: path.to_path_buf(),
        reason: e.to_string(),
    };
    let ratios = mesh.jacobian_ratios().map_err(invalid)?;
    let perm = vtk_quad_ordering(mesh.order).map_err(invalid)?;
    write_atomically(path, |w| write_high_order_body(mesh, &ratios, &perm, w)).map_err(|source| {
        VtuError::Io {
            path: path.to_path_buf(),
            source,
        }
    })
}

/// The XML document of [`write_high_order_vtu`].
fn write_high_order_body<W: Write>(
    mesh: &HighOrderQuadMesh,
    ratios: &[f64],
    perm: &[usize],
    w: &mut W,
) -> io::Result<()> {
    let (ne, k) = (mesh.num_elements(), mesh.nodes_per_element());
    write_header(w)?;
    open_piece(w, mesh.nodes.len(), ne)?;
    writeln!(w, "      <PointData Scalars=\"class_dim\">")?;
    open_array(w, "Int32", "class_dim", 1)?;
    write_values(w, mesh.node_class.iter().map(|c| class_dim_tag(c).0), 20)?;
    close_array(w)?;
    open_array(w, "Int32", "class_tag", 1)?;
    write_values(w, mesh.node_class.iter().map(|c| class_dim_tag(c).1), 20)?;
    close_array(w)?;
    writeln!(w, "      </PointData>")?;
    writeln!(w, "      <CellData Scalars=\"jacobian_ratio\">")?;
    open_array(w, "Int32", "cad_face", 1)?;
    write_values(w, mesh.element_face.iter().map(|f| f.0 as i64 + 1), 20)?;
    close_array(w)?;
    open_array(w, "Float64", "jacobian_ratio", 1)?;
    let ratios = ratios
        .iter()
        .map(|&x| if x.is_finite() { x } else { NO_VALUE });
    write_values(w, ratios, 6)?;
    close_array(w)?;
    writeln!(w, "      </CellData>")?;
    write_points(w, mesh.nodes.iter())?;
    let conn = (0..ne).flat_map(|e| {
        let elem = mesh.element(e);
        perm.iter().map(move |&p| elem[p])
    });
    let offsets = (1..=ne).map(|e| k * e);
    let types = (0..ne).map(|_| VTK_LAGRANGE_QUADRILATERAL);
    write_cells_and_close_piece(w, conn, offsets, types)?;
    write_footer(w)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use geometry::{CornerId, CurveId, FaceId};

    /// A 2×1 strip of quads plus one triangle, classified on corners, a curve and faces.
    pub(crate) fn small_mixed_mesh() -> QuadMesh {
        QuadMesh {
            nodes: vec![
                [0., 0., 0.],
                [1., 0., 0.],
                [2., 0., 0.],
                [0., 1., 0.],
                [1., 1., 0.],
                [2., 1., 0.],
                [3., 0.5, 0.],
            ],
            node_class: vec![
                NodeClass::Corner(CornerId(0)),
                NodeClass::Curve(CurveId(0), Some(0.5)),
                NodeClass::Corner(CornerId(1)),
                NodeClass::Corner(CornerId(3)),
                NodeClass::Face(FaceId(0), Some([1.0, 1.0])),
                NodeClass::Corner(CornerId(2)),
                NodeClass::Unclassified,
            ],
            quads: vec![[0, 1, 4, 3], [1, 2, 5, 4]],
            quad_face: vec![FaceId(0), FaceId(0)],
            triangles: vec![[2, 6, 5]],
            triangle_face: vec![FaceId(1)],
            ..Default::default()
        }
    }

    /// The text between `<DataArray … Name="name" …>` and `</DataArray>`, split on whitespace.
    pub(crate) fn array_values(xml: &str, name: &str) -> Vec<String> {
        let key = format!("Name=\"{name}\"");
        let Some(start) = xml.find(&key) else {
            return Vec::new();
        };
        let body_start = start + xml[start..].find('>').unwrap() + 1;
        let body_end = body_start + xml[body_start..].find("</DataArray>").unwrap();
        xml[body_start..body_end]
            .split_whitespace()
            .map(str::to_string)
            .collect()
    }

    fn tmp(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("quadrille-vtu-{}-{name}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn writes_counts_connectivity_and_data() {
        let dir = tmp("ok");
        let path = dir.join("m.vtu");
        let mesh = small_mixed_mesh();
        write_vtu(&mesh, Some(&[0.9, f64::NAN]), &path).unwrap();
        let xml = std::fs::read_to_string(&path).unwrap();
        assert!(xml.contains("NumberOfPoints=\"7\" NumberOfCells=\"3\""));
        assert_eq!(
            array_values(&xml, "connectivity"),
            ["0", "1", "4", "3", "1", "2", "5", "4", "2", "6", "5"]
        );
        assert_eq!(array_values(&xml, "offsets"), ["4", "8", "11"]);
        assert_eq!(array_values(&xml, "types"), ["9", "9", "5"]);
        assert_eq!(array_values(&xml, "Points").len(), 21);
        let pts: Vec<f64> = array_values(&xml, "Points")
            .iter()
            .map(|s| s.parse().unwrap())
            .collect();
        assert_eq!(pts[18..], [3.0, 0.5, 0.0]);
        assert_eq!(array_values(&xml, "SICN"), ["0.9", "-2", "-2"]);
        assert_eq!(array_values(&xml, "cad_face"), ["1", "1", "2"]);
        assert_eq!(
            array_values(&xml, "class_dim"),
            ["0", "1", "0", "0", "2", "0", "-1"]
        );
        assert_eq!(
            array_values(&xml, "class_tag"),
            ["1", "1", "2", "4", "1", "3", "0"]
        );
        assert_eq!(
            array_values(&xml, "valence"),
            ["1", "2", "1", "1", "2", "1", "0"]
        );
        // well-formed enough: every opened DataArray is closed
        assert_eq!(
            xml.matches("<DataArray").count(),
            xml.matches("</DataArray>").count()
        );
        // without SICN there is no SICN array
        write_vtu(&mesh, None, &path).unwrap();
        assert!(!std::fs::read_to_string(&path).unwrap().contains("SICN"));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn field_file_has_triangles_then_singularity_vertices() {
        let dir = tmp("field");
        let path = dir.join("f.vtu");
        let field = crate::field::tests::square_field(2);
        write_field_vtu(&field, &path).unwrap();
        let xml = std::fs::read_to_string(&path).unwrap();
        assert_eq!(xml.matches("<Piece").count(), 1);
        assert!(
            xml.contains("<Piece NumberOfPoints=\"11\" NumberOfCells=\"10\">"),
            "{xml}"
        );
        assert_eq!(
            xml.matches("<DataArray").count(),
            xml.matches("</DataArray>").count()
        );
        let types = array_values(&xml, "types");
        assert_eq!(types[..8], ["5"; 8]);
        assert_eq!(types[8..], ["1", "1"]);
        assert_eq!(array_values(&xml, "offsets")[6..], ["21", "24", "25", "26"]);
        assert_eq!(array_values(&xml, "connectivity")[..3], ["0", "1", "4"]);
        assert_eq!(array_values(&xml, "connectivity")[24..], ["9", "10"]);
        let cross = array_values(&xml, "cross");
        assert_eq!(cross.len(), 3 * 10);
        assert_eq!(cross[..3], ["1", "0", "0"]);
        assert_eq!(cross[24..], ["0"; 6]);
        let index = array_values(&xml, "singularity_index");
        assert_eq!(index[..8], ["0"; 8]);
        assert_eq!(index[8..], ["1", "-1"]);
        assert_eq!(
            array_values(&xml, "Points")[27..],
            ["0.5", "0.5", "0", "0.25", "0.25", "0"]
        );
        let size = array_values(&xml, "size");
        assert_eq!(size.len(), 10);
        assert_eq!(size[8..], ["-2", "-2"]);
        assert_eq!(array_values(&xml, "cad_face"), ["1"; 10]);
        // without sizes and singularities: triangles only, no size array
        let plain = CrossFieldMesh {
            size: None,
            singularities: Vec::new(),
            ..field.clone()
        };
        write_field_vtu(&plain, &path).unwrap();
        let xml = std::fs::read_to_string(&path).unwrap();
        assert!(xml.contains("NumberOfPoints=\"9\" NumberOfCells=\"8\""));
        assert!(!xml.contains("\"size\""));
        // inconsistent input is refused and leaves the old file alone
        let broken = CrossFieldMesh {
            cross: Vec::new(),
            ..field
        };
        let e = write_field_vtu(&broken, &path).unwrap_err();
        assert!(
            e.to_string().contains("f.vtu") && e.to_string().contains("cross"),
            "{e}"
        );
        assert_eq!(std::fs::read_to_string(&path).unwrap(), xml);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn bad_input_and_unwritable_paths_give_errors_naming_the_file() {
        let dir = tmp("bad");
        let mesh = small_mixed_mesh();
        let path = dir.join("m.vtu");
        let e = write_vtu(&mesh, Some(&[1.0]), &path).unwrap_err();
        assert!(
            e.to_string().contains("m.vtu") && e.to_string().contains("SICN"),
            "{e}"
        );
        let mut broken = mesh.clone();
        broken.quads[1][2] = 99;
        assert!(write_vtu(&broken, None, &path)
            .unwrap_err()
            .to_string()
            .contains("quad 1"));
        let mut nan = mesh.clone();
        nan.nodes[3][1] = f64::NAN;
        assert!(write_vtu(&nan, None, &path)
            .unwrap_err()
            .to_string()
            .contains("node 3"));
        assert!(!path.exists());
        // a directory in the way: the rename fails, and no partial file is left
        let blocker = dir.join("taken.vtu");
        std::fs::create_dir_all(blocker.join("x")).unwrap();
        let e = write_vtu(&mesh, None, &blocker).unwrap_err();
        assert!(
            matches!(e, VtuError::Io { .. }) && e.to_string().contains("taken.vtu"),
            "{e}"
        );
        let left: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(left.len(), 1, "left behind: {left:?}");
        let missing = dir.join("no/such/dir/m.vtu");
        assert!(write_vtu(&mesh, None, &missing).is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn high_order_file_has_lagrange_cells_in_vtk_order() {
        let dir = tmp("ho");
        let path = dir.join("ho.vtu");
        // 2 × 1 elements of order 3 over (u, v, u²/4): 7 × 4 nodes, index a + 7 b
        let mesh = crate::fixtures::high_order_patch(3, 2, 1, |u, v| [u, v, 0.25 * u * u]);
        write_high_order_vtu(&mesh, &path).unwrap();
        let xml = std::fs::read_to_string(&path).unwrap();
        assert!(
            xml.contains("NumberOfPoints=\"28\" NumberOfCells=\"2\""),
            "{xml}"
        );
        assert_eq!(array_values(&xml, "types"), ["70", "70"]);
        assert_eq!(array_values(&xml, "offsets"), ["16", "32"]);
        let conn: Vec<u32> = array_values(&xml, "connectivity")
            .iter()
            .map(|s| s.parse().unwrap())
            .collect();
        // element 0: corners, bottom, right, top (rising u), left (rising v), rows
        let want0 = [0, 3, 24, 21, 1, 2, 10, 17, 22, 23, 7, 14, 8, 9, 15, 16];
        assert_eq!(conn[..16], want0);
        assert_eq!(conn[16..20], [3, 6, 27, 24]);
        assert_eq!(array_values(&xml, "cad_face"), ["1", "1"]);
        let ratios: Vec<f64> = array_values(&xml, "jacobian_ratio")
            .iter()
            .map(|s| s.parse().unwrap())
            .collect();
        let want = mesh.jacobian_ratios().unwrap();
        assert_eq!(ratios, want);
        assert!(ratios.iter().all(|&r| r > 0.5 && r < 1.0), "{ratios:?}");
        assert_eq!(array_values(&xml, "class_dim").len(), 28);
        assert_eq!(array_values(&xml, "Points").len(), 3 * 28);
        assert_eq!(
            xml.matches("<DataArray").count(),
            xml.matches("</DataArray>").count()
        );
        // a bad mesh is refused and the old file stays
        let mut bad = mesh.clone();
        bad.order = 11;
        let e = write_high_order_vtu(&bad, &path).unwrap_err();
        assert!(
            e.to_string().contains("order 11") && e.to_string().contains("ho.vtu"),
            "{e}"
        );
        bad.order = 3;
        bad.element_nodes[3] = 28;
        assert!(write_high_order_vtu(&bad, &path)
            .unwrap_err()
            .to_string()
            .contains("node 28"));
        assert_eq!(std::fs::read_to_string(&path).unwrap(), xml);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
