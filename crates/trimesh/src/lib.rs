//! Triangle-mesh input: an STL, OBJ, PLY or MSH triangle mesh turned into the
//! same [`geometry::Model`] a CAD import gives (a *discrete B-rep*), so every
//! Quadrille command works on it.
//!
//! Stages, one module each, in order:
//! 1. [`read`]: the file into points and triangles (errors name the line,
//!    byte or triangle: non-finite coordinates, indices out of range,
//!    truncated binary STL, no triangle);
//! 2. [`weld`]: points within `weld_tolerance × diagonal` merged (hash grid);
//! 3. [`topology`]: degenerate triangles dropped (warning), edge table,
//!    **non-manifold edges rejected** (the error gives the edge's end
//!    points), orientation made consistent per component by a breadth-first
//!    search (non-orientable components rejected), closed components outward;
//! 4. [`features`]: feature edges (dihedral angle above
//!    [`Options::feature_angle`], open boundary, user edges) and corners
//!    (where the number of curve edges is not 2, or a chain turns by more than
//!    [`Options::corner_angle`]);
//! 5. [`patches`]: faces = connected triangles between feature edges; creases
//!    that separate nothing are dropped; a face whose triangles all face one
//!    direction keeps its holes as inner loops (it is projected, step 6);
//!    any other face that is not a disk is cut by seams (shortest paths
//!    joining its boundary loops; one path between two far vertices on a
//!    closed face); faces with handles (genus > 0) are an error; curves =
//!    chains of feature and seam edges between corners (a closed chain
//!    without a corner gets one at its lowest-numbered vertex);
//! 6. [`parametrize`]: a projection onto the mean plane when every triangle
//!    faces within ~72° of the mean normal, else a Tutte map of the cut face
//!    onto a rectangle (four corners) or a circle: no flipped triangle either
//!    way (checked, reported in [`FaceReport::min_uv_area`]);
//! 7. [`surface`]: the piecewise-linear [`geometry::Surface`] /
//!    [`geometry::Curve`] / [`geometry::Curve2d`] of faces, curves and pcurves.
//!
//! The model follows `geometry::model`'s conventions: each face has one outer
//! loop (then holes, for projected faces); a seam curve appears twice in it, once each way (`CurveUse::seam`);
//! the face normal `du × dv` is the oriented triangles' normal (outward on
//! closed components), so no face is `reversed`; there are no degenerate
//! curves.

pub mod charts;
pub mod error;
pub mod features;
pub mod parametrize;
pub mod patches;
pub mod read;
pub mod surface;
pub mod topology;
pub mod weld;

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use geometry::{vec3, Corner, CornerId, CurveEntity, CurveId, CurveUse, Face, Loop, Model, Vec3};

pub use error::TrimeshError;
pub use parametrize::Shape;
pub use read::{Format, Soup};

/// Import options.
#[derive(Clone, Debug)]
pub struct Options {
    /// Dihedral angle (degrees) above which an edge is a feature edge.
    pub feature_angle: f64,
    /// Turn angle (degrees) above which a feature chain gets a corner. Larger
    /// than the feature angle by default: a coarsely tessellated circle (12
    /// segments turn by 30° each) must stay one curve.
    pub corner_angle: f64,
    /// User feature edges: pairs of 1-based vertex numbers as the file
    /// numbers its vertices (STL: the facets' vertices in order, 3 per facet).
    pub feature_edges: Vec<[u32; 2]>,
    /// Points closer than this times the bounding-box diagonal are welded.
    pub weld_tolerance: f64,
}

/// Default feature angle, degrees.
pub const DEFAULT_FEATURE_ANGLE: f64 = 30.0;
/// Default corner angle, degrees.
pub const DEFAULT_CORNER_ANGLE: f64 = 60.0;

impl Default for Options {
    fn default() -> Self {
        Options {
            feature_angle: DEFAULT_FEATURE_ANGLE,
            corner_angle: DEFAULT_CORNER_ANGLE,
            feature_edges: Vec::new(),
            weld_tolerance: 1e-9,
        }
    }
}

