//! Cross fields of a whole CAD model, face by face: the "model → field"
//! routine shared by `quadrille field` and the `crossfield_models` example.
//!
//! For every face: the curves are discretized once ([`plan_curves`],
//! [`discretize_all`]) at the *background* size `h_bg = h / refine` (`h` the
//! quad size, [`FieldOptions::refine`] = [`BACKGROUND_REFINE`] by default, and
//! at least the default size / [`MAX_BACKGROUND_DIVISIONS`]);
//! the face is triangulated with the baseline's [`FaceTriangulation`] (target
//! `2 h_bg`, refined); [`FaceMesh::from_face_triangulation`] turns it into
//! cross-field input; [`compute_cross_field`] solves for the field,
//! [`extract_singularities`] finds its singularities and checks relation (2)
//! of the paper ([`Singularities::satisfies_eq2`]), and, when asked,
//! [`conformal_scaling`] gives the size map `e^{H + C}` with `C` chosen for
//! about `area / h²` quads on the face. Faces run in parallel; results are in
//! face order and do not depend on the thread count.
//!
//! A face whose triangulation or field fails does not stop the others: its
//! [`FaceFieldReport::outcome`] holds the reason.

use std::sync::atomic::{AtomicUsize, Ordering};

use geometry::vec3::Vec3;
use geometry::{FaceId, Model};
use mesh::field::{CrossFieldMesh, FieldSingularity};

use crate::core::error::MeshError;
use crate::core::options::{resolve_size, ProgressFn, Size};
use crate::core::patch::NodeRef;
use crate::curves::curve_mesh::CurvePlan;
use crate::curves::curve_mesh::{discretize_all, plan_curves, CurveMesh};
use crate::field::crossfield::{
    compute_cross_field, CrossField, CrossFieldError, CrossFieldOptions, FaceMesh,
};
use crate::field::scaling::{conformal_scaling, scaling_constant};
use crate::field::singularities::{extract_singularities, Singularities};
use crate::field::size_map::{
    build_size_map, FaceBackground, SizeMap, SizeMapError, SizeMapOptions,
};
use crate::triangulate::face_triangulation::FaceTriangulation;

/// Default ratio between the quad size and the background size (the
/// background triangulation has edges of about a third of the quad size).
/// 6 rather than 8: on the 26 shared models the default method then runs in
/// 0.72 of the time at 8 (geometric mean), with the same irregular share and
/// average SICN within noise (BENCHMARKS.md, "Background size").
pub const BACKGROUND_REFINE: f64 = 6.0;

/// The background size never goes below the default quad size (1/24 of the
/// diagonal) divided by this: the fields are smooth, and a background that
/// follows a fine quad size costs time that grows much faster than the
/// output (at `--size-factor 0.0625`, 96 % of the run went to fields on a
/// background of diagonal / 2304). Diagonal / 288 rather than / 576 took
/// the fields on i01o_m1 at size factors 0.125 and 0.0625 from 5 s to 0.7 s
/// with meshes as good or better (BENCHMARKS.md, "Background size").
/// Diagonal / 216 (the background of size factor 0.67) rather than / 288:
/// at 0.0625 the fields take 0.4 s instead of 0.8 s, the run about 10 %
/// less, with 0.173 % irregular vertices instead of 0.163 % and an average
/// SICN 0.001 lower; at 0.125, 0.301 % instead of 0.354 % and 0.003 lower
/// (BENCHMARKS.md, session of 2026-12-02, sixth). At the default size and
/// coarser the bound is not reached.
pub const MAX_BACKGROUND_DIVISIONS: f64 = 9.0;

/// Options of [`model_fields`].
#[derive(Clone)]
pub struct FieldOptions {
    /// Target quad size; the background triangulation is finer by `refine`.
    pub size: Size,
    /// Background size = quad size / `refine` (must be positive).
    pub refine: f64,
    /// Parameters of the cross-field diffusion.
    pub cross_field: CrossFieldOptions,
    /// Also compute the conformal scaling of each face and the model's size map.
    pub size_map: bool,
    /// How the size map is built (gradient, small features, user sizes).
    pub sizing: SizeMapOptions,
    /// Called with `(faces done, total faces)` as faces finish (from worker threads).
    pub progress: Option<ProgressFn>,
}

