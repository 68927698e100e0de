//! The size map of a whole model (paper §4.1–4.2, spec §5): the target quad
//! edge length `s(x)` at every vertex of the faces' background triangulations.
//!
//! `s = min(s_cf, s_min)`, clamped to the user's bounds:
//! - `s_cf`, the **conformal** size: per face `e^{H_i + C_i}` ([`crate::field::scaling`]),
//!   `C_i` chosen for `N_i = area_i / h_i²` quads (`h_i` the face's own size if
//!   the user gave one, else the global size). On vertices shared by faces
//!   (curves, corners) the smallest face value wins, then the field is graded.
//! - `s_min`, the **small-feature** size, set on curve and corner vertices:
//!   at most the length of the curve, and at most the distance to the nearest
//!   curve that shares no corner with it (two close curves need small quads
//!   between them); user sizes on corners and curves are min-ed in; then it is
//!   graded over the whole model.
//!
//! Grading is the one-way Dijkstra relaxation of Eq. 10,
//! `s(x2) ← min(s(x2), s(x1) + g · |x1 x2|)` over every background edge, run on
//! the background vertices of **all** faces welded along their shared curves,
//! so sizes flow across CAD curves. `g` is [`SizeMapOptions::gradient`]
//! (the paper gives no value; [`DEFAULT_GRADIENT`]).
//!
//! Curves are then quantized against the map (§4.3): [`SizeMap::curve_sizes`]
//! gives each curve's size profile for [`crate::curves::curve_mesh::plan_curves_sized`].

use std::cmp::Ordering;
use std::collections::{BinaryHeap, HashMap};

use geometry::vec3::{self, Vec3};
use geometry::{CornerId, CurveId, FaceId, Model};

use crate::core::patch::NodeRef;
use crate::curves::curve_mesh::CurveMesh;
use crate::field::crossfield::FaceTopology;
use crate::field::scaling::scaling_constant;

mod narrow;
pub use narrow::boundary_loop_count;

/// Default largest size gradient `g` of Eq. 10: the size grows by at most
/// 20 % of the distance travelled (spec §5.3; useful range 0.1–0.5).
pub const DEFAULT_GRADIENT: f64 = 0.2;

/// On a band around an axis (a face of two boundary loops,
/// [`boundary_loop_count`]: a fillet of revolution), the floor lowered by the
/// turn rule ([`SizeMapOptions::floor_turn`]) is never below this fraction of
/// [`SizeMapOptions::min_size`]. Such a fillet whose 90° arc is shorter gets
/// quads longer along it than across instead of squares, because its loops
/// are whole loops of the faces beside it, which ring grids and bands
/// (`curves::count_balance`) carry over their whole area: on the held-out
/// shaft `h71207_14_turned` (fillets of radius 0.025 under a floor of 0.67)
/// the squares put 834 edges on each fillet circle (187,390 quads, 1,432
/// irregular vertices; 25,460 and 123 with this bound). Fillets of one loop
/// keep the arc: bounded too, the gears' tiny root fillets
/// (`t_gear_60_teeth`, a held-out spur gear) lost 0.7–0.9 points of
/// irregular share and took twice the time. The same quarter as the width
/// rule's [`narrow::NARROW_MIN_FRACTION`].
pub const TURN_MIN_FRACTION: f64 = 0.25;

/// Distances below this fraction of the model diagonal are contact, not a
/// gap: corners that close are one corner, and a curve that close to a point
/// is not a separate feature there.
pub const CONTACT_TOLERANCE: f64 = 1e-7;

/// Segments of a curve polyline grouped under one bounding box for the
/// distance queries of the small-feature size.
const CHUNK: usize = 16;

/// A model entity a user can give a size to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Entity {
    /// A CAD corner: the size at that point.
    Corner(CornerId),
    /// A CAD curve: the size along the curve (and at its end corners).
    Curve(CurveId),
    /// A CAD face: sets the face's quad target `N_i = area / size²`.
    Face(FaceId),
}

