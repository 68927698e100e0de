//! Every operation on hand-built stars (spec §5.1–5.5, §14 "unit templates").
//!
//! Each test draws the quads an operation touches by hand (the *core*), wraps
//! them in a ring of quads ([`Patch::ring`]) so that every core vertex is
//! interior with the valence the template needs, the ring's outer loop being
//! the fixed boundary, and applies the operation(s) through [`apply_checked`],
//! which checks, at every step:
//! - (a)/(e) the valences [`effect`] predicts are exactly those
//!   [`apply_topology`] and [`apply`] produce (no other vertex changes), and
//!   each test compares the prediction with the numbers Eq. 1, Eq. 2 or the
//!   split formula give by hand (written in the comments);
//! - (b) ΔV and ΔQ (swap 0/0, collapse −1/−1, split +1/+1), hence V − Q unchanged;
//! - (c) every boundary vertex bit-identical and the boundary edges unchanged;
//! - (d) every quad with 4 distinct live vertices, every edge used at most
//!   once per direction (consistent orientation).
//!
//! The stars are geometrically valid for the base window (5°, 175°), and each
//! star test also runs its operation(s) through the driver's guarded path
//! ([`Regularizer::try_sequence`]: placement, repair, validity, rollback),
//! which must accept them with the same topology.
//!
//! The double split needs a vertex V outside the first ring: its star gets a
//! second ring ([`Patch::ring_regular`], then [`Patch::relaxed`]). Operations
//! that involve boundary vertices themselves (a swap of an edge ending on the
//! boundary, a collapse into a boundary vertex, a split through a boundary
//! link) use small grids, whose outer-loop vertices are the fixed ones.
//!
//! Paper templates: swap (Eq. 1, Fig. 3), collapse (Eq. 2, Fig. 3), split
//! (Figs. 3–4), translation (Fig. 5), swap-split (Fig. 7), swap-collapse,
//! double collapse (Fig. 9), double split (Fig. 10), double swap (Fig. 11,
//! adjacent quads).

use super::*;
use crate::fixtures::face_quads::Patch;
use crate::topology::regularize::ops::hexagon;

/// The valences of `vs`.
fn vals(fq: &FaceQuads, vs: &[u32]) -> Vec<u32> {
    vs.iter().map(|&v| fq.valence(v)).collect()
}

/// Builds the star: `core` ringed so that core vertex `v` gets `want[v]` edges.
fn ringed(core: Patch, want: &[u32]) -> FaceQuads {
    let n = core.pts.len();
    assert_eq!(want.len(), n);
    let fq = core.ring(|v| want[v as usize]).build();
    assert_eq!(
        vals(&fq, &(0..n as u32).collect::<Vec<_>>()),
        want,
        "the star has the requested valences"
    );
    assert_valid(&fq);
    fq
}

/// Every quad of `fq` is geometrically valid for the base window (5°, 175°).
fn assert_valid(fq: &FaceQuads) {
    let m = plane(8.0);
    let bad: Vec<_> = fq
        .live_quads()
        .filter(|&q| !quad_valid(fq, &m.faces[0], q, AngleWindow::BASE))
        .map(|q| (q, fq.quads[q as usize], quad_angles(fq, &m.faces[0], q)))
        .collect();
    assert!(
        bad.is_empty(),
        "invalid quads (id, vertices, angles and signs): {bad:?}"
    );
}

/// Runs `ops` on a copy of `start` through the driver's guarded path
/// (placement, local repair, validity check, rollback on failure): the
/// sequence must be accepted and end, every quad valid, with the same
/// topology as the bookkeeping run `after`.
fn assert_accepted(start: &FaceQuads, ops: &[Op], after: &FaceQuads) {
    let m = plane(8.0);
    let mut g = start.clone();
    let mut r = Regularizer::new(&m.faces[0], &mut g);
    assert!(
        r.try_sequence(ops),
        "{ops:?} rejected by the geometric guard"
    );
    drop(r);
    assert_valid(&g);
    assert_eq!((&g.quads, &g.quad_alive), (&after.quads, &after.quad_alive));
    for v in 0..g.verts.len() {
        assert_eq!(
            (g.verts[v].alive, &g.verts[v].fan),
            (after.verts[v].alive, &after.verts[v].fan)
        );
    }
}

