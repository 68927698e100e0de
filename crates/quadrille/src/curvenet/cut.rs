//! The cut of a disconnected chord graph (spec §5.1, Fig. 10) and the merge
//! of smooth neighbouring chords (spec §5.1).

use super::layout::{chord_components, chords_of, validate, LayoutError};
use super::{CycleLoops, LoopPolyline, PairedCycle};

/// One part of a cut cycle: a closed polyline whose closing edge (from its
/// last point back to its first) is the cut.
#[derive(Clone, Debug, PartialEq)]
pub struct CutPart {
    /// The part as a cycle to segment and pair again; the segment starts of
    /// the original cycle that fall in this part are its fixed points, and so
    /// are the two ends of the cut (its first and last point).
    pub loops: CycleLoops,
    /// The original segments this part keeps, in order.
    pub segments: Vec<usize>,
    /// The closing edge is the cut: it must stay one segment (unsplittable).
    pub closing_edge_unsplittable: bool,
}

/// The cut of a disconnected chord graph (Fig. 10): a straight segment between
/// two segment starts that separates chord components.
#[derive(Clone, Debug, PartialEq)]
pub struct CycleCut {
    /// Point index (into the cycle's points) of the cut's first end: the start
    /// of the first segment of part 0.
    pub from: usize,
    /// Point index of the cut's other end: the start of the first segment of
    /// part 1.
    pub to: usize,
    /// The two sub-cycles: segments `from..to` closed by the cut, then the rest.
    pub parts: [CutPart; 2],
}

/// The cut of a disconnected chord graph, or `None` when it is connected: the
/// shortest run of consecutive segments that no pair leaves, closed by the
/// straight cut between its end points.
pub fn find_cut(cycle: &PairedCycle) -> Result<Option<CycleCut>, LayoutError> {
    validate(cycle)?;
    let chords = chords_of(cycle);
    let comps = chord_components(&chords);
    if comps.iter().all(|&c| c == 0) {
        return Ok(None);
    }
    let n = cycle.starts.len();
    let mut mate = vec![0; n];
    for &(i, j) in &chords {
        mate[i] = j;
        mate[j] = i;
    }
    // The shortest closed run [a, a + len) (cyclic), ties by the lowest a.
    for len in 2..n - 1 {
        for a in 0..n {
            let inside = |s: usize| (s + n - a) % n < len;
            if (0..len).all(|t| inside(mate[(a + t) % n])) {
                let b = (a + len) % n;
                let parts = [cut_part(cycle, a, b), cut_part(cycle, b, a)];
                return Ok(Some(CycleCut {
                    from: cycle.starts[a],
                    to: cycle.starts[b],
                    parts,
                }));
            }
        }
    }
    // Components never interleave, so a closed run exists; unreachable for
    // valid input, reported rather than panicking.
    Err(LayoutError::Disconnected {
        components: comps.iter().max().map_or(0, |m| m + 1),
        from: 0,
        to: 0,
    })
}

/// The sub-cycle of segments `a, a+1, …` up to (not including) `b`, cyclic.
fn cut_part(cycle: &PairedCycle, a: usize, b: usize) -> CutPart {
    let n = cycle.starts.len();
    let np = cycle.points.len();
    let (pa, pb) = (cycle.starts[a], cycle.starts[b]);
    let count = (pb + np - pa) % np;
    let points: Vec<[f64; 3]> = (0..=count).map(|t| cycle.points[(pa + t) % np]).collect();
    let mut segments = Vec::new();
    let mut fixed = Vec::new();
    let mut s = a;
    while s != b {
        segments.push(s);
        fixed.push((cycle.starts[s] + np - pa) % np);
        s = (s + 1) % n;
    }
    fixed.push(count);
    CutPart {
        loops: CycleLoops {
            outer: LoopPolyline { points, fixed },
            holes: Vec::new(),
            surface: None,
        },
        segments,
        closing_edge_unsplittable: true,
    }
}

