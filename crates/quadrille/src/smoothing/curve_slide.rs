//! The last pass of the default and unstructured methods, after assembly:
//! nodes on CAD curves slide along their curve to raise the SICN of the
//! quads around them, on every face that uses the curve.
//!
//! Each face's own smoothing ([`crate::smoothing::raise_average`]) moves only
//! face-interior nodes: a curve's nodes are laid before the faces are meshed
//! and shared by them. Where a face's interior grid wants the curve's nodes
//! elsewhere (the seam of a sphere laid as a cube, the fillets of a rounded
//! cube) only a pass over the assembled mesh can move them, because a curve
//! node's quads lie on several faces (or, on a seam, on both sides of one).
//!
//! A curve node moves in its curve parameter `t`, strictly between its two
//! neighbours on the curve; the face nodes within [`FACE_RINGS`] rings of the
//! curve nodes move with them, by compass steps in their tangent plane mapped
//! back onto the surface, on the faces whose quads along their curves average
//! below [`ASCENT_DONE`] (so at fine sizes, where most faces are about square,
//! the pass stays cheap). Every step must raise the sum of the node's quads'
//! SICN (measured as the statistics measure it: CAD normals at the corners,
//! [`mesh::stats::quad_corner_normals`]) and keep each quad above the floor
//! of [`crate::smoothing::raise_average`] (a quad below 0.5 never gets worse,
//! a better one keeps 95 % of its SICN). Corners, poles (degenerate curves)
//! and nodes whose quads are all about square stay where they are. Each
//! sweep moves the curve nodes first, colour by colour (a greedy colouring
//! in node order: nodes of one colour share no quad, so they move side by
//! side), then the face nodes face by face in parallel (faces share no
//! quad): the result is the same on any number of threads. The face
//! nodes gain what the curve nodes' moves made room for: on the 25 shared
//! models (wing out) the average SICN rises by up to 0.005 more than with
//! the curve nodes alone (i04o_m4 0.8965 → 0.9016).

use std::collections::{BTreeMap, HashMap};

use geometry::{vec3, FaceId, Model, Vec3};
use mesh::quadmesh::{NodeClass, QuadMesh};
use mesh::quality::quad_sicn_both_judges;

use crate::smoothing::kernels::{ascent_floor, ASCENT_DONE, ASCENT_GOOD, COMPASS};

/// First step, as a share of the node's parameter interval (between its two
/// curve neighbours).
pub const SLIDE_STEP: f64 = 0.05;
/// A node stops when its step falls below this share of its interval.
pub const SLIDE_MIN_STEP: f64 = 0.0005;
/// A node keeps at least this share of its interval to each curve neighbour.
pub const SLIDE_MARGIN: f64 = 0.1;
/// Rings of face nodes around the curve nodes that move with them.
pub const FACE_RINGS: usize = 2;

/// What [`slide_curve_nodes`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SlideReport {
    /// Curve nodes that could move (not corners, poles, or nodes without quads).
    pub nodes: usize,
    /// Steps kept.
    pub moves: usize,
    /// Sweeps made over the nodes.
    pub sweeps: usize,
    /// Average SICN of the quads around those nodes before the pass.
    pub before: f64,
    /// The same after the pass (never lower).
    pub after: f64,
}

/// A node the pass may move: a curve node (between the parameters of its
/// two curve neighbours, `lo < t < hi`) or a face node next to one.
#[derive(Clone, Copy, Debug)]
enum Mover {
    Curve { node: u32, lo: f64, hi: f64 },
    Face { node: u32 },
}

impl Mover {
    fn node(&self) -> u32 {
        match *self {
            Mover::Curve { node, .. } | Mover::Face { node } => node,
        }
    }
}

