//! A cheap measure of how many quads a size map asks for, before anything is
//! sampled at the target size: the integral `∫ dA / s(x)²` of the size map
//! `s` over every face (ours; the size guard of `crate::methods` turns it
//! into a quad count).
//!
//! The integral is taken on a background whose resolution does not follow
//! the target size `h` down: curves are discretized at
//! `max(h, default size) / ESTIMATE_REFINE` ([`ESTIMATE_REFINE`]) and faces
//! triangulated at twice that ([`FaceTriangulation`], refined), so the cost
//! is that of meshing at the default size or coarser, whatever `h` is. The
//! size map is [`build_size_map`] on that background with the caller's
//! bounds, the faces' curvature bound and the small-feature sizes, but a
//! uniform conformal size per face (no cross field is solved: the conformal
//! scaling keeps each face's `area / h_f²` before the bounds). Per triangle
//! the integrand is the mean of `1 / s²` at its three vertices.
//!
//! The curves are also planned against that map ([`plan_final_curves`];
//! below [`PLAN_DIVISIONS`] of the default size at that size, the map
//! scaled alike and the counts scaled back: the plan samples curves at the
//! sizes), which
//! gives each face's planned boundary edges: a face meshed as a grid by a pattern
//! follows its curves' counts rather than the map
//! ([`SizeIntegral::grid_quads`]).
//!
//! A face whose background triangulation fails is left out and listed in
//! [`SizeIntegral::failed`] (and logged).

use geometry::{FaceId, Model};

use crate::core::error::MeshError;
use crate::core::options::default_size;
use crate::core::patch::NodeRef;
use crate::curves::curve_mesh::{
    discretize_all, largest_faces_first, plan_curves, plan_final_curves,
};
use crate::field::crossfield::{FaceMesh, FaceTopology};
use crate::field::size_map::{build_size_map, typical_curvature, FaceBackground, SizeMapOptions};
use crate::triangulate::face_triangulation::{degenerate_metric, FaceTriangulation};

/// Background size of the estimate: `max(h, default size)` divided by this
/// (triangles of twice that). 2: triangle edges about the quad size at the
/// default size and coarser, a fixed resolution below it.
pub const ESTIMATE_REFINE: f64 = 2.0;

/// The curve plan of the estimate is made at no finer a size than the
/// default size divided by this (counts scaled below it): the plan samples
/// every curve at its sizes, up to 2¹⁸ points a curve (at `--size 1e-5` on
/// i01o_m1 that took 11 s and 1.1 GB). 16: exact down to 1/16 of the default
/// size, 256 times the default quad count.
pub const PLAN_DIVISIONS: f64 = 16.0;

/// The size integral of one model (see the module documentation).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SizeIntegral {
    /// `∫ dA / s²` per face, in face order (0 for a face left out).
    pub per_face: Vec<f64>,
    /// Area of each face on the estimate's background, in face order.
    pub area: Vec<f64>,
    /// Faces whose background triangulation failed (left out).
    pub failed: Vec<FaceId>,
    /// Background triangles the integral was taken on (all faces).
    pub triangles: usize,
    /// Mesh edges on each face's loops in the curve plan against this size
    /// map (a seam counted on both sides), in face order; below
    /// [`PLAN_DIVISIONS`] of the default size, scaled from the plan there.
    pub plan_edges: Vec<f64>,
    /// Length of each face's loops (a seam counted on both sides), in face order.
    pub loop_length: Vec<f64>,
}

impl SizeIntegral {
    /// `∫ dA / s²` over the whole model.
    pub fn total(&self) -> f64 {
        self.per_face.iter().sum()
    }

    /// The quads of face `f` as a structured grid of square cells of its
    /// loops' mean planned spacing: `area · (plan edges / loop length)²`
    /// (exact for an `n × m` grid of squares; what a pattern face makes of
    /// curves the plan refined, e.g. an airfoil's bends). 0 without loops.
    pub fn grid_quads(&self, f: usize) -> f64 {
        if self.loop_length[f] > 0.0 {
            self.area[f] * (self.plan_edges[f] / self.loop_length[f]).powi(2)
        } else {
            0.0
        }
    }

