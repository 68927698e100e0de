//! Meshing a simple CAD face directly with a pattern (paper §6.1.2, spec
//! §9.6): a face with one boundary loop whose convex corners (ideal
//! valence 1) split it into the sides of a library pattern
//! ([`crate::combinatorics::patterns`]) gets the refined pattern, its boundary on the
//! face's curve meshes, its interior placed by a harmonic map in (u, v)
//! and evaluated on the surface.
//! The result is kept only when every quad has a SICN (with CAD normals) of
//! at least [`MIN_PATTERN_SICN`]; otherwise the caller meshes the face
//! another way.

use std::collections::HashMap;

use geometry::vec3::{self, Vec3};
use geometry::{FaceId, Model};

use crate::combinatorics::patterns::{library, match_pattern, refine};
use crate::core::patch::QuadPatch;
use crate::core::patch::{LocalNode, NodeRef};
use crate::core::quality::quad_quality;
use crate::core::queries::folds_at_pole;
use crate::core::valence::ideal_corner_valence;
use crate::curves::curve_chords::use_start_angle;
use crate::curves::curve_mesh::CurveMesh;

/// Smallest quad SICN a pattern mesh must reach to be kept (the paper's
/// "satisfactory quality"; its value is ours).
pub const MIN_PATTERN_SICN: f64 = 0.3;

/// Conjugate-gradient iterations of the harmonic map, at most (times √n).
const CG_ITERATIONS_PER_ROOT: usize = 40;

/// One boundary loop of a face as a ring of local nodes with 3D positions,
/// and the ring positions of its CAD corners with their interior angles.
pub(crate) struct Ring {
    /// The loop's nodes in its order.
    pub(crate) nodes: Vec<LocalNode>,
    /// Their 3D positions.
    pub(crate) pos: Vec<Vec3>,
    /// (ring position, interior angle in radians) of each CAD corner.
    pub(crate) corners: Vec<(usize, f64)>,
}

/// The face's single loop as a ring ([`loop_ring`]).
pub(crate) fn boundary_ring(model: &Model, fid: FaceId, cms: &[CurveMesh]) -> Result<Ring, String> {
    let face = &model.faces[fid.idx()];
    if face.loops.len() != 1 {
        return Err(format!("{} boundary loops", face.loops.len()));
    }
    loop_ring(model, fid, cms, 0)
}

