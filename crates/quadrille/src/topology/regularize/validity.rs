//! Geometric validity of a quad (paper §II.B, Fig. 12): the quad's vertices are
//! projected onto the tangent plane of the surface at the quad's (u, v) centre
//! (normal = the face's oriented normal there), and the quad is valid when
//! - the four triangles `(A,B,C)`, `(A,C,D)`, `(B,C,D)`, `(B,D,A)` all have
//!   positive signed area about the normal (no fold, no bow-tie, no reflex
//!   angle: the "consistent triangle signs" of the paper), and
//! - the internal angle at every movable vertex lies in the window
//!   `(min_deg, max_deg)`; at fixed (boundary) vertices only the upper bound
//!   of the base window applies, because a CAD corner may be sharper than any
//!   lower bound and cannot move.
//!
//! Why the centre normal: it is what the paper uses, and it is defined even
//! when a vertex sits on a pole.

use geometry::vec3::{self, cross, dot, sub, Vec3};
use geometry::Face;

use crate::core::face_quads::FaceQuads;

/// An angle window in degrees: angles must lie strictly inside.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AngleWindow {
    /// Lower bound (degrees).
    pub min_deg: f64,
    /// Upper bound (degrees).
    pub max_deg: f64,
}

impl AngleWindow {
    /// The permissive window used during regularization, (5°, 175°).
    pub const BASE: AngleWindow = AngleWindow {
        min_deg: 5.0,
        max_deg: 175.0,
    };
}

/// The projected internal angles (degrees, in [0, 360)) of quad `q` and
/// whether its four triangles have positive signed area. `None` when no
/// normal can be found (degenerate quad at a singular point).
pub fn quad_angles(fq: &FaceQuads, face: &Face, q: u32) -> Option<([f64; 4], bool)> {
    let p = fq.quad_xyz(q);
    let c = fq.quad_uv_centre(q);
    let n = face
        .normal(c)
        .or_else(|| vec3::normalize(cross(sub(p[2], p[0]), sub(p[3], p[1]))))?;
    let centre = [
        0.25 * (p[0][0] + p[1][0] + p[2][0] + p[3][0]),
        0.25 * (p[0][1] + p[1][1] + p[2][1] + p[3][1]),
        0.25 * (p[0][2] + p[1][2] + p[2][2] + p[3][2]),
    ];
    let proj = |x: Vec3| -> Vec3 {
        let d = sub(x, centre);
        sub(x, vec3::scale(n, dot(d, n)))
    };
    let pp = [proj(p[0]), proj(p[1]), proj(p[2]), proj(p[3])];
    let mut ang = [0.0; 4];
    for i in 0..4 {
        let e1 = sub(pp[(i + 1) % 4], pp[i]);
        let e2 = sub(pp[(i + 3) % 4], pp[i]);
        let a = dot(n, cross(e1, e2)).atan2(dot(e1, e2)).to_degrees();
        ang[i] = if a < 0.0 { a + 360.0 } else { a };
    }
    let area = |a: usize, b: usize, c: usize| dot(n, cross(sub(pp[b], pp[a]), sub(pp[c], pp[a])));
    let signs =
        area(0, 1, 2) > 0.0 && area(0, 2, 3) > 0.0 && area(1, 2, 3) > 0.0 && area(1, 3, 0) > 0.0;
    Some((ang, signs))
}

/// True when quad `q` is valid for the window `w` (see the module documentation).
pub fn quad_valid(fq: &FaceQuads, face: &Face, q: u32, w: AngleWindow) -> bool {
    let Some((ang, signs)) = quad_angles(fq, face, q) else {
        return false;
    };
    if !signs {
        return false;
    }
    let vs = fq.quads[q as usize];
    (0..4).all(|i| {
        if fq.verts[vs[i] as usize].fixed {
            ang[i] < AngleWindow::BASE.max_deg.max(w.max_deg)
        } else {
            ang[i] > w.min_deg && ang[i] < w.max_deg
        }
    })
}

/// How far quad `q`'s movable-vertex angles are outside the window `w`
/// (degrees; 0 when inside), or `f64::INFINITY` when the quad fails the base
/// validity (folded, or outside [`AngleWindow::BASE`]).
pub fn quad_violation(fq: &FaceQuads, face: &Face, q: u32, w: AngleWindow) -> f64 {
    if !quad_valid(fq, face, q, AngleWindow::BASE) {
        return f64::INFINITY;
    }
    let Some((ang, _)) = quad_angles(fq, face, q) else {
        return f64::INFINITY;
    };
    let vs = fq.quads[q as usize];
    let mut worst: f64 = 0.0;
    for i in 0..4 {
        if !fq.verts[vs[i] as usize].fixed {
            worst = worst.max(w.min_deg - ang[i]).max(ang[i] - w.max_deg);
        }
    }
    worst.max(0.0)
}

/// Largest projected angle of quad `q` at a movable vertex, with that vertex.
pub fn worst_movable_vertex(fq: &FaceQuads, face: &Face, q: u32, w: AngleWindow) -> Option<u32> {
    let vs = fq.quads[q as usize];
    let ang = quad_angles(fq, face, q).map(|a| a.0).unwrap_or([180.0; 4]);
    let mut best: Option<(f64, u32)> = None;
    for i in 0..4 {
        if fq.verts[vs[i] as usize].fixed {
            continue;
        }
        // distance outside the window; the largest angle first, as in the paper
        let bad = (ang[i] - w.max_deg).max(w.min_deg - ang[i]) + ang[i] * 1e-6;
        if best.is_none_or(|b| bad > b.0) {
            best = Some((bad, vs[i]));
        }
    }
    best.map(|b| b.1)
}

/// Number of live quads of `fq` with a corner SICN < 0 against the oriented
/// CAD normals at their corners ([`Face::corner_normal`], limit normals at
/// poles), or by the element geometry alone ([`quad_inverted`]): what the
/// mesh statistics count as inverted. The projected check of [`quad_valid`]
/// uses one normal per quad, so on a curved face a large quad can pass it
/// while a corner folds against the surface there.
pub fn inverted_count(fq: &FaceQuads, face: &Face) -> usize {
    fq.live_quads()
        .filter(|&q| quad_inverted(fq, face, q))
        .count()
}

/// True when quad `q` is inverted by either judge of the final check
/// ([`mesh::quality::quad_sicn_both_judges`]: a corner SICN < 0 with the CAD
/// normals at its corners, or with the element's own normals).
pub fn quad_inverted(fq: &FaceQuads, face: &Face, q: u32) -> bool {
    let p = fq.quad_xyz(q);
    let c = fq.quad_uv_centre(q);
    let own = vec3::normalize(cross(sub(p[2], p[0]), sub(p[3], p[1]))).unwrap_or([0.0, 0.0, 1.0]);
    let n = fq.quads[q as usize].map(|v| {
        let x = &fq.verts[v as usize];
        let at = match (x.pole, &x.class) {
            (Some(seg), _) => geometry::CornerUv::Pole(seg),
            (None, mesh::NodeClass::Face(..)) => geometry::CornerUv::Point(x.uv),
            (None, _) => geometry::CornerUv::Curve(x.uv),
        };
        face.corner_normal(at, c).unwrap_or(own)
    });
    mesh::quality::quad_sicn_both_judges(&p, &n) < 0.0
}

/// Quads of `v`'s fan inverted by either judge ([`quad_inverted`]).
pub fn fan_inverted(fq: &FaceQuads, face: &Face, v: u32) -> usize {
    fq.verts[v as usize]
        .fan
        .iter()
        .filter(|&&q| quad_inverted(fq, face, q))
        .count()
}
