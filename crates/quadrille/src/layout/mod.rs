//! S8 of `quadrille spline` for shells that need no interior cone (spec
//! ricci-flow-iga-reconstruction §8.5, §9.1–9.2): the immersion ψ of a disk
//! whose only cones are boundary corners is an orthogonal polygon; the two
//! axis-aligned separatrices of every reflex corner are traced across it to
//! the boundary (full length, so they cross rather than end on each other:
//! no T-junctions), and the faces of that arrangement are the rectangles of
//! the quad layout. [`PsiLocator`] maps a point of ψ back to the shell.
//!
//! The arrangement lives on the grid of the corners' distinct coordinates:
//! every separatrix runs along grid lines, so it is exact (no predicates),
//! and a rectangle is a connected set of grid cells not split by a
//! boundary edge or a separatrix.

use thiserror::Error;

mod annulus;
mod locate;
mod polygon;

pub use annulus::{annulus_layout, AnnulusLayout};
pub use locate::PsiLocator;
pub use polygon::{orthogonal_boundary, OrthogonalPolygon};

/// Why the layout could not be traced.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum LayoutError {
    /// ψ's boundary is not an orthogonal polygon (Q3).
    #[error("layout: {0}")]
    NotOrthogonal(String),
    /// A separatrix did not reach the boundary (Q5).
    #[error("layout: the separatrix from the reflex corner at {start:?} did not reach the boundary in {steps} grid steps")]
    Unterminated {
        /// Its corner in ψ.
        start: [f64; 2],
        /// Steps taken.
        steps: usize,
    },
    /// A face of the arrangement is not a rectangle, or a side is split (a T-junction).
    #[error("layout: {0}")]
    NotConforming(String),
}

/// One rectangle of the layout: corner nodes counter-clockwise from the
/// bottom left (minimum x and y), and its four sides as arcs.
#[derive(Clone, Debug, PartialEq)]
pub struct LayoutRect {
    /// Nodes at (x0, y0), (x1, y0), (x1, y1), (x0, y1).
    pub corners: [usize; 4],
    /// The arcs of the sides bottom (+x), top (+x), left (+y), right (+y):
    /// the arc index and whether it runs against that direction.
    pub sides: [(usize, bool); 4],
}

/// The quad layout of an orthogonal polygon.
#[derive(Clone, Debug, PartialEq)]
pub struct Layout {
    /// Node positions in ψ.
    pub nodes: Vec<[f64; 2]>,
    /// Arcs as (start node, end node), each straight and axis-aligned.
    pub arcs: Vec<[usize; 2]>,
    /// Arc lies on ψ's boundary.
    pub arc_on_boundary: Vec<bool>,
    /// The rectangles.
    pub rects: Vec<LayoutRect>,
    /// Separatrices traced (two per reflex corner).
    pub separatrices: usize,
    /// Per node: the node it is glued to (itself, or an earlier node with the
    /// same place on the shell: the seam's copies in an annulus).
    pub node_glue: Vec<usize>,
    /// ψ repeats with this period along x (an annulus's loop length; `None`: a disk).
    pub period_x: Option<f64>,
}

/// Grid indices of the four axis directions +x, +y, −x, −y.
const STEPS: [(i64, i64); 4] = [(1, 0), (0, 1), (-1, 0), (0, -1)];

struct Grid {
    nx: usize,
    ny: usize,
    /// Vertical edge x = X[i], y ∈ [Y[j], Y[j+1]]: index i * (ny − 1) + j;
    /// 0 = none, 1 = boundary, 2 = separatrix.
    vertical: Vec<u8>,
    /// Horizontal edge y = Y[j], x ∈ [X[i], X[i+1]]: index j * (nx − 1) + i.
    horizontal: Vec<u8>,
}

