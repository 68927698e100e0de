use super::*;
use std::collections::{BTreeMap, HashMap};

/// Side `s` of quad `q`, as an index `4q + s`.
type Side = usize;
const FREE: usize = usize::MAX;

fn find(p: &mut [usize], mut i: usize) -> usize {
    while p[i] != i {
        p[i] = p[p[i]];
        i = p[i];
    }
    i
}

/// An independent count: every connected way to glue `f` quads side to side
/// (orientation-reversing), kept when it is a disk quadrangulation with the
/// table's valence limits and no double edge, deduplicated by a canonical
/// form rooted at a quad side (not at the boundary, as the enumerator's is).
/// Returns the number of classes per (b, n_int).
fn brute_force_counts(f: usize) -> BTreeMap<(usize, usize), usize> {
    let mut partner = vec![None::<usize>; 4 * f];
    let mut classes: HashMap<(usize, usize), HashSet<Vec<usize>>> = HashMap::new();
    fn dfs(
        f: usize,
        used: usize,
        partner: &mut Vec<Option<usize>>,
        classes: &mut HashMap<(usize, usize), HashSet<Vec<usize>>>,
    ) {
        let Some(s) = (0..4 * used).find(|&s| partner[s].is_none()) else {
            if used == f {
                if let Some(key) = evaluate(f, partner) {
                    classes
                        .entry(key)
                        .or_default()
                        .insert(side_rooted_canonical(f, partner));
                }
            }
            return;
        };
        // a boundary side
        partner[s] = Some(FREE);
        dfs(f, used, partner, classes);
        // glued to another open side of the quads in use
        for t in s + 1..4 * used {
            if partner[t].is_none() {
                partner[s] = Some(t);
                partner[t] = Some(s);
                dfs(f, used, partner, classes);
                partner[t] = None;
            }
        }
        // glued to side 0 of a new quad
        if used < f {
            let t = 4 * used;
            partner[s] = Some(t);
            partner[t] = Some(s);
            dfs(f, used + 1, partner, classes);
            partner[t] = None;
        }
        partner[s] = None;
    }
    dfs(f, 1, &mut partner, &mut classes);
    classes.into_iter().map(|(k, v)| (k, v.len())).collect()
}

/// (b, n_int) of a glued complex when it is a valid disk for the table.
fn evaluate(f: usize, partner: &[Option<usize>]) -> Option<(usize, usize)> {
    let n = 4 * f; // corners: corner (q, s) = 4q + s starts side (q, s)
    let mut p: Vec<usize> = (0..n).collect();
    let side_end = |s: Side| 4 * (s / 4) + (s % 4 + 1) % 4;
    for s in 0..n {
        let t = partner[s].expect("complete gluing");
        if t != FREE && s < t {
            // orientation-reversing: start of s ~ end of t, end of s ~ start of t
            let (a, b) = (find(&mut p, s), find(&mut p, side_end(t)));
            p[a] = b;
            let (a, b) = (find(&mut p, side_end(s)), find(&mut p, t));
            p[a] = b;
        }
    }
    let v: Vec<usize> = (0..n).map(|c| find(&mut p, c)).collect();
    // quads with four distinct vertices
    for q in 0..f {
        let c = [v[4 * q], v[4 * q + 1], v[4 * q + 2], v[4 * q + 3]];
        if (0..4).any(|i| (i + 1..4).any(|j| c[i] == c[j])) {
            return None;
        }
    }
    // edges: one per glued pair or free side; no two with the same ends
    let mut edges = HashSet::new();
    let mut n_edges = 0;
    for s in 0..n {
        let t = partner[s].unwrap();
        if t == FREE || s < t {
            n_edges += 1;
            let (a, b) = (v[s], v[side_end(s)]);
            if !edges.insert((a.min(b), a.max(b))) {
                return None;
            }
        }
    }
    let mut verts: Vec<usize> = v.clone();
    verts.sort_unstable();
    verts.dedup();
    // Euler characteristic of a disk (connected, orientable, so one boundary, genus 0)
    if verts.len() as i64 - n_edges as i64 + f as i64 != 1 {
        return None;
    }
    let mut on_boundary = HashSet::new();
    for s in 0..n {
        if partner[s] == Some(FREE) {
            on_boundary.insert(v[s]);
            on_boundary.insert(v[side_end(s)]);
        }
    }
    let mut quads_at: HashMap<usize, usize> = HashMap::new();
    for &x in &v {
        *quads_at.entry(x).or_default() += 1;
    }
    for (x, &k) in &quads_at {
        let ok = if on_boundary.contains(x) {
            (1..=3).contains(&k)
        } else {
            (3..=5).contains(&k)
        };
        if !ok {
            return None;
        }
    }
    Some((on_boundary.len(), verts.len() - on_boundary.len()))
}

