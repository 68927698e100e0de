//! The closed wires of a CAD file with no face (issue 30, item 1: "No face:
//! its closed wires"), for curve networks drawn as wireframes.
//!
//! Wireframe STEP files (a `GEOMETRIC_CURVE_SET`, as Gmsh and most CAD tools
//! write them) keep curves but not wires, and give each curve its own end
//! vertices, so the wires are rebuilt here from the curves: end corners
//! closer than the weld tolerance (1e-7 × the diagonal, or the vertices' own
//! OCCT tolerance when larger) are one point, and every connected set of
//! curves in which each point ends exactly two curve uses is a closed wire
//! (a closed curve alone is one). Curves in any other set (a dead end, or a
//! junction of three or more curves, where the cycles are ambiguous without
//! faces) are listed in [`Wires::open_curves`].
//!
//! Each curve use is sampled at equal arc lengths at most 1/200 of the
//! diagonal apart and turning at most 5° per segment, its ends replaced by
//! the welded points, so consecutive uses share their end points exactly.
//!
//! `quadrille curves` reads it when [`crate::load`] finds no face
//! (`ImportError::NoFace`): each [`ClosedWire`] becomes one cycle of one
//! loop (`quadrille::curvenet::network_from_wires`), the quads facing the
//! loop's Newell normal (a wireframe has no face orientation), and
//! [`Wires::open_curves`] are named on one line.

use std::path::Path;

use geometry::vec3::{dist, dot, normalize, sub, Vec3};
use geometry::{CurveEntity, Model};

use crate::ffi::ModelPtr;
use crate::import::{build_curves, counts, CurveSet};
use crate::ImportError;

/// Largest sample spacing, as a share of the diagonal.
const SPACING: f64 = 1.0 / 200.0;
/// Largest turn per sample segment, in degrees.
const TURN_DEG: f64 = 5.0;
/// Weld tolerance of curve ends, as a share of the diagonal.
const WELD: f64 = 1e-7;
/// Dense samples per curve used to measure length and turn.
const DENSE: usize = 512;

/// One curve use of a closed wire, sampled.
#[derive(Clone, Debug, PartialEq)]
pub struct WireUse {
    /// The CAD curve, 0-based (`Wires::model.curves` index; CAD files number
    /// it one higher).
    pub curve: usize,
    /// True when the wire runs the curve from its start corner to its end.
    pub forward: bool,
    /// Samples in the wire's direction; the first is the previous use's last.
    pub points: Vec<Vec3>,
}

/// A closed wire: curve uses in order, the last ending where the first starts.
#[derive(Clone, Debug, PartialEq)]
pub struct ClosedWire {
    /// The uses, in order.
    pub uses: Vec<WireUse>,
}

impl ClosedWire {
    /// The wire as one closed polyline (first point not repeated at the end).
    pub fn polyline(&self) -> Vec<Vec3> {
        self.uses
            .iter()
            .flat_map(|u| u.points[..u.points.len() - 1].iter().copied())
            .collect()
    }
}

/// What [`load_wires`] found in a faceless file.
#[derive(Debug)]
pub struct Wires {
    /// Corners and curves as read (no faces), ids as in [`crate::load`].
    pub model: Model,
    /// The closed wires, ordered by their lowest curve id.
    pub closed: Vec<ClosedWire>,
    /// Curves in no closed wire (0-based, increasing), degenerate ones included.
    pub open_curves: Vec<usize>,
}

/// Reads a STEP, IGES or BREP file that has curves but no face and returns
/// its closed wires as sampled polylines with their CAD curve ids. A file
/// with faces is refused (use [`crate::load`] and the faces' loops), as is one
/// with no curve.
pub fn load_wires(path: &Path) -> Result<Wires, ImportError> {
    let owned = path.to_path_buf();
    crate::open_with(path, move |shape| build(&shape, &owned))
}

