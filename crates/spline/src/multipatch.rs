//! A conforming multipatch (spec §9.5): one global control-point array and,
//! per patch, its knot vectors and a grid of indices into that array. Arcs
//! shared by two patches are stored once, so both patches hold the same
//! indices there and the shared boundary is bit-identical (gap 0).

use crate::coons::coons_patch;
use crate::curve::BSplineCurve;
use crate::error::{Result, SplineError};
use crate::knots::KnotVector;
use crate::refine::refine;
use crate::surface::BSplinePatch;
use crate::vec3::{dist, Point3};
use std::collections::BTreeMap;

/// One patch of a multipatch: knots and a row-major (s fastest) grid of
/// global control-point indices.
#[derive(Clone, Debug, PartialEq)]
pub struct PatchGrid {
    /// Knots in s.
    pub knots_s: KnotVector,
    /// Knots in t.
    pub knots_t: KnotVector,
    /// `indices[j * n_s + i]`: the global index of P_ij.
    pub indices: Vec<usize>,
}

impl PatchGrid {
    /// Control points along s.
    pub fn n_s(&self) -> usize {
        self.knots_s.num_control_points()
    }
    /// Control points along t.
    pub fn n_t(&self) -> usize {
        self.knots_t.num_control_points()
    }
    /// The index sequence of side 0 = bottom (+s), 1 = right (+t),
    /// 2 = top (+s), 3 = left (+t).
    pub fn side(&self, side: usize) -> Vec<usize> {
        let (ns, nt) = (self.n_s(), self.n_t());
        match side {
            0 => (0..ns).map(|i| self.indices[i]).collect(),
            1 => (0..nt).map(|j| self.indices[j * ns + ns - 1]).collect(),
            2 => (0..ns).map(|i| self.indices[(nt - 1) * ns + i]).collect(),
            _ => (0..nt).map(|j| self.indices[j * ns]).collect(),
        }
    }
}

/// What [`Multipatch::shared_sides`] found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SharedSides {
    /// Pairs of patch sides along one arc.
    pub pairs: usize,
    /// The largest control-point distance across those pairs: 0 when watertight.
    pub max_gap: f64,
}

/// Control points shared by index between untrimmed tensor-product patches.
#[derive(Clone, Debug, PartialEq)]
pub struct Multipatch {
    points: Vec<Point3>,
    patches: Vec<PatchGrid>,
}

impl Multipatch {
    /// A multipatch from its parts, checked: every grid has the size its
    /// knots need and every index points into `points`.
    pub fn from_parts(points: Vec<Point3>, patches: Vec<PatchGrid>) -> Result<Self> {
        for (k, p) in patches.iter().enumerate() {
            if p.indices.len() != p.n_s() * p.n_t() {
                return Err(SplineError::Multipatch(format!(
                    "patch {k}: {} indices for a {} × {} grid",
                    p.indices.len(),
                    p.n_s(),
                    p.n_t()
                )));
            }
            if let Some(&bad) = p.indices.iter().find(|&&i| i >= points.len()) {
                return Err(SplineError::Multipatch(format!(
                    "patch {k}: index {bad} past the {} control points",
                    points.len()
                )));
            }
        }
        if let Some(i) = points.iter().position(|p| p.iter().any(|x| !x.is_finite())) {
            return Err(SplineError::Multipatch(format!(
                "control point {i} is not finite"
            )));
        }
        Ok(Self { points, patches })
    }

    /// The global control points.
    pub fn points(&self) -> &[Point3] {
        &self.points
    }

    /// The patches' index grids.
    pub fn patches(&self) -> &[PatchGrid] {
        &self.patches
    }

    /// Patch `k` as a stand-alone B-spline patch (an error past the last).
    pub fn patch(&self, k: usize) -> Result<BSplinePatch> {
        let g = self.patches.get(k).ok_or_else(|| {
            SplineError::Multipatch(format!(
                "patch {k} does not exist ({} patches)",
                self.patches.len()
            ))
        })?;
        BSplinePatch::new(
            g.knots_s.clone(),
            g.knots_t.clone(),
            g.indices.iter().map(|&i| self.points[i]).collect(),
        )
    }

