//! Element quality: SICN and scaled Jacobian of quads sampled at the four
//! corners with a reference normal (Eq. 12 of the quasi-structured paper).
//!
//! For corner i of quad (x0, x1, x2, x3), with `a = x_{i+1} − x_i` and
//! `b = x_{i−1} − x_i` and unit normal `N_i`:
//! - `SJ_i   = (a × b)·N_i / (|a| |b|)`
//! - `SICN_i = 2 (a × b)·N_i / (|a|² + |b|²)`
//!
//! and the quad's value is the minimum over its corners. A square gives 1, a
//! 2:1 rectangle SICN 0.8 and SJ 1, an inverted corner a negative value.
//!
//! [`element_corner_sicn`] is the same measure judged from the element alone,
//! without a surface normal: the judge of users' tools (Gmsh's `minSICN` on a
//! mesh file read without its CAD).

use geometry::vec3::{cross, dot, norm, sub, Vec3};

/// SICN of each corner of the quad `p` with corner normals `n` (unit vectors).
pub fn corner_sicn(p: &[Vec3; 4], n: &[Vec3; 4]) -> [f64; 4] {
    [0, 1, 2, 3].map(|i| {
        let (c, den) = corner_cross(p, i);
        cad_value(c, den, n[i])
    })
}

/// One corner's SICN with the normal `n` from its cross product `c` and
/// `den` ([`corner_cross`]); 0 for a corner of zero length.
#[inline]
fn cad_value(c: Vec3, den: f64, n: Vec3) -> f64 {
    if den > 0.0 {
        2.0 * dot(c, n) / den
    } else {
        0.0
    }
}

/// Scaled Jacobian of each corner of the quad `p` with corner normals `n`.
pub fn corner_scaled_jacobian(p: &[Vec3; 4], n: &[Vec3; 4]) -> [f64; 4] {
    let mut out = [0.0; 4];
    for i in 0..4 {
        let a = sub(p[(i + 1) % 4], p[i]);
        let b = sub(p[(i + 3) % 4], p[i]);
        let den = (dot(a, a) * dot(b, b)).sqrt();
        out[i] = if den > 0.0 {
            dot(cross(a, b), n[i]) / den
        } else {
            0.0
        };
    }
    out
}

/// Quad SICN: the minimum of [`corner_sicn`].
pub fn quad_sicn(p: &[Vec3; 4], n: &[Vec3; 4]) -> f64 {
    corner_sicn(p, n).into_iter().fold(f64::INFINITY, f64::min)
}

/// The quad's SICN as both validity judges see it, the number every
/// acceptance test of the meshers compares: [`quad_sicn`] with the CAD
/// normals `n`, replaced by [`quad_element_sicn`] when the CAD normals find
/// the quad valid but the element geometry does not (a quad Gmsh's `minSICN`
/// would call inverted in the written file is rejected).
///
/// A quad already invalid with the CAD normals keeps its CAD value: that one
/// varies smoothly as a node moves, which the untangling needs, while the
/// element judge jumps when corner 1, its reference, flips.
pub fn quad_sicn_both_judges(p: &[Vec3; 4], n: &[Vec3; 4]) -> f64 {
    // each corner's cross product and denominator, shared by both judges
    // (the same arithmetic as [`corner_sicn`] and [`element_corner_sicn`],
    // so the values are theirs bit for bit)
    let mut c = [[0.0; 3]; 4];
    let mut den = [0.0; 4];
    let mut cad = f64::INFINITY;
    for i in 0..4 {
        (c[i], den[i]) = corner_cross(p, i);
        cad = cad.min(cad_value(c[i], den[i], n[i]));
    }
    if cad > 0.0 {
        // the element judge's minimum matters only when negative, and a
        // corner is negative only on the far side of the reference: the
        // others' norms are not taken
        let reference = element_reference(c[1]);
        let mut element = f64::INFINITY;
        for i in 0..4 {
            if dot(c[i], reference) < 0.0 {
                element = element.min(element_value(c[i], den[i], reference));
            }
        }
        if element < 0.0 {
            return element;
        }
    }
    cad
}

/// Quad scaled Jacobian: the minimum of [`corner_scaled_jacobian`].
pub fn quad_scaled_jacobian(p: &[Vec3; 4], n: &[Vec3; 4]) -> f64 {
    corner_scaled_jacobian(p, n)
        .into_iter()
        .fold(f64::INFINITY, f64::min)
}