/// Loop `li` of the face as a ring of every curve-mesh point (the odd
/// midpoints included), with the interior angle at each CAD corner.
pub(crate) fn loop_ring(
    model: &Model,
    fid: FaceId,
    cms: &[CurveMesh],
    li: usize,
) -> Result<Ring, String> {
    let face = &model.faces[fid.idx()];
    let lp = face.loops.get(li).ok_or("no such loop")?;
    let mut ring = Ring {
        nodes: Vec::new(),
        pos: Vec::new(),
        corners: Vec::new(),
    };
    let n = lp.uses.len();
    let degenerate = |k: usize| model.curves[lp.uses[k % n].curve.idx()].degenerate;
    if (0..n).all(degenerate) {
        return Err("only degenerate curves".into());
    }
    // a pole (degenerate use) is one ring node; its corner angle is measured
    // in 3D between the neighbouring ring points, once they are known
    for (k, u) in lp.uses.iter().enumerate() {
        let ce = &model.curves[u.curve.idx()];
        let cm = cms.get(u.curve.idx()).ok_or("missing curve mesh")?;
        if ce.degenerate {
            if degenerate(k + n - 1) {
                return Err("two degenerate curves in a row".into());
            }
            let seg = face.pole_segment(u, ce);
            let mid = [0.5 * (seg[0][0] + seg[1][0]), 0.5 * (seg[0][1] + seg[1][1])];
            ring.corners.push((ring.nodes.len(), f64::NAN));
            ring.nodes.push(LocalNode {
                uv: mid,
                node: NodeRef::Corner(ce.start),
                pole: Some(seg),
            });
            ring.pos.push(model.corners[ce.start.idx()].point);
            continue;
        }
        let m = cm.params.len() - 1;
        let after_pole = degenerate(k + n - 1);
        if !after_pole {
            // the corner where this use starts: angle between the previous use's end and this use's start
            let angle = use_start_angle(model, face, lp, k).ok_or("corner angle undefined")?;
            ring.corners.push((ring.nodes.len(), angle));
        }
        // after a pole, the use's first point is the pole, already in the ring
        for j in usize::from(after_pole)..m {
            let i = if u.forward { j } else { m - j };
            let node = if i == 0 {
                NodeRef::Corner(ce.start)
            } else if i == m {
                NodeRef::Corner(ce.end)
            } else {
                NodeRef::Curve(u.curve, i as u32)
            };
            let uv = u.pcurve.eval(cm.params[i]);
            if !(uv[0].is_finite() && uv[1].is_finite()) {
                return Err(format!("pcurve of curve {} is not finite", u.curve.0 + 1));
            }
            ring.nodes.push(LocalNode {
                uv,
                node,
                pole: None,
            });
            ring.pos.push(cm.points[i]);
        }
    }
    let len = ring.nodes.len();
    if len < 3 {
        return Err("fewer than 3 boundary points".into());
    }
    for c in ring.corners.iter_mut().filter(|c| c.1.is_nan()) {
        let p = ring.pos[c.0];
        let (a, b) = (
            vec3::sub(ring.pos[(c.0 + len - 1) % len], p),
            vec3::sub(ring.pos[(c.0 + 1) % len], p),
        );
        c.1 = (vec3::dot(a, b) / (vec3::norm(a) * vec3::norm(b)))
            .clamp(-1.0, 1.0)
            .acos();
        if !c.1.is_finite() {
            return Err("corner angle at a pole undefined".into());
        }
    }
    Ok(ring)
}

/// The interior (u, v) of a refined grid pattern (pattern coordinates
/// `coords` in the unit square, boundary values in `uv` where `fixed`) by
/// transfinite interpolation: each grid line blends the boundary nodes at
/// its two ends. Only the start of [`harmonic_uv`]: from the centroid, the
/// conjugate gradients of a large grid face take most of the pattern stage
/// (i01o_m1 at size factor 0.0625). Vertices whose four boundary
/// neighbours are not found keep their (u, v).
fn transfinite_uv(coords: &[[f64; 2]], uv: &mut [[f64; 2]], fixed: &[bool]) {
    let key = |x: f64| (x * 1e9).round() as i64;
    // boundary values on the four sides, by the coordinate along the side
    let mut sides: [HashMap<i64, [f64; 2]>; 4] = Default::default();
    for (v, c) in coords.iter().enumerate() {
        if !fixed[v] {
            continue;
        }
        for (side, (along, at)) in [
            (c[0], c[1] == 0.0),
            (c[0], c[1] == 1.0),
            (c[1], c[0] == 0.0),
            (c[1], c[0] == 1.0),
        ]
        .into_iter()
        .enumerate()
        {
            if at {
                sides[side].insert(key(along), uv[v]);
            }
        }
    }
    let [bottom, top, left, right] = &sides;
    let (Some(p00), Some(p10), Some(p01), Some(p11)) = (
        bottom.get(&key(0.0)),
        bottom.get(&key(1.0)),
        top.get(&key(0.0)),
        top.get(&key(1.0)),
    ) else {
        return;
    };
    for (v, &[s, t]) in coords.iter().enumerate() {
        if fixed[v] {
            continue;
        }
        let (Some(b), Some(tp), Some(l), Some(r)) = (
            bottom.get(&key(s)),
            top.get(&key(s)),
            left.get(&key(t)),
            right.get(&key(t)),
        ) else {
            continue;
        };
        for d in 0..2 {
            uv[v][d] = (1.0 - t) * b[d] + t * tp[d] + (1.0 - s) * l[d] + s * r[d]
                - ((1.0 - s) * (1.0 - t) * p00[d]
                    + s * (1.0 - t) * p10[d]
                    + (1.0 - s) * t * p01[d]
                    + s * t * p11[d]);
        }
    }
}

