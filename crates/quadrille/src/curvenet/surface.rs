//! The CAD surface a cycle bounds, when the network comes from CAD faces
//! (issue 30): the face's surface and orientation, asked for closest points
//! and oriented normals. JSON, OBJ and wire networks have none; every stage
//! that uses it falls back to the curves alone without it.

use std::fmt;
use std::sync::Arc;

use geometry::traits::Surface;
use geometry::vec3::{self, Vec3};

/// A cycle's CAD surface: the untrimmed surface of its face and whether the
/// face's normal is opposite to `du × dv`.
#[derive(Clone)]
pub struct CycleSurface {
    surface: Arc<dyn Surface>,
    reversed: bool,
}

impl CycleSurface {
    /// The surface of a face with its orientation (`Face::reversed`).
    pub fn new(surface: Arc<dyn Surface>, reversed: bool) -> Self {
        CycleSurface { surface, reversed }
    }

    /// The closest point of the (untrimmed) surface to `p` and the face's
    /// unit normal there; `None` when the projection fails or the normal is
    /// undefined (a pole, an apex).
    pub fn closest(&self, p: Vec3) -> Option<(Vec3, Vec3)> {
        let (uv, q) = self.surface.project(p, None)?;
        let n = self.surface.normal(uv)?;
        let n = if self.reversed {
            vec3::scale(n, -1.0)
        } else {
            n
        };
        Some((q, n))
    }

    /// [`CycleSurface::closest`], with no normal where the closest point is a
    /// singular point of the parametrization (a cone apex, whose normal
    /// depends on the side it is approached from: `du × dv` there is the
    /// normal along whichever generatrix the projection's u happens to
    /// name). An element corner there takes [`CycleSurface::corner_normals`].
    pub fn closest_regular(&self, p: Vec3) -> Option<(Vec3, Option<Vec3>)> {
        let (uv, q) = self.surface.project(p, None)?;
        Some((q, self.regular_normal(uv)))
    }

    /// The face's oriented normal at `uv`, `None` at a singular point
    /// (`geometry::model::SINGULAR_RATIO`, as `Face::is_singular`) or where
    /// the surface gives none.
    fn regular_normal(&self, uv: [f64; 2]) -> Option<Vec3> {
        let d = self.surface.first_derivs(uv);
        let ratio =
            vec3::norm(vec3::cross(d.du, d.dv)) / (vec3::dot(d.du, d.du) + vec3::dot(d.dv, d.dv));
        if ratio.is_nan() || ratio < geometry::model::SINGULAR_RATIO {
            return None;
        }
        self.oriented(self.surface.normal(uv)?)
    }

    /// `n` flipped for a reversed face.
    fn oriented(&self, n: Vec3) -> Option<Vec3> {
        let n = if self.reversed {
            vec3::scale(n, -1.0)
        } else {
            n
        };
        n.iter().all(|x| x.is_finite()).then_some(n)
    }

    /// The face's normals at the four corners `p` of an element, as `stats
    /// --cad` reads them (`Face::corner_normal`): at an ordinary point the
    /// normal at the corner's closest point; at a singular point (a cone
    /// apex) the limit normal approached from the element, taken
    /// `geometry::model::POLE_OFFSET` of the way toward the element's
    /// (u, v) centre after sliding the corner along the parameter whose
    /// derivative vanishes to the centre's. The centre is the
    /// element's 3D centroid projected (not a mean of the corners' (u, v):
    /// on i04o's half cones a quad spans exactly half the period, and
    /// moving the corners into one's period tips at ½ period to the other
    /// half, which is what `stats --cad` does there).
    /// `None` where a projection fails or no normal is defined.
    pub fn corner_normals(&self, p: &[Vec3; 4]) -> [Option<Vec3>; 4] {
        let uvs = p.map(|q| self.surface.project(q, None).map(|(uv, _)| uv));
        let normals = uvs.map(|uv| uv.and_then(|uv| self.regular_normal(uv)));
        let periods = self.surface.periods();
        let unwrap =
            |uv: [f64; 2], target: [f64; 2]| geometry::nearest_periodic_uv(uv, periods, target);
        if normals.iter().all(Option::is_some) {
            return normals;
        }
        let mean = vec3::scale(p.iter().fold([0.0; 3], |a, &q| vec3::add(a, q)), 0.25);
        let Some((centre, _)) = self.surface.project(mean, None) else {
            return normals;
        };
        let mut out = normals;
        for k in 0..4 {
            let Some(uv) = uvs[k].filter(|_| normals[k].is_none()) else {
                continue;
            };
            let c = unwrap(centre, uv);
            let d = self.surface.first_derivs(uv);
            let (uu, vv) = (vec3::dot(d.du, d.du), vec3::dot(d.dv, d.dv));
            let mut at = uv;
            if uu < 1e-6 * vv {
                at[0] = c[0];
            } else if vv < 1e-6 * uu {
                at[1] = c[1];
            }
            let off = geometry::model::POLE_OFFSET;
            let w = [at[0] + off * (c[0] - at[0]), at[1] + off * (c[1] - at[1])];
            out[k] = self
                .surface
                .normal(w)
                .or_else(|| self.surface.normal(c))
                .and_then(|n| self.oriented(n));
        }
        out
    }

    /// The face's unit normal at the closest point to `p`.
    pub fn normal_at(&self, p: Vec3) -> Option<Vec3> {
        self.closest(p).map(|(_, n)| n)
    }

    /// [`CycleSurface::normal_at`] rounded to multiples of
    /// [`BRIDGE_NORMAL_STEP`] per coordinate and normalised, for the bridge
    /// directions: a projection converges to about 1e-9 of the surface's
    /// size, which would make pair costs that are equal by symmetry (the
    /// three arcs of a spherical triangle) differ by more than the ties'
    /// relative 1e-9, and the odd party would not be found.
    pub fn bridge_normal_at(&self, p: Vec3) -> Option<Vec3> {
        let n = self.normal_at(p)?;
        vec3::normalize(n.map(|x| (x / BRIDGE_NORMAL_STEP).round() * BRIDGE_NORMAL_STEP))
    }
}

/// The grid the bridge directions' CAD normals are rounded to (2⁻²⁰ ≈ 1e-6).
pub const BRIDGE_NORMAL_STEP: f64 = 1.0 / 1_048_576.0;

/// Names the surface without printing it (OCCT surfaces print as handles).
impl fmt::Debug for CycleSurface {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "CycleSurface {{ reversed: {} }}", self.reversed)
    }
}

/// Two cycle surfaces are equal when they are the same surface object with
/// the same orientation.
impl PartialEq for CycleSurface {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.surface, &other.surface) && self.reversed == other.reversed
    }
}
