//! The cone proposal (spec §4.1): the boundary-aligned cross field of the
//! whole shell as one [`FaceMesh`] (creases sharper than
//! [`CREASE_ANGLE_DEGREES`] aligned too), its singularities (vertex regions
//! and medial triangles, `field::singularities`) snapped to shell vertices,
//! and the boundary corners at I = 2 − n̄ (`ricci::boundary_corner_cones`).

use geometry::vec3::{cross, dist, dot, norm, sub};
use geometry::{CornerId, CurveId};

use super::{check_cones, ConeError};
use crate::field::crossfield::{compute_cross_field, CrossFieldOptions, FaceMesh, VertexClass};
use crate::field::singularities::{extract_singularities, SingularitySite};
use crate::ricci::{boundary_corner_cones, Cone};
use crate::shell::{Shell, ShellTopology, NO_FACE};

/// Interior edges whose dihedral angle (between the two triangle normals)
/// is above this many degrees are creases: the field is aligned to them,
/// like the default `--feature-angle`.
pub const CREASE_ANGLE_DEGREES: f64 = 30.0;

fn unit_normal(shell: &Shell, t: [usize; 3]) -> [f64; 3] {
    let [a, b, c] = t.map(|v| shell.vertices[v]);
    let n = cross(sub(b, a), sub(c, a));
    let l = norm(n);
    if l > 0.0 {
        [n[0] / l, n[1] / l, n[2] / l]
    } else {
        n
    }
}

/// The shell as cross-field input: boundary corners as CAD corners, other
/// boundary vertices on one curve, creases as feature edges.
fn field_mesh(shell: &Shell, topo: &ShellTopology, corners: &[Cone]) -> FaceMesh {
    let mut vertex_class: Vec<VertexClass> = topo
        .on_boundary
        .iter()
        .map(|&b| {
            if b {
                VertexClass::Curve(CurveId(0))
            } else {
                VertexClass::Interior
            }
        })
        .collect();
    for (k, c) in corners.iter().enumerate() {
        vertex_class[c.vertex] = VertexClass::Corner(CornerId(k as u32));
    }
    let normals: Vec<[f64; 3]> = shell
        .triangles
        .iter()
        .map(|&t| unit_normal(shell, t))
        .collect();
    let crease_cos = CREASE_ANGLE_DEGREES.to_radians().cos();
    let feature_edges = topo
        .edges
        .iter()
        .zip(&topo.edge_faces)
        .filter(|(_, f)| f[0] != NO_FACE && f[1] != NO_FACE)
        .filter(|(_, f)| dot(normals[f[0]], normals[f[1]]) < crease_cos)
        .map(|(&[a, b], _)| [a as u32, b as u32])
        .collect();
    FaceMesh {
        uv: vec![[0.0, 0.0]; shell.vertices.len()],
        xyz: shell.vertices.clone(),
        triangles: shell
            .triangles
            .iter()
            .map(|t| t.map(|v| v as u32))
            .collect(),
        vertex_class,
        feature_edges,
    }
}

/// The interior vertex nearest `p` among `candidates`, else among all.
fn nearest_interior(
    shell: &Shell,
    topo: &ShellTopology,
    candidates: &[usize],
    p: [f64; 3],
) -> Option<usize> {
    let best = |it: &mut dyn Iterator<Item = usize>| {
        it.filter(|&v| !topo.on_boundary[v]).min_by(|&a, &b| {
            dist(shell.vertices[a], p)
                .total_cmp(&dist(shell.vertices[b], p))
                .then(a.cmp(&b))
        })
    };
    best(&mut candidates.iter().copied()).or_else(|| best(&mut (0..shell.vertices.len())))
}

/// Proposes the cones of `shell` (spec §4.1) and checks them
/// ([`check_cones`]: Σ I = 4χ, interior I ≤ 3, boundary I ≤ 1). Cones come
/// sorted by vertex; singularities snapped to one vertex add up (−1, −1 →
/// −2; +1, −1 → none). The cross field's extra +1 at acute corners is left
/// out: the corner's own index (at most 1) stands for it.
pub fn propose_cones(shell: &Shell, topo: &ShellTopology) -> Result<Vec<Cone>, ConeError> {
    let corners = boundary_corner_cones(shell, topo);
    let mesh = field_mesh(shell, topo, &corners);
    let field = compute_cross_field(&mesh, &CrossFieldOptions::default())
        .map_err(|e| ConeError::Field(e.to_string()))?;
    let ft = &field.topology;
    // Welded field vertex → the first shell vertex mapped to it.
    let mut shell_of = vec![usize::MAX; ft.positions.len()];
    for (v, &w) in ft.vertex_map.iter().enumerate() {
        if let Some(s) = shell_of.get_mut(w as usize) {
            if *s == usize::MAX {
                *s = v;
            }
        }
    }
    let mut index = vec![0i32; shell.vertices.len()];
    for s in &extract_singularities(&field).list {
        let (candidates, at): (Vec<usize>, [f64; 3]) = match s.site {
            SingularitySite::Vertex(w) => (vec![shell_of[w as usize]], s.position),
            SingularitySite::Triangle(t) => (
                ft.triangles[t as usize]
                    .iter()
                    .map(|&w| shell_of[w as usize])
                    .collect(),
                s.position,
            ),
            SingularitySite::AcuteCorner(..) => continue,
        };
        let candidates: Vec<usize> = candidates
            .into_iter()
            .filter(|&v| v < shell.vertices.len())
            .collect();
        if let Some(v) = nearest_interior(shell, topo, &candidates, at) {
            index[v] += s.index;
        }
    }
    let mut cones: Vec<Cone> = index
        .iter()
        .enumerate()
        .filter(|&(_, &i)| i != 0)
        .map(|(vertex, &index)| Cone { vertex, index })
        .chain(corners)
        .collect();
    cones.sort_by_key(|c| c.vertex);
    check_cones(shell, topo, &cones, "cone proposal")?;
    Ok(cones)
}