    /// Per face the larger of `∫ dA / s²` and [`SizeIntegral::grid_quads`],
    /// summed: the measure of a method that meshes simple faces by patterns.
    pub fn total_with_grids(&self) -> f64 {
        (0..self.per_face.len())
            .map(|f| self.per_face[f].max(self.grid_quads(f)))
            .sum()
    }
}

/// One face's background for the estimate: the welded triangulation and the
/// model identity of each welded vertex, and the face's typical curvature.
struct EstimateFace {
    topo: FaceTopology,
    refs: Vec<NodeRef>,
    curvature: Option<f64>,
}

/// The background of face `fid` at triangle size `2 · h_bg`.
fn estimate_face(
    model: &Model,
    fid: FaceId,
    cms: &[crate::curves::curve_mesh::CurveMesh],
    h_bg: f64,
) -> Result<EstimateFace, String> {
    let ft = FaceTriangulation::new(model, fid, cms, 2.0 * h_bg)
        .and_then(|mut ft| ft.refine().map(|_| ft))
        .map_err(|e| format!("{e:?}"))?;
    let mesh = FaceMesh::from_face_triangulation(&ft);
    let topo = FaceTopology::build(&mesh).map_err(|e| e.to_string())?;
    let mut refs = vec![NodeRef::Interior; topo.positions.len()];
    for (i, &w) in topo.vertex_map.iter().enumerate() {
        if ft.nodes[i].node != NodeRef::Interior {
            refs[w as usize] = ft.nodes[i].node;
        }
    }
    let uvs: Vec<[f64; 2]> = ft.nodes.iter().map(|n| n.uv).collect();
    let curvature = typical_curvature(&model.faces[fid.idx()], &uvs, &ft.pos, &ft.triangles());
    Ok(EstimateFace {
        topo,
        refs,
        curvature,
    })
}