/// Solves the uniform-weight Laplace equation for the interior (u, v) of a
/// quad mesh with fixed boundary values (conjugate gradients, one solve per
/// coordinate). `fixed[v]` marks boundary vertices.
pub(crate) fn harmonic_uv(quads: &[[u32; 4]], uv: &mut [[f64; 2]], fixed: &[bool]) {
    let n = uv.len();
    // the edges as sorted (vertex, neighbour) pairs: each vertex's
    // neighbours in increasing order, without a list per vertex
    let mut pairs: Vec<(u32, u32)> = Vec::with_capacity(8 * quads.len());
    for q in quads {
        for k in 0..4 {
            pairs.push((q[k], q[(k + 1) % 4]));
            pairs.push((q[k], q[(k + 3) % 4]));
        }
    }
    pairs.sort_unstable();
    pairs.dedup();
    let mut first = vec![0usize; n + 1];
    for &(v, _) in &pairs {
        first[v as usize + 1] += 1;
    }
    for v in 0..n {
        first[v + 1] += first[v];
    }
    let nbrs = |v: usize| pairs[first[v]..first[v + 1]].iter().map(|&(_, w)| w);
    let free: Vec<usize> = (0..n).filter(|&v| !fixed[v]).collect();
    let mut slot = vec![usize::MAX; n];
    for (i, &v) in free.iter().enumerate() {
        slot[v] = i;
    }
    let m = free.len();
    if m == 0 {
        return;
    }
    // each free vertex's degree and its free neighbours' slots, in order
    let degree: Vec<f64> = free
        .iter()
        .map(|&v| (first[v + 1] - first[v]) as f64)
        .collect();
    let mut free_first = Vec::with_capacity(m + 1);
    let mut free_nbrs: Vec<usize> = Vec::new();
    free_first.push(0);
    for &v in &free {
        free_nbrs.extend(
            nbrs(v)
                .map(|w| slot[w as usize])
                .filter(|&s| s != usize::MAX),
        );
        free_first.push(free_nbrs.len());
    }
    // A x = b: deg(v) x_v − Σ_{free nbrs} x_w = Σ_{fixed nbrs} uv_w
    let apply = |x: &[f64], out: &mut [f64]| {
        for i in 0..m {
            let mut s = degree[i] * x[i];
            for &j in &free_nbrs[free_first[i]..free_first[i + 1]] {
                s -= x[j];
            }
            out[i] = s;
        }
    };
    let max_iter = CG_ITERATIONS_PER_ROOT * ((m as f64).sqrt() as usize + 1);
    for c in 0..2 {
        let b: Vec<f64> = free
            .iter()
            .map(|&v| {
                nbrs(v)
                    .filter(|&w| fixed[w as usize])
                    .map(|w| uv[w as usize][c])
                    .sum()
            })
            .collect();
        let mut x: Vec<f64> = free.iter().map(|&v| uv[v][c]).collect();
        let mut ax = vec![0.0; m];
        apply(&x, &mut ax);
        let mut r: Vec<f64> = b.iter().zip(&ax).map(|(b, a)| b - a).collect();
        let mut p = r.clone();
        let mut rr: f64 = r.iter().map(|x| x * x).sum();
        let stop = 1e-16 * b.iter().map(|x| x * x).sum::<f64>().max(1e-300);
        let mut ap = vec![0.0; m];
        for _ in 0..max_iter {
            if rr <= stop {
                break;
            }
            apply(&p, &mut ap);
            let pap: f64 = p.iter().zip(&ap).map(|(a, b)| a * b).sum();
            if !(pap > 0.0) {
                break;
            }
            let alpha = rr / pap;
            for i in 0..m {
                x[i] += alpha * p[i];
                r[i] -= alpha * ap[i];
            }
            let rr_new: f64 = r.iter().map(|x| x * x).sum();
            let beta = rr_new / rr;
            rr = rr_new;
            for i in 0..m {
                p[i] = r[i] + beta * p[i];
            }
        }
        for (i, &v) in free.iter().enumerate() {
            uv[v][c] = x[i];
        }
    }
}