/// Slides the nodes of `mesh` that lie on CAD curves along their curves, and
/// moves the face nodes next to them in their tangent planes, at most
/// `max_sweeps` Gauss–Seidel sweeps, see the module documentation.
/// Positions and parameters of `mesh` change; its topology does not.
/// Parallel by colours and faces; the result does not depend on the number of threads.
pub fn slide_curve_nodes(model: &Model, mesh: &mut QuadMesh, max_sweeps: usize) -> SlideReport {
    let mut report = SlideReport::default();
    let mut movers: Vec<Mover> = sliders(model, mesh)
        .into_iter()
        .map(|s| Mover::Curve {
            node: s.node,
            lo: s.lo,
            hi: s.hi,
        })
        .collect();
    if movers.is_empty() || max_sweeps == 0 {
        return report;
    }
    let mut quads_of: Vec<Vec<u32>> = vec![Vec::new(); mesh.nodes.len()];
    for (qi, q) in mesh.quads.iter().enumerate() {
        for &v in q {
            if let Some(l) = quads_of.get_mut(v as usize) {
                l.push(qi as u32);
            }
        }
    }
    movers.retain(|m| !quads_of[m.node() as usize].is_empty());
    // corner normals and SICN of the quads around the movers (indexed by
    // quad; NaN elsewhere), added as movers are
    let mut normals: Vec<[Vec3; 4]> = vec![[[0.0; 3]; 4]; mesh.quads.len()];
    let mut sicn: Vec<f64> = vec![f64::NAN; mesh.quads.len()];
    let mut around: Vec<u32> = Vec::new();
    measure(
        model,
        mesh,
        &quads_of,
        &movers,
        &mut normals,
        &mut sicn,
        &mut around,
    );
    // the face nodes within FACE_RINGS rings of the curve nodes, on faces
    // whose quads along their curves are not about square already
    let mut face_sum: HashMap<FaceId, (f64, usize)> = HashMap::new();
    for &q in &around {
        let e = face_sum.entry(mesh.quad_face[q as usize]).or_default();
        e.0 += sicn[q as usize];
        e.1 += 1;
    }
    let rough = |f: FaceId| {
        face_sum
            .get(&f)
            .is_some_and(|&(s, n)| s / (n as f64) < ASCENT_DONE)
    };
    let mut seen = vec![false; mesh.nodes.len()];
    let mut frontier: Vec<u32> = movers.iter().map(|m| m.node()).collect();
    let first_face_mover = movers.len();
    for _ in 0..FACE_RINGS {
        let mut next = Vec::new();
        for v in frontier {
            for &q in &quads_of[v as usize] {
                for &w in &mesh.quads[q as usize] {
                    if let NodeClass::Face(f, Some(_)) = mesh.node_class[w as usize] {
                        if !seen[w as usize] && rough(f) {
                            seen[w as usize] = true;
                            movers.push(Mover::Face { node: w });
                            next.push(w);
                        }
                    }
                }
            }
        }
        frontier = next;
    }
    measure(
        model,
        mesh,
        &quads_of,
        &movers[first_face_mover..],
        &mut normals,
        &mut sicn,
        &mut around,
    );
    report.nodes = movers.len();
    let initial = sicn.clone();
    let average =
        |sicn: &[f64]| around.iter().map(|&q| sicn[q as usize]).sum::<f64>() / around.len() as f64;
    report.before = average(&sicn);
    let curve_count = first_face_mover;
    let mut step = vec![SLIDE_STEP; movers.len()];
    let fixed = Fixed {
        model,
        quads: &mesh.quads,
        quad_face: &mesh.quad_face,
        quads_of: &quads_of,
        initial: &initial,
    };
    // the phases of a sweep, each a list of groups of movers that share no
    // quad with another group, so the groups move side by side and the
    // result is the same on any number of threads: first the curve nodes by
    // colour (nodes of one colour share no quad), in chunks
    let mut phases = colour_movers(&movers[..curve_count], &quads_of, mesh.quads.len());
    // the face nodes by face, largest face first: faces share no quad, so
    // they move side by side once the curve nodes have moved
    let mut by_face: BTreeMap<FaceId, Vec<usize>> = BTreeMap::new();
    for (k, m) in movers.iter().enumerate().skip(curve_count) {
        if let NodeClass::Face(f, _) = mesh.node_class[m.node() as usize] {
            by_face.entry(f).or_default().push(k);
        }
    }
    let mut faces: Vec<Vec<usize>> = by_face.into_values().collect();
    faces.sort_by_key(|g| std::cmp::Reverse(g.len()));
    phases.push(faces);
    for _ in 0..max_sweeps {
        report.sweeps += 1;
        let mut active = false;
        for groups in &phases {
            let (a, moves) = sweep_groups(
                &fixed,
                &movers,
                groups,
                &mut step,
                &mut mesh.nodes,
                &mut mesh.node_class,
                &mut normals,
                &mut sicn,
            );
            active |= a;
            report.moves += moves;
        }
        if !active {
            break;
        }
    }
    report.after = average(&sicn);
    report
}

