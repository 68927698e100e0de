//! The unstructured all-quad mesher of one face (paper §5, spec §7): frontal
//! point insertion along the scaled cross field into the face's constrained
//! Delaunay triangulation ([`crate::frontal::insertion`]), greedy recombination into a
//! quad-dominant mesh ([`crate::triangulate::recombine`]), midpoint subdivision into
//! all-quads on the CAD with snapping repair ([`crate::triangulate::subdivide`]), then the
//! baseline's smoothing and untangling with rollback ([`crate::smoothing`]),
//! and last the paper's Winslow / angle-based kernels
//! ([`crate::smoothing::optimize`]), kept only if the face got better.
//! [`improve_face`] then improves the topology: disk-quadrangulation defect
//! removal ([`crate::topology::defects`], paper §6.3) and cavity remeshing
//! ([`crate::topology::cavity`], paper §6.2; [`UnstructuredOptions::cavity`]).
//!
//! The output is the baseline's [`QuadPatch`], so the pipeline assembles it
//! like any other face. A face whose result is not valid (an inverted quad,
//! a boundary edge left out, a triangulation failure) returns an error and
//! the pipeline meshes it with the baseline instead.

use geometry::vec3::{self, Vec3};
use geometry::{FaceId, Model};

use crate::core::error::FaceError;
use crate::core::patch::NodeRef;
use crate::core::patch::QuadPatch;
use crate::core::quality::quad_quality;
use crate::curves::curve_mesh::CurveMesh;
use crate::field::background::{Background, DirectionalRatios};
use crate::field::crossfield::CrossField;
use crate::frontal::insertion::{insert_frontal_points_directional, FrontalOptions, FrontalStats};
use crate::methods::report::{timed, StageTimes};
use crate::smoothing::{optimize, smooth_then_untangle, OptimizeOptions};
use crate::topology::cavity::{remesh_cavities, CavityOptions, CavityReport};
use crate::topology::defects::{remove_defects, DefectReport};
use crate::triangulate::face_triangulation::FaceTriangulation;
use crate::triangulate::recombine::{recombine, MinSicn, MIN_SICN};
use crate::triangulate::subdivide::{snap_repair, subdivide};
use rayon::prelude::*;
use std::time::Instant;

/// Smoothing sweeps after subdivision.
const SUBDIVISION_LAPLACIAN_SWEEPS: usize = 12;
/// Sweeps of the Winslow / angle-based smoothing that ends the face (20:
/// within 0.002 of the average SICN of 30 on the wing, 8 % faster).
const FINAL_SWEEPS: usize = 20;
/// Size growth away from the boundary edges in the first stage of the
/// quasi-structured method: off. (0.25 and 0.6 were tried on the bundled
/// models: more quads and more fallbacks at 0.25, no gain at 0.6, with the
/// curve meshes at the uniform target size; with today's curve meshes 0.15
/// leaves 713 irregular vertices on the 25 models instead of 682.)
const GRADATION: f64 = f64::INFINITY;
/// Size growth away from the boundary edges for the plain unstructured
/// method ([`UnstructuredOptions::plain`]), whose mesh is final: half
/// the curves' own grading ([`crate::curves::curve_mesh::GRADING`], on the coarse
/// spacing), so the interior continues the spacing of curves refined at
/// tight bends. On wing_surface, whose airfoils are spaced by their leading
/// and trailing edges at a fifth of the size map, the front met the curves
/// with fans of slivers: average SICN 0.717 with an ungraded size, 0.918
/// with this (BENCHMARKS.md, "A graded size for the plain unstructured
/// method").
pub const PLAIN_GRADATION: f64 = 0.15;
/// [`UnstructuredOptions::min_curve_corner_sicn`] of the plain unstructured
/// method: a curve node is not left with one quad whose corner there is
/// flatter than about 163°. On the 26 shared models, 1 782 interior irregular
/// vertices against 1 574 with the paper's 0.1, but the worst SICN of
/// n11o_limit_cycle rises from 0.131 to 0.738, of s15o_cylinder from 0.161
/// to 0.820, and the mean average SICN from 0.9459 to 0.9490 (BENCHMARKS.md,
/// "Flat corners on curves in the plain method").
pub const PLAIN_MIN_CURVE_CORNER_SICN: f64 = 0.3;
/// A boundary edge's spacing ratio to the size map counts within
/// `[SPACING_RATIO_MIN, 1 / SPACING_RATIO_MIN]`. 0.15 lets the curves of
/// wing_surface, spaced at a fifth of the size map at the leading and
/// trailing edges, set the chordwise spacing: one near-grid with 2.0 %
/// irregular vertices (5 890 quads) instead of rows of transitions along
/// both edges with 12.0 % (2 976 quads). On the 26 shared models: 3 320
/// interior irregular vertices at 0.15, 3 368 at 0.2, 3 515 at 0.7, and at
/// 0.5 the wing's minimum SICN falls to 0.24 (BENCHMARKS.md, "The front's
/// spacing per cross branch").
const SPACING_RATIO_MIN: f64 = 0.15;
/// Longest augmenting path of the recombination.
const AUGMENT_PATH: usize = 9;
/// Passes of the snapping repair.
const SNAP_PASSES: usize = 3;
/// The refinement after frontal insertion targets this many times the
/// largest spacing (it splits edges above 1.4 × its target): the diagonals
/// of the front's squares (√2 × spacing) must not be refined.
const REFINE_SLACK: f64 = 1.3;

