//! Mesh statistics: counts, valences, irregular vertices, SICN / scaled
//! Jacobian summaries, inverted quads, open and non-manifold edges and, when
//! the CAD [`Model`] is known, the distance of the nodes to it and the quads
//! excused from minimum-quality bars because they touch a cusp-like CAD corner.
//!
//! Definitions (DESIGN.md §5, quasi-structured spec §8.1):
//! - quality is sampled at the four corners of each quad with a reference
//!   normal: the oriented CAD normal with a Model (by
//!   [`geometry::Face::corner_normal`], the mesher's rule: at a pole or cone
//!   apex the limit normal from inside the quad), else the mean normal of
//!   the same-face quads sharing a node with the quad;
//! - "irregular" = a face-interior node (classified on a face) whose quad
//!   valence is not 4; "inverted" = a quad with some corner SICN < 0;
//! - inverted quads are counted twice (DESIGN.md §5): with the reference
//!   normals above, and by the element geometry alone
//!   ([`crate::quality::element_corner_sicn`]), the sign Gmsh's `minSICN`
//!   gives to the written file read without its CAD, which is what users'
//!   tools check.

use std::collections::{BTreeMap, HashMap};

use geometry::vec3;
use geometry::{CornerId, FaceId, Model};
use serde::Serialize;

use crate::quadmesh::{NodeClass, QuadMesh};
use crate::quality::{corner_scaled_jacobian, corner_sicn, element_corner_sicn};

mod normals;
mod report;
mod sharp;

use normals::{corner_normals_and_folds, mesh_corner_normals, min4, quad_points};
pub use normals::{
    quad_acceptance_sicn_values, quad_corner_normals, quad_corner_normals_of,
    quad_element_sicn_values, quad_scaled_jacobian_values, quad_sicn_values,
};
pub use sharp::{sharp_corners, sharp_corners_in_face};

/// CAD corners whose interior angle in a face is below this (degrees) excuse
/// the quads touching them from minimum-SICN bars (DESIGN.md §5).
pub const SHARP_CORNER_DEG: f64 = 10.0;

/// Minimum, average and 1st percentile of a per-quad quality measure.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct QualitySummary {
    /// Smallest value (0 when there are no quads).
    pub min: f64,
    /// Mean value.
    pub avg: f64,
    /// 1st percentile (nearest-rank): 1 % of the quads are at or below it.
    pub p1: f64,
}

impl QualitySummary {
    /// Summary of `values` (all zeros for an empty slice).
    pub fn of(values: &[f64]) -> Self {
        if values.is_empty() {
            return Self::default();
        }
        let mut v: Vec<f64> = values.to_vec();
        v.sort_by(f64::total_cmp);
        let rank = ((0.01 * v.len() as f64).ceil() as usize).clamp(1, v.len());
        Self {
            min: v[0],
            avg: v.iter().sum::<f64>() / v.len() as f64,
            p1: v[rank - 1],
        }
    }
}

/// Distance of the mesh nodes to the CAD entities they are classified on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct CadDistance {
    /// Largest node-to-CAD distance.
    pub max: f64,
    /// Mean node-to-CAD distance over the measured nodes.
    pub mean: f64,
    /// `max / diagonal`.
    pub max_relative: f64,
    /// `mean / diagonal`.
    pub mean_relative: f64,
    /// The model's bounding-box diagonal used for the relative values.
    pub diagonal: f64,
    /// Nodes measured (classified nodes whose projection succeeded).
    pub measured: usize,
    /// Classified nodes whose projection failed (not in the figures above).
    pub failed: usize,
}

/// A CAD corner whose interior angle in one face is below [`SHARP_CORNER_DEG`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SharpCorner {
    /// The corner (0-based id).
    pub corner: u32,
    /// The face in which the angle is measured (0-based id).
    pub face: u32,
    /// Interior angle in degrees.
    pub angle_deg: f64,
}

/// A quad excused from minimum-SICN bars because it touches a sharp corner.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ExcusedQuad {
    /// Quad index in `QuadMesh::quads`.
    pub quad: usize,
    /// The sharp corner it touches (0-based id).
    pub corner: u32,
    /// Interior angle of that corner in the quad's face, degrees.
    pub angle_deg: f64,
    /// The quad's SICN.
    pub sicn: f64,
}