/// What the import found about one face.
#[derive(Clone, Debug)]
pub struct FaceReport {
    /// Triangles of the face.
    pub triangles: usize,
    /// Smallest signed (u, v) triangle area (positive: no flipped triangle).
    pub min_uv_area: f64,
    /// The boundary shape of its Tutte map.
    pub shape: Shape,
    /// Seam curves cut into it.
    pub seams: usize,
    /// [`parametrize::scale_spread`] of its map.
    pub scale_spread: f64,
}

/// What the import did: counts, repairs and warnings, stage times.
#[derive(Clone, Debug, Default)]
pub struct ImportReport {
    /// Triangles in the file.
    pub input_triangles: usize,
    /// Vertices after welding.
    pub vertices: usize,
    /// Triangles kept.
    pub triangles: usize,
    /// Degenerate triangles dropped.
    pub dropped_degenerate: usize,
    /// Triangles flipped to make orientations consistent.
    pub flipped: usize,
    /// Patches: the connected regions between feature curves (the model's
    /// faces, except that a charted patch gives several).
    pub patches: usize,
    /// Patches split into charts (their single map was too distorted, or
    /// they have handles), and the charts made of them.
    pub charted_faces: usize,
    /// Charts made (faces of the model that come from charted patches).
    pub charts: usize,
    /// Feature edges dropped because they separate nothing.
    pub dangling_feature_edges: usize,
    /// Per face.
    pub faces: Vec<FaceReport>,
    /// Human-readable warnings (repairs done).
    pub warnings: Vec<String>,
    /// Seconds per stage: read, weld + topology, features, patches + cuts, parametrization.
    pub seconds: [f64; 5],
}

/// A triangle mesh turned into a model.
pub struct Import {
    /// The discrete B-rep.
    pub model: Model,
    /// What was found and repaired.
    pub report: ImportReport,
}

/// Reads a triangle-mesh file (format from its extension) into a model.
pub fn load(path: &Path, opts: &Options) -> Result<Import, TrimeshError> {
    let t = Instant::now();
    let soup = read::read_file(path)?;
    let read_s = t.elapsed().as_secs_f64();
    let mut imp = build(soup, opts, path)?;
    imp.report.seconds[0] = read_s;
    Ok(imp)
}

/// Reads a file of user feature edges: one pair of 1-based vertex numbers
/// per line (`#` starts a comment).
pub fn read_feature_edges(path: &Path) -> Result<Vec<[u32; 2]>, TrimeshError> {
    let text = std::fs::read_to_string(path).map_err(|source| TrimeshError::Io {
        path: path.into(),
        source,
    })?;
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let nums: Vec<&str> = line
            .split(|c: char| c.is_whitespace() || c == ',')
            .filter(|s| !s.is_empty())
            .collect();
        let parse = |s: &str| s.parse::<u32>().ok().filter(|&x| x > 0);
        match (
            nums.len(),
            nums.first().and_then(|s| parse(s)),
            nums.get(1).and_then(|s| parse(s)),
        ) {
            (2, Some(a), Some(b)) => out.push([a, b]),
            _ => {
                return Err(TrimeshError::Parse {
                    path: path.into(),
                    msg: format!(
                        "line {}: expected two vertex numbers (1-based), got `{line}`",
                        i + 1
                    ),
                })
            }
        }
    }
    Ok(out)
}

/// Largest [`parametrize::scale_spread`] of a face's Tutte map; a patch
/// whose map spreads more is split into charts ([`charts`]). A cylinder side
/// on its rectangle is at 1.0; a sphere cut open along one seam onto a
/// circle at 4.6, and its quads then come out poor (min SICN near 0), as do
/// those of a rounded cube's one-face shell (4.2).
pub const MAX_SCALE_SPREAD: f64 = 3.0;

/// True when a flip-free map of a cut patch is one-to-one: its boundary
/// loops stay simple and apart in (u, v).
fn one_to_one(map: &parametrize::DiskMap, cp: &patches::CutPatch) -> bool {
    let loops: Vec<Vec<u32>> = cp
        .loops
        .iter()
        .map(|lp| lp.iter().map(|&(c, _)| c).collect())
        .collect();
    parametrize::loops_are_simple(&map.uv, &loops)
}

/// What seam cutting reads of the whole mesh.
struct SeamContext<'a> {
    points: &'a [Vec3],
    tris: &'a [[u32; 3]],
    topo: &'a topology::Topology,
    adj: &'a patches::Adjacency,
    patch_of: &'a [u32],
}

