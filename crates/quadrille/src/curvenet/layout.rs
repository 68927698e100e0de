//! Quad connectivity of one paired cycle (spec §5.1–§5.3): the poly-chords of
//! the pairs, their crossings, the cut of a disconnected chord graph (Fig. 10),
//! the merge of smooth neighbouring chords, and the incremental embedding of
//! the chords as shortest paths in the cell graph, ties broken by the scaled
//! Jacobian of the straight-edge quads (Fig. 11).
//!
//! The chords are embedded as a pseudo-line arrangement in the disk: each
//! chord runs from the midpoint of its first segment to the midpoint of its
//! second, and crosses exactly the chords whose segments interleave with its
//! own, once each. The arrangement is kept combinatorially: per chord, the
//! order in which it crosses the others. Its faces are the layout vertices
//! (the face at each segment start is that boundary vertex, the faces away
//! from the boundary are the interior vertices), its crossings the quads.

use std::collections::{HashMap, VecDeque};

use super::cut::find_cut;
use super::geometry::{layout_quality, place_interior_vertices};
use super::PairedCycle;

/// Why a paired cycle has no quad layout: one line naming the place and the
/// numbers.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum LayoutError {
    /// Segments must come in an even count of at least 2.
    #[error("curvenet layout: {segments} segments, need an even count of at least 4")]
    SegmentCount { segments: usize },
    /// A segment start is out of range or the starts do not ascend.
    #[error("curvenet layout: segment start {index} ({value}) is out of the {points} points or not ascending")]
    BadStart {
        index: usize,
        value: usize,
        points: usize,
    },
    /// The pairs do not cover every segment exactly once.
    #[error("curvenet layout: segment {segment} is in {times} pairs, need exactly 1")]
    BadPairs { segment: usize, times: usize },
    /// A point is NaN or infinite.
    #[error("curvenet layout: point {index} is not finite")]
    NotFinite { index: usize },
    /// The chord graph is disconnected: the cycle must be cut (see [`find_cut`]).
    #[error("curvenet layout: the chord graph has {components} components; cut the cycle between segment starts {from} and {to} and redo each part")]
    Disconnected {
        components: usize,
        from: usize,
        to: usize,
    },
    /// A chord could not be embedded crossing exactly its interleaving chords.
    #[error("curvenet layout: chord {chord} crosses {found} chords on its shortest path, expected {expected}")]
    Embedding {
        chord: usize,
        found: usize,
        expected: usize,
    },
    /// The arrangement's faces do not form a quad layout.
    #[error(
        "curvenet layout: the arrangement has {found} faces at the boundary, expected {expected}"
    )]
    Arrangement { found: usize, expected: usize },
    /// Eq. (1) for the interior vertices has a singular matrix.
    #[error(
        "curvenet geometry: Eq. (1) for {vertices} interior vertices is singular at row {row}"
    )]
    Singular { vertices: usize, row: usize },
    /// Some sampled quads are inverted: by the element geometry, or facing
    /// away from the cycle.
    #[error("curvenet layout: {quads} of {of} quads are inverted (element geometry, or facing away from the cycle)")]
    Folded { quads: usize, of: usize },
    /// The target edge length is not a positive finite number.
    #[error("curvenet sampling: edge length h = {h} must be positive and finite")]
    BadSize { h: f64 },
}

/// A poly-chord: the two segments it joins, first < second.
pub type Chord = (usize, usize);

/// True when chords `a` and `b` cross: their segments interleave along the
/// cycle.
pub fn chords_cross(a: Chord, b: Chord) -> bool {
    let (i, j) = a;
    let (k, l) = b;
    (i < k && k < j && j < l) || (k < i && i < l && l < j)
}

/// Number of crossing chord pairs.
pub fn crossing_count(chords: &[Chord]) -> usize {
    let mut n = 0;
    for a in 0..chords.len() {
        for b in a + 1..chords.len() {
            n += usize::from(chords_cross(chords[a], chords[b]));
        }
    }
    n
}

