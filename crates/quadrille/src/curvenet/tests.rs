//! Tests of the layout, dislocation, geometry and sampling stages on paired
//! cycles built by hand.

use std::collections::HashMap;

use geometry::vec3::{cross, dist, dot, norm, scale, sub, Vec3};
use mesh::quality::quad_scaled_jacobian;

use super::cut::{find_cut, merge_smooth_chords};
use super::dislocation::{evaluate_swap, remove_dislocations, swap_candidates};
use super::geometry::{layout_quality, newell};
use super::layout::{build_layout, chords_of, crossing_count, embed, EdgeKind, LayoutError};
use super::{quadrangulate, CycleQuads, PairedCycle};

/// A closed polygon through `corners`, each side cut into `per_side` pieces;
/// returns the points and the index of each corner.
fn polygon(corners: &[Vec3], per_side: usize) -> (Vec<Vec3>, Vec<usize>) {
    let mut pts = Vec::new();
    let mut idx = Vec::new();
    for k in 0..corners.len() {
        let (a, b) = (corners[k], corners[(k + 1) % corners.len()]);
        idx.push(pts.len());
        for t in 0..per_side {
            let f = t as f64 / per_side as f64;
            pts.push([
                a[0] + f * (b[0] - a[0]),
                a[1] + f * (b[1] - a[1]),
                a[2] + f * (b[2] - a[2]),
            ]);
        }
    }
    (pts, idx)
}

fn diameter(points: &[Vec3]) -> f64 {
    let mut d: f64 = 0.0;
    for a in points {
        for b in points {
            d = d.max(dist(*a, *b));
        }
    }
    d
}

fn paired(points: Vec<Vec3>, starts: Vec<usize>, pairs: &[(usize, usize)]) -> PairedCycle {
    let n = starts.len();
    let d = diameter(&points);
    PairedCycle {
        points,
        starts,
        pairs: pairs.to_vec(),
        costs: pairs.iter().map(|&(i, j)| 0.01 * (i + j) as f64).collect(),
        unsplittable: vec![false; n],
        diameter: d,
    }
}

/// A polygon cycle whose segments are its sides.
fn polygon_cycle(corners: &[Vec3], pairs: &[(usize, usize)]) -> PairedCycle {
    let (pts, idx) = polygon(corners, 8);
    paired(pts, idx, pairs)
}

/// Position of `p` along the closed polyline (arc length), if on it.
fn arc_position(points: &[Vec3], p: Vec3, tol: f64) -> Option<f64> {
    let mut acc = 0.0;
    for k in 0..points.len() {
        let (a, b) = (points[k], points[(k + 1) % points.len()]);
        let ab = sub(b, a);
        let l = norm(ab);
        let t = (dot(sub(p, a), ab) / (l * l)).clamp(0.0, 1.0);
        let q = [a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]];
        if dist(p, q) <= tol {
            return Some(acc + t * l);
        }
        acc += l;
    }
    None
}

/// What every case must satisfy; returns (min scaled Jacobian, quads).
fn check_invariants(cycle: &PairedCycle, cq: &CycleQuads) -> (f64, usize) {
    let (min_sj, quads) = check_topology(cycle, cq);
    assert!(min_sj > 0.0, "a quad with scaled Jacobian {min_sj}");
    (min_sj, quads)
}