/// Options of [`mesh_face_unstructured`].
#[derive(Clone, Debug)]
pub struct UnstructuredOptions {
    /// Frontal insertion parameters.
    pub frontal: FrontalOptions,
    /// Recombination threshold on the SICN of a quad (the paper's 0.1).
    pub min_sicn: f64,
    /// Recombination threshold on the SICN, after subdivision, of a quad's
    /// corners between two curve edges ([`crate::triangulate::recombine::MinSicn::curve_corner`]).
    pub min_curve_corner_sicn: f64,
    /// Smoothing sweeps after subdivision.
    pub smoothing_sweeps: usize,
    /// Growth of the size away from the boundary: the size at a background
    /// vertex `x` is at most `h_e + gradation · |x − m_e|` for every boundary
    /// edge `e` (final spacing `h_e` = half its length, midpoint `m_e`), so
    /// the front starts at the spacing of the curve meshes and grows
    /// smoothly toward the size map. Infinite to use the size map alone.
    pub gradation: f64,
    /// Longest augmenting path (in candidate quads) searched after the greedy
    /// recombination to pair leftover triangles; 0 for the greedy pairing only.
    pub augment_path: usize,
    /// How the front steps along the cross branches: one run per entry, the
    /// face keeps the mesh with the fewest face-interior irregular vertices
    /// ([`mesh_face_unstructured`]). Empty is `[FrontSpacing::Size]`.
    pub front_spacings: Vec<FrontSpacing>,
    /// The triangulation is refined for curvature only past about 120° of
    /// turn ([`FaceTriangulation::curvature_by_size_map`]): the size map
    /// bounds the turn per quad already and the curves allow 90° per coarse
    /// segment.
    pub curvature_by_size_map: bool,
    /// Defect removal by disk quadrangulations ([`improve_face`]); `false` switches it off.
    pub defects: bool,
    /// Cavity remeshing after the defect removal ([`improve_face`]); `None` switches it off.
    pub cavity: Option<CavityOptions>,
}

impl Default for UnstructuredOptions {
    fn default() -> Self {
        UnstructuredOptions {
            frontal: FrontalOptions::default(),
            min_sicn: MIN_SICN,
            min_curve_corner_sicn: MIN_SICN,
            smoothing_sweeps: SUBDIVISION_LAPLACIAN_SWEEPS,
            gradation: GRADATION,
            augment_path: AUGMENT_PATH,
            front_spacings: vec![FrontSpacing::Size],
            curvature_by_size_map: false,
            defects: true,
            cavity: Some(CavityOptions::default()),
        }
    }
}

impl UnstructuredOptions {
    /// The plain unstructured method's preset ([`crate::MeshMethod::Unstructured`]):
    /// its §5 mesh is the output, so its interior follows the curves'
    /// spacing ([`PLAIN_GRADATION`], both [`FrontSpacing`]s, curvature
    /// refinement by the size map, [`PLAIN_MIN_CURVE_CORNER_SICN`]) and no
    /// topology stage runs.
    pub fn plain() -> Self {
        UnstructuredOptions {
            gradation: PLAIN_GRADATION,
            front_spacings: vec![FrontSpacing::BoundaryRatio, FrontSpacing::BoundarySpacing],
            curvature_by_size_map: true,
            min_curve_corner_sicn: PLAIN_MIN_CURVE_CORNER_SICN,
            defects: false,
            cavity: None,
            ..Default::default()
        }
    }

    /// The quasi-structured method's options: the defaults, with defect
    /// removal and cavity remeshing as asked.
    pub fn with_topology(defects: bool, cavities: bool) -> Self {
        UnstructuredOptions {
            defects,
            cavity: cavities.then(CavityOptions::default),
            ..Default::default()
        }
    }
}

/// Counts of one face's unstructured meshing.
#[derive(Clone, Copy, Debug, Default)]
pub struct FaceReport {
    /// Frontal insertion counts.
    pub frontal: FrontalStats,
    /// Triangles of the Delaunay triangulation.
    pub triangles: usize,
    /// Quads made by recombination.
    pub recombined: usize,
    /// Triangles left alone by recombination.
    pub leftover: usize,
    /// Nodes moved by the snapping repair.
    pub snapped: usize,
    /// Time of the stages: [`StageTimes::frontal`] (insertion, recombination,
    /// subdivision) and [`StageTimes::smoothing`].
    pub times: StageTimes,
}

/// How the front steps along each cross branch ([`UnstructuredOptions::front_spacings`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrontSpacing {
    /// By the (graded) size alone, the same along both branches.
    Size,
    /// By the size times the ratio of the boundary edges' spacing to the size
    /// map along that branch ([`boundary_spacing_ratios`]): the interior keeps
    /// the curves' rounding but follows the size map's variation.
    BoundaryRatio,
    /// By the boundary edges' spacing along that branch itself, never above
    /// the graded size: where the size map varies
    /// between the sides and the middle (a flat face between fillets), the
    /// fronts of opposite sides still meet on one grid.
    BoundarySpacing,
}

