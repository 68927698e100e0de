//! The baseline mesher of one face: triangulate it in (u, v) against the
//! curve meshes, refine to the size, split every triangle into three quads
//! on the CAD, smooth and untangle. Not from a paper: it is always valid
//! where a face can be meshed at all, so every other method falls back on
//! it face by face. When quads stay invalid it tries normal layers, then
//! asks the driver ([`crate::methods::driver`]) for finer curves.
//!
//! As a method ([`crate::MeshMethod::Baseline`], [`mesh_baseline`]): curves
//! at the target size, every face by this mesher, assembly.

use std::collections::BTreeSet;

use geometry::{CornerId, CurveId, FaceId, Model};
use mesh::QuadMesh;

use crate::core::error::MeshError;
use crate::curves::curve_mesh::plan_curves;
use crate::methods::driver::{assemble, mesh_faces, FaceContext};
use crate::methods::options::MeshOptions;
use crate::methods::report::{timed, FaceOutcome, MadeBy, MeshReport, StageTimes};

use crate::core::patch::{FaceFailure, FailureSpot};
use crate::core::patch::QuadPatch;
use crate::core::quality::quad_quality;
use crate::curves::curve_mesh::CurveMesh;
use crate::smoothing::smooth_then_untangle;
use crate::triangulate::face_triangulation::FaceTriangulation;
use crate::triangulate::split::split_triangles;

/// A face with more bad quads than this (or than 5 % of its quads) fails at
/// once instead of asking for finer curves.
const MAX_REFINABLE_BAD: usize = 16;
/// Smoothing sweeps per face.
const BASELINE_LAPLACIAN_SWEEPS: usize = 4;

/// The baseline method: curves planned at the target size `h`, every face
/// meshed by [`mesh_face`] (triangles at twice `h`, split into quads of
/// about `h`), the model's mesh assembled; `merged` lists the corners of
/// collapsed sliver curves (none for this method's own callers).
pub(crate) fn mesh_baseline(
    model: &Model,
    h: f64,
    opts: &MeshOptions,
    merged: &[CornerId],
) -> Result<(QuadMesh, MeshReport), MeshError> {
    let mut times = StageTimes::default();
    let plan = timed(&mut times.curves, "curve plan", || plan_curves(model, h));
    let face_mesher = |ctx: &FaceContext<'_>, ft: &mut StageTimes| {
        timed(&mut ft.fallback, "baseline", || {
            mesh_face(ctx.model, ctx.fid, ctx.cms, 2.0 * h)
        })
        .map(|p| FaceOutcome::new(p, MadeBy::Method))
    };
    let (cms, results) = mesh_faces(
        model,
        plan,
        opts.progress.as_ref(),
        &face_mesher,
        // the classes doubled, as before local refinement: the regular
        // method regularizes the default method's mesh where this fails
        // (local rounds let the socket-weld flange's baseline through, and
        // its regular mesh fell from average SICN 0.84 to 0.52)
        false,
        &mut times,
    )?;
    let m = timed(&mut times.assembly, "assembly", || {
        assemble(model, &cms, &results, merged)
    })?;
    Ok((
        m,
        MeshReport {
            times,
            ..Default::default()
        },
    ))
}

/// Meshes one face against the given curve meshes; `target` is the triangle
/// size. When quads stay invalid, it tries once more with normal layers
/// ([`FaceTriangulation::insert_normal_layers`]) before asking for finer
/// curves. When quads stay invalid all over the face, it asks for all of the
/// face's curves finer (the caller's rounds are capped): at a size larger
/// than a curved face (i04o_m4 at size factor 4: a quarter torus of tube
/// radius 1 against triangles of 13) the boundary had a few segments, the
/// refinement crowded nodes onto a boundary curve and 7 266 of 63 588 quads
/// folded, at any triangle size; with finer curves the face meshes.
pub fn mesh_face(
    model: &Model,
    fid: FaceId,
    cms: &[CurveMesh],
    target: f64,
) -> Result<QuadPatch, FaceFailure> {
    match mesh_face_at(model, fid, cms, target) {
        Err(FaceFailure::Fatal(reason)) => {
            let curves: BTreeSet<CurveId> = model.faces[fid.idx()]
                .curve_uses()
                .map(|u| u.curve)
                .filter(|c| !model.curves[c.idx()].degenerate)
                .collect();
            if curves.is_empty() {
                Err(FaceFailure::Fatal(reason))
            } else {
                Err(FaceFailure::RefineCurves(
                    curves.into_iter().collect(),
                    reason,
                ))
            }
        }
        r => r,
    }
}