/// Two unit quads sharing a vertical edge, labelled as the hexagon of
/// [`hexagon`]: vertex `i` is `h_i`, Q0 = (h0, h1, h2, h3) (id 0) and
/// Q1 = (h3, h4, h5, h0) (id 1); the shared edge is (h0, h3) = edge 3 of Q0.
///
/// ```text
///   h1 ── h0 ── h5
///   │ Q0  │  Q1 │
///   h2 ── h3 ── h4
/// ```
fn quad_pair() -> Patch {
    Patch::new(
        &[
            [1.0, 1.0],
            [0.0, 1.0],
            [0.0, 0.0],
            [1.0, 0.0],
            [2.0, 0.0],
            [2.0, 1.0],
        ],
        &[[0, 1, 2, 3], [3, 4, 5, 0]],
    )
}

/// The swap of the shared edge of [`quad_pair`] to diagonal `k`.
fn pair_swap(k: u8) -> Op {
    Op::Swap { q: 0, e: 3, k }
}

/// The star of a vertex `0` of valence `k`: links `n_i = 1 + i`, opposites
/// `o_i = 1 + k + i`, sector `i` = quad `i` = (c, n_i, o_i, n_{i+1}).
fn star(k: u32) -> Patch {
    let mut pts = vec![[0.0, 0.0]];
    for r in [(1.0, 0.0), (1.6, 0.5)] {
        for i in 0..k {
            let a = std::f64::consts::TAU * (i as f64 + r.1) / k as f64;
            pts.push([r.0 * a.cos(), r.0 * a.sin()]);
        }
    }
    let quads: Vec<[u32; 4]> = (0..k)
        .map(|i| [0, 1 + i, 1 + k + i, 1 + (i + 1) % k])
        .collect();
    Patch::new(&pts, &quads)
}

// ----- swap (Eq. 1) ------------------------------------------------------

#[test]
fn swap_of_a_5_5_edge_to_a_3_3_pair_is_perfect() {
    // (h0 .. h5) = (5, 3, 4, 5, 3, 4): the (5,5) edge (h0,h3), the (3,3) pair (h1,h4)
    let mut fq = ringed(quad_pair(), &[5, 3, 4, 5, 3, 4]);
    let start = fq.clone();
    assert_eq!(hexagon(&fq, 0, 3), Some(([0, 1, 2, 3, 4, 5], 1)));
    let irr = fq.irregular_count();
    // the other diagonal (h2,h5) follows Eq. 1 too but only moves irregularity:
    // h0, h3: 5 − 1 = 4; h2, h5: 4 + 1 = 5
    let eff2 = apply_checked(&mut fq.clone(), pair_swap(2));
    assert_eq!(
        sorted(&eff2),
        vec![(0, 5, 4), (2, 4, 5), (3, 5, 4), (5, 4, 5)]
    );
    // Eq. 1, k = 1: val(h0)' = val(h3)' = 5 − 1 = 4; val(h1)' = val(h4)' = 3 + 1 = 4
    let eff = apply_checked(&mut fq, pair_swap(1));
    assert_eq!(
        sorted(&eff),
        vec![(0, 5, 4), (1, 3, 4), (3, 5, 4), (4, 3, 4)]
    );
    assert_eq!(vals(&fq, &[0, 1, 2, 3, 4, 5]), vec![4; 6]);
    assert_eq!(fq.irregular_count(), irr - 4);
    // k = 1: Q0' = (h1, h2, h3, h4), Q1' = (h4, h5, h0, h1)
    assert_eq!((fq.quads[0], fq.quads[1]), ([1, 2, 3, 4], [4, 5, 0, 1]));
    assert!(fq.linked(1, 4) && !fq.linked(0, 3));
    assert_accepted(&start, &[pair_swap(1)], &fq);
}