/// The counts, welding, boundary and orientation checks; returns the
/// minimum scaled Jacobian without judging it.
fn check_topology(cycle: &PairedCycle, cq: &CycleQuads) -> (f64, usize) {
    let chords = chords_of(cycle);
    let crossings = crossing_count(&chords);
    assert_eq!(cq.patches, crossings, "patches = crossings");
    assert_eq!(
        cq.layout.interior_vertices() + chords.len(),
        crossings + 1,
        "V_int = I - k + 1"
    );
    let d = cycle.diameter;
    let tol = 1e-9 * d;
    // Every edge in 2 quads with opposite directions, or in 1 and on the polyline.
    let mut uses: HashMap<(usize, usize), Vec<(usize, usize)>> = HashMap::new();
    for q in &cq.quads {
        for t in 0..4 {
            let (u, v) = (q[t], q[(t + 1) % 4]);
            assert_ne!(u, v, "degenerate quad {q:?}");
            uses.entry((u.min(v), u.max(v))).or_default().push((u, v));
        }
    }
    let total: f64 = (0..cycle.points.len())
        .map(|k| dist(cycle.points[k], cycle.points[(k + 1) % cycle.points.len()]))
        .sum();
    let mut boundary_length = 0.0;
    let mut boundary_edges = 0;
    for (key, dirs) in &uses {
        match dirs.len() {
            2 => assert_ne!(dirs[0], dirs[1], "edge {key:?} used twice in one direction"),
            1 => {
                let (u, v) = dirs[0];
                assert!(
                    cq.boundary[u] && cq.boundary[v],
                    "open edge {key:?} off the boundary"
                );
                let pu = arc_position(&cycle.points, cq.nodes[u], tol)
                    .expect("boundary node on the polyline");
                let pv = arc_position(&cycle.points, cq.nodes[v], tol)
                    .expect("boundary node on the polyline");
                let step = (pv - pu).rem_euclid(total);
                assert!(
                    step < 0.5 * total,
                    "boundary edge {u}->{v} runs against the cycle"
                );
                boundary_length += step;
                boundary_edges += 1;
            }
            k => panic!("edge {key:?} in {k} quads"),
        }
    }
    let expected: usize = (0..cycle.starts.len())
        .map(|s| cq.intervals[chords.iter().position(|&(i, j)| i == s || j == s).unwrap()])
        .sum();
    assert_eq!(
        boundary_edges, expected,
        "boundary edges = the sampled segments"
    );
    // A welded disk: every node used, Euler characteristic 1.
    let mut used = vec![false; cq.nodes.len()];
    for q in &cq.quads {
        for &k in q {
            used[k] = true;
        }
    }
    assert!(used.iter().all(|&u| u), "a node in no quad");
    assert_eq!(
        cq.nodes.len() + cq.quads.len(),
        uses.len() + 1,
        "V - E + F = 1"
    );
    assert_eq!(
        cq.boundary.iter().filter(|&&b| b).count(),
        boundary_edges,
        "boundary nodes = boundary edges"
    );
    assert!(
        (boundary_length - total).abs() < 1e-6 * total,
        "boundary edges cover the polyline once"
    );
    // Node normals from the quads (right-hand rule), then the scaled Jacobian.
    let mut normals = vec![[0.0; 3]; cq.nodes.len()];
    for q in &cq.quads {
        let p = q.map(|k| cq.nodes[k]);
        let n = cross(sub(p[2], p[0]), sub(p[3], p[1]));
        for &k in q {
            normals[k] = [
                normals[k][0] + n[0],
                normals[k][1] + n[1],
                normals[k][2] + n[2],
            ];
        }
    }
    let normals: Vec<Vec3> = normals.iter().map(|n| scale(*n, 1.0 / norm(*n))).collect();
    let mut min_sj = f64::INFINITY;
    for q in &cq.quads {
        let sj = quad_scaled_jacobian(&q.map(|k| cq.nodes[k]), &q.map(|k| normals[k]));
        min_sj = min_sj.min(sj);
    }
    // The quads face the side the cycle's right-hand rule gives.
    let area = newell(&cycle.points);
    let mut sum = [0.0; 3];
    for q in &cq.quads {
        let p = q.map(|k| cq.nodes[k]);
        let n = cross(sub(p[2], p[0]), sub(p[3], p[1]));
        sum = [sum[0] + n[0], sum[1] + n[1], sum[2] + n[2]];
    }
    assert!(dot(sum, area) > 0.0, "quads oriented against the cycle");
    (min_sj, cq.quads.len())
}

