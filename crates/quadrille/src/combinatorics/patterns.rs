//! Quad patterns (paper §6.1, spec §9): coarse quad meshes of a convex disk
//! whose refinements mesh a cavity (or a whole simple CAD face) with only
//! the pattern's irregular vertices.
//!
//! A pattern is given by its coarse quads alone; [`Pattern::from_quads`]
//! derives the rest: the boundary, the **corners** (boundary vertices in one
//! quad), the **sides** between consecutive corners, and the **chords**
//! (classes of coarse edges joined through opposite quad sides). Refining
//! chord `j` into `s_j ≥ 1` layers gives side `i` `Σ_j w_ij s_j` edges, `w_ij`
//! the edges of side `i` in chord `j` (0, 1 or 2). Matching a cavity with side
//! counts `N_i` is the integer system of Eq. 14, `W s = N`, `s ≥ 1`, solved
//! for the solution nearest the balanced one ([`solve`]: fraction-free
//! elimination, then a depth-first search over the free chords, capped).
//!
//! The library ([`library`]) is the spec's proposal (the paper's figure was
//! not available): the grid R1, the triangle T3 and pentagon P5 with one
//! irregular vertex, the corner dipole R3 (the paper's third pattern, with its
//! equations), two corner dipoles R2c, and the U-turn RU.

use std::collections::HashMap;
use std::sync::OnceLock;

/// Leaves of the search tried per orientation before giving up (spec: "a few hundred").
pub const MAX_ATTEMPTS: usize = 300;

/// Why a coarse mesh is not a pattern.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum PatternError {
    /// The quads do not form one disk.
    #[error("pattern {0}: not a disk ({1})")]
    NotADisk(String, String),
    /// A boundary vertex has three or more quads (the pattern is not convex).
    #[error("pattern {0}: boundary vertex {1} is concave")]
    Concave(String, usize),
}

/// A pattern: coarse quads and what is derived from them.
#[derive(Clone, Debug)]
pub struct Pattern {
    /// Short name (R1, T3, …).
    pub name: String,
    /// Coarse quads, counter-clockwise.
    pub quads: Vec<[usize; 4]>,
    /// Coarse vertex positions in the pattern's plane (for initial geometry).
    pub coords: Vec<[f64; 2]>,
    /// Boundary vertices counter-clockwise, starting at the first corner.
    pub boundary: Vec<usize>,
    /// Positions in `boundary` of the corners, in order (side `i` runs from
    /// corner `i` to corner `i + 1`).
    pub corners: Vec<usize>,
    /// Chord of each coarse edge, keyed by its sorted vertex pair.
    pub chord_of_edge: HashMap<(usize, usize), usize>,
    /// Number of chords.
    pub chords: usize,
    /// `w[i][j]`: edges of side `i` in chord `j`.
    pub w: Vec<Vec<u32>>,
    /// Interior vertices with a valence other than 4.
    pub irregular: usize,
}

fn key(a: usize, b: usize) -> (usize, usize) {
    (a.min(b), a.max(b))
}

