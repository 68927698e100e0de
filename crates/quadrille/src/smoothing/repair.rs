//! Light Laplacian smoothing of face-interior nodes in (u, v), with rollback:
//! a node moves to the mean (u, v) of its quad neighbours only when the worst
//! quad around it does not get worse (SICN with CAD normals), so smoothing
//! never creates or worsens an invalid quad.
//!
//! [`super::kernels`] holds the paper's 3D kernels (Winslow on regular nodes,
//! angle-based on irregular ones) and their smoothing loop, [`super::optimize`].

use geometry::vec3::{self, Vec3};
use geometry::{CornerId, Face, FaceId, Model};

use crate::core::patch::NodeRef;
use crate::core::patch::QuadPatch;
use crate::core::quality::{node_normal, quad_quality_with, NodeNormal, NodeNormals};
use crate::core::queries::sharp_corners_of;

use super::kernels::{optimize_nodes, OptimizeOptions};

/// Node → incident quads, and node → neighbours along quad edges (sorted, deduplicated).
fn adjacency(p: &QuadPatch) -> (Vec<Vec<u32>>, Vec<Vec<u32>>) {
    let n = p.nodes.len();
    let mut quads_of = vec![Vec::new(); n];
    let mut nbrs = vec![Vec::new(); n];
    for (qi, q) in p.quads.iter().enumerate() {
        for k in 0..4 {
            let a = q[k] as usize;
            quads_of[a].push(qi as u32);
            nbrs[a].push(q[(k + 1) % 4]);
            nbrs[a].push(q[(k + 3) % 4]);
        }
    }
    for l in &mut nbrs {
        l.sort_unstable();
        l.dedup();
    }
    (quads_of, nbrs)
}

/// Smooths (with [`optimize_nodes`], default options) the vertices `changed`
/// and those of the quads around them: the last step of a stage that
/// replaced parts of a face (defects, cavities). The rest of the face was
/// smoothed before and did not move, so it is not swept again. Does nothing
/// when `changed` is empty.
pub fn optimize_around(face: &Face, p: &mut QuadPatch, changed: &[u32]) {
    if changed.is_empty() {
        return;
    }
    let mut near = vec![false; p.nodes.len()];
    for &v in changed {
        if let Some(x) = near.get_mut(v as usize) {
            *x = true;
        }
    }
    let mut nodes: Vec<u32> = Vec::new();
    for q in &p.quads {
        if q.iter()
            .any(|&v| near.get(v as usize).copied().unwrap_or(false))
        {
            nodes.extend_from_slice(q);
        }
    }
    optimize_nodes(face, p, Some(&nodes), &OptimizeOptions::default());
}

/// Runs `sweeps` Gauss–Seidel sweeps (in node order, so deterministic) over the
/// face-interior nodes of `p`. Returns the number of accepted moves.
pub fn smooth(face: &Face, p: &mut QuadPatch, sweeps: usize) -> usize {
    let (quads_of, nbrs) = adjacency(p);
    let mut accepted = 0;
    let mut normals = NodeNormals::new(p.nodes.len());
    let worst = |p: &QuadPatch, normals: &mut NodeNormals, qs: &[u32]| {
        qs.iter()
            .map(|&q| normals.quality(face, &p.nodes, &p.pos, &p.quads[q as usize]))
            .fold(f64::INFINITY, f64::min)
    };
    // a node is smoothed again only while it or a neighbour moved by more
    // than WAKE_SHARE of its mean edge in the previous sweep
    let mut active = vec![true; p.nodes.len()];
    let mut woke = vec![false; p.nodes.len()];
    for _ in 0..sweeps {
        let mut moved = 0;
        for i in 0..p.nodes.len() {
            if !active[i]
                || p.nodes[i].node != NodeRef::Interior
                || quads_of[i].is_empty()
                || nbrs[i].is_empty()
            {
                continue;
            }
            let old = p.nodes[i].uv;
            let mut s = [0.0, 0.0];
            for &j in &nbrs[i] {
                let uv = p.nodes[j as usize].uv_toward(old);
                s[0] += uv[0];
                s[1] += uv[1];
            }
            let k = nbrs[i].len() as f64;
            let new = [s[0] / k, s[1] / k];
            if !(new[0].is_finite() && new[1].is_finite())
                || (new[0] - old[0]).abs() + (new[1] - old[1]).abs() < 1e-14
            {
                continue;
            }
            let before = worst(p, &mut normals, &quads_of[i]);
            let old_pos = p.pos[i];
            let x = face.surface.eval(new);
            if !(x[0].is_finite() && x[1].is_finite() && x[2].is_finite()) {
                continue;
            }
            let old_normal = normals.get(i);
            p.nodes[i].uv = new;
            p.pos[i] = x;
            normals.forget(i);
            let after = worst(p, &mut normals, &quads_of[i]);
            if after >= before {
                moved += 1;
                let edge = nbrs[i]
                    .iter()
                    .map(|&j| vec3::dist(p.pos[j as usize], old_pos))
                    .sum::<f64>()
                    / nbrs[i].len() as f64;
                if vec3::dist(x, old_pos) > WAKE_SHARE * edge {
                    woke[i] = true;
                }
            } else {
                p.nodes[i].uv = old;
                p.pos[i] = old_pos;
                normals.set(i, old_normal);
            }
        }
        accepted += moved;
        if moved == 0 {
            break;
        }
        for i in 0..p.nodes.len() {
            active[i] = woke[i] || nbrs[i].iter().any(|&j| woke[j as usize]);
        }
        woke.iter_mut().for_each(|w| *w = false);
    }
    accepted
}