/// A face's quads straight from the front: recombined and subdivided, not
/// yet smoothed.
struct FrontMesh {
    patch: QuadPatch,
    report: FaceReport,
    /// Face-interior vertices with other than four quads.
    irregular: usize,
}

/// Meshes face `fid` against the curve meshes `cms` (their coarse points at
/// about twice the final size) guided by the cross field `field` and the
/// size map `size` (one final edge length per welded vertex of
/// `field.topology`), graded from the boundary edges ([`UnstructuredOptions::gradation`]).
/// With several [`UnstructuredOptions::front_spacings`], the front runs once
/// per spacing and the face keeps the mesh with the fewest face-interior
/// irregular vertices (the first on ties; the next when one cannot be made
/// valid).
pub fn mesh_face_unstructured(
    model: &Model,
    fid: FaceId,
    cms: &[CurveMesh],
    field: &CrossField,
    size: &[f64],
    opts: &UnstructuredOptions,
) -> Result<(QuadPatch, FaceReport), FaceError> {
    let face = model
        .faces
        .get(fid.idx())
        .ok_or(FaceError::NoSuchFace(fid.0 + 1))?;
    // validates the size array
    Background::new(field, size).map_err(|e| FaceError::Field(e.to_string()))?;
    let started = Instant::now();
    let max_size = size.iter().cloned().fold(0.0, f64::max);
    let boundary = FaceTriangulation::new(
        model,
        fid,
        cms,
        REFINE_SLACK * opts.frontal.factor * max_size,
    )
    .map_err(|e| FaceError::Boundary(format!("{e:?}")))?;
    let graded = graded_sizes(&boundary, field, size, opts.gradation);
    let bg = Background::new(field, &graded).map_err(|e| FaceError::Field(e.to_string()))?;
    let mut meshes: Vec<FrontMesh> = Vec::new();
    let mut why = FaceError::NoFrontSpacing;
    let spacings: &[FrontSpacing] = if opts.front_spacings.is_empty() {
        &[FrontSpacing::Size]
    } else {
        &opts.front_spacings
    };
    let front = Front {
        field,
        size,
        graded: &graded,
        bg: &bg,
    };
    let run = |spacing: FrontSpacing| front_mesh(face, boundary.clone(), &front, opts, spacing);
    // in the spacings' order, up to the first run with no irregular vertex
    // (no later one can do better): on one worker the later runs are not
    // made at all, on more they run side by side (a large face left last
    // does not keep one worker alone) and are dropped, so the output is the same
    let runs: Vec<Result<FrontMesh, FaceError>> = if rayon::current_num_threads() > 1 {
        spacings.par_iter().map(|&s| run(s)).collect()
    } else {
        let mut runs = Vec::new();
        for &spacing in spacings {
            let r = run(spacing);
            let done = matches!(&r, Ok(m) if m.irregular == 0);
            runs.push(r);
            if done {
                break;
            }
        }
        runs
    };
    for r in runs {
        match r {
            Ok(m) => {
                let done = m.irregular == 0;
                meshes.push(m);
                if done {
                    break;
                }
            }
            Err(e) => why = e,
        }
    }
    let frontal_time = started.elapsed();
    // fewest irregular vertices first; the sort is stable, so ties keep the order of the spacings
    meshes.sort_by_key(|m| m.irregular);
    for FrontMesh {
        mut patch,
        mut report,
        ..
    } in meshes
    {
        report.times.frontal = frontal_time;
        let smoothing = Instant::now();
        smooth_then_untangle(model, fid, &mut patch, opts.smoothing_sweeps);
        // the paper's kernels (Winslow, angle-based) on the valid mesh
        optimize(
            face,
            &mut patch,
            &OptimizeOptions {
                max_sweeps: FINAL_SWEEPS,
                ..Default::default()
            },
        );
        report.times.smoothing = smoothing.elapsed();
        let bad = invalid_quads(face, &patch);
        if bad == 0 {
            return Ok((patch, report));
        }
        if tracing::enabled!(tracing::Level::DEBUG) {
            let nt = report.leftover as u32;
            for (qi, q) in patch.quads.iter().enumerate() {
                let s = quad_quality(face, &patch.nodes, &patch.pos, q);
                if !(s > 0.0) {
                    let el = patch.quad_tri[qi];
                    tracing::debug!(
                        "face {} quad {qi} sicn {s:.3} from {} {}: {:?}",
                        fid.0 + 1,
                        if el < nt { "triangle" } else { "quad" },
                        el,
                        q.map(|i| patch.nodes[i as usize].node)
                    );
                }
            }
        }
        why = FaceError::InvertedQuads(bad);
    }
    Err(why)
}

/// What every run of the front on one face shares: the cross field, the
/// size map, the size graded from the boundary and its background.
struct Front<'f> {
    field: &'f CrossField,
    size: &'f [f64],
    graded: &'f [f64],
    bg: &'f Background<'f>,
}