/// Builds the wires of a loaded shape.
fn build(m: &ModelPtr, path: &Path) -> Result<Wires, ImportError> {
    let (nf, ne, nv) = counts(m);
    let invalid = |detail: String| ImportError::Invalid {
        path: path.to_path_buf(),
        detail,
    };
    if nf > 0 {
        return Err(invalid(format!(
            "the shape has {nf} faces: its curve cycles are the faces' loops, not free wires"
        )));
    }
    if ne == 0 {
        return Err(ImportError::NoFace {
            path: path.to_path_buf(),
            detail: format!("the shape has no face and no curve ({nv} vertices)"),
        });
    }
    let CurveSet {
        corners,
        curves,
        corner_tolerance,
        ..
    } = build_curves(m, path)?;
    let model = Model {
        corners,
        curves,
        faces: Vec::new(),
    };
    let dense: Vec<Option<Vec<(f64, Vec3)>>> = model
        .curves
        .iter()
        .map(|c| dense_samples(&model, c))
        .collect();
    let diag = diagonal(&model);
    let spacing = SPACING * diag;

    // weld the end corners of the usable curves
    let mut point_of: Vec<usize> = Vec::with_capacity(model.corners.len());
    let mut reps: Vec<(Vec3, f64)> = Vec::new();
    for (c, tol) in model.corners.iter().zip(&corner_tolerance) {
        let tol = (WELD * diag).max(*tol);
        match reps
            .iter()
            .position(|(p, t)| dist(*p, c.point) <= tol.max(*t))
        {
            Some(i) => point_of.push(i),
            None => {
                point_of.push(reps.len());
                reps.push((c.point, tol));
            }
        }
    }
    let ends = |ci: usize| {
        let c = &model.curves[ci];
        (point_of[c.start.idx()], point_of[c.end.idx()])
    };
    let usable: Vec<bool> = dense.iter().map(Option::is_some).collect();

    // connected sets of usable curves (union-find over welded points)
    let mut parent: Vec<usize> = (0..reps.len()).collect();
    fn find(parent: &mut [usize], mut x: usize) -> usize {
        while parent[x] != x {
            parent[x] = parent[parent[x]];
            x = parent[x];
        }
        x
    }
    let mut degree = vec![0usize; reps.len()];
    for ci in (0..model.curves.len()).filter(|&ci| usable[ci]) {
        let (a, b) = ends(ci);
        degree[a] += 1;
        degree[b] += 1;
        let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
        parent[ra] = rb;
    }
    let mut sets: Vec<(usize, Vec<usize>)> = Vec::new(); // (root, curves), by lowest curve id
    for ci in (0..model.curves.len()).filter(|&ci| usable[ci]) {
        let root = find(&mut parent, ends(ci).0);
        match sets.iter_mut().find(|(r, _)| *r == root) {
            Some((_, v)) => v.push(ci),
            None => sets.push((root, vec![ci])),
        }
    }

    let mut closed = Vec::new();
    let mut open_curves: Vec<usize> = (0..model.curves.len()).filter(|&ci| !usable[ci]).collect();
    for (_, set) in sets {
        let simple = set.iter().all(|&ci| {
            let (a, b) = ends(ci);
            degree[a] == 2 && degree[b] == 2
        });
        if !simple {
            open_curves.extend(&set);
            continue;
        }
        // walk the cycle from its lowest curve, forward first
        let mut uses = Vec::with_capacity(set.len());
        let mut used = vec![false; set.len()];
        let (mut ci, mut forward) = (set[0], true);
        loop {
            let k = set.iter().position(|&c| c == ci).unwrap_or(0);
            used[k] = true;
            let (a, b) = ends(ci);
            let (from, to) = if forward { (a, b) } else { (b, a) };
            let samples = dense[ci].as_deref().unwrap_or(&[]);
            let curve = &model.curves[ci];
            let params = resample(samples, forward, spacing);
            let mut points: Vec<Vec3> = params.iter().map(|&t| curve.eval(&model, t)).collect();
            if let Some(first) = points.first_mut() {
                *first = reps[from].0;
            }
            if let Some(last) = points.last_mut() {
                *last = reps[to].0;
            }
            uses.push(WireUse {
                curve: ci,
                forward,
                points,
            });
            let next = set.iter().enumerate().find(|&(j, &c)| {
                let (p, q) = ends(c);
                !used[j] && (p == to || q == to)
            });
            match next {
                Some((_, &c)) => {
                    forward = ends(c).0 == to;
                    ci = c;
                }
                None => break,
            }
        }
        closed.push(ClosedWire { uses });
    }
    open_curves.sort_unstable();
    Ok(Wires {
        model,
        closed,
        open_curves,
    })
}