/// Share of a node's mean edge length above which its move in [`smooth`]
/// keeps it and its neighbours in the next sweep.
const WAKE_SHARE: f64 = 0.01;

/// SICN below which the quads of a finished face get one more untangling
/// pass ([`lift_poor_quads`]): the minimum-quality bar of the method.
pub const POOR_SICN: f64 = 0.1;

/// A quad touching a sharp CAD corner (`sharp`, below
/// `mesh::stats::SHARP_CORNER_DEG` in this face) counts in [`untangle`] and
/// [`lift_poor_quads`] as this many times its SICN. Its corner angle is the
/// CAD's, so it is poor whatever is done; counted at face value it pins the
/// node opposite the corner, and the quads beyond it stay slivers (i11o_s1:
/// the centre of the split tip triangle of a 0.04° cusp sat a third of the
/// way along the wedge, the next quad had SICN 0.047). Weighted, it still
/// keeps that quad from folding.
pub const SHARP_CORNER_WEIGHT: f64 = 10.0;

/// Per quad, the factor its SICN is weighted by in [`untangle`]:
/// [`SHARP_CORNER_WEIGHT`] when it touches one of the corners `sharp`, else 1.
pub fn sharp_corner_weights(p: &QuadPatch, sharp: &[CornerId]) -> Vec<f64> {
    p.quads
        .iter()
        .map(|q| {
            let at_sharp = q.iter().any(
                |&v| matches!(p.nodes[v as usize].node, NodeRef::Corner(c) if sharp.contains(&c)),
            );
            if at_sharp {
                SHARP_CORNER_WEIGHT
            } else {
                1.0
            }
        })
        .collect()
}

/// A last [`untangle`] pass on a finished face whose worst quad (weighted
/// as [`sharp_corner_weights`] says) is below `threshold`: the nodes of those
/// quads and their neighbours move to raise the worst SICN around them. The
/// face keeps the result only when its worst quad rose at least half way to
/// `threshold`; otherwise every node goes back, so a face whose worst quads
/// cannot be lifted (slivers along a thin rounded edge) keeps the smoother's
/// positions and average quality (moves around such slivers trade the
/// average for a worst that barely changes). Returns whether the face changed.
pub fn lift_poor_quads(face: &Face, p: &mut QuadPatch, threshold: f64, sharp: &[CornerId]) -> bool {
    let weights = sharp_corner_weights(p, sharp);
    let worst = |p: &QuadPatch| {
        let mut normals = NodeNormals::new(p.nodes.len());
        p.quads
            .iter()
            .zip(&weights)
            .map(|(q, w)| w * normals.quality(face, &p.nodes, &p.pos, q))
            .fold(f64::INFINITY, f64::min)
    };
    let before = worst(p);
    if before >= threshold || p.quads.is_empty() {
        return false;
    }
    let saved: Vec<([f64; 2], Vec3)> = p
        .nodes
        .iter()
        .zip(&p.pos)
        .map(|(n, &x)| (n.uv, x))
        .collect();
    untangle(face, p, threshold, 4, 5000, sharp);
    if worst(p) >= before + 0.5 * (threshold - before) {
        return true;
    }
    for ((n, x), &(uv, y)) in p.nodes.iter_mut().zip(p.pos.iter_mut()).zip(&saved) {
        n.uv = uv;
        *x = y;
    }
    false
}