/// Element-geometry SICN values smaller than this in magnitude are 0 (flat
/// corner, neither sign): see [`element_corner_sicn`].
pub const ELEMENT_SICN_FLAT: f64 = 1e-8;

/// SICN of each corner of the quad `p` judged from the element alone, with
/// no reference normal from outside: the sign Gmsh's `minSICN` gives to a
/// linear quad of a mesh read without its CAD.
///
/// Derivation. The bilinear map `x(u, v) = x0 + u e + v f + u v d` on
/// [0, 1]² (`e = x1 − x0`, `f = x3 − x0`, `d = x0 − x1 + x2 − x3`) has
/// `x_u × x_v = e × f + u (e × d) + v (d × f)` (the `uv` term is `d × d = 0`),
/// so for any fixed normal `n` the Jacobian `n · (x_u × x_v)` is affine in
/// (u, v): its sign over the element is decided at the four corners, where
/// `x_u × x_v` is the corner cross product `c_i = a_i × b_i` of Eq. 12. The
/// element's own natural normal would be the centre one, `½ (x2 − x0) ×
/// (x3 − x1)`; Gmsh's reference is another (measured with Gmsh 4.15.2, not
/// documented by it): the corner cross product at node 1, `c_1 = (x1 − x0) ×
/// (x2 − x0)`, the normal of the triangle (x0, x1, x2), with the corner's
/// unprojected magnitude:
///
/// `value_i = sign(c_i · c_1) · 2 |c_i| / (|a_i|² + |b_i|²)`.
///
/// This reproduces Gmsh's `minSICN` to 2e-14 on every quad of its own
/// meshes of the bundled models at size factors 1 and 3 but a few
/// near-degenerate ones (nodes 1e-7 apart), and its sign on all of them
/// (the centre normal disagreed in sign on up to 8 quads a mesh: twisted
/// quads, whose verdict in Gmsh depends on which node is numbered first). A
/// value below [`ELEMENT_SICN_FLAT`] in magnitude is 0: its sign is rounding
/// noise, and Gmsh's evaluation returns 0 there (measured: 0 for a corner
/// 1e-9 off straight, where this formula gives −4e-9). When `c_1 = 0`
/// (corner 1 straight) every value is 0, as in Gmsh.
pub fn element_corner_sicn(p: &[Vec3; 4]) -> [f64; 4] {
    let reference = element_reference(corner_cross(p, 1).0);
    [0, 1, 2, 3].map(|i| {
        let (c, den) = corner_cross(p, i);
        element_value(c, den, reference)
    })
}

/// Corner `i`'s cross product `a × b` and `|a|² + |b|²` (module docs).
#[inline]
fn corner_cross(p: &[Vec3; 4], i: usize) -> (Vec3, f64) {
    let a = sub(p[(i + 1) % 4], p[i]);
    let b = sub(p[(i + 3) % 4], p[i]);
    (cross(a, b), dot(a, a) + dot(b, b))
}

/// The element judge's reference normal from corner 1's cross product `c1`,
/// scaled to its largest component (the sign of `c_i · c_1` survives
/// coordinates whose squares underflow); 0 when `c1` is 0 or not finite.
#[inline]
fn element_reference(c1: Vec3) -> Vec3 {
    let big = c1.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if big > 0.0 && c1.iter().all(|x| x.is_finite()) {
        c1.map(|x| x / big)
    } else {
        [0.0; 3]
    }
}

/// One corner's element-geometry SICN from its cross product `c`, its
/// `den` and the [`element_reference`] (see [`element_corner_sicn`]).
#[inline]
fn element_value(c: Vec3, den: f64, reference: Vec3) -> f64 {
    let side = dot(c, reference);
    let value = 2.0 * norm(c) / den;
    // NaN (a zero-length corner, non-finite coordinates) fails the tests
    if side != 0.0 && !side.is_nan() && value >= ELEMENT_SICN_FLAT {
        value.copysign(side)
    } else {
        0.0
    }
}