impl Pattern {
    /// Derives a pattern from coarse quads on vertices `0..coords.len()`.
    pub fn from_quads(
        name: &str,
        coords: Vec<[f64; 2]>,
        quads: Vec<[usize; 4]>,
    ) -> Result<Pattern, PatternError> {
        let err = |why: String| PatternError::NotADisk(name.to_string(), why);
        let nv = coords.len();
        let mut directed = HashMap::new();
        let mut valence = vec![0usize; nv];
        for (qi, q) in quads.iter().enumerate() {
            for k in 0..4 {
                if q[k] >= nv {
                    return Err(err(format!("quad {qi} has vertex {} of {nv}", q[k])));
                }
                valence[q[k]] += 1;
                if directed.insert((q[k], q[(k + 1) % 4]), qi).is_some() {
                    return Err(err(format!("edge {}→{} twice", q[k], q[(k + 1) % 4])));
                }
            }
        }
        let mut next = HashMap::new();
        for &(a, b) in directed.keys() {
            if !directed.contains_key(&(b, a)) && next.insert(a, b).is_some() {
                return Err(err(format!("vertex {a} is pinched")));
            }
        }
        let start = *next
            .keys()
            .filter(|&&v| valence[v] == 1)
            .min()
            .ok_or_else(|| err("no corner".into()))?;
        let mut boundary = vec![start];
        let mut v = next[&start];
        while v != start {
            boundary.push(v);
            v = *next.get(&v).ok_or_else(|| err("open boundary".into()))?;
            if boundary.len() > next.len() {
                return Err(err("boundary loops".into()));
            }
        }
        if boundary.len() != next.len() {
            return Err(err("more than one boundary loop".into()));
        }
        let n_edges = directed.len() - (directed.len() - boundary.len()) / 2;
        if nv as i64 - n_edges as i64 + quads.len() as i64 != 1 {
            return Err(err("Euler characteristic is not 1".into()));
        }
        if let Some(&c) = boundary.iter().find(|&&b| valence[b] >= 3) {
            return Err(PatternError::Concave(name.to_string(), c));
        }
        let corners: Vec<usize> = (0..boundary.len())
            .filter(|&i| valence[boundary[i]] == 1)
            .collect();
        // chords: union the opposite edges of every quad
        let mut edge_ids: HashMap<(usize, usize), usize> = HashMap::new();
        for q in &quads {
            for k in 0..4 {
                let n = edge_ids.len();
                edge_ids.entry(key(q[k], q[(k + 1) % 4])).or_insert(n);
            }
        }
        let mut parent: Vec<usize> = (0..edge_ids.len()).collect();
        fn root(p: &mut [usize], mut i: usize) -> usize {
            while p[i] != i {
                p[i] = p[p[i]];
                i = p[i];
            }
            i
        }
        for q in &quads {
            for k in 0..2 {
                let a = edge_ids[&key(q[k], q[k + 1])];
                let b = edge_ids[&key(q[k + 2], q[(k + 3) % 4])];
                let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
                parent[ra] = rb;
            }
        }
        // chords numbered in order of first appearance along the boundary
        let mut chord_id: HashMap<usize, usize> = HashMap::new();
        let nb = boundary.len();
        for i in 0..nb {
            let r = root(
                &mut parent,
                edge_ids[&key(boundary[i], boundary[(i + 1) % nb])],
            );
            let n = chord_id.len();
            chord_id.entry(r).or_insert(n);
        }
        let chords = chord_id.len();
        let mut chord_of_edge = HashMap::new();
        for (&e, &id) in &edge_ids {
            let r = root(&mut parent, id);
            let Some(&c) = chord_id.get(&r) else {
                return Err(err("a chord never reaches the boundary".into()));
            };
            chord_of_edge.insert(e, c);
        }
        let m = corners.len();
        let mut w = vec![vec![0u32; chords]; m];
        for (i, row) in w.iter_mut().enumerate() {
            let (from, to) = (corners[i], corners[(i + 1) % m]);
            let mut p = from;
            while p != to {
                row[chord_of_edge[&key(boundary[p], boundary[(p + 1) % nb])]] += 1;
                p = (p + 1) % nb;
            }
        }
        let on_boundary: std::collections::HashSet<usize> = boundary.iter().copied().collect();
        let irregular = (0..nv)
            .filter(|v| !on_boundary.contains(v) && valence[*v] != 4)
            .count();
        Ok(Pattern {
            name: name.to_string(),
            quads,
            coords,
            boundary,
            corners,
            chord_of_edge,
            chords,
            w,
            irregular,
        })
    }

    /// Number of sides.
    pub fn sides(&self) -> usize {
        self.corners.len()
    }

    /// Edges on each side for chord subdivisions `s`.
    pub fn side_counts(&self, s: &[u32]) -> Vec<u32> {
        self.w
            .iter()
            .map(|row| row.iter().zip(s).map(|(w, s)| w * s).sum())
            .collect()
    }
}