/// The connected component of each chord in the crossing graph, numbered in
/// order of their first chord.
pub fn chord_components(chords: &[Chord]) -> Vec<usize> {
    let mut comp = vec![usize::MAX; chords.len()];
    let mut next = 0;
    for s in 0..chords.len() {
        if comp[s] != usize::MAX {
            continue;
        }
        comp[s] = next;
        let mut queue = VecDeque::from([s]);
        while let Some(a) = queue.pop_front() {
            for b in 0..chords.len() {
                if comp[b] == usize::MAX && chords_cross(chords[a], chords[b]) {
                    comp[b] = next;
                    queue.push_back(b);
                }
            }
        }
        next += 1;
    }
    comp
}

/// Checks the cycle's counts, ranges and pairs.
pub fn validate(cycle: &PairedCycle) -> Result<(), LayoutError> {
    let n = cycle.starts.len();
    if n < 4 || n % 2 == 1 {
        return Err(LayoutError::SegmentCount { segments: n });
    }
    for (i, &s) in cycle.starts.iter().enumerate() {
        if s >= cycle.points.len() || (i > 0 && s <= cycle.starts[i - 1]) {
            return Err(LayoutError::BadStart {
                index: i,
                value: s,
                points: cycle.points.len(),
            });
        }
    }
    for (i, p) in cycle.points.iter().enumerate() {
        if p.iter().any(|c| !c.is_finite()) {
            return Err(LayoutError::NotFinite { index: i });
        }
    }
    let mut times = vec![0usize; n];
    for &(i, j) in &cycle.pairs {
        for s in [i, j] {
            if s >= n {
                return Err(LayoutError::BadPairs {
                    segment: s,
                    times: 0,
                });
            }
            times[s] += 1;
        }
        if i == j {
            times[i] += 1;
        }
    }
    if let Some(s) = (0..n).find(|&s| times[s] != 1) {
        return Err(LayoutError::BadPairs {
            segment: s,
            times: times[s],
        });
    }
    Ok(())
}

/// The chords of the cycle's pairs, each ordered first < second.
pub fn chords_of(cycle: &PairedCycle) -> Vec<Chord> {
    cycle
        .pairs
        .iter()
        .map(|&(i, j)| (i.min(j), i.max(j)))
        .collect()
}

/// Which side of the layout an edge is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EdgeKind {
    /// A boundary segment, by index: the edge runs from its start to its end.
    Boundary(usize),
    /// An interior edge (a rung of the chord that crosses it).
    Interior,
}

/// A side of the coarse layout.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LayoutEdge {
    /// Its two layout vertices; a boundary edge runs along the cycle.
    pub ends: [usize; 2],
    /// Boundary segment or interior edge.
    pub kind: EdgeKind,
    /// The chord that crosses it (it is a rung of that chord).
    pub chord: usize,
}

/// A quad of the coarse layout: the crossing of two chords.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LayoutQuad {
    /// Its corners, counter-clockwise seen with the surface on the left of
    /// the boundary.
    pub corners: [usize; 4],
    /// Side `k` joins corner `k` to corner `k + 1`: the edge and whether the
    /// edge's `ends` run in that direction.
    pub sides: [(usize, bool); 4],
    /// The chord crossing sides 0 and 2, then the chord crossing sides 1 and 3.
    pub chords: [usize; 2],
}

/// One piece of a chord between two consecutive crossings (or a crossing and
/// a boundary end), seen as the layout edge it crosses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChordPiece {
    /// The layout edge it crosses.
    pub edge: usize,
    /// The layout vertex on the chord's left (walking from its first segment).
    pub left: usize,
    /// The layout vertex on its right.
    pub right: usize,
}

