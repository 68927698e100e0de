//! Which way a cycle's dense quads must face, and the rescue of a layout
//! that leaves a few of them inverted (issue 30): [`Facing`] judges a quad
//! against the cycle's CAD normals, its plane or its Newell normal;
//! [`unfolded`] puts the interior nodes on the CAD surface and, when only
//! a few quads fold, untangles them (`curvenet::untangle`) before refusing
//! the layout. Used by the `curves` driver (`methods::curvenet`) and its
//! network stage (`methods::curvenet_network`).

use geometry::vec3::{self, Vec3};

use crate::curvenet::untangle::untangle;
use crate::curvenet::{CycleLoops, CycleQuads, CycleSurface, LayoutError};

/// Quads whose normal turns more than 120° from the cycle's Newell normal
/// fold over (the cycle has no such face: one cycle spans less than a
/// hemisphere around its Newell normal).
const FOLDED_COS: f64 = -0.5;

/// A cycle within this share of its diameter of its mean plane is planar:
/// its quads must all face the plane's normal.
const PLANAR: f64 = 1e-6;

/// Which way a cycle's quads must face: the CAD normals of its face when it
/// bounds one (every quad's corner SICN with them ≥ 0, the judge of `stats
/// --cad`); else its Newell normal, and whether the cycle is planar (then
/// every quad faces it, else none turns more than 120° away).
#[derive(Clone, Debug)]
pub(super) struct Facing {
    normal: Option<Vec3>,
    planar: bool,
    surface: Option<CycleSurface>,
}

impl Facing {
    pub(super) fn of(loops: &CycleLoops) -> Self {
        let points = &loops.outer.points;
        let n = points.len();
        let normal = vec3::normalize(crate::curvenet::geometry::newell(points));
        let planar = normal.is_some_and(|u| {
            let centre = vec3::scale(points.iter().fold([0.0; 3], |a, &p| vec3::add(a, p)), 1.0 / n as f64);
            let size = points.iter().map(|&p| vec3::dist(p, centre)).fold(0.0, f64::max);
            points.iter().all(|&p| vec3::dot(vec3::sub(p, centre), u).abs() <= PLANAR * size)
        });
        Facing { normal, planar, surface: loops.surface.clone() }
    }

    /// On a CAD face: the nodes of `q` with its interior ones moved to
    /// their closest points on the surface (the Coons patches span the
    /// boundary curves, not the face: on a cylinder they cut through it),
    /// and the CAD normal at every node (`None` where the projection fails
    /// or the normal is undefined or depends on the element, at a cone
    /// apex: [`Facing::corner_normals`]). `None` without a surface.
    fn surface_nodes(&self, q: &CycleQuads) -> Option<(Vec<Vec3>, Vec<Option<Vec3>>)> {
        let surface = self.surface.as_ref()?;
        let mut nodes = q.nodes.clone();
        let mut normals = Vec::with_capacity(q.nodes.len());
        for (v, node) in nodes.iter_mut().enumerate() {
            let found = surface.closest_regular(*node);
            if let Some((on, _)) = found {
                if !q.boundary[v] {
                    *node = on;
                }
            }
            normals.push(found.and_then(|(_, n)| n));
        }
        Some((nodes, normals))
    }

    /// Where a moved node goes: its closest point on the CAD surface and
    /// the face's normal there; without a surface (or where the projection
    /// fails) the point itself and no normal.
    fn place(&self, p: Vec3) -> (Vec3, Option<Vec3>) {
        match self.surface.as_ref().and_then(|s| s.closest_regular(p)) {
            Some((on, n)) => (on, n),
            None => (p, None),
        }
    }

    /// The CAD normals at the corners of the quad `p`, its nodes' normals
    /// `cad` where known, the others ([`Facing::surface_nodes`] leaves a
    /// cone apex without one) as `stats --cad` reads them: the limit normal
    /// approached from the quad (`CycleSurface::corner_normals`). On i04o
    /// the apex's own `du × dv` (along the generatrix the projection's u
    /// named) let six corner quads pass that `stats` found inverted.
    fn corner_normals(&self, p: &[Vec3; 4], cad: [Option<Vec3>; 4]) -> [Option<Vec3>; 4] {
        match &self.surface {
            Some(surface) if cad.iter().any(Option::is_none) => {
                let limit = surface.corner_normals(p);
                [0, 1, 2, 3].map(|k| cad[k].or(limit[k]))
            }
            _ => cad,
        }
    }