/// Merges neighbouring parallel chords (i, j) and (i+1, j−1) when both
/// junctions between their segments are smooth (spec §5.1): the polyline
/// turns by less than `max_turn` radians there and the junction is not in
/// `keep` (corners, T-junctions, junctions the caller must keep). Segments
/// merge with their neighbour; costs of merged pairs are the larger of the two.
pub fn merge_smooth_chords(
    cycle: &PairedCycle,
    keep: &[usize],
    max_turn: f64,
) -> Result<PairedCycle, LayoutError> {
    validate(cycle)?;
    let mut cur = cycle.clone();
    'outer: loop {
        let n = cur.starts.len();
        if n <= 4 {
            return Ok(cur);
        }
        let chords = chords_of(&cur);
        let mut mate = vec![0; n];
        for &(i, j) in &chords {
            mate[i] = j;
            mate[j] = i;
        }
        for i in 0..n {
            let j = mate[i];
            let (i1, j1) = ((i + 1) % n, (j + n - 1) % n);
            if mate[i1] != j1 || i1 == j || i1 == j1 {
                continue;
            }
            let (p, q) = (cur.starts[i1], cur.starts[j]);
            if keep.contains(&p) || keep.contains(&q) {
                continue;
            }
            if turn_angle(&cur.points, p) >= max_turn || turn_angle(&cur.points, q) >= max_turn {
                continue;
            }
            if cur.unsplittable[i]
                || cur.unsplittable[i1]
                || cur.unsplittable[j]
                || cur.unsplittable[j1]
            {
                continue;
            }
            // Drop the starts of segments i1 and j: i absorbs i1, j1 absorbs j.
            let drop = [i1, j];
            let old_index: Vec<usize> = (0..n).filter(|s| !drop.contains(s)).collect();
            let new_of = |s: usize| -> usize {
                let owner = if s == i1 {
                    i
                } else if s == j {
                    j1
                } else {
                    s
                };
                old_index.iter().position(|&o| o == owner).unwrap_or(0)
            };
            let mut pairs = Vec::new();
            let mut costs = Vec::new();
            for (k, &(a, b)) in cur.pairs.iter().enumerate() {
                let (a, b) = (a.min(b), a.max(b));
                if (a, b) == (i.min(j), i.max(j)) {
                    let other = cur
                        .pairs
                        .iter()
                        .position(|&(x, y)| (x.min(y), x.max(y)) == (i1.min(j1), i1.max(j1)));
                    let c = other.map_or(cur.costs[k], |o| cur.costs[k].max(cur.costs[o]));
                    let (x, y) = (new_of(i), new_of(j1));
                    pairs.push((x.min(y), x.max(y)));
                    costs.push(c);
                } else if (a, b) != (i1.min(j1), i1.max(j1)) {
                    let (x, y) = (new_of(a), new_of(b));
                    pairs.push((x.min(y), x.max(y)));
                    costs.push(cur.costs.get(k).copied().unwrap_or(0.0));
                }
            }
            let starts: Vec<usize> = old_index.iter().map(|&o| cur.starts[o]).collect();
            let unsplittable: Vec<bool> = old_index.iter().map(|&o| cur.unsplittable[o]).collect();
            // Keep the starts ascending: rotate when segment 0's start dropped.
            let mut order: Vec<usize> = (0..starts.len()).collect();
            order.sort_by_key(|&k| starts[k]);
            let rank: Vec<usize> = {
                let mut r = vec![0; order.len()];
                for (pos, &k) in order.iter().enumerate() {
                    r[k] = pos;
                }
                r
            };
            let unsplittable_v: Vec<bool> = unsplittable_vec(&unsplittable, &order);
            cur = PairedCycle {
                points: cur.points.clone(),
                starts: order.iter().map(|&k| starts[k]).collect(),
                pairs: pairs
                    .iter()
                    .map(|&(x, y)| (rank[x].min(rank[y]), rank[x].max(rank[y])))
                    .collect(),
                costs,
                unsplittable: unsplittable_v,
                diameter: cur.diameter,
            };
            continue 'outer;
        }
        return Ok(cur);
    }
}

fn unsplittable_vec(v: &[bool], order: &[usize]) -> Vec<bool> {
    order.iter().map(|&k| v[k]).collect()
}

/// The turning angle of the closed polyline at point `p`, in radians.
pub fn turn_angle(points: &[[f64; 3]], p: usize) -> f64 {
    use geometry::vec3::{dot, norm, sub};
    let n = points.len();
    let a = sub(points[p], points[(p + n - 1) % n]);
    let b = sub(points[(p + 1) % n], points[p]);
    let d = norm(a) * norm(b);
    if d <= 0.0 {
        return std::f64::consts::PI;
    }
    (dot(a, b) / d).clamp(-1.0, 1.0).acos()
}