impl Default for FieldOptions {
    fn default() -> Self {
        FieldOptions {
            size: Size::default(),
            refine: BACKGROUND_REFINE,
            cross_field: CrossFieldOptions::default(),
            size_map: true,
            sizing: SizeMapOptions::default(),
            progress: None,
        }
    }
}

impl std::fmt::Debug for FieldOptions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FieldOptions")
            .field("size", &self.size)
            .field("refine", &self.refine)
            .field("cross_field", &self.cross_field)
            .field("size_map", &self.size_map)
            .field("sizing", &self.sizing)
            .field("progress", &self.progress.as_ref().map(|_| "callback"))
            .finish()
    }
}

/// Why one face has no field.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FaceFieldError {
    /// The background triangulation of the face failed.
    #[error("no background triangulation: {0}")]
    Triangulation(String),
    /// The cross-field solve failed.
    #[error("cross field failed: {0}")]
    CrossField(#[from] CrossFieldError),
}

/// The cross field of one face and what is derived from it.
#[derive(Clone, Debug)]
pub struct FaceField {
    /// The field, on the welded background triangulation (`field.topology`).
    pub field: CrossField,
    /// Its singularities and the corner data of relation (2).
    pub singularities: Singularities,
    /// Model identity of each welded vertex of `field.topology` (curve point,
    /// corner or interior): how faces are welded into one size map.
    pub refs: Vec<NodeRef>,
    /// The conformal scaling `H` per welded vertex, when asked for and when
    /// its solve succeeded.
    pub scaling: Option<Vec<f64>>,
    /// The size map per welded vertex of `field.topology`. From
    /// [`face_field`] alone: the face's conformal size `e^{H + C}`; from
    /// [`model_fields`]: the model's size map ([`crate::field::size_map`]), which
    /// adds small features, gradation and continuity across curves.
    pub size: Option<Vec<f64>>,
    /// The face's typical largest principal curvature
    /// ([`crate::field::size_map::typical_curvature`] of its background nodes).
    pub curvature: Option<f64>,
}

impl FaceField {
    /// Number of background triangles the field lives on.
    pub fn triangles(&self) -> usize {
        self.field.topology.triangles.len()
    }

    /// One unit branch direction of the cross at the barycentre of each
    /// background triangle (`None` where the interpolated cross vanishes).
    pub fn triangle_directions(&self) -> Vec<Option<[Vec3; 2]>> {
        (0..self.triangles())
            .map(|t| self.field.triangle_cross(t))
            .collect()
    }

    /// Index of each boundary CAD corner in relation (2): `2 − n̄` for the
    /// ideal valence `n̄` (a 90° corner gives +1, 180° 0, 270° −1).
    pub fn corner_indices(&self) -> Vec<i64> {
        self.singularities
            .corners
            .iter()
            .map(|c| 2 - c.ideal_valence as i64)
            .collect()
    }
}

/// The outcome for one face of the model.
#[derive(Clone, Debug)]
pub struct FaceFieldReport {
    /// The face.
    pub face: FaceId,
    /// Its field, or why there is none.
    pub outcome: Result<FaceField, FaceFieldError>,
}

impl FaceFieldReport {
    /// True when the face has a field whose singularities satisfy relation (2).
    pub fn euler_ok(&self) -> bool {
        self.outcome
            .as_ref()
            .is_ok_and(|f| f.singularities.satisfies_eq2())
    }
}

/// The fields of every face of a model.
#[derive(Clone, Debug)]
pub struct ModelFields {
    /// The target quad size `h` (model units).
    pub size: f64,
    /// The background size `h / refine` the curves are discretized at.
    pub background_size: f64,
    /// One report per face, in face order.
    pub faces: Vec<FaceFieldReport>,
    /// The background curve meshes the faces were triangulated against.
    pub curves: Vec<CurveMesh>,
    /// The model's size map over the faces that have a field (when asked for).
    pub size_map: Option<SizeMap>,
}

