//! Cross-field singularities of one face (paper §3.2, spec §3).
//!
//! Index (Eq. 5, factor 2/π so that +1 ↔ valence 3, −1 ↔ valence 5) is
//! measured on closed loops through edge midpoints. With one cross per edge
//! (Crouzeix–Raviart), the loops through the midpoints of the spokes of an
//! interior vertex (its *vertex region*) and the loops through the three edge
//! midpoints of each triangle (its *medial triangle*) tile the surface, and
//! every mid-segment is walked once in each direction. So the vertex indices
//! (with the angle defect of the vertex, spec §3.1) plus the triangle indices
//! add up **exactly** to the index of the whole face: on a closed surface
//! their sum is 4χ whatever the field. A singularity is stored at the 3D
//! position of its vertex or at the barycentre of its triangle; a
//! singularity that sits on an edge midpoint (where the two regions meet) is
//! reported by one of the regions next to that edge.
//!
//! Compatibility fix (spec §3.3): one artificial singularity of index +1 is
//! added at each CAD corner whose interior angle is below 45°.
//! [`Singularities::satisfies_eq2`] checks relation (2) of the paper, written
//! as `Σ singularity indices = 4χ − Σ_corners (2 − n̄_c)` with the ideal
//! corner valence `n̄ = clamp(round(γ / 90°), 1, 4)`.

use std::f64::consts::PI;

use geometry::vec3::{self, Vec3};
use geometry::CornerId;

use crate::core::valence::ideal_corner_valence;
use crate::field::crossfield::topology::arg_ratio;
use crate::field::crossfield::{CrossField, VertexClass};

/// Corners sharper than this (radians) get an artificial +1 singularity.
pub const ACUTE_CORNER_ANGLE: f64 = PI / 4.0;

/// Where a singularity was found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SingularitySite {
    /// The region around a (welded) vertex of the triangulation.
    Vertex(u32),
    /// The medial triangle of a triangle.
    Triangle(u32),
    /// Added at an acute CAD corner (welded vertex id and corner).
    AcuteCorner(u32, CornerId),
}

/// One cross-field singularity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Singularity {
    /// Index in quad-mesh units: +1 ↔ valence 3, −1 ↔ valence 5.
    pub index: i32,
    /// Its 3D position (a vertex or a triangle barycentre).
    pub position: Vec3,
    /// What it sits on.
    pub site: SingularitySite,
    /// The size map at it, once the model's size map is known
    /// ([`crate::field::field_report::ModelFields`]); the cavity stage measures its
    /// match radius in this size (spec §10.2: ρ · s(p_σ)).
    pub size: Option<f64>,
}

impl Singularity {
    /// The mean of `size` (per welded vertex of `topo`) over the
    /// singularity's site: its vertex, or its triangle's three vertices.
    pub fn size_from(
        &self,
        topo: &crate::field::crossfield::FaceTopology,
        size: &[f64],
    ) -> Option<f64> {
        let at = |v: u32| size.get(v as usize).copied();
        let s = match self.site {
            SingularitySite::Vertex(v) | SingularitySite::AcuteCorner(v, _) => at(v)?,
            SingularitySite::Triangle(t) => {
                let tri = topo.triangles.get(t as usize)?;
                (at(tri[0])? + at(tri[1])? + at(tri[2])?) / 3.0
            }
        };
        (s > 0.0 && s.is_finite()).then_some(s)
    }
}

/// A CAD corner on the face boundary with its interior angle and ideal valence.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundaryCorner {
    /// Welded vertex id.
    pub vertex: u32,
    /// The CAD corner.
    pub corner: CornerId,
    /// Interior angle γ of the face at the corner (sum of triangle angles), radians.
    pub angle: f64,
    /// Ideal quad valence `clamp(round(γ / 90°), 1, 4)`.
    pub ideal_valence: i32,
}

/// The singularities of a face, with what relation (2) needs.
#[derive(Clone, Debug)]
pub struct Singularities {
    /// Singularities, vertices first (by id), then triangles (by id), then
    /// acute corners; each entry has index ±1 (a region of index k gives |k| entries).
    pub list: Vec<Singularity>,
    /// CAD corners on the triangulation boundary.
    pub corners: Vec<BoundaryCorner>,
    /// Euler characteristic of the welded triangulation.
    pub euler_characteristic: i64,
}

impl Singularities {
    /// Sum of the singularity indices (including acute-corner ones).
    pub fn index_sum(&self) -> i64 {
        self.list.iter().map(|s| s.index as i64).sum()
    }

    /// What relation (2) demands of that sum: `4χ − Σ_corners (2 − n̄_c)`.
    pub fn expected_index_sum(&self) -> i64 {
        4 * self.euler_characteristic
            - self
                .corners
                .iter()
                .map(|c| (2 - c.ideal_valence) as i64)
                .sum::<i64>()
    }