/// Planar cycles stay on their plane.
fn check_planar(cycle: &PairedCycle, cq: &CycleQuads) {
    let n = newell(&cycle.points);
    let n = scale(n, 1.0 / norm(n));
    let o = cycle.points[0];
    for p in &cq.nodes {
        assert!(
            dot(sub(*p, o), n).abs() <= 1e-9 * cycle.diameter,
            "node {p:?} off the plane"
        );
    }
}

fn report(name: &str, cycle: &PairedCycle, cq: &CycleQuads, min_sj: f64) {
    eprintln!(
        "| {name} | {} | {} | {} | {} | {} {:?} | {} | {:.3} |",
        cycle.starts.len(),
        cycle.pairs.len(),
        crossing_count(&chords_of(cycle)),
        cq.patches,
        cq.layout.interior_vertices(),
        cq.interior_vertex_valences,
        cq.quads.len(),
        min_sj
    );
}

fn run_planar(name: &str, cycle: &PairedCycle, h: f64) -> CycleQuads {
    let cq = quadrangulate(cycle, h).expect("quadrangulate");
    let (sj, _) = check_invariants(cycle, &cq);
    check_planar(cycle, &cq);
    report(name, cycle, &cq, sj);
    cq
}

fn hexagon(r: f64) -> Vec<Vec3> {
    (0..6)
        .map(|k| {
            let a = std::f64::consts::PI / 3.0 * k as f64;
            [r * a.cos(), r * a.sin(), 0.0]
        })
        .collect()
}

#[test]
fn rectangle_four_segments_is_one_patch() {
    let c = polygon_cycle(
        &[
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [2.0, 1.3, 0.0],
            [0.0, 1.3, 0.0],
        ],
        &[(0, 2), (1, 3)],
    );
    let cq = run_planar("rectangle", &c, 0.25);
    assert_eq!((cq.patches, cq.layout.interior_vertices()), (1, 0));
    // 2 / 0.25 = 8 intervals by 1.3 / 0.25 -> 6.
    assert_eq!(cq.quads.len(), 8 * 6);
}