impl Grid {
    /// The edge from grid point (i, j) one step in direction `d`, if inside the grid.
    fn edge(&self, i: usize, j: usize, d: usize) -> Option<(bool, usize)> {
        let (di, dj) = STEPS[d];
        let (ni, nj) = (i as i64 + di, j as i64 + dj);
        if ni < 0 || nj < 0 || ni as usize >= self.nx || nj as usize >= self.ny {
            return None;
        }
        Some(if dj == 0 {
            (false, j * (self.nx - 1) + i.min(ni as usize))
        } else {
            (true, i * (self.ny - 1) + j.min(nj as usize))
        })
    }
    fn mark(&self, e: (bool, usize)) -> u8 {
        if e.0 {
            self.vertical[e.1]
        } else {
            self.horizontal[e.1]
        }
    }
    fn set(&mut self, e: (bool, usize), m: u8) {
        let slot = if e.0 {
            &mut self.vertical[e.1]
        } else {
            &mut self.horizontal[e.1]
        };
        if *slot == 0 {
            *slot = m;
        }
    }
    fn marked(&self, i: usize, j: usize, d: usize) -> bool {
        self.edge(i, j, d).is_some_and(|e| self.mark(e) != 0)
    }
    fn step(i: usize, j: usize, d: usize) -> (usize, usize) {
        let (di, dj) = STEPS[d];
        ((i as i64 + di) as usize, (j as i64 + dj) as usize)
    }
}

/// Distinct values of `v` (sorted, merged within `eps`) and the index of each input.
fn distinct(values: &[f64], eps: f64) -> (Vec<f64>, Vec<usize>) {
    let mut order: Vec<usize> = (0..values.len()).collect();
    order.sort_by(|&a, &b| values[a].total_cmp(&values[b]));
    let mut out: Vec<f64> = Vec::new();
    let mut index = vec![0; values.len()];
    for &k in &order {
        if out.last().is_none_or(|&l| values[k] - l > eps) {
            out.push(values[k]);
        }
        index[k] = out.len() - 1;
    }
    (out, index)
}

/// Traces the separatrices of `poly`'s reflex corners and returns the
/// rectangles of the arrangement with their nodes and arcs (each arc once).
/// Checks Q5 (every separatrix ends on the boundary) and conformity (every
/// face a rectangle, every rectangle side one arc).
pub fn trace_layout(poly: &OrthogonalPolygon) -> Result<Layout, LayoutError> {
    let n = poly.corners.len();
    let eps = 1e-9 * poly.size.max(f64::MIN_POSITIVE);
    let xs: Vec<f64> = poly.corners.iter().map(|p| p[0]).collect();
    let ys: Vec<f64> = poly.corners.iter().map(|p| p[1]).collect();
    let (gx, ix) = distinct(&xs, eps);
    let (gy, iy) = distinct(&ys, eps);
    let (nx, ny) = (gx.len(), gy.len());
    if nx < 2 || ny < 2 {
        return Err(LayoutError::NotOrthogonal(format!(
            "ψ's boundary has no area ({nx} distinct x and {ny} distinct y corner coordinates)"
        )));
    }
    let mut grid = Grid {
        nx,
        ny,
        vertical: vec![0; nx * (ny - 1)],
        horizontal: vec![0; (nx - 1) * ny],
    };
    let direction = |a: (usize, usize), b: (usize, usize)| -> Option<usize> {
        match (a.0.cmp(&b.0), a.1.cmp(&b.1)) {
            (std::cmp::Ordering::Less, std::cmp::Ordering::Equal) => Some(0),
            (std::cmp::Ordering::Equal, std::cmp::Ordering::Less) => Some(1),
            (std::cmp::Ordering::Greater, std::cmp::Ordering::Equal) => Some(2),
            (std::cmp::Ordering::Equal, std::cmp::Ordering::Greater) => Some(3),
            _ => None,
        }
    };
    let at = |k: usize| (ix[k % n], iy[k % n]);
    let mut dirs = Vec::with_capacity(n);
    for k in 0..n {
        let (a, b) = (at(k), at(k + 1));
        let d = direction(a, b).ok_or_else(|| {
            LayoutError::NotOrthogonal(format!(
                "the boundary run from {:?} to {:?} is not axis-aligned or has no length",
                poly.corners[k],
                poly.corners[(k + 1) % n]
            ))
        })?;
        let (mut p, mut steps) = (a, 0);
        while p != b && steps <= nx + ny {
            let e = grid.edge(p.0, p.1, d).ok_or_else(|| {
                LayoutError::NotOrthogonal("a boundary run leaves the grid".into())
            })?;
            if grid.mark(e) != 0 {
                return Err(LayoutError::NotOrthogonal(format!(
                    "ψ's boundary overlaps itself near {:?}",
                    poly.corners[k]
                )));
            }
            grid.set(e, 1);
            p = Grid::step(p.0, p.1, d);
            steps += 1;
        }
        dirs.push(d);
    }
    // Separatrices: at a reflex corner (a right turn of the counter-clockwise
    // boundary), the incoming direction continued and the outgoing reversed.
    let on_boundary = |g: &Grid, i: usize, j: usize| {
        (0..4).any(|d| g.edge(i, j, d).is_some_and(|e| g.mark(e) == 1))
    };
    let mut separatrices = 0;
    for k in 0..n {
        let (din, dout) = (dirs[(k + n - 1) % n], dirs[k]);
        if (din + 3) % 4 != dout {
            continue;
        }
        for d in [din, (dout + 2) % 4] {
            let (mut p, mut steps) = (at(k), 0);
            loop {
                let e = grid.edge(p.0, p.1, d).filter(|_| steps <= nx + ny).ok_or(
                    LayoutError::Unterminated {
                        start: poly.corners[k],
                        steps,
                    },
                )?;
                if grid.mark(e) == 1 {
                    return Err(LayoutError::NotOrthogonal(format!(
                        "the separatrix from {:?} runs along the boundary",
                        poly.corners[k]
                    )));
                }
                grid.set(e, 2);
                p = Grid::step(p.0, p.1, d);
                steps += 1;
                if on_boundary(&grid, p.0, p.1) {
                    break;
                }
            }
            separatrices += 1;
        }
    }
    build_layout(&grid, &gx, &gy, poly, separatrices)
}