/// The front of one [`FrontSpacing`] on `face` from its boundary
/// triangulation `ft`: frontal points, refinement, recombination,
/// subdivision and snapping.
fn front_mesh(
    face: &geometry::Face,
    mut ft: FaceTriangulation<'_>,
    front: &Front<'_>,
    opts: &UnstructuredOptions,
    spacing: FrontSpacing,
) -> Result<FrontMesh, FaceError> {
    let mut report = FaceReport::default();
    let bg = front.bg;
    let ratios = boundary_spacing_ratios(&ft, front.field, front.size, front.graded, spacing)?;
    report.frontal =
        insert_frontal_points_directional(&mut ft, face, bg, &opts.frontal, ratios.as_ref());
    // fills holes and fixes what the front cannot see (chord deviation,
    // folded triangles on curved surfaces)
    if opts.curvature_by_size_map {
        ft.curvature_by_size_map();
    }
    ft.refine()
        .map_err(|e| FaceError::Refinement(format!("{e:?}")))?;
    let mut tris = ft.triangles();
    if tris.is_empty() {
        return Err(FaceError::EmptyTriangulation);
    }
    let missing = ft.missing_boundary_edges(&tris);
    if !missing.is_empty() {
        return Err(FaceError::MissingBoundaryEdges(
            missing.iter().map(|c| c.0 + 1).collect(),
        ));
    }
    report.triangles = tris.len();
    // a pole corner's two triangles beside the vanishing one may pair up
    ft.merge_poles(&mut tris);
    let boundary = &ft.boundary_mid;
    let qd = recombine(
        face,
        &ft.nodes,
        &ft.pos,
        &tris,
        |a, b| boundary.get(&(a.min(b), a.max(b))).map(|m| m.pos),
        |q| bg.alignment(q).unwrap_or(0.0),
        MinSicn {
            quad: opts.min_sicn,
            curve_corner: opts.min_curve_corner_sicn,
        },
        opts.augment_path,
    );
    report.recombined = qd.quads.len();
    report.leftover = qd.triangles.len();
    let (mut patch, origins) = subdivide(
        face,
        &ft.nodes,
        &ft.pos,
        &qd.quads,
        &qd.triangles,
        &ft.boundary_mid,
    );
    report.snapped = snap_repair(face, &mut patch, &origins, SNAP_PASSES);
    let irregular = patch.interior_irregular();
    Ok(FrontMesh {
        patch,
        report,
        irregular,
    })
}

/// Improves the topology of one face's unstructured mesh `p`: unless
/// `opts.defects` is `false`, very irregular vertices out by disk
/// quadrangulations (paper §6.3), then, unless `opts.cavity` is `None`,
/// cavity remeshing around the unnecessary irregular vertices, keeping the
/// ones matched to the face's cross-field `singularities` (paper §6.2). Every
/// change is kept only if the quads stay valid. Adds the time of the two
/// stages to [`StageTimes::defects`] and [`StageTimes::cavities`] of `times`.
pub fn improve_face(
    face: &geometry::Face,
    p: &mut QuadPatch,
    singularities: &[crate::field::singularities::Singularity],
    opts: &UnstructuredOptions,
    times: &mut StageTimes,
) -> (DefectReport, CavityReport) {
    let mut defects = DefectReport::default();
    if opts.defects {
        defects = timed(&mut times.defects, "defects", || remove_defects(face, p));
    }
    let mut cavities = CavityReport::default();
    if let Some(c) = &opts.cavity {
        cavities = timed(&mut times.cavities, "cavities", || {
            remesh_cavities(face, p, singularities, c)
        });
    }
    (defects, cavities)
}

/// `size` limited by the graded spacing of the boundary edges of `ft`: at
/// each background vertex `x`, `min(size, min_e h_e + gradation · |x − m_e|)`.
pub fn graded_sizes(
    ft: &FaceTriangulation<'_>,
    field: &CrossField,
    size: &[f64],
    gradation: f64,
) -> Vec<f64> {
    let mut edges: Vec<((u32, u32), Vec3, f64)> = ft
        .boundary_mid
        .iter()
        .filter(|(_, m)| m.node.pole.is_none())
        .map(|(&(a, b), m)| {
            (
                (a, b),
                m.pos,
                0.5 * (vec3::dist(ft.pos[a as usize], m.pos)
                    + vec3::dist(m.pos, ft.pos[b as usize])),
            )
        })
        .filter(|e| e.2 > 0.0 && e.2.is_finite())
        .collect();
    edges.sort_by_key(|e| e.0);
    let mut out = size.to_vec();
    if !(gradation.is_finite() && gradation >= 0.0) {
        return out;
    }
    for (v, s) in out.iter_mut().enumerate() {
        let x = field.topology.positions[v];
        for &(_, m, h) in &edges {
            *s = s.min(h + gradation * vec3::dist(x, m));
        }
    }
    out
}