/// Meshes face `fid` with a library pattern against the curve meshes `cms`
/// (every curve point is a boundary node); an annulus as a ring grid when
/// `ring_grids`. Returns the patch and the pattern's name, or why the face
/// is not meshed that way.
pub fn mesh_face_pattern(
    model: &Model,
    fid: FaceId,
    cms: &[CurveMesh],
    ring_grids: bool,
) -> Result<(QuadPatch, String), String> {
    if let Some(Ok(patch)) = crate::direct::sphere_face::mesh_full_sphere(model, fid, cms) {
        return Ok((patch, "cube".into()));
    }
    let face = &model.faces[fid.idx()];
    if ring_grids && crate::curves::curve_chords::annulus_loops(model, face).is_some() {
        return crate::direct::ring_face::mesh_ring_face(model, fid, cms)
            .map(|p| (p, crate::direct::ring_face::RING_GRID.into()));
    }
    if face.loops.len() == 2 {
        return crate::direct::holed_face::mesh_holed_face(model, fid, cms)
            .map(|p| (p, crate::direct::holed_face::HOLED_GRID.into()));
    }
    let ring = boundary_ring(model, fid, cms)?;
    let nb = ring.nodes.len();
    // two CAD corners: a narrow lens gets two rows of quads on its boundary
    // points; its tips are cusps, whose angle may read 0° or 360°
    if let [(c0, _), (c1, _)] = ring.corners[..] {
        match crate::direct::strip_face::mesh_lens_strip(face, &ring, [c0, c1]) {
            Ok(p) => return Ok((p, crate::direct::strip_face::LENS_STRIP.into())),
            Err(why) => tracing::debug!("face {}: no lens strip: {why}", fid.0 + 1),
        }
    }
    // convex corners (ideal valence 1) are the pattern's corners; flat ones
    // (2) lie inside sides; a concave one rules patterns out
    let mut corners = Vec::new();
    for &(at, angle) in &ring.corners {
        match ideal_corner_valence(angle) {
            // one quad would span the whole fan of normals at the pole (a
            // half cone's apex: its corner folds, SICN ≈ 0 with the CAD
            // normals, however it looks from the middle direction)
            1 if ring.nodes[at]
                .pole
                .is_some_and(|seg| folds_at_pole(face, seg)) =>
            {
                return Err(format!(
                    "a folding pole corner ({:.0}°)",
                    angle.to_degrees()
                ))
            }
            1 => corners.push(at),
            2 => {}
            _ => return Err(format!("a concave corner ({:.0}°)", angle.to_degrees())),
        }
    }
    if corners.is_empty() {
        // every corner flat: a disk bounded by one smooth loop
        return crate::direct::o_grid::mesh_disk_o_grid(face, &ring)
            .map(|(p, name)| (p, name.into()));
    }
    if corners.len() < 3 {
        return Err(format!("{} convex corners", corners.len()));
    }
    let m = corners.len();
    let sides: Vec<u32> = (0..m)
        .map(|i| ((corners[(i + 1) % m] + nb - corners[i]) % nb) as u32)
        .collect();
    let found = match_pattern(&sides).ok_or_else(|| format!("no pattern for sides {sides:?}"))?;
    let pattern = &library()[found.pattern];
    let refined = refine(pattern, &found.subdivisions);
    // refined boundary vertex k ↔ ring position (see `PatternMatch`)
    let ring_of = |k: usize| {
        if found.mirror {
            (corners[(found.shift + 1) % m] + nb - k % nb) % nb
        } else {
            (corners[found.shift] + k) % nb
        }
    };
    let nv = refined.coords.len();
    let mut local = vec![u32::MAX; nv];
    let mut nodes: Vec<LocalNode> = ring.nodes.clone();
    let mut pos: Vec<Vec3> = ring.pos.clone();
    let mut fixed = vec![false; nv];
    for (k, &v) in refined.boundary.iter().enumerate() {
        local[v as usize] = ring_of(k) as u32;
        fixed[v as usize] = true;
    }
    // interior (u, v): harmonic in the pattern's connectivity, starting from the ring's centroid
    let centroid = uv_centroid(&ring.nodes);
    let mut uv: Vec<[f64; 2]> = (0..nv)
        .map(|v| {
            if fixed[v] {
                ring.nodes[local[v] as usize].uv
            } else {
                centroid
            }
        })
        .collect();
    // a grid starts from its transfinite interpolation, which the harmonic
    // solve then needs few iterations to correct
    if pattern.sides() == 4 && pattern.irregular == 0 {
        transfinite_uv(&refined.coords, &mut uv, &fixed);
    }
    harmonic_uv(&refined.quads, &mut uv, &fixed);
    place_interior(face, &uv, &fixed, &mut local, &mut nodes, &mut pos)?;
    let quads: Vec<[u32; 4]> = refined
        .quads
        .iter()
        .map(|q| {
            let l = q.map(|v| local[v as usize]);
            // counter-clockwise in (u, v), then about the oriented normal
            if found.mirror != face.reversed {
                [l[0], l[3], l[2], l[1]]
            } else {
                l
            }
        })
        .collect();
    let patch = smooth_and_check(face, nodes, pos, quads, &pattern.name)?;
    Ok((patch, pattern.name.clone()))
}

