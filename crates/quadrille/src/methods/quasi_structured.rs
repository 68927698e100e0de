//! The field-guided methods, after the quasi-structured meshing paper:
//! the cross field and size map of every face (§3–4), curves quantized
//! against the size map (§4.3), then per face:
//!
//! 1. a simple face meshed directly by a pattern (§6.1.2), else
//! 2. frontal points along the field, recombination and midpoint
//!    subdivision (§5, [`crate::methods::unstructured`]), the baseline where
//!    that fails;
//! 3. very irregular vertices replaced by disk quadrangulations (§6.3) and
//!    cavities remeshed (§6.2);
//! 4. quads below the quality bar untangled once more (ours);
//! 5. the regular method's operations on what the cavities left (ours,
//!    [`crate::topology::regular_pass`]);
//! 6. the face's average quality raised (§5.3 kernels, ours: average SICN
//!    ascent);
//!
//! and on the assembled mesh: faces with a quad the mesh statistics find
//! inverted meshed again by the baseline, then curve nodes slid along their
//! curves (ours). [`Stages`] switches steps 1, 3 and 5 off; with all of them
//! off this is the plain unstructured method, with its own preset
//! ([`UnstructuredOptions::plain`]) and a coarser background.

use std::collections::BTreeSet;
use std::time::Instant;

use geometry::{CornerId, FaceId, Model};
use mesh::QuadMesh;
use rayon::prelude::*;

use crate::core::error::{FaceError, MeshError};
use crate::core::options::{default_size, Size};
use crate::core::patch::FaceFailure;
use crate::direct::pattern_face::mesh_face_pattern;
use crate::field::field_report::{model_fields, FieldOptions, BACKGROUND_REFINE};
use crate::field::size_map::SizeMapOptions;
use crate::methods::baseline::mesh_face;
use crate::methods::driver::{assemble, mesh_faces, FaceContext, CURVE_SLIDE_SWEEPS};
use crate::methods::options::{MeshOptions, Stages};
use crate::methods::report::{timed, FaceOutcome, MadeBy, MeshReport, StageTimes};
use crate::methods::unstructured::{improve_face, mesh_face_unstructured, UnstructuredOptions};
use crate::topology::regular_pass::{reduce_irregular, RegularPassOptions};

/// Sweeps of [`crate::smoothing::raise_average`] on every face of the
/// default and unstructured methods, last: on the 25 shared models (wing
/// out) the average SICN rises by up to 0.006 (s17o_sphere 0.948 → 0.976)
/// for 4.5 % more time in all. 40 sweeps with nodes counted as done only
/// when their quads are all 0.995 ([`crate::smoothing::kernels::ASCENT_GOOD`])
/// instead of 10 and 0.98: s17o 0.979 → 0.986 (Gmsh 0.9856), the others
/// up by 0.0000 to 0.0009, time within noise (BENCHMARKS.md, "Raising the
/// average SICN").
const ASCENT_SWEEPS: usize = 40;

/// Ratio of the quad size to the background size for the plain unstructured
/// method ([`crate::MeshMethod::Unstructured`]), against [`crate::field::field_report::BACKGROUND_REFINE`]
/// (6) for the others. The finer background places the singularities the
/// topology steps match; the plain method only follows the field's
/// directions and sizes. On the 26 shared models it runs about 40 % faster
/// (the fields were most of the time of the small ones: n12o 0.22 → 0.10 s)
/// with the average SICN within ±0.01 except s17o_sphere (0.934 → 0.911)
/// (BENCHMARKS.md, "A coarser background for the plain unstructured method").
const PLAIN_BACKGROUND_REFINE: f64 = 4.0;
/// The unstructured method bounds the size map to these multiples of the
/// target size, for faces and curves alike (the baseline fallback meshes at
/// the target size and copes with curves at most twice finer).
const SIZE_MAP_MIN: f64 = 0.5;
/// See [`SIZE_MAP_MIN`].
const SIZE_MAP_MAX: f64 = 2.0;
/// At coarse sizes the size map's floor is at most this multiple of the
/// default size: curved faces and small features keep a resolution a
/// coarse target would take away. With the floor at half the target, at
/// `--size-factor 4` a 90° fillet was one or two quads wide and i03o_m3 had
/// a quad of SICN 0.000 and an average of 0.525 (Gmsh: 0.727); with this,
/// 0.153 and 0.730 (BENCHMARKS.md, "Coarse sizes"). At size factors up to
/// 2 (the floor is then half the target) nothing changes.
const COARSE_FLOOR: f64 = 1.0;