    /// True when singularity and corner indices satisfy relation (2).
    pub fn satisfies_eq2(&self) -> bool {
        self.index_sum() == self.expected_index_sum()
    }

    /// Number of singularities of index `k`.
    pub fn count(&self, k: i32) -> usize {
        self.list.iter().filter(|s| s.index == k).count()
    }
}

/// Per triangle, the representation-angle steps `d[a] = arg(w_{a+1} / w_a)`
/// between its edge crosses expressed in the triangle frame (indices mod 3).
fn triangle_steps(field: &CrossField, t: usize) -> [f64; 3] {
    let w = [
        field.in_triangle(t, 0),
        field.in_triangle(t, 1),
        field.in_triangle(t, 2),
    ];
    [
        arg_ratio(w[0], w[1]),
        arg_ratio(w[1], w[2]),
        arg_ratio(w[2], w[0]),
    ]
}

/// Index of each welded vertex region (0 for vertices on the triangulation
/// boundary, whose loop is open): `round((2/π)(Σ Δθ + K_i))`, Δθ the cross-angle
/// steps between consecutive spokes and `K_i = 2π − Σ corner angles`.
pub fn vertex_indices(field: &CrossField) -> Vec<i32> {
    let topo = &field.topology;
    let nv = topo.positions.len();
    let mut steps = vec![0.0; nv];
    let mut angles = vec![0.0; nv];
    for t in 0..topo.triangles.len() {
        let d = triangle_steps(field, t);
        for p in 0..3 {
            let v = topo.triangles[t][p] as usize;
            // from spoke (local edge p+2) to spoke (local edge p+1): −d[p+1]
            steps[v] -= d[(p + 1) % 3];
            angles[v] += topo.corner_angle(t, p);
        }
    }
    (0..nv)
        .map(|v| {
            if topo.on_boundary[v] {
                0
            } else {
                ((2.0 / PI) * (steps[v] / 4.0 + 2.0 * PI - angles[v])).round() as i32
            }
        })
        .collect()
}

/// Index of each medial triangle: `round(Σ_a d[a] / 2π)` (a flat loop).
pub fn triangle_indices(field: &CrossField) -> Vec<i32> {
    (0..field.topology.triangles.len())
        .map(|t| {
            let d = triangle_steps(field, t);
            ((d[0] + d[1] + d[2]) / (2.0 * PI)).round() as i32
        })
        .collect()
}

/// CAD corners that lie on the triangulation boundary, with their interior angle.
pub fn boundary_corners(field: &CrossField) -> Vec<BoundaryCorner> {
    let topo = &field.topology;
    let mut angle = vec![0.0; topo.positions.len()];
    for t in 0..topo.triangles.len() {
        for p in 0..3 {
            angle[topo.triangles[t][p] as usize] += topo.corner_angle(t, p);
        }
    }
    let mut out = Vec::new();
    for v in 0..topo.positions.len() {
        if let VertexClass::Corner(c) = topo.class[v] {
            if topo.on_boundary[v] {
                out.push(BoundaryCorner {
                    vertex: v as u32,
                    corner: c,
                    angle: angle[v],
                    ideal_valence: ideal_corner_valence(angle[v]),
                });
            }
        }
    }
    out
}