/// Smallest gluing code over every quad side as root and both orientations.
fn side_rooted_canonical(f: usize, partner: &[Option<usize>]) -> Vec<usize> {
    let mut best: Option<Vec<usize>> = None;
    for root in 0..4 * f {
        for mirror in [false, true] {
            // local side j of a quad entered through original side e
            let map = |e: usize, j: usize| {
                if mirror {
                    4 * (e / 4) + (e % 4 + 4 - j) % 4
                } else {
                    4 * (e / 4) + (e % 4 + j) % 4
                }
            };
            let mut order: Vec<usize> = vec![root]; // entry side per visited quad
            let mut index = vec![usize::MAX; f];
            index[root / 4] = 0;
            let mut code = Vec::new();
            let mut i = 0;
            while i < order.len() {
                let e = order[i];
                for j in 0..4 {
                    let s = map(e, j);
                    let t = partner[s].unwrap();
                    if t == FREE {
                        code.push(usize::MAX);
                        continue;
                    }
                    if index[t / 4] == usize::MAX {
                        index[t / 4] = order.len();
                        order.push(t);
                    }
                    let te = order[index[t / 4]];
                    let local = (0..4).find(|&k| map(te, k) == t).unwrap();
                    code.push(4 * index[t / 4] + local);
                }
                i += 1;
            }
            if best.as_ref().is_none_or(|b| code < *b) {
                best = Some(code);
            }
        }
    }
    best.unwrap()
}

fn table_counts(disks: &[DiskQuadrangulation]) -> BTreeMap<(usize, usize), usize> {
    let mut m = BTreeMap::new();
    for d in disks {
        *m.entry((d.boundary, d.interior)).or_default() += 1;
    }
    m
}

#[test]
fn small_counts_match_the_hand_counts() {
    let c = table_counts(&enumerate(8, 1));
    assert_eq!(c.get(&(4, 0)), Some(&1), "one quad");
    assert_eq!(c.get(&(6, 0)), Some(&1), "two quads in a row");
    assert_eq!(
        c.get(&(6, 1)),
        Some(&1),
        "three quads around a valence-3 vertex"
    );
    assert_eq!(c.get(&(8, 0)), Some(&2), "1×3 strip and L-tromino");
    assert_eq!(
        c.get(&(8, 1)),
        Some(&2),
        "2×2 grid and the three-quad star with a quad on one side"
    );
    assert_eq!(
        c.get(&(4, 1)),
        None,
        "no disk of 4 boundary vertices has one interior vertex of valence 3–5"
    );
}

#[test]
fn counts_match_an_independent_brute_force() {
    // every class with at most 4 quads: F = (b − 2)/2 + n_int ≤ 4
    let shelled = table_counts(&enumerate(10, 3));
    let mut brute = BTreeMap::new();
    for f in 1..=4 {
        brute.extend(brute_force_counts(f));
    }
    let small: BTreeMap<_, _> = shelled
        .into_iter()
        .filter(|((b, i), _)| (b - 2) / 2 + i <= 4)
        .collect();
    assert_eq!(small, brute);
    assert!(brute.values().sum::<usize>() >= 8, "{brute:?}");
}

