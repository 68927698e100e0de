//! S8 for an annulus with no cone (spec ricci-flow-iga-reconstruction §8,
//! footnote 3: "an annulus with no cone or feature uses its loop cut"). With
//! K̄ = 0 everywhere the flat metric is a straight cylinder: the two sides of
//! the loop cut differ by a pure translation t (no rotation), both boundary
//! loops are straight lines parallel to t, and ψ is periodic along t. Rotated
//! so t = (C, 0), the layout is ONE rectangle [x0, x0 + C] × [y0, y1] whose
//! left and right sides are the same arc: the seam, the vertical line through
//! the cut's end on the lower loop. Its four corners are two layout nodes
//! ([`Layout::node_glue`]), its bottom and top arcs are the closed loops, and
//! points of the strip are located through the period ([`Layout::period_x`],
//! [`super::PsiLocator::with_period`]).

use super::{Layout, LayoutError, LayoutRect};
use crate::cut::CutMesh;
use crate::immersion::Immersion;
use crate::shell::ShellTopology;

/// The layout of a cone-free annulus and the immersion rotated to it.
#[derive(Clone, Debug, PartialEq)]
pub struct AnnulusLayout {
    /// One rectangle, its sides glued along the seam.
    pub layout: Layout,
    /// ψ rotated so the cut's translation is (C, 0) and the loops are horizontal.
    pub immersion: Immersion,
    /// The translation C between the two sides of the cut (the loops' length in ψ).
    pub period: f64,
    /// The height H of the strip.
    pub height: f64,
    /// The rotation between the cut's two sides, from the chords of its two
    /// copies (radians; 0 for a cylinder).
    pub seam_rotation: f64,
    /// The largest distance of a loop vertex from its loop's line, in ψ.
    pub max_deviation: f64,
    /// The diagonal √(C² + H²) of the rectangle.
    pub size: f64,
}