/// `DENSE + 1` (parameter, point) pairs at equal parameter steps over the
/// curve's range, or `None` for a degenerate curve or one with no 3D
/// geometry or non-finite points.
fn dense_samples(model: &Model, c: &CurveEntity) -> Option<Vec<(f64, Vec3)>> {
    if c.degenerate || c.geom.is_none() {
        return None;
    }
    let (t0, t1) = c.range;
    let pts: Vec<(f64, Vec3)> = (0..=DENSE)
        .map(|i| t0 + (t1 - t0) * i as f64 / DENSE as f64)
        .map(|t| (t, c.eval(model, t)))
        .collect();
    pts.iter()
        .all(|(_, p)| p.iter().all(|x| x.is_finite()))
        .then_some(pts)
}

/// The model's bounding-box diagonal ([`Model::diagonal`]), 1 when empty or flat to a point.
fn diagonal(model: &Model) -> f64 {
    let d = model.diagonal();
    if d.is_finite() && d > 0.0 {
        d
    } else {
        1.0
    }
}

/// The parameters of a curve's samples in the use's direction (reversed
/// when `!forward`), from its dense samples: equal arc lengths (measured on
/// the dense polyline), at most `spacing` apart and turning at most
/// [`TURN_DEG`] per segment, both ends included.
fn resample(dense: &[(f64, Vec3)], forward: bool, spacing: f64) -> Vec<f64> {
    let mut dense: Vec<(f64, Vec3)> = dense.to_vec();
    if !forward {
        dense.reverse();
    }
    let pts: Vec<Vec3> = dense.iter().map(|(_, p)| *p).collect();
    let ts: Vec<f64> = dense.iter().map(|(t, _)| *t).collect();
    if ts.len() < 2 {
        return ts;
    }
    let mut arc = vec![0.0; pts.len()];
    let mut turn = 0.0;
    for i in 1..pts.len() {
        arc[i] = arc[i - 1] + dist(pts[i - 1], pts[i]);
        if i + 1 < pts.len() {
            if let (Some(u), Some(v)) = (
                normalize(sub(pts[i], pts[i - 1])),
                normalize(sub(pts[i + 1], pts[i])),
            ) {
                turn += dot(u, v).clamp(-1.0, 1.0).acos();
            }
        }
    }
    let len = arc.last().copied().unwrap_or(0.0);
    let by_length = if spacing > 0.0 {
        (len / spacing).ceil()
    } else {
        1.0
    };
    let by_turn = (turn.to_degrees() / TURN_DEG).ceil();
    let n = by_length.max(by_turn).clamp(1.0, 1e6) as usize;
    let mut out = Vec::with_capacity(n + 1);
    out.push(ts[0]);
    let mut j = 1;
    for k in 1..n {
        let s = len * k as f64 / n as f64;
        while j + 1 < arc.len() && arc[j] < s {
            j += 1;
        }
        let (a, b) = (arc[j - 1], arc[j]);
        let w = if b > a { (s - a) / (b - a) } else { 0.0 };
        out.push(ts[j - 1] + (ts[j] - ts[j - 1]) * w);
    }
    out.push(ts[ts.len() - 1]);
    out
}