/// Every stored disk is a valid disk quadrangulation in canonical labelling.
#[test]
fn table_entries_are_valid_disks() {
    let t = table();
    assert!(t.len() > 100, "{} entries", t.len());
    let mut codes = HashSet::new();
    for d in t {
        let (b, ni) = (d.boundary, d.interior);
        assert!(b % 2 == 0 && (4..=TABLE_MAX_BOUNDARY).contains(&b) && ni <= TABLE_MAX_INTERIOR);
        assert_eq!(
            d.quads.len(),
            (b - 2) / 2 + ni,
            "Euler: F = (b − 2)/2 + n_int"
        );
        let val = d.valences();
        assert_eq!(d.boundary_quads, val[..b]);
        assert!(val[..b].iter().all(|&k| (1..=3).contains(&k)));
        assert!(val[b..].iter().all(|&k| (3..=5).contains(&k)));
        // directed edges: each at most once; the boundary cycle 0 → 1 → … is on the quads' left
        let mut directed = HashSet::new();
        for q in &d.quads {
            let mut s = q.to_vec();
            s.sort_unstable();
            s.dedup();
            assert_eq!(s.len(), 4, "a quad repeats a vertex: {q:?}");
            for k in 0..4 {
                assert!(
                    directed.insert((q[k], q[(k + 1) % 4])),
                    "edge used twice in one direction: {d:?}"
                );
            }
        }
        for (a, c) in directed.iter().copied() {
            let on_boundary = (a as usize) < b && (c as usize) == (a as usize + 1) % b;
            assert_eq!(
                !directed.contains(&(c, a)),
                on_boundary,
                "edge {a}→{c} of {d:?}"
            );
        }
        // (two edges joining the same vertices would show as a boundary edge
        // whose reverse is present: refused by the check above)
        assert!(codes.insert(d.quads.clone()), "duplicate entry {d:?}");
    }
    // the table holds every size it promises
    let c = table_counts(t);
    for b in (4..=TABLE_MAX_BOUNDARY).step_by(2) {
        assert!(
            c.keys().any(|k| k.0 == b),
            "no disk with {b} boundary vertices"
        );
    }
}

/// The canonical form does not depend on how the disk was built or labelled.
#[test]
fn canonical_form_ignores_labels_rotation_and_mirror() {
    // a 2 × 2 grid built two ways
    let mut a = Disk::single_quad();
    for (at, k) in [(0, 1), (3, 1), (2, 2)] {
        a = a.attach(at, k).expect("attach");
    }
    assert_eq!(a.quads.len(), 4);
    assert_eq!(a.interior, 1);
    let mut b = Disk::single_quad();
    for (at, k) in [(2, 1), (1, 1), (3, 2)] {
        b = b.attach(at, k).expect("attach");
    }
    assert_eq!(a.canonical(), b.canonical());
    // relabel vertices by a permutation and rotate the boundary start
    let nv = a.quads_at.len() as u16;
    let perm: Vec<u16> = (0..nv).map(|i| (i * 5 + 3) % nv).collect();
    let mut c = a.clone();
    c.quads = a
        .quads
        .iter()
        .map(|q| q.map(|v| perm[v as usize]))
        .collect();
    c.boundary = a.boundary.iter().map(|&v| perm[v as usize]).collect();
    c.boundary.rotate_left(3);
    c.quads_at = vec![0; nv as usize];
    for (i, &k) in a.quads_at.iter().enumerate() {
        c.quads_at[perm[i] as usize] = k;
    }
    assert_eq!(a.canonical(), c.canonical());
    // the mirror image: reversed quads and boundary
    let mut m = a.clone();
    m.quads = a.quads.iter().map(|q| [q[0], q[3], q[2], q[1]]).collect();
    m.boundary.reverse();
    assert_eq!(a.canonical(), m.canonical());
    // a different disk has a different code
    // (after the first attach the boundary is 0, 4, 5, 1, 2, 3: edge 4 → 5 is
    // opposite the shared edge, 0 → 4 and 5 → 1 are beside it)
    let strip = Disk::single_quad()
        .attach(0, 1)
        .unwrap()
        .attach(1, 1)
        .unwrap();
    let l1 = Disk::single_quad()
        .attach(0, 1)
        .unwrap()
        .attach(0, 1)
        .unwrap();
    let l2 = Disk::single_quad()
        .attach(0, 1)
        .unwrap()
        .attach(2, 1)
        .unwrap();
    assert_ne!(strip.canonical(), l1.canonical());
    assert_eq!(
        l1.canonical(),
        l2.canonical(),
        "the two L-trominoes are mirror images"
    );
}

#[test]
fn closing_a_square_is_refused() {
    let d = Disk::single_quad();
    assert!(
        d.attach(0, 3).is_none(),
        "b = 4: the path ends are adjacent"
    );
    let two = d.attach(0, 1).unwrap();
    assert_eq!(two.boundary.len(), 6);
    // three edges whose ends are joined by an edge of the other quad
    let blocked = (0..6).filter(|&at| two.attach(at, 3).is_none()).count();
    assert_eq!(
        blocked, 6,
        "every 3-edge path of a domino has adjacent ends or a vertex above valence limits"
    );
}