/// Builds a pattern from quads given by their corner coordinates (shared
/// corners are the same point).
fn from_coordinate_quads(name: &str, quads: &[[[i32; 2]; 4]]) -> Pattern {
    let mut ids: HashMap<[i32; 2], usize> = HashMap::new();
    let mut coords = Vec::new();
    let q: Vec<[usize; 4]> = quads
        .iter()
        .map(|q| {
            q.map(|p| {
                *ids.entry(p).or_insert_with(|| {
                    coords.push([p[0] as f64, p[1] as f64]);
                    coords.len() - 1
                })
            })
        })
        .collect();
    Pattern::from_quads(name, coords, q).expect("library patterns are valid")
}

/// Star of `n` quads around one interior vertex: `n` corners on a regular
/// polygon, side midpoints, the centre (T3 for n = 3, P5 for n = 5).
fn star(name: &str, n: usize) -> Pattern {
    let mut coords = Vec::new();
    for i in 0..n {
        let a = std::f64::consts::TAU * i as f64 / n as f64;
        coords.push([a.cos(), a.sin()]);
    }
    for i in 0..n {
        let (p, q) = (coords[i], coords[(i + 1) % n]);
        coords.push([0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])]);
    }
    coords.push([0.0, 0.0]);
    let c = 2 * n;
    let quads = (0..n).map(|i| [i, n + i, c, n + (i + n - 1) % n]).collect();
    Pattern::from_quads(name, coords, quads).expect("stars are valid")
}

/// The corner dipole R3 in [0,3]² (spec §9.3), optionally mirrored x → −x.
fn r3_quads(mirror: bool) -> Vec<[[i32; 2]; 4]> {
    let q = [
        [[0, 0], [1, 0], [1, 1], [0, 1]],
        [[1, 0], [2, 0], [2, 2], [1, 1]],
        [[0, 1], [1, 1], [2, 2], [0, 2]],
        [[0, 2], [2, 2], [2, 3], [0, 3]],
        [[2, 0], [3, 0], [3, 2], [2, 2]],
        [[2, 2], [3, 2], [3, 3], [2, 3]],
    ];
    if mirror {
        q.iter()
            .map(|q| [q[0], q[3], q[2], q[1]].map(|p| [-p[0], p[1]]))
            .collect()
    } else {
        q.to_vec()
    }
}

/// The pattern library (built once).
pub fn library() -> &'static [Pattern] {
    static LIB: OnceLock<Vec<Pattern>> = OnceLock::new();
    LIB.get_or_init(|| {
        let r1 = from_coordinate_quads("R1", &[[[0, 0], [1, 0], [1, 1], [0, 1]]]);
        let r3 = from_coordinate_quads("R3", &r3_quads(false));
        let mut r2c = r3_quads(false)[..4].to_vec();
        r2c.extend([
            [[4, 0], [5, 0], [5, 1], [4, 1]],
            [[3, 0], [4, 0], [4, 1], [3, 2]],
            [[4, 1], [5, 1], [5, 2], [3, 2]],
            [[3, 2], [5, 2], [5, 3], [3, 3]],
            [[2, 0], [3, 0], [3, 2], [2, 2]],
            [[2, 2], [3, 2], [3, 3], [2, 3]],
        ]);
        let r2c = from_coordinate_quads("R2c", &r2c);
        let mut ru = r3_quads(false);
        ru.extend(r3_quads(true));
        let ru = from_coordinate_quads("RU", &ru);
        vec![r1, star("T3", 3), star("P5", 5), r3, r2c, ru]
    })
}