    /// A quad's quality for untangling, valid when > 0 and ≤ 0 wherever
    /// [`Facing::inverted`] holds: the least of its element SICN and its
    /// corner SICN with the CAD normals at its corners (all known), else
    /// with the plane's normal (planar cycle), else its facing margin
    /// (cosine to the Newell normal above −0.5).
    fn quality(&self, p: &[Vec3; 4], cad: [Option<Vec3>; 4]) -> f64 {
        let element = mesh::quality::quad_element_sicn(p);
        let facing = if let [Some(a), Some(b), Some(c), Some(d)] = self.corner_normals(p, cad) {
            mesh::quality::quad_sicn(p, &[a, b, c, d])
        } else {
            match self.normal {
                Some(u) if self.planar => mesh::quality::quad_sicn(p, &[u; 4]),
                Some(u) => {
                    let n = vec3::cross(vec3::sub(p[2], p[0]), vec3::sub(p[3], p[1]));
                    vec3::normalize(n).map_or(-1.0, |n| vec3::dot(n, u) - FOLDED_COS)
                }
                None => f64::INFINITY,
            }
        };
        element.min(facing)
    }

    /// True when the quad `p` is inverted: by the element geometry (Gmsh's
    /// `minSICN` sign); with the CAD normals `cad` at its corners, by a
    /// negative corner SICN; else facing away from the cycle (any amount on
    /// a planar cycle, over 120° on a curved one).
    fn inverted(&self, p: &[Vec3; 4], cad: Option<[Option<Vec3>; 4]>) -> bool {
        if mesh::quality::quad_element_sicn(p) < 0.0 {
            return true;
        }
        if let Some([Some(a), Some(b), Some(c), Some(d)]) = cad.map(|n| self.corner_normals(p, n)) {
            return mesh::quality::quad_sicn(p, &[a, b, c, d]) < 0.0;
        }
        let Some(u) = self.normal else { return false };
        if self.planar {
            return mesh::quality::quad_sicn(p, &[u; 4]) <= 0.0;
        }
        let n = vec3::cross(vec3::sub(p[2], p[0]), vec3::sub(p[3], p[1]));
        vec3::normalize(n).is_some_and(|n| vec3::dot(n, u) < FOLDED_COS)
    }
}

/// A layout with at most this share of its quads inverted, or (when the
/// caller allows it, [`unfolded`]'s `by_count`) at most
/// [`UNTANGLE_MAX_QUADS`], is untangled (`curvenet::untangle`) before it is
/// refused; more is a layout that folds, not a few thin quads. The share
/// is allowed on every try: on i02o it keeps the 3-hole plate's network
/// counts (140 open edges; 162 when the share waits for the second pass).
const UNTANGLE_MAX_SHARE: f64 = 0.05;
/// See [`UNTANGLE_MAX_SHARE`].
const UNTANGLE_MAX_QUADS: usize = 8;

/// `q` with its interior nodes on the cycle's CAD surface, if it has one
/// ([`Facing::surface_nodes`]), when none of its quads is inverted
/// ([`Facing::inverted`]); else `q` as sampled (Coons), when none of its
/// quads is inverted with the same CAD normals (a node moved onto the
/// surface can fold a thin quad at the boundary); else, when only a few
/// quads are inverted (at most [`UNTANGLE_MAX_SHARE`] of them, or at most
/// [`UNTANGLE_MAX_QUADS`] when `by_count`), `q` with the free nodes around
/// them untangled (`curvenet::untangle`, on the surface) when that leaves
/// none; else an error naming the count.
pub(super) fn unfolded(mut q: CycleQuads, facing: &Facing, by_count: bool) -> Result<CycleQuads, LayoutError> {
    let folded_at = |nodes: &[Vec3], normals: Option<&Vec<Option<Vec3>>>| {
        q.quads
            .iter()
            .filter(|quad| facing.inverted(&quad.map(|v| nodes[v]), normals.map(|n| quad.map(|v| n[v]))))
            .count()
    };
    let few = |folded: usize| {
        folded as f64 <= UNTANGLE_MAX_SHARE * q.quads.len() as f64 || by_count && folded <= UNTANGLE_MAX_QUADS
    };
    let untangled = |mut nodes: Vec<Vec3>, mut normals: Vec<Option<Vec3>>| {
        let place = |p: Vec3| facing.place(p);
        let quality = |p: &[Vec3; 4], n: [Option<Vec3>; 4]| facing.quality(p, n);
        untangle(&mut nodes, &mut normals, &q.quads, &q.boundary, &place, &quality);
        (nodes, normals)
    };
    let Some((on_surface, normals)) = facing.surface_nodes(&q) else {
        let folded = folded_at(&q.nodes, None);
        if folded == 0 {
            return Ok(q);
        }
        if few(folded) {
            let (nodes, _) = untangled(q.nodes.clone(), vec![None; q.nodes.len()]);
            if folded_at(&nodes, None) == 0 {
                q.nodes = nodes;
                return Ok(q);
            }
        }
        return Err(LayoutError::Folded { quads: folded, of: q.quads.len() });
    };
    let folded = folded_at(&on_surface, Some(&normals));
    if folded == 0 {
        q.nodes = on_surface;
        return Ok(q);
    }
    if folded_at(&q.nodes, Some(&normals)) == 0 {
        return Ok(q);
    }
    if few(folded) {
        let (nodes, normals) = untangled(on_surface, normals);
        if folded_at(&nodes, Some(&normals)) == 0 {
            q.nodes = nodes;
            return Ok(q);
        }
    }
    Err(LayoutError::Folded { quads: folded, of: q.quads.len() })
}


