//! The paper's figure cycles, built by hand as [`CycleLoops`] (compiled for
//! tests only): the saddle (Fig. 4), the equilateral triangle (Fig. 12), the
//! spherical octant, the house with an off-centre apex (Figs. 5 top and 7),
//! the L (Fig. 5 bottom), the circle (Fig. 16b), a two-sided lens and the
//! letter P (Fig. 17). Outer loops run counter-clockwise about +z (the
//! octant: about (1,1,1)); holes run the other way.

use std::f64::consts::{FRAC_PI_2, PI};

use super::{CycleLoops, LoopPolyline};

/// A loop through the given points, none fixed.
fn free_loop(points: Vec<[f64; 3]>) -> LoopPolyline {
    LoopPolyline { points, fixed: Vec::new() }
}

/// A planar polygon (z = 0) from its corners.
fn polygon(corners: &[[f64; 2]]) -> LoopPolyline {
    free_loop(corners.iter().map(|c| [c[0], c[1], 0.0]).collect())
}

/// A cycle with no holes.
fn single(outer: LoopPolyline) -> CycleLoops {
    CycleLoops { outer, holes: Vec::new(), surface: None }
}

/// Fig. 4: a twisted 4-sided saddle, the boundary of z = h·xy over [−1, 1]²
/// (four straight sides of a skew quadrilateral, corners at heights ±h).
pub fn saddle(h: f64) -> CycleLoops {
    single(free_loop(vec![[-1.0, -1.0, h], [1.0, -1.0, -h], [1.0, 1.0, h], [-1.0, 1.0, -h]]))
}

/// Fig. 12: an equilateral triangle of side 1.
pub fn triangle() -> CycleLoops {
    polygon(&[[0.0, 0.0], [1.0, 0.0], [0.5, 0.75f64.sqrt()]]).into()
}

/// Fig. 12: the spherical octant, three 90° great-circle arcs of the unit
/// sphere from x to y to z, `per_arc` samples each.
pub fn octant(per_arc: usize) -> CycleLoops {
    let axes = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let mut points = Vec::new();
    for a in 0..3 {
        let (u, v) = (axes[a], axes[(a + 1) % 3]);
        for k in 0..per_arc {
            let th = FRAC_PI_2 * k as f64 / per_arc as f64;
            points.push([0, 1, 2].map(|i| th.cos() * u[i] + th.sin() * v[i]));
        }
    }
    single(free_loop(points))
}

/// Figs. 5 top and 7: a house pentagon with its apex off-centre: bottom
/// (0,0)–(2,0), walls of height 1, apex at (0.7, 1.5).
pub fn house() -> CycleLoops {
    house_with_apex([0.7, 1.5])
}

/// A house pentagon with the given apex (bottom (0,0)–(2,0), walls of height 1).
pub fn house_with_apex(apex: [f64; 2]) -> CycleLoops {
    polygon(&[[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], apex, [0.0, 1.0]]).into()
}

/// The house's bottom side: its two end points (for checking it was split).
pub const HOUSE_BOTTOM: [[f64; 3]; 2] = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0]];

