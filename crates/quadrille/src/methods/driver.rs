//! The driver every method shares: each face meshed in parallel by the
//! method's per-face mesher, the curves around failed faces refined and
//! those faces meshed again, then one global [`QuadMesh`] assembled in face
//! order, so that the output is bit-identical for any thread count.

use std::collections::{BTreeMap, BTreeSet};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::OnceLock;
use std::time::Instant;

use geometry::vec3::{self, Vec3};
use geometry::{CornerId, CurveId, Face, FaceId, Model};
use mesh::{NodeClass, QuadMesh};

use crate::core::error::MeshError;
use crate::core::options::ProgressFn;
use crate::core::patch::{FaceFailure, FailureSpot, NodeRef};
use crate::core::queries::sharp_corners_of;
use crate::curves::curve_mesh::{discretize_all, CurveMesh, CurvePlan};
use crate::methods::report::{FaceOutcome, StageTimes};

/// Sweeps of [`crate::smoothing::curve_slide::slide_curve_nodes`] over the assembled mesh.
pub(crate) const CURVE_SLIDE_SWEEPS: usize = 10;
/// Rounds that double the chord classes of failed faces' curves (the last
/// resort after [`LOCAL_ROUNDS`]) and mesh them again.
const CURVE_ROUNDS: usize = 6;
/// Rounds of local refinement ([`refine_near_spots`]) a face with inverted
/// quads gets before the chord classes of its curves are doubled.
const LOCAL_ROUNDS: usize = 8;
/// The coarse spacing a local refinement asks for at an inverted quad, as a
/// share of the coarse segment nearest to it.
const LOCAL_SPACING_FRACTION: f64 = 0.25;
/// Refinement stops (the face fails, with a warning) before a round that is
/// expected to take the model's quads beyond this multiple of the first
/// round's: doubling whole chord classes round after round took a flange
/// from 2,900 quads to a million. Not 4 or 16: the baseline method meshes
/// that flange after four doubling rounds at 5.9 times its first round's
/// quads, and an NPS 4 slip-on flange at 11 times (this estimate: 22).
const MAX_GROWTH: f64 = 32.0;
/// Curves shorter than this share of the model's diagonal are slivers, meshed
/// as a point ([`geometry::slivers`]): far below any mesh size (the default
/// is 1/24 of the diagonal), and a quad edge that short is a degenerate quad.
pub const SLIVER_LENGTH: f64 = 1e-5;

/// The model [`crate::MeshMethod::Unstructured`] and
/// [`crate::MeshMethod::QuasiStructured`] work on: `model` with its sliver
/// curves (shorter than [`SLIVER_LENGTH`] of the diagonal) collapsed to
/// points, same ids ([`geometry::slivers::collapse_short_curves`]); `None`
/// when it has none. The baseline keeps them: its triangle split gives a
/// sliver two short quad edges, which the regular method then works around.
pub fn collapse_slivers(model: &Model) -> Option<(Model, Vec<geometry::slivers::Collapsed>)> {
    geometry::slivers::collapse_short_curves(model, SLIVER_LENGTH * model.diagonal())
}

/// What a per-face mesher gets: the model, the face, the curve meshes, and
/// the face's sharp corners computed once when first asked for.
pub(crate) struct FaceContext<'a> {
    /// The model.
    pub model: &'a Model,
    /// The face's id.
    pub fid: FaceId,
    /// The face.
    pub face: &'a Face,
    /// The meshes of every curve of the model.
    pub cms: &'a [CurveMesh],
    sharp: OnceLock<Vec<CornerId>>,
}

impl<'a> FaceContext<'a> {
    /// The context of face `fid`.
    pub fn new(model: &'a Model, fid: FaceId, cms: &'a [CurveMesh]) -> Self {
        FaceContext {
            model,
            fid,
            face: &model.faces[fid.idx()],
            cms,
            sharp: OnceLock::new(),
        }
    }

    /// The face's corners too sharp for any good quad ([`sharp_corners_of`]).
    pub fn sharp_corners(&self) -> &[CornerId] {
        self.sharp
            .get_or_init(|| sharp_corners_of(self.model, self.fid))
    }
}

/// Runs `go` on a pool of `threads` threads, or on rayon's global pool.
pub(crate) fn in_pool<T: Send>(
    threads: Option<usize>,
    go: impl FnOnce() -> Result<T, MeshError> + Send,
) -> Result<T, MeshError> {
    match threads {
        Some(n) => {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(n.max(1))
                .build()
                .map_err(|e| MeshError::Threads {
                    threads: n,
                    reason: e.to_string(),
                })?;
            pool.install(go)
        }
        None => go(),
    }
}