/// SICN below which [`smooth_then_untangle`] untangles a quad's nodes.
pub const UNTANGLE_BELOW: f64 = 0.1;
/// Passes of that untangling.
pub const UNTANGLE_PASSES: usize = 4;
/// A face with more nodes to untangle than this is beyond local repair.
pub const UNTANGLE_MAX_NODES: usize = 5000;
/// [`untangle_budget`]'s allowance per node of the patch (star evaluations).
pub const UNTANGLE_EVALUATIONS_PER_NODE: u64 = 100;
/// [`untangle_budget`]'s allowance whatever the patch's size.
pub const UNTANGLE_EVALUATIONS_FIXED: u64 = 2_000;

/// The first smoothing of a face mesher's fresh patch `p` of face `fid`:
/// `sweeps` sweeps of [`smooth`], then [`untangle`] of the quads below
/// [`UNTANGLE_BELOW`], the model's sharp corners weighted.
pub fn smooth_then_untangle(model: &Model, fid: FaceId, p: &mut QuadPatch, sweeps: usize) {
    let face = &model.faces[fid.idx()];
    smooth(face, p, sweeps);
    untangle(
        face,
        p,
        UNTANGLE_BELOW,
        UNTANGLE_PASSES,
        UNTANGLE_MAX_NODES,
        &sharp_corners_of(model, fid),
    );
}

/// Moves face-interior nodes of quads whose SICN is below `threshold` (and
/// their interior neighbours) by a compass search in (u, v) that maximizes the
/// worst SICN of the quads around each node: it untangles inverted quads that
/// Laplacian smoothing cannot fix (thin wedges at cusps, curved boundaries).
/// A move is kept only when it raises that worst value. Quads at the corners
/// `sharp` count as [`SHARP_CORNER_WEIGHT`] times their SICN. Returns the
/// number of improved nodes. Gives up when more than `max_nodes` nodes would
/// move, and stops when it has spent [`untangle_budget`] evaluations of a
/// node's star (a count, not seconds, so the result does not depend on the
/// machine's load).
pub fn untangle(
    face: &Face,
    p: &mut QuadPatch,
    threshold: f64,
    passes: usize,
    max_nodes: usize,
    sharp: &[CornerId],
) -> usize {
    untangle_counted(face, p, threshold, passes, max_nodes, sharp).improved
}

/// Star evaluations [`untangle`] may spend on a patch of `nodes` nodes.
pub fn untangle_budget(nodes: usize) -> u64 {
    UNTANGLE_EVALUATIONS_FIXED + UNTANGLE_EVALUATIONS_PER_NODE * nodes as u64
}

/// What one [`untangle_counted`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Untangled {
    /// Nodes whose star's worst value rose.
    pub improved: usize,
    /// Star evaluations spent (each a quality evaluation of the quads
    /// around one node): the work callers charge to their own budgets.
    pub evaluations: u64,
    /// The evaluation budget ran out before the search ended.
    pub exhausted: bool,
}

/// The CAD normal of node `j` of `p` where it depends on the node's (u, v)
/// alone: a face-interior node off any pole at an ordinary point, whose
/// corner normal ([`geometry::Face::corner_normal`]) is the same in every
/// quad around it. Kept in `normals` until the node moves (the caller
/// forgets it then); `None` for every other node (evaluate per quad).
fn interior_normal(
    face: &Face,
    p: &QuadPatch,
    normals: &mut NodeNormals,
    j: usize,
) -> Option<Vec3> {
    let n = &p.nodes[j];
    if n.pole.is_some() || n.node != NodeRef::Interior {
        return None;
    }
    match normals.get(j) {
        NodeNormal::Regular(v) => Some(v),
        NodeNormal::PerQuad => None,
        NodeNormal::Unknown => {
            let v = face.regular_normal(n.uv);
            normals.set(j, v.map_or(NodeNormal::PerQuad, NodeNormal::Regular));
            v
        }
    }
}