/// How the size map is built.
#[derive(Clone, Debug)]
pub struct SizeMapOptions {
    /// Largest size gradient `g` (Eq. 10); must be positive.
    pub gradient: f64,
    /// Adapt to small CAD features (short curves, close curves).
    pub small_features: bool,
    /// Sizes are never below this (model units).
    pub min_size: Option<f64>,
    /// Sizes are never above this (model units).
    pub max_size: Option<f64>,
    /// User sizes on corners, curves and faces.
    pub entity_sizes: Vec<(Entity, f64)>,
    /// Quads per full turn of the surface normal on curved faces: a face
    /// whose typical curvature is `κ` gets at most the size `2π / (n κ)`
    /// (a fillet of radius r at most `2πr / n`), unless the user gave the
    /// face a size. `None`: no curvature bound.
    pub quads_per_turn: Option<f64>,
    /// Turn of the surface normal (radians) whose arc length bounds the
    /// floor on curved faces: a face of typical curvature `κ` with
    /// `turn / κ` below [`SizeMapOptions::min_size`] lowers the floor to
    /// `turn / κ` on its vertices, graded like the sizes (with 90°, a 90°
    /// fillet of radius r narrower than the floor gets quads about as long
    /// along it, `π r / 2`, as the fillet is wide, instead of the floor),
    /// on bands never below [`TURN_MIN_FRACTION`] of the floor.
    /// `None`: the floor is `min_size` everywhere.
    pub floor_turn: Option<f64>,
    /// A strip-like face narrower than [`SizeMapOptions::min_size`] (width
    /// `w = 2 A / P` from its area and boundary length, at least
    /// [`narrow::NARROW_ELONGATION`] times as long, at least
    /// [`narrow::NARROW_MIN_FRACTION`] of the floor wide, of even width along it,
    /// [`narrow::NARROW_EVENNESS`], and with one boundary loop,
    /// [`boundary_loop_count`]) lowers the floor on its vertices to `w`,
    /// graded like the sizes: its two quads across (the curves' smallest
    /// count) are 1 : 2, not stretched along it to the floor. Tapering faces
    /// (chamfer crescents, vanishing fillets) and bands around an axis keep
    /// the floor.
    pub floor_narrow: bool,
}

impl Default for SizeMapOptions {
    fn default() -> Self {
        SizeMapOptions {
            gradient: DEFAULT_GRADIENT,
            small_features: true,
            min_size: None,
            max_size: None,
            entity_sizes: Vec::new(),
            quads_per_turn: None,
            floor_turn: None,
            floor_narrow: false,
        }
    }
}

/// Why a size map could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SizeMapError {
    /// An option is out of range.
    #[error("invalid size-map option: {0}")]
    InvalidOption(String),
    /// A user size names an entity the model does not have.
    #[error("a size is given for {0:?}, which the model does not have")]
    UnknownEntity(Entity),
}

/// One face's background triangulation as the size map sees it.
#[derive(Clone, Copy, Debug)]
pub struct FaceBackground<'a> {
    /// The face.
    pub face: FaceId,
    /// Its welded background triangulation (positions, edges, triangles, areas).
    pub topo: &'a FaceTopology,
    /// Model identity of each welded vertex (curve point, corner or interior).
    pub refs: &'a [NodeRef],
    /// The conformal scaling `H` per welded vertex, when it was computed
    /// (without it the face's conformal size is uniform).
    pub scaling: Option<&'a [f64]>,
    /// The face's typical largest principal curvature ([`typical_curvature`]),
    /// which bounds its size when [`SizeMapOptions::quads_per_turn`] is set.
    pub curvature: Option<f64>,
}