/// The spacing the front keeps along each cross branch, as ratios to the
/// graded size `graded` per background vertex of `field`
/// ([`crate::field::background::DirectionalRatios`]).
///
/// A boundary edge of `ft` with spacing `h` (half its length, the final
/// spacing) where the size map `size` asks for `s` says "along my direction,
/// points are `h` apart": the ratio `h / s` (within [`SPACING_RATIO_MIN`] and
/// its inverse) is interpolated to every background vertex, for each of its
/// two cross branches from the edges running along that branch (weights
/// `cos⁴` of the angle between edge and branch, times the edge's spacing
/// over the cube of its distance: on the 26 shared models, with ratios
/// within 0.5 and 2, 3 550 interior irregular vertices against 3 576 with
/// the square and 3 579 with the fourth power; BENCHMARKS.md, "The front's
/// spacing per cross branch"). The spacing
/// along a branch is then `min(s · ratio, graded)`. So a front that starts
/// from a side whose quantized count rounded the size map up or down keeps
/// that side's spacing, and the fronts of opposite sides meet on the same
/// grid lines (on a square whose sides were rounded to 0.05 where the size
/// map asked for 0.06, every interior point lands on the grid; a test). On
/// a long strip, the spacing across comes from its short ends and the
/// spacing along from its long sides; on a wing, the chordwise spacing from
/// the airfoils, refined at their leading and trailing edges, and the
/// spanwise spacing from the edges' curves.
///
/// That is [`FrontSpacing::BoundaryRatio`]. With
/// [`FrontSpacing::BoundarySpacing`] the edges' spacing `h` itself is
/// interpolated the same way (its logarithm), not rescaled by the size map:
/// the spacing along a branch is `min(h, graded)` (on the flat faces of
/// s13o_cube_rounded_2, between fillets where the size map is smaller than
/// in their middle, every interior point then lands on the sides' grid).
/// With [`FrontSpacing::Size`], `None`: the front steps by the size alone.
pub fn boundary_spacing_ratios(
    ft: &FaceTriangulation<'_>,
    field: &CrossField,
    size: &[f64],
    graded: &[f64],
    spacing: FrontSpacing,
) -> Result<Option<DirectionalRatios>, FaceError> {
    // what each edge carries: ln(h / s), or ln h
    let relative = match spacing {
        FrontSpacing::Size => return Ok(None),
        FrontSpacing::BoundaryRatio => true,
        FrontSpacing::BoundarySpacing => false,
    };
    let bg = Background::new(field, size).map_err(|e| FaceError::Field(e.to_string()))?;
    let mut keys: Vec<&(u32, u32)> = ft.boundary_mid.keys().collect();
    keys.sort();
    // (midpoint, unit direction, spacing, ln(spacing / size) or ln(spacing))
    let edges: Vec<(Vec3, Vec3, f64, f64)> = keys
        .into_iter()
        .filter_map(|key| {
            let m = &ft.boundary_mid[key];
            if m.node.pole.is_some() {
                return None;
            }
            let (pa, pb) = (ft.pos[key.0 as usize], ft.pos[key.1 as usize]);
            let h = 0.5 * (vec3::dist(pa, m.pos) + vec3::dist(m.pos, pb));
            let t = vec3::normalize(vec3::sub(pb, pa))?;
            let s = bg.sample(m.pos)?.size;
            let ratio = (h / s).clamp(SPACING_RATIO_MIN, 1.0 / SPACING_RATIO_MIN);
            // what is interpolated: ln(h / s), or ln h
            let carried = if relative { ratio.ln() } else { h.ln() };
            (h > 0.0 && s > 0.0).then_some((m.pos, t, h, carried))
        })
        .collect();
    let n = field.topology.positions.len();
    let mut out = DirectionalRatios {
        dir: Vec::with_capacity(n),
        log_ratio: Vec::with_capacity(n),
    };
    for v in 0..n {
        let x = field.topology.positions[v];
        let Some(smp) = bg.sample(x) else {
            out.dir.push([1.0, 0.0, 0.0]);
            out.log_ratio.push([0.0; 2]);
            continue;
        };
        // per branch: (Σ w · carried, Σ w)
        let mut acc = [[0.0f64; 2]; 2];
        for &(m, t, h, carried) in &edges {
            let d2 = vec3::dist(x, m).powi(2) + h * h;
            let w = h / (d2 * d2.sqrt());
            for (k, a) in acc.iter_mut().enumerate() {
                let c2 = vec3::dot(t, smp.cross[k]).powi(2);
                a[0] += w * c2 * c2 * carried;
                a[1] += w * c2 * c2;
            }
        }
        out.dir.push(smp.cross[0]);
        // the step is graded · exp(log ratio): size · ratio, or h
        let base = if relative {
            (size[v] / graded[v]).ln()
        } else {
            -graded[v].ln()
        };
        // no edge along a branch: the graded size
        out.log_ratio.push(acc.map(|a| {
            if a[1] > 0.0 {
                (base + a[0] / a[1]).min(0.0)
            } else {
                0.0
            }
        }));
    }
    Ok(Some(out))
}

/// Number of invalid quads of a patch: SICN ≤ 0 (CAD normals), two corners
/// on one mesh node, or a face-interior node on a singular point of the
/// surface (an apex: its normal is not defined).
pub fn invalid_quads(face: &geometry::Face, p: &QuadPatch) -> usize {
    let mut bad = 0;
    for q in &p.quads {
        let on_apex = q.iter().any(|&i| {
            let n = &p.nodes[i as usize];
            n.node == NodeRef::Interior
                && (face.is_singular(n.uv) || face.surface.normal(n.uv).is_none())
        });
        if on_apex || p.repeats_a_node(q) || !(quad_quality(face, &p.nodes, &p.pos, q) > 0.0) {
            bad += 1;
        }
    }
    bad
}