/// Cuts a patch with several boundary loops (or none: a closed patch) open
/// along seams: shortest paths joining its loops (between corners when it can,
/// so that a seam splits no curve), or, for a closed patch, one path between
/// two far-apart vertices. Marks the seam edges in `seam` and `cut`, their ends
/// in `corner`, recording every change in `changed_*`; returns the patch's
/// triangles, or `None` when no seam could be found.
#[allow(clippy::too_many_arguments)]
fn cut_with_seams(
    cp: &patches::CutPatch,
    p: u32,
    ctx: SeamContext<'_>,
    seam: &mut [bool],
    cut: &mut [bool],
    corner: &mut [bool],
    changed_edges: &mut Vec<u32>,
    changed_corners: &mut Vec<u32>,
) -> Option<Vec<u32>> {
    let SeamContext {
        points,
        tris,
        topo,
        adj,
        patch_of,
    } = ctx;
    let mut on_boundary = std::collections::HashSet::new();
    for lp in &cp.loops {
        for &(c, _) in lp {
            on_boundary.insert(cp.copy_vertex[c as usize]);
        }
    }
    let mut inner = std::collections::HashSet::new();
    let mut add_path = |path: &[u32],
                        seam: &mut [bool],
                        cut: &mut [bool],
                        corner: &mut [bool],
                        inner: &mut std::collections::HashSet<u32>| {
        for &e in path {
            if !cut[e as usize] {
                changed_edges.push(e);
            }
            seam[e as usize] = true;
            cut[e as usize] = true;
            for v in topo.edges[e as usize] {
                inner.insert(v);
            }
        }
        // the path's end vertices: those of the first / last edge not shared with a neighbour edge
        let end = |e: u32, other: u32| -> u32 {
            let [a, b] = topo.edges[e as usize];
            let [c, d] = topo.edges[other as usize];
            if a == c || a == d {
                b
            } else {
                a
            }
        };
        let ends = if path.len() == 1 {
            topo.edges[path[0] as usize]
        } else {
            [
                end(path[0], path[1]),
                end(path[path.len() - 1], path[path.len() - 2]),
            ]
        };
        for v in ends {
            if !corner[v as usize] {
                corner[v as usize] = true;
                changed_corners.push(v);
            }
        }
    };
    if cp.loops.is_empty() {
        // a closed face: one seam between two far-apart vertices
        let s = tris[cp.tris[0] as usize][0];
        let (a, _) = patches::bfs_far(topo, adj, patch_of, p, s);
        let (b, prev) = patches::bfs_far(topo, adj, patch_of, p, a);
        let mut path = Vec::new();
        let mut v = b;
        while let Some(&(u, e)) = prev.get(&v) {
            if u == u32::MAX {
                break;
            }
            path.push(e);
            v = u;
        }
        if path.len() < 2 {
            return None;
        }
        add_path(&path, seam, cut, corner, &mut inner);
    } else {
        let loop_verts: Vec<Vec<u32>> = cp
            .loops
            .iter()
            .map(|lp| {
                lp.iter()
                    .map(|&(c, _)| cp.copy_vertex[c as usize])
                    .collect()
            })
            .collect();
        let mut joined = vec![0usize];
        for i in 1..cp.loops.len() {
            // first between corners (a seam then splits no curve), else
            // between any loop vertices (the seam's end becomes a corner)
            let mut found = None;
            for any in [false, true] {
                let pick = |j: usize| -> Vec<u32> {
                    let cs: Vec<u32> = loop_verts[j]
                        .iter()
                        .copied()
                        .filter(|&v| any || corner[v as usize])
                        .collect();
                    if cs.is_empty() {
                        loop_verts[j].clone()
                    } else {
                        cs
                    }
                };
                let sources: Vec<u32> = joined.iter().flat_map(|&j| pick(j)).collect();
                let targets: std::collections::HashSet<u32> = pick(i).into_iter().collect();
                found = patches::shortest_path(
                    points,
                    topo,
                    adj,
                    patch_of,
                    p,
                    cut,
                    &sources,
                    &|v| targets.contains(&v),
                    &|v| !on_boundary.contains(&v) && !inner.contains(&v),
                );
                if found.is_some() {
                    break;
                }
            }
            add_path(&found?, seam, cut, corner, &mut inner);
            joined.push(i);
        }
    }
    Some(cp.tris.clone())
}