impl ModelFields {
    /// Why the first face without a field has none (`None` when every
    /// face has one): what a command says when no face could be given a
    /// cross field.
    pub fn first_failure(&self) -> Option<String> {
        self.faces
            .iter()
            .find_map(|f| f.outcome.as_ref().err())
            .map(|e| e.to_string())
    }

    /// Number of faces whose field satisfies relation (2).
    pub fn faces_euler_ok(&self) -> usize {
        self.faces.iter().filter(|f| f.euler_ok()).count()
    }

    /// Number of faces without a field (triangulation or solve failed).
    pub fn faces_failed(&self) -> usize {
        self.faces.iter().filter(|f| f.outcome.is_err()).count()
    }

    /// Share of **all** faces (failed ones count as not satisfying it) whose
    /// field satisfies relation (2); 0 for a model without faces.
    pub fn euler_ok_share(&self) -> f64 {
        self.faces_euler_ok() as f64 / self.faces.len().max(1) as f64
    }

    /// Total number of background triangles over the faces that have a field.
    pub fn triangles(&self) -> usize {
        self.faces
            .iter()
            .filter_map(|f| f.outcome.as_ref().ok())
            .map(FaceField::triangles)
            .sum()
    }

    /// Curve quantization against the size map (paper §4.3): each curve's
    /// count from ∫ dl / s, chords of 4-sided faces equalized; without a
    /// size map, the uniform plan for the quad size.
    pub fn curve_plan(&self, model: &Model) -> CurvePlan {
        let sizes = self
            .size_map
            .as_ref()
            .map(|m| m.curve_sizes(model, &self.curves))
            .unwrap_or_default();
        crate::curves::curve_mesh::plan_final_curves(model, self.size, &sizes)
    }

    /// The fields of all faces that have one as a single [`CrossFieldMesh`]
    /// (for files and pictures): each face's welded triangulation, in face
    /// order, turned counter-clockwise about the face's oriented normal
    /// (triangles of `reversed` faces are flipped); per triangle the cross at
    /// its barycentre and the mean size map of its vertices (the size array
    /// is present when at least one face has a size map; NaN elsewhere).
    pub fn to_field_mesh(&self, model: &Model) -> CrossFieldMesh {
        let mut out = CrossFieldMesh::default();
        let any_size = self
            .faces
            .iter()
            .any(|f| f.outcome.as_ref().is_ok_and(|f| f.size.is_some()));
        let mut sizes = Vec::new();
        for report in &self.faces {
            let Ok(ff) = &report.outcome else { continue };
            let topo = &ff.field.topology;
            let base = out.nodes.len() as u32;
            let flip = model
                .faces
                .get(report.face.idx())
                .is_some_and(|f| f.reversed);
            out.nodes.extend_from_slice(&topo.positions);
            for (t, tri) in topo.triangles.iter().enumerate() {
                let tri = if flip { [tri[0], tri[2], tri[1]] } else { *tri };
                out.triangles.push(tri.map(|v| v + base));
                out.triangle_face.push(report.face);
                out.cross.push(ff.field.triangle_cross(t).map(|d| d[0]));
                if any_size {
                    sizes.push(ff.size.as_ref().map_or(f64::NAN, |s| {
                        tri.iter().map(|&v| s[v as usize]).sum::<f64>() / 3.0
                    }));
                }
            }
            out.singularities
                .extend(ff.singularities.list.iter().map(|s| FieldSingularity {
                    position: s.position,
                    index: s.index,
                    face: report.face,
                }));
        }
        out.size = any_size.then_some(sizes);
        out
    }
}