    /// The pairs of patch sides that run along one arc, and the largest
    /// distance between their corresponding control points (0 when
    /// watertight). Two sides are taken as one arc when they join the same
    /// end points, have as many control points, and their polygons lie
    /// within a tenth of the side's polygon length of each other (either
    /// direction for a closed arc); sides farther apart between the same two
    /// nodes are distinct arcs (a bigon) and are not compared.
    pub fn shared_sides(&self) -> SharedSides {
        // (first, last index) → (side's polygon, oriented from the smaller end index).
        let mut by_ends: BTreeMap<(usize, usize), Vec<Vec<usize>>> = BTreeMap::new();
        for g in &self.patches {
            for side in 0..4 {
                let mut seq = g.side(side);
                let rev: Vec<usize> = seq.iter().rev().copied().collect();
                if rev < seq {
                    seq = rev;
                }
                by_ends
                    .entry((seq[0], seq[seq.len() - 1]))
                    .or_default()
                    .push(seq);
            }
        }
        let mut out = SharedSides {
            pairs: 0,
            max_gap: 0.0,
        };
        let gap = |a: &[usize], b: &[usize]| -> f64 {
            a.iter()
                .zip(b)
                .map(|(&i, &j)| dist(self.points[i], self.points[j]))
                .fold(0.0, f64::max)
        };
        for sides in by_ends.values() {
            for (m, a) in sides.iter().enumerate() {
                let length: f64 = a
                    .windows(2)
                    .map(|w| dist(self.points[w[0]], self.points[w[1]]))
                    .sum();
                for b in &sides[m + 1..] {
                    if a.len() != b.len() {
                        continue;
                    }
                    let mut g = gap(a, b);
                    if a[0] == a[a.len() - 1] {
                        let rb: Vec<usize> = b.iter().rev().copied().collect();
                        g = g.min(gap(a, &rb));
                    }
                    if g <= 0.1 * length {
                        out.pairs += 1;
                        out.max_gap = out.max_gap.max(g);
                    }
                }
            }
        }
        out
    }

    /// The number of connected components of the control-point graph
    /// (neighbours in some patch grid are joined); a control point no patch
    /// uses is a component of its own. One for a connected model.
    pub fn components(&self) -> usize {
        let mut parent: Vec<usize> = (0..self.points.len()).collect();
        fn find(parent: &mut [usize], mut x: usize) -> usize {
            while parent[x] != x {
                parent[x] = parent[parent[x]];
                x = parent[x];
            }
            x
        }
        let mut join = |a: usize, b: usize| {
            let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
            if ra != rb {
                parent[ra.max(rb)] = ra.min(rb);
            }
        };
        for g in &self.patches {
            let ns = g.n_s();
            for j in 0..g.n_t() {
                for i in 0..ns {
                    let here = g.indices[j * ns + i];
                    if i + 1 < ns {
                        join(here, g.indices[j * ns + i + 1]);
                    }
                    if j + 1 < g.n_t() {
                        join(here, g.indices[(j + 1) * ns + i]);
                    }
                }
            }
        }
        (0..self.points.len())
            .filter(|&i| find(&mut parent, i) == i)
            .count()
    }