/// The coarse quad layout of one paired cycle (spec §5.3).
#[derive(Clone, Debug, PartialEq)]
pub struct Layout {
    /// The chords (segment pairs).
    pub chords: Vec<Chord>,
    /// Per chord, the chords it crosses in order from its first segment.
    pub crossing_order: Vec<Vec<usize>>,
    /// Number of boundary layout vertices: vertex `s < n` is the start of
    /// segment `s`; the others are interior.
    pub boundary_vertices: usize,
    /// Position of each layout vertex (interior ones by Eq. (1)).
    pub positions: Vec<[f64; 3]>,
    /// The layout sides.
    pub edges: Vec<LayoutEdge>,
    /// The quads, one per chord crossing.
    pub quads: Vec<LayoutQuad>,
    /// Per chord, its pieces in order: piece 0 crosses its first segment,
    /// the last its second segment, the others the chord's interior rungs.
    pub pieces: Vec<Vec<ChordPiece>>,
}

impl Layout {
    /// Number of interior layout vertices.
    pub fn interior_vertices(&self) -> usize {
        self.positions.len() - self.boundary_vertices
    }

    /// The number of quads at each interior vertex, in vertex order.
    pub fn interior_valences(&self) -> Vec<usize> {
        let mut val = vec![0; self.positions.len()];
        for q in &self.quads {
            for &c in &q.corners {
                val[c] += 1;
            }
        }
        val[self.boundary_vertices..].to_vec()
    }
}

/// The planar arrangement of the embedded chords, as a rotation system.
struct Arrangement {
    /// Counter-clockwise neighbours of each node. Nodes: segment starts
    /// `0..n`, chord ends (segment midpoints) `n..2n`, crossings after.
    rot: Vec<Vec<usize>>,
    /// First half-edge id of each node.
    he_base: Vec<usize>,
    /// The face left of each half-edge.
    face: Vec<usize>,
    faces: usize,
}

impl Arrangement {
    fn build(n: usize, chords: &[Chord], orders: &[Vec<usize>], embedded: &[bool]) -> Arrangement {
        let mut cross_node: HashMap<(usize, usize), usize> = HashMap::new();
        let mut next = 2 * n;
        for (a, order) in orders.iter().enumerate() {
            for &b in order {
                let key = (a.min(b), a.max(b));
                if let std::collections::hash_map::Entry::Vacant(e) = cross_node.entry(key) {
                    e.insert(next);
                    next += 1;
                }
            }
        }
        let mut rot = vec![Vec::new(); next];
        for s in 0..n {
            rot[s] = vec![n + s, n + (s + n - 1) % n];
            rot[n + s] = vec![(s + 1) % n, s];
        }
        let nodes_of = |a: usize| -> Vec<usize> {
            let mut v = vec![n + chords[a].0];
            v.extend(orders[a].iter().map(|&b| cross_node[&(a.min(b), a.max(b))]));
            v.push(n + chords[a].1);
            v
        };
        let mut along: Vec<Vec<usize>> = vec![Vec::new(); chords.len()];
        for a in 0..chords.len() {
            if embedded[a] {
                along[a] = nodes_of(a);
                let v = &along[a];
                rot[v[0]] = vec![(chords[a].0 + 1) % n, v[1], chords[a].0];
                let m = v.len() - 1;
                rot[v[m]] = vec![(chords[a].1 + 1) % n, v[m - 1], chords[a].1];
            }
        }
        for a in 0..chords.len() {
            if !embedded[a] {
                continue;
            }
            for (t, &b) in orders[a].iter().enumerate() {
                if a > b {
                    continue;
                }
                let x = along[a][t + 1];
                let (ap, an) = (along[a][t], along[a][t + 2]);
                let tb = orders[b].iter().position(|&c| c == a).unwrap_or(0);
                let (bp, bn) = (along[b][tb], along[b][tb + 2]);
                let (i, j) = chords[a];
                let right_to_left = i < chords[b].0 && chords[b].0 < j;
                rot[x] = if right_to_left {
                    vec![an, bn, ap, bp]
                } else {
                    vec![an, bp, ap, bn]
                };
            }
        }
        let mut he_base = vec![0; next + 1];
        for u in 0..next {
            he_base[u + 1] = he_base[u] + rot[u].len();
        }
        let total = he_base[next];
        let mut face = vec![usize::MAX; total];
        let mut faces = 0;
        for start in 0..total {
            if face[start] != usize::MAX {
                continue;
            }
            let mut he = start;
            while face[he] == usize::MAX {
                face[he] = faces;
                let u = he_base.partition_point(|&b| b <= he) - 1;
                let v = rot[u][he - he_base[u]];
                let pos = rot[v].iter().position(|&w| w == u).unwrap_or(0);
                let deg = rot[v].len();
                let k = (pos + deg - 1) % deg;
                he = he_base[v] + k;
            }
            faces += 1;
        }
        Arrangement {
            rot,
            he_base,
            face,
            faces,
        }
    }