/// Puts every vertex of a pattern that is not `fixed` on the surface at its
/// `uv`, appending it to `nodes` and `pos` and recording its local id in
/// `local`; an error when one falls outside the surface.
pub(crate) fn place_interior(
    face: &geometry::Face,
    uv: &[[f64; 2]],
    fixed: &[bool],
    local: &mut [u32],
    nodes: &mut Vec<LocalNode>,
    pos: &mut Vec<Vec3>,
) -> Result<(), String> {
    for v in 0..uv.len() {
        if fixed[v] {
            continue;
        }
        let p = face.surface.eval(uv[v]);
        if !p.iter().all(|x| x.is_finite()) {
            return Err("a pattern vertex falls outside the surface".into());
        }
        local[v] = nodes.len() as u32;
        nodes.push(LocalNode {
            uv: uv[v],
            node: NodeRef::Interior,
            pole: None,
        });
        pos.push(p);
    }
    Ok(())
}

/// The ring position `k` steps from position `r` on a ring of `n` nodes,
/// forward when `same_sense` (the ring turns like the loop it is matched
/// to), backward otherwise: how the ring and holed grids walk a hole's
/// loop beside the outer one.
pub(crate) fn ring_step(r: usize, k: usize, n: usize, same_sense: bool) -> usize {
    if same_sense {
        (r + k) % n
    } else {
        (r + n - k % n) % n
    }
}

/// Whether `quads`, with their vertices at `uv`, must be reversed to run
/// counter-clockwise in (u, v) and then about the face's oriented normal.
pub(crate) fn needs_reversal(face: &geometry::Face, quads: &[[u32; 4]], uv: &[[f64; 2]]) -> bool {
    let area: f64 = quads
        .iter()
        .map(|q| {
            let p = q.map(|v| uv[v as usize]);
            (p[2][0] - p[0][0]) * (p[3][1] - p[1][1]) - (p[2][1] - p[0][1]) * (p[3][0] - p[1][0])
        })
        .sum();
    (area < 0.0) != face.reversed
}