/// Lays out a cone-free annulus cut by one loop cut: checks the cut's sides
/// differ by a translation (no quarter turn; the rotation of the copies'
/// chords, times the chord, and each child's distance from the translation
/// within `tolerance` × C) and both
/// loops are straight within `tolerance` × the rectangle's diagonal, and
/// returns the one-rectangle layout (see the module docs).
pub fn annulus_layout(
    topo: &ShellTopology,
    cut: &CutMesh,
    imm: &Immersion,
    tolerance: f64,
) -> Result<AnnulusLayout, LayoutError> {
    let not = |s: String| LayoutError::NotOrthogonal(s);
    if topo.boundary_loops.len() != 2 || cut.paths.len() != 1 || imm.transitions.len() != 1 {
        return Err(not(format!(
            "an annulus needs two boundary loops and one loop cut ({} loops, {} cut paths)",
            topo.boundary_loops.len(),
            cut.paths.len()
        )));
    }
    let path = &cut.paths[0];
    let tr = &imm.transitions[0];
    // The rotation between the two copies, from their chords (first to last
    // child): per-edge angles of short cut edges carry ψ's rounding.
    let (l0, l1) = (
        path.sides[0].left[0],
        path.sides[path.sides.len() - 1].left[1],
    );
    let (r0, r1) = (
        path.sides[0].right[0],
        path.sides[path.sides.len() - 1].right[1],
    );
    let dl = [imm.uv[l1][0] - imm.uv[l0][0], imm.uv[l1][1] - imm.uv[l0][1]];
    let dr = [imm.uv[r1][0] - imm.uv[r0][0], imm.uv[r1][1] - imm.uv[r0][1]];
    let seam_rotation = (dl[0] * dr[1] - dl[1] * dr[0])
        .atan2(dl[0] * dr[0] + dl[1] * dr[1])
        .abs();
    if tr.quarter_turns != 0 {
        return Err(not(format!(
            "the two sides of the loop cut differ by a rotation of {} quarter turn(s), not a translation (the flat annulus is not a cylinder)",
            tr.quarter_turns
        )));
    }
    // The translation: the mean of right − left over the path's children.
    let (mut t, mut n) = ([0.0f64; 2], 0.0);
    for s in &path.sides {
        for m in 0..2 {
            let (l, r) = (imm.uv[s.left[m]], imm.uv[s.right[m]]);
            t[0] += r[0] - l[0];
            t[1] += r[1] - l[1];
            n += 1.0;
        }
    }
    t = [t[0] / n, t[1] / n];
    let period = (t[0] * t[0] + t[1] * t[1]).sqrt();
    if !(period > 0.0 && period.is_finite()) {
        return Err(not("the loop cut's two sides coincide in ψ".into()));
    }
    let mut residual: f64 = 0.0;
    for s in &path.sides {
        for m in 0..2 {
            let (l, r) = (imm.uv[s.left[m]], imm.uv[s.right[m]]);
            residual =
                residual.max(((r[0] - l[0] - t[0]).powi(2) + (r[1] - l[1] - t[1]).powi(2)).sqrt());
        }
    }
    // ψ's curvature residue, summed over Ω and carried across the strip,
    // tilts the copies slightly: both checks are shifts against C.
    let chord = (dl[0] * dl[0] + dl[1] * dl[1]).sqrt();
    if seam_rotation * chord > tolerance * period {
        return Err(not(format!(
            "the two sides of the loop cut differ by a rotation of {seam_rotation:.3e} rad, a shift of {:.3e} × the loop length along the cut (the limit is {tolerance:.0e}): the flat annulus is not a cylinder",
            seam_rotation * chord / period
        )));
    }
    if residual > tolerance * period {
        return Err(not(format!(
            "the two sides of the loop cut are {:.3e} × the loop length from a translation (the limit is {tolerance:.0e})",
            residual / period
        )));
    }
    // Rotate t onto +x.
    let (c, s) = (t[0] / period, -t[1] / period);
    let uv: Vec<[f64; 2]> = imm
        .uv
        .iter()
        .map(|p| [c * p[0] - s * p[1], s * p[0] + c * p[1]])
        .collect();
    // The loops: each a horizontal line (every child of its vertices).
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); topo.on_boundary.len()];
    for (ch, &p) in cut.parent.iter().enumerate() {
        children[p].push(ch);
    }
    let mut lines = Vec::with_capacity(2);
    for l in &topo.boundary_loops {
        let ys: Vec<f64> = l
            .iter()
            .flat_map(|&v| children[v].iter().map(|&ch| uv[ch][1]))
            .collect();
        let mean = ys.iter().sum::<f64>() / ys.len().max(1) as f64;
        let dev = ys.iter().map(|y| (y - mean).abs()).fold(0.0, f64::max);
        lines.push((mean, dev));
    }
    let (lower, upper) = if lines[0].0 <= lines[1].0 {
        (0, 1)
    } else {
        (1, 0)
    };
    let (y0, y1) = (lines[lower].0, lines[upper].0);
    let height = y1 - y0;
    let size = (period * period + height * height).sqrt();
    let max_deviation = lines[0].1.max(lines[1].1);
    if !(height > tolerance * size) {
        return Err(not(format!(
            "the flat annulus has no height: its loops lie at y = {y0:.6e} and {y1:.6e} in ψ"
        )));
    }
    if max_deviation > tolerance * size {
        return Err(not(format!(
            "a boundary loop in ψ bends {:.3e} × its size off its line (the limit is {tolerance:.0e})",
            max_deviation / size
        )));
    }
    // The seam: the vertical through the cut's end on the lower loop (its left child).
    let lower_loop = &topo.boundary_loops[lower];
    let first = path.vertices[0];
    let start_child = if lower_loop.contains(&first) {
        path.sides[0].left[0]
    } else {
        path.sides[path.sides.len() - 1].left[1]
    };
    let x0 = uv[start_child][0];
    let layout = Layout {
        nodes: vec![[x0, y0], [x0, y1], [x0 + period, y0], [x0 + period, y1]],
        arcs: vec![[0, 2], [1, 3], [0, 1]],
        arc_on_boundary: vec![true, true, false],
        rects: vec![LayoutRect {
            corners: [0, 2, 3, 1],
            sides: [(0, false), (1, false), (2, false), (2, false)],
        }],
        separatrices: 0,
        node_glue: vec![0, 1, 0, 1],
        period_x: Some(period),
    };
    let immersion = Immersion {
        uv,
        rotation: imm.rotation + s.atan2(c),
        ..imm.clone()
    };
    Ok(AnnulusLayout {
        layout,
        immersion,
        period,
        height,
        seam_rotation,
        max_deviation,
        size,
    })
}