    /// The face left of the half-edge u → v.
    fn left(&self, u: usize, v: usize) -> usize {
        let k = self.rot[u].iter().position(|&w| w == v).unwrap_or(0);
        self.face[self.he_base[u] + k]
    }

    /// The nodes along embedded chord `a`.
    fn along(&self, n: usize, chords: &[Chord], a: usize) -> Vec<usize> {
        let mut v = vec![n + chords[a].0];
        let mut prev = n + chords[a].0;
        let mut cur = self.rot[prev][1];
        while cur != n + chords[a].1 {
            v.push(cur);
            // A crossing: go straight on (the neighbour two places round).
            let pos = self.rot[cur].iter().position(|&w| w == prev).unwrap_or(0);
            let nxt = self.rot[cur][(pos + 2) % 4];
            prev = cur;
            cur = nxt;
        }
        v.push(cur);
        v
    }
}

/// Builds the layout of fully embedded chords with straight-edge geometry.
pub(crate) fn build_layout(
    cycle: &PairedCycle,
    chords: &[Chord],
    orders: &[Vec<usize>],
) -> Result<Layout, LayoutError> {
    let n = cycle.starts.len();
    let arr = Arrangement::build(n, chords, orders, &vec![true; chords.len()]);
    let outer = arr.left(n, 0);
    let mut vertex_of = vec![usize::MAX; arr.faces];
    for s in 0..n {
        let f = arr.left(s, n + s);
        if vertex_of[f] != usize::MAX || f == outer {
            return Err(LayoutError::Arrangement {
                found: s,
                expected: n,
            });
        }
        vertex_of[f] = s;
    }
    let mut count = n;
    for (f, v) in vertex_of.iter_mut().enumerate() {
        if f != outer && *v == usize::MAX {
            *v = count;
            count += 1;
        }
    }
    // Faces of a connected pseudo-line arrangement: n at the boundary and
    // crossings − chords + 1 inside.
    let expected = (n + crossing_count(chords) + 1).saturating_sub(chords.len());
    if count != expected {
        return Err(LayoutError::Arrangement {
            found: count,
            expected,
        });
    }
    let mut positions: Vec<[f64; 3]> = cycle.starts.iter().map(|&p| cycle.points[p]).collect();
    positions.resize(count, [0.0; 3]);
    let mut edges = Vec::new();
    let mut pieces = Vec::new();
    let mut edge_of: HashMap<(usize, usize), usize> = HashMap::new();
    for (a, &(i, j)) in chords.iter().enumerate() {
        let along = arr.along(n, chords, a);
        let mut ps = Vec::new();
        for t in 0..along.len() - 1 {
            let (u, v) = (along[t], along[t + 1]);
            let left = vertex_of[arr.left(u, v)];
            let right = vertex_of[arr.left(v, u)];
            let (ends, kind) = if t == 0 {
                ([left, right], EdgeKind::Boundary(i))
            } else if t + 2 == along.len() {
                ([right, left], EdgeKind::Boundary(j))
            } else {
                ([left, right], EdgeKind::Interior)
            };
            if let EdgeKind::Boundary(s) = kind {
                if ends != [s, (s + 1) % n] {
                    return Err(LayoutError::Arrangement {
                        found: ends[0],
                        expected: s,
                    });
                }
            }
            edge_of.insert((u.min(v), u.max(v)), edges.len());
            ps.push(ChordPiece {
                edge: edges.len(),
                left,
                right,
            });
            edges.push(LayoutEdge {
                ends,
                kind,
                chord: a,
            });
        }
        pieces.push(ps);
    }
    let mut quads = Vec::new();
    for x in 2 * n..arr.rot.len() {
        let r = &arr.rot[x];
        let corners = [0, 1, 2, 3].map(|t| vertex_of[arr.left(x, r[t])]);
        if (0..4).any(|a| (a + 1..4).any(|b| corners[a] == corners[b])) {
            return Err(LayoutError::Arrangement {
                found: 3,
                expected: 4,
            });
        }
        let sides = [0, 1, 2, 3].map(|t| {
            let e = edge_of[&(x.min(r[(t + 1) % 4]), x.max(r[(t + 1) % 4]))];
            (e, edges[e].ends[0] == corners[t])
        });
        quads.push(LayoutQuad {
            corners,
            sides,
            chords: [edges[sides[0].0].chord, edges[sides[1].0].chord],
        });
    }
    let mut layout = Layout {
        chords: chords.to_vec(),
        crossing_order: orders.to_vec(),
        boundary_vertices: n,
        positions,
        edges,
        quads,
        pieces,
    };
    layout.positions = place_interior_vertices(&layout, cycle.diameter)?;
    Ok(layout)
}