fn two_by_one() -> PairedCycle {
    let corners = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [2.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    polygon_cycle(&corners, &[(0, 4), (1, 3), (2, 5)])
}

#[test]
fn two_by_one_rectangle_is_two_patches() {
    let c = two_by_one();
    let cq = run_planar("2x1 rectangle", &c, 0.25);
    assert_eq!((cq.patches, cq.layout.interior_vertices()), (2, 0));
    assert_eq!(cq.quads.len(), 2 * 4 * 4);
    // Straight interior edge from (1,0) to (1,1): every node at x = 1 exists.
    let on_mid = cq
        .nodes
        .iter()
        .filter(|p| (p[0] - 1.0).abs() < 1e-12)
        .count();
    assert_eq!(on_mid, 5);
}

#[test]
fn regular_hexagon_has_a_valence_three_centre() {
    let c = polygon_cycle(&hexagon(1.0), &[(0, 3), (1, 4), (2, 5)]);
    let cq = run_planar("hexagon", &c, 0.2);
    assert_eq!(cq.patches, 3);
    assert_eq!(cq.interior_vertex_valences, vec![3]);
    let g = cq.layout.positions[6];
    assert!(norm(g) < 1e-9, "centre at {g:?}");
}

fn split_triangle() -> PairedCycle {
    let s = 3f64.sqrt();
    let (a, b, cc) = ([0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [1.0, s, 0.0]);
    let mid = |p: Vec3, q: Vec3| scale([p[0] + q[0], p[1] + q[1], p[2] + q[2]], 0.5);
    polygon_cycle(
        &[a, mid(a, b), b, mid(b, cc), cc, mid(cc, a)],
        &[(0, 3), (1, 4), (2, 5)],
    )
}

#[test]
fn split_triangle_has_a_valence_three_centre() {
    let c = split_triangle();
    let cq = run_planar("triangle (sides split)", &c, 0.15);
    assert_eq!(cq.patches, 3);
    assert_eq!(cq.interior_vertex_valences, vec![3]);
    let g = cq.layout.positions[6];
    let centroid = [1.0, 3f64.sqrt() / 3.0, 0.0];
    assert!(dist(g, centroid) < 1e-9, "centre at {g:?}");
    // The tie-break keeps one triangle corner (layout vertices 0, 2, 4) per quad.
    for q in &cq.layout.quads {
        assert_eq!(
            q.corners.iter().filter(|&&v| v < 6 && v % 2 == 0).count(),
            1,
            "{q:?}"
        );
    }
}

/// Fig. 11: the order in which the last chord crosses the other two gives
/// two layouts; the embedding keeps the one with the better scaled Jacobian.
#[test]
fn crossing_order_is_chosen_by_scaled_jacobian() {
    let c = split_triangle();
    let chords = chords_of(&c);
    let mut layouts = Vec::new();
    for mask in 0..8u32 {
        let orders: Vec<Vec<usize>> = (0..3)
            .map(|a| {
                let mut o: Vec<usize> = (0..3).filter(|&b| b != a).collect();
                if mask & (1 << a) != 0 {
                    o.reverse();
                }
                o
            })
            .collect();
        if let Ok(l) = build_layout(&c, &chords, &orders) {
            let mut key: Vec<[usize; 4]> = l
                .quads
                .iter()
                .map(|q| {
                    let mut k = q.corners;
                    k.sort();
                    k
                })
                .collect();
            key.sort();
            if !layouts.iter().any(|(k, _)| *k == key) {
                layouts.push((key, layout_quality(&l).0));
            }
        }
    }
    assert_eq!(
        layouts.len(),
        2,
        "two arrangements of three crossing chords"
    );
    let best = layouts
        .iter()
        .map(|l| l.1)
        .fold(f64::NEG_INFINITY, f64::max);
    let worst = layouts.iter().map(|l| l.1).fold(f64::INFINITY, f64::min);
    assert!(best > 0.5 && worst < 0.1, "qualities {best} {worst}");
    let chosen = layout_quality(&embed(&c).unwrap()).0;
    assert!((chosen - best).abs() < 1e-12);
}

fn l_shape() -> PairedCycle {
    let corners = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [2.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
        [1.0, 2.0, 0.0],
        [0.0, 2.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    polygon_cycle(&corners, &[(2, 7), (0, 5), (1, 3), (4, 6)])
}

#[test]
fn l_shape_is_three_patches() {
    let c = l_shape();
    let cq = run_planar("L (Fig. 5 bottom)", &c, 0.2);
    assert_eq!((cq.patches, cq.layout.interior_vertices()), (3, 0));
    assert!(layout_quality(&cq.layout).0 > 0.99, "three unit squares");
}

#[test]
fn house_with_split_bottom_is_two_patches() {
    let corners = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [2.0, 1.0, 0.0],
        [1.3, 1.8, 0.0],
        [0.0, 1.0, 0.0],
    ];
    let c = polygon_cycle(&corners, &[(0, 4), (1, 3), (2, 5)]);
    let cq = run_planar("house", &c, 0.2);
    assert_eq!((cq.patches, cq.layout.interior_vertices()), (2, 0));
}

#[test]
fn saddle_is_one_patch() {
    let corners = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.5],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.5],
    ];
    let c = polygon_cycle(&corners, &[(0, 2), (1, 3)]);
    let cq = quadrangulate(&c, 0.1).unwrap();
    let (sj, _) = check_invariants(&c, &cq);
    report("saddle (non-planar)", &c, &cq, sj);
    assert_eq!((cq.patches, cq.layout.interior_vertices()), (1, 0));
    // Straight sides by arc length: x = u, y = v, and z is the bicubically
    // blended Coons formula with F1 = 1 - F0 (not the bilinear patch).
    let f0 = |t: f64| 1.0 - 3.0 * t * t + 2.0 * t * t * t;
    for p in &cq.nodes {
        let (u, v) = (p[0], p[1]);
        let (a0, a1, b0, b1) = (f0(u), 1.0 - f0(u), f0(v), 1.0 - f0(v));
        let z = 0.5 * (a0 * v + a1 * (1.0 - v) + b0 * u + b1 * (1.0 - u) - a1 * b0 - a0 * b1);
        assert!((p[2] - z).abs() < 1e-12, "{p:?} vs z = {z}");
    }
}