/// The background vertices of all faces, welded along shared curves and
/// corners, with their edges: the graph the grading runs on.
#[derive(Clone, Debug, Default)]
pub struct BackgroundGraph {
    /// Position of each global vertex.
    pub positions: Vec<Vec3>,
    /// Model identity of each global vertex.
    pub refs: Vec<NodeRef>,
    /// Per face given to [`BackgroundGraph::build`] (same order): global id of
    /// each of its welded vertices.
    pub face_vertices: Vec<Vec<u32>>,
    /// Neighbours of each global vertex (sorted, without repeats).
    pub neighbours: Vec<Vec<u32>>,
}

impl BackgroundGraph {
    /// Welds the faces' background vertices: one global vertex per curve
    /// point and per corner, one per interior vertex of each face.
    pub fn build(faces: &[FaceBackground<'_>]) -> BackgroundGraph {
        let mut g = BackgroundGraph::default();
        let mut shared: HashMap<NodeRef, u32> = HashMap::new();
        for f in faces {
            let mut ids = Vec::with_capacity(f.refs.len());
            for (v, &r) in f.refs.iter().enumerate() {
                let fresh = g.positions.len() as u32;
                let id = if r == NodeRef::Interior {
                    fresh
                } else {
                    *shared.entry(r).or_insert(fresh)
                };
                if id == fresh {
                    g.positions.push(f.topo.positions[v]);
                    g.refs.push(r);
                    g.neighbours.push(Vec::new());
                }
                ids.push(id);
            }
            for e in &f.topo.edges {
                let (a, b) = (ids[e[0] as usize], ids[e[1] as usize]);
                if a != b {
                    g.neighbours[a as usize].push(b);
                    g.neighbours[b as usize].push(a);
                }
            }
            g.face_vertices.push(ids);
        }
        for n in &mut g.neighbours {
            n.sort_unstable();
            n.dedup();
        }
        g
    }

    /// Number of global vertices.
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// True when there is no vertex.
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }
}

/// Area quantile of the curvature that [`typical_curvature`] returns: a
/// fillet or a cylinder (constant curvature) reads its 1/R, while a small,
/// sharply curved strip of a free-form face (a wing's leading and trailing
/// edges) does not make the whole face fine.
pub const CURVATURE_QUANTILE: f64 = 0.75;

/// Triangles [`typical_curvature`] samples at most per face.
const CURVATURE_SAMPLES: usize = 512;

/// The curvature below which [`CURVATURE_QUANTILE`] of the area of `face`
/// lies: the largest principal curvature ([`geometry::Face::max_curvature`])
/// at the centroid (u, v) of each triangle of a triangulation of the face
/// (`uvs`, `xyz` per node, `triangles`; evenly strided down to
/// [`CURVATURE_SAMPLES`]), weighted by the triangle's area. `None` when no
/// centroid has a curvature (all singular) or the area is zero.
pub fn typical_curvature(
    face: &geometry::Face,
    uvs: &[[f64; 2]],
    xyz: &[Vec3],
    triangles: &[[u32; 3]],
) -> Option<f64> {
    let stride = triangles.len().div_ceil(CURVATURE_SAMPLES).max(1);
    let k: Vec<(f64, f64)> = triangles
        .iter()
        .step_by(stride)
        .filter_map(|t| {
            let [a, b, c] = t.map(|i| i as usize);
            let uv = [
                (uvs[a][0] + uvs[b][0] + uvs[c][0]) / 3.0,
                (uvs[a][1] + uvs[b][1] + uvs[c][1]) / 3.0,
            ];
            let area = 0.5
                * vec3::norm(vec3::cross(
                    vec3::sub(xyz[b], xyz[a]),
                    vec3::sub(xyz[c], xyz[a]),
                ));
            Some((face.max_curvature(uv)?, area))
        })
        .filter(|&(_, a)| a.is_finite())
        .collect();
    narrow::weighted_quantile(&k, CURVATURE_QUANTILE)
}

/// A heap entry ordered by size, smallest first.
#[derive(Clone, Copy, PartialEq)]
struct Smallest(f64, u32);