/// Statistics of a [`QuadMesh`], the numbers of the `stats` command and of
/// the JSON report. Build with [`MeshStats::compute`]; print with `Display`.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct MeshStats {
    /// Number of nodes.
    pub nodes: usize,
    /// Number of quads.
    pub quads: usize,
    /// Number of triangles.
    pub triangles: usize,
    /// Number of distinct element edges (of quads and triangles).
    pub edges: usize,
    /// `V − edges + quads + triangles`, V counting the nodes used by an
    /// element (2 for a closed genus-0 surface; nodes of curves no face
    /// uses, e.g. free wire edges, do not count).
    pub euler_characteristic: i64,
    /// Number of face-interior nodes (classified on a face).
    pub face_interior_nodes: usize,
    /// Quad valence → number of face-interior nodes with it.
    pub valence_histogram: BTreeMap<u32, usize>,
    /// Face-interior nodes whose quad valence is not 4.
    pub irregular_nodes: usize,
    /// `100 · irregular_nodes / face_interior_nodes`.
    pub irregular_percent: f64,
    /// Number of curve nodes (classified on a CAD curve, corners excluded).
    pub curve_nodes: usize,
    /// Curve nodes that some face meets with other than two quads per side
    /// ([`curve_node_is_irregular`]): a node on one quad of a face makes a
    /// 180° corner, a node on three an extra edge into the face. The face-
    /// interior count above does not see them, so a mesher can trade one
    /// kind for the other; this keeps the trade visible.
    pub irregular_curve_nodes: usize,
    /// Per-quad SICN summary.
    pub sicn: QualitySummary,
    /// Per-quad scaled Jacobian summary.
    pub scaled_jacobian: QualitySummary,
    /// Quads with a corner SICN < 0 against the reference normals (the CAD
    /// normals with a Model, else the mesh normals; see `cad_normals`).
    pub inverted_quads: usize,
    /// Quads with a corner SICN < 0 judged from the element alone
    /// ([`crate::quality::element_corner_sicn`]): the quads Gmsh's `minSICN`
    /// finds negative in the written mesh file read without its CAD. The
    /// same with or without a Model.
    pub inverted_quads_element_geometry: usize,
    /// `inverted_quads` less the quads in `excused_quads` (those touching a
    /// CAD corner below [`SHARP_CORNER_DEG`]): the count the validity bars use.
    pub inverted_quads_outside_sharp: usize,
    /// `inverted_quads_element_geometry` less the quads in `excused_quads`.
    pub inverted_quads_element_geometry_outside_sharp: usize,
    /// Element edges used by exactly one element (holes or the boundary of an open shell).
    pub open_edges: usize,
    /// Element edges used by more than two elements.
    pub non_manifold_edges: usize,
    /// True when the CAD normal was used for quality (a Model was given).
    pub cad_normals: bool,
    /// Quad corners on a CAD curve where the surface folds back by more than
    /// 90° before the quad's centre (a bend the quad does not resolve, such
    /// as a trailing edge rounded far below the quad size), measured with the
    /// centre's normal ([`geometry::Face::corner_normal`]); 0 without CAD.
    pub fold_corners: usize,
    /// Node-to-CAD distance (only with a Model).
    pub cad_distance: Option<CadDistance>,
    /// CAD corners below [`SHARP_CORNER_DEG`] in some face (only with a Model).
    pub sharp_corners: Vec<SharpCorner>,
    /// Quads touching a sharp corner in their face.
    pub excused_quads: Vec<ExcusedQuad>,
    /// Minimum SICN over the quads not in `excused_quads` (equals
    /// `sicn.min` when none are excused; 0 when no quad remains).
    pub min_sicn_excluding_sharp: f64,
}

/// Distance of each classified node to its CAD entity (None when unclassified
/// or when the projection fails).
pub fn node_cad_distances(mesh: &QuadMesh, model: &Model) -> Vec<Option<f64>> {
    mesh.nodes
        .iter()
        .zip(&mesh.node_class)
        .map(|(&p, class)| match *class {
            NodeClass::Corner(c) => model.corners.get(c.idx()).map(|k| vec3::dist(p, k.point)),
            NodeClass::Curve(c, t) => {
                let curve = model.curves.get(c.idx())?;
                match &curve.geom {
                    Some(g) => g.project(p, t).map(|(_, q)| vec3::dist(p, q)),
                    None => model
                        .corners
                        .get(curve.start.idx())
                        .map(|k| vec3::dist(p, k.point)),
                }
            }
            NodeClass::Face(f, uv) => {
                let face = model.faces.get(f.idx())?;
                face.surface.project(p, uv).map(|(_, q)| vec3::dist(p, q))
            }
            NodeClass::Unclassified => None,
        })
        .map(|d| d.filter(|x| x.is_finite()))
        .collect()
}

/// Counts of element edges by number of incident elements (quads and triangles).
/// The quads around each node.
fn node_quads(mesh: &QuadMesh) -> Vec<Vec<u32>> {
    let mut at = vec![Vec::new(); mesh.nodes.len()];
    for (qi, q) in mesh.quads.iter().enumerate() {
        for &v in q {
            at[v as usize].push(qi as u32);
        }
    }
    at
}

/// True when some face meets curve node `v` (its quads `at`) with other
/// than two quads per side of the curve: two on each face of an ordinary
/// curve, four on a face the curve is a seam of (all quads around the node
/// in one face, no open edge at it), two on an open shell's boundary.
pub fn curve_node_is_irregular(
    mesh: &QuadMesh,
    v: u32,
    at: &[u32],
    uses: &HashMap<(u32, u32), u32>,
) -> bool {
    let mut per_face: BTreeMap<u32, usize> = BTreeMap::new();
    for &q in at {
        *per_face.entry(mesh.quad_face[q as usize].0).or_insert(0) += 1;
    }
    let open = at.iter().any(|&q| {
        let quad = &mesh.quads[q as usize];
        (0..4).any(|k| {
            let (a, b) = (quad[k], quad[(k + 1) % 4]);
            (a == v || b == v) && uses.get(&(a.min(b), a.max(b))) == Some(&1)
        })
    });
    let expected = if per_face.len() == 1 && !open { 4 } else { 2 };
    per_face.values().any(|&n| n != expected)
}