/// Movers per task of a colour in [`colour_movers`].
const COLOUR_CHUNK: usize = 32;

/// The indices of `movers` split into colours, each in chunks of
/// [`COLOUR_CHUNK`]: a mover takes the first colour that no earlier mover
/// sharing a quad with it has. Movers of one colour share no quad, so no
/// step of one reads what another writes.
fn colour_movers(
    movers: &[Mover],
    quads_of: &[Vec<u32>],
    quad_count: usize,
) -> Vec<Vec<Vec<usize>>> {
    // the colours already taken around each quad, as bits
    let mut taken: Vec<u64> = vec![0; quad_count];
    let mut colours: Vec<Vec<usize>> = Vec::new();
    for (k, m) in movers.iter().enumerate() {
        let quads = &quads_of[m.node() as usize];
        let used = quads.iter().fold(0u64, |a, &q| a | taken[q as usize]);
        // 64 colours at most: a node with neighbours of all 64 takes the
        // last (still the same result on any number of threads: each group
        // reads the state as it was before its phase)
        let c = (used.trailing_ones() as usize).min(63);
        for &q in quads {
            taken[q as usize] |= 1 << c;
        }
        if colours.len() <= c {
            colours.resize(c + 1, Vec::new());
        }
        colours[c].push(k);
    }
    colours
        .into_iter()
        .map(|c| c.chunks(COLOUR_CHUNK).map(<[usize]>::to_vec).collect())
        .collect()
}

/// One sweep over `groups` of movers, side by side: each group moves its
/// movers in order on its own overlay of the state, then the overlays are
/// applied in group order. Groups must share no quad (the chunks of one
/// curve colour; the faces' groups). Returns whether a mover was active and
/// how many moved.
// the four state arrays are borrowed apart: `fixed` holds the mesh's quads
#[allow(clippy::too_many_arguments)]
fn sweep_groups(
    fixed: &Fixed<'_>,
    movers: &[Mover],
    groups: &[Vec<usize>],
    step: &mut [f64],
    nodes: &mut [Vec3],
    classes: &mut [NodeClass],
    normals: &mut [[Vec3; 4]],
    sicn: &mut [f64],
) -> (bool, usize) {
    let results: Vec<GroupSweep> = {
        let base = Base {
            nodes,
            classes,
            normals,
            sicn,
        };
        let step = &*step;
        crate::core::work_queue::map_in_order(groups, |g| {
            let mut state = OverlayState {
                base: &base,
                over: Overlay::default(),
            };
            let (mut active, mut moves) = (false, 0);
            let mut steps = Vec::with_capacity(g.len());
            for &k in g {
                let mut st = step[k];
                let (a, moved) = fixed.step(&movers[k], &mut st, &mut state);
                active |= a;
                moves += usize::from(moved);
                steps.push((k, st));
            }
            GroupSweep {
                over: state.over,
                steps,
                active,
                moves,
            }
        })
    };
    let (mut active, mut moved) = (false, 0);
    for GroupSweep {
        over,
        steps,
        active: a,
        moves,
    } in results
    {
        for (v, x) in over.pos {
            nodes[v as usize] = x;
        }
        for (v, c) in over.class {
            classes[v as usize] = c;
        }
        for (q, n) in over.normals {
            normals[q as usize] = n;
        }
        for (q, val) in over.sicn {
            sicn[q as usize] = val;
        }
        for (k, st) in steps {
            step[k] = st;
        }
        active |= a;
        moved += moves;
    }
    (active, moved)
}