/// Fraction-free row echelon form of the augmented integer matrix `[W | N]`:
/// rows reduced by their gcd. Returns the nonzero rows and their pivot
/// columns, or `None` when the system is inconsistent.
fn echelon(w: &[Vec<u32>], n: &[u32]) -> Option<(Vec<Vec<i64>>, Vec<usize>)> {
    let c = w.first().map_or(0, Vec::len);
    let mut rows: Vec<Vec<i64>> = w
        .iter()
        .zip(n)
        .map(|(r, &x)| r.iter().map(|&v| v as i64).chain([x as i64]).collect())
        .collect();
    let gcd = |mut a: i64, mut b: i64| {
        a = a.abs();
        b = b.abs();
        while b != 0 {
            (a, b) = (b, a % b);
        }
        a
    };
    let mut pivots = Vec::new();
    let mut r = 0;
    for col in 0..c {
        let Some(p) = (r..rows.len()).find(|&i| rows[i][col] != 0) else {
            continue;
        };
        rows.swap(r, p);
        for i in r + 1..rows.len() {
            if rows[i][col] != 0 {
                let (a, b) = (rows[r][col], rows[i][col]);
                let new: Vec<i64> = (0..=c).map(|k| a * rows[i][k] - b * rows[r][k]).collect();
                let g = new.iter().fold(0, |g, &x| gcd(g, x));
                rows[i] = if g > 1 {
                    new.iter().map(|x| x / g).collect()
                } else {
                    new
                };
            }
        }
        pivots.push(col);
        r += 1;
    }
    // rows below the rank must read 0 = 0
    if rows[r..].iter().any(|row| row[c] != 0) {
        return None;
    }
    rows.truncate(r);
    Some((rows, pivots))
}

/// The balanced chord subdivision: each side spreads its count evenly over
/// its chord slots; each chord averages its slots.
pub fn ideal_subdivision(w: &[Vec<u32>], n: &[u32]) -> Vec<f64> {
    let c = w.first().map_or(0, Vec::len);
    (0..c)
        .map(|j| {
            let (mut num, mut den) = (0.0, 0.0);
            for (row, &ni) in w.iter().zip(n) {
                let wi: u32 = row.iter().sum();
                if row[j] > 0 && wi > 0 {
                    num += row[j] as f64 * ni as f64 / wi as f64;
                    den += row[j] as f64;
                }
            }
            if den > 0.0 {
                num / den
            } else {
                1.0
            }
        })
        .collect()
}

/// Solves Eq. 14, `W s = N` with every `s_j ≥ 1`, for the solution nearest
/// the balanced one (least `Σ (s_j − x_j)²`) among the first `max_attempts`
/// leaves of the search; `None` when none is found.
pub fn solve(w: &[Vec<u32>], n: &[u32], max_attempts: usize) -> Option<Vec<u32>> {
    if w.len() != n.len() || w.is_empty() {
        return None;
    }
    let c = w[0].len();
    let (rows, pivots) = echelon(w, n)?;
    let x = ideal_subdivision(w, n);
    // bound of each chord: it fits in every side it crosses
    let upper: Vec<i64> = (0..c)
        .map(|j| {
            w.iter()
                .zip(n)
                .filter(|(r, _)| r[j] > 0)
                .map(|(r, &ni)| (ni / r[j]) as i64)
                .min()
                .unwrap_or(1)
        })
        .collect();
    let free: Vec<usize> = (0..c).filter(|j| !pivots.contains(j)).collect();
    let mut s = vec![0i64; c];
    let mut best: Option<(f64, Vec<u32>)> = None;
    let mut attempts = 0usize;
    fn back_substitute(rows: &[Vec<i64>], pivots: &[usize], upper: &[i64], s: &mut [i64]) -> bool {
        let c = s.len();
        for (row, &p) in rows.iter().zip(pivots).rev() {
            let rest: i64 = (p + 1..c).map(|k| row[k] * s[k]).sum();
            let num = row[c] - rest;
            if num % row[p] != 0 {
                return false;
            }
            let v = num / row[p];
            if v < 1 || v > upper[p] {
                return false;
            }
            s[p] = v;
        }
        true
    }
    #[allow(clippy::too_many_arguments)]
    fn dfs(
        k: usize,
        free: &[usize],
        rows: &[Vec<i64>],
        pivots: &[usize],
        upper: &[i64],
        x: &[f64],
        s: &mut Vec<i64>,
        best: &mut Option<(f64, Vec<u32>)>,
        attempts: &mut usize,
        max: usize,
    ) {
        if *attempts >= max {
            return;
        }
        if k == free.len() {
            *attempts += 1;
            if back_substitute(rows, pivots, upper, s) {
                let e: f64 = s
                    .iter()
                    .zip(x)
                    .map(|(&v, &xi)| (v as f64 - xi).powi(2))
                    .sum();
                if best.as_ref().is_none_or(|(b, _)| e < *b) {
                    *best = Some((e, s.iter().map(|&v| v as u32).collect()));
                }
            }
            return;
        }
        let j = free[k];
        let centre = (x[j].round() as i64).clamp(1, upper[j].max(1));
        // centre, +1, −1, +2, −2, … within [1, upper]
        let mut order = vec![centre];
        for d in 1.. {
            let (up, down) = (centre + d, centre - d);
            if up > upper[j] && down < 1 {
                break;
            }
            order.extend([up, down].into_iter().filter(|&v| v >= 1 && v <= upper[j]));
        }
        for v in order {
            s[j] = v;
            dfs(k + 1, free, rows, pivots, upper, x, s, best, attempts, max);
            if *attempts >= max {
                return;
            }
        }
    }
    dfs(
        0,
        &free,
        &rows,
        &pivots,
        &upper,
        &x,
        &mut s,
        &mut best,
        &mut attempts,
        max_attempts,
    );
    best.map(|(_, s)| s)
}

