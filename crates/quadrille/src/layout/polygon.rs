//! ψ's boundary as an exact orthogonal polygon: the boundary loop of a
//! cone-free disk read in the immersion, cut at its corner cones, each run
//! between two corners checked straight and axis-aligned (Q3) and snapped
//! to its mean coordinate.

use super::LayoutError;
use crate::cut::CutMesh;
use crate::immersion::Immersion;
use crate::ricci::Cone;
use crate::shell::ShellTopology;

/// ψ's boundary, counter-clockwise, as the polygon of its corners.
#[derive(Clone, Debug, PartialEq)]
pub struct OrthogonalPolygon {
    /// Corner positions, snapped so every side is exactly axis-aligned.
    pub corners: Vec<[f64; 2]>,
    /// The shell vertex of each corner.
    pub corner_vertices: Vec<usize>,
    /// The largest distance of a boundary vertex of ψ from its run's snapped line.
    pub max_deviation: f64,
    /// The diagonal of ψ's bounding box.
    pub size: f64,
}

/// Reads the boundary of a disk cut with no cut path (ψ's children are its
/// shell vertices), cuts it at the `corners`, checks every run is straight
/// and axis-aligned within `tolerance` × ψ's diagonal, and snaps it.
pub fn orthogonal_boundary(
    topo: &ShellTopology,
    cut: &CutMesh,
    imm: &Immersion,
    corners: &[Cone],
    tolerance: f64,
) -> Result<OrthogonalPolygon, LayoutError> {
    if topo.boundary_loops.len() != 1 || !cut.paths.is_empty() {
        return Err(LayoutError::NotOrthogonal(format!(
            "the shell is not a disk without cuts ({} boundary loops, {} cut paths)",
            topo.boundary_loops.len(),
            cut.paths.len()
        )));
    }
    let mut child = vec![usize::MAX; topo.on_boundary.len()];
    for (c, &p) in cut.parent.iter().enumerate() {
        if child[p] == usize::MAX {
            child[p] = c;
        }
    }
    let mut lp: Vec<usize> = topo.boundary_loops[0].clone();
    let uv = |v: usize| imm.uv[child[v]];
    let area: f64 = (0..lp.len())
        .map(|i| {
            let (a, b) = (uv(lp[i]), uv(lp[(i + 1) % lp.len()]));
            a[0] * b[1] - a[1] * b[0]
        })
        .sum();
    if area < 0.0 {
        lp.reverse();
    }
    let is_corner = |v: usize| corners.iter().any(|c| c.vertex == v && c.index != 0);
    let Some(first) = lp.iter().position(|&v| is_corner(v)) else {
        return Err(LayoutError::NotOrthogonal(
            "ψ's boundary has no corner".into(),
        ));
    };
    lp.rotate_left(first);
    let starts: Vec<usize> = (0..lp.len()).filter(|&i| is_corner(lp[i])).collect();
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for &v in &lp {
        let p = uv(v);
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let size = ((hi[0] - lo[0]).powi(2) + (hi[1] - lo[1]).powi(2)).sqrt();
    let m = starts.len();
    // Per run: its axis (0: horizontal, the y is shared) and snapped coordinate.
    let mut runs = Vec::with_capacity(m);
    let mut max_deviation: f64 = 0.0;
    for r in 0..m {
        let (s, e) = (starts[r], if r + 1 < m { starts[r + 1] } else { lp.len() });
        let pts: Vec<[f64; 2]> = (s..=e).map(|i| uv(lp[i % lp.len()])).collect();
        let (a, b) = (pts[0], pts[pts.len() - 1]);
        let horizontal = (b[0] - a[0]).abs() >= (b[1] - a[1]).abs();
        let k = if horizontal { 1 } else { 0 };
        let mean = pts.iter().map(|p| p[k]).sum::<f64>() / pts.len() as f64;
        let dev = pts.iter().map(|p| (p[k] - mean).abs()).fold(0.0, f64::max);
        max_deviation = max_deviation.max(dev);
        if dev > tolerance * size {
            return Err(LayoutError::NotOrthogonal(format!(
                "the boundary run from {a:?} to {b:?} in ψ bends {:.3e} × its size off its axis (the limit is {tolerance:.0e})",
                dev / size
            )));
        }
        runs.push((horizontal, mean));
    }
    let mut out = Vec::with_capacity(m);
    for r in 0..m {
        let (prev, cur) = (runs[(r + m - 1) % m], runs[r]);
        if prev.0 == cur.0 {
            return Err(LayoutError::NotOrthogonal(format!(
                "two boundary runs in a row share one axis at the corner {:?} of ψ",
                uv(lp[starts[r]])
            )));
        }
        let (x, y) = if cur.0 {
            (prev.1, cur.1)
        } else {
            (cur.1, prev.1)
        };
        out.push([x, y]);
    }
    Ok(OrthogonalPolygon {
        corners: out,
        corner_vertices: starts.iter().map(|&i| lp[i]).collect(),
        max_deviation,
        size,
    })
}