/// What the moves read and write: node positions and classes, and the
/// corner normals and SICN of the quads around the movers.
trait SlideState {
    fn pos(&self, v: u32) -> Vec3;
    fn class(&self, v: u32) -> NodeClass;
    fn normals(&self, q: u32) -> [Vec3; 4];
    fn sicn(&self, q: u32) -> f64;
    fn set(&mut self, v: u32, x: Vec3, class: NodeClass);
    fn set_quad(&mut self, q: u32, normals: [Vec3; 4], sicn: f64);
}

/// The state read-only, shared by the groups of a parallel phase.
struct Base<'a> {
    nodes: &'a [Vec3],
    classes: &'a [NodeClass],
    normals: &'a [[Vec3; 4]],
    sicn: &'a [f64],
}

/// One group's changes in a sweep, applied after the parallel phase.
#[derive(Default)]
struct Overlay {
    pos: IdMap<Vec3>,
    class: IdMap<NodeClass>,
    normals: IdMap<[Vec3; 4]>,
    sicn: IdMap<f64>,
}

/// A map keyed by node or quad number: the overlays are read at every step.
type IdMap<V> = crate::core::fast_hash::FastMap<u32, V>;

/// What one group's sweep of the parallel phase gives back.
struct GroupSweep {
    over: Overlay,
    /// The new step size of each of its movers.
    steps: Vec<(usize, f64)>,
    active: bool,
    moves: usize,
}

/// A group's view: its own changes over the shared state.
struct OverlayState<'a> {
    base: &'a Base<'a>,
    over: Overlay,
}

impl SlideState for OverlayState<'_> {
    fn pos(&self, v: u32) -> Vec3 {
        self.over
            .pos
            .get(&v)
            .copied()
            .unwrap_or(self.base.nodes[v as usize])
    }
    fn class(&self, v: u32) -> NodeClass {
        self.over
            .class
            .get(&v)
            .copied()
            .unwrap_or(self.base.classes[v as usize])
    }
    fn normals(&self, q: u32) -> [Vec3; 4] {
        self.over
            .normals
            .get(&q)
            .copied()
            .unwrap_or(self.base.normals[q as usize])
    }
    fn sicn(&self, q: u32) -> f64 {
        self.over
            .sicn
            .get(&q)
            .copied()
            .unwrap_or(self.base.sicn[q as usize])
    }
    fn set(&mut self, v: u32, x: Vec3, class: NodeClass) {
        self.over.pos.insert(v, x);
        self.over.class.insert(v, class);
    }
    fn set_quad(&mut self, q: u32, normals: [Vec3; 4], sicn: f64) {
        self.over.normals.insert(q, normals);
        self.over.sicn.insert(q, sicn);
    }
}

/// What does not change during the pass.
struct Fixed<'a> {
    model: &'a Model,
    quads: &'a [[u32; 4]],
    quad_face: &'a [FaceId],
    quads_of: &'a [Vec<u32>],
    /// The quads' SICN before the pass (their floors).
    initial: &'a [f64],
}