/// Fig. 5 bottom: an L of three unit squares.
pub fn ell() -> CycleLoops {
    polygon(&[[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [1.0, 1.0], [1.0, 2.0], [0.0, 2.0]]).into()
}

/// Fig. 16b: a unit circle of `n` samples.
pub fn circle(n: usize) -> CycleLoops {
    single(free_loop(
        (0..n).map(|k| 2.0 * PI * k as f64 / n as f64).map(|t| [t.cos(), t.sin(), 0.0]).collect(),
    ))
}

/// A two-sided lens: two arcs of radius 1 (centres (0, ∓0.5)) meeting at
/// (±√0.75, 0) at 60° turns, `per_arc` samples each.
pub fn lens(per_arc: usize) -> CycleLoops {
    let mut points = Vec::new();
    for k in 0..per_arc {
        let th = (30.0 + 120.0 * k as f64 / per_arc as f64).to_radians();
        points.push([th.cos(), th.sin() - 0.5, 0.0]);
    }
    for k in 0..per_arc {
        let th = (210.0 + 120.0 * k as f64 / per_arc as f64).to_radians();
        points.push([th.cos(), th.sin() + 0.5, 0.0]);
    }
    single(free_loop(points))
}

/// Fig. 17: a letter P: a rectilinear outline (stem 1 wide, bowl on top) with
/// one rectangular hole in the bowl, the hole clockwise.
pub fn letter_p() -> CycleLoops {
    CycleLoops {
        outer: polygon(&[[0.0, 0.0], [1.0, 0.0], [1.0, 1.5], [2.5, 1.5], [2.5, 4.0], [0.0, 4.0]]),
        holes: vec![polygon(&[[1.0, 2.0], [1.0, 3.5], [2.0, 3.5], [2.0, 2.0]])],
        surface: None,
    }
}

/// The hole of [`letter_p`], for checks.
pub const P_HOLE: [[f64; 2]; 2] = [[1.0, 2.0], [2.0, 3.5]];

impl From<LoopPolyline> for CycleLoops {
    fn from(outer: LoopPolyline) -> Self {
        single(outer)
    }
}

/// Fig. 15: an L (corners (0,0), (2,0), (2,1), (1,1), (1,2), (0,2)) above a
/// 2 × 1 rectangle that shares the L's bottom side, as a two-cycle network
/// (JSON text, docs/curve-networks.md). Every curve is sampled every 0.05
/// (δ = 0.05), so the L's segment end at the middle of the shared side,
/// 1 away from the rectangle's corners, is a T-junction beyond 5δ.
pub fn ell_on_rectangle_json() -> String {
    let dense = |corners: &[[f64; 2]]| -> Vec<[f64; 3]> {
        let mut out = vec![[corners[0][0], corners[0][1], 0.0]];
        for w in corners.windows(2) {
            let len = ((w[1][0] - w[0][0]).powi(2) + (w[1][1] - w[0][1]).powi(2)).sqrt();
            let n = (len / 0.05).round() as usize;
            for k in 1..=n {
                let t = k as f64 / n as f64;
                out.push([w[0][0] + t * (w[1][0] - w[0][0]), w[0][1] + t * (w[1][1] - w[0][1]), 0.0]);
            }
        }
        out
    };
    let curves = [
        // 0: the shared side, (0,0) to (2,0)
        dense(&[[0.0, 0.0], [2.0, 0.0]]),
        // 1: the rest of the L, (2,0) round to (0,0)
        dense(&[[2.0, 0.0], [2.0, 1.0], [1.0, 1.0], [1.0, 2.0], [0.0, 2.0], [0.0, 0.0]]),
        // 2: the rest of the rectangle, (0,0) down and round to (2,0)
        dense(&[[0.0, 0.0], [0.0, -1.0], [2.0, -1.0], [2.0, 0.0]]),
    ];
    let curves: Vec<String> = curves
        .iter()
        .map(|c| format!("{{\"points\": {:?}}}", c))
        .collect();
    format!(
        "{{\"curves\": [{}], \"cycles\": [{{\"loops\": [[[0, 1], [1, 1]]]}}, {{\"loops\": [[[2, 1], [0, -1]]]}}]}}",
        curves.join(", ")
    )
}

/// A circle of radius `r` about `centre` (z = 0), `n` samples,
/// counter-clockwise about +z, or clockwise when `hole`.
fn circle_loop(centre: [f64; 2], r: f64, n: usize, hole: bool) -> LoopPolyline {
    let sign = if hole { -1.0 } else { 1.0 };
    free_loop(
        (0..n)
            .map(|k| sign * 2.0 * PI * k as f64 / n as f64)
            .map(|t| [centre[0] + r * t.cos(), centre[1] + r * t.sin(), 0.0])
            .collect(),
    )
}

/// An annulus: the unit circle pierced by a circular hole of radius
/// `hole_r` about `hole_centre`, 64 and 48 samples.
pub fn annulus(hole_centre: [f64; 2], hole_r: f64) -> CycleLoops {
    CycleLoops {
        outer: circle_loop([0.0, 0.0], 1.0, 64, false),
        holes: vec![circle_loop(hole_centre, hole_r, 48, true)],
        surface: None,
    }
}

/// A square [−1, 1]² pierced by a circular hole of radius `hole_r` about
/// `hole_centre` (48 samples).
pub fn square_with_round_hole(hole_centre: [f64; 2], hole_r: f64) -> CycleLoops {
    CycleLoops {
        outer: polygon(&[[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]),
        holes: vec![circle_loop(hole_centre, hole_r, 48, true)],
        surface: None,
    }
}

/// A square [−1, 1]² pierced by circular holes (centre, radius), 48
/// samples each.
pub fn square_with_round_holes(holes: &[([f64; 2], f64)]) -> CycleLoops {
    CycleLoops {
        outer: polygon(&[[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]),
        holes: holes.iter().map(|&(c, r)| circle_loop(c, r, 48, true)).collect(),
        surface: None,
    }
}

/// A 2w × 2 rectangle centred at the origin with round holes (48-gons,
/// clockwise): `square_with_round_holes` stretched along x.
pub fn rectangle_with_round_holes(w: f64, holes: &[([f64; 2], f64)]) -> CycleLoops {
    CycleLoops {
        outer: polygon(&[[-w, -1.0], [w, -1.0], [w, 1.0], [-w, 1.0]]),
        holes: holes.iter().map(|&(c, r)| circle_loop(c, r, 48, true)).collect(),
        surface: None,
    }
}