#[cfg(test)]
mod tests {
    use super::*;
    use geometry::primitives;

    fn run(model: &Model, h: f64) -> Vec<(QuadPatch, FaceReport)> {
        let (fields, cms) = crate::fixtures::grids::fields_and_curves(model, h);
        (0..model.faces.len())
            .map(|f| {
                let ff = fields.faces[f].outcome.as_ref().unwrap();
                let size = ff.size.clone().unwrap();
                mesh_face_unstructured(
                    model,
                    FaceId(f as u32),
                    &cms,
                    &ff.field,
                    &size,
                    &UnstructuredOptions::default(),
                )
                .unwrap()
            })
            .collect()
    }

    /// The unit square with sides split for a final spacing of 0.05 (10
    /// coarse segments each), its field, and a size map asking for 0.06
    /// everywhere, as if quantization had rounded the sides' counts up.
    fn square_with_rounded_sides() -> (Model, Vec<CurveMesh>, CrossField, Vec<f64>) {
        let h = 0.05;
        let model = primitives::square(1.0);
        let (fields, cms) = crate::fixtures::grids::fields_and_curves(&model, h);
        let field = fields.faces[0].outcome.as_ref().unwrap().field.clone();
        let size = vec![0.06; field.topology.positions.len()];
        (model, cms, field, size)
    }

    #[test]
    fn the_spacing_along_each_branch_is_the_sides_spacing() {
        let (model, cms, field, size) = square_with_rounded_sides();
        let ft = FaceTriangulation::new(&model, FaceId(0), &cms, 0.1).unwrap();
        let ratios =
            boundary_spacing_ratios(&ft, &field, &size, &size, FrontSpacing::BoundaryRatio)
                .unwrap()
                .unwrap();
        assert_eq!(ratios.log_ratio.len(), field.topology.positions.len());
        for r in &ratios.log_ratio {
            for k in 0..2 {
                let spacing = 0.06 * r[k].exp();
                assert!((spacing - 0.05).abs() < 1e-9, "{spacing}");
            }
        }
        // a graded size already at the sides' spacing is kept (never raised)
        let graded = vec![0.04; size.len()];
        let ratios =
            boundary_spacing_ratios(&ft, &field, &size, &graded, FrontSpacing::BoundaryRatio)
                .unwrap()
                .unwrap();
        assert!(ratios.log_ratio.iter().all(|r| r[0] == 0.0 && r[1] == 0.0));
    }