/// Computes the field of face `fid` on its background triangulation, built
/// against the curve meshes `cms` with triangle size `2 · background_size`;
/// `quad_size` sets the size-map constant (about `area / quad_size²` quads).
pub fn face_field(
    model: &Model,
    fid: FaceId,
    cms: &[CurveMesh],
    background_size: f64,
    quad_size: f64,
    opts: &FieldOptions,
) -> Result<FaceField, FaceFieldError> {
    let ft = FaceTriangulation::new(model, fid, cms, 2.0 * background_size)
        .and_then(|mut ft| ft.refine().map(|_| ft))
        .map_err(|e| FaceFieldError::Triangulation(format!("{e:?}")))?;
    let mesh = FaceMesh::from_face_triangulation(&ft);
    let field = compute_cross_field(&mesh, &opts.cross_field)?;
    let mut refs = vec![NodeRef::Interior; field.topology.positions.len()];
    for (i, &w) in field.topology.vertex_map.iter().enumerate() {
        if ft.nodes[i].node != NodeRef::Interior {
            refs[w as usize] = ft.nodes[i].node;
        }
    }
    let singularities = extract_singularities(&field);
    let scaling = if opts.size_map {
        conformal_scaling(&field)
            .ok()
            .map(|s| s.h)
            .filter(|h| h.iter().all(|x| x.is_finite()))
    } else {
        None
    };
    let size = scaling
        .as_ref()
        .and_then(|h| face_conformal_size(&field, h, quad_size));
    let face = &model.faces[fid.idx()];
    let uvs: Vec<[f64; 2]> = ft.nodes.iter().map(|n| n.uv).collect();
    let curvature = crate::field::size_map::typical_curvature(face, &uvs, &ft.pos, &ft.triangles());
    Ok(FaceField {
        field,
        singularities,
        refs,
        scaling,
        size,
        curvature,
    })
}

/// `e^{H + C}` per welded vertex, `C` set for `area / quad_size²` quads;
/// `None` when the constant cannot be computed.
fn face_conformal_size(field: &CrossField, h: &[f64], quad_size: f64) -> Option<Vec<f64>> {
    let topo = &field.topology;
    let area: f64 = topo.areas.iter().sum();
    let c = scaling_constant(topo, h, area / (quad_size * quad_size)).ok()?;
    let sizes: Vec<f64> = h.iter().map(|&x| (x + c).exp()).collect();
    sizes.iter().all(|s| s.is_finite()).then_some(sizes)
}

/// Computes the cross field of every face of `model` (see the module
/// documentation). Errors only on an invalid model, a model without faces, or
/// an invalid size; per-face failures are reported in the result.
pub fn model_fields(model: &Model, opts: &FieldOptions) -> Result<ModelFields, MeshError> {
    model.validate()?;
    if model.faces.is_empty() {
        return Err(MeshError::NoFaces);
    }
    let h = resolve_size(model, opts.size)?;
    if !(opts.refine.is_finite() && opts.refine > 0.0) {
        return Err(MeshError::InvalidSize(opts.refine));
    }
    let h_bg =
        (h / opts.refine).max(crate::core::options::default_size(model) / MAX_BACKGROUND_DIVISIONS);
    let cms = discretize_all(model, &plan_curves(model, h_bg));
    let nf = model.faces.len();
    let done = AtomicUsize::new(0);
    let mut order: Vec<usize> = (0..nf).collect();
    crate::curves::curve_mesh::largest_faces_first(model, &cms, &mut order);
    let mut faces: Vec<FaceFieldReport> = crate::core::work_queue::map_in_order(&order, |&f| {
        let face = FaceId(f as u32);
        let outcome = face_field(model, face, &cms, h_bg, h, opts);
        let d = done.fetch_add(1, Ordering::Relaxed) + 1;
        if let Some(p) = &opts.progress {
            p(d, nf);
        }
        FaceFieldReport { face, outcome }
    });
    faces.sort_by_key(|r| r.face.0);
    let mut fields = ModelFields {
        size: h,
        background_size: h_bg,
        faces,
        curves: cms,
        size_map: None,
    };
    if opts.size_map {
        let started = std::time::Instant::now();
        fields.apply_size_map(model, &opts.sizing)?;
        if tracing::enabled!(tracing::Level::DEBUG) {
            tracing::debug!("size map in {:.4} s", started.elapsed().as_secs_f64());
        }
    }
    Ok(fields)
}