/// Per-face mesher of [`mesh_faces`]: meshes the face of `ctx`, adding
/// its stage times to the second argument.
pub(crate) type FaceMesher<'a> =
    dyn Fn(&FaceContext<'_>, &mut StageTimes) -> Result<FaceOutcome, FaceFailure> + Sync + 'a;

/// Meshes every face with `mesher`, refining the curves around faces that
/// ask for it (near their inverted quads first when `local`; else, and as
/// the last resort, their chord classes); returns the final curve meshes and
/// the faces' outcomes.
/// Adds the curve discretization to `times.curves`, the per-face phase to
/// `times.faces` and every attempt's stage times (in face order) to the
/// per-face stages of `times`.
pub(crate) fn mesh_faces(
    model: &Model,
    mut plan: CurvePlan,
    progress: Option<&ProgressFn>,
    mesher: &FaceMesher<'_>,
    local: bool,
    times: &mut StageTimes,
) -> Result<(Vec<CurveMesh>, Vec<Option<FaceOutcome>>), MeshError> {
    let nf = model.faces.len();
    let curve_faces = model.curve_faces();
    let mut results: Vec<Option<FaceOutcome>> = vec![None; nf];
    let mut pending: Vec<usize> = (0..nf).collect();
    let done = AtomicUsize::new(0);
    let mut cms: Vec<CurveMesh>;
    let mut round = 0;
    // quads of each face's latest attempt, and their sum after the first round
    let mut quads_of = vec![0usize; nf];
    let mut first_quads = 0usize;
    let mut local_rounds = vec![0usize; nf];
    let mut class_rounds = 0;
    loop {
        let t = Instant::now();
        cms = discretize_all(model, &plan);
        times.curves += t.elapsed();
        let t = Instant::now();
        crate::curves::curve_mesh::largest_faces_first(model, &cms, &mut pending);
        type Attempt = (usize, Result<FaceOutcome, FaceFailure>, StageTimes);
        let mut out: Vec<Attempt> = crate::core::work_queue::map_in_order(&pending, |&f| {
            let started = Instant::now();
            let ctx = FaceContext::new(model, FaceId(f as u32), &cms);
            let _span = tracing::debug_span!("face", id = f + 1).entered();
            let mut ft = StageTimes::default();
            let r = mesher(&ctx, &mut ft);
            if tracing::enabled!(tracing::Level::DEBUG) {
                tracing::debug!(
                    "face {} meshed in {:.4} s",
                    f + 1,
                    started.elapsed().as_secs_f64()
                );
            }
            if r.is_ok() {
                let d = done.fetch_add(1, Ordering::Relaxed) + 1;
                if let Some(p) = progress {
                    p(d.min(nf), nf);
                }
            }
            (f, r, ft)
        });
        out.sort_by_key(|(f, _, _)| *f);
        times.faces += t.elapsed();
        let mut failed: BTreeMap<usize, (String, Ask)> = BTreeMap::new();
        for (f, r, ft) in out {
            times.add_face(&ft);
            match r {
                Ok(p) => {
                    quads_of[f] = p.patch.quads.len();
                    results[f] = Some(p);
                }
                Err(FaceFailure::Fatal(reason)) => {
                    return Err(MeshError::Face {
                        face: FaceId(f as u32),
                        reason,
                    })
                }
                Err(FaceFailure::RefineCurves(cs, reason)) => {
                    failed.insert(f, (reason, Ask::Classes(cs)));
                }
                Err(FaceFailure::InvertedAt {
                    curves,
                    spots,
                    quads,
                    reason,
                }) => {
                    quads_of[f] = quads;
                    failed.insert(f, (reason, Ask::Local(curves, spots)));
                }
            }
        }
        if tracing::enabled!(tracing::Level::DEBUG) {
            tracing::debug!(
                "round {round}: {} faces meshed, failed {:?}",
                pending.len(),
                failed
            );
        }
        if round == 0 {
            first_quads = quads_of.iter().sum();
        }
        if failed.is_empty() {
            break;
        }
        round += 1;
        let give_up = |f: usize, reason: &str| MeshError::Face {
            face: FaceId(f as u32),
            reason: reason.to_string(),
        };
        // local refinement around the inverted quads of each face that has
        // rounds of it left; the chord classes of the rest doubled
        let mut next = plan.clone();
        let mut refine: BTreeSet<CurveId> = BTreeSet::new();
        let mut changed: BTreeSet<CurveId> = BTreeSet::new();
        for (&f, (_, ask)) in &failed {
            match ask {
                Ask::Local(cs, spots) => {
                    let near = if local && local_rounds[f] < LOCAL_ROUNDS {
                        local_rounds[f] += 1;
                        refine_near_spots(model, f, spots, &cms, &mut next)
                    } else {
                        Vec::new()
                    };
                    if near.is_empty() {
                        refine.extend(cs.iter().copied());
                    }
                    changed.extend(near);
                }
                Ask::Classes(cs) => refine.extend(cs.iter().copied()),
            }
        }
        if !refine.is_empty() {
            class_rounds += 1;
        }
        if class_rounds >= CURVE_ROUNDS || (refine.is_empty() && changed.is_empty()) {
            let (&f, (reason, _)) = failed.iter().next().ok_or(MeshError::NoFaces)?;
            return Err(give_up(f, reason));
        }
        let mut doubled: BTreeSet<CurveId> = BTreeSet::new();
        for &c in &refine {
            if !doubled.contains(&c) {
                doubled.extend(next.refine(c));
            }
        }
        changed.extend(doubled);
        let mut again: BTreeSet<usize> = failed.keys().copied().collect();
        for c in &changed {
            again.extend(curve_faces[c.idx()].iter().map(|f| f.idx()));
        }
        let expected = expected_quads(model, &quads_of, &again, &plan, &next);
        if expected > MAX_GROWTH * first_quads as f64 {
            let (&f, (reason, _)) = failed.iter().next().ok_or(MeshError::NoFaces)?;
            let why = format!(
                "{reason}; finer curves around it would take the model from {first_quads} \
                 to about {expected:.0} quads (more than {MAX_GROWTH} times), so refinement stopped"
            );
            tracing::warn!("face {}: {why}", f + 1);
            return Err(give_up(f, &why));
        }
        tracing::debug!(
            "round {round}: curves {:?} refined, expected quads {expected:.0} (first round {first_quads})",
            changed
        );
        plan = next;
        for &f in &again {
            if results[f].take().is_some() {
                done.fetch_sub(1, Ordering::Relaxed);
            }
        }
        pending = again.into_iter().collect();
    }
    Ok((cms, results))
}

/// What a failed face asks of the next round.
#[derive(Debug)]
enum Ask {
    /// These curves finer, with their chord classes.
    Classes(Vec<CurveId>),
    /// The face's curves finer near these inverted quads; these curves'
    /// chord classes when that does nothing.
    Local(Vec<CurveId>, Vec<FailureSpot>),
}

/// Refines the curves of face `f` in `plan` around its inverted quads
/// `spots` ([`CurvePlan::refine_near`]): at each spot that a coarse segment of
/// the face's current curve meshes `cms` comes within its diameter of, the
/// spacing becomes [`LOCAL_SPACING_FRACTION`] of the nearest such segment's,
/// over the spot's radius, graded away from it. Returns the curves changed.
fn refine_near_spots(
    model: &Model,
    f: usize,
    spots: &[FailureSpot],
    cms: &[CurveMesh],
    plan: &mut CurvePlan,
) -> Vec<CurveId> {
    let curves: BTreeSet<usize> = model.faces[f]
        .curve_uses()
        .map(|u| u.curve.idx())
        .filter(|&c| !model.curves[c].degenerate && c < cms.len())
        .collect();
    let mut near: Vec<(Vec3, f64, f64)> = Vec::new();
    for s in spots {
        // (distance, coarse segment length) of the nearest coarse segment
        let mut best: Option<(f64, f64)> = None;
        for &c in &curves {
            let p = &cms[c].points;
            for k in 0..cms[c].coarse {
                let (Some(&a), Some(&m), Some(&b)) =
                    (p.get(2 * k), p.get(2 * k + 1), p.get(2 * k + 2))
                else {
                    continue;
                };
                let d = vec3::segment_distance(s.at, a, m).min(vec3::segment_distance(s.at, m, b));
                let len = vec3::dist(a, m) + vec3::dist(m, b);
                if d <= s.diameter && best.is_none_or(|(bd, _)| d < bd) {
                    best = Some((d, len));
                }
            }
        }
        if let Some((_, len)) = best {
            if len > 0.0 {
                near.push((s.at, 0.5 * s.diameter, LOCAL_SPACING_FRACTION * len));
            }
        }
    }
    curves
        .into_iter()
        .map(|c| CurveId(c as u32))
        .filter(|&c| plan.refine_near(model, c, &near))
        .collect()
}

/// The model's quads expected after a refinement round from `plan` to
/// `next` (the growth bound of [`mesh_faces`]): `quads_of` per face as they
/// are, but each face of `again` (meshed again) scaled by the square of the
/// ratio of its boundary edge counts, next to now.
fn expected_quads(
    model: &Model,
    quads_of: &[usize],
    again: &BTreeSet<usize>,
    plan: &CurvePlan,
    next: &CurvePlan,
) -> f64 {
    let edges = |p: &CurvePlan, f: usize| -> f64 {
        model.faces[f]
            .curve_uses()
            .map(|u| 2.0 * p.counts[u.curve.idx()] as f64)
            .sum()
    };
    quads_of
        .iter()
        .enumerate()
        .map(|(f, &q)| {
            let q = q as f64;
            if again.contains(&f) && edges(plan, f) > 0.0 {
                q * (edges(next, f) / edges(plan, f)).powi(2)
            } else {
                q
            }
        })
        .sum()
}

/// Builds the global mesh: corners (but the ones in `merged`, which no curve
/// uses any more), then curve nodes by curve, then each face's interior
/// nodes in face order; quads in face order.
pub(crate) fn assemble(
    model: &Model,
    cms: &[CurveMesh],
    results: &[Option<FaceOutcome>],
    merged: &[CornerId],
) -> Result<QuadMesh, MeshError> {
    let mut m = QuadMesh::default();
    let mut corner_node = vec![u32::MAX; model.corners.len()];
    for (i, c) in model.corners.iter().enumerate() {
        if merged.contains(&CornerId(i as u32)) {
            continue;
        }
        corner_node[i] = m.nodes.len() as u32;
        m.corner_nodes
            .push((m.nodes.len() as u32, CornerId(i as u32)));
        m.nodes.push(c.point);
        m.node_class.push(NodeClass::Corner(CornerId(i as u32)));
    }
    let mut offset = vec![0u32; model.curves.len()];
    for (ci, ce) in model.curves.iter().enumerate() {
        if ce.degenerate {
            continue;
        }
        let cm = &cms[ci];
        let n = cm.params.len();
        offset[ci] = m.nodes.len() as u32;
        for i in 1..n - 1 {
            m.nodes.push(cm.points[i]);
            m.node_class
                .push(NodeClass::Curve(CurveId(ci as u32), Some(cm.params[i])));
        }
        let id = |i: usize| {
            if i == 0 {
                corner_node[ce.start.idx()]
            } else if i == n - 1 {
                corner_node[ce.end.idx()]
            } else {
                offset[ci] + i as u32 - 1
            }
        };
        for i in 0..n - 1 {
            m.curve_edges.push(([id(i), id(i + 1)], CurveId(ci as u32)));
        }
    }
    for (fi, r) in results.iter().enumerate() {
        let fid = FaceId(fi as u32);
        let p = &r
            .as_ref()
            .ok_or(MeshError::Face {
                face: fid,
                reason: "no mesh was produced".into(),
            })?
            .patch;
        let mut map = vec![u32::MAX; p.nodes.len()];
        for q in &p.quads {
            let mut g = [0u32; 4];
            for k in 0..4 {
                let l = q[k] as usize;
                if map[l] == u32::MAX {
                    map[l] = match p.nodes[l].node {
                        NodeRef::Corner(c) => corner_node[c.idx()],
                        NodeRef::Curve(c, i) => offset[c.idx()] + i - 1,
                        NodeRef::Interior => {
                            m.nodes.push(p.pos[l]);
                            m.node_class.push(NodeClass::Face(fid, Some(p.nodes[l].uv)));
                            (m.nodes.len() - 1) as u32
                        }
                    };
                }
                g[k] = map[l];
            }
            m.quads.push(g);
            m.quad_face.push(fid);
        }
    }
    Ok(m)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::curves::curve_mesh::plan_curves;
    use geometry::primitives;

    /// A 4 × 4 square at coarse spacing 0.2: 4 × 20 coarse segments, 160
    /// boundary edges. Doubling the bottom side's chord class (bottom and
    /// top) makes 240: a face of 100 quads is expected at 100 × (240 /
    /// 160)² = 225, and at 100 when it is not meshed again.
    #[test]
    fn expected_quads_grow_with_the_square_of_the_boundary() {
        let m = primitives::square(4.0);
        let plan = plan_curves(&m, 0.1);
        let mut next = plan.clone();
        assert_eq!(next.refine(CurveId(0)), vec![CurveId(0), CurveId(2)]);
        let again: BTreeSet<usize> = [0].into_iter().collect();
        let e = expected_quads(&m, &[100], &again, &plan, &next);
        assert!((e - 225.0).abs() < 1e-9, "{e}");
        let e = expected_quads(&m, &[100], &BTreeSet::new(), &plan, &next);
        assert!((e - 100.0).abs() < 1e-9, "{e}");
    }
}