impl Eq for Smallest {}
impl PartialOrd for Smallest {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Smallest {
    fn cmp(&self, other: &Self) -> Ordering {
        other.0.total_cmp(&self.0).then(other.1.cmp(&self.1))
    }
}

/// Grades `sizes` in place over `graph` (Eq. 10): afterwards
/// `s(b) ≤ s(a) + gradient · |ab|` on every edge and no size has grown.
/// Infinite sizes are "no constraint yet". Dijkstra from every finite size,
/// `O(E log V)`.
pub fn grade(graph: &BackgroundGraph, sizes: &mut [f64], gradient: f64) {
    let mut heap: BinaryHeap<Smallest> = sizes
        .iter()
        .enumerate()
        .filter(|(_, s)| s.is_finite())
        .map(|(v, &s)| Smallest(s, v as u32))
        .collect();
    while let Some(Smallest(s, v)) = heap.pop() {
        if s > sizes[v as usize] {
            continue; // stale entry
        }
        let p = graph.positions[v as usize];
        for &w in &graph.neighbours[v as usize] {
            let cand = s + gradient * vec3::dist(p, graph.positions[w as usize]);
            if cand < sizes[w as usize] {
                sizes[w as usize] = cand;
                heap.push(Smallest(cand, w));
            }
        }
    }
}

/// A run of curve segments under one bounding box.
struct Chunk {
    curve: usize,
    lo: Vec3,
    hi: Vec3,
    points: Vec<Vec3>,
}

/// Distance from `p` to an axis-aligned box (0 inside).
fn box_distance(p: Vec3, lo: Vec3, hi: Vec3) -> f64 {
    let d = |i: usize| (lo[i] - p[i]).max(0.0).max(p[i] - hi[i]);
    (d(0).powi(2) + d(1).powi(2) + d(2).powi(2)).sqrt()
}

/// Cluster id of each corner: corners within `tol` of each other (chained)
/// share one, the smallest corner index of the cluster.
fn corner_clusters(model: &Model, tol: f64) -> Vec<usize> {
    let n = model.corners.len();
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let cell = |p: Vec3| p.map(|x| (x / tol.max(1e-300)).floor() as i64);
    let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for (i, k) in model.corners.iter().enumerate() {
        if k.point.iter().all(|x| x.is_finite()) {
            grid.entry(cell(k.point)).or_default().push(i);
        }
    }
    for (i, k) in model.corners.iter().enumerate() {
        if !k.point.iter().all(|x| x.is_finite()) {
            continue;
        }
        let c = cell(k.point);
        for d in 0..27i64 {
            // saturating: a far-away point's cell index is clamped to i64's
            // ends (the distance test below still decides)
            let key = [
                c[0].saturating_add(d % 3 - 1),
                c[1].saturating_add((d / 3) % 3 - 1),
                c[2].saturating_add(d / 9 - 1),
            ];
            for &j in grid.get(&key).map(Vec::as_slice).unwrap_or(&[]) {
                if j != i && vec3::dist(k.point, model.corners[j].point) <= tol {
                    let (a, b) = (root(&mut parent, i), root(&mut parent, j));
                    parent[a.max(b)] = a.min(b);
                }
            }
        }
    }
    (0..n).map(|i| root(&mut parent, i)).collect()
}

/// The small-feature size on curve and corner vertices of `graph` (spec §5.2),
/// +∞ on interior vertices: the length of the vertex's curve (for a corner,
/// of its shortest non-degenerate curve) and the distance to the nearest
/// curve that shares no corner with the vertex's curve, measured to the
/// curves' polylines `cms`. Only curves bounding a face count; corners and
/// curves in contact (within [`CONTACT_TOLERANCE`] × diagonal) are adjacent.
pub fn feature_sizes(model: &Model, cms: &[CurveMesh], graph: &BackgroundGraph) -> Vec<f64> {
    use rayon::prelude::*;
    let nc = model.curves.len();
    // curves on no face (free wires, often copies of face curves) neither get
    // nor give a feature size
    let mut on_face = vec![false; nc];
    for u in model
        .faces
        .iter()
        .flat_map(|f| &f.loops)
        .flat_map(|l| &l.uses)
    {
        if let Some(x) = on_face.get_mut(u.curve.idx()) {
            *x = true;
        }
    }
    let contact = CONTACT_TOLERANCE * model.diagonal();
    let length: Vec<f64> = (0..nc)
        .map(|c| {
            cms.get(c).map_or(0.0, |m| {
                m.points.windows(2).map(|w| vec3::dist(w[0], w[1])).sum()
            })
        })
        .collect();
    // a curve shorter than the contact tolerance is a point, not a feature
    let live = |c: usize| on_face[c] && !model.curves[c].degenerate && length[c] > contact;
    let mut chunks = Vec::new();
    for c in (0..nc).filter(|&c| live(c)) {
        let pts = &cms[c].points;
        let mut start = 0;
        while start + 1 < pts.len() {
            let end = (start + CHUNK).min(pts.len() - 1);
            let points = pts[start..=end].to_vec();
            let mut lo = [f64::INFINITY; 3];
            let mut hi = [f64::NEG_INFINITY; 3];
            for p in &points {
                for i in 0..3 {
                    lo[i] = lo[i].min(p[i]);
                    hi[i] = hi[i].max(p[i]);
                }
            }
            chunks.push(Chunk {
                curve: c,
                lo,
                hi,
                points,
            });
            start = end;
        }
    }
    // corners closer than the contact tolerance are one corner (unsewn
    // shells repeat their shared corners; CAD tolerance gaps)
    let cluster = corner_clusters(model, contact);
    let ends = |c: usize| {
        [
            cluster[model.curves[c].start.idx()],
            cluster[model.curves[c].end.idx()],
        ]
    };
    let adjacent = |a: usize, b: usize| a == b || ends(a).iter().any(|x| ends(b).contains(x));
    let mut corner_curves: Vec<Vec<usize>> = vec![Vec::new(); model.corners.len()];
    for c in (0..nc).filter(|&c| live(c)) {
        for k in ends(c) {
            if !corner_curves[k].contains(&c) {
                corner_curves[k].push(c);
            }
        }
    }
    let nearest_far_curve = |p: Vec3, own: &[usize], cap: f64| -> f64 {
        let mut order: Vec<(f64, usize)> = chunks
            .iter()
            .enumerate()
            .filter(|(_, ch)| own.iter().any(|&c| !adjacent(c, ch.curve)))
            .map(|(i, ch)| (box_distance(p, ch.lo, ch.hi), i))
            .filter(|&(d, _)| d < cap)
            .collect();
        order.sort_by(|a, b| a.0.total_cmp(&b.0));
        // nearest distance per curve; a curve touching `p` (within the
        // contact tolerance) is not a separate feature and is skipped
        let mut per_curve: HashMap<usize, f64> = HashMap::new();
        let mut touching: Vec<usize> = Vec::new();
        let mut best = cap;
        for (d, i) in order {
            if d >= best {
                break;
            }
            let c = chunks[i].curve;
            let near = chunks[i]
                .points
                .windows(2)
                .map(|w| vec3::segment_distance(p, w[0], w[1]))
                .fold(f64::INFINITY, f64::min);
            if near <= contact {
                touching.push(c);
                continue;
            }
            let e = per_curve.entry(c).or_insert(f64::INFINITY);
            *e = e.min(near);
            if !touching.contains(&c) {
                best = per_curve
                    .iter()
                    .filter(|(k, _)| !touching.contains(k))
                    .map(|(_, &d)| d)
                    .fold(cap, f64::min);
            }
        }
        per_curve
            .iter()
            .filter(|(k, _)| !touching.contains(k))
            .map(|(_, &d)| d)
            .fold(cap, f64::min)
    };
    (0..graph.len())
        .into_par_iter()
        .map(|v| {
            let own: Vec<usize> = match graph.refs[v] {
                NodeRef::Interior => return f64::INFINITY,
                NodeRef::Curve(c, _) => vec![c.idx()].into_iter().filter(|&c| live(c)).collect(),
                NodeRef::Corner(k) => corner_curves
                    .get(cluster[k.idx()])
                    .cloned()
                    .unwrap_or_default(),
            };
            let cap = own.iter().map(|&c| length[c]).fold(f64::INFINITY, f64::min);
            nearest_far_curve(graph.positions[v], &own, cap)
        })
        .collect()
}

/// The size map of a model on its background triangulations.
#[derive(Clone, Debug)]
pub struct SizeMap {
    /// The welded background vertices.
    pub graph: BackgroundGraph,
    /// The conformal size `s_cf`, made continuous and graded.
    pub conformal: Vec<f64>,
    /// The small-feature size `s_min` after grading (+∞ where nothing constrains it).
    pub feature: Vec<f64>,
    /// The size map `s = min(s_cf, s_min)`, clamped to the user's bounds.
    pub size: Vec<f64>,
    /// Faces the map was built for, in the order given.
    pub faces: Vec<FaceId>,
}

impl SizeMap {
    /// The size at each welded vertex of the `i`-th face given to [`build_size_map`].
    pub fn face_sizes(&self, i: usize) -> Vec<f64> {
        self.graph.face_vertices[i]
            .iter()
            .map(|&g| self.size[g as usize])
            .collect()
    }