/// The patch of a grid between two loops (`outer`, then `hole`, are the
/// first local nodes): the grid's vertices not `fixed` placed at `uv` on the
/// surface, its `quads` (grid vertex ids, mapped through `local`) turned to
/// run counter-clockwise about the face normal, smoothed and checked
/// ([`smooth_and_check`], naming `pattern`; with `excuse_short_edges`, a
/// quad on a loop edge shorter than [`SHORT_LOOP_EDGE`] of its loop's mean
/// edge, or beside one, need only be valid, see [`short_loop_edge_nodes`]). Shared by
/// [`crate::direct::holed_face`] and [`crate::direct::ring_face`].
#[allow(clippy::too_many_arguments)]
pub(crate) fn two_loop_patch(
    face: &geometry::Face,
    outer: &Ring,
    hole: &Ring,
    uv: &[[f64; 2]],
    fixed: &[bool],
    local: &mut [u32],
    quads: &[[u32; 4]],
    pattern: &str,
    excuse_short_edges: bool,
) -> Result<QuadPatch, String> {
    let mut nodes: Vec<LocalNode> = outer.nodes.iter().chain(&hole.nodes).copied().collect();
    let mut pos: Vec<Vec3> = outer.pos.iter().chain(&hole.pos).copied().collect();
    place_interior(face, uv, fixed, local, &mut nodes, &mut pos)?;
    let reverse = needs_reversal(face, quads, uv);
    let quads: Vec<[u32; 4]> = quads
        .iter()
        .map(|q| {
            let mut l = q.map(|v| local[v as usize]);
            if reverse {
                l.reverse();
            }
            l
        })
        .collect();
    let short = if excuse_short_edges {
        short_loop_edge_nodes(&[&outer.pos, &hole.pos])
    } else {
        Vec::new()
    };
    smooth_and_check_excusing(face, nodes, pos, quads, pattern, MIN_PATTERN_SICN, &short)
}

/// A loop edge shorter than this share of its loop's mean edge length is a
/// sliver of the CAD (a curve of a few thousandths of the cell size, as
/// where a hex nut's corner is turned off by its across-corners cylinder):
/// the quad on it is as thin as the edge, whatever the pattern.
pub const SHORT_LOOP_EDGE: f64 = 0.1;

/// Share of the floor that the quads not at a sliver edge must reach when
/// the loops hold one ([`smooth_and_check_excusing`]).
pub const SLIVER_FLOOR_SHARE: f64 = 0.5;

/// The pairs of local node ids (the closed loops' points numbered
/// `loops[0]` first, as in [`two_loop_patch`]) joined by a loop edge shorter
/// than [`SHORT_LOOP_EDGE`] × its loop's mean edge.
pub(crate) fn short_loop_edge_nodes(loops: &[&[Vec3]]) -> Vec<[u32; 2]> {
    let mut pairs = Vec::new();
    let mut first = 0usize;
    for pos in loops {
        let n = pos.len();
        let length = |k: usize| vec3::norm(vec3::sub(pos[(k + 1) % n], pos[k]));
        let mean = (0..n).map(length).sum::<f64>() / n.max(1) as f64;
        for k in 0..n {
            if length(k) < SHORT_LOOP_EDGE * mean {
                pairs.push([(first + k) as u32, (first + (k + 1) % n) as u32]);
            }
        }
        first += n;
    }
    pairs
}

/// A patch from a pattern's quads (counter-clockwise about the face normal)
/// on `nodes` at `pos`, smoothed; refused when a quad stays below
/// [`MIN_PATTERN_SICN`] (the error names `pattern`). Shared by the library
/// patterns and [`crate::direct::sphere_face`].
pub fn smooth_and_check(
    face: &geometry::Face,
    nodes: Vec<LocalNode>,
    pos: Vec<Vec3>,
    quads: Vec<[u32; 4]>,
    pattern: &str,
) -> Result<QuadPatch, String> {
    smooth_and_check_above(face, nodes, pos, quads, pattern, MIN_PATTERN_SICN)
}