/// Quad element-geometry SICN: the minimum of [`element_corner_sicn`].
pub fn quad_element_sicn(p: &[Vec3; 4]) -> f64 {
    element_corner_sicn(p)
        .into_iter()
        .fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;
    const Z: [Vec3; 4] = [[0.0, 0.0, 1.0]; 4];

    #[test]
    fn hand_computed_values() {
        let square = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        assert!((quad_sicn(&square, &Z) - 1.0).abs() < 1e-15);
        let rect = [
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [2.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        assert!((quad_sicn(&rect, &Z) - 0.8).abs() < 1e-15);
        assert!((quad_scaled_jacobian(&rect, &Z) - 1.0).abs() < 1e-15);
        // clockwise seen from +z: inverted
        let cw = [square[0], square[3], square[2], square[1]];
        assert!(quad_sicn(&cw, &Z) < 0.0);
        // a tiny edge: SICN → 0 while SJ stays sin(angle)
        let tiny = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [1e-12, 1.0, 0.0],
        ];
        let flat = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0 + 1e-12, 1e-12, 0.0],
            [1.0, 1.0, 0.0],
        ];
        assert!(quad_sicn(&tiny, &Z) > 0.99);
        assert!(quad_sicn(&flat, &Z) < 1e-9);
    }

    fn close4(got: [f64; 4], want: [f64; 4]) -> bool {
        got.iter().zip(&want).all(|(a, b)| (a - b).abs() < 1e-12)
    }

    #[test]
    fn element_sicn_of_a_square_is_one() {
        let square = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        assert!(close4(element_corner_sicn(&square), [1.0; 4]));
        // no outside normal: the square seen from below is a square too
        let flipped = [square[0], square[3], square[2], square[1]];
        assert!(close4(element_corner_sicn(&flipped), [1.0; 4]));
    }

    /// The arrow (0,0) (2,0) (2,2) (1.5,0.5): corner 3 is reflex,
    /// c_3 = (−1.5,−0.5) × (0.5,1.5) = −2 against c_1 = (0,2) × (−2,0) = 4,
    /// |a|² + |b|² = 5, so −2·2/5 = −0.8; corners 0 and 2 give 2·1/6.5, corner 1 1.
    #[test]
    fn planar_arrow_is_negative_at_its_reflex_corner() {
        let arrow = [
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [2.0, 2.0, 0.0],
            [1.5, 0.5, 0.0],
        ];
        let want = [4.0 / 13.0, 1.0, 4.0 / 13.0, -0.8];
        assert!(close4(element_corner_sicn(&arrow), want));
        // planar: the same values as Eq. 12 with the plane's normal
        assert!(close4(corner_sicn(&arrow, &Z), want));
        assert!((quad_element_sicn(&arrow) + 0.8).abs() < 1e-12);
    }

    /// Two non-planar quads on the unit square with node 2 or 3 lifted.
    #[test]
    fn twisted_quads_valid_and_folded() {
        // node 2 lifted by 0.5: c_1 = (0,1,.5) × (−1,0,0) = (0,−.5,1); every
        // corner agrees with it; the smallest is corner 2,
        // |(−.5,−.5,1)| = √1.5 over |a|² + |b|² = 2.5
        let twisted = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.5],
            [0.0, 1.0, 0.0],
        ];
        let side = 2.0 * 1.25f64.sqrt() / 2.25;
        let want = [1.0, side, 2.0 * 1.5f64.sqrt() / 2.5, side];
        assert!(close4(element_corner_sicn(&twisted), want));
        // node 3 at (1.5, .5, 1), over the quad's other half: c_1 = (0,0,1),
        // c_2 = (.5,−.5,1) × (0,−1,0) = (1,0,−.5) and c_3 = (1,−1,−1) point
        // against it: −2·√1.25/2.5 and −2·√3/5; corner 0 (0,−1,.5): 2·√1.25/4.5
        let folded = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [1.5, 0.5, 1.0],
        ];
        let want = [
            2.0 * 1.25f64.sqrt() / 4.5,
            1.0,
            -2.0 * 1.25f64.sqrt() / 2.5,
            -2.0 * 3f64.sqrt() / 5.0,
        ];
        assert!(close4(element_corner_sicn(&folded), want));
        // the centre normal ½ (x2 − x0) × (x3 − x1) ∝ (1,−1,0) would pass it
        // (corner 1 exactly 0, the others positive): Gmsh does not use it
        let centre = [[
            std::f64::consts::FRAC_1_SQRT_2,
            -std::f64::consts::FRAC_1_SQRT_2,
            0.0,
        ]; 4];
        assert!(quad_sicn(&folded, &centre) >= 0.0);
    }

    #[test]
    fn flat_corners_are_zero_not_negative() {
        // corner 1 straight: no reference normal, every value 0 (as Gmsh)
        let straight = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [1.0, -1.0, 0.0],
        ];
        assert_eq!(element_corner_sicn(&straight), [0.0; 4]);
        // corner 2 reflex by 1e-12: rounding noise, 0; by 1e-3: negative
        for (e, negative) in [(1e-12, false), (1e-3, true)] {
            let p = [
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.5 - e, 0.5 - e, 0.0],
                [0.0, 1.0, 0.0],
            ];
            assert_eq!(quad_element_sicn(&p) < 0.0, negative, "{e}");
            assert!(quad_element_sicn(&p) <= 0.0);
        }
        // degenerate and non-finite input: 0, never NaN
        assert_eq!(element_corner_sicn(&[[1.0; 3]; 4]), [0.0; 4]);
        let nan = [
            [f64::NAN, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        assert_eq!(element_corner_sicn(&nan), [0.0; 4]);
    }

    /// A bow-tie with each corner's normal along its own cross product:
    /// every CAD-normal corner value is positive, but corners 2 and 3 turn
    /// against corner 1, so Gmsh would call it inverted and the acceptance
    /// value is the element judge's; a quad invalid with the CAD normals
    /// keeps its CAD value.
    #[test]
    fn both_judges_reject_what_either_rejects() {
        let bow = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
        ];
        let up = [0.0, 0.0, 1.0];
        let down = [0.0, 0.0, -1.0];
        let own = [up, up, down, down];
        assert!(quad_sicn(&bow, &own) > 0.0);
        let element = quad_element_sicn(&bow);
        assert!(element < 0.0);
        assert_eq!(quad_sicn_both_judges(&bow, &own), element);
        // with one outside normal the CAD judge already rejects it
        assert_eq!(quad_sicn_both_judges(&bow, &Z), quad_sicn(&bow, &Z));
        assert!(quad_sicn(&bow, &Z) < 0.0);
        // a valid square: both judges agree, the CAD value is kept
        let square = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        assert_eq!(quad_sicn_both_judges(&square, &Z), quad_sicn(&square, &Z));
        assert!((quad_sicn_both_judges(&square, &Z) - 1.0).abs() < 1e-12);
    }
    /// The two judges as separate functions (the definition
    /// [`quad_sicn_both_judges`] computes in one pass).
    fn both_judges_by_definition(p: &[Vec3; 4], n: &[Vec3; 4]) -> f64 {
        let cad = quad_sicn(p, n);
        if cad > 0.0 {
            let element = quad_element_sicn(p);
            if element < 0.0 {
                return element;
            }
        }
        cad
    }

    #[test]
    fn both_judges_in_one_pass_equal_the_definition_bit_for_bit() {
        // a fixed pseudo-random sequence (64-bit LCG) of quads near a unit
        // square: perturbed, folded, twisted, with repeated and tiny corners
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let base = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let (mut element_won, mut cad_negative) = (0, 0);
        for case in 0..20_000 {
            let scale = [1.0, 0.3, 1e-9][case % 3];
            let mut p = base;
            for c in p.iter_mut() {
                for x in c.iter_mut() {
                    *x += scale * next();
                }
            }
            if case % 7 == 0 {
                p[2] = p[1]; // a repeated corner
            }
            if case % 11 == 0 {
                p[3][2] += 2.0 * next(); // out of plane
            }
            let mut n = Z;
            for c in n.iter_mut() {
                let v = [0.2 * next(), 0.2 * next(), 1.0];
                let l = norm(v);
                *c = v.map(|x| x / l);
            }
            let want = both_judges_by_definition(&p, &n);
            let got = quad_sicn_both_judges(&p, &n);
            assert_eq!(got.to_bits(), want.to_bits(), "case {case}: {p:?} {n:?}");
            if want < 0.0 && quad_sicn(&p, &n) > 0.0 {
                element_won += 1;
            }
            if quad_sicn(&p, &n) < 0.0 {
                cad_negative += 1;
            }
        }
        // both branches were exercised
        assert!(element_won > 100, "{element_won}");
        assert!(cad_negative > 100, "{cad_negative}");
    }
}