impl Fixed<'_> {
    /// One step of mover `m` with step size `step` (a share of its curve
    /// interval or of its shortest edge), grown after a kept move and shrunk
    /// after a refused one. Returns whether the mover was active and whether
    /// it moved.
    fn step<S: SlideState>(&self, m: &Mover, step: &mut f64, state: &mut S) -> (bool, bool) {
        if *step < SLIDE_MIN_STEP {
            return (false, false);
        }
        let v = m.node();
        let quads = &self.quads_of[v as usize];
        if quads.iter().all(|&q| state.sicn(q) >= ASCENT_GOOD) {
            return (false, false);
        }
        let sum_before: f64 = quads.iter().map(|&q| state.sicn(q)).sum();
        let old_pos = state.pos(v);
        let corner_of = |q: u32| self.quads[q as usize].iter().position(|&w| w == v);
        // the first candidate that raises the sum and keeps every floor is kept
        let accept = |x: Vec3, class: NodeClass, cn: &[(u32, usize, Vec3)], state: &mut S| {
            let mut new_q: Vec<([Vec3; 4], f64)> = Vec::with_capacity(cn.len());
            for &(q, at, n) in cn {
                let mut nq = state.normals(q);
                nq[at] = n;
                let p = self.quads[q as usize].map(|w| if w == v { x } else { state.pos(w) });
                new_q.push((nq, quad_sicn_both_judges(&p, &nq)));
            }
            let sum: f64 = new_q.iter().map(|(_, s)| s).sum();
            let floor_ok = cn
                .iter()
                .zip(&new_q)
                .all(|(&(q, _, _), &(_, val))| val >= ascent_floor(self.initial[q as usize]));
            if sum > sum_before + 1e-12 && floor_ok {
                state.set(v, x, class);
                for (&(q, _, _), &(nq, val)) in cn.iter().zip(&new_q) {
                    state.set_quad(q, nq, val);
                }
                true
            } else {
                false
            }
        };
        match *m {
            Mover::Curve { lo, hi, .. } => {
                let NodeClass::Curve(c, Some(t0)) = state.class(v) else {
                    return (true, false);
                };
                let Some(geom) = self.model.curves[c.idx()].geom.as_ref() else {
                    return (true, false);
                };
                let width = hi - lo;
                for dir in [1.0, -1.0] {
                    let t = t0 + dir * *step * width;
                    if !(t > lo + SLIDE_MARGIN * width && t < hi - SLIDE_MARGIN * width) {
                        continue;
                    }
                    let mut cn = Vec::with_capacity(quads.len());
                    let ok = quads.iter().all(|&q| {
                        let face = &self.model.faces[self.quad_face[q as usize].idx()];
                        let n = face
                            .curve_uses()
                            .find(|u| u.curve == c)
                            .and_then(|u| face.regular_normal(u.pcurve.eval(t)));
                        match (n, corner_of(q)) {
                            (Some(n), Some(at)) => {
                                cn.push((q, at, n));
                                true
                            }
                            _ => false,
                        }
                    });
                    if ok && accept(geom.eval(t), NodeClass::Curve(c, Some(t)), &cn, state) {
                        *step *= 1.5;
                        return (true, true);
                    }
                }
            }
            Mover::Face { .. } => {
                let NodeClass::Face(f, Some(uv)) = state.class(v) else {
                    return (true, false);
                };
                let face = &self.model.faces[f.idx()];
                let edge = quads
                    .iter()
                    .filter_map(|&q| corner_of(q).map(|at| (q, at)))
                    .map(|(q, at)| {
                        vec3::dist(old_pos, state.pos(self.quads[q as usize][(at + 1) % 4]))
                    })
                    .fold(f64::INFINITY, f64::min);
                if !(edge > 0.0 && edge.is_finite()) {
                    return (true, false);
                }
                let dd = face.surface.first_derivs(uv);
                let (Some(n0), Some(t1)) = (face.regular_normal_from(&dd), vec3::normalize(dd.du))
                else {
                    return (true, false);
                };
                let t2 = vec3::cross(n0, t1);
                for (a, b) in COMPASS {
                    let target = vec3::add(
                        old_pos,
                        vec3::scale(
                            vec3::add(vec3::scale(t1, a), vec3::scale(t2, b)),
                            *step * edge,
                        ),
                    );
                    let Some((uv2, x, n)) =
                        crate::smoothing::kernels::map_to_surface(face, uv, target, 1e-9 * edge)
                    else {
                        continue;
                    };
                    let cn: Vec<(u32, usize, Vec3)> = quads
                        .iter()
                        .filter_map(|&q| corner_of(q).map(|at| (q, at, n)))
                        .collect();
                    if cn.len() == quads.len()
                        && accept(x, NodeClass::Face(f, Some(uv2)), &cn, state)
                    {
                        *step *= 1.5;
                        return (true, true);
                    }
                }
            }
        }
        *step *= 0.25;
        (true, false)
    }
}

/// Computes the corner normals and SICN of the quads around `movers` not
/// measured yet (NaN in `sicn`), and adds them to `around` (kept sorted).
fn measure(
    model: &Model,
    mesh: &QuadMesh,
    quads_of: &[Vec<u32>],
    movers: &[Mover],
    normals: &mut [[Vec3; 4]],
    sicn: &mut [f64],
    around: &mut Vec<u32>,
) {
    let mut fresh: Vec<u32> = movers
        .iter()
        .flat_map(|m| quads_of[m.node() as usize].iter().copied())
        .filter(|&q| sicn[q as usize].is_nan())
        .collect();
    fresh.sort_unstable();
    fresh.dedup();
    for (&q, n) in fresh
        .iter()
        .zip(mesh::stats::quad_corner_normals_of(mesh, model, &fresh))
    {
        normals[q as usize] = n;
        sicn[q as usize] =
            quad_sicn_both_judges(&mesh.quads[q as usize].map(|v| mesh.nodes[v as usize]), &n);
    }
    around.extend(fresh);
    around.sort_unstable();
}

