use super::*;

fn pattern(name: &str) -> &'static Pattern {
    library()
        .iter()
        .find(|p| p.name == name)
        .expect("in the library")
}

#[test]
fn derived_sides_and_chords_reproduce_the_papers_equations() {
    // R3: N1 = a + b + c, N2 = d + e, N3 = a + c, N4 = b + d + e
    let r3 = pattern("R3");
    assert_eq!(r3.sides(), 4);
    assert_eq!(r3.chords, 5);
    assert_eq!(
        r3.w,
        vec![
            vec![1, 1, 1, 0, 0],
            vec![0, 0, 0, 1, 1],
            vec![1, 0, 1, 0, 0],
            vec![0, 1, 0, 1, 1]
        ]
    );
    assert_eq!(r3.irregular, 2);
    // R1: opposite sides share a chord
    let r1 = pattern("R1");
    assert_eq!(r1.w, vec![vec![1, 0], vec![0, 1], vec![1, 0], vec![0, 1]]);
    // T3: side i holds chords x_i and x_{i−1}
    let t3 = pattern("T3");
    assert_eq!((t3.sides(), t3.chords, t3.irregular), (3, 3, 1));
    for row in &t3.w {
        assert_eq!(row.iter().sum::<u32>(), 2);
    }
    // P5: N_i = c_i + c_{i+2}
    let p5 = pattern("P5");
    assert_eq!((p5.sides(), p5.chords, p5.irregular), (5, 5, 1));
    // R2c: N1 − N3 = b1 + b2 and N4 − N2 = b1 − b2 (a 5-term bottom, 3-term right and left, 3-term top)
    let r2c = pattern("R2c");
    assert_eq!((r2c.sides(), r2c.irregular), (4, 4));
    let counts: Vec<u32> = r2c.w.iter().map(|r| r.iter().sum()).collect();
    assert_eq!(counts, vec![5, 3, 3, 3]);
    // RU: a chord with w = 2 (U-turn) on one side
    let ru = pattern("RU");
    assert_eq!((ru.sides(), ru.irregular), (4, 4));
    assert!(ru.w.iter().any(|r| r.contains(&2)), "{:?}", ru.w);
}

#[test]
fn bad_coarse_meshes_are_refused() {
    let c = vec![[0.0, 0.0]; 6];
    // two quads sharing only a vertex
    assert!(matches!(
        Pattern::from_quads("x", c.clone(), vec![[0, 1, 2, 3], [2, 4, 5, 1]]),
        Err(PatternError::NotADisk(..))
    ));
    // a vertex index out of range
    assert!(Pattern::from_quads("x", c.clone(), vec![[0, 1, 2, 9]]).is_err());
    // an L of three quads has a concave boundary vertex
    let l = vec![[0.0, 0.0]; 8];
    assert!(matches!(
        Pattern::from_quads("L", l, vec![[0, 1, 2, 3], [1, 4, 5, 2], [3, 2, 6, 7]]),
        Err(PatternError::Concave(..))
    ));
}

#[test]
fn closed_forms_of_the_star_patterns() {
    // T3: x_i = (N_i + N_{i+1} − N_{i−1}) / 2; sides 6, 8, 10 → 2, 4, 6 up to labelling
    let t3 = pattern("T3");
    let s = solve(&t3.w, &[6, 8, 10], MAX_ATTEMPTS).expect("solvable");
    assert_eq!(t3.side_counts(&s), vec![6, 8, 10]);
    let mut sorted = s.clone();
    sorted.sort();
    assert_eq!(sorted, vec![2, 4, 6]);
    // odd total or a broken triangle inequality: no solution
    assert!(solve(&t3.w, &[6, 8, 9], MAX_ATTEMPTS).is_none());
    assert!(solve(&t3.w, &[2, 2, 8], MAX_ATTEMPTS).is_none());
    // P5 with 4, 4, 4, 4, 4: every chord 2
    let p5 = pattern("P5");
    assert_eq!(solve(&p5.w, &[4; 5], MAX_ATTEMPTS), Some(vec![2; 5]));
}