/// The cavity of an interior valence-6 vertex in an otherwise regular mesh:
/// 12 boundary vertices, alternately an edge neighbour (2 quads inside, 2
/// outside) and a diagonal one (1 inside, 3 outside). Its own I_r is
/// (4 − 6)² = 4; the best table disk does better and has no vertex of
/// valence ≥ 6, and its quads close the cavity exactly.
#[test]
fn a_valence_six_vertex_is_replaced_by_a_more_regular_disk() {
    let cavity: Vec<CavityVertex> = (0..12)
        .map(|j| CavityVertex {
            ideal: 4,
            outside: if j % 2 == 0 { 2 } else { 3 },
            allowed: (3, 5),
        })
        .collect();
    let t = table();
    let p = best_replacement(t, &cavity).expect("a replacement");
    assert!(
        p.irregularity < 4,
        "I_r {} not below the valence-6 star's 4",
        p.irregularity
    );
    let d = &t[p.disk];
    assert_eq!(d.boundary, 12);
    // recompute I_r and the valences from the placed quads
    let boundary: Vec<u32> = (0..12).collect();
    let interior: Vec<u32> = (100..100 + d.interior as u32).collect();
    let quads = p.quads(d, &boundary, &interior);
    let mut inside = std::collections::HashMap::<u32, u32>::new();
    for q in &quads {
        for &v in q {
            *inside.entry(v).or_default() += 1;
        }
    }
    let mut ir = 0;
    for (j, c) in cavity.iter().enumerate() {
        let total = inside[&(j as u32)] + c.outside as u32;
        assert!(
            (3..=5).contains(&total),
            "boundary vertex {j}: valence {total}"
        );
        ir += (4 - total as i32).pow(2);
    }
    for v in &interior {
        let k = inside[v] as i32;
        assert!((3..=5).contains(&k));
        ir += (4 - k).pow(2);
    }
    assert_eq!(ir as u32, p.irregularity);
    // the boundary cycle 0 → 1 → … → 11 is on the quads' left (counter-clockwise)
    let directed: HashSet<(u32, u32)> = quads
        .iter()
        .flat_map(|q| (0..4).map(move |k| (q[k], q[(k + 1) % 4])))
        .collect();
    for j in 0..12u32 {
        assert!(
            directed.contains(&(j, (j + 1) % 12)),
            "cavity edge {j} not closed"
        );
    }
}

/// Ranges are respected: a curve vertex on the cavity (total valence exactly
/// 2) rules out every placement that gives it anything else; an impossible
/// cavity gets no replacement.
#[test]
fn allowed_ranges_are_respected() {
    // the cavity of a single quad with one side on a curve
    let mut cavity = vec![
        CavityVertex {
            ideal: 4,
            outside: 3,
            allowed: (3, 5)
        };
        4
    ];
    cavity[0] = CavityVertex {
        ideal: 2,
        outside: 1,
        allowed: (2, 2),
    };
    cavity[1] = CavityVertex {
        ideal: 2,
        outside: 1,
        allowed: (2, 2),
    };
    let p = best_replacement(table(), &cavity).expect("the quad itself fits");
    assert_eq!(
        table()[p.disk].interior,
        0,
        "the quad itself (the 4-interior-vertex split scores 4)"
    );
    assert_eq!(p.irregularity, 0);
    cavity[0].allowed = (3, 3);
    cavity[1].allowed = (3, 3);
    cavity[2].allowed = (6, 6);
    assert!(best_replacement(table(), &cavity).is_none());
}

/// The stored table is exactly what the enumerator produces, and reads back.
#[test]
fn the_stored_table_is_the_enumerators_output() {
    let fresh = enumerate(TABLE_MAX_BOUNDARY, TABLE_MAX_INTERIOR);
    assert_eq!(
        STORED_TABLE,
        format_table(&fresh),
        "rewrite it: cargo run --release -p quadrille --example disk_table -- --write"
    );
    assert_eq!(parse_table(STORED_TABLE).unwrap(), fresh);
    assert_eq!(table(), &fresh[..]);
    assert!(
        parse_table("6 1 0 1 2").is_none(),
        "a short line is refused"
    );
    assert!(
        parse_table("4 0 0 1 2 9").is_none(),
        "a vertex out of range is refused"
    );
}