/// Nodes, arcs and rectangles from the marked grid.
fn build_layout(
    grid: &Grid,
    gx: &[f64],
    gy: &[f64],
    poly: &OrthogonalPolygon,
    separatrices: usize,
) -> Result<Layout, LayoutError> {
    let (nx, ny) = (grid.nx, grid.ny);
    // Cells inside ψ: the crossing count of a ray from the cell centre to +x.
    let inside_cell = |i: usize, j: usize| -> bool {
        (i + 1..nx)
            .filter(|&k| grid.vertical[k * (ny - 1) + j] == 1)
            .count()
            % 2
            == 1
    };
    let cell = |i: usize, j: usize| j * (nx - 1) + i;
    let ncell = (nx - 1) * (ny - 1);
    let inside: Vec<bool> = (0..ncell)
        .map(|c| inside_cell(c % (nx - 1), c / (nx - 1)))
        .collect();
    // Cells joined across unmarked edges.
    let mut parent: Vec<usize> = (0..ncell).collect();
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            if !inside[cell(i, j)] {
                continue;
            }
            if i + 1 < nx - 1
                && inside[cell(i + 1, j)]
                && grid.vertical[(i + 1) * (ny - 1) + j] == 0
            {
                crate::shell::union(&mut parent, cell(i, j), cell(i + 1, j));
            }
            if j + 1 < ny - 1
                && inside[cell(i, j + 1)]
                && grid.horizontal[(j + 1) * (nx - 1) + i] == 0
            {
                crate::shell::union(&mut parent, cell(i, j), cell(i, j + 1));
            }
        }
    }
    // Nodes: grid points where the marked edges do not pass straight through.
    let mut node_of = vec![usize::MAX; nx * ny];
    let mut nodes = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let m: Vec<bool> = (0..4).map(|d| grid.marked(i, j, d)).collect();
            let count = m.iter().filter(|&&b| b).count();
            let straight = count == 2 && ((m[0] && m[2]) || (m[1] && m[3]));
            if count > 0 && !straight {
                node_of[j * nx + i] = nodes.len();
                nodes.push([gx[i], gy[j]]);
            }
        }
    }
    // Arcs: from every node along each marked direction to the next node.
    let mut arcs: Vec<[usize; 2]> = Vec::new();
    let mut arc_on_boundary = Vec::new();
    let mut arc_index = std::collections::BTreeMap::new();
    for j in 0..ny {
        for i in 0..nx {
            let a = node_of[j * nx + i];
            if a == usize::MAX {
                continue;
            }
            for d in 0..2 {
                if !grid.marked(i, j, d) {
                    continue;
                }
                let boundary = grid.edge(i, j, d).is_some_and(|e| grid.mark(e) == 1);
                let mut p = Grid::step(i, j, d);
                while node_of[p.1 * nx + p.0] == usize::MAX {
                    if !grid.marked(p.0, p.1, d) {
                        return Err(LayoutError::NotConforming(format!(
                            "a layout line ends at ({}, {}) without a node",
                            gx[p.0], gy[p.1]
                        )));
                    }
                    p = Grid::step(p.0, p.1, d);
                }
                let b = node_of[p.1 * nx + p.0];
                arc_index.insert((a, b), arcs.len());
                arcs.push([a, b]);
                arc_on_boundary.push(boundary);
            }
        }
    }
    // Rectangles: each component of cells must fill its bounding box.
    let mut boxes: std::collections::BTreeMap<usize, (usize, usize, usize, usize, usize)> =
        std::collections::BTreeMap::new();
    for c in 0..ncell {
        if !inside[c] {
            continue;
        }
        let r = crate::shell::find(&mut parent, c);
        let (i, j) = (c % (nx - 1), c / (nx - 1));
        let e = boxes.entry(r).or_insert((i, i, j, j, 0));
        e.0 = e.0.min(i);
        e.1 = e.1.max(i);
        e.2 = e.2.min(j);
        e.3 = e.3.max(j);
        e.4 += 1;
    }
    let mut rects = Vec::new();
    for &(i0, i1, j0, j1, count) in boxes.values() {
        if (i1 - i0 + 1) * (j1 - j0 + 1) != count {
            return Err(LayoutError::NotConforming(format!(
                "the layout face at x ∈ [{}, {}], y ∈ [{}, {}] is not a rectangle",
                gx[i0],
                gx[i1 + 1],
                gy[j0],
                gy[j1 + 1]
            )));
        }
        let node = |i: usize, j: usize| node_of[j * nx + i];
        let corners = [
            node(i0, j0),
            node(i1 + 1, j0),
            node(i1 + 1, j1 + 1),
            node(i0, j1 + 1),
        ];
        if corners.contains(&usize::MAX) {
            return Err(LayoutError::NotConforming(format!(
                "a corner of the rectangle at ({}, {}) is not a layout node",
                gx[i0], gy[j0]
            )));
        }
        let side = |a: usize, b: usize| -> Result<(usize, bool), LayoutError> {
            if let Some(&k) = arc_index.get(&(a, b)) {
                Ok((k, false))
            } else if let Some(&k) = arc_index.get(&(b, a)) {
                Ok((k, true))
            } else {
                Err(LayoutError::NotConforming(format!(
                    "the rectangle side from {:?} to {:?} holds a T-junction",
                    nodes[a], nodes[b]
                )))
            }
        };
        let [bl, br, tr, tl] = corners;
        rects.push(LayoutRect {
            corners,
            sides: [side(bl, br)?, side(tl, tr)?, side(bl, tl)?, side(br, tr)?],
        });
    }
    let _ = poly;
    Ok(Layout {
        node_glue: (0..nodes.len()).collect(),
        nodes,
        arcs,
        arc_on_boundary,
        rects,
        separatrices,
        period_x: None,
    })
}

#[cfg(test)]
mod tests;