/// Every edge of `mesh` (quads and triangles), as (smaller node, larger
/// node), with the number of elements using it: 1 on an open edge, 2 inside
/// a manifold mesh, more on a non-manifold edge.
pub fn edge_uses(mesh: &QuadMesh) -> HashMap<(u32, u32), u32> {
    let mut uses: HashMap<(u32, u32), u32> =
        HashMap::with_capacity(2 * (mesh.quads.len() + mesh.triangles.len()));
    let mut add_edge = |a: u32, b: u32| *uses.entry((a.min(b), a.max(b))).or_insert(0) += 1;
    for q in &mesh.quads {
        for k in 0..4 {
            add_edge(q[k], q[(k + 1) % 4]);
        }
    }
    for t in &mesh.triangles {
        for k in 0..3 {
            add_edge(t[k], t[(k + 1) % 3]);
        }
    }
    uses
}

impl MeshStats {
    /// Computes the statistics of `mesh`; with `model`, quality uses the CAD
    /// normals and the CAD distance and sharp corners are reported.
    ///
    /// Node indices out of range in elements are the caller's bug; they are
    /// ignored here rather than panicking (meshes read from files are checked
    /// by the readers).
    pub fn compute(mesh: &QuadMesh, model: Option<&Model>) -> MeshStats {
        let nn = mesh.nodes.len();
        let valid_mesh;
        let mesh = if mesh
            .quads
            .iter()
            .flatten()
            .chain(mesh.triangles.iter().flatten())
            .any(|&v| v as usize >= nn)
            || mesh.node_class.len() != nn
            || mesh.quad_face.len() != mesh.quads.len()
        {
            valid_mesh = sanitized(mesh);
            &valid_mesh
        } else {
            mesh
        };
        let mut s = MeshStats {
            nodes: nn,
            quads: mesh.quads.len(),
            triangles: mesh.triangles.len(),
            cad_normals: model.is_some(),
            ..Default::default()
        };
        let uses = edge_uses(mesh);
        s.edges = uses.len();
        s.open_edges = uses.values().filter(|&&u| u == 1).count();
        s.non_manifold_edges = uses.values().filter(|&&u| u > 2).count();
        let mut used = vec![false; nn];
        for &v in mesh
            .quads
            .iter()
            .flatten()
            .chain(mesh.triangles.iter().flatten())
        {
            used[v as usize] = true;
        }
        let used_nodes = used.iter().filter(|&&u| u).count();
        s.euler_characteristic =
            used_nodes as i64 - s.edges as i64 + (s.quads + s.triangles) as i64;

        let val = mesh.node_valences();
        for (v, &d) in val.iter().enumerate() {
            if mesh.is_face_interior(v) {
                s.face_interior_nodes += 1;
                *s.valence_histogram.entry(d).or_insert(0) += 1;
                if d != 4 {
                    s.irregular_nodes += 1;
                }
            }
        }
        if s.face_interior_nodes > 0 {
            s.irregular_percent = 100.0 * s.irregular_nodes as f64 / s.face_interior_nodes as f64;
        }
        let quads_at = node_quads(mesh);
        for (v, at) in quads_at.iter().enumerate() {
            if matches!(mesh.node_class[v], NodeClass::Curve(..)) && !at.is_empty() {
                s.curve_nodes += 1;
                if curve_node_is_irregular(mesh, v as u32, at, &uses) {
                    s.irregular_curve_nodes += 1;
                }
            }
        }

        let normals = match model {
            Some(model) => {
                let all: Vec<u32> = (0..mesh.quads.len() as u32).collect();
                let (normals, folds) = corner_normals_and_folds(mesh, model, &all);
                s.fold_corners = folds;
                normals
            }
            None => mesh_corner_normals(mesh),
        };
        let mut sicn = Vec::with_capacity(mesh.quads.len());
        let mut sj = Vec::with_capacity(mesh.quads.len());
        // per quad: inverted by the CAD normals, by the element geometry
        let mut inverted = Vec::with_capacity(mesh.quads.len());
        for (q, n) in mesh.quads.iter().zip(&normals) {
            let p = quad_points(mesh, q);
            let cs = corner_sicn(&p, n);
            let by_normals = cs.iter().any(|&x| x < 0.0);
            let by_element = element_corner_sicn(&p).iter().any(|&x| x < 0.0);
            s.inverted_quads += usize::from(by_normals);
            s.inverted_quads_element_geometry += usize::from(by_element);
            inverted.push((by_normals, by_element));
            sicn.push(min4(cs));
            sj.push(min4(corner_scaled_jacobian(&p, n)));
        }
        s.sicn = QualitySummary::of(&sicn);
        s.scaled_jacobian = QualitySummary::of(&sj);

        if let Some(model) = model {
            let d: Vec<f64> = node_cad_distances(mesh, model)
                .into_iter()
                .flatten()
                .collect();
            let classified = mesh
                .node_class
                .iter()
                .filter(|c| !matches!(c, NodeClass::Unclassified))
                .count();
            let diagonal = model.diagonal();
            let max = d.iter().copied().fold(0.0, f64::max);
            let mean = if d.is_empty() {
                0.0
            } else {
                d.iter().sum::<f64>() / d.len() as f64
            };
            let rel = |x: f64| if diagonal > 0.0 { x / diagonal } else { 0.0 };
            s.cad_distance = Some(CadDistance {
                max,
                mean,
                max_relative: rel(max),
                mean_relative: rel(mean),
                diagonal,
                measured: d.len(),
                failed: classified - d.len(),
            });
            s.sharp_corners = sharp_corners(model, SHARP_CORNER_DEG);
            let sharp: HashMap<(CornerId, FaceId), f64> = s
                .sharp_corners
                .iter()
                .map(|c| ((CornerId(c.corner), FaceId(c.face)), c.angle_deg))
                .collect();
            if !sharp.is_empty() {
                for (qi, (q, &f)) in mesh.quads.iter().zip(&mesh.quad_face).enumerate() {
                    let hit = q.iter().find_map(|&v| match mesh.node_class[v as usize] {
                        NodeClass::Corner(c) => sharp.get(&(c, f)).map(|&a| (c, a)),
                        _ => None,
                    });
                    if let Some((c, a)) = hit {
                        s.excused_quads.push(ExcusedQuad {
                            quad: qi,
                            corner: c.0,
                            angle_deg: a,
                            sicn: sicn[qi],
                        });
                    }
                }
            }
        }
        let mut excused = vec![false; sicn.len()];
        for e in &s.excused_quads {
            excused[e.quad] = true;
        }
        for (&(by_normals, by_element), &e) in inverted.iter().zip(&excused) {
            if !e {
                s.inverted_quads_outside_sharp += usize::from(by_normals);
                s.inverted_quads_element_geometry_outside_sharp += usize::from(by_element);
            }
        }
        s.min_sicn_excluding_sharp = sicn
            .iter()
            .zip(&excused)
            .filter(|(_, &e)| !e)
            .map(|(&x, _)| x)
            .fold(None, |m: Option<f64>, x| Some(m.map_or(x, |m| m.min(x))))
            .unwrap_or(0.0);
        s
    }
}