#[cfg(test)]
mod tests {
    use std::f64::consts::FRAC_PI_4;

    use geometry::{CornerId, FaceId};
    use mesh::quadmesh::{NodeClass, QuadMesh};

    use super::*;

    /// A fan of 4 quads round the apex of `primitives::cone(1, 1)` (apex,
    /// ring u_{2i+2}, ring u_{2i+1}, ring u_{2i}, the ring at half height
    /// every 45°, as `mesh::stats`' apex test): the mesher's judge reads the
    /// apex corner as `stats --cad` does, the limit normal along the quad's
    /// middle generatrix, not the apex's own `du × dv` (the normal along
    /// whichever generatrix the projection names), which it used to take.
    #[test]
    fn curvenet_facing_reads_a_cone_apex_corner_as_stats_does() {
        let model = geometry::primitives::cone(1.0, 1.0);
        let face = &model.faces[0];
        let surface = CycleSurface::new(face.surface.clone(), face.reversed);
        let facing = Facing { normal: None, planar: false, surface: Some(surface.clone()) };
        let v = 0.5 * face.uv_bounds.vmin;
        let ring = |k: usize| face.surface.eval([FRAC_PI_4 * k as f64, v]);
        // the cone's oriented normal along generatrix u (half-angle 45°)
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let n = |k: usize| {
            let u = FRAC_PI_4 * k as f64;
            [s * u.cos(), s * u.sin(), -s]
        };
        let mut m = QuadMesh::default();
        m.nodes.push([0.0; 3]);
        m.node_class.push(NodeClass::Corner(CornerId(0)));
        for k in 0..8 {
            m.nodes.push(ring(k));
            m.node_class.push(NodeClass::Face(FaceId(0), Some([FRAC_PI_4 * k as f64, v])));
        }
        for i in 0..4u32 {
            m.quads.push([0, 1 + (2 * i + 2) % 8, 2 + 2 * i, 1 + 2 * i]);
            m.quad_face.push(FaceId(0));
        }
        let by_stats = mesh::stats::quad_sicn_values(&m, Some(&model));
        // the apex has no normal of its own now; the old one (closest point)
        let (_, own) = surface.closest_regular([0.0; 3]).expect("the apex projects");
        assert!(own.is_none());
        let (_, old) = surface.closest([0.0; 3]).expect("the apex projects");
        let mut differed = 0;
        for i in 0..4usize {
            let p = m.quads[i].map(|v| m.nodes[v as usize]);
            let cad = [None, Some(n((2 * i + 2) % 8)), Some(n(2 * i + 1)), Some(n(2 * i))];
            let got = facing.corner_normals(&p, cad);
            let apex = got[0].expect("a limit normal at the apex");
            assert!(vec3::dist(apex, n(2 * i + 1)) < 1e-6, "quad {i}: {apex:?}");
            let ours = mesh::quality::quad_sicn(&p, &got.map(|x| x.unwrap_or([0.0; 3])));
            assert!((ours - by_stats[i]).abs() < 1e-9, "quad {i}: {ours} vs stats {}", by_stats[i]);
            assert!(ours > 0.3, "quad {i}: {ours}");
            assert!(!facing.inverted(&p, Some(cad)));
            assert!((facing.quality(&p, cad) - ours.min(mesh::quality::quad_element_sicn(&p))).abs() < 1e-12);
            let before = mesh::quality::quad_sicn(&p, &[old, n((2 * i + 2) % 8), n(2 * i + 1), n(2 * i)]);
            differed += usize::from((before - by_stats[i]).abs() > 0.1);
        }
        // one generatrix's normal cannot serve four quads 90° apart: the
        // two whose middles are 135° from it read more than 0.1 off
        assert!(differed >= 2, "{differed}");
    }
}
