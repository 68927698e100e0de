use super::*;
use crate::shell::tests::grid;

/// The dense Hessian from the assembled lower triangle (vertex 0 pinned).
fn dense_hessian(shell: &Shell, topo: &ShellTopology, u: &[f64], eta: &[f64]) -> Vec<Vec<f64>> {
    let n = shell.vertices.len();
    let m = n - 1;
    let mut below = vec![Vec::new(); m];
    for &[a, b] in &topo.edges {
        if a > 0 && b > 0 {
            below[(a - 1).min(b - 1)].push((a - 1).max(b - 1));
        }
    }
    let pattern = LowerPattern::from_columns(m, below);
    let edge_position: Vec<Option<usize>> = topo
        .edges
        .iter()
        .map(|&[a, b]| {
            if a > 0 && b > 0 {
                pattern.position(a.max(b) - 1, a.min(b) - 1)
            } else {
                None
            }
        })
        .collect();
    let spd = SparseSpd::analyze(pattern, None).unwrap();
    let mut lengths = vec![0.0; topo.edges.len()];
    lengths_from(u, eta, topo, &mut lengths);
    let mut values = vec![0.0; spd.pattern.nnz()];
    assemble_hessian(
        shell,
        topo,
        u,
        eta,
        &lengths,
        &spd,
        &edge_position,
        &mut values,
    );
    let mut h = vec![vec![0.0; m]; m];
    for (j, w) in spd.pattern.col_ptr.windows(2).enumerate() {
        for (&i, &value) in spd.pattern.row_idx[w[0]..w[1]]
            .iter()
            .zip(&values[w[0]..w[1]])
        {
            h[i][j] = value;
            h[j][i] = value;
        }
    }
    h
}

#[test]
fn the_chain_rule_hessian_matches_finite_differences_of_the_curvature() {
    // A bumpy 3 × 3 grid with uneven radii: η differs from edge to edge.
    let shell = grid(3, |x, y| [x + 0.07 * y * y, y, 0.2 * (3.0 * x).sin() * y]);
    let topo = shell.check().unwrap();
    let n = shell.vertices.len();
    let mut u: Vec<f64> = (0..n)
        .map(|v| (0.08 + 0.01 * (v % 4) as f64).ln())
        .collect();
    let eta: Vec<f64> = topo
        .edges
        .iter()
        .map(|&[a, b]| {
            let l = shell.edge_length(a, b);
            let (ga, gb) = (u[a].exp(), u[b].exp());
            (l * l - ga * ga - gb * gb) / (2.0 * ga * gb)
        })
        .collect();
    assert!(eta.iter().all(|&e| e > 1.0), "disjoint circles: η > 1");
    let h = dense_hessian(&shell, &topo, &u, &eta);
    let curvature = |u: &[f64]| {
        let mut l = vec![0.0; topo.edges.len()];
        lengths_from(u, &eta, &topo, &mut l);
        curvature_from(&shell, &topo, &l).unwrap()
    };
    let step = 1e-6;
    let mut worst: f64 = 0.0;
    for j in 1..n {
        let base = u[j];
        u[j] = base + step;
        let kp = curvature(&u);
        u[j] = base - step;
        let km = curvature(&u);
        u[j] = base;
        for i in 1..n {
            let fd = (kp[i] - km[i]) / (2.0 * step);
            worst = worst.max((fd - h[i - 1][j - 1]).abs());
        }
    }
    assert!(worst < 1e-6, "Hessian vs finite differences: {worst:e}");
    // Positive definite with one vertex pinned: a Cholesky factor exists.
    let diag_positive = (0..n - 1).all(|i| h[i][i] > 0.0);
    assert!(diag_positive);
}

#[test]
fn the_input_metric_is_reproduced_at_the_initial_radii() {
    let shell = grid(5, |x, y| [x, y, 0.3 * x * y]);
    let topo = shell.check().unwrap();
    let cones = [0, 5, 35, 30].map(|vertex| Cone { vertex, index: 1 });
    let options = RicciOptions {
        tolerance: 1e-9,
        max_iterations: 0,
    };
    // Zero iterations allowed: the error reports the input curvature error.
    match ricci_flow(&shell, &topo, &cones, &options) {
        Err(RicciError::NotConverged {
            iterations: 0,
            residual,
            vertex,
            ..
        }) => {
            let sums = shell.angle_sums();
            let k = if topo.on_boundary[vertex] {
                std::f64::consts::PI
            } else {
                std::f64::consts::TAU
            } - sums[vertex];
            let target = if [0, 5, 35, 30].contains(&vertex) {
                std::f64::consts::FRAC_PI_2
            } else {
                0.0
            };
            assert!((residual - (k - target).abs()).abs() < 1e-12);
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn refining_cone_rings_keeps_a_valid_shell_and_its_area() {
    let shell = grid(4, |x, y| [x, y, 0.2 * x * y]);
    let topo = shell.check().unwrap();
    // An interior cone (vertex 6, valence 6) and a corner cone (vertex 0).
    let refined = refine_cone_rings(&shell, &topo, &[6, 0]);
    let t2 = refined.check().expect("still a manifold disk");
    assert_eq!(t2.euler, 1);
    let valence6 = topo.edges.iter().filter(|e| e.contains(&6)).count();
    let valence0 = topo.edges.iter().filter(|e| e.contains(&0)).count();
    assert_eq!(
        refined.vertices.len(),
        shell.vertices.len() + valence6 + valence0
    );
    assert!((refined.area() - shell.area()).abs() < 1e-12);
    // The cone keeps its valence; its ring edges are halved.
    assert_eq!(t2.edges.iter().filter(|e| e.contains(&6)).count(), valence6);
    // Same angle sum at the cone, so the same index.
    assert!((refined.angle_sums()[6] - shell.angle_sums()[6]).abs() < 1e-12);
}

#[test]
fn a_refined_annulus_still_converges() {
    let (rings, sectors) = (6, 32);
    let mut vertices = Vec::new();
    for i in 0..=rings {
        for j in 0..sectors {
            let t = std::f64::consts::TAU * j as f64 / sectors as f64;
            let s = 1.0 + i as f64 / rings as f64;
            vertices.push([s * t.cos(), s * t.sin(), 0.0]);
        }
    }
    let id = |i: usize, j: usize| i * sectors + j % sectors;
    let mut quads = Vec::new();
    for i in 0..rings {
        for j in 0..sectors {
            quads.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let shell = Shell::from_quad_mesh(vertices, &quads);
    let topo = shell.check().unwrap();
    let (a, b) = (id(3, 0), id(3, sectors / 2));
    let refined = refine_cone_rings(&shell, &topo, &[a, b]);
    let t2 = refined.check().unwrap();
    let cones = [
        Cone {
            vertex: a,
            index: 1,
        },
        Cone {
            vertex: b,
            index: -1,
        },
    ];
    let metric = ricci_flow(&refined, &t2, &cones, &RicciOptions::default()).unwrap();
    assert!(metric.max_error < 1e-9 && metric.iterations <= 100);
    assert!((metric.curvature[a] - std::f64::consts::FRAC_PI_2).abs() < 1e-9);
    assert!((metric.curvature[b] + std::f64::consts::FRAC_PI_2).abs() < 1e-9);
}