    /// Each curve's size profile, as `(curve parameter, size)` pairs in
    /// increasing parameter order, from the background vertices on the curve
    /// and its end corners (`cms` the background curve meshes); `None` for a
    /// curve without background vertices (degenerate, or on no meshed face).
    pub fn curve_sizes(&self, model: &Model, cms: &[CurveMesh]) -> Vec<Option<Vec<[f64; 2]>>> {
        let mut at_curve: Vec<Vec<[f64; 2]>> = vec![Vec::new(); model.curves.len()];
        let mut at_corner: Vec<f64> = vec![f64::NAN; model.corners.len()];
        for (v, r) in self.graph.refs.iter().enumerate() {
            match *r {
                NodeRef::Curve(c, i) => {
                    if let Some(t) = cms.get(c.idx()).and_then(|m| m.params.get(i as usize)) {
                        at_curve[c.idx()].push([*t, self.size[v]]);
                    }
                }
                NodeRef::Corner(k) => at_corner[k.idx()] = self.size[v],
                NodeRef::Interior => {}
            }
        }
        at_curve
            .into_iter()
            .enumerate()
            .map(|(c, mut pts)| {
                let ce = &model.curves[c];
                if ce.degenerate || pts.is_empty() && at_corner[ce.start.idx()].is_nan() {
                    return None;
                }
                for (t, k) in [(ce.range.0, ce.start), (ce.range.1, ce.end)] {
                    if at_corner[k.idx()].is_finite() {
                        pts.push([t, at_corner[k.idx()]]);
                    }
                }
                pts.retain(|p| p[1].is_finite() && p[1] > 0.0);
                pts.sort_by(|a, b| a[0].total_cmp(&b[0]));
                (!pts.is_empty()).then_some(pts)
            })
            .collect()
    }
}

/// Checks the options against the model.
fn check_options(model: &Model, opts: &SizeMapOptions) -> Result<(), SizeMapError> {
    let positive = |x: f64| x.is_finite() && x > 0.0;
    if !positive(opts.gradient) {
        return Err(SizeMapError::InvalidOption(format!(
            "gradient {} must be a positive number",
            opts.gradient
        )));
    }
    for (name, v) in [
        ("minimum size", opts.min_size),
        ("maximum size", opts.max_size),
        ("quads per turn", opts.quads_per_turn),
        ("floor turn", opts.floor_turn),
    ] {
        if let Some(v) = v.filter(|&v| !positive(v)) {
            return Err(SizeMapError::InvalidOption(format!(
                "{name} {v} must be a positive number"
            )));
        }
    }
    if let (Some(lo), Some(hi)) = (opts.min_size, opts.max_size) {
        if lo > hi {
            return Err(SizeMapError::InvalidOption(format!(
                "minimum size {lo} is above maximum size {hi}"
            )));
        }
    }
    for &(e, s) in &opts.entity_sizes {
        let exists = match e {
            Entity::Corner(k) => k.idx() < model.corners.len(),
            Entity::Curve(c) => c.idx() < model.curves.len(),
            Entity::Face(f) => f.idx() < model.faces.len(),
        };
        if !exists {
            return Err(SizeMapError::UnknownEntity(e));
        }
        if !positive(s) {
            return Err(SizeMapError::InvalidOption(format!(
                "size {s} of {e:?} must be a positive number"
            )));
        }
    }
    Ok(())
}

/// The lowered floor of every graph vertex ([`SizeMapOptions::floor_turn`],
/// [`SizeMapOptions::floor_narrow`]): `turn / κ` or the width `w`, the
/// smaller, on the vertices of each face where that is below the floor `lo`
/// (unless [`narrow::keep_strips_off_wide_faces`] drops the face), graded
/// over the graph (+∞ elsewhere); `None` when no face lowers it.
fn turn_floors(
    graph: &BackgroundGraph,
    faces: &[FaceBackground<'_>],
    lo: f64,
    opts: &SizeMapOptions,
) -> Option<Vec<f64>> {
    if opts.floor_turn.is_none() && !opts.floor_narrow {
        return None;
    }
    let by_turn: Vec<f64> = faces
        .iter()
        .map(|f| match (opts.floor_turn, f.curvature) {
            (Some(turn), Some(k)) if k.is_finite() && k > 0.0 => {
                // on a band, never below a quarter of the floor: a fillet of
                // revolution whose 90° arc is shorter gets quads longer along
                // it than wide, not tiny squares whose count the faces beside
                // it would carry round their whole circumference
                let arc = turn / k;
                let bound = TURN_MIN_FRACTION * lo;
                let by_turn = if arc < bound && boundary_loop_count(f.topo).is_some_and(|n| n >= 2) {
                    bound
                } else {
                    arc
                };
                if by_turn < lo {
                    tracing::debug!(
                        "turn rule: face {} curvature {k:.4} lowers the floor {lo:.4} to {by_turn:.4}{}",
                        f.face.idx() + 1,
                        if by_turn == bound { " (bounded: a band)" } else { "" }
                    );
                }
                by_turn
            }
            _ => f64::INFINITY,
        })
        .collect();
    let by_width: Vec<f64> = match opts.floor_narrow {
        true => narrow::width_floors(faces, &by_turn, lo),
        false => vec![f64::INFINITY; faces.len()],
    };
    let mut by_face: Vec<f64> = by_turn
        .iter()
        .zip(&by_width)
        .map(|(&t, &w)| Some(t.min(w)).filter(|&s| s < lo).unwrap_or(f64::INFINITY))
        .collect();
    narrow::keep_strips_off_wide_faces(graph, faces, lo, &mut by_face);
    if by_face.iter().all(|s| !s.is_finite()) {
        return None;
    }
    let mut floors = vec![f64::INFINITY; graph.len()];
    for (i, &s) in by_face.iter().enumerate() {
        if s.is_finite() {
            for &g in &graph.face_vertices[i] {
                floors[g as usize] = floors[g as usize].min(s);
            }
        }
    }
    grade(graph, &mut floors, opts.gradient);
    Some(floors)
}

/// Builds the size map of `model` over `faces` (see the module
/// documentation). `h` is the global target size, `cms` the background curve
/// meshes the triangulations were built on.
pub fn build_size_map(
    model: &Model,
    cms: &[CurveMesh],
    faces: &[FaceBackground<'_>],
    h: f64,
    opts: &SizeMapOptions,
) -> Result<SizeMap, SizeMapError> {
    check_options(model, opts)?;
    if !(h.is_finite() && h > 0.0) {
        return Err(SizeMapError::InvalidOption(format!(
            "global size {h} must be a positive number"
        )));
    }
    let graph = BackgroundGraph::build(faces);
    // a face's own size (the smallest given), else the global one, bounded
    // by its curvature
    let face_size = |f: &FaceBackground<'_>| {
        let own = opts
            .entity_sizes
            .iter()
            .filter(|(e, _)| *e == Entity::Face(f.face))
            .map(|&(_, s)| s)
            .fold(f64::INFINITY, f64::min);
        if own.is_finite() {
            return own;
        }
        match (opts.quads_per_turn, f.curvature) {
            (Some(n), Some(k)) if n > 0.0 && k > 0.0 => h.min(std::f64::consts::TAU / (n * k)),
            _ => h,
        }
    };
    // conformal: per face e^{H + C_i}, smallest face value on shared vertices
    let mut conformal = vec![f64::INFINITY; graph.len()];
    for (i, f) in faces.iter().enumerate() {
        let hf = face_size(f);
        let area: f64 = f.topo.areas.iter().sum();
        let sizes: Vec<f64> = match f.scaling.and_then(|hs| {
            scaling_constant(f.topo, hs, area / (hf * hf))
                .ok()
                .map(|c| (hs, c))
        }) {
            Some((hs, c)) => hs.iter().map(|&x| (x + c).exp()).collect(),
            None => vec![hf; f.refs.len()],
        };
        for (v, &g) in graph.face_vertices[i].iter().enumerate() {
            let s = sizes[v];
            if s.is_finite() && s > 0.0 {
                conformal[g as usize] = conformal[g as usize].min(s);
            }
        }
    }
    // the two fields are graded independently: side by side
    let (_, feature) = rayon::join(
        || grade(&graph, &mut conformal, opts.gradient),
        || {
            // small features and user sizes on corners and curves
            let mut feature = if opts.small_features {
                feature_sizes(model, cms, &graph)
            } else {
                vec![f64::INFINITY; graph.len()]
            };
            for &(e, s) in &opts.entity_sizes {
                for (v, r) in graph.refs.iter().enumerate() {
                    let on = match (e, *r) {
                        (Entity::Corner(k), NodeRef::Corner(x)) => k == x,
                        (Entity::Curve(c), NodeRef::Curve(x, _)) => c == x,
                        (Entity::Curve(c), NodeRef::Corner(x)) => {
                            model.curves[c.idx()].start == x || model.curves[c.idx()].end == x
                        }
                        _ => false,
                    };
                    if on {
                        feature[v] = feature[v].min(s);
                    }
                }
            }
            grade(&graph, &mut feature, opts.gradient);
            feature
        },
    );
    let lo = opts.min_size.unwrap_or(0.0);
    let hi = opts.max_size.unwrap_or(f64::INFINITY);
    let floors = turn_floors(&graph, faces, lo, opts);
    let size: Vec<f64> = conformal
        .iter()
        .zip(&feature)
        .enumerate()
        .map(|(v, (&a, &b))| {
            let s = a.min(b);
            let lo = floors.as_ref().map_or(lo, |f| f[v].min(lo));
            // a vertex no face gave a finite size to keeps the global one
            (if s.is_finite() { s } else { h }).clamp(lo, hi)
        })
        .collect();
    Ok(SizeMap {
        graph,
        conformal,
        feature,
        size,
        faces: faces.iter().map(|f| f.face).collect(),
    })
}

#[cfg(test)]
mod tests;