/// The size map's lower bound for target size `h` ([`SIZE_MAP_MIN`] of it,
/// at most [`COARSE_FLOOR`] default sizes).
fn size_map_floor(model: &Model, h: f64) -> f64 {
    (SIZE_MAP_MIN * h).min(COARSE_FLOOR * default_size(model))
}

/// The turn of the normal whose arc length bounds the size map's floor on
/// narrow curved faces, for the methods with topology stages
/// ([`SizeMapOptions::floor_turn`]): 90°. A 90° fillet of radius r
/// then gets quads about `π r / 2` long along it and two across (the
/// curves' smallest count, 45° of turn each: CAD-normal SICN at most
/// cos 22.5° = 0.92 times 0.8 for 2 : 1). Before, the floor stretched them
/// along it: the spur gear's root fillets (r = 0.2, floor 0.66) had
/// 0.157 × 0.625 quads, average SICN 0.42. 45° (square quads) gave the
/// fillets 0.91 but 2–5 times the quads and time on flanges, screws and
/// bearings, and thin transitions on the gear flanks (BENCHMARKS.md,
/// "narrow fillets").
pub const NARROW_FILLET_TURN: f64 = std::f64::consts::FRAC_PI_2;

/// The size map's options for target size `h`: bounded so that faces,
/// curves and the baseline fallback agree (also what the size guard
/// estimates the quad count from). With topology `stages` on, narrow
/// curved faces lower the floor ([`NARROW_FILLET_TURN`]) and so do strips
/// of even width ([`SizeMapOptions::floor_narrow`]: the gears' fillets,
/// flanks and tooth chamfers; BENCHMARKS.md, "the width rule, enabled");
/// the plain unstructured method keeps it.
pub(crate) fn size_map_options(
    model: &Model,
    h: f64,
    opts: &MeshOptions,
    stages: Stages,
) -> SizeMapOptions {
    let quads_per_turn = (opts.quads_per_turn.is_finite() && opts.quads_per_turn > 0.0)
        .then_some(opts.quads_per_turn);
    SizeMapOptions {
        min_size: Some(size_map_floor(model, h)),
        max_size: Some(SIZE_MAP_MAX * h),
        quads_per_turn,
        // without a curvature bound the floor is never reached on a fillet
        floor_turn: (stages != Stages::NONE && quads_per_turn.is_some())
            .then_some(NARROW_FILLET_TURN),
        floor_narrow: stages != Stages::NONE,
        ..Default::default()
    }
}

/// The background refinement of the fields for `stages`:
/// [`PLAIN_BACKGROUND_REFINE`] for the plain method, the finer default as
/// soon as a topology step will match singularities or fit patterns.
fn background_refine(stages: Stages) -> f64 {
    if stages == Stages::NONE {
        PLAIN_BACKGROUND_REFINE
    } else {
        BACKGROUND_REFINE
    }
}

