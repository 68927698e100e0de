//! Segmentation and pairing of the paper's figure cycles (spec §1–§4), and
//! the invariants of every returned [`PairedCycle`].

use super::fixtures;
use super::polyline::{dist, P3};
use super::{pair_cycle, CycleLoops, PairedCycle, PairingError, PairingOptions, PairingReport};

/// Pairs a fixture with the default options and checks the hand-off
/// invariants: even count, every segment in exactly one pair, pairs `i < j`
/// ascending, one finite cost per pair equal to the report's, starts
/// ascending and in range.
fn run(cycle: &CycleLoops) -> (PairedCycle, PairingReport) {
    let (p, r) = pair_cycle(cycle, &PairingOptions::default()).expect("the fixture pairs");
    let n = p.starts.len();
    assert!(n >= 2 && n % 2 == 0, "even segment count, got {n}");
    assert!(p.starts.windows(2).all(|w| w[0] < w[1]), "starts ascending: {:?}", p.starts);
    assert!(p.starts.iter().all(|&s| s < p.points.len()));
    assert_eq!(p.unsplittable.len(), n);
    assert_eq!(p.pairs.len(), n / 2);
    let mut seen = vec![0; n];
    for &(i, j) in &p.pairs {
        assert!(i < j && j < n, "pair ({i}, {j})");
        seen[i] += 1;
        seen[j] += 1;
    }
    assert!(seen.iter().all(|&c| c == 1), "each segment in exactly one pair: {seen:?}");
    assert!(p.pairs.windows(2).all(|w| w[0].0 < w[1].0), "pairs in order");
    assert_eq!(p.costs.len(), p.pairs.len());
    assert!(p.costs.iter().all(|c| c.is_finite() && *c >= 0.0));
    assert_eq!(p.costs, r.costs);
    assert_eq!(r.final_segments, n);
    (p, r)
}

/// How many segment starts lie strictly between the points `a` and `b` of a
/// straight side (for "side split once").
fn starts_inside_side(p: &PairedCycle, a: P3, b: P3) -> usize {
    let len = dist(a, b);
    p.starts
        .iter()
        .map(|&s| p.points[s])
        .filter(|&q| {
            let (da, db) = (dist(q, a), dist(q, b));
            da > 1e-9 && db > 1e-9 && (da + db - len).abs() < 1e-9 * len.max(1.0)
        })
        .count()
}

/// The segment (index) whose start is at the point `q`.
fn segment_starting_at(p: &PairedCycle, q: P3) -> Option<usize> {
    p.starts.iter().position(|&s| dist(p.points[s], q) < 1e-9)
}

fn mate(p: &PairedCycle, s: usize) -> usize {
    p.pairs.iter().find_map(|&(i, j)| if i == s { Some(j) } else if j == s { Some(i) } else { None }).unwrap()
}

#[test]
fn saddle_gives_four_segments_paired_opposite() {
    let (p, r) = run(&fixtures::saddle(0.5));
    assert_eq!((r.initial_segments, r.final_segments), (4, 4), "{r:?}");
    assert_eq!(p.pairs, vec![(0, 2), (1, 3)]);
    assert!(r.fallbacks.is_empty() && r.odd_parties.is_empty());
}

#[test]
fn equilateral_triangle_is_an_odd_party_then_six_segments() {
    let (p, r) = run(&fixtures::triangle());
    assert_eq!(r.initial_segments, 3, "{r:?}");
    assert_eq!(r.odd_parties.first(), Some(&vec![0, 1, 2]), "{r:?}");
    assert_eq!(p.starts.len(), 6, "{r:?}");
    // Every side split at its midpoint.
    let c = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, 0.75f64.sqrt(), 0.0]];
    for k in 0..3 {
        assert_eq!(starts_inside_side(&p, c[k], c[(k + 1) % 3]), 1);
    }
}

#[test]
fn spherical_octant_is_an_odd_party_then_six_segments() {
    let (p, r) = run(&fixtures::octant(60));
    assert_eq!(r.initial_segments, 3, "{r:?}");
    assert_eq!(r.odd_parties.first(), Some(&vec![0, 1, 2]), "{r:?}");
    assert_eq!(p.starts.len(), 6, "{r:?}");
}

#[test]
fn house_with_an_off_centre_apex_splits_its_bottom_once() {
    let (p, r) = run(&fixtures::house());
    assert_eq!(r.initial_segments, 5, "{r:?}");
    assert_eq!(p.starts.len(), 6, "{r:?}");
    let [a, b] = fixtures::HOUSE_BOTTOM;
    assert_eq!(starts_inside_side(&p, a, b), 1, "{r:?}");
    // The targeted split (Fig. 7): the bottom cut in the ratio of the two
    // roof lengths, each part paired with the roof above it, walls paired.
    let (left_roof, right_roof) = (dist([0.0, 1.0, 0.0], [0.7, 1.5, 0.0]), dist([2.0, 1.0, 0.0], [0.7, 1.5, 0.0]));
    let cut = p.points[p.starts[1]];
    let expected = 2.0 * left_roof / (left_roof + right_roof);
    assert!((cut[0] - expected).abs() < 0.02, "cut at {cut:?}, expected x = {expected}");
    let seg = |q: [f64; 3]| segment_starting_at(&p, q).unwrap();
    let (b1, b2, wall_r, roof_r, roof_l, wall_l) =
        (seg([0.0; 3]), seg(cut), seg([2.0, 0.0, 0.0]), seg([2.0, 1.0, 0.0]), seg([0.7, 1.5, 0.0]), seg([0.0, 1.0, 0.0]));
    assert_eq!((mate(&p, b1), mate(&p, b2), mate(&p, wall_r)), (roof_l, roof_r, wall_l), "{p:?}");
}