/// A pattern matched to a cavity: pattern side `i` lies on cavity side
/// `(shift + i) mod m`, or `(shift − i) mod m` when `mirror`.
#[derive(Clone, Debug, PartialEq)]
pub struct PatternMatch {
    /// Index in the library.
    pub pattern: usize,
    /// Cavity side of pattern side 0.
    pub shift: usize,
    /// The pattern is read clockwise.
    pub mirror: bool,
    /// Chord subdivisions.
    pub subdivisions: Vec<u32>,
}

/// The cavity side counts as pattern side `i` sees them.
fn oriented(sides: &[u32], shift: usize, mirror: bool) -> Vec<u32> {
    let m = sides.len();
    (0..m)
        .map(|i| {
            if mirror {
                sides[(shift + m - i) % m]
            } else {
                sides[(shift + i) % m]
            }
        })
        .collect()
}

/// The best pattern for a convex cavity with side counts `sides` (in
/// counter-clockwise order): over the library patterns with as many sides,
/// every rotation and both directions, the one with the fewest irregular
/// vertices, then the most balanced subdivision; `None` when none matches.
pub fn match_pattern(sides: &[u32]) -> Option<PatternMatch> {
    match_pattern_where(sides, |_| true)
}

/// [`match_pattern`] over the library patterns for which `keep` holds (the
/// cavity remeshing asks for the grid only, the rectangles, or the
/// triangle / pentagon with one irregular vertex).
pub fn match_pattern_where(sides: &[u32], keep: impl Fn(&Pattern) -> bool) -> Option<PatternMatch> {
    let mut best: Option<((usize, f64), PatternMatch)> = None;
    for (pi, p) in library()
        .iter()
        .enumerate()
        .filter(|(_, p)| p.sides() == sides.len() && keep(p))
    {
        for mirror in [false, true] {
            for shift in 0..sides.len() {
                let n = oriented(sides, shift, mirror);
                let Some(s) = solve(&p.w, &n, MAX_ATTEMPTS) else {
                    continue;
                };
                let x = ideal_subdivision(&p.w, &n);
                let e: f64 = s
                    .iter()
                    .zip(&x)
                    .map(|(&v, &xi)| (v as f64 - xi).powi(2))
                    .sum();
                let key = (p.irregular, e);
                if best
                    .as_ref()
                    .is_none_or(|(k, _)| key.0 < k.0 || (key.0 == k.0 && key.1 < k.1))
                {
                    best = Some((
                        key,
                        PatternMatch {
                            pattern: pi,
                            shift,
                            mirror,
                            subdivisions: s,
                        },
                    ));
                }
            }
        }
    }
    best.map(|(_, m)| m)
}