#[test]
fn swap_of_a_5_5_edge_to_a_3_4_pair_improves_without_being_perfect() {
    // spec §5.1: a (5,5) edge swapped for a (3,4) pair gives (4,4) and (4,5);
    // (h0 .. h5) = (5, 4, 3, 5, 4, 4), new diagonal k = 2: (h2, h5) = (3, 4)
    let mut fq = ringed(quad_pair(), &[5, 4, 3, 5, 4, 4]);
    let start = fq.clone();
    let irr = fq.irregular_count();
    // Eq. 1: h0, h3: 5 − 1 = 4; h2: 3 + 1 = 4; h5: 4 + 1 = 5
    let eff = apply_checked(&mut fq, pair_swap(2));
    assert_eq!(
        sorted(&eff),
        vec![(0, 5, 4), (2, 3, 4), (3, 5, 4), (5, 4, 5)]
    );
    assert_eq!(fq.irregular_count(), irr - 2, "3 irregular → 1");
    // k = 2: Q0' = (h2, h3, h4, h5), Q1' = (h5, h0, h1, h2)
    assert_eq!((fq.quads[0], fq.quads[1]), ([2, 3, 4, 5], [5, 0, 1, 2]));
    assert_accepted(&start, &[pair_swap(2)], &fq);
}

#[test]
fn translation_swap_moves_a_3_5_dipole_without_changing_the_score() {
    // spec §5.4 (Fig. 5): a (4,5) edge swapped to a (3,4) pair gives (3,4) and (4,5);
    // (h0 .. h5) = (5, 3, 4, 4, 4, 4): the dipole is the edge (h0, h1)
    let mut fq = ringed(quad_pair(), &[5, 3, 4, 4, 4, 4]);
    let start = fq.clone();
    let irr = fq.irregular_count();
    assert!(fq.linked(0, 1));
    let eff = effect(&fq, pair_swap(1)).unwrap();
    assert_eq!(score_delta(&fq, &eff), (0, 0), "valence-neutral");
    // Eq. 1: h0: 5 − 1 = 4; h3: 4 − 1 = 3; h1: 3 + 1 = 4; h4: 4 + 1 = 5
    let eff = apply_checked(&mut fq, pair_swap(1));
    assert_eq!(
        sorted(&eff),
        vec![(0, 5, 4), (1, 3, 4), (3, 4, 3), (4, 4, 5)]
    );
    assert_eq!(fq.irregular_count(), irr);
    // the (3,5) dipole moved from (h1, h0) to (h3, h4), now an edge
    assert!(fq.linked(3, 4) && !fq.is_irregular(0) && !fq.is_irregular(1));
    assert_accepted(&start, &[pair_swap(1)], &fq);
}

#[test]
fn swap_of_an_edge_ending_on_the_boundary_changes_only_valences_there() {
    // 3 × 3 grid: quad 0 = (0, 1, 5, 4), its edge 1 → 5 joins the boundary
    // vertex 1 (bottom side, 3 edges) to the interior vertex 5
    let mut fq = grid(3);
    assert_eq!(hexagon(&fq, 0, 1), Some(([5, 4, 0, 1, 2, 6], 1)));
    assert!(fq.verts[1].fixed && fq.verts[0].fixed && !fq.verts[5].fixed);
    // the swap would leave the curve vertex 1 with 2 edges: refused (spec
    // §5.1, an Edge vertex keeps ≥ 3 edges); a CAD corner may keep 2
    assert!(effect(&fq, Op::Swap { q: 0, e: 1, k: 2 }).is_none());
    as_corner(&mut fq, &[1]);
    // Eq. 1 with k = 2, new diagonal (h2, h5) = (0, 6): h0 = 5: 4 − 1 = 3;
    // h3 = 1: 3 − 1 = 2; corner 0: 2 + 1 = 3; 6: 4 + 1 = 5
    let eff = apply_checked(&mut fq, Op::Swap { q: 0, e: 1, k: 2 });
    assert_eq!(
        sorted(&eff),
        vec![(0, 2, 3), (1, 3, 2), (5, 4, 3), (6, 4, 5)]
    );
    assert!(fq.linked(0, 6));
    // the boundary edge itself (0 → 1, single quad) is never swapped
    assert!(effect(&fq, Op::Swap { q: 0, e: 0, k: 1 }).is_none());
}

// ----- collapse (Eq. 2) ----------------------------------------------------