    /// Every patch refined by `r` (uniform Boehm insertion), keeping the
    /// sharing: corner points keep their index, and a side shared by patches
    /// gets its refined points once, from the first patch that has it.
    pub fn refined(&self, r: usize) -> Result<Self> {
        let mut points: Vec<Point3> = Vec::new();
        let mut corner_map: BTreeMap<usize, usize> = BTreeMap::new();
        // Canonical old side sequence → new indices in canonical order.
        let mut side_map: BTreeMap<Vec<usize>, Vec<usize>> = BTreeMap::new();
        let mut patches = Vec::with_capacity(self.patches.len());
        for k in 0..self.patches.len() {
            let old = &self.patches[k];
            let fine = refine(&self.patch(k)?, r)?;
            let (ns, nt) = (fine.n_s(), fine.n_t());
            let mut idx = vec![usize::MAX; ns * nt];
            let pos = |i: usize, j: usize| j * ns + i;
            // Sides: positions of the new boundary in side order.
            let side_cells = |side: usize| -> Vec<usize> {
                match side {
                    0 => (0..ns).map(|i| pos(i, 0)).collect(),
                    1 => (0..nt).map(|j| pos(ns - 1, j)).collect(),
                    2 => (0..ns).map(|i| pos(i, nt - 1)).collect(),
                    _ => (0..nt).map(|j| pos(0, j)).collect(),
                }
            };
            // Corners first.
            let corners = [
                (old.indices[0], pos(0, 0)),
                (old.indices[old.n_s() - 1], pos(ns - 1, 0)),
                (old.indices[(old.n_t() - 1) * old.n_s()], pos(0, nt - 1)),
                (old.indices[old.n_t() * old.n_s() - 1], pos(ns - 1, nt - 1)),
            ];
            for (old_i, cell) in corners {
                let new_i = *corner_map.entry(old_i).or_insert_with(|| {
                    points.push(fine.control_points()[cell]);
                    points.len() - 1
                });
                idx[cell] = new_i;
            }
            for side in 0..4 {
                let seq = old.side(side);
                let cells = side_cells(side);
                let flip = seq.iter().rev().lt(seq.iter());
                let canon: Vec<usize> = if flip {
                    seq.iter().rev().copied().collect()
                } else {
                    seq
                };
                let mut cells_c = cells.clone();
                if flip {
                    cells_c.reverse();
                }
                let new = side_map.entry(canon).or_insert_with(|| {
                    cells_c
                        .iter()
                        .enumerate()
                        .map(|(m, &c)| {
                            if m == 0 || m + 1 == cells_c.len() {
                                idx[c]
                            } else {
                                points.push(fine.control_points()[c]);
                                points.len() - 1
                            }
                        })
                        .collect()
                });
                for (&c, &n) in cells_c.iter().zip(new.iter()) {
                    idx[c] = n;
                }
            }
            for (c, slot) in idx.iter_mut().enumerate() {
                if *slot == usize::MAX {
                    points.push(fine.control_points()[c]);
                    *slot = points.len() - 1;
                }
            }
            patches.push(PatchGrid {
                knots_s: fine.knots_s().clone(),
                knots_t: fine.knots_t().clone(),
                indices: idx,
            });
        }
        Self::from_parts(points, patches)
    }
}

/// An arc of a multipatch under construction.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct ArcId(pub usize);

/// An arc used as a patch side, in its stored direction or reversed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ArcUse {
    /// The arc.
    pub arc: ArcId,
    /// True when the side runs from the arc's end to its start.
    pub reversed: bool,
}

impl ArcUse {
    /// The arc in its stored direction.
    pub fn forward(arc: ArcId) -> Self {
        Self {
            arc,
            reversed: false,
        }
    }
    /// The arc reversed.
    pub fn reverse(arc: ArcId) -> Self {
        Self {
            arc,
            reversed: true,
        }
    }
}

/// Builds a [`Multipatch`]: nodes, then arcs between nodes (each arc's
/// control polygon stored once), then patches whose four sides are arcs.
#[derive(Clone, Debug, Default)]
pub struct MultipatchBuilder {
    points: Vec<Point3>,
    arcs: Vec<(BSplineCurve, Vec<usize>)>,
    patches: Vec<PatchGrid>,
}

impl MultipatchBuilder {
    /// An empty builder.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a layout node (a patch corner); returns its control-point index.
    pub fn add_node(&mut self, p: Point3) -> usize {
        self.points.push(p);
        self.points.len() - 1
    }