#[test]
fn the_corner_dipole_example() {
    let r3 = pattern("R3");
    // [10, 4, 8, 6]: b = 2, a = c = 4, d = e = 2
    assert_eq!(
        solve(&r3.w, &[10, 4, 8, 6], MAX_ATTEMPTS),
        Some(vec![4, 2, 4, 2, 2])
    );
    // N1 − N3 = 1 ≠ N4 − N2 = 2: no solution, and the search stops
    assert!(solve(&r3.w, &[9, 4, 8, 6], MAX_ATTEMPTS).is_none());
    // large unsolvable input: still terminates (bounded attempts)
    assert!(solve(&r3.w, &[401, 200, 300, 300], MAX_ATTEMPTS).is_none());
}

#[test]
fn matching_tries_every_rotation_and_direction() {
    // the R3 cavity read from another side still matches R3 (or better)
    for sides in [[10, 4, 8, 6], [6, 10, 4, 8], [8, 4, 10, 6], [4, 10, 6, 8]] {
        let m = match_pattern(&sides).expect("a match");
        let p = &library()[m.pattern];
        assert_eq!(p.name, "R3", "{sides:?}");
        let n = oriented(&sides, m.shift, m.mirror);
        assert_eq!(p.side_counts(&m.subdivisions), n);
    }
    // a rectangle with equal opposite sides is a grid
    let m = match_pattern(&[5, 3, 5, 3]).unwrap();
    assert_eq!(library()[m.pattern].name, "R1");
    // a hexagonal cavity has no pattern
    assert!(match_pattern(&[2; 6]).is_none());
}

/// Refined meshes: side counts as asked, only the pattern's irregular
/// vertices, Euler characteristic 1, every quad counter-clockwise.
#[test]
fn refined_patterns_are_valid_meshes() {
    let r1 = refine(pattern("R1"), &[5, 3]);
    assert_eq!(r1.quads.len(), 15);
    for (name, sides) in [
        ("R1", vec![5u32, 3, 5, 3]),
        ("R3", vec![10, 4, 8, 6]),
        ("T3", vec![6, 8, 10]),
        ("P5", vec![4, 6, 4, 6, 4]),
        ("R2c", vec![12, 5, 6, 9]),
        ("RU", vec![4, 6, 4, 10]),
    ] {
        let p = pattern(name);
        let s = solve(&p.w, &sides, MAX_ATTEMPTS).unwrap_or_else(|| panic!("{name} {sides:?}"));
        let r = refine(p, &s);
        // sides between consecutive corners
        let nb = r.boundary.len();
        let m = r.corners.len();
        let got: Vec<u32> = (0..m)
            .map(|i| ((r.corners[(i + 1) % m] + nb - r.corners[i]) % nb) as u32)
            .collect();
        assert_eq!(got, sides, "{name}");
        // valences and Euler
        let nv = r.coords.len();
        let mut val = vec![0usize; nv];
        let mut edges = std::collections::HashSet::new();
        for q in &r.quads {
            let area: f64 = (0..4)
                .map(|k| {
                    let (a, b) = (r.coords[q[k] as usize], r.coords[q[(k + 1) % 4] as usize]);
                    a[0] * b[1] - b[0] * a[1]
                })
                .sum();
            assert!(area > 0.0, "{name}: quad {q:?} not counter-clockwise");
            for k in 0..4 {
                val[q[k] as usize] += 1;
                edges.insert((q[k].min(q[(k + 1) % 4]), q[k].max(q[(k + 1) % 4])));
            }
        }
        assert!(val.iter().all(|&v| v > 0), "{name}: unused vertex");
        assert_eq!(
            nv as i64 - edges.len() as i64 + r.quads.len() as i64,
            1,
            "{name}: Euler"
        );
        let on_b: std::collections::HashSet<u32> = r.boundary.iter().copied().collect();
        assert_eq!(on_b.len(), nb);
        let irregular = (0..nv as u32)
            .filter(|v| !on_b.contains(v) && val[*v as usize] != 4)
            .count();
        assert_eq!(
            irregular, p.irregular,
            "{name}: irregular interior vertices"
        );
        for (i, &b) in r.boundary.iter().enumerate() {
            let want = if r.corners.contains(&i) { 1 } else { 2 };
            assert_eq!(val[b as usize], want, "{name}: boundary vertex {i}");
        }
    }
}