/// A curve node that may slide: its node and the parameters of its two
/// curve neighbours (`lo < t < hi`).
struct Slider {
    node: u32,
    lo: f64,
    hi: f64,
}

/// The curve nodes of `mesh` that may slide, each with the parameters of its
/// neighbours along the curve (from the mesh's curve edges; a corner
/// neighbour at the curve's end nearer the node's side).
fn sliders(model: &Model, mesh: &QuadMesh) -> Vec<Slider> {
    let mut next: HashMap<u32, Vec<u32>> = HashMap::new();
    for &([a, b], _) in &mesh.curve_edges {
        next.entry(a).or_default().push(b);
        next.entry(b).or_default().push(a);
    }
    let mut out = Vec::new();
    for (v, class) in mesh.node_class.iter().enumerate() {
        let NodeClass::Curve(c, Some(t)) = *class else {
            continue;
        };
        let Some(curve) = model.curves.get(c.idx()) else {
            continue;
        };
        if curve.degenerate || curve.geom.is_none() {
            continue;
        }
        let Some(nb) = next.get(&(v as u32)) else {
            continue;
        };
        // the neighbours' parameters (both ends for a corner)
        let mut params: Vec<f64> = Vec::with_capacity(4);
        for &w in nb {
            match mesh.node_class.get(w as usize) {
                Some(NodeClass::Curve(d, Some(s))) if *d == c => params.push(*s),
                Some(NodeClass::Corner(_)) => params.extend([curve.range.0, curve.range.1]),
                _ => {}
            }
        }
        let lo = params
            .iter()
            .copied()
            .filter(|&s| s < t)
            .fold(f64::NEG_INFINITY, f64::max);
        let hi = params
            .iter()
            .copied()
            .filter(|&s| s > t)
            .fold(f64::INFINITY, f64::min);
        if nb.len() == 2 && lo.is_finite() && hi.is_finite() {
            out.push(Slider {
                node: v as u32,
                lo,
                hi,
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::options::Size;
    use crate::{mesh_model_with, MeshMethod, MeshOptions};
    use geometry::primitives;

    #[test]
    fn neighbours_along_a_curve_take_alternate_colours() {
        // five curve nodes along a strip of quads: node i lies on quads i − 1
        // and i, so each shares a quad with the next only
        let movers: Vec<Mover> = (0..5)
            .map(|i| Mover::Curve {
                node: i,
                lo: 0.0,
                hi: 1.0,
            })
            .collect();
        let quads_of: Vec<Vec<u32>> = (0..5u32)
            .map(|i| if i == 0 { vec![0] } else { vec![i - 1, i] })
            .collect();
        let colours = colour_movers(&movers, &quads_of, 5);
        assert_eq!(colours, vec![vec![vec![0, 2, 4]], vec![vec![1, 3]]]);
        // a node sharing quads with nodes of colours 0 and 1 takes colour 2
        let movers3: Vec<Mover> = (0..3).map(|i| Mover::Face { node: i }).collect();
        let quads_of3 = vec![vec![0], vec![0, 1], vec![0, 1]];
        assert_eq!(
            colour_movers(&movers3, &quads_of3, 2),
            vec![vec![vec![0]], vec![vec![1]], vec![vec![2]]]
        );
        // more movers of one colour than a chunk: several groups
        let many: Vec<Mover> = (0..(COLOUR_CHUNK as u32 + 1))
            .map(|i| Mover::Face { node: i })
            .collect();
        let own: Vec<Vec<u32>> = (0..(COLOUR_CHUNK as u32 + 1)).map(|i| vec![i]).collect();
        let c = colour_movers(&many, &own, COLOUR_CHUNK + 1);
        assert_eq!(c.len(), 1);
        assert_eq!(c[0].len(), 2);
        assert_eq!(c[0][1], vec![COLOUR_CHUNK]);
    }

    /// The quads' SICN with the statistics' normals.
    fn sicn(model: &Model, mesh: &QuadMesh) -> Vec<f64> {
        mesh::stats::quad_sicn_values(mesh, Some(model))
    }

    #[test]
    fn a_curve_node_pushed_aside_slides_back_and_every_node_stays_on_the_cad() {
        let model = primitives::square(1.0);
        let opts = MeshOptions {
            size: Size::Absolute(0.1),
            threads: Some(1),
            ..Default::default()
        };
        let (mut mesh, _) = mesh_model_with(&model, &opts, MeshMethod::Baseline).unwrap();
        let sliders = sliders(&model, &mesh);
        assert!(!sliders.is_empty());
        // push one curve node a third of the way toward a neighbour
        let s = &sliders[sliders.len() / 2];
        let v = s.node as usize;
        let NodeClass::Curve(c, Some(t0)) = mesh.node_class[v] else {
            panic!("not a curve node");
        };
        let t1 = t0 + (s.lo - t0) / 3.0;
        let geom = model.curves[c.idx()].geom.clone().unwrap();
        mesh.nodes[v] = geom.eval(t1);
        mesh.node_class[v] = NodeClass::Curve(c, Some(t1));
        let before = sicn(&model, &mesh);
        let corners: Vec<Vec3> = mesh
            .corner_nodes
            .iter()
            .map(|&(n, _)| mesh.nodes[n as usize])
            .collect();
        // the face nodes farther than FACE_RINGS rings from every curve node
        let mut near: Vec<bool> = (0..mesh.nodes.len())
            .map(|n| !mesh.is_face_interior(n))
            .collect();
        for _ in 0..FACE_RINGS {
            let grow: Vec<u32> = mesh
                .quads
                .iter()
                .filter(|q| q.iter().any(|&w| near[w as usize]))
                .flatten()
                .copied()
                .collect();
            for w in grow {
                near[w as usize] = true;
            }
        }
        let far: Vec<(usize, Vec3)> = (0..mesh.nodes.len())
            .filter(|&n| !near[n])
            .map(|n| (n, mesh.nodes[n]))
            .collect();
        assert!(!far.is_empty());
        let report = slide_curve_nodes(&model, &mut mesh, 20);
        let after = sicn(&model, &mesh);
        let avg = |q: &[f64]| q.iter().sum::<f64>() / q.len() as f64;
        assert!(
            report.moves > 0 && report.after > report.before,
            "{report:?}"
        );
        assert!(avg(&after) > avg(&before));
        // no quad fell below its floor
        for (b, a) in before.iter().zip(&after) {
            assert!(*a >= ascent_floor(*b) - 1e-12, "{b} → {a}");
        }
        // the pushed node went back toward where it was, between its neighbours
        let NodeClass::Curve(c2, Some(t2)) = mesh.node_class[v] else {
            panic!("reclassified");
        };
        assert_eq!(c2, c);
        assert!((t2 - t0).abs() < (t1 - t0).abs(), "{t0} {t1} {t2}");
        // every curve node sits on its curve at its parameter, every face
        // node on the surface at its (u, v); corners and the face nodes far
        // from the curves did not move
        for (n, class) in mesh.node_class.iter().enumerate() {
            match class {
                NodeClass::Curve(c, Some(t)) => {
                    let on = model.curves[c.idx()].geom.as_ref().unwrap().eval(*t);
                    assert!(geometry::vec3::dist(on, mesh.nodes[n]) < 1e-12);
                }
                NodeClass::Face(f, Some(uv)) => {
                    let on = model.faces[f.idx()].surface.eval(*uv);
                    assert!(geometry::vec3::dist(on, mesh.nodes[n]) < 1e-9);
                }
                _ => {}
            }
        }
        for (n, x) in far {
            assert_eq!(mesh.nodes[n], x, "node {n} moved");
        }
        let corners_after: Vec<Vec3> = mesh
            .corner_nodes
            .iter()
            .map(|&(n, _)| mesh.nodes[n as usize])
            .collect();
        assert_eq!(corners, corners_after);
    }
}