#[test]
fn fillet_stays_on_its_cylinder() {
    let k = 24;
    let arc = |t: f64, z: f64| [t.cos(), t.sin(), z];
    let q = std::f64::consts::FRAC_PI_2;
    let mut pts = Vec::new();
    for i in 0..k {
        pts.push(arc(q * i as f64 / k as f64, 0.0));
    }
    for i in 0..8 {
        pts.push(arc(q, 2.0 * i as f64 / 8.0));
    }
    for i in 0..k {
        pts.push(arc(q * (k - i) as f64 / k as f64, 2.0));
    }
    for i in 0..8 {
        pts.push(arc(0.0, 2.0 - 2.0 * i as f64 / 8.0));
    }
    let c = paired(pts, vec![0, k, k + 8, 2 * k + 8], &[(0, 2), (1, 3)]);
    let arc_len = 2.0 * k as f64 * (q / (2.0 * k as f64)).sin();
    let cq = quadrangulate(&c, arc_len / 12.0 * 1.0001).unwrap();
    assert_eq!(cq.intervals[0], 12);
    let (sj, _) = check_invariants(&c, &cq);
    report("fillet (cylinder)", &c, &cq, sj);
    for p in &cq.nodes {
        let r = (p[0] * p[0] + p[1] * p[1]).sqrt();
        assert!(
            (r - 1.0).abs() <= 1e-6 * c.diameter,
            "node {p:?} at radius {r}"
        );
    }
}

/// Fig. 10: two chord components; the cut is the shortest closed run.
#[test]
fn disconnected_pairing_gives_the_cut() {
    let corners: Vec<Vec3> = (0..8)
        .map(|k| {
            let a = std::f64::consts::PI / 4.0 * k as f64;
            [a.cos(), a.sin(), 0.0]
        })
        .collect();
    let c = polygon_cycle(&corners, &[(1, 3), (2, 4), (5, 7), (0, 6)]);
    let cut = find_cut(&c).unwrap().expect("a cut");
    assert_eq!((cut.from, cut.to), (c.starts[1], c.starts[5]));
    assert_eq!(cut.parts[0].segments, vec![1, 2, 3, 4]);
    assert_eq!(cut.parts[1].segments, vec![5, 6, 7, 0]);
    for part in &cut.parts {
        let pts = &part.loops.outer.points;
        assert!(part.closing_edge_unsplittable);
        assert_eq!(
            part.loops.outer.fixed.len(),
            5,
            "4 segment starts and the cut's far end"
        );
        assert_eq!(*part.loops.outer.fixed.last().unwrap(), pts.len() - 1);
    }
    assert_eq!(cut.parts[0].loops.outer.points[0], c.points[c.starts[1]]);
    assert_eq!(
        *cut.parts[0].loops.outer.points.last().unwrap(),
        c.points[c.starts[5]]
    );
    match quadrangulate(&c, 0.1) {
        Err(LayoutError::Disconnected {
            components: 2,
            from,
            to,
        }) => assert_eq!((from, to), (cut.from, cut.to)),
        other => panic!("expected the cut error, got {other:?}"),
    }
    // A connected pairing has no cut.
    let h = polygon_cycle(&hexagon(1.0), &[(0, 3), (1, 4), (2, 5)]);
    assert!(find_cut(&h).unwrap().is_none());
}