/// Most shortest paths tried per chord.
const MAX_PATHS: usize = 32;

/// The shortest paths in the cell graph for chord `c`, each as the list of
/// (chord, piece) crossed.
fn shortest_paths(
    n: usize,
    chords: &[Chord],
    orders: &[Vec<usize>],
    embedded: &[bool],
    c: usize,
) -> Vec<Vec<(usize, usize)>> {
    let arr = Arrangement::build(n, chords, orders, embedded);
    let mut adj: Vec<Vec<(usize, usize, usize)>> = vec![Vec::new(); arr.faces];
    for (a, _) in embedded.iter().enumerate().filter(|(_, &e)| e) {
        let along = arr.along(n, chords, a);
        for t in 0..along.len() - 1 {
            let f = arr.left(along[t], along[t + 1]);
            let g = arr.left(along[t + 1], along[t]);
            adj[f].push((g, a, t));
            adj[g].push((f, a, t));
        }
    }
    let (i, j) = chords[c];
    let start = arr.left(n + i, (i + 1) % n);
    let end = arr.left(n + j, (j + 1) % n);
    let mut dist = vec![usize::MAX; arr.faces];
    dist[end] = 0;
    let mut queue = VecDeque::from([end]);
    while let Some(f) = queue.pop_front() {
        for &(g, _, _) in &adj[f] {
            if dist[g] == usize::MAX {
                dist[g] = dist[f] + 1;
                queue.push_back(g);
            }
        }
    }
    let mut out = Vec::new();
    let mut stack = vec![(start, Vec::new())];
    while let Some((f, path)) = stack.pop() {
        if out.len() >= MAX_PATHS {
            break;
        }
        if f == end {
            out.push(path);
            continue;
        }
        for &(g, a, t) in adj[f].iter().rev() {
            if dist[g] != usize::MAX && dist[g] + 1 == dist[f] {
                let mut p: Vec<(usize, usize)> = path.clone();
                p.push((a, t));
                stack.push((g, p));
            }
        }
    }
    out
}

/// Inserts chord `c` along `path` into the crossing orders.
fn insert_path(orders: &mut [Vec<usize>], c: usize, path: &[(usize, usize)]) {
    for &(a, t) in path {
        orders[a].insert(t, c);
    }
    orders[c] = path.iter().map(|&(a, _)| a).collect();
}

