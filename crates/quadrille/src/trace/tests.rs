//! S8 on shells built here through the core and the layout energy: the
//! issue's square with four corner cones (one patch), a house with one
//! interior −1 cone (five separatrices, five quads), and the flat ring
//! with cones ±1 (Fig. 3/8).

use super::*;
use crate::layout_energy::tests::{core, grid, house, ring};
use crate::methods::spline::{cone_core, layout_energy, ConeCore};

fn patches(core: &ConeCore) -> PatchLayout {
    let map = layout_energy(core).expect("the energy converges");
    let layout = trace_patches(
        &core.shell,
        &core.topo,
        &core.cut,
        &core.cones,
        &map.uv,
        &TraceOptions::default(),
    )
    .expect("the tracing ends");
    eprintln!("{}", layout.describe());
    layout
}

#[test]
fn a_square_with_four_corner_cones_is_one_patch() {
    let n = 8;
    let shell = grid(n, |u, v| [3.0 * u, 3.0 * v, 0.0]);
    let cones: Vec<Cone> = [0, n, (n + 1) * (n + 1) - 1, n * (n + 1)]
        .iter()
        .map(|&vertex| Cone { vertex, index: 1 })
        .collect();
    let layout = patches(&core(&shell, &cones));
    // A convex corner (I = 1) sends no separatrix: the boundary alone.
    assert!(layout.traces.is_empty());
    assert_eq!((layout.nodes.len(), layout.arcs.len()), (4, 4));
    assert_eq!(layout.patches.len(), 1);
    assert_eq!(layout.patches[0].corners, 4);
    assert_eq!(layout.patches[0].sides.len(), 4);
    assert_eq!(layout.euler, 1);
    layout.check().expect("one quad");
}

#[test]
fn a_house_with_one_interior_minus_one_cone_is_five_quads() {
    let (shell, cones) = house(12);
    let layout = patches(&core(&shell, &cones));
    // A −1 cone sends 4 − (−1) = 5 separatrices; each ends on a side.
    assert_eq!(layout.traces.len(), 5);
    assert!(layout
        .traces
        .iter()
        .all(|t| matches!(t.end, TraceEnd::Boundary { .. })));
    // 5 boundary corners + 5 hits + the cone; 5 traces + 10 boundary pieces.
    assert_eq!(layout.crossings(), 0);
    assert_eq!((layout.nodes.len(), layout.arcs.len()), (11, 15));
    assert_eq!(layout.patches.len(), 5);
    layout.check().expect("five quads");
    assert_eq!(layout.quads(), 5);
}

#[test]
fn the_flat_ring_with_cones_plus_and_minus_one_traces_to_six_quads() {
    // Fig. 3/8 after the layout energy (converged through the exact snap).
    let (shell, cones) = ring(6, 32);
    let layout = patches(&core(&shell, &cones));
    // 3 + 5 rays; one ray of each cone runs round the ring back into its
    // own cone, so its reverse is the same curve: 6 separatrices.
    assert_eq!(layout.traces.len(), 6);
    let loops = layout
        .traces
        .iter()
        .filter(|t| t.end == TraceEnd::Cone(t.cone))
        .count();
    assert_eq!(loops, 2);
    assert_eq!(layout.crossings(), 2);
    assert_eq!(layout.patches.len(), 6);
    assert_eq!(layout.euler, 0);
    layout.check().expect("six quads");
}

#[test]
fn the_torus_tube_and_drilled_cylinder_traces_to_quads_both_ways() {
    // Issue 31 shell (c): n10o faces 5 and 7 with the proposed cones (χ = −1).
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/cad/n10o_qtorus_cyl.step");
    let model = occt::load(&path).expect("n10o loads");
    let shell = crate::shell::shell_from_model(&model, &[4, 6], model.diagonal() / 72.0).unwrap();
    let topo = shell.check().unwrap();
    let cones = crate::cones::propose_cones(&shell, &topo).unwrap();
    let core = cone_core(&shell, &topo, &cones).unwrap();
    let map = layout_energy(&core).expect("the energy converges");
    let run = |stop_at_traces: bool| {
        let opts = TraceOptions { stop_at_traces };
        let layout = trace_patches(
            &core.shell,
            &core.topo,
            &core.cut,
            &core.cones,
            &map.uv,
            &opts,
        )
        .expect("every separatrix ends");
        eprintln!(
            "n10o, stop at traces {stop_at_traces}: {}",
            layout.describe()
        );
        layout
    };
    let complete = run(false);
    // 1 × (+1) and 5 × (−1): 3 + 25 rays, cone-to-cone ones kept once.
    let rays: usize = core.cones.iter().map(|c| (4 - c.index) as usize).sum();
    assert_eq!(rays, 28);
    assert!(complete.traces.len() <= rays && complete.traces.len() >= rays / 2);
    complete
        .check()
        .expect("complete tracing: every patch a quad");
    assert_eq!(complete.euler, -1);
    assert!(complete.crossings() > 0);
    // Ending on earlier traces: fewer patches (T-junctions), still quads.
    let stopped = run(true);
    assert!(stopped.patches.len() < complete.patches.len());
    stopped
        .check()
        .expect("T-junction layout: every patch a quad");
}