fn bbox(points: &[Vec3]) -> (Vec3, Vec3) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}

/// Builds the model of a triangle soup; `name` is used in messages.
pub fn build(soup: Soup, opts: &Options, name: &Path) -> Result<Import, TrimeshError> {
    let invalid = |msg: String| TrimeshError::Invalid {
        path: name.into(),
        msg,
    };
    let mut report = ImportReport {
        input_triangles: soup.tris.len(),
        ..Default::default()
    };
    if soup.tris.is_empty() {
        return Err(invalid("the mesh has no triangle".into()));
    }
    if !(opts.feature_angle > 0.0 && opts.feature_angle < 180.0) {
        return Err(invalid(format!(
            "feature angle {}° is not between 0 and 180",
            opts.feature_angle
        )));
    }
    if !(opts.corner_angle > 0.0 && opts.corner_angle < 180.0) {
        return Err(invalid(format!(
            "corner angle {}° is not between 0 and 180",
            opts.corner_angle
        )));
    }
    let t0 = Instant::now();
    // 2. weld
    let used: Vec<Vec3> = soup.points.clone();
    let (lo, hi) = bbox(&used);
    let diag = vec3::dist(lo, hi);
    if !(diag > 0.0) {
        return Err(invalid("all points coincide".into()));
    }
    let (points, map) = weld::weld(&soup.points, opts.weld_tolerance * diag);
    let tris: Vec<[u32; 3]> = soup
        .tris
        .iter()
        .map(|t| t.map(|v| map[v as usize]))
        .collect();
    let mut user = Vec::with_capacity(opts.feature_edges.len());
    for (i, &[a, b]) in opts.feature_edges.iter().enumerate() {
        let n = soup.points.len() as u32;
        if a == 0 || b == 0 || a > n || b > n {
            return Err(invalid(format!(
                "feature edge {} ({a} {b}): vertex number out of range 1..{n}",
                i + 1
            )));
        }
        user.push([map[a as usize - 1], map[b as usize - 1]]);
    }
    // 3. topology
    let (mut tris, dropped, first) = topology::drop_degenerate(&points, &tris, 1e-16 * diag * diag);
    report.dropped_degenerate = dropped;
    if tris.is_empty() {
        return Err(invalid(format!(
            "all {} triangles are degenerate (zero area)",
            soup.tris.len()
        )));
    }
    if dropped > 0 {
        report.warnings.push(format!(
            "{dropped} degenerate (zero-area) triangles dropped, the first is triangle {}",
            first.unwrap_or(0)
        ));
    }
    let nm = |(a, b, n): (u32, u32, usize)| {
        invalid(format!(
            "non-manifold edge: {n} triangles share the edge from {:?} to {:?} (vertex {a} to {b} after welding)",
            points[a as usize], points[b as usize]
        ))
    };
    let mut topo = topology::build(&tris).map_err(nm)?;
    let flipped = topology::orient(&points, &mut tris, &topo).map_err(|t| {
        invalid(format!(
            "the surface is not orientable (a Möbius-like strip): conflict at triangle {:?}",
            tris[t].map(|v| points[v as usize])
        ))
    })?;
    if flipped > 0 {
        report.flipped = flipped;
        report.warnings.push(format!(
            "{flipped} triangles flipped to make the orientation consistent"
        ));
        topo = topology::build(&tris).map_err(nm)?;
    }
    // drop vertices no triangle uses (they would be isolated)
    report.vertices = points.len();
    report.triangles = tris.len();
    let t1 = Instant::now();
    // 4. features
    let angle = opts.feature_angle.to_radians();
    let normals = features::tri_normals(&points, &tris);
    let mut feature = features::feature_edges(&normals, &topo, angle, &user).map_err(|i| {
        let [a, b] = opts.feature_edges[i];
        invalid(format!(
            "feature edge {} ({a} {b}) is not an edge of the mesh",
            i + 1
        ))
    })?;
    let t2 = Instant::now();
    // 5. patches and cuts
    let (patch_of, npatch) = patches::label(tris.len(), &topo, &feature);
    report.dangling_feature_edges = patches::drop_dangling(&topo, &patch_of, &mut feature);
    if report.dangling_feature_edges > 0 {
        report.warnings.push(format!(
            "{} feature edges inside a face (separating nothing) ignored",
            report.dangling_feature_edges
        ));
    }
    report.patches = npatch;
    let mut corner = features::corners(&points, &topo, &feature, opts.corner_angle.to_radians());
    let mut by_patch: Vec<Vec<u32>> = vec![Vec::new(); npatch];
    for (t, &p) in patch_of.iter().enumerate() {
        by_patch[p as usize].push(t as u32);
    }
    let mut seam = vec![false; topo.edges.len()];
    let mut cut: Vec<bool> = feature.clone();
    let mut local = vec![u32::MAX; tris.len()];
    let adj = patches::Adjacency::new(points.len(), &topo);
    let mut cuts = Vec::with_capacity(npatch);
    let pinch = |v: u32| {
        invalid(format!(
            "the surface pinches at vertex {:?} (a non-manifold vertex)",
            points[v as usize]
        ))
    };
    // a Tutte map of a disk with the corners known so far, judged by its scale spread
    let maps_well = |cp: &patches::CutPatch, corner: &[bool]| -> bool {
        let xyz: Vec<Vec3> = cp.copy_vertex.iter().map(|&v| points[v as usize]).collect();
        let boundary: Vec<u32> = cp.loops[0].iter().map(|&(c, _)| c).collect();
        let corner_at: Vec<usize> = (0..boundary.len())
            .filter(|&i| corner[cp.copy_vertex[boundary[i] as usize] as usize])
            .collect();
        parametrize::tutte(&xyz, &cp.copy_tris, &boundary, &corner_at).is_ok_and(|m| {
            parametrize::scale_spread(&xyz, &cp.copy_tris, &m.uv) <= MAX_SCALE_SPREAD
        })
    };
    for (p, list) in by_patch.into_iter().enumerate() {
        let cp = patches::cut_patch(&tris, &topo, list, &cut, &mut local).map_err(pinch)?;
        // a patch facing one direction is projected (holes stay holes, no seam)
        let xyz: Vec<Vec3> = cp.copy_vertex.iter().map(|&v| points[v as usize]).collect();
        if !cp.loops.is_empty() {
            if let Some(map) =
                parametrize::project_plane(&xyz, &cp.copy_tris).filter(|m| one_to_one(m, &cp))
            {
                cuts.push((cp, Some(map)));
                continue;
            }
        }
        if cp.is_disk() && maps_well(&cp, &corner) {
            cuts.push((cp, None));
            continue;
        }
        let at = cp
            .tris
            .first()
            .map(|&t| points[tris[t as usize][0] as usize])
            .unwrap_or([0.0; 3]);
        if !cp.is_disk() && cp.genus() == 0 {
            // seams; what they change is recorded to undo it when the cut
            // patch still maps badly (it is then split into charts)
            let mut changed_edges: Vec<u32> = Vec::new();
            let mut changed_corners: Vec<u32> = Vec::new();
            if let Some(cut_open) = cut_with_seams(
                &cp,
                p as u32,
                SeamContext {
                    points: &points,
                    tris: &tris,
                    topo: &topo,
                    adj: &adj,
                    patch_of: &patch_of,
                },
                &mut seam,
                &mut cut,
                &mut corner,
                &mut changed_edges,
                &mut changed_corners,
            ) {
                let cp2 =
                    patches::cut_patch(&tris, &topo, cut_open, &cut, &mut local).map_err(pinch)?;
                if cp2.is_disk() && maps_well(&cp2, &corner) {
                    cuts.push((cp2, None));
                    continue;
                }
            }
            for &e in &changed_edges {
                seam[e as usize] = false;
                cut[e as usize] = false;
            }
            for &v in &changed_corners {
                corner[v as usize] = false;
            }
        }
        // charts: disks within a normal cone, their borders become curves; a
        // chart that neither projects one-to-one nor maps well by Tutte is
        // split again with half the cone
        report.charted_faces += 1;
        let mut pending = vec![(cp.tris.clone(), charts::CHART_CONE_DEG)];
        while let Some((region, cone)) = pending.pop() {
            let (label, ncharts) =
                charts::split_into_charts(&points, &tris, &topo, &normals, &region, &cut, cone);
            let mut members: Vec<Vec<u32>> = vec![Vec::new(); ncharts];
            for (i, &t) in region.iter().enumerate() {
                members[label[i] as usize].push(t);
                local[t as usize] = label[i];
            }
            for &t in &region {
                for &e in &topo.tri_edges[t as usize] {
                    let [t0, t1] = topo.edge_tris[e as usize];
                    let o = if t0 == t { t1 } else { t0 };
                    if o != u32::MAX
                        && local[o as usize] != u32::MAX
                        && local[o as usize] != local[t as usize]
                    {
                        cut[e as usize] = true;
                    }
                }
            }
            for &t in &region {
                local[t as usize] = u32::MAX;
            }
            for list in members {
                let cc = patches::cut_patch(&tris, &topo, list, &cut, &mut local).map_err(pinch)?;
                if !cc.is_disk() {
                    return Err(invalid(format!(
                        "face {} (near {at:?}): a chart is not a disk (Euler characteristic {}, {} boundary loops)",
                        p + 1,
                        cc.euler,
                        cc.loops.len()
                    )));
                }
                let xyz: Vec<Vec3> = cc.copy_vertex.iter().map(|&v| points[v as usize]).collect();
                let map =
                    parametrize::project_plane(&xyz, &cc.copy_tris).filter(|m| one_to_one(m, &cc));
                if map.is_none()
                    && cone > charts::MIN_CHART_CONE_DEG
                    && cc.tris.len() > charts::MIN_CHART_TRIANGLES
                    && !maps_well(&cc, &corner)
                {
                    pending.push((cc.tris, 0.5 * cone));
                    continue;
                }
                report.charts += 1;
                cuts.push((cc, map));
            }
        }
    }
    let (chains, edge_chain) = patches::chain_curves(points.len(), &topo, &cut, &seam, &mut corner);
    let t3 = Instant::now();
    // 6-7. model: corners, curves, faces
    let mut model = Model::default();
    let mut corner_id = vec![u32::MAX; points.len()];
    let mut cid = |v: u32, model: &mut Model| -> CornerId {
        if corner_id[v as usize] == u32::MAX {
            corner_id[v as usize] = model.corners.len() as u32;
            model.corners.push(Corner {
                point: points[v as usize],
            });
        }
        CornerId(corner_id[v as usize])
    };
    let mut curves = Vec::with_capacity(chains.len());
    for ch in &chains {
        let c = Arc::new(surface::PolyCurve::new(
            ch.verts.iter().map(|&v| points[v as usize]).collect(),
        ));
        let start = cid(ch.verts[0], &mut model);
        let end = cid(*ch.verts.last().unwrap_or(&ch.verts[0]), &mut model);
        model.curves.push(CurveEntity {
            geom: Some(c.clone()),
            range: (0.0, c.length()),
            start,
            end,
            degenerate: false,
        });
        curves.push(c);
    }
    for (p, (cp, projected)) in cuts.iter().enumerate() {
        let xyz: Vec<Vec3> = cp.copy_vertex.iter().map(|&v| points[v as usize]).collect();
        let starts: Vec<usize> = cp
            .loops
            .iter()
            .map(|lp| (0..lp.len()).find(|&i| corner[cp.copy_vertex[lp[i].0 as usize] as usize]))
            .collect::<Option<Vec<usize>>>()
            .ok_or_else(|| invalid(format!("face {}: a boundary loop has no corner", p + 1)))?;
        let map = match projected {
            Some(m) => m.clone(),
            None => {
                let lp = &cp.loops[0];
                let n = lp.len();
                let boundary: Vec<u32> = (0..n).map(|i| lp[(starts[0] + i) % n].0).collect();
                let corner_at: Vec<usize> = (0..n)
                    .filter(|&i| corner[cp.copy_vertex[boundary[i] as usize] as usize])
                    .collect();
                let tutte = parametrize::tutte(&xyz, &cp.copy_tris, &boundary, &corner_at)
                    .map_err(|m| invalid(format!("face {}: parametrization failed: {m}", p + 1)))?;
                // a circle boundary squeezes curved charts: a free-boundary conformal
                // map instead when it is one-to-one and spreads lengths less
                let spread = |m: &parametrize::DiskMap| {
                    parametrize::scale_spread(&xyz, &cp.copy_tris, &m.uv)
                };
                let free = (tutte.shape == parametrize::Shape::Circle)
                    .then(|| parametrize::lscm(&xyz, &cp.copy_tris, &boundary))
                    .flatten()
                    .filter(|m| one_to_one(m, cp) && spread(m) < spread(&tutte));
                free.unwrap_or(tutte)
            }
        };
        // curve uses along each loop
        let mut loops: Vec<(f64, Vec<CurveUse>)> = Vec::new();
        for (lp, &s0) in cp.loops.iter().zip(&starts) {
            let n = lp.len();
            let mut uses: Vec<CurveUse> = Vec::new();
            let mut i = 0;
            while i < n {
                let (c0, e0) = lp[(s0 + i) % n];
                let (ch, seg) = edge_chain[e0 as usize];
                let chain = &chains[ch as usize];
                let forward = chain.verts[seg as usize] == cp.copy_vertex[c0 as usize];
                let m = chain.verts.len() - 1;
                let mut copies = Vec::with_capacity(m + 1);
                for k in 0..m {
                    let (c, e) = lp[(s0 + i + k) % n];
                    if edge_chain[e as usize].0 != ch {
                        return Err(invalid(format!(
                            "face {}: boundary curve {} is interrupted",
                            p + 1,
                            ch + 1
                        )));
                    }
                    copies.push(c);
                }
                copies.push(lp[(s0 + i + m) % n].0);
                let mut uv: Vec<[f64; 2]> = copies.iter().map(|&c| map.uv[c as usize]).collect();
                if !forward {
                    uv.reverse();
                }
                let pc = surface::PolyCurve2d {
                    t: curves[ch as usize].t.clone(),
                    uv,
                };
                uses.push(CurveUse {
                    curve: CurveId(ch),
                    forward,
                    pcurve: Arc::new(pc),
                    seam: false,
                });
                i += m;
            }
            let poly: Vec<[f64; 2]> = lp.iter().map(|&(c, _)| map.uv[c as usize]).collect();
            loops.push((geometry::model::signed_area(&poly), uses));
        }
        // the outer loop (largest signed area) first, then the holes
        loops.sort_by(|a, b| b.0.total_cmp(&a.0));
        if !(loops[0].0 > 0.0) || loops.iter().skip(1).any(|l| !(l.0 < 0.0)) {
            return Err(invalid(format!(
                "face {}: its boundary loops are not one outer loop and holes in (u, v)",
                p + 1
            )));
        }
        let mut uses: Vec<CurveUse> = loops[0].1.clone();
        let nseam = uses.iter().filter(|u| chains[u.curve.idx()].seam).count() / 2;
        for k in 0..uses.len() {
            let c = uses[k].curve;
            uses[k].seam = uses.iter().filter(|u| u.curve == c).count() == 2;
        }
        let scale_spread = parametrize::scale_spread(&xyz, &cp.copy_tris, &map.uv);
        let surf = surface::TriSurface::new(xyz, map.uv, cp.copy_tris.clone());
        report.faces.push(FaceReport {
            triangles: cp.tris.len(),
            min_uv_area: map.min_area,
            shape: map.shape,
            seams: nseam,
            scale_spread,
        });
        let uv_bounds = geometry::Surface::uv_bounds(&surf);
        let mut face_loops = vec![Loop { uses, outer: true }];
        face_loops.extend(
            loops
                .into_iter()
                .skip(1)
                .map(|(_, uses)| Loop { uses, outer: false }),
        );
        model.faces.push(Face {
            surface: Arc::new(surf),
            reversed: false,
            loops: face_loops,
            uv_bounds,
        });
    }
    let t4 = Instant::now();
    report.seconds[1] = (t1 - t0).as_secs_f64();
    report.seconds[2] = (t2 - t1).as_secs_f64();
    report.seconds[3] = (t3 - t2).as_secs_f64();
    report.seconds[4] = (t4 - t3).as_secs_f64();
    model.validate().map_err(|e| invalid(e.to_string()))?;
    Ok(Import { model, report })
}