#[test]
fn ell_gives_eight_segments() {
    let (p, r) = run(&fixtures::ell());
    assert_eq!(r.initial_segments, 6, "{r:?}");
    assert_eq!(p.starts.len(), 8, "{r:?}");
    assert!(r.fallbacks.is_empty());
    // The three-square layout of Fig. 5 bottom: the bottom and the left side
    // cut at the inner corner's projections, each arm's ends paired.
    let seg = |x: f64, y: f64| segment_starting_at(&p, [x, y, 0.0]).unwrap_or_else(|| panic!("no start at ({x}, {y}): {p:?}"));
    assert_eq!(mate(&p, seg(0.0, 0.0)), seg(1.0, 2.0), "bottom-left half with the top");
    assert_eq!(mate(&p, seg(1.0, 0.0)), seg(2.0, 1.0), "bottom-right half with the foot's top");
    assert_eq!(mate(&p, seg(2.0, 0.0)), seg(0.0, 1.0), "right wall with the left side's lower half");
    assert_eq!(mate(&p, seg(1.0, 1.0)), seg(0.0, 2.0), "inner wall with the left side's upper half");
}

#[test]
fn circle_uses_the_fallback_and_pairs_opposite_quarters() {
    let (p, r) = run(&fixtures::circle(256));
    assert_eq!(r.fallbacks, vec![(0, 0)], "{r:?}");
    assert!(r.notes()[0].contains("fallback"));
    assert_eq!(r.initial_segments, 4);
    assert_eq!(p.starts.len(), 4, "{r:?}");
    assert_eq!(p.pairs, vec![(0, 2), (1, 3)]);
}

#[test]
fn lens_uses_the_fallback_with_an_even_count_of_at_least_four() {
    let (p, r) = run(&fixtures::lens(80));
    assert_eq!(r.fallbacks, vec![(0, 2)], "{r:?}");
    assert!(p.starts.len() >= 4, "{r:?}");
    // The two sharp corners stay segment ends.
    let h = 0.75f64.sqrt();
    assert!(segment_starting_at(&p, [h, 0.0, 0.0]).is_some() && segment_starting_at(&p, [-h, 0.0, 0.0]).is_some());
}

#[test]
fn letter_p_gets_exactly_one_unsplittable_connector() {
    let (p, r) = run(&fixtures::letter_p());
    assert_eq!(r.connectors, 1);
    let flagged: Vec<usize> = (0..p.starts.len()).filter(|&s| p.unsplittable[s]).collect();
    assert_eq!(flagged.len(), 2, "the connector, once each way: {flagged:?}");
    // The two sides are the same straight segment, run in opposite directions.
    let n = p.starts.len();
    let ends = |s: usize| (p.points[p.starts[s]], p.points[p.starts[(s + 1) % n]]);
    let (a0, a1) = ends(flagged[0]);
    let (b0, b1) = ends(flagged[1]);
    assert!(dist(a0, b1) < 1e-12 && dist(a1, b0) < 1e-12);
    // One end on the outer loop, the other on the hole's rectangle.
    let on_hole = |q: P3| {
        let [lo, hi] = fixtures::P_HOLE;
        let inside_x = q[0] >= lo[0] - 1e-12 && q[0] <= hi[0] + 1e-12;
        let inside_y = q[1] >= lo[1] - 1e-12 && q[1] <= hi[1] + 1e-12;
        inside_x && inside_y && ((q[0] - lo[0]).abs() < 1e-12 || (q[0] - hi[0]).abs() < 1e-12 || (q[1] - lo[1]).abs() < 1e-12 || (q[1] - hi[1]).abs() < 1e-12)
    };
    assert!(on_hole(a1) && !on_hole(a0), "connector {a0:?} → {a1:?}");
    // Connectors stay unsplit: no start strictly inside the connector.
    assert_eq!(starts_inside_side(&p, a0, a1), 0);
}

#[test]
fn bad_cycles_are_errors_not_panics() {
    let o = PairingOptions::default();
    let flat = fixtures::saddle(0.5);
    let mut two = flat.clone();
    two.outer.points.truncate(2);
    assert!(matches!(pair_cycle(&two, &o), Err(PairingError::TooFewPoints { count: 2, .. }) | Err(PairingError::NoInwardSide { .. })));
    let mut nan = flat.clone();
    nan.outer.points[1][0] = f64::NAN;
    assert!(matches!(pair_cycle(&nan, &o), Err(PairingError::NotFinite { loop_index: 0, point: 1 })));
    let mut folded = flat.clone();
    folded.outer.points = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
    let e = pair_cycle(&folded, &o).unwrap_err();
    assert!(matches!(e, PairingError::NoInwardSide { .. }), "{e}");
    let mut fixed = flat;
    fixed.outer.fixed = vec![9];
    assert!(matches!(pair_cycle(&fixed, &o), Err(PairingError::FixedOutOfRange { index: 9, count: 4, .. })));
}
