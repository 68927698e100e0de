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