    #[test]
    fn fronts_at_the_sides_spacing_meet_on_one_grid() {
        let (model, cms, field, size) = square_with_rounded_sides();
        let bg = Background::new(&field, &size).unwrap();
        // interior points off the grid of step 0.1 (the coarse spacing)
        let off_grid = |ft: &FaceTriangulation<'_>, first: usize| {
            ft.pos[first..]
                .iter()
                .filter(|p| {
                    (0..2).any(|k| {
                        let x = p[k] / 0.1;
                        (x - x.round()).abs() > 1e-6
                    })
                })
                .count()
        };
        let face = &model.faces[0];
        let opts = FrontalOptions::default();
        let mut plain = FaceTriangulation::new(&model, FaceId(0), &cms, 0.1).unwrap();
        let nb = plain.nodes.len();
        insert_frontal_points_directional(&mut plain, face, &bg, &opts, None);
        assert!(
            off_grid(&plain, nb) > 0,
            "steps of 0.12 cannot stay on the grid"
        );
        let mut ft = FaceTriangulation::new(&model, FaceId(0), &cms, 0.1).unwrap();
        let ratios =
            boundary_spacing_ratios(&ft, &field, &size, &size, FrontSpacing::BoundaryRatio)
                .unwrap()
                .unwrap();
        let st = insert_frontal_points_directional(&mut ft, face, &bg, &opts, Some(&ratios));
        // the 9 × 9 interior nodes of the 10 × 10 grid, every one on it
        assert_eq!(st.inserted, 81, "{st:?}");
        assert_eq!(off_grid(&ft, nb), 0);
    }

    /// [`square_with_rounded_sides`] with a size map growing from 0.06 on
    /// the sides to 0.08 at 0.2 from them and beyond.
    fn square_with_a_size_growing_inside() -> (Model, Vec<CurveMesh>, CrossField, Vec<f64>) {
        let (model, cms, field, _) = square_with_rounded_sides();
        let size = field
            .topology
            .positions
            .iter()
            .map(|p| {
                let d = p[0].min(1.0 - p[0]).min(p[1]).min(1.0 - p[1]);
                0.06 + 0.02 * (d / 0.2).min(1.0)
            })
            .collect();
        (model, cms, field, size)
    }

    #[test]
    fn the_boundary_spacing_stays_where_the_size_grows_inside() {
        let (model, cms, field, size) = square_with_a_size_growing_inside();
        let ft = FaceTriangulation::new(&model, FaceId(0), &cms, 0.1).unwrap();
        let step = |r: &DirectionalRatios, v: usize, k: usize| size[v] * r.log_ratio[v][k].exp();
        let spacings =
            boundary_spacing_ratios(&ft, &field, &size, &size, FrontSpacing::BoundarySpacing)
                .unwrap()
                .unwrap();
        let ratios =
            boundary_spacing_ratios(&ft, &field, &size, &size, FrontSpacing::BoundaryRatio)
                .unwrap()
                .unwrap();
        // the background vertex nearest the centre
        let centre = (0..size.len())
            .min_by(|&a, &b| {
                let d = |v: usize| {
                    let p = field.topology.positions[v];
                    (p[0] - 0.5).powi(2) + (p[1] - 0.5).powi(2)
                };
                d(a).total_cmp(&d(b))
            })
            .unwrap();
        for k in 0..2 {
            for v in 0..size.len() {
                let s = step(&spacings, v, k);
                assert!((s - 0.05).abs() < 1e-9, "vertex {v}: {s}");
            }
            // the ratio carries the size map's growth: 0.08 · 0.05 / 0.06
            let s = step(&ratios, centre, k);
            assert!((s - 0.08 * 0.05 / 0.06).abs() < 1e-3, "{s}");
        }
        // on that size map, only the boundary spacing puts the points on the grid
        let bg = Background::new(&field, &size).unwrap();
        let face = &model.faces[0];
        let opts = FrontalOptions::default();
        // the largest distance of an inserted point from the grid of step 0.1
        let off_grid = |ft: &FaceTriangulation<'_>, first: usize| {
            ft.pos[first..]
                .iter()
                .flat_map(|p| (0..2).map(move |k| (p[k] - 0.1 * (p[k] / 0.1).round()).abs()))
                .fold(0.0, f64::max)
        };
        let mut by_ratio = FaceTriangulation::new(&model, FaceId(0), &cms, 0.1).unwrap();
        let nb = by_ratio.nodes.len();
        insert_frontal_points_directional(&mut by_ratio, face, &bg, &opts, Some(&ratios));
        let mut by_spacing = FaceTriangulation::new(&model, FaceId(0), &cms, 0.1).unwrap();
        let st =
            insert_frontal_points_directional(&mut by_spacing, face, &bg, &opts, Some(&spacings));
        assert_eq!(st.inserted, 81, "{st:?}");
        // the ratio's steps drift by up to half a cell; the spacing's stay
        // within a thousandth of it (the size and the ratio are interpolated
        // apart, the size linearly and the ratio in logarithm: 6e-6 here)
        let (ratio_off, spacing_off) = (off_grid(&by_ratio, nb), off_grid(&by_spacing, nb));
        assert!(ratio_off > 0.01, "{ratio_off}");
        assert!(spacing_off < 1e-4, "{spacing_off}");
    }

    #[test]
    fn of_several_front_spacings_the_face_keeps_the_fewest_irregular_vertices() {
        let (model, cms, field, size) = square_with_a_size_growing_inside();
        let mesh = |spacings: Vec<FrontSpacing>| {
            let opts = UnstructuredOptions {
                front_spacings: spacings,
                ..Default::default()
            };
            let (p, _) =
                mesh_face_unstructured(&model, FaceId(0), &cms, &field, &size, &opts).unwrap();
            (p.interior_irregular(), p)
        };
        let (by_ratio, _) = mesh(vec![FrontSpacing::BoundaryRatio]);
        let (by_spacing, grid) = mesh(vec![FrontSpacing::BoundarySpacing]);
        // the sides' grid: 10 × 10 coarse cells, 20 × 20 quads, all regular
        assert_eq!(by_spacing, 0);
        assert_eq!(grid.quads.len(), 400);
        assert!(by_ratio > 0, "the ratio's steps leave the grid");
        for order in [
            vec![FrontSpacing::BoundaryRatio, FrontSpacing::BoundarySpacing],
            vec![FrontSpacing::BoundarySpacing, FrontSpacing::BoundaryRatio],
        ] {
            let (irregular, p) = mesh(order);
            assert_eq!(irregular, 0);
            assert_eq!((&p.quads, &p.pos), (&grid.quads, &grid.pos));
        }
    }

    #[test]
    fn square_is_a_near_grid_of_valid_quads() {
        let m = primitives::square(1.0);
        let out = run(&m, 0.05);
        let (p, r) = &out[0];
        assert_eq!(p.quads.len(), 3 * r.leftover + 4 * r.recombined);
        // most triangles recombine
        assert!(r.recombined * 2 > 8 * r.leftover, "{r:?}");
        assert_eq!(invalid_quads(&m.faces[0], p), 0);
        // about (1 / 0.05)² = 400 quads
        assert!(
            (300..=560).contains(&p.quads.len()),
            "{} quads",
            p.quads.len()
        );
        // interior irregular nodes are few on a square
        let val = p.valences();
        let interior: Vec<usize> = (0..p.nodes.len())
            .filter(|&i| p.nodes[i].node == NodeRef::Interior && val[i] > 0)
            .collect();
        let irregular = interior.iter().filter(|&&i| val[i] != 4).count();
        assert!(
            irregular * 100 < 15 * interior.len(),
            "{irregular} of {} interior nodes irregular",
            interior.len()
        );
        let avg = p
            .quads
            .iter()
            .map(|q| quad_quality(&m.faces[0], &p.nodes, &p.pos, q))
            .sum::<f64>()
            / p.quads.len() as f64;
        assert!(avg > 0.8, "average SICN {avg}");
    }

    #[test]
    fn curved_faces_mesh_validly() {
        for m in [
            primitives::cylinder(1.0, 2.0),
            primitives::sphere(1.0),
            primitives::cone(1.0, 1.5),
        ] {
            for (f, (p, _)) in run(&m, 0.2).iter().enumerate() {
                assert!(!p.quads.is_empty());
                assert_eq!(invalid_quads(&m.faces[f], p), 0);
            }
        }
    }

    #[test]
    fn boundary_grading_limits_the_size() {
        let h = 0.05;
        let m = primitives::square(1.0);
        let (fields, cms) = crate::fixtures::grids::fields_and_curves(&m, h);
        let ff = fields.faces[0].outcome.as_ref().unwrap();
        let ft = FaceTriangulation::new(&m, FaceId(0), &cms, 2.0 * h).unwrap();
        let n = ff.field.topology.positions.len();
        let big = vec![1.0; n];
        let g = graded_sizes(&ft, &ff.field, &big, 0.5);
        for (v, s) in g.iter().enumerate() {
            let p = ff.field.topology.positions[v];
            // distance to the square's boundary
            let d = p[0].min(p[1]).min(1.0 - p[0]).min(1.0 - p[1]);
            assert!(
                *s >= h + 0.5 * d - 1e-9 && *s <= h + 0.5 * (d + h) + 1e-9,
                "vertex {v} at {p:?}: {s}"
            );
        }
        // infinite gradation: the size map itself
        assert_eq!(graded_sizes(&ft, &ff.field, &big, f64::INFINITY), big);
    }

    #[test]
    fn cavity_remeshing_keeps_faces_valid_and_never_adds_irregular_vertices() {
        let m = primitives::sphere(1.0);
        let h = 0.125;
        let (fields, cms) = crate::fixtures::grids::fields_and_curves(&m, h);
        let ff = fields.faces[0].outcome.as_ref().unwrap();
        let size = ff.size.clone().unwrap();
        let (p, _) = mesh_face_unstructured(
            &m,
            FaceId(0),
            &cms,
            &ff.field,
            &size,
            &UnstructuredOptions::default(),
        )
        .unwrap();
        let irregular = |p: &QuadPatch| p.interior_irregular();
        let face = &m.faces[0];
        let off = UnstructuredOptions {
            cavity: None,
            ..Default::default()
        };
        let (mut without, mut with) = (p.clone(), p);
        let (_, none) = improve_face(
            face,
            &mut without,
            &ff.singularities.list,
            &off,
            &mut StageTimes::default(),
        );
        assert_eq!(none, CavityReport::default());
        let (_, r) = improve_face(
            face,
            &mut with,
            &ff.singularities.list,
            &UnstructuredOptions::default(),
            &mut StageTimes::default(),
        );
        assert_eq!(invalid_quads(face, &with), 0);
        assert_eq!(r.irregular_after, irregular(&with));
        assert!(r.irregular_after <= r.irregular_before, "{r:?}");
        assert!(
            irregular(&with) <= irregular(&without),
            "{} with cavities, {} without: {r:?}",
            irregular(&with),
            irregular(&without)
        );
        assert!(!r.capped, "{r:?}");
        // the sphere's frontal mesh has removable irregular vertices
        assert!(
            r.replaced.iter().sum::<usize>() > 0 && irregular(&with) < irregular(&without),
            "{r:?}"
        );
    }

    #[test]
    fn the_pipeline_method_meshes_primitives_without_fallback() {
        use crate::{mesh_model_with, MeshMethod, MeshOptions};
        for m in [
            primitives::cylinder(1.0, 2.0),
            primitives::sphere(1.0),
            primitives::cone(1.0, 1.5),
            primitives::square(1.0),
        ] {
            let (mesh, report) =
                mesh_model_with(&m, &MeshOptions::default(), MeshMethod::default()).unwrap();
            assert!(report.fallback.is_empty(), "{:?}", report.fallback);
            let sicn = mesh::stats::quad_acceptance_sicn_values(&mesh, Some(&m));
            assert!(!sicn.is_empty() && sicn.iter().all(|&s| s > 0.0));
            // fewer quads than the baseline's three per triangle
            let base = mesh_model_with(&m, &MeshOptions::default(), MeshMethod::Baseline)
                .unwrap()
                .0;
            assert!(
                mesh.quads.len() < base.quads.len(),
                "{} vs {}",
                mesh.quads.len(),
                base.quads.len()
            );
        }
        let m = primitives::square(1.0);
        let bad = MeshOptions {
            size: crate::core::options::Size::Absolute(-1.0),
            ..Default::default()
        };
        assert!(mesh_model_with(&m, &bad, MeshMethod::default()).is_err());
        let mut empty = m.clone();
        empty.faces.clear();
        assert!(mesh_model_with(&empty, &MeshOptions::default(), MeshMethod::default()).is_err());
    }
}