/// A refined pattern mesh.
#[derive(Clone, Debug)]
pub struct RefinedPattern {
    /// Vertex positions in the pattern's plane (bilinear in each coarse quad).
    pub coords: Vec<[f64; 2]>,
    /// Quads, counter-clockwise.
    pub quads: Vec<[u32; 4]>,
    /// Boundary vertices counter-clockwise from the pattern's first corner.
    pub boundary: Vec<u32>,
    /// Positions in `boundary` of the pattern's corners (kept for the tests,
    /// which check that refinement keeps them; the cavities find corners
    /// from the pattern itself).
    #[cfg(test)]
    pub corners: Vec<usize>,
}

/// Refines `pattern` with chord subdivisions `s` (one per chord, each ≥ 1).
pub fn refine(pattern: &Pattern, s: &[u32]) -> RefinedPattern {
    let mut coords: Vec<[f64; 2]> = pattern.coords.clone();
    let lerp =
        |a: [f64; 2], b: [f64; 2], t: f64| [a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t];
    // points of each coarse edge from its lower to its higher vertex
    let mut edge_points: HashMap<(usize, usize), Vec<u32>> = HashMap::new();
    let mut points = |a: usize, b: usize, coords: &mut Vec<[f64; 2]>| -> Vec<u32> {
        let k = key(a, b);
        let n = s[pattern.chord_of_edge[&k]].max(1) as usize;
        let pts = edge_points.entry(k).or_insert_with(|| {
            let mut v = vec![k.0 as u32];
            for i in 1..n {
                coords.push(lerp(
                    pattern.coords[k.0],
                    pattern.coords[k.1],
                    i as f64 / n as f64,
                ));
                v.push((coords.len() - 1) as u32);
            }
            v.push(k.1 as u32);
            v
        });
        if a == k.0 {
            pts.clone()
        } else {
            pts.iter().rev().copied().collect()
        }
    };
    let mut quads = Vec::new();
    for q in &pattern.quads {
        let bottom = points(q[0], q[1], &mut coords);
        let right = points(q[1], q[2], &mut coords);
        let top = points(q[3], q[2], &mut coords);
        let left = points(q[0], q[3], &mut coords);
        let (na, nb) = (bottom.len() - 1, left.len() - 1);
        let c = q.map(|v| pattern.coords[v]);
        let mut grid = vec![vec![0u32; nb + 1]; na + 1];
        for i in 0..=na {
            for j in 0..=nb {
                grid[i][j] = if j == 0 {
                    bottom[i]
                } else if j == nb {
                    top[i]
                } else if i == 0 {
                    left[j]
                } else if i == na {
                    right[j]
                } else {
                    let (u, v) = (i as f64 / na as f64, j as f64 / nb as f64);
                    coords.push(lerp(lerp(c[0], c[1], u), lerp(c[3], c[2], u), v));
                    (coords.len() - 1) as u32
                };
            }
        }
        for i in 0..na {
            for j in 0..nb {
                quads.push([
                    grid[i][j],
                    grid[i + 1][j],
                    grid[i + 1][j + 1],
                    grid[i][j + 1],
                ]);
            }
        }
    }
    let nb = pattern.boundary.len();
    let mut boundary = Vec::new();
    #[cfg(test)]
    let mut corners = Vec::new();
    for i in 0..nb {
        #[cfg(test)]
        if pattern.corners.contains(&i) {
            corners.push(boundary.len());
        }
        let pts = points(
            pattern.boundary[i],
            pattern.boundary[(i + 1) % nb],
            &mut coords,
        );
        boundary.extend_from_slice(&pts[..pts.len() - 1]);
    }
    RefinedPattern {
        coords,
        quads,
        boundary,
        #[cfg(test)]
        corners,
    }
}

#[cfg(test)]
mod tests;
