use super::*;

/// An n×n grid of unit squares over [0, n]², lifted by `lift`, quads split.
pub(crate) fn grid(n: usize, lift: impl Fn(f64, f64) -> [f64; 3]) -> Shell {
    holed_grid(n, &[], lift)
}

/// [`grid`] without the cells in `holes` (each hole a single cell, apart
/// from the others: one more loop each).
pub(crate) fn holed_grid(
    n: usize,
    holes: &[(usize, usize)],
    lift: impl Fn(f64, f64) -> [f64; 3],
) -> Shell {
    let mut vertices = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            vertices.push(lift(i as f64 / n as f64, j as f64 / n as f64));
        }
    }
    let id = |i: usize, j: usize| j * (n + 1) + i;
    let mut quads = Vec::new();
    for j in 0..n {
        for i in 0..n {
            if !holes.contains(&(i, j)) {
                quads.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
    }
    Shell::from_quad_mesh(vertices, &quads)
}

/// A torus (radii 2 and 0.5) of n × m quads with quad `skip` left out.
fn holed_torus(n: usize, m: usize, skip: usize) -> Shell {
    let tau = std::f64::consts::TAU;
    let mut vertices = Vec::new();
    for i in 0..n {
        for j in 0..m {
            let (a, b) = (tau * i as f64 / n as f64, tau * j as f64 / m as f64);
            let r = 2.0 + 0.5 * b.cos();
            vertices.push([r * a.cos(), r * a.sin(), 0.5 * b.sin()]);
        }
    }
    let id = |i: usize, j: usize| (i % n) * m + (j % m);
    let mut quads = Vec::new();
    for i in 0..n {
        for j in 0..m {
            if i * m + j != skip {
                quads.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
    }
    Shell::from_quad_mesh(vertices, &quads)
}

/// The surface of the unit cube, outward-facing.
pub(crate) fn cube() -> Shell {
    let mut vertices = Vec::new();
    for z in 0..2 {
        for y in 0..2 {
            for x in 0..2 {
                vertices.push([x as f64, y as f64, z as f64]);
            }
        }
    }
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    Shell::from_quad_mesh(vertices, &quads)
}

#[test]
fn a_two_by_two_grid_is_a_disk_with_hand_counted_topology() {
    let s = grid(2, |x, y| [x, y, 0.0]);
    let t = s.check().expect("a disk");
    assert_eq!(
        (s.vertices.len(), t.edges.len(), s.triangles.len()),
        (9, 16, 8)
    );
    assert_eq!(t.euler, 1);
    assert_eq!(t.boundary_loops.len(), 1);
    assert_eq!(t.boundary_loops[0].len(), 8);
    assert_eq!(t.components, 1);
    assert_eq!(t.on_boundary.iter().filter(|&&b| b).count(), 8);
    // The loop runs counter-clockwise (the shell on its left): 0 → 1 → 2.
    let l = &t.boundary_loops[0];
    let at = l.iter().position(|&v| v == 0).unwrap();
    assert_eq!(l[(at + 1) % 8], 1);
    // Angle sums: π/2 at a corner, π on an edge, 2π inside.
    let sums = s.angle_sums();
    assert!((sums[0] - std::f64::consts::FRAC_PI_2).abs() < 1e-14);
    assert!((sums[1] - std::f64::consts::PI).abs() < 1e-14);
    assert!((sums[4] - std::f64::consts::TAU).abs() < 1e-14);
    assert!((s.area() - 1.0).abs() < 1e-14);
}

#[test]
fn a_closed_cube_is_refused_as_not_open() {
    let err = cube().check().unwrap_err();
    assert_eq!(err, ShellError::Closed { component: 0 });
    assert!(
        err.to_string().contains("open shells only; use --faces"),
        "{err}"
    );
}

#[test]
fn a_non_manifold_edge_is_named_by_its_end_points() {
    let s = Shell::from_triangles(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.5, 1.0, 0.0],
            [0.5, -1.0, 0.0],
            [0.5, 0.0, 1.0],
        ],
        vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]],
    );
    let err = s.check().unwrap_err();
    assert_eq!(
        err,
        ShellError::NonManifoldEdge {
            a: [0.0, 0.0, 0.0],
            b: [1.0, 0.0, 0.0],
            count: 3
        }
    );
    let msg = err.to_string();
    assert!(
        msg.contains("[0.0, 0.0, 0.0]") && msg.contains("[1.0, 0.0, 0.0]"),
        "{msg}"
    );
}

#[test]
fn a_flipped_triangle_is_an_orientation_error() {
    let mut s = grid(2, |x, y| [x, y, 0.0]);
    s.triangles[3].swap(0, 1);
    assert!(matches!(s.check(), Err(ShellError::Orientation { .. })));
}

#[test]
fn a_bow_tie_vertex_is_non_manifold() {
    let s = Shell::from_triangles(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [-1.0, 0.0, 0.0],
            [-1.0, -1.0, 0.0],
        ],
        vec![[0, 1, 2], [0, 3, 4]],
    );
    assert!(matches!(
        s.check(),
        Err(ShellError::NonManifoldVertex { vertex: 0, .. })
    ));
}

#[test]
fn a_torus_with_a_hole_is_refused_for_its_genus() {
    let s = holed_torus(12, 8, 5);
    let err = s.check().unwrap_err();
    assert_eq!(
        err,
        ShellError::Genus {
            genus: 1,
            euler: -1,
            loops: 1,
            components: 1
        }
    );
    assert!(err.to_string().contains("genus 1"), "{err}");
}

#[test]
fn bad_indices_and_unused_vertices_are_errors() {
    let s = Shell::from_triangles(vec![[0.0; 3]; 3], vec![[0, 1, 7]]);
    assert!(matches!(
        s.check(),
        Err(ShellError::BadIndex { index: 7, .. })
    ));
    let s = Shell::from_triangles(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [5.0, 5.0, 5.0],
        ],
        vec![[0, 1, 2]],
    );
    assert!(matches!(
        s.check(),
        Err(ShellError::UnusedVertex { vertex: 3, .. })
    ));
    assert_eq!(Shell::default().check(), Err(ShellError::Empty));
}

#[test]
fn two_disks_are_two_components() {
    let mut s = grid(1, |x, y| [x, y, 0.0]);
    let t = grid(1, |x, y| [x + 3.0, y, 0.0]);
    let off = s.vertices.len();
    s.vertices.extend(t.vertices);
    s.triangles.extend(
        t.triangles
            .iter()
            .map(|tr| [tr[0] + off, tr[1] + off, tr[2] + off]),
    );
    let topo = s.check().expect("two disks");
    assert_eq!(
        (topo.components, topo.boundary_loops.len(), topo.euler),
        (2, 2, 2)
    );
}

#[test]
fn welding_triangle_soup_merges_equal_positions() {
    // Two triangles of a unit square, each with its own copies of the corners.
    let soup = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [-0.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    let s = Shell::welded(&soup, &[[0, 1, 2], [3, 4, 5]]);
    assert_eq!(s.vertices.len(), 4);
    assert_eq!(s.triangles.len(), 2);
    let t = s.check().expect("a welded disk");
    assert_eq!((t.edges.len(), t.euler, t.boundary_loops.len()), (5, 1, 1));
    // Unwelded, the same soup is two components.
    let u = Shell::from_triangles(soup.to_vec(), vec![[0, 1, 2], [3, 4, 5]]);
    assert_eq!(u.check().unwrap().components, 2);
}