/// Meshes `model` at target size `h` with the steps of `stages` (the
/// module's recipe); `merged` lists the corners of collapsed sliver curves.
pub(crate) fn mesh_quasi_structured(
    model: &Model,
    h: f64,
    opts: &MeshOptions,
    stages: Stages,
    merged: &[CornerId],
) -> Result<(QuadMesh, MeshReport), MeshError> {
    if !(opts.quads_per_turn.is_finite() && opts.quads_per_turn >= 0.0) {
        return Err(MeshError::Sizing(format!(
            "quads per turn {} must be 0 (off) or a positive number",
            opts.quads_per_turn
        )));
    }
    let mut times = StageTimes::default();
    let sizing = size_map_options(model, h, opts, stages);
    let field_options = FieldOptions {
        size: Size::Absolute(h),
        sizing,
        refine: background_refine(stages),
        ..Default::default()
    };
    let fields = timed(&mut times.fields, "fields", || {
        model_fields(model, &field_options)
    })?;
    let uopts = if stages == Stages::NONE {
        UnstructuredOptions::plain()
    } else {
        UnstructuredOptions::with_topology(stages.defects, stages.cavities)
    };
    let pass_opts = RegularPassOptions::default();
    // steps 1–4 of the recipe: a pattern, else §5 and the topology stages,
    // else the baseline
    let mesh_one_face =
        |ctx: &FaceContext<'_>, ft: &mut StageTimes| -> Result<FaceOutcome, FaceFailure> {
            let (model, fid, face) = (ctx.model, ctx.fid, ctx.face);
            if stages.patterns {
                let r = timed(&mut ft.patterns, "patterns", || {
                    mesh_face_pattern(model, fid, ctx.cms, opts.ring_grids)
                });
                match r {
                    Ok((p, name)) => return Ok(FaceOutcome::new(p, MadeBy::Pattern(name))),
                    Err(why) => tracing::debug!("face {}: no pattern: {why}", fid.0 + 1),
                }
            }
            let attempt = (|| -> Result<FaceOutcome, FaceError> {
                let ff = fields.faces[fid.idx()]
                    .outcome
                    .as_ref()
                    .map_err(|e| FaceError::Field(e.to_string()))?;
                let topo_n = ff.field.topology.positions.len();
                // without a size map, the uniform size
                let size: Vec<f64> = match &ff.size {
                    Some(s) => s.clone(),
                    None => vec![h; topo_n],
                };
                let (mut p, fr) =
                    mesh_face_unstructured(model, fid, ctx.cms, &ff.field, &size, &uopts)?;
                ft.frontal += fr.times.frontal;
                ft.smoothing += fr.times.smoothing;
                // very irregular vertices out (paper §6.3), then cavity remeshing (§6.2)
                let r = improve_face(face, &mut p, &ff.singularities.list, &uopts, ft);
                // quads left below the quality bar: one more untangling pass
                timed(&mut ft.smoothing, "lift poor quads", || {
                    crate::smoothing::lift_poor_quads(
                        face,
                        &mut p,
                        crate::smoothing::POOR_SICN,
                        ctx.sharp_corners(),
                    )
                });
                tracing::debug!(
                    "face {}: {} quads ({} triangles, {} left), {} singularities, {:?}, {:?}",
                    fid.0 + 1,
                    p.quads.len(),
                    fr.triangles,
                    fr.leftover,
                    ff.singularities.list.len(),
                    r.0,
                    r.1
                );
                let mut outcome = FaceOutcome::new(p, MadeBy::Method);
                outcome.topology = Some(r);
                Ok(outcome)
            })();
            match attempt {
                Ok(o) => Ok(o),
                Err(reason) => {
                    let r = timed(&mut ft.fallback, "fallback", || {
                        mesh_face(model, fid, ctx.cms, 2.0 * h)
                    });
                    match r {
                        Ok(p) => Ok(FaceOutcome::new(p, MadeBy::Fallback(reason))),
                        // a boundary no triangulation in (u, v) takes (a curve
                        // on both sides of a slit of a plane): without the
                        // pattern step, a pattern is the last resort before
                        // the face is given up
                        Err(failure) if !stages.patterns => {
                            match timed(&mut ft.patterns, "patterns", || {
                                mesh_face_pattern(model, fid, ctx.cms, opts.ring_grids)
                            }) {
                                Ok((p, name)) => {
                                    tracing::debug!(
                                        "face {}: {failure:?}; meshed by pattern {name}",
                                        fid.0 + 1
                                    );
                                    Ok(FaceOutcome::new(p, MadeBy::Pattern(name)))
                                }
                                Err(_) => Err(failure),
                            }
                        }
                        Err(failure) => Err(failure),
                    }
                }
            }
        };
    // steps 5 and 6
    let face_mesher =
        |ctx: &FaceContext<'_>, ft: &mut StageTimes| -> Result<FaceOutcome, FaceFailure> {
            let mut outcome = mesh_one_face(ctx, ft)?;
            let p = &mut outcome.patch;
            // the regular method's operations on what the cavities left
            let by_pattern = matches!(outcome.made_by, MadeBy::Pattern(_));
            if stages.regular_pass && !by_pattern {
                let rep = timed(&mut ft.regular_pass, "regular pass", || {
                    reduce_irregular(ctx.face, ctx.fid, p, ctx.sharp_corners(), &pass_opts)
                });
                tracing::debug!("face {}: regular pass {rep:?}", ctx.fid.0 + 1);
                if rep.tried {
                    outcome.regular_pass = Some(rep);
                }
            }
            // last, the face's average quality (square quads, sizes free)
            let rep = timed(&mut ft.smoothing, "raise average", || {
                crate::smoothing::raise_average(ctx.face, &mut outcome.patch, ASCENT_SWEEPS)
            });
            tracing::debug!(
                "face {}: average SICN {:?} → {:?} sweeps {} moves {}",
                ctx.fid.0 + 1,
                rep.before,
                rep.after,
                rep.sweeps,
                rep.moves
            );
            Ok(outcome)
        };
    // curves quantized against the size map (paper §4.3)
    let plan = timed(&mut times.curves, "curve plan", || fields.curve_plan(model));
    let (cms, mut results) = mesh_faces(
        model,
        plan,
        opts.progress.as_ref(),
        &face_mesher,
        true,
        &mut times,
    )?;
    let t = Instant::now();
    let mut mesh = assemble(model, &cms, &results, merged)?;
    // the final judge is the mesh statistics' SICN on the assembled mesh:
    // a face with a quad it finds inverted is meshed again with the baseline
    let sicn = mesh::stats::quad_acceptance_sicn_values(&mesh, Some(model));
    let mut again: BTreeSet<usize> = BTreeSet::new();
    for (q, v) in sicn.iter().enumerate() {
        let f = mesh.quad_face[q].idx();
        let fell_back = matches!(
            results[f].as_ref().map(|o| &o.made_by),
            Some(MadeBy::Fallback(_))
        );
        if *v < 0.0 && !fell_back {
            again.insert(f);
        }
    }
    times.assembly += t.elapsed();
    if !again.is_empty() {
        let t = Instant::now();
        let redo: Vec<(usize, Result<_, FaceFailure>)> = again
            .iter()
            .copied()
            .collect::<Vec<_>>()
            .into_par_iter()
            .map(|f| (f, mesh_face(model, FaceId(f as u32), &cms, 2.0 * h)))
            .collect();
        times.fallback += t.elapsed();
        let t = Instant::now();
        for (f, r) in redo {
            if let Ok(p) = r {
                results[f] = Some(FaceOutcome::new(
                    p,
                    MadeBy::Fallback(FaceError::InvertedInAssembly),
                ));
            }
        }
        mesh = assemble(model, &cms, &results, merged)?;
        times.assembly += t.elapsed();
    }
    // last, curve nodes slide along their curves (on every face that uses them)
    let rep = timed(&mut times.curve_slide, "curve slide", || {
        crate::smoothing::curve_slide::slide_curve_nodes(model, &mut mesh, CURVE_SLIDE_SWEEPS)
    });
    tracing::debug!("curve nodes slid: {rep:?}");
    let mut report = MeshReport::from_faces(&results);
    report.times = times;
    Ok((mesh, report))
}