/// `∫ dA / s²` of the size map `sizing` builds for target size `h` on
/// `model`, on a background of bounded resolution (module documentation).
/// Faces run on the current rayon pool; the result does not depend on the
/// thread count.
pub fn size_integral(
    model: &Model,
    h: f64,
    sizing: &SizeMapOptions,
) -> Result<SizeIntegral, MeshError> {
    if !(h.is_finite() && h > 0.0) {
        return Err(MeshError::InvalidSize(h));
    }
    // a face no plane triangulation can hold: refused before any work (the
    // fuzzer's torus with a major radius of 9.2e18 ran for hours here)
    for (f, face) in model.faces.iter().enumerate() {
        if let Some(reason) = degenerate_metric(face) {
            return Err(MeshError::Face {
                face: FaceId(f as u32),
                reason,
            });
        }
    }
    let h_bg = h.max(default_size(model)) / ESTIMATE_REFINE;
    let cms = discretize_all(model, &plan_curves(model, h_bg));
    let nf = model.faces.len();
    let mut order: Vec<usize> = (0..nf).collect();
    largest_faces_first(model, &cms, &mut order);
    let mut faces: Vec<(usize, Result<EstimateFace, String>)> =
        crate::core::work_queue::map_in_order(&order, |&f| {
            (f, estimate_face(model, FaceId(f as u32), &cms, h_bg))
        });
    faces.sort_by_key(|(f, _)| *f);
    let mut out = SizeIntegral {
        per_face: vec![0.0; nf],
        area: vec![0.0; nf],
        failed: Vec::new(),
        triangles: 0,
        plan_edges: vec![0.0; nf],
        loop_length: vec![0.0; nf],
    };
    let mut ok = Vec::new();
    for (f, r) in &faces {
        match r {
            Ok(ef) => ok.push((*f, ef)),
            Err(why) => {
                tracing::debug!("estimate: face {} left out: {why}", f + 1);
                out.failed.push(FaceId(*f as u32));
            }
        }
    }
    let inputs: Vec<FaceBackground<'_>> = ok
        .iter()
        .map(|(f, ef)| FaceBackground {
            face: FaceId(*f as u32),
            topo: &ef.topo,
            refs: &ef.refs,
            scaling: None,
            curvature: ef.curvature,
        })
        .collect();
    let map = build_size_map(model, &cms, &inputs, h, sizing)
        .map_err(|e| MeshError::Sizing(e.to_string()))?;
    for (k, (f, ef)) in ok.iter().enumerate() {
        let s = map.face_sizes(k);
        let inv2: Vec<f64> = s.iter().map(|&x| 1.0 / (x * x)).collect();
        let mut sum = 0.0;
        for (t, tri) in ef.topo.triangles.iter().enumerate() {
            let w = tri.iter().map(|&v| inv2[v as usize]).sum::<f64>() / 3.0;
            sum += ef.topo.areas[t] * w;
        }
        out.per_face[*f] = sum;
        out.area[*f] = ef.topo.areas.iter().sum();
        out.triangles += ef.topo.triangles.len();
    }
    // the plan samples each curve finer than its sizes: below
    // 1 / PLAN_DIVISIONS of the default size it is made there on the map
    // scaled up alike, and its counts scaled back down (bends tighter than
    // the size refine in proportion to it)
    let scale = (default_size(model) / PLAN_DIVISIONS / h).max(1.0);
    let sizes: Vec<Option<Vec<[f64; 2]>>> = map
        .curve_sizes(model, &cms)
        .into_iter()
        .map(|p| p.map(|p| p.into_iter().map(|[t, s]| [t, s * scale]).collect()))
        .collect();
    let plan = plan_final_curves(model, h * scale, &sizes);
    let lengths: Vec<f64> = cms
        .iter()
        .map(|m| {
            m.points
                .windows(2)
                .map(|w| geometry::vec3::dist(w[0], w[1]))
                .sum()
        })
        .collect();
    for (f, face) in model.faces.iter().enumerate() {
        for u in face.curve_uses() {
            out.plan_edges[f] += 2.0 * plan.counts[u.curve.idx()] as f64 * scale;
            out.loop_length[f] += lengths[u.curve.idx()];
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A size map without bounds or features other than the target size.
    fn uniform(h: f64) -> SizeMapOptions {
        SizeMapOptions {
            min_size: Some(h),
            max_size: Some(h),
            small_features: false,
            ..Default::default()
        }
    }

    #[test]
    fn a_uniform_map_integrates_to_area_over_size_squared() {
        // the square primitive of side 2: area 4
        let model = geometry::primitives::square(2.0);
        for h in [0.5, 0.1, 1e-4] {
            let s = size_integral(&model, h, &uniform(h)).unwrap();
            assert!((s.area[0] - 4.0).abs() < 1e-9, "area {}", s.area[0]);
            let want = 4.0 / (h * h);
            assert!(
                (s.total() / want - 1.0).abs() < 1e-9,
                "{} vs {want}",
                s.total()
            );
        }
    }

    #[test]
    fn a_curved_model_gets_its_area_at_a_bounded_resolution() {
        // sphere of radius 1: area 4π, whatever the (tiny) target size
        let model = geometry::primitives::sphere(1.0);
        let d = default_size(&model);
        let at_default = size_integral(&model, d, &uniform(d)).unwrap();
        let h = 1e-5;
        let s = size_integral(&model, h, &uniform(h)).unwrap();
        let area: f64 = s.area.iter().sum();
        assert!(
            (area / (4.0 * std::f64::consts::PI) - 1.0).abs() < 0.02,
            "area {area}"
        );
        assert!((s.total() * h * h / area - 1.0).abs() < 1e-9);
        // the background below the default size is the default size's
        assert_eq!(s.triangles, at_default.triangles);
        assert!(s.failed.is_empty() && s.triangles > 0);
        // and coarser above it
        let coarse = size_integral(&model, 4.0 * d, &uniform(4.0 * d)).unwrap();
        assert!(coarse.triangles < at_default.triangles);
    }

    #[test]
    fn bad_sizes_are_refused() {
        let model = geometry::primitives::square(1.0);
        for h in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(size_integral(&model, h, &uniform(1.0)).is_err());
        }
    }
}