impl ModelFields {
    /// Builds the model's size map from the faces' fields and stores it,
    /// replacing each face's conformal size with it.
    fn apply_size_map(&mut self, model: &Model, sizing: &SizeMapOptions) -> Result<(), MeshError> {
        let ok: Vec<usize> = (0..self.faces.len())
            .filter(|&i| self.faces[i].outcome.is_ok())
            .collect();
        let inputs: Vec<FaceBackground<'_>> = ok
            .iter()
            .map(|&i| {
                let f = self.faces[i].outcome.as_ref().expect("filtered on ok");
                FaceBackground {
                    face: self.faces[i].face,
                    topo: &f.field.topology,
                    refs: &f.refs,
                    scaling: f.scaling.as_deref(),
                    curvature: f.curvature,
                }
            })
            .collect();
        let map = build_size_map(model, &self.curves, &inputs, self.size, sizing)
            .map_err(|e: SizeMapError| MeshError::Sizing(e.to_string()))?;
        for (k, &i) in ok.iter().enumerate() {
            if let Ok(f) = &mut self.faces[i].outcome {
                let sizes = map.face_sizes(k);
                for s in &mut f.singularities.list {
                    s.size = s.size_from(&f.field.topology, &sizes);
                }
                f.size = Some(sizes);
            }
        }
        self.size_map = Some(map);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn background_size_stops_at_a_fraction_of_the_default_size() {
        // square of side 2: diagonal 2√2, default size 2√2 / DEFAULT_DIVISIONS
        let model = geometry::primitives::square(2.0);
        let default = crate::core::options::default_size(&model);
        // a coarse quad size: h / BACKGROUND_REFINE
        let f = model_fields(
            &model,
            &FieldOptions {
                size: Size::Absolute(0.5),
                size_map: false,
                ..Default::default()
            },
        )
        .unwrap();
        assert!((f.background_size - 0.5 / BACKGROUND_REFINE).abs() < 1e-12);
        // a quad size 16 × finer than the default: the background stops at
        // default / MAX_BACKGROUND_DIVISIONS
        let f = model_fields(
            &model,
            &FieldOptions {
                size: Size::Factor(1.0 / 16.0),
                size_map: false,
                ..Default::default()
            },
        )
        .unwrap();
        assert!(
            (f.background_size - default / MAX_BACKGROUND_DIVISIONS).abs() < 1e-12,
            "{}",
            f.background_size
        );
        assert!(f.faces[0].outcome.is_ok());
    }

    #[test]
    fn square_model_has_a_regular_field_and_a_uniform_size() {
        let model = geometry::primitives::square(2.0);
        let fields = model_fields(
            &model,
            &FieldOptions {
                size: Size::Absolute(0.5),
                ..Default::default()
            },
        )
        .unwrap();
        assert_eq!(fields.faces.len(), 1);
        assert!((fields.background_size - 0.5 / BACKGROUND_REFINE).abs() < 1e-12);
        let f = fields.faces[0].outcome.as_ref().expect("field");
        assert!(
            f.singularities.list.is_empty(),
            "{:?}",
            f.singularities.list
        );
        assert_eq!(f.corner_indices(), [1, 1, 1, 1]);
        assert!(fields.faces[0].euler_ok());
        assert_eq!(fields.faces_euler_ok(), 1);
        assert_eq!(fields.euler_ok_share(), 1.0);
        assert_eq!(fields.triangles(), f.triangles());
        // crosses follow the square's sides
        for d in f.triangle_directions().into_iter().flatten() {
            let c = d[0][0].abs().max(d[0][1].abs());
            assert!(c > 0.99, "cross {:?} not aligned with the sides", d[0]);
        }
        // about 16 quads of side 0.5: the size map is ≈ 0.5 everywhere
        let s = f.size.as_ref().expect("size map");
        assert!(
            s.iter().all(|&x| (x - 0.5).abs() < 0.02),
            "sizes {:?}",
            &s[..4]
        );
        // as one mesh for files and pictures
        let fm = fields.to_field_mesh(&model);
        assert!(fm.check().is_ok());
        assert_eq!(fm.triangles.len(), f.triangles());
        assert!(fm.singularities.is_empty());
        assert_eq!(fm.size.as_ref().map(Vec::len), Some(f.triangles()));
    }

    #[test]
    fn cylinder_side_takes_the_parallel_field_along_its_axis() {
        let model = geometry::primitives::cylinder(1.0, 2.0);
        let fields = model_fields(
            &model,
            &FieldOptions {
                size: Size::Absolute(0.4),
                ..Default::default()
            },
        )
        .unwrap();
        let mut sides = 0;
        for report in &fields.faces {
            let f = report.outcome.as_ref().expect("field");
            if f.singularities.list.is_empty() {
                // the side: no diffusion ran, one branch along z everywhere
                sides += 1;
                assert!(f.field.levels.is_empty());
                // (within the tilt of a secant triangle's plane)
                for d in f.triangle_directions().into_iter().flatten() {
                    let along = d[0][2].abs().max(d[1][2].abs());
                    assert!(along > 0.99, "cross {d:?} off the axis");
                }
            } else {
                // a disc: round boundary, the diffusion and its singularities
                assert!(!f.field.levels.is_empty());
            }
        }
        assert_eq!(sides, 1);
    }

    #[test]
    fn field_mesh_triangles_follow_the_oriented_normal() {
        for reversed in [false, true] {
            let mut model = geometry::primitives::square(1.0);
            model.faces[0].reversed = reversed;
            let fields = model_fields(
                &model,
                &FieldOptions {
                    size: Size::Absolute(0.5),
                    size_map: false,
                    ..Default::default()
                },
            )
            .unwrap();
            let fm = fields.to_field_mesh(&model);
            assert!(fm.size.is_none());
            let want = model.faces[0].normal([0.5, 0.5]).unwrap();
            for t in &fm.triangles {
                let p = t.map(|v| fm.nodes[v as usize]);
                let n = geometry::vec3::cross(
                    geometry::vec3::sub(p[1], p[0]),
                    geometry::vec3::sub(p[2], p[0]),
                );
                assert!(geometry::vec3::dot(n, want) > 0.0, "reversed = {reversed}");
            }
        }
    }

    #[test]
    fn bad_sizes_are_refused() {
        let model = geometry::primitives::square(1.0);
        assert!(model_fields(
            &model,
            &FieldOptions {
                size: Size::Absolute(-1.0),
                ..Default::default()
            }
        )
        .is_err());
        assert!(model_fields(
            &model,
            &FieldOptions {
                refine: 0.0,
                ..Default::default()
            }
        )
        .is_err());
    }

    #[test]
    fn progress_reaches_the_face_count() {
        let model = geometry::primitives::sphere(1.0);
        let last = std::sync::Arc::new(AtomicUsize::new(0));
        let l = last.clone();
        let progress: ProgressFn = std::sync::Arc::new(move |d, n| {
            assert!(d <= n);
            l.fetch_max(d, Ordering::Relaxed);
        });
        let fields = model_fields(
            &model,
            &FieldOptions {
                progress: Some(progress),
                size_map: false,
                ..Default::default()
            },
        )
        .unwrap();
        assert_eq!(last.load(Ordering::Relaxed), model.faces.len());
        let sum: i64 = fields
            .faces
            .iter()
            .filter_map(|f| f.outcome.as_ref().ok())
            .map(|f| f.singularities.index_sum())
            .sum();
        assert_eq!(sum, 8, "a sphere's indices add up to 4χ = 8");
        assert!(fields
            .faces
            .iter()
            .all(|f| f.outcome.as_ref().unwrap().size.is_none()));
    }
}