/// [`untangle`], also returning the work it spent.
pub fn untangle_counted(
    face: &Face,
    p: &mut QuadPatch,
    threshold: f64,
    passes: usize,
    max_nodes: usize,
    sharp: &[CornerId],
) -> Untangled {
    let budget = untangle_budget(p.nodes.len());
    let mut evaluations = 0u64;
    let (quads_of, nbrs) = adjacency(p);
    let weights = sharp_corner_weights(p, sharp);
    // CAD normals of the face-interior nodes, kept while they do not move
    // (bit-identical to evaluating them at every corner: see `interior_normal`)
    let mut normals = NodeNormals::new(p.nodes.len());
    // the eight search directions, (cos, sin) of k·45°, computed once (the
    // sines and cosines were a tenth of the untangler's time)
    let directions: [(f64, f64); 8] = std::array::from_fn(|k| {
        let a = k as f64 * std::f64::consts::FRAC_PI_4;
        (a.cos(), a.sin())
    });
    let quality = |p: &QuadPatch, normals: &mut NodeNormals, q: u32| {
        let quad = &p.quads[q as usize];
        let mut known = [None; 4];
        for (k, slot) in known.iter_mut().enumerate() {
            *slot = interior_normal(face, p, normals, quad[k] as usize);
        }
        weights[q as usize] * quad_quality_with(face, &p.nodes, &p.pos, quad, &known)
    };
    let mut improved = 0;
    for _ in 0..passes {
        // nodes to move: interior nodes of poor quads and their interior neighbours
        let mut set = std::collections::BTreeSet::new();
        for (qi, q) in p.quads.iter().enumerate() {
            if quality(p, &mut normals, qi as u32) < threshold {
                for &i in q {
                    if p.nodes[i as usize].node == NodeRef::Interior {
                        set.insert(i as usize);
                    }
                    for &j in &nbrs[i as usize] {
                        if p.nodes[j as usize].node == NodeRef::Interior {
                            set.insert(j as usize);
                        }
                    }
                }
            }
        }
        if set.is_empty() || set.len() > max_nodes {
            break;
        }
        let mut any = false;
        for i in set {
            // normals of the corners that do not move (poles and singular
            // points excepted: their limit normal follows the quad centre)
            let known: Vec<[Option<Vec3>; 4]> = quads_of[i]
                .iter()
                .map(|&q| {
                    let quad = &p.quads[q as usize];
                    let mut k = [None; 4];
                    for c in 0..4 {
                        let j = quad[c] as usize;
                        if j != i {
                            k[c] = interior_normal(face, p, &mut normals, j);
                            if k[c].is_none()
                                && p.nodes[j].pole.is_none()
                                && !face.is_singular(p.nodes[j].uv)
                            {
                                k[c] = node_normal(face, &p.nodes, quad, c);
                            }
                        }
                    }
                    k
                })
                .collect();
            // the moving node's normal at a trial (u, v), evaluated once for
            // all its quads where it depends on (u, v) alone (no pole)
            let moving_normal = |p: &QuadPatch| -> Option<Vec3> {
                if p.nodes[i].pole.is_some() {
                    None
                } else {
                    face.regular_normal(p.nodes[i].uv)
                }
            };
            let star_worst = |p: &QuadPatch| {
                let ni = moving_normal(p);
                quads_of[i]
                    .iter()
                    .zip(&known)
                    .map(|(&q, k)| {
                        let quad = &p.quads[q as usize];
                        let mut k = *k;
                        if ni.is_some() {
                            for c in 0..4 {
                                if quad[c] as usize == i {
                                    k[c] = ni;
                                }
                            }
                        }
                        weights[q as usize] * quad_quality_with(face, &p.nodes, &p.pos, quad, &k)
                    })
                    .fold(f64::INFINITY, f64::min)
            };
            if evaluations >= budget {
                return Untangled { improved, evaluations, exhausted: true };
            }
            let mut w = star_worst(p);
            evaluations += 1;
            let mut cur = p.nodes[i].uv;
            let mut step = f64::INFINITY;
            for &j in &nbrs[i] {
                let o = p.nodes[j as usize].uv_toward(cur);
                step = step.min((o[0] - cur[0]).hypot(o[1] - cur[1]));
            }
            if !(step.is_finite() && step > 0.0) {
                continue;
            }
            step *= 0.25;
            let stop = step * 1e-4;
            let start_w = w;
            let mut iters = 0;
            while step > stop && iters < 40 && evaluations < budget {
                iters += 1;
                let mut best: Option<([f64; 2], f64, [f64; 3])> = None;
                for &(cos, sin) in &directions {
                    let uv = [cur[0] + step * cos, cur[1] + step * sin];
                    let x = face.surface.eval(uv);
                    if !(x[0].is_finite() && x[1].is_finite() && x[2].is_finite()) {
                        continue;
                    }
                    let (old_uv, old_x) = (p.nodes[i].uv, p.pos[i]);
                    p.nodes[i].uv = uv;
                    p.pos[i] = x;
                    let v = star_worst(p);
                    evaluations += 1;
                    p.nodes[i].uv = old_uv;
                    p.pos[i] = old_x;
                    if v > w && best.is_none_or(|b| v > b.1) {
                        best = Some((uv, v, x));
                    }
                }
                match best {
                    Some((uv, v, x)) => {
                        cur = uv;
                        w = v;
                        p.nodes[i].uv = uv;
                        p.pos[i] = x;
                        normals.forget(i);
                    }
                    None => step *= 0.5,
                }
            }
            if w > start_w {
                improved += 1;
                any = true;
            }
        }
        if !any {
            break;
        }
    }
    Untangled { improved, evaluations, exhausted: evaluations >= budget }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::quality::quad_quality;
    use crate::curves::curve_mesh::{discretize_all, plan_curves};
    use crate::triangulate::face_triangulation::FaceTriangulation;
    use crate::triangulate::split::split_triangles;
    use geometry::{primitives, FaceId};

    /// The side face of `m` (a cylinder) triangulated at 0.3 and split into quads.
    fn cylinder_side_patch(m: &Model) -> QuadPatch {
        let plan = plan_curves(m, 0.15);
        let cms = discretize_all(m, &plan);
        let mut ft = FaceTriangulation::new(m, FaceId(0), &cms, 0.3).unwrap();
        ft.refine().unwrap();
        let tris = ft.triangles();
        split_triangles(&m.faces[0], &ft.nodes, &ft.pos, &tris, &ft.boundary_mid)
    }

    #[test]
    fn kept_interior_normals_equal_the_per_quad_corner_normals() {
        // the untangler keeps a face-interior node's normal for all its
        // quads: it must be the corner normal each quad would evaluate
        let m = primitives::cylinder(1.0, 2.0);
        let face = &m.faces[0];
        let p = cylinder_side_patch(&m);
        let mut normals = NodeNormals::new(p.nodes.len());
        let (mut kept, mut per_quad) = (0, 0);
        for q in &p.quads {
            for k in 0..4 {
                let j = q[k] as usize;
                match interior_normal(face, &p, &mut normals, j) {
                    Some(n) => {
                        assert_eq!(Some(n), node_normal(face, &p.nodes, q, k), "node {j}");
                        kept += 1;
                    }
                    None => {
                        assert_ne!(p.nodes[j].node, NodeRef::Interior, "node {j}");
                        per_quad += 1;
                    }
                }
            }
        }
        assert!(kept > 100 && per_quad > 10, "{kept} {per_quad}");
    }

    /// The worst SICN (CAD normals) of `p`'s quads on `face`.
    fn worst_quality(face: &Face, p: &QuadPatch) -> f64 {
        p.quads
            .iter()
            .map(|q| quad_quality(face, &p.nodes, &p.pos, q))
            .fold(f64::INFINITY, f64::min)
    }

    #[test]
    fn smoothing_never_worsens_the_worst_quad() {
        let m = primitives::cylinder(1.0, 2.0);
        let face = &m.faces[0];
        let mut p = cylinder_side_patch(&m);
        let q = |p: &QuadPatch| worst_quality(face, p);
        let before = q(&p);
        let moves = smooth(face, &mut p, 3);
        assert!(moves > 0);
        assert!(q(&p) >= before);
    }

    #[test]
    fn untangling_stays_within_its_evaluation_budget() {
        let m = primitives::cylinder(1.0, 2.0);
        let face = &m.faces[0];
        let mut p = cylinder_side_patch(&m);
        smooth(face, &mut p, 3);
        // every face-interior node pulled half way towards the first one:
        // many quads fold, far more work than the budget allows
        let interior: Vec<usize> = (0..p.nodes.len())
            .filter(|&i| p.nodes[i].node == NodeRef::Interior)
            .collect();
        let c = p.nodes[interior[0]].uv;
        for &i in &interior {
            let uv = p.nodes[i].uv;
            let moved = [0.5 * (uv[0] + c[0]), 0.5 * (uv[1] + c[1])];
            p.nodes[i].uv = moved;
            p.pos[i] = face.surface.eval(moved);
        }
        let worst = |p: &QuadPatch| worst_quality(face, p);
        let before = worst(&p);
        assert!(before < 0.0, "the test needs folded quads: {before}");
        let budget = untangle_budget(p.nodes.len());
        let r = untangle_counted(face, &mut p, 0.5, 50, 100_000, &[]);
        // the count may pass the budget by at most one node's compass step (8)
        assert!(r.evaluations <= budget + 8, "{} > {budget}", r.evaluations);
        assert!(r.exhausted, "50 passes on a folded face should exhaust the budget");
        assert!(r.improved > 0);
        // a move is kept only when it raises its star's worst value
        assert!(worst(&p) >= before);
    }
}