#[cfg(test)]
mod tests {
    use super::*;
    use geometry::primitives;

    #[test]
    fn the_size_floor_is_half_the_target_up_to_the_default_size() {
        let m = primitives::square(1.0);
        let d = default_size(&m);
        assert_eq!(size_map_floor(&m, d), SIZE_MAP_MIN * d);
        assert_eq!(size_map_floor(&m, 0.25 * d), SIZE_MAP_MIN * 0.25 * d);
        assert_eq!(size_map_floor(&m, 2.0 * d), COARSE_FLOOR * d);
        assert_eq!(size_map_floor(&m, 8.0 * d), COARSE_FLOOR * d);
    }

    #[test]
    fn only_the_plain_unstructured_method_has_the_coarse_background() {
        assert_eq!(background_refine(Stages::NONE), PLAIN_BACKGROUND_REFINE);
        const { assert!(PLAIN_BACKGROUND_REFINE < crate::field::field_report::BACKGROUND_REFINE) };
        assert_eq!(
            background_refine(Stages::ALL),
            crate::field::field_report::BACKGROUND_REFINE
        );
        // any one topology step brings the default background back
        let one = Stages {
            regular_pass: true,
            ..Stages::NONE
        };
        assert_eq!(
            background_refine(one),
            crate::field::field_report::BACKGROUND_REFINE
        );
    }
}