/// Extracts the singularities of `field` (vertex and triangle regions, plus
/// one +1 at each acute corner) and the corner data of relation (2).
pub fn extract_singularities(field: &CrossField) -> Singularities {
    let topo = &field.topology;
    let mut list = Vec::new();
    for (v, &k) in vertex_indices(field).iter().enumerate() {
        for _ in 0..k.unsigned_abs() {
            list.push(Singularity {
                index: k.signum(),
                position: topo.positions[v],
                site: SingularitySite::Vertex(v as u32),
                size: None,
            });
        }
    }
    for (t, &k) in triangle_indices(field).iter().enumerate() {
        let tri = topo.triangles[t];
        let mut c = [0.0; 3];
        for &v in &tri {
            c = vec3::add(c, topo.positions[v as usize]);
        }
        let c = vec3::scale(c, 1.0 / 3.0);
        for _ in 0..k.unsigned_abs() {
            list.push(Singularity {
                index: k.signum(),
                position: c,
                site: SingularitySite::Triangle(t as u32),
                size: None,
            });
        }
    }
    let corners = boundary_corners(field);
    for c in &corners {
        if c.angle < ACUTE_CORNER_ANGLE {
            list.push(Singularity {
                index: 1,
                position: topo.positions[c.vertex as usize],
                site: SingularitySite::AcuteCorner(c.vertex, c.corner),
                size: None,
            });
        }
    }
    Singularities {
        list,
        corners,
        euler_characteristic: topo.euler_characteristic(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::crossfield::{compute_cross_field, CrossFieldOptions};
    use crate::fixtures::crossfield_meshes as fixtures;

    fn singularities_of(mesh: &crate::field::crossfield::FaceMesh) -> Singularities {
        let f = compute_cross_field(mesh, &CrossFieldOptions::default()).expect("cross field");
        extract_singularities(&f)
    }

    #[test]
    fn ideal_valences() {
        assert_eq!(ideal_corner_valence(PI / 2.0), 1);
        assert_eq!(ideal_corner_valence(PI / 6.0), 1);
        assert_eq!(ideal_corner_valence(PI), 2);
        assert_eq!(ideal_corner_valence(1.5 * PI), 3);
        assert_eq!(ideal_corner_valence(1.9 * PI), 4);
    }

    #[test]
    fn square_has_no_interior_singularity() {
        let s = singularities_of(&fixtures::square_grid(1.0, 24));
        assert!(s.list.is_empty(), "{:?}", s.list);
        assert_eq!(s.corners.len(), 4);
        assert!(s.corners.iter().all(|c| c.ideal_valence == 1));
        assert_eq!(s.euler_characteristic, 1);
        assert!(s.satisfies_eq2());
    }

    #[test]
    fn disk_has_four_plus_one_singularities() {
        let s = singularities_of(&fixtures::disk(24));
        assert_eq!(s.count(1), 4, "{:?}", s.list);
        assert_eq!(s.count(-1), 0);
        assert!(s.satisfies_eq2());
        // about 90° apart, inside the disk, away from the boundary layer
        let mut ang: Vec<f64> = s
            .list
            .iter()
            .map(|x| x.position[1].atan2(x.position[0]))
            .collect();
        ang.sort_by(f64::total_cmp);
        for i in 0..4 {
            let gap = (ang[(i + 1) % 4] - ang[i]).rem_euclid(2.0 * PI);
            assert!((gap - PI / 2.0).abs() < 0.35, "gaps {ang:?}");
        }
        for x in &s.list {
            let r = vec3::norm(x.position);
            assert!(r > 0.2 && r < 0.92, "radius {r}");
        }
    }

    #[test]
    fn sphere_indices_sum_to_eight() {
        let s = singularities_of(&fixtures::uv_sphere(1.0, 48, 24));
        assert_eq!(s.euler_characteristic, 2);
        assert_eq!(s.index_sum(), 8, "{:?}", s.list);
        assert!(s.corners.is_empty());
        assert!(s.satisfies_eq2());
    }

    #[test]
    fn torus_and_annulus_sum_to_zero() {
        let t = singularities_of(&fixtures::torus(2.0, 0.7, 48, 20));
        assert_eq!(t.euler_characteristic, 0);
        assert_eq!(t.index_sum(), 0);
        let a = singularities_of(&fixtures::annulus(0.5, 1.0, 12, 64));
        assert_eq!(a.euler_characteristic, 0);
        assert_eq!(a.index_sum(), 0);
        assert!(
            a.list.is_empty(),
            "annulus field should be regular: {:?}",
            a.list
        );
        assert!(a.satisfies_eq2());
    }

    #[test]
    fn polygons_satisfy_relation_two() {
        // equilateral triangle: n̄ = 1 at 60° corners, one +1 inside
        let tri = fixtures::convex_polygon(&[[0.0, 0.0], [1.0, 0.0], [0.5, 0.75f64.sqrt()]], 14);
        let s = singularities_of(&tri);
        assert_eq!(s.index_sum(), 1);
        assert!(s.satisfies_eq2());
        // regular pentagon (108°, n̄ = 1): one −1
        let pent: Vec<[f64; 2]> = (0..5)
            .map(|k| {
                [
                    (2.0 * PI * k as f64 / 5.0).cos(),
                    (2.0 * PI * k as f64 / 5.0).sin(),
                ]
            })
            .collect();
        let s = singularities_of(&fixtures::convex_polygon(&pent, 14));
        assert_eq!(s.count(-1), 1, "{:?}", s.list);
        assert!(s.satisfies_eq2());
        // regular hexagon (120°, n̄ = 1): sum −2
        let hex: Vec<[f64; 2]> = (0..6)
            .map(|k| [(PI * k as f64 / 3.0).cos(), (PI * k as f64 / 3.0).sin()])
            .collect();
        let s = singularities_of(&fixtures::convex_polygon(&hex, 14));
        assert_eq!(s.index_sum(), -2);
        assert!(s.satisfies_eq2());
    }

    #[test]
    fn acute_wedge_gets_an_artificial_singularity() {
        let a = 30f64.to_radians();
        let wedge = fixtures::convex_polygon(&[[0.0, 0.0], [1.0, 0.0], [a.cos(), a.sin()]], 16);
        let s = singularities_of(&wedge);
        let acute: Vec<_> = s
            .list
            .iter()
            .filter(|x| matches!(x.site, SingularitySite::AcuteCorner(..)))
            .collect();
        assert_eq!(acute.len(), 1);
        assert_eq!(acute[0].position, [0.0, 0.0, 0.0]);
        assert!(
            s.satisfies_eq2(),
            "sum {} expected {}",
            s.index_sum(),
            s.expected_index_sum()
        );
    }
}