    /// Adds an arc from node `start` to node `end`: the curve's end control
    /// points are replaced by the nodes' positions (they must agree within
    /// 1e-9 of the curve's size), its interior control points are stored.
    pub fn add_arc(&mut self, start: usize, end: usize, curve: &BSplineCurve) -> Result<ArcId> {
        let n = self.points.len();
        if start >= n || end >= n {
            return Err(SplineError::Multipatch(format!(
                "arc {}: node {} past the {n} points",
                self.arcs.len(),
                start.max(end)
            )));
        }
        let cp = curve.control_points();
        let size = cp
            .iter()
            .map(|p| dist(*p, cp[0]))
            .fold(0.0, f64::max)
            .max(1.0);
        for (which, node, p) in [("start", start, cp[0]), ("end", end, cp[cp.len() - 1])] {
            let gap = dist(p, self.points[node]);
            if !(gap <= 1e-9 * size) {
                return Err(SplineError::Multipatch(format!(
                    "arc {}: its {which} is {gap:.3e} from node {node}",
                    self.arcs.len()
                )));
            }
        }
        let mut idx = vec![start];
        for p in &cp[1..cp.len() - 1] {
            self.points.push(*p);
            idx.push(self.points.len() - 1);
        }
        idx.push(end);
        let snapped: Vec<Point3> = idx.iter().map(|&i| self.points[i]).collect();
        self.arcs
            .push((BSplineCurve::new(curve.knots().clone(), snapped)?, idx));
        Ok(ArcId(self.arcs.len() - 1))
    }

    fn side(&self, u: ArcUse) -> Result<(BSplineCurve, Vec<usize>)> {
        let (c, idx) = self.arcs.get(u.arc.0).ok_or_else(|| {
            SplineError::Multipatch(format!(
                "arc {} does not exist ({} arcs)",
                u.arc.0,
                self.arcs.len()
            ))
        })?;
        Ok(if u.reversed {
            (c.reversed(), idx.iter().rev().copied().collect())
        } else {
            (c.clone(), idx.clone())
        })
    }

    /// Adds a patch with sides bottom (+s), top (+s), left (+t), right (+t)
    /// and interior control points from `interior` — given the Coons patch
    /// of the sides, it returns the net to use (its boundary is ignored:
    /// the arcs' points are used there). Errors when the sides do not meet
    /// at shared corner nodes or `interior` changes the net's size.
    pub fn add_patch_with(
        &mut self,
        sides: [ArcUse; 4],
        interior: impl FnOnce(&BSplinePatch) -> Result<BSplinePatch>,
    ) -> Result<usize> {
        let k = self.patches.len();
        let [(cb, ib), (ct, it), (cl, il), (cr, ir)] = [
            self.side(sides[0])?,
            self.side(sides[1])?,
            self.side(sides[2])?,
            self.side(sides[3])?,
        ];
        let corner_pairs = [
            ("bottom-left", ib[0], il[0]),
            ("bottom-right", ib[ib.len() - 1], ir[0]),
            ("top-left", it[0], il[il.len() - 1]),
            ("top-right", it[it.len() - 1], ir[ir.len() - 1]),
        ];
        for (name, a, b) in corner_pairs {
            if a != b {
                return Err(SplineError::Multipatch(format!(
                    "patch {k}: the {name} corner joins nodes {a} and {b}, not one node"
                )));
            }
        }
        let coons = coons_patch(&cb, &ct, &cl, &cr)?;
        let net = interior(&coons)?;
        let (ns, nt) = (coons.n_s(), coons.n_t());
        if (net.n_s(), net.n_t()) != (ns, nt) {
            return Err(SplineError::Multipatch(format!(
                "patch {k}: the interior net is {} × {}, the sides need {ns} × {nt}",
                net.n_s(),
                net.n_t()
            )));
        }
        let mut indices = vec![0; ns * nt];
        for j in 0..nt {
            for i in 0..ns {
                indices[j * ns + i] = if j == 0 {
                    ib[i]
                } else if j == nt - 1 {
                    it[i]
                } else if i == 0 {
                    il[j]
                } else if i == ns - 1 {
                    ir[j]
                } else {
                    self.points.push(net.control_point(i, j));
                    self.points.len() - 1
                };
            }
        }
        self.patches.push(PatchGrid {
            knots_s: coons.knots_s().clone(),
            knots_t: coons.knots_t().clone(),
            indices,
        });
        Ok(k)
    }

    /// Adds the Coons patch of four arcs (see [`Self::add_patch_with`]).
    pub fn add_coons_patch(&mut self, sides: [ArcUse; 4]) -> Result<usize> {
        self.add_patch_with(sides, |c| Ok(c.clone()))
    }

    /// The finished multipatch.
    pub fn build(self) -> Result<Multipatch> {
        Multipatch::from_parts(self.points, self.patches)
    }
}

#[cfg(test)]
pub(crate) mod tests;