#[test]
fn smooth_neighbouring_chords_merge_unless_kept() {
    let c = two_by_one();
    let merged = merge_smooth_chords(&c, &[], 40f64.to_radians()).unwrap();
    assert_eq!(merged.starts.len(), 4);
    assert_eq!(merged.pairs.len(), 2);
    let cq = quadrangulate(&merged, 0.25).unwrap();
    check_invariants(&merged, &cq);
    assert_eq!(cq.patches, 1);
    let kept = merge_smooth_chords(&c, &[c.starts[1]], 40f64.to_radians()).unwrap();
    assert_eq!(kept, c);
    // Corners (90° turns) never merge.
    let l = l_shape();
    assert_eq!(
        merge_smooth_chords(&l, &[], 40f64.to_radians())
            .unwrap()
            .starts
            .len(),
        8
    );
}

/// Fig. 14: a hexagon flattened at two opposite vertices; the star layout
/// has a bad corner there, the swap to two quads removes the interior vertex.
fn flat_hexagon() -> PairedCycle {
    let corners = [
        [1.0, -1.0, 0.0],
        [1.15, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [-1.0, 1.0, 0.0],
        [-1.15, 0.0, 0.0],
        [-1.0, -1.0, 0.0],
    ];
    polygon_cycle(&corners, &[(0, 3), (1, 4), (2, 5)])
}

#[test]
fn dislocation_swap_when_all_rules_hold() {
    let c = flat_hexagon();
    let cost = |_: usize, _: usize| 0.1;
    let (after, swaps) = remove_dislocations(&c, &cost).unwrap();
    assert_eq!(swaps.len(), 1);
    assert!(swaps[0].valid());
    let cq = run_planar("flattened hexagon after swap", &after, 0.2);
    assert_eq!(cq.layout.interior_vertices(), 0);
    assert_eq!(cq.patches, 2);
    assert!(swaps[0].quality.1 > swaps[0].quality.0);
    eprintln!("swap {:?} -> {:?}, layout SJ {:?}", swaps[0].before, swaps[0].after, swaps[0].quality);
}

#[test]
fn dislocation_refused_when_quality_does_not_improve() {
    let c = split_triangle();
    let cost = |_: usize, _: usize| 0.1;
    let mut connected = 0;
    for (a, b, new) in swap_candidates(&c) {
        let v = evaluate_swap(&c, a, b, new, &cost).unwrap();
        if v.no_new_cycle {
            connected += 1;
            assert!(
                v.costs_acceptable && !v.quality_improves && !v.valid(),
                "{v:?}"
            );
        }
    }
    assert!(connected > 0);
    assert!(remove_dislocations(&c, &cost).unwrap().1.is_empty());
}

#[test]
fn dislocation_refused_when_a_cycle_appears_or_the_graph_splits() {
    let c = flat_hexagon();
    let cost = |_: usize, _: usize| 0.1;
    let cands = swap_candidates(&c);
    // Each crossing on the cycle has one swap that splits the chord graph.
    let split: Vec<_> = cands
        .iter()
        .map(|&(a, b, new)| evaluate_swap(&c, a, b, new, &cost).unwrap())
        .filter(|v| v.cycles.1.is_none())
        .collect();
    assert_eq!(split.len(), 3);
    assert!(split.iter().all(|v| !v.no_new_cycle && !v.valid()));
}

#[test]
fn dislocation_refused_when_a_new_pair_costs_more_than_the_worst() {
    let c = flat_hexagon();
    let old: Vec<(usize, usize)> = c.pairs.clone();
    let cost = move |i: usize, j: usize| {
        if old.contains(&(i.min(j), i.max(j))) {
            0.1
        } else {
            0.3
        }
    };
    let (after, swaps) = remove_dislocations(&c, &cost).unwrap();
    assert!(swaps.is_empty());
    assert_eq!(after.pairs, c.pairs);
    let (a, b, new) = swap_candidates(&c)[0];
    let v = evaluate_swap(&c, a, b, new, &cost).unwrap();
    assert!(!v.costs_acceptable && !v.valid());
}

#[test]
fn bad_input_is_an_error() {
    let c = two_by_one();
    assert!(matches!(
        quadrangulate(&c, 0.0),
        Err(LayoutError::BadSize { .. })
    ));
    assert!(matches!(
        quadrangulate(&c, f64::NAN),
        Err(LayoutError::BadSize { .. })
    ));
    let mut odd = c.clone();
    odd.starts.pop();
    assert!(matches!(
        quadrangulate(&odd, 0.1),
        Err(LayoutError::SegmentCount { segments: 5 })
    ));
    let mut twice = c.clone();
    twice.pairs[0] = (1, 4);
    assert!(matches!(
        quadrangulate(&twice, 0.1),
        Err(LayoutError::BadPairs { .. })
    ));
    let mut nan = c.clone();
    nan.points[3][1] = f64::NAN;
    assert!(matches!(
        quadrangulate(&nan, 0.1),
        Err(LayoutError::NotFinite { index: 3 })
    ));
    let mut unsorted = c;
    unsorted.starts.swap(1, 2);
    assert!(matches!(
        quadrangulate(&unsorted, 0.1),
        Err(LayoutError::BadStart { .. })
    ));
}

#[test]
fn layout_sides_are_segments_or_rungs() {
    let c = l_shape();
    let l = embed(&c).unwrap();
    let boundary = l
        .edges
        .iter()
        .filter(|e| matches!(e.kind, EdgeKind::Boundary(_)))
        .count();
    assert_eq!(boundary, 8);
    assert_eq!(
        l.edges.len() - boundary,
        2,
        "two interior edges between the three squares"
    );
    for q in &l.quads {
        assert_ne!(q.chords[0], q.chords[1]);
        for (t, &(e, fwd)) in q.sides.iter().enumerate() {
            let ends = l.edges[e].ends;
            let (a, b) = if fwd {
                (ends[0], ends[1])
            } else {
                (ends[1], ends[0])
            };
            assert_eq!((a, b), (q.corners[t], q.corners[(t + 1) % 4]));
        }
    }
}

/// Fig. 12's spherical octant (three 90° arcs, each split in two): three
/// curved patches around one valence-3 vertex on the symmetry axis; the
/// interior edges are curved rungs, not straight lines.
#[test]
fn spherical_octant_has_a_centre_on_its_axis() {
    let k = 16;
    let q = std::f64::consts::FRAC_PI_2;
    let mut pts = Vec::new();
    for i in 0..k {
        let t = q * i as f64 / k as f64;
        pts.push([t.cos(), t.sin(), 0.0]);
    }
    for i in 0..k {
        let t = q * i as f64 / k as f64;
        pts.push([0.0, t.cos(), t.sin()]);
    }
    for i in 0..k {
        let t = q * i as f64 / k as f64;
        pts.push([t.sin(), 0.0, t.cos()]);
    }
    let starts = (0..6).map(|s| s * k / 2).collect();
    let c = paired(pts, starts, &[(0, 3), (1, 4), (2, 5)]);
    let cq = quadrangulate(&c, 0.1).unwrap();
    let (sj, _) = check_invariants(&c, &cq);
    report("spherical octant", &c, &cq, sj);
    assert_eq!(cq.patches, 3);
    assert_eq!(cq.interior_vertex_valences, vec![3]);
    let g = cq.layout.positions[6];
    assert!(
        (g[0] - g[1]).abs() < 1e-9 && (g[1] - g[2]).abs() < 1e-9,
        "centre {g:?} off the axis"
    );
    // Three quads around the symmetric centre: its three interior edges are
    // the same curve turned by 120°, and they bulge out of the flat chord
    // from the arc midpoint to the centre.
    let rung_nodes: Vec<Vec3> = cq
        .nodes
        .iter()
        .copied()
        .filter(|p| (p[1] - p[2]).abs() < 1e-12 && p[0] > 1e-9 && p[0] < g[0] - 1e-9)
        .collect();
    assert!(
        !rung_nodes.is_empty(),
        "the rung from (0, .7, .7) to the centre lies in the plane y = z"
    );
    let m = [0.0, 0.5f64.sqrt(), 0.5f64.sqrt()];
    let bulge = rung_nodes
        .iter()
        .map(|p| geometry::vec3::segment_distance(*p, m, g))
        .fold(0.0, f64::max);
    eprintln!("octant rung bulge {bulge}");
    assert!(bulge > 1e-3, "the rung is straight (bulge {bulge})");
}

/// Regular 2k-gons with every chord joining opposite sides: all chords cross
/// pairwise, k(k−1)/2 patches and (k−1)(k−2)/2 interior vertices.
#[test]
fn all_crossing_chords_on_regular_polygons() {
    for k in [4usize, 5, 6] {
        let n = 2 * k;
        let corners: Vec<Vec3> = (0..n)
            .map(|s| {
                let a = 2.0 * std::f64::consts::PI * s as f64 / n as f64;
                [a.cos(), a.sin(), 0.0]
            })
            .collect();
        let pairs: Vec<(usize, usize)> = (0..k).map(|s| (s, s + k)).collect();
        let c = polygon_cycle(&corners, &pairs);
        let cq = run_planar(&format!("regular {n}-gon, opposite sides"), &c, 0.1);
        assert_eq!(cq.patches, k * (k - 1) / 2);
        assert_eq!(cq.layout.interior_vertices(), (k - 1) * (k - 2) / 2);
    }
}

/// Every connected perfect pairing of the sides of regular 8- and 10-gons:
/// the embedding always gives a welded disk with patches = crossings and
/// I − k + 1 interior vertices. (Shapes are not judged: many pairings are
/// absurd on a regular polygon; the count with a scaled Jacobian ≤ 0 is
/// printed.)
#[test]
fn every_connected_pairing_embeds() {
    fn matchings(
        free: &mut Vec<usize>,
        cur: &mut Vec<(usize, usize)>,
        out: &mut Vec<Vec<(usize, usize)>>,
    ) {
        if free.is_empty() {
            out.push(cur.clone());
            return;
        }
        let a = free.remove(0);
        for k in 0..free.len() {
            let b = free.remove(k);
            cur.push((a, b));
            matchings(free, cur, out);
            cur.pop();
            free.insert(k, b);
        }
        free.insert(0, a);
    }
    for n in [8usize, 10] {
        let corners: Vec<Vec3> = (0..n)
            .map(|s| {
                let a = 2.0 * std::f64::consts::PI * s as f64 / n as f64;
                [a.cos(), a.sin(), 0.0]
            })
            .collect();
        let mut all = Vec::new();
        matchings(&mut (0..n).collect(), &mut Vec::new(), &mut all);
        let (mut connected, mut bad_shape) = (0, 0);
        for pairs in &all {
            let c = polygon_cycle(&corners, pairs);
            let comps = super::layout::chord_components(&chords_of(&c));
            if comps.iter().any(|&x| x != 0) {
                assert!(matches!(
                    quadrangulate(&c, 0.3),
                    Err(LayoutError::Disconnected { .. })
                ));
                continue;
            }
            connected += 1;
            let cq = quadrangulate(&c, 0.3).unwrap_or_else(|e| panic!("{pairs:?}: {e}"));
            let (sj, _) = check_topology(&c, &cq);
            check_planar(&c, &cq);
            bad_shape += usize::from(sj <= 0.0);
        }
        eprintln!(
            "{n}-gon: {} pairings, {connected} connected, {bad_shape} with a quad SJ <= 0",
            all.len()
        );
        assert!(connected > 0);
    }
}