/// A copy of `mesh` without elements referring to missing nodes and with the
/// classification and face lists padded to the right lengths.
fn sanitized(mesh: &QuadMesh) -> QuadMesh {
    let nn = mesh.nodes.len() as u32;
    let mut m = QuadMesh {
        nodes: mesh.nodes.clone(),
        node_class: mesh.node_class.clone(),
        ..Default::default()
    };
    m.node_class
        .resize(mesh.nodes.len(), NodeClass::Unclassified);
    for (i, q) in mesh.quads.iter().enumerate() {
        if q.iter().all(|&v| v < nn) {
            m.quads.push(*q);
            m.quad_face
                .push(mesh.quad_face.get(i).copied().unwrap_or(FaceId(0)));
        }
    }
    for (i, t) in mesh.triangles.iter().enumerate() {
        if t.iter().all(|&v| v < nn) {
            m.triangles.push(*t);
            m.triangle_face
                .push(mesh.triangle_face.get(i).copied().unwrap_or(FaceId(0)));
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures;
    use geometry::vec3::{add, scale, Vec3};
    use geometry::CurveId;

    /// Curve nodes with two quads per side are regular (on an open
    /// boundary, between two faces, and on a seam inside one face); a face
    /// that meets one with a single quad makes it irregular.
    #[test]
    fn curve_nodes_count_quads_per_side() {
        let (_, mut mesh) = fixtures::square_grid(3.0, 3);
        let id = |i: u32, j: u32| j * 4 + i;
        let s = MeshStats::compute(&mesh, None);
        assert_eq!((s.curve_nodes, s.irregular_curve_nodes), (8, 0));
        // a seam through the middle node: four quads of one face, no open edge
        mesh.node_class[id(1, 1) as usize] = NodeClass::Curve(CurveId(4), None);
        let s = MeshStats::compute(&mesh, None);
        assert_eq!((s.curve_nodes, s.irregular_curve_nodes), (9, 0));
        assert_eq!(s.face_interior_nodes, 3);
        // the corner quad moved to another face: the boundary nodes (1, 0)
        // and (0, 1) now have one quad of each face, and the seam node one
        // quad of face 1 against three of face 0
        mesh.quad_face[0] = FaceId(1);
        let s = MeshStats::compute(&mesh, None);
        assert_eq!((s.curve_nodes, s.irregular_curve_nodes), (9, 3));
    }

    /// Nodes no element uses (the mesh of a free wire curve) are nodes of the
    /// file but not vertices of the surface: χ of the disk stays 1.
    #[test]
    fn unused_nodes_do_not_change_the_euler_characteristic() {
        let (_, mut mesh) = fixtures::square_grid(2.0, 2);
        for k in 0..3 {
            mesh.nodes.push([5.0 + k as f64, 0.0, 0.0]);
            mesh.node_class.push(NodeClass::Unclassified);
        }
        let s = MeshStats::compute(&mesh, None);
        assert_eq!(s.nodes, 12);
        assert_eq!(s.euler_characteristic, 1);
    }

    #[test]
    fn square_grid_counts_and_boundary() {
        let (model, mesh) = fixtures::square_grid(2.0, 2);
        let s = MeshStats::compute(&mesh, Some(&model));
        assert_eq!((s.nodes, s.quads, s.triangles), (9, 4, 0));
        assert_eq!(s.face_interior_nodes, 1);
        assert_eq!(s.valence_histogram, BTreeMap::from([(4, 1)]));
        assert_eq!(s.irregular_nodes, 0);
        assert_eq!(s.open_edges, 8);
        assert_eq!(s.non_manifold_edges, 0);
        assert_eq!(s.edges, 12);
        assert_eq!(s.euler_characteristic, 1); // a disk
        assert!((s.sicn.min - 1.0).abs() < 1e-12 && (s.sicn.avg - 1.0).abs() < 1e-12);
        assert_eq!(s.inverted_quads, 0);
        assert_eq!(s.inverted_quads_element_geometry, 0);
        let d = s.cad_distance.unwrap();
        assert!(d.max < 1e-12 && d.failed == 0 && d.measured == 9);
        assert!(s.sharp_corners.is_empty());
        // without the model: the same quality from mesh normals
        let s2 = MeshStats::compute(&mesh, None);
        assert!((s2.sicn.min - 1.0).abs() < 1e-12 && s2.cad_distance.is_none());
    }

    #[test]
    fn pentagon_star_is_irregular() {
        // 5 quads around a centre node of valence 5.
        let mut mesh = QuadMesh::default();
        mesh.nodes.push([0.0; 3]);
        mesh.node_class.push(NodeClass::Face(FaceId(0), None));
        for i in 0..10 {
            let a = std::f64::consts::TAU * i as f64 / 10.0;
            let r = if i % 2 == 0 { 1.0 } else { 0.85 };
            mesh.nodes.push([r * a.cos(), r * a.sin(), 0.0]);
            mesh.node_class.push(NodeClass::Curve(CurveId(0), None));
        }
        for k in 0..5u32 {
            let m0 = 1 + 2 * k;
            mesh.quads
                .push([0, m0, 1 + (2 * k + 1) % 10, 1 + (2 * k + 2) % 10]);
            mesh.quad_face.push(FaceId(0));
        }
        let s = MeshStats::compute(&mesh, None);
        assert_eq!(s.valence_histogram, BTreeMap::from([(5, 1)]));
        assert_eq!(s.irregular_nodes, 1);
        assert!((s.irregular_percent - 100.0).abs() < 1e-12);
        assert_eq!(s.open_edges, 10);
        assert_eq!(s.inverted_quads, 0);
        // flip one quad: it becomes inverted against its neighbours' normal
        mesh.quads[0].reverse();
        let s = MeshStats::compute(&mesh, None);
        assert!(s.inverted_quads >= 1, "{s}");
        // the element alone cannot see a whole quad flipped
        assert_eq!(s.inverted_quads_element_geometry, 0, "{s}");
    }

    #[test]
    fn quality_summary_percentile() {
        let v: Vec<f64> = (0..200).map(|i| i as f64 / 199.0).collect();
        let q = QualitySummary::of(&v);
        assert_eq!(q.min, 0.0);
        assert!((q.p1 - 1.0 / 199.0).abs() < 1e-15); // 2nd smallest of 200
        assert!((q.avg - 0.5).abs() < 1e-12);
        assert_eq!(QualitySummary::of(&[]), QualitySummary::default());
    }

    #[test]
    fn cad_normals_on_a_sphere_pole() {
        // One quad fan touching the north pole of a sphere: the CAD normal at
        // the pole is undefined in (u, v) and must be evaluated just inside.
        let model = geometry::primitives::sphere(1.0);
        // ring nodes every 45° at one latitude, even ones on quad corners
        let ring: Vec<Vec3> = (0..8)
            .map(|i| {
                let u = std::f64::consts::FRAC_PI_4 * i as f64;
                let v: f64 = 1.2;
                [v.cos() * u.cos(), v.cos() * u.sin(), v.sin()]
            })
            .collect();
        let mut mesh = QuadMesh::default();
        mesh.nodes.push([0.0, 0.0, 1.0]);
        mesh.node_class.push(NodeClass::Corner(CornerId(1)));
        for p in ring {
            mesh.nodes.push(p);
            mesh.node_class.push(NodeClass::Face(FaceId(0), None));
        }
        // the quad (pole, ring i, mid i, ring i+1) is CCW seen from outside
        for i in 0..4u32 {
            mesh.quads
                .push([0, 1 + 2 * i, 2 + 2 * i, 1 + (2 * i + 2) % 8]);
            mesh.quad_face.push(FaceId(0));
        }
        let normals = quad_corner_normals(&mesh, Some(&model));
        for n in &normals {
            assert!(n[0][2] > 0.99, "pole normal {:?}", n[0]);
        }
        let s = MeshStats::compute(&mesh, Some(&model));
        assert_eq!(s.inverted_quads, 0);
        assert!(s.sicn.min > 0.3, "{s}");
        assert!(s.cad_distance.unwrap().max < 1e-9);
    }

    /// `primitives::cone(1, 1)` with its apex pcurve moved `past` beyond the
    /// apex in v (where `du × dv` belongs to the other nappe), as
    /// OpenCASCADE's are on data/cad/i04o_m4.step (1.8e-12), and a fan of 4
    /// quads around the apex: (apex, ring u_{2i+2}, ring u_{2i+1}, ring u_{2i})
    /// with the ring at half height, every 45°; the ring node at u = 0 lies on
    /// the seam.
    fn cone_apex_fan(past: f64) -> (Model, QuadMesh) {
        use geometry::primitives::{cone, Line2d};
        use std::sync::Arc;
        let mut model = cone(1.0, 1.0);
        let va = model.faces[0].uv_bounds.vmin;
        model.faces[0].loops[0].uses[0].pcurve = Arc::new(Line2d {
            origin: [0.0, va - past],
            dir: [1.0, 0.0],
        });
        let v = 0.5 * va;
        let mut mesh = QuadMesh::default();
        mesh.nodes.push([0.0; 3]);
        mesh.node_class.push(NodeClass::Corner(CornerId(0)));
        for k in 0..8 {
            let u = std::f64::consts::FRAC_PI_4 * k as f64;
            mesh.nodes.push(model.faces[0].surface.eval([u, v]));
            // the seam curve's parameter is v
            mesh.node_class.push(if k == 0 {
                NodeClass::Curve(CurveId(1), Some(v))
            } else {
                NodeClass::Face(FaceId(0), Some([u, v]))
            });
        }
        for i in 0..4u32 {
            mesh.quads
                .push([0, 1 + (2 * i + 2) % 8, 2 + 2 * i, 1 + 2 * i]);
            mesh.quad_face.push(FaceId(0));
        }
        (model, mesh)
    }

    /// Eq. 12 on the fan of [`cone_apex_fan`] computed by hand: the cone's
    /// normal at a ring node is `(cos a cos u, cos a sin u, −sin a)` (a = 45°),
    /// at the apex the limit along the quad's middle generatrix.
    fn cone_fan_expected(mesh: &QuadMesh) -> Vec<f64> {
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let n = |u: f64| [s * u.cos(), s * u.sin(), -s];
        (0..4)
            .map(|i| {
                let u = |k: usize| std::f64::consts::FRAC_PI_4 * k as f64;
                let ns = [
                    n(u(2 * i + 1)),
                    n(u(2 * i + 2)),
                    n(u(2 * i + 1)),
                    n(u(2 * i)),
                ];
                min4(corner_sicn(&quad_points(mesh, &mesh.quads[i]), &ns))
            })
            .collect()
    }

    #[test]
    fn quads_at_a_cone_apex_take_the_limit_normal_from_inside() {
        let (model, mesh) = cone_apex_fan(1e-12);
        let expected = cone_fan_expected(&mesh);
        assert!(expected.iter().all(|&x| x > 0.3), "{expected:?}");
        // the apex pcurve's own normal points into the cone: the old evaluation
        let apex_uv = [0.0, model.faces[0].uv_bounds.vmin - 1e-12];
        assert!(model.faces[0].normal(apex_uv).unwrap()[2] > 0.7);
        let sicn = quad_sicn_values(&mesh, Some(&model));
        for (got, want) in sicn.iter().zip(&expected) {
            assert!((got - want).abs() < 1e-9, "{sicn:?} vs {expected:?}");
        }
        let s = MeshStats::compute(&mesh, Some(&model));
        assert_eq!(s.inverted_quads, 0, "{s}");
        // as Gmsh writes them: the apex and the ring as face nodes without (u, v)
        let mut g = mesh.clone();
        for c in g.node_class.iter_mut() {
            *c = NodeClass::Face(FaceId(0), None);
        }
        let sicn = quad_sicn_values(&g, Some(&model));
        for (got, want) in sicn.iter().zip(&expected) {
            assert!((got - want).abs() < 1e-6, "{sicn:?} vs {expected:?}");
        }
    }

    /// Two quads each spanning half of `primitives::cone(1, 1)` round its
    /// apex (i04o's corner quads): (ring u, ring u − π/2, ring u − π, apex)
    /// for u = π and 2π, the ring at half height. The ring node at u = 0 is
    /// read at u = 2π, so on the upper half the first corner's period puts
    /// the corner at u = π exactly half a period away (the tie), and the
    /// apex, as a pole corner or as a face node at an arbitrary u = π, must
    /// still take the limit normal along the quad's own middle generatrix.
    #[test]
    fn a_half_cone_quad_at_the_apex_reads_its_own_half() {
        use std::f64::consts::{FRAC_PI_2, PI, TAU};
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let n = |u: f64| [s * u.cos(), s * u.sin(), -s];
        for apex_as_pole in [true, false] {
            let model = geometry::primitives::cone(1.0, 1.0);
            let va = model.faces[0].uv_bounds.vmin;
            let v = 0.5 * va;
            let mut mesh = QuadMesh::default();
            mesh.nodes.push([0.0; 3]);
            mesh.node_class.push(if apex_as_pole {
                NodeClass::Corner(CornerId(0))
            } else {
                NodeClass::Face(FaceId(0), Some([PI, va]))
            });
            // ring nodes 1..=4 at u = 2π (the seam, read on its right side), π/2, π, 3π/2
            for u in [TAU, FRAC_PI_2, PI, 3.0 * FRAC_PI_2] {
                mesh.nodes.push(model.faces[0].surface.eval([u, v]));
                mesh.node_class
                    .push(NodeClass::Face(FaceId(0), Some([u, v])));
            }
            mesh.quads.push([3, 2, 1, 0]); // lower half: u = π, π/2, 0
            mesh.quads.push([1, 4, 3, 0]); // upper half: u = 2π, 3π/2, π
            mesh.quad_face.push(FaceId(0));
            mesh.quad_face.push(FaceId(0));
            // the fixture reaches the tie: π moved to 2π's period is 3π
            let periods = model.faces[0].surface.periods();
            let tied = geometry::nearest_periodic_uv([PI, v], periods, [TAU, v]);
            assert!((tied[0] - 3.0 * PI).abs() < 1e-12, "{tied:?}");
            let normals = quad_corner_normals(&mesh, Some(&model));
            let expected = [
                [n(PI), n(FRAC_PI_2), n(0.0), n(FRAC_PI_2)],
                [n(TAU), n(3.0 * FRAC_PI_2), n(PI), n(3.0 * FRAC_PI_2)],
            ];
            for (qi, want) in expected.iter().enumerate() {
                for k in 0..4 {
                    let d = vec3::dist(normals[qi][k], want[k]);
                    assert!(
                        d < 1e-6,
                        "pole {apex_as_pole} quad {qi} corner {k}: {:?} vs {:?}",
                        normals[qi][k],
                        want[k]
                    );
                }
            }
            let sicn = quad_sicn_values(&mesh, Some(&model));
            for (qi, want) in expected.iter().enumerate() {
                let hand = min4(corner_sicn(&quad_points(&mesh, &mesh.quads[qi]), want));
                assert!(hand > 0.3, "{hand}");
                assert!(
                    (sicn[qi] - hand).abs() < 1e-6,
                    "pole {apex_as_pole}: {sicn:?} vs {hand}"
                );
            }
            let st = MeshStats::compute(&mesh, Some(&model));
            assert_eq!(st.inverted_quads, 0, "pole {apex_as_pole}: {st}");
        }
    }

    /// A planar triangle face with a 5° angle at corner 0, split into 3 quads.
    fn wedge() -> (Model, QuadMesh) {
        let a = 5f64.to_radians();
        let p = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [a.cos(), a.sin(), 0.0]];
        let model = geometry::primitives::polygon(&[[0.0, 0.0], [1.0, 0.0], [a.cos(), a.sin()]]);
        let mid = |i: usize, j: usize| scale(add(p[i], p[j]), 0.5);
        let g = scale(add(add(p[0], p[1]), p[2]), 1.0 / 3.0);
        let mut mesh = QuadMesh::default();
        for (k, q) in p.iter().enumerate() {
            mesh.nodes.push(*q);
            mesh.node_class.push(NodeClass::Corner(CornerId(k as u32)));
        }
        for k in 0..3 {
            mesh.nodes.push(mid(k, (k + 1) % 3));
            mesh.node_class
                .push(NodeClass::Curve(CurveId(k as u32), Some(0.5)));
        }
        mesh.nodes.push(g);
        mesh.node_class
            .push(NodeClass::Face(FaceId(0), Some([g[0], g[1]])));
        // corner k, mid of its outgoing side, centre, mid of its incoming side
        for k in 0..3u32 {
            mesh.quads.push([k, 3 + k, 6, 3 + (k + 2) % 3]);
            mesh.quad_face.push(FaceId(0));
        }
        (model, mesh)
    }

    #[test]
    fn inverted_counts_outside_sharp_corners_leave_out_the_excused_quads() {
        // quad 0 touches the 5° corner (excused), quad 1 does not; a bow-tie
        // (nodes 1 and 2 of the quad swapped) is negative by both judges
        let bow_tie = |q: [u32; 4]| [q[0], q[2], q[1], q[3]];
        let (model, mut mesh) = wedge();
        mesh.quads[0] = bow_tie(mesh.quads[0]);
        let s = MeshStats::compute(&mesh, Some(&model));
        assert_eq!(
            (s.inverted_quads, s.inverted_quads_element_geometry),
            (1, 1),
            "{s}"
        );
        assert_eq!(s.inverted_quads_outside_sharp, 0, "{s}");
        assert_eq!(s.inverted_quads_element_geometry_outside_sharp, 0, "{s}");
        let (model, mut mesh) = wedge();
        mesh.quads[1] = bow_tie(mesh.quads[1]);
        let s = MeshStats::compute(&mesh, Some(&model));
        assert_eq!(
            (s.inverted_quads, s.inverted_quads_element_geometry),
            (1, 1),
            "{s}"
        );
        assert_eq!(s.inverted_quads_outside_sharp, 1, "{s}");
        assert_eq!(s.inverted_quads_element_geometry_outside_sharp, 1, "{s}");
        assert!(s.to_string().contains("1 / 1"), "{s}");
    }

    #[test]
    fn quads_at_a_cusp_corner_are_excused() {
        let (model, mesh) = wedge();
        let sharp = sharp_corners(&model, SHARP_CORNER_DEG);
        assert_eq!(sharp.len(), 1, "{sharp:?}");
        assert_eq!((sharp[0].corner, sharp[0].face), (0, 0));
        assert!((sharp[0].angle_deg - 5.0).abs() < 1e-9);
        let s = MeshStats::compute(&mesh, Some(&model));
        assert_eq!(s.excused_quads.len(), 1);
        assert_eq!(s.excused_quads[0].quad, 0);
        let sicn = quad_sicn_values(&mesh, Some(&model));
        assert!(sicn[0] < 0.1 && sicn[0] > 0.0);
        assert_eq!(s.sicn.min, sicn[0]);
        assert_eq!(s.min_sicn_excluding_sharp, sicn[1].min(sicn[2]));
        assert!(s.min_sicn_excluding_sharp > sicn[0]);
        assert!(s.to_string().contains("min SICN excluding them"));
        // the other two corners are at about 87.5°: not sharp
        assert!(sharp_corners(&model, 90.0).len() == 3);
    }

    #[test]
    fn a_cusp_reads_as_0_degrees_whichever_way_rounding_tips_its_tangents() {
        for tilt in [0.0, 1e-9, -1e-9] {
            let sharp = sharp_corners(&geometry::primitives::cusp(1.0, tilt), SHARP_CORNER_DEG);
            // the two cusps, at the origin and at (1, 1) where the arc is
            // tangent to the line x = 1; not the 90° corner at (1, 0)
            let mut corners: Vec<u32> = sharp.iter().map(|s| s.corner).collect();
            corners.sort_unstable();
            assert_eq!(corners, [0, 2], "tilt {tilt}: {sharp:?}");
            assert!(
                sharp.iter().all(|s| s.angle_deg < 0.1),
                "tilt {tilt}: {sharp:?}"
            );
        }
    }

    #[test]
    fn serializes_to_json() {
        let (model, mesh) = fixtures::square_grid(1.0, 3);
        let s = MeshStats::compute(&mesh, Some(&model));
        let j = serde_json::to_value(&s).unwrap();
        assert_eq!(j["quads"], 9);
        assert_eq!(j["valence_histogram"]["4"], 4);
        assert_eq!(j["inverted_quads"], 0);
        assert_eq!(j["inverted_quads_element_geometry"], 0);
        let text = s.to_string();
        assert!(text.contains("irregular nodes"));
        assert!(text.contains("inverted (CAD normals)"), "{text}");
        assert!(text.contains("inverted (element geometry)"), "{text}");
        let text = MeshStats::compute(&mesh, None).to_string();
        assert!(text.contains("inverted (mesh normals)"), "{text}");
    }

    /// A sliver on the unit cylinder (u in degrees, v): (90, 0.1), (105, 0.2),
    /// (60, 0.1), (45, 0): a thin strip 60° around the axis. Against the CAD
    /// normals every corner is fine (SICN 0.133 at each), but the strip
    /// bends so far that corner 2's cross product points against corner 1's:
    /// Gmsh 4.15.2 reports minSICN −0.3391 for it, in any node numbering
    /// (measured; its minSJ and minDetJac stay positive).
    #[test]
    fn element_judge_catches_a_bent_sliver_the_cad_normals_pass() {
        let model = geometry::primitives::cylinder(1.0, 1.0);
        let mut mesh = QuadMesh::default();
        for (deg, v) in [(90.0f64, 0.1), (105.0, 0.2), (60.0, 0.1), (45.0, 0.0)] {
            let uv = [deg.to_radians(), v];
            mesh.nodes.push(model.faces[0].surface.eval(uv));
            mesh.node_class.push(NodeClass::Face(FaceId(0), Some(uv)));
        }
        mesh.quads.push([0, 1, 2, 3]);
        mesh.quad_face.push(FaceId(0));
        let s = MeshStats::compute(&mesh, Some(&model));
        assert_eq!(s.inverted_quads, 0, "{s}");
        assert!(s.sicn.min > 0.13, "{s}");
        assert_eq!(s.inverted_quads_element_geometry, 1, "{s}");
        let e = quad_element_sicn_values(&mesh);
        assert!((e[0] + 0.339_127_957).abs() < 1e-8, "{e:?}");
        // the element judge needs no model
        let s = MeshStats::compute(&mesh, None);
        assert_eq!(s.inverted_quads_element_geometry, 1, "{s}");
    }
}