/// [`smooth_and_check`] with a floor of the pattern's own instead of
/// [`MIN_PATTERN_SICN`].
pub(crate) fn smooth_and_check_above(
    face: &geometry::Face,
    nodes: Vec<LocalNode>,
    pos: Vec<Vec3>,
    quads: Vec<[u32; 4]>,
    pattern: &str,
    min_sicn: f64,
) -> Result<QuadPatch, String> {
    smooth_and_check_excusing(face, nodes, pos, quads, pattern, min_sicn, &[])
}

/// [`smooth_and_check_above`], where a quad at a node of a pair of
/// `short_edges` (the ends of a CAD sliver curve, see [`SHORT_LOOP_EDGE`])
/// need only be valid (SICN above 0), and the others, when there are such
/// edges, [`SLIVER_FLOOR_SHARE`] of `min_sicn`: the grid lines from a
/// sliver's two ends stay close for a few cells, so its neighbours are thin
/// too (a hex nut's ring grid: 0.295 two cells in, 0.73 at worst by angle).
pub(crate) fn smooth_and_check_excusing(
    face: &geometry::Face,
    nodes: Vec<LocalNode>,
    pos: Vec<Vec3>,
    quads: Vec<[u32; 4]>,
    pattern: &str,
    min_sicn: f64,
    short_edges: &[[u32; 2]],
) -> Result<QuadPatch, String> {
    let mut patch = QuadPatch {
        quad_tri: (0..quads.len() as u32).collect(),
        nodes,
        pos,
        quads,
    };
    crate::smoothing::optimize(
        face,
        &mut patch,
        &crate::smoothing::OptimizeOptions::default(),
    );
    let at_short_edge = |q: &[u32; 4]| q.iter().any(|v| short_edges.iter().any(|e| e.contains(v)));
    for q in &patch.quads {
        let sicn = quad_quality(face, &patch.nodes, &patch.pos, q);
        let floor = if at_short_edge(q) {
            0.0
        } else if short_edges.is_empty() {
            min_sicn
        } else {
            SLIVER_FLOOR_SHARE * min_sicn
        };
        if !(sicn > floor || (floor > 0.0 && sicn >= floor)) {
            return Err(format!("pattern {pattern} gives a quad of SICN {sicn:.3}"));
        }
    }
    Ok(patch)
}

/// Signed area of a ring in (u, v) (positive: counter-clockwise).
pub(crate) fn uv_area(ring: &Ring) -> f64 {
    let n = ring.nodes.len();
    (0..n)
        .map(|i| {
            let (a, b) = (ring.nodes[i].uv, ring.nodes[(i + 1) % n].uv);
            a[0] * b[1] - a[1] * b[0]
        })
        .sum::<f64>()
        * 0.5
}