/// [`mesh_face`] at one triangle size.
fn mesh_face_at(
    model: &Model,
    fid: FaceId,
    cms: &[CurveMesh],
    target: f64,
) -> Result<QuadPatch, FaceFailure> {
    let face = &model.faces[fid.idx()];
    let mut attempt = mesh_face_once(model, fid, cms, target, false)?;
    if attempt.2.is_empty() {
        return Ok(attempt.0);
    }
    if let Ok(second) = mesh_face_once(model, fid, cms, target, true) {
        if second.2.len() < attempt.2.len() {
            attempt = second;
        }
    }
    let (patch, ft_tris, bad, ft_mid) = (attempt.0, attempt.1, attempt.2, attempt.3);
    if bad.is_empty() {
        return Ok(patch);
    }
    let tris = ft_tris;
    // quads that stay invalid: refine the curves around them
    let mut curves = BTreeSet::new();
    for &t in &bad {
        let tri = tris[t as usize];
        for (&(a, b), bm) in &ft_mid {
            if tri.contains(&a) || tri.contains(&b) {
                curves.insert(bm.curve);
            }
        }
    }
    if tracing::enabled!(tracing::Level::DEBUG) {
        for (qi, q) in patch.quads.iter().enumerate() {
            if bad.contains(&patch.quad_tri[qi]) {
                tracing::debug!(
                    "face {} quad {qi} sicn {:.3}",
                    fid.0,
                    quad_quality(face, &patch.nodes, &patch.pos, q)
                );
                for &i in q {
                    let n = &patch.nodes[i as usize];
                    tracing::debug!(
                        "   {i}: uv {:?} {:?} pole {} pos {:?} n {:?}",
                        n.uv,
                        n.node,
                        n.pole.is_some(),
                        patch.pos[i as usize],
                        face.normal(n.uv)
                    );
                }
            }
        }
    }
    let reason = format!("{} quads stay inverted", bad.len());
    // finer curves repair a few quads at the boundary; when many fold, the
    // face's map is at fault and every round would only cost more time
    if bad.len() > MAX_REFINABLE_BAD.max(patch.quads.len() / 20) {
        return Err(FaceFailure::Fatal(format!(
            "{reason} of {} (the face's (u, v) map is too distorted for its size)",
            patch.quads.len()
        )));
    }
    if curves.is_empty() {
        return Err(FaceFailure::Fatal(format!("{reason} inside the face")));
    }
    Err(FaceFailure::InvertedAt {
        curves: curves.into_iter().collect(),
        spots: failure_spots(&patch, &bad),
        quads: patch.quads.len(),
        reason,
    })
}

/// The quads of `patch` whose source triangle is in `bad`, as
/// [`FailureSpot`]s in quad order.
fn failure_spots(patch: &QuadPatch, bad: &[u32]) -> Vec<FailureSpot> {
    patch
        .quads
        .iter()
        .zip(&patch.quad_tri)
        .filter(|(_, t)| bad.contains(t))
        .map(|(q, _)| {
            let p = q.map(|i| patch.pos[i as usize]);
            let mut at = [0.0; 3];
            for c in &p {
                at = geometry::vec3::add(at, geometry::vec3::scale(*c, 0.25));
            }
            let mut diameter: f64 = 0.0;
            for i in 0..4 {
                for j in i + 1..4 {
                    diameter = diameter.max(geometry::vec3::dist(p[i], p[j]));
                }
            }
            FailureSpot { at, diameter }
        })
        .collect()
}

type Attempt = (
    QuadPatch,
    Vec<[u32; 3]>,
    Vec<u32>,
    crate::core::fast_hash::FastMap<
        (u32, u32),
        crate::triangulate::face_triangulation::BoundaryMid,
    >,
);

/// One meshing attempt: the patch, its triangles, the triangles with invalid
/// quads, and the boundary midpoints.
fn mesh_face_once(
    model: &Model,
    fid: FaceId,
    cms: &[CurveMesh],
    target: f64,
    layers: bool,
) -> Result<Attempt, FaceFailure> {
    let face = &model.faces[fid.idx()];
    let mut ft = FaceTriangulation::new(model, fid, cms, target)?;
    if layers {
        ft.insert_normal_layers();
    }
    ft.refine()?;
    let tris = ft.triangles();
    if tris.is_empty() {
        return Err(FaceFailure::RefineCurves(
            ft.curves.clone(),
            "the triangulation is empty".into(),
        ));
    }
    let missing = ft.missing_boundary_edges(&tris);
    if !missing.is_empty() {
        return Err(FaceFailure::RefineCurves(
            missing,
            "boundary edges left out of the triangulation".into(),
        ));
    }
    let mut patch = split_triangles(face, &ft.nodes, &ft.pos, &tris, &ft.boundary_mid);
    smooth_then_untangle(model, fid, &mut patch, BASELINE_LAPLACIAN_SWEEPS);
    let bad = bad_triangles(face, &patch);
    Ok((patch, tris, bad, ft.boundary_mid))
}

/// Source triangles of the quads that are invalid (SICN ≤ 0, or two corners on one node).
fn bad_triangles(face: &geometry::Face, p: &QuadPatch) -> Vec<u32> {
    let mut bad = BTreeSet::new();
    for (qi, q) in p.quads.iter().enumerate() {
        if p.repeats_a_node(q) || !(quad_quality(face, &p.nodes, &p.pos, q) > 0.0) {
            bad.insert(p.quad_tri[qi]);
        }
    }
    bad.into_iter().collect()
}
