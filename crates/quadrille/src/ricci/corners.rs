//! Boundary corner cones (spec §4): a boundary vertex whose angle sum θ in
//! the surface rounds to n̄ quarter turns gets index I = 2 − n̄ (90° → 1,
//! 180° → 0, 270° → −1), so the flat metric turns its boundary by exactly
//! I·π/2 there and runs straight in between.

use std::f64::consts::FRAC_PI_2;

use super::Cone;
use crate::shell::{Shell, ShellTopology};

/// The cones of the boundary corners of `shell`: every boundary vertex whose
/// index 2 − round(θ / (π/2)) is not 0, in vertex order. A vertex with a
/// zero angle sum counts as one quarter turn (index 1 at most).
pub fn boundary_corner_cones(shell: &Shell, topo: &ShellTopology) -> Vec<Cone> {
    let sums = shell.angle_sums();
    (0..shell.vertices.len())
        .filter(|&v| topo.on_boundary[v])
        .filter_map(|v| {
            let quarters = ((sums[v] / FRAC_PI_2).round() as i32).max(1);
            let index = 2 - quarters;
            (index != 0).then_some(Cone { vertex: v, index })
        })
        .collect()
}
