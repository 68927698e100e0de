use super::*;
use crate::shell::tests::grid;

#[test]
fn a_cone_walled_in_by_other_cones_is_unreachable() {
    let shell = grid(4, |x, y| [x, y, 0.0]);
    let topo = shell.check().unwrap();
    // Vertex 12 is (2, 2); all its neighbours are interior cones too.
    let mut cones = vec![Cone {
        vertex: 12,
        index: 1,
    }];
    for &[a, b] in &topo.edges {
        if a == 12 || b == 12 {
            cones.push(Cone {
                vertex: a + b - 12,
                index: -1,
            });
        }
    }
    let err = cut_to_disk(&shell, &topo, &cones).unwrap_err();
    assert_eq!(
        err,
        CutError::Unreachable {
            what: "the cone on vertex 12".into(),
            position: [0.5, 0.5, 0.0]
        }
    );
}

#[test]
fn a_disk_with_one_interior_cone_gets_one_cut_to_it() {
    let shell = grid(4, |x, y| [x, y, 0.0]);
    let topo = shell.check().unwrap();
    let cones = [Cone {
        vertex: 12,
        index: 1,
    }];
    let cut = cut_to_disk(&shell, &topo, &cones).unwrap();
    assert_eq!(cut.branches.len(), 1);
    let path = &cut.branches[0].vertices;
    // From the boundary to the cone, two edges long (the grid's nearest side).
    assert_eq!(path.len(), 3);
    assert!(topo.on_boundary[path[0]] && path[2] == 12);
    assert_eq!(cut.is_cut.iter().filter(|&&c| c).count(), 2);
    // The path's inner vertex gets two children, the cone one, the boundary end two.
    let children = |v: usize| cut.parent.iter().filter(|&&p| p == v).count();
    assert_eq!(
        (children(path[0]), children(path[1]), children(12)),
        (2, 2, 1)
    );
    assert_eq!(cut.parent.len(), shell.vertices.len() + 2);
    assert_eq!(cut.euler, 1);
    // One β with two sides whose children differ except at the cone.
    assert_eq!(cut.paths.len(), 1);
    let beta = &cut.paths[0];
    assert_eq!(beta.sides.len(), 2);
    for s in &beta.sides {
        assert_ne!(s.left[0], s.right[0]);
    }
    let last = beta.sides.last().unwrap();
    let cone_end = if *beta.vertices.last().unwrap() == 12 {
        1
    } else {
        0
    };
    assert_eq!(last.left[cone_end], last.right[cone_end]);
}
