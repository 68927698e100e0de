//! The ideal valence of a vertex from its angle: one rule for the whole
//! crate, in two counts. At a CAD corner or boundary vertex the face wants
//! one quad per right angle of its interior angle (paper "quasi-structured
//! quad meshing", §6.1: `n̄ = clamp(round(γ / 90°), 1, 4)` quads, so
//! `n̄ + 1` edges along a boundary); at a pole with a closed fan, one quad
//! per right angle of the cone angle, at least 3. [`ideal_corner_valence`]
//! counts quads from radians, [`ideal_boundary_valence`] edges from
//! degrees; they agree (edges = quads + 1) on every finite angle, which the
//! tests check.

use std::f64::consts::PI;

/// Ideal quad valence of a corner of interior angle `angle` (radians):
/// `clamp(round(γ / 90°), 1, 4)` (spec §11.1).
pub fn ideal_corner_valence(angle: f64) -> i32 {
    ((angle / (PI / 2.0)).round() as i32).clamp(1, 4)
}

/// Ideal valence (edge count) of a boundary vertex from the face's interior
/// angle θ there (degrees): < 135° → 2, < 225° → 3, < 315° → 4, else 5.
/// A straight boundary (180°) wants 3 edges (2 quads), a 90° corner 2.
pub fn ideal_boundary_valence(theta_deg: f64) -> u32 {
    if theta_deg < 135.0 {
        2
    } else if theta_deg < 225.0 {
        3
    } else if theta_deg < 315.0 {
        4
    } else {
        5
    }
}

/// Ideal valence of a pole with a closed fan (a sphere pole, a cone apex)
/// from its cone angle θ (the sum of the 3D quad angles there, degrees): the
/// number of right angles that fit, θ / 90° rounded, at least 3 (a point of a
/// smooth surface, 360°, wants 4; a sharp cone tip 3).
pub fn ideal_pole_valence(theta_deg: f64) -> u32 {
    if !theta_deg.is_finite() {
        return 4;
    }
    ((theta_deg / 90.0).round() as i64).clamp(3, 8) as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn boundary_edges_are_corner_quads_plus_one_at_every_angle() {
        for i in 0..=7200 {
            let deg = i as f64 * 0.1;
            let quads = ideal_corner_valence(deg.to_radians());
            assert_eq!(ideal_boundary_valence(deg) as i32, quads + 1, "at {deg}°");
        }
        assert_eq!(ideal_corner_valence(PI / 2.0), 1);
        assert_eq!(ideal_corner_valence(PI), 2);
        assert_eq!(ideal_boundary_valence(270.0), 4);
    }

    #[test]
    fn poles_want_one_quad_per_right_angle_of_cone_angle_at_least_three() {
        assert_eq!(ideal_pole_valence(360.0), 4);
        assert_eq!(ideal_pole_valence(200.0), 3);
        assert_eq!(ideal_pole_valence(500.0), 6);
        assert_eq!(ideal_pole_valence(f64::NAN), 4);
    }
}