#[test]
fn collapse_of_a_3_5_3_5_quad_is_perfect() {
    // one quad (v1, v2, v3, v4) = (0, 1, 2, 3) with valences (3, 5, 3, 5)
    let core = Patch::new(
        &[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
        &[[0, 1, 2, 3]],
    );
    let mut fq = ringed(core, &[3, 5, 3, 5]);
    let start = fq.clone();
    let irr = fq.irregular_count();
    // merging the two 5s would leave the 3s with 2 edges (doublets): refused
    assert!(effect(&fq, Op::Collapse { q: 0, d: 1 }).is_none());
    // Eq. 2: val(v13) = 3 + 3 − 2 = 4; val(v2)' = val(v4)' = 5 − 1 = 4; v1 disappears
    let eff = apply_checked(&mut fq, Op::Collapse { q: 0, d: 0 });
    assert_eq!(sorted(&eff), vec![(1, 5, 4), (2, 3, 4), (3, 5, 4)]);
    assert_eq!(eff.removed, Some((0, 3)));
    assert!(!fq.quad_alive[0]);
    assert_eq!(fq.irregular_count(), irr - 4);
    // the merged vertex sits at the centre of the removed quad
    assert_eq!(fq.verts[2].uv, [0.5, 0.5]);
    assert_accepted(&start, &[Op::Collapse { q: 0, d: 0 }], &fq);
}

#[test]
fn collapse_of_a_3_5_3_4_quad_leaves_one_irregular_vertex() {
    // spec §5.2 [C]: (3,5,3,4) → irregular count 3 → 1
    let core = Patch::new(
        &[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
        &[[0, 1, 2, 3]],
    );
    let mut fq = ringed(core, &[3, 5, 3, 4]);
    let start = fq.clone();
    let irr = fq.irregular_count();
    // Eq. 2: val(v13) = 3 + 3 − 2 = 4; v2: 5 − 1 = 4; v4: 4 − 1 = 3
    let eff = apply_checked(&mut fq, Op::Collapse { q: 0, d: 0 });
    assert_eq!(sorted(&eff), vec![(1, 5, 4), (2, 3, 4), (3, 4, 3)]);
    assert_eq!(eff.removed, Some((0, 3)));
    assert_eq!(fq.irregular_count(), irr - 2);
    assert_accepted(&start, &[Op::Collapse { q: 0, d: 0 }], &fq);
}

#[test]
fn collapse_into_a_boundary_vertex_keeps_it_in_place() {
    // 4 × 4 grid: quad 1 = (1, 2, 7, 6); its diagonal (1, 7) joins the
    // boundary vertex 1 (bottom side, 3 edges) and the interior vertex 7
    let mut fq = grid(4);
    assert_eq!(fq.quads[1], [1, 2, 7, 6]);
    // v2 = 2 would keep 2 edges: refused on a curve, allowed at a CAD corner
    assert!(effect(&fq, Op::Collapse { q: 1, d: 0 }).is_none());
    as_corner(&mut fq, &[2]);
    // Eq. 2: the boundary vertex survives: val(v13) = 3 + 4 − 2 = 5;
    // v2 = 2 (boundary): 3 − 1 = 2; v4 = 6: 4 − 1 = 3; 7 disappears
    let eff = apply_checked(&mut fq, Op::Collapse { q: 1, d: 0 });
    assert_eq!(sorted(&eff), vec![(1, 3, 5), (2, 3, 2), (6, 4, 3)]);
    assert_eq!(eff.removed, Some((7, 4)));
    assert_eq!(fq.verts[1].uv, [1.0, 0.0]);
    // two boundary vertices are never merged: quad 0 = (0, 1, 6, 5) has the
    // diagonal (1, 5), both fixed
    assert!(effect(&grid(4), Op::Collapse { q: 0, d: 1 }).is_none());
}

// ----- split (inverse of Eq. 2) ----------------------------------------------

#[test]
fn split_of_a_valence_6_vertex_three_sectors_apart_is_perfect() {
    // star of c = 0 with k = 6: links n_0 = 1 and n_3 = 4 of valence 3, the rest 4
    let mut want = vec![4; 13];
    want[0] = 6;
    want[1] = 3;
    want[4] = 3;
    let mut fq = ringed(star(6), &want);
    let start = fq.clone();
    let irr = fq.irregular_count();
    // d = 1 or d = k − 1 = 5 would leave a doublet: refused
    assert!(effect(&fq, Op::Split { c: 0, a: 1, b: 2 }).is_none());
    assert!(effect(&fq, Op::Split { c: 0, a: 2, b: 1 }).is_none());
    // Fig. 4, option 2 (d = 2): c' = 2 + 1 = 3, c = 6 − 2 + 1 = 5, n_0: 3 + 1 = 4, n_2: 4 + 1 = 5
    let e2 = apply_checked(&mut fq.clone(), Op::Split { c: 0, a: 1, b: 3 });
    assert_eq!(
        (sorted(&e2), e2.created),
        (vec![(0, 6, 5), (1, 3, 4), (3, 4, 5)], Some(3))
    );
    // Fig. 4, option 1 (d = 3): c' = 3 + 1 = 4, c = 6 − 3 + 1 = 4, n_0, n_3: 3 + 1 = 4
    let eff = apply_checked(&mut fq, Op::Split { c: 0, a: 1, b: 4 });
    assert_eq!(
        (sorted(&eff), eff.created),
        (vec![(0, 6, 4), (1, 3, 4), (4, 3, 4)], Some(4))
    );
    let c2 = fq.verts.len() as u32 - 1;
    assert_eq!(
        fq.quads[fq.quads.len() - 1],
        [0, 1, c2, 4],
        "new quad (c, n_p, c', n_q)"
    );
    assert_eq!(fq.irregular_count(), irr - 3);
    assert_accepted(&start, &[Op::Split { c: 0, a: 1, b: 4 }], &fq);
}

#[test]
fn split_of_a_valence_5_vertex_through_two_3_links_leaves_one_3() {
    // Fig. 3 / spec §5.3 [I]: c = 5 with n_p = n_q = 3 at d = 2 gives 4, 4 and (c, c') = (4, 3)
    let mut want = vec![4; 11];
    want[0] = 5;
    want[1] = 3;
    want[3] = 3;
    let mut fq = ringed(star(5), &want);
    let start = fq.clone();
    let irr = fq.irregular_count();
    // the other way round, d = 3: c' = 3 + 1 = 4, c = 5 − 3 + 1 = 3
    let back = effect(&fq, Op::Split { c: 0, a: 3, b: 1 }).unwrap();
    assert_eq!(
        (sorted(&back), back.created),
        (vec![(0, 5, 3), (1, 3, 4), (3, 3, 4)], Some(4))
    );
    // d = 2: c' = 2 + 1 = 3, c = 5 − 2 + 1 = 4 (c + c' = k + 2 = 7), n_0, n_2: 3 + 1 = 4
    let eff = apply_checked(&mut fq, Op::Split { c: 0, a: 1, b: 3 });
    assert_eq!(
        (sorted(&eff), eff.created),
        (vec![(0, 5, 4), (1, 3, 4), (3, 3, 4)], Some(3))
    );
    assert_eq!(fq.irregular_count(), irr - 2, "3 irregular → 1 (c')");
    assert_accepted(&start, &[Op::Split { c: 0, a: 1, b: 3 }], &fq);
}

#[test]
fn split_through_a_boundary_link_keeps_the_boundary() {
    // 3 × 3 grid: interior vertex 5 with links 1 (boundary), 4 (boundary), 6, 9
    let mut fq = grid(3);
    assert_eq!(fq.links(5), vec![1, 4, 6, 9]);
    // k = 4, d = 2: c' = 3, c = 4 − 2 + 1 = 3; boundary link 1: 3 + 1 = 4; 9: 4 + 1 = 5
    let eff = apply_checked(&mut fq, Op::Split { c: 5, a: 1, b: 9 });
    assert_eq!(
        (sorted(&eff), eff.created),
        (vec![(1, 3, 4), (5, 4, 3), (9, 4, 5)], Some(3))
    );
    // a boundary vertex is never split
    assert!(effect(&fq, Op::Split { c: 1, a: 0, b: 2 }).is_none());
}

// ----- compositions (spec §5.5) ------------------------------------------------

#[test]
fn swap_split_fig7_leaves_a_single_3() {
    // Fig. 7: a (4,4) edge (h0, h3) with a (5,3) pair (h1, h4); V = 3 is the link
    // of h1 across the quad W = (h1, V, o, h2) left of Q0:
    //
    //   V ── h1 ── h0 ── h5
    //   │ W  │ Q0  │ Q1  │
    //   o ── h2 ── h3 ── h4
    let mut core = quad_pair();
    core.pts.extend([[-1.0, 1.0], [-1.0, 0.0]]);
    core.quads.push([1, 6, 7, 2]);
    let (v, h) = (6u32, [0u32, 1, 2, 3, 4, 5]);
    let mut fq = ringed(core, &[4, 5, 4, 4, 3, 4, 3, 4]);
    let start = fq.clone();
    let irr = fq.irregular_count();
    // 1. swap to (h1, h4), Eq. 1: h0, h3: 4 − 1 = 3; h1: 5 + 1 = 6; h4: 3 + 1 = 4
    let e1 = apply_checked(&mut fq, pair_swap(1));
    assert_eq!(
        sorted(&e1),
        vec![(0, 4, 3), (1, 5, 6), (3, 4, 3), (4, 3, 4)]
    );
    assert_eq!(
        fq.irregular_count(),
        irr + 1,
        "the swap alone makes it worse"
    );
    // 2. split the 6 (h1) through the 3-link h0 and the link three sectors away, V
    let s = fq.ordered_star(h[1]).unwrap();
    let pos = |x: u32| s.iter().position(|t| t.1[1] == x).unwrap();
    assert_eq!((pos(v) + 6 - pos(h[0])) % 6, 3);
    // k = 6, d = 3: c' = 4, c = 6 − 3 + 1 = 4; h0: 3 + 1 = 4; V: 3 + 1 = 4
    let e2 = apply_checked(
        &mut fq,
        Op::Split {
            c: h[1],
            a: h[0],
            b: v,
        },
    );
    assert_eq!(
        (sorted(&e2), e2.created),
        (vec![(0, 3, 4), (1, 6, 4), (v, 3, 4)], Some(4))
    );
    assert_eq!(
        fq.irregular_count(),
        irr - 2,
        "3 irregular (h1, h4, V) → 1 (h3 = 3)"
    );
    assert_eq!(fq.valence(h[3]), 3);
    assert_accepted(
        &start,
        &[
            pair_swap(1),
            Op::Split {
                c: h[1],
                a: h[0],
                b: v,
            },
        ],
        &fq,
    );
}

#[test]
fn swap_collapse_removes_four_of_five_irregular_vertices() {
    // [C] trigger: a (4,4) edge (h0, h3) with a (3,5) hexagon edge (h1, h2);
    // the pair (h1, h4) = (3, 3), and W = (h3, h2, w, x) below Q0 is (4, 5, 3, 5):
    //
    //   h1 ── h0 ── h5
    //   │ Q0  │  Q1 │
    //   h2 ── h3 ── h4
    //   │  W  │
    //   w ─── x
    let mut core = quad_pair();
    core.pts.extend([[0.0, -1.0], [1.0, -1.0]]);
    core.quads.push([3, 2, 6, 7]);
    let (w, x) = (6u32, 7u32);
    let mut fq = ringed(core, &[4, 3, 5, 4, 3, 4, 3, 5]);
    let start = fq.clone();
    let irr = fq.irregular_count();
    // 1. swap to (h1, h4), Eq. 1: h0, h3: 4 − 1 = 3; h1, h4: 3 + 1 = 4 (neutral)
    let e1 = apply_checked(&mut fq, pair_swap(1));
    assert_eq!(
        sorted(&e1),
        vec![(0, 4, 3), (1, 3, 4), (3, 4, 3), (4, 3, 4)]
    );
    assert_eq!(fq.irregular_count(), irr);
    // 2. W is now (3, 5, 3, 5): collapse (h3, w), Eq. 2: 3 + 3 − 2 = 4; h2, x: 5 − 1 = 4
    assert_eq!(vals(&fq, &fq.quads[2]), vec![3, 5, 3, 5]);
    let e2 = apply_checked(&mut fq, Op::Collapse { q: 2, d: 0 });
    assert_eq!(sorted(&e2), vec![(2, 5, 4), (w, 3, 4), (x, 5, 4)]);
    assert_eq!(e2.removed, Some((3, 3)));
    assert_eq!(
        fq.irregular_count(),
        irr - 4,
        "5 irregular (h1, h2, h4, w, x) → 1 (h0 = 3)"
    );
    assert_accepted(&start, &[pair_swap(1), Op::Collapse { q: 2, d: 0 }], &fq);
}

#[test]
fn double_collapse_fig9_leaves_a_single_5() {
    // Fig. 9: the lower quad L = (a, b, c, d) = (4, 4, 5, 3) and the quad above,
    // U = (a, d, y, z) = (4, 3, 4, 5): the triple (3, 5, 5) = (d, c, z), (c, d) a (5,3) link
    //
    //   z ── y
    //   │ U  │
    //   a ── d      (d is pulled in: its single ring quad needs the room)
    //   │ L  │
    //   b ── c
    let core = Patch::new(
        &[
            [0.0, 1.0],
            [0.0, 0.0],
            [1.0, 0.0],
            [0.7, 1.0],
            [1.0, 2.0],
            [0.0, 2.0],
        ],
        &[[0, 1, 2, 3], [0, 3, 4, 5]],
    );
    let [a, b, c, d, y, z] = [0u32, 1, 2, 3, 4, 5];
    let mut fq = ringed(core, &[4, 4, 5, 3, 4, 5]);
    let start = fq.clone();
    let irr = fq.irregular_count();
    // 1. collapse L along its (4,3) diagonal (b, d), Eq. 2: 4 + 3 − 2 = 5; a: 4 − 1 = 3; c: 5 − 1 = 4
    let e1 = apply_checked(&mut fq, Op::Collapse { q: 0, d: 1 });
    assert_eq!(sorted(&e1), vec![(a, 4, 3), (c, 5, 4), (d, 3, 5)]);
    assert_eq!(e1.removed, Some((b, 4)));
    assert_eq!(fq.irregular_count(), irr, "neutral: (d, c, z) → (a, d, z)");
    // 2. U is now (3, 5, 4, 5): collapse its (3,4) diagonal (a, y), Eq. 2:
    //    3 + 4 − 2 = 5; d, z: 5 − 1 = 4
    assert_eq!(vals(&fq, &fq.quads[1]), vec![3, 5, 4, 5]);
    let e2 = apply_checked(&mut fq, Op::Collapse { q: 1, d: 0 });
    assert_eq!(sorted(&e2), vec![(d, 5, 4), (y, 4, 5), (z, 5, 4)]);
    assert_eq!(e2.removed, Some((a, 3)));
    assert_eq!(
        fq.irregular_count(),
        irr - 2,
        "3 irregular → 1 (the merged 5)"
    );
    assert_accepted(
        &start,
        &[Op::Collapse { q: 0, d: 1 }, Op::Collapse { q: 1, d: 0 }],
        &fq,
    );
}

#[test]
fn double_split_fig10_leaves_v_plus_one_only() {
    // Fig. 10 / spec §5.5 [I]: C = 5 with a 5-link P and a 3-link T two sectors apart
    let (c, p, t) = (0u32, 1u32, 3u32);
    let mut want = [4; 11];
    want[c as usize] = 5;
    want[p as usize] = 5;
    want[t as usize] = 3;
    let once = star(5).ring(|v| want[v as usize]);
    // V: the link of P three sectors from c' after the first split; it lies on
    // the first ring, so a second ring makes it interior with valence v_val
    let split1 = Op::Split { c, a: p, b: t };
    let mut probe = once.build();
    apply_topology(&mut probe, split1).unwrap();
    let c2 = probe.verts.len() as u32 - 1;
    let s = probe.ordered_star(p).unwrap();
    assert_eq!(s.len(), 6);
    let i = s.iter().position(|x| x.1[1] == c2).unwrap();
    let v = s[(i + 3) % 6].1[1];
    assert!(v as usize >= want.len(), "V is outside the star of C");
    for v_val in [4, 3] {
        let mut fq = once
            .clone()
            .ring_regular(&[(v, v_val)])
            .relaxed(want.len())
            .build();
        let start = fq.clone();
        assert_valid(&fq);
        assert_eq!(vals(&fq, &[c, p, t, v]), vec![5, 5, 3, v_val]);
        let irr = fq.irregular_count();
        // 1. split C through P and T, d = 2: c' = 2 + 1 = 3, C = 5 − 2 + 1 = 4;
        //    P: 5 + 1 = 6; T: 3 + 1 = 4
        let e1 = apply_checked(&mut fq, split1);
        assert_eq!(
            (sorted(&e1), e1.created),
            (vec![(c, 5, 4), (p, 5, 6), (t, 3, 4)], Some(3))
        );
        let c2 = fq.verts.len() as u32 - 1;
        let s = fq.ordered_star(p).unwrap();
        let pos = |x: u32| s.iter().position(|y| y.1[1] == x).unwrap();
        assert_eq!((pos(v) + 6 - pos(c2)) % 6, 3);
        // 2. split the 6 (P) through c' and V, d = 3: P' = 3 + 1 = 4, P = 6 − 3 + 1 = 4;
        //    c': 3 + 1 = 4; V: v_val + 1
        let e2 = apply_checked(&mut fq, Op::Split { c: p, a: c2, b: v });
        assert_eq!(
            (sorted(&e2), e2.created),
            (vec![(p, 6, 4), (v, v_val, v_val + 1), (c2, 3, 4)], Some(4))
        );
        // 3 irregular (C, P, T) → 1 (V = 5); or 4 (with V = 3) → 0
        let expected = if v_val == 4 { irr - 2 } else { irr - 4 };
        assert_eq!(fq.irregular_count(), expected, "V = {v_val}");
        assert_accepted(&start, &[split1, Op::Split { c: p, a: c2, b: v }], &fq);
    }
}

#[test]
fn double_swap_fig11_leaves_one_or_no_irregular_vertex() {
    // Fig. 11, adjacent quads: three quads in a row, the triple (3, 5, 5) =
    // (t0, b1, t2); the two swaps pass a (3,5) dipole along and cancel it:
    //
    //   t0 ── t1 ── t2 ── t3
    //   │  A  │  B  │  C  │
    //   b0 ── b1 ── b2 ── b3
    let pts = [
        [0.0, 0.0],
        [1.0, 0.0],
        [2.0, 0.0],
        [3.0, 0.0],
        [0.0, 1.0],
        [1.0, 1.0],
        [2.0, 1.0],
        [3.0, 1.0],
    ];
    let core = Patch::new(&pts, &[[0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6]]);
    let [b1, b2, b3, t0, t1, t2] = [1u32, 2, 3, 4, 5, 6];
    for b3_val in [4, 3] {
        let mut fq = ringed(core.clone(), &[4, 5, 4, b3_val, 3, 4, 5, 4]);
        let start = fq.clone();
        let irr = fq.irregular_count();
        // 1. swap (b1, t1) to (t0, b2), Eq. 1: t1: 4 − 1 = 3; b1: 5 − 1 = 4;
        //    t0: 3 + 1 = 4; b2: 4 + 1 = 5 (neutral: (t0, b1, t2) → (t1, b2, t2))
        let s1 = Op::Swap { q: 0, e: 1, k: 1 };
        assert_eq!(hexagon(&fq, 0, 1), Some(([t1, t0, 0, b1, b2, t2], 1)));
        let e1 = apply_checked(&mut fq, s1);
        assert_eq!(
            sorted(&e1),
            vec![(b1, 5, 4), (b2, 4, 5), (t0, 3, 4), (t1, 4, 3)]
        );
        assert_eq!(fq.irregular_count(), irr);
        // 2. swap (b2, t2) to (t1, b3), Eq. 1: t2: 5 − 1 = 4; b2: 5 − 1 = 4;
        //    t1: 3 + 1 = 4; b3: b3_val + 1
        let s2 = Op::Swap { q: 1, e: 0, k: 1 };
        assert_eq!(hexagon(&fq, 1, 0), Some(([t2, t1, t0, b2, b3, 7], 2)));
        let e2 = apply_checked(&mut fq, s2);
        assert_eq!(
            sorted(&e2),
            vec![(b2, 5, 4), (b3, b3_val, b3_val + 1), (t1, 3, 4), (t2, 5, 4)]
        );
        // 3 irregular → 1 (b3 = 5); or 4 (with b3 = 3) → 0
        let expected = if b3_val == 4 { irr - 2 } else { irr - 4 };
        assert_eq!(fq.irregular_count(), expected, "b3 = {b3_val}");
        assert_accepted(&start, &[s1, s2], &fq);
    }
}