/// The mean (u, v) of `nodes` (the start of a harmonic fill inside a ring).
pub(crate) fn uv_centroid(nodes: &[LocalNode]) -> [f64; 2] {
    let s = nodes
        .iter()
        .fold([0.0, 0.0], |s, n| [s[0] + n.uv[0], s[1] + n.uv[1]]);
    let n = nodes.len().max(1) as f64;
    [s[0] / n, s[1] / n]
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_loop_edge_far_below_its_loops_mean_is_a_sliver() {
        // a unit square's outer loop with one corner cut off by an edge of
        // 0.014 (its loop's mean edge 0.8), and a hole of four equal edges:
        // only the cut is short
        let outer = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 0.99, 0.0],
            [0.99, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let hole = [
            [0.4, 0.4, 0.0],
            [0.6, 0.4, 0.0],
            [0.6, 0.6, 0.0],
            [0.4, 0.6, 0.0],
        ];
        assert_eq!(super::short_loop_edge_nodes(&[&outer, &hole]), vec![[2, 3]]);
        // the hole's edges (0.2) are short beside the outer loop's but not
        // beside their own loop's mean: loops are judged apart; a hole with
        // one short edge is numbered after the outer loop's five points
        let hole_cut = [
            [0.4, 0.4, 0.0],
            [0.6, 0.4, 0.0],
            [0.6, 0.599, 0.0],
            [0.599, 0.6, 0.0],
            [0.4, 0.6, 0.0],
        ];
        assert_eq!(
            super::short_loop_edge_nodes(&[&outer, &hole_cut]),
            vec![[2, 3], [7, 8]]
        );
    }

    use super::*;
    use crate::direct::O_GRID;
    use crate::curves::curve_mesh::{discretize_all, plan_curves};
    use geometry::primitives;

    fn valences(p: &QuadPatch) -> Vec<usize> {
        p.valences()
    }

    #[test]
    fn a_rectangle_is_a_grid() {
        let model = primitives::rectangle(3.0, 1.0);
        let cms = discretize_all(&model, &plan_curves(&model, 0.25));
        let (patch, name) = mesh_face_pattern(&model, FaceId(0), &cms, true).expect("a pattern");
        assert_eq!(name, "R1");
        // 3 / 0.25 = 12 by 1 / 0.25 = 4
        assert_eq!(patch.quads.len(), 48);
        let v = valences(&patch);
        for (i, n) in patch.nodes.iter().enumerate() {
            if n.node == NodeRef::Interior {
                assert_eq!(v[i], 4);
                // a harmonic grid on a rectangle is the uniform grid
                let (x, y) = (n.uv[0] / 0.25, n.uv[1] / 0.25);
                assert!(
                    (x - x.round()).abs() < 1e-6 && (y - y.round()).abs() < 1e-6,
                    "{:?}",
                    n.uv
                );
            }
        }
        assert!(patch.quads.iter().all(|q| quad_quality(
            &model.faces[0],
            &patch.nodes,
            &patch.pos,
            q
        ) > 0.999));
        // a reversed face gets its quads turned the other way, still valid
        let mut flipped = model.clone();
        flipped.faces[0].reversed = true;
        let (back, _) = mesh_face_pattern(&flipped, FaceId(0), &cms, true).expect("a pattern");
        assert_eq!(back.quads.len(), 48);
        assert_ne!(back.quads[0], patch.quads[0]);
        assert!(back.quads.iter().all(|q| quad_quality(
            &flipped.faces[0],
            &back.nodes,
            &back.pos,
            q
        ) > 0.999));
    }

    #[test]
    fn a_cylinder_side_is_a_grid_and_its_discs_are_o_grids() {
        let model = primitives::cylinder(1.0, 2.0);
        let cms = discretize_all(&model, &plan_curves(&model, 0.3));
        let mut names = Vec::new();
        for f in 0..model.faces.len() {
            let (patch, name) =
                mesh_face_pattern(&model, FaceId(f as u32), &cms, true).expect("a pattern");
            let v = valences(&patch);
            let interior = |i: usize| patch.nodes[i].node == NodeRef::Interior;
            let irregular = (0..v.len()).filter(|&i| interior(i) && v[i] != 4).count();
            if name == O_GRID {
                // the middle grid's four corners, valence 3; every boundary
                // node on two quads (no 180° corner)
                assert_eq!(irregular, 4, "face {f}");
                assert!((0..v.len())
                    .all(|i| interior(i) && (v[i] == 3 || v[i] == 4) || !interior(i) && v[i] == 2));
                let worst = patch
                    .quads
                    .iter()
                    .map(|q| quad_quality(&model.faces[f], &patch.nodes, &patch.pos, q))
                    .fold(f64::INFINITY, f64::min);
                assert!(worst > 0.6, "face {f}: worst SICN {worst}");
            } else {
                assert_eq!(irregular, 0, "face {f}");
            }
            names.push(name);
        }
        names.sort();
        // the side (seam, circle, seam, circle) is a 4-sided grid
        assert_eq!(names, ["O", "O", "R1"]);
    }
}