/// Embeds chords `sequence[k..]` by their first shortest paths.
fn complete_first(
    n: usize,
    chords: &[Chord],
    orders: &mut [Vec<usize>],
    embedded: &mut [bool],
    sequence: &[usize],
) -> Result<(), LayoutError> {
    for &c in sequence {
        let paths = shortest_paths(n, chords, orders, embedded, c);
        let path = checked_first(&paths, chords, embedded, c)?;
        insert_path(orders, c, &path);
        embedded[c] = true;
    }
    Ok(())
}

fn expected_crossings(chords: &[Chord], embedded: &[bool], c: usize) -> usize {
    (0..chords.len())
        .filter(|&a| embedded[a] && chords_cross(chords[a], chords[c]))
        .count()
}

fn checked_first(
    paths: &[Vec<(usize, usize)>],
    chords: &[Chord],
    embedded: &[bool],
    c: usize,
) -> Result<Vec<(usize, usize)>, LayoutError> {
    let expected = expected_crossings(chords, embedded, c);
    match paths.first() {
        Some(p) if p.len() == expected => Ok(p.clone()),
        Some(p) => Err(LayoutError::Embedding {
            chord: c,
            found: p.len(),
            expected,
        }),
        None => Err(LayoutError::Embedding {
            chord: c,
            found: usize::MAX,
            expected,
        }),
    }
}

/// The coarse layout of a connected paired cycle (spec §5.2): chords embedded
/// one at a time in ascending cost order, each along a shortest path in the
/// cell graph; among equal-length paths the one whose completed layout has
/// the best straight-edge quads (minimum scaled Jacobian, then mean).
pub fn embed(cycle: &PairedCycle) -> Result<Layout, LayoutError> {
    validate(cycle)?;
    let chords = chords_of(cycle);
    let comps = chord_components(&chords);
    if comps.iter().any(|&c| c != 0) {
        let cut = find_cut(cycle)?;
        let (from, to) = cut.map_or((0, 0), |c| (c.from, c.to));
        return Err(LayoutError::Disconnected {
            components: comps.iter().max().map_or(0, |m| m + 1),
            from,
            to,
        });
    }
    let mut sequence: Vec<usize> = (0..chords.len()).collect();
    sequence.sort_by(|&a, &b| {
        let ca = cycle.costs.get(a).copied().unwrap_or(0.0);
        let cb = cycle.costs.get(b).copied().unwrap_or(0.0);
        ca.total_cmp(&cb).then(a.cmp(&b))
    });
    embed_in_order(cycle, &chords, &sequence)
}

/// [`embed`] with a given insertion order (Fig. 11 tests both orders).
pub fn embed_in_order(
    cycle: &PairedCycle,
    chords: &[Chord],
    sequence: &[usize],
) -> Result<Layout, LayoutError> {
    let n = cycle.starts.len();
    let mut orders = vec![Vec::new(); chords.len()];
    let mut embedded = vec![false; chords.len()];
    for (k, &c) in sequence.iter().enumerate() {
        let paths = shortest_paths(n, chords, &orders, &embedded, c);
        let first = checked_first(&paths, chords, &embedded, c)?;
        let mut best = first;
        if paths.len() > 1 {
            let mut best_score = (f64::NEG_INFINITY, f64::NEG_INFINITY);
            for p in &paths {
                if p.len() != best.len() {
                    continue;
                }
                let mut o = orders.clone();
                let mut e = embedded.clone();
                insert_path(&mut o, c, p);
                e[c] = true;
                complete_first(n, chords, &mut o, &mut e, &sequence[k + 1..])?;
                let score = match build_layout(cycle, chords, &o) {
                    Ok(l) => layout_quality(&l),
                    Err(_) => (f64::NEG_INFINITY, f64::NEG_INFINITY),
                };
                if score.0 > best_score.0 + 1e-12
                    || (score.0 > best_score.0 - 1e-12 && score.1 > best_score.1 + 1e-12)
                {
                    best_score = score;
                    best = p.clone();
                }
            }
        }
        insert_path(&mut orders, c, &best);
        embedded[c] = true;
    }
    build_layout(cycle, chords, &orders)
}
