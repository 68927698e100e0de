//! The O-grid: a face bounded by one smooth loop (every corner flat) as a
//! middle grid inside rings of quads (ours, for the disks of paper §6.1.2's
//! direct meshing). A round disk gets a square middle grid; an elongated one
//! (a slot, an obround top, a plate with tangent corner fillets) a middle
//! grid of its own proportions, so its quads stay square.

use geometry::vec3::{self, Vec3};

use crate::core::patch::{LocalNode, QuadPatch};
use crate::core::quality::patch_quality;
use crate::direct::pattern_face::{
    harmonic_uv, needs_reversal, place_interior, smooth_and_check_above, uv_centroid, Ring,
};

/// Name of the disk pattern of [`mesh_disk_o_grid`].
pub const O_GRID: &str = "O";

/// Name of [`mesh_disk_o_grid`]'s plain grid of an elongated disk (no ring,
/// no irregular interior vertex).
pub const PLAIN_GRID: &str = "plain";

/// Rings of quads an O-grid puts between its middle grid and the boundary,
/// per boundary edge: a disk of radius R with N boundary edges of length
/// e = 2πR / N gets about 0.4 R / e rings (the middle square's corners sit
/// about half-way out), at least one.
const O_GRID_RINGS_PER_EDGE: f64 = 0.4 / std::f64::consts::TAU;

/// A face bounded by one smooth loop (every corner flat: a disk, a
/// cylinder's cap) as an O-grid: an `a × b` grid in the middle (`a + b` half
/// the boundary's edge count), rings of quads from its perimeter out to the
/// boundary, every boundary node on two quads. The middle grid's four corners
/// are the only irregular vertices (valence 3): the four index-¼
/// singularities of a disk's cross field. Before it, the unstructured mesher
/// met them at the boundary, where a node on one quad made a 180° corner
/// (s15o_cylinder's caps: worst SICN 0.16).
///
/// An elongated disk (a slot, an obround key top, a plate with tangent
/// corner fillets) is also meshed with a middle grid shaped like it
/// ([`fitted_layout`]), which is kept when its average SICN is higher and
/// at least [`FITTED_MIN_AVERAGE_SICN`].
///
/// Returns the patch and its pattern's name ([`O_GRID`] or [`PLAIN_GRID`]).
pub(crate) fn mesh_disk_o_grid(
    face: &geometry::Face,
    ring: &Ring,
) -> Result<(QuadPatch, &'static str), String> {
    let nb = ring.nodes.len();
    if nb % 2 != 0 || nb < 8 {
        return Err(format!("a disk of {nb} boundary edges"));
    }
    if ring.nodes.iter().any(|n| n.pole.is_some()) {
        return Err("a disk with a pole on its boundary".into());
    }
    let round = round_layout(nb);
    let fitted = match fitted_layout(&ring.pos) {
        Some(fitted) if fitted != round => fitted,
        _ => return mesh_o_grid(face, ring, round).map(|p| (p, O_GRID)),
    };
    // the fitted one when it is good on average and better than the round
    // one (which may have failed the check: the face then goes to the
    // frontal mesher, which does about as well as a mediocre O-grid)
    let round_mesh = mesh_o_grid(face, ring, round);
    let Ok(f) = mesh_o_grid(face, ring, fitted) else {
        return round_mesh.map(|p| (p, O_GRID));
    };
    let fa = patch_quality(face, &f).1;
    let ra = round_mesh.as_ref().map_or(f64::NEG_INFINITY, |r| patch_quality(face, r).1);
    tracing::debug!(
        "O-grid of {nb} boundary edges: fitted {fitted:?}, {} quads, SICN {fa:.3}; round {round:?}, SICN {ra:.3}",
        f.quads.len()
    );
    let ringed = if fa >= FITTED_MIN_AVERAGE_SICN && fa > ra { Ok(f) } else { round_mesh };
    // the fitted middle grid stretched out to the boundary: no ring, so no
    // interior irregular vertex; its four corners are boundary nodes on one
    // quad each, where the boundary turns by one edge's angle
    let plain = OGridLayout { rings: 0, ..fitted };
    let p = match mesh_o_grid(face, ring, plain) {
        Ok(p) => p,
        Err(e) => {
            tracing::debug!("O-grid of {nb} boundary edges: no plain grid {plain:?}: {e}");
            return ringed.map(|p| (p, O_GRID));
        }
    };
    let (pw, pa) = patch_quality(face, &p);
    let (rw, ra) = ringed.as_ref().map_or((f64::NEG_INFINITY, f64::NEG_INFINITY), |r| patch_quality(face, r));
    tracing::debug!(
        "O-grid of {nb} boundary edges: plain grid {} quads, SICN min {pw:.3} avg {pa:.3}; ringed min {rw:.3} avg {ra:.3}",
        p.quads.len()
    );
    if pa >= FITTED_MIN_AVERAGE_SICN && pw >= PLAIN_MIN_SICN && pa >= ra - PLAIN_AVERAGE_SICN_SLACK {
        Ok((p, PLAIN_GRID))
    } else {
        ringed.map(|p| (p, O_GRID))
    }
}

/// Worst SICN a plain grid ([`mesh_disk_o_grid`]) may have, below
/// [`crate::direct::pattern_face::MIN_PATTERN_SICN`]: a corner quad's angle
/// at its boundary node is 180° less the boundary's turn there, one edge's
/// angle e / R, so its SICN is about sin(e / R): 0.31 for three edges per
/// radius (Gmsh's quadqs leaves such corners on an obround face too).
pub const PLAIN_MIN_SICN: f64 = 0.2;

/// Average SICN a plain grid may give up against the ringed O-grid for its
/// four fewer irregular interior vertices.
const PLAIN_AVERAGE_SICN_SLACK: f64 = 0.03;

/// Average SICN a fitted O-grid must reach to be kept (about what the
/// frontal mesher gives a face the round O-grid fails on).
const FITTED_MIN_AVERAGE_SICN: f64 = 0.85;

/// The shape of an O-grid on a ring of `nb` boundary nodes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct OGridLayout {
    /// Edges of the middle grid's first and third sides.
    a: usize,
    /// Edges of its second and fourth sides (`a + b` = `nb / 2`).
    b: usize,
    /// Rings of quads between the middle grid and the boundary.
    rings: usize,
    /// The ring position the middle grid's first corner is joined to.
    shift: usize,
}

/// The layout of a round disk: a square middle grid, rings by
/// [`O_GRID_RINGS_PER_EDGE`], the first corner joined to ring node 0.
fn round_layout(nb: usize) -> OGridLayout {
    let a = nb / 4;
    OGridLayout {
        a,
        b: nb / 2 - a,
        rings: ((O_GRID_RINGS_PER_EDGE * nb as f64).round() as usize).max(1),
        shift: 0,
    }
}

/// A disk whose principal extents differ by less than this ratio is round.
const ELONGATED_RATIO: f64 = 1.25;

/// Rings per edge length of the ring layer's thickness t (see
/// [`fitted_layout`]): chosen so a circle gets the round layout's rings,
/// 0.4 R / e for t = (8 − 2π) R / 8.
const RINGS_PER_THICKNESS: f64 = 0.4 * 8.0 / (8.0 - std::f64::consts::TAU);

/// The layout of an elongated disk from its boundary points `pos`, or `None`
/// when the disk is round (extents within [`ELONGATED_RATIO`]) or its shape
/// cannot be measured. In the loop's principal frame (Newell normal, then
/// the 2D principal axes) the disk spans X × Y; a middle grid of X′ × Y′
/// inside rings of thickness t satisfies the perimeter 2 (X′ + Y′) + 8 t = P
/// when X′ = X − 2t, Y′ = Y − 2t, so t = (2 (X + Y) − P) / 8: about 0 for a
/// rectangle with small tangent fillets (almost a plain grid), 0.21 R for a
/// circle. The middle grid's corners are joined to the boundary nodes
/// nearest the frame's bounding-box corners, its long sides to the long
/// arcs.
fn fitted_layout(pos: &[Vec3]) -> Option<OGridLayout> {
    let nb = pos.len();
    let n = nb as f64;
    let c = pos.iter().fold([0.0; 3], |s, p| vec3::add(s, *p));
    let c = vec3::scale(c, 1.0 / n);
    let mut normal = [0.0; 3];
    for i in 0..nb {
        normal = vec3::add(normal, vec3::cross(pos[i], pos[(i + 1) % nb]));
    }
    let normal = vec3::normalize(normal)?;
    let helper = if normal[0].abs() < 0.9 { [1.0, 0.0, 0.0] } else { [0.0, 1.0, 0.0] };
    let e1 = vec3::normalize(vec3::cross(normal, helper))?;
    let e2 = vec3::cross(normal, e1);
    let flat: Vec<[f64; 2]> = pos
        .iter()
        .map(|p| {
            let d = vec3::sub(*p, c);
            [vec3::dot(d, e1), vec3::dot(d, e2)]
        })
        .collect();
    let (mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0);
    for q in &flat {
        sxx += q[0] * q[0];
        syy += q[1] * q[1];
        sxy += q[0] * q[1];
    }
    let theta = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    let (major, minor) = ([theta.cos(), theta.sin()], [-theta.sin(), theta.cos()]);
    let frame: Vec<[f64; 2]> = flat
        .iter()
        .map(|q| {
            [
                q[0] * major[0] + q[1] * major[1],
                q[0] * minor[0] + q[1] * minor[1],
            ]
        })
        .collect();
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for q in &frame {
        for k in 0..2 {
            lo[k] = lo[k].min(q[k]);
            hi[k] = hi[k].max(q[k]);
        }
    }
    let (x, y) = (hi[0] - lo[0], hi[1] - lo[1]);
    if !(x.is_finite() && y > 0.0 && x >= ELONGATED_RATIO * y) {
        return None;
    }
    let perimeter: f64 = (0..nb).map(|i| vec3::dist(pos[i], pos[(i + 1) % nb])).sum();
    let edge = perimeter / n;
    let thickness = ((2.0 * (x + y) - perimeter) / 8.0).max(0.0);
    let rings = ((RINGS_PER_THICKNESS * thickness / edge).round() as usize).max(1);
    // the ring nodes nearest the box's corners, counter-clockwise in the frame
    let boxed = [[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]];
    let nearest = boxed.map(|b| {
        (0..nb)
            .min_by(|&i, &j| {
                let d = |k: usize| (frame[k][0] - b[0]).hypot(frame[k][1] - b[1]);
                d(i).total_cmp(&d(j))
            })
            .unwrap_or(0)
    });
    let ahead = |from: usize, to: usize| (to + nb - from) % nb;
    // the ring runs the box's corners in order 0 1 2 3 or 0 3 2 1; the
    // middle grid's first side must face a long (X) side
    let forward = ahead(nearest[0], nearest[1]) < ahead(nearest[0], nearest[3]);
    let order = if forward { [0, 1, 2, 3] } else { [1, 0, 3, 2] };
    let corner = order.map(|k| nearest[k]);
    let arcs: Vec<usize> = (0..4).map(|k| ahead(corner[k], corner[(k + 1) % 4])).collect();
    if arcs.iter().any(|&s| s == 0) || arcs.iter().sum::<usize>() != nb {
        return None;
    }
    let half = nb / 2;
    let a = (((arcs[0] + arcs[2]) as f64 / 2.0).round() as usize).clamp(1, half - 1);
    Some(OGridLayout {
        a,
        b: half - a,
        rings,
        shift: corner[0],
    })
}

/// The O-grid of `layout` on `ring`, smoothed and checked.
fn mesh_o_grid(face: &geometry::Face, ring: &Ring, layout: OGridLayout) -> Result<QuadPatch, String> {
    let nb = ring.nodes.len();
    let OGridLayout { a, b, rings, shift } = layout;
    // ring node k of the layout is node (k + shift) of the ring
    let rotated = |v: &[LocalNode]| -> Vec<LocalNode> { (0..nb).map(|k| v[(k + shift) % nb]).collect() };
    let ring_nodes = rotated(&ring.nodes);
    let ring_pos: Vec<Vec3> = (0..nb).map(|k| ring.pos[(k + shift) % nb]).collect();
    // ids: the boundary ring first (level 0), then levels 1..=rings (level
    // `rings` is the middle grid's perimeter), then the middle grid's inside
    let level = |j: usize, i: usize| (j * nb + i % nb) as u32;
    let inside = |x: usize, y: usize| ((rings + 1) * nb + (y - 1) * (a - 1) + (x - 1)) as u32;
    let grid = |x: usize, y: usize| -> u32 {
        let i = if y == 0 {
            x
        } else if x == a {
            a + y
        } else if y == b {
            2 * a + b - x
        } else if x == 0 {
            (2 * a + 2 * b - y) % nb
        } else {
            return inside(x, y);
        };
        level(rings, i)
    };
    let nv = (rings + 1) * nb + (a - 1) * (b - 1);
    let mut quads: Vec<[u32; 4]> = Vec::with_capacity(rings * nb + a * b);
    for j in 0..rings {
        for i in 0..nb {
            quads.push([
                level(j, i),
                level(j, i + 1),
                level(j + 1, i + 1),
                level(j + 1, i),
            ]);
        }
    }
    for y in 0..b {
        for x in 0..a {
            quads.push([
                grid(x, y),
                grid(x + 1, y),
                grid(x + 1, y + 1),
                grid(x, y + 1),
            ]);
        }
    }
    let mut fixed = vec![false; nv];
    fixed[..nb].fill(true);
    let centroid = uv_centroid(&ring_nodes);
    let mut uv: Vec<[f64; 2]> = (0..nv)
        .map(|v| if v < nb { ring_nodes[v].uv } else { centroid })
        .collect();
    harmonic_uv(&quads, &mut uv, &fixed);
    if needs_reversal(face, &quads, &uv) {
        for q in &mut quads {
            q.reverse();
        }
    }
    let mut nodes = ring_nodes;
    let mut pos = ring_pos;
    let mut local: Vec<u32> = (0..nv as u32).collect();
    place_interior(face, &uv, &fixed, &mut local, &mut nodes, &mut pos)?;
    let floor = if rings == 0 { PLAIN_MIN_SICN } else { crate::direct::pattern_face::MIN_PATTERN_SICN };
    smooth_and_check_above(face, nodes, pos, quads, O_GRID, floor)
}


#[cfg(test)]
mod tests {
    use super::*;
    use crate::curves::curve_mesh::{discretize_all, plan_curves};
    use crate::direct::pattern_face::boundary_ring;
    use geometry::{primitives, FaceId};

    /// Points of a closed polyline around a stadium: two half circles of
    /// radius `r` joined by straight runs of length `l`, `n` per half circle
    /// and `m` per straight run.
    fn stadium(l: f64, r: f64, n: usize, m: usize) -> Vec<Vec3> {
        let mut p = Vec::new();
        for k in 0..m {
            p.push([-l / 2.0 + l * k as f64 / m as f64, -r, 0.0]);
        }
        for k in 0..n {
            let t = -std::f64::consts::FRAC_PI_2 + std::f64::consts::PI * k as f64 / n as f64;
            p.push([l / 2.0 + r * t.cos(), r * t.sin(), 0.0]);
        }
        for k in 0..m {
            p.push([l / 2.0 - l * k as f64 / m as f64, r, 0.0]);
        }
        for k in 0..n {
            let t = std::f64::consts::FRAC_PI_2 + std::f64::consts::PI * k as f64 / n as f64;
            p.push([-l / 2.0 + r * t.cos(), r * t.sin(), 0.0]);
        }
        p
    }

    #[test]
    fn a_circle_keeps_the_round_layout() {
        let pos: Vec<Vec3> = (0..40)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / 40.0;
                [t.cos(), t.sin(), 0.0]
            })
            .collect();
        assert_eq!(fitted_layout(&pos), None);
        assert_eq!(round_layout(40), OGridLayout { a: 10, b: 10, rings: 3, shift: 0 });
    }

    #[test]
    fn a_stadium_gets_a_long_middle_grid_facing_its_straight_sides() {
        // 20 × 6 overall (a straight run of 14, radius 3), 28 edges per
        // straight run and 20 per half circle (9° each): perimeter
        // 28 + 6π = 46.85 over 96 edges, e = 0.488
        let pos = stadium(14.0, 3.0, 20, 28);
        let l = fitted_layout(&pos).expect("elongated");
        assert_eq!(l.a + l.b, 48);
        // ring thickness t = (2 (20 + 6) − 46.85) / 8 = 0.643, 1.32 edges:
        // 1.864 × 1.32 = 2.46 → 2 rings
        assert_eq!(l.rings, 2);
        // the box corners are nearest the arcs' nodes at ±45°: a long side
        // takes a straight run and 45° of each end, 28 + 5 + 5 = 38 edges
        assert_eq!((l.a, l.b), (38, 10));
        // the middle grid's first side faces a straight run: its corners'
        // spokes end at mirror points of one side of the stadium
        let (p, q) = (pos[l.shift], pos[(l.shift + l.a) % pos.len()]);
        assert!((p[0] + q[0]).abs() < 1e-9 && (p[1] - q[1]).abs() < 1e-9, "{p:?} {q:?}");
        assert!(p[0].abs() > 9.0 && p[1].abs() > 2.0, "{p:?}");
    }

    #[test]
    fn an_ellipse_is_meshed_with_squarer_quads_than_by_the_round_layout() {
        let model = primitives::ellipse(2.0, 1.0);
        let cms = discretize_all(&model, &plan_curves(&model, 0.1));
        let ring = boundary_ring(&model, FaceId(0), &cms).unwrap();
        let face = &model.faces[0];
        let nb = ring.nodes.len();
        let fitted = fitted_layout(&ring.pos).expect("a 2:1 ellipse is elongated");
        assert_ne!(fitted, round_layout(nb));
        let average = |layout| {
            let p = mesh_o_grid(face, &ring, layout).unwrap();
            // an O-grid: 4 valence-3 interior vertices, nothing else irregular
            let valences = p.valences();
            let irregular = valences.iter().zip(&p.nodes).filter(|(v, n)| {
                n.node == crate::core::patch::NodeRef::Interior && **v != 4
            });
            assert_eq!(irregular.count(), 4);
            patch_quality(face, &p).1
        };
        let (fit, round) = (average(fitted), average(round_layout(nb)));
        assert!(fit > round + 0.02, "fitted {fit:.3}, round {round:.3}");
    }

    /// A planar stadium face in z = 0: straight runs of length `l` along
    /// y = ±r, joined by half circles of radius `r` about (±l/2, 0), tangent
    /// to the runs (4 curves, 4 flat corners, one smooth loop).
    fn stadium_face(l: f64, r: f64) -> geometry::Model {
        use geometry::model::{CurveEntity, CurveUse};
        use geometry::primitives::{Circle, Circle2d};
        use geometry::CurveId;
        use std::f64::consts::FRAC_PI_2;
        use std::sync::Arc;
        let h = l / 2.0;
        let mut m = primitives::polygon(&[[-h, -r], [h, -r], [h, r], [-h, r]]);
        // curves 1 and 3 become the half circles, counter-clockwise
        for (k, cx, from) in [(1usize, h, -FRAC_PI_2), (3, -h, FRAC_PI_2)] {
            let range = (from, from + std::f64::consts::PI);
            let start = m.curves[k].start;
            let end = m.curves[k].end;
            m.curves[k] = CurveEntity {
                geom: Some(Arc::new(Circle {
                    center: [cx, 0.0, 0.0],
                    xdir: [1.0, 0.0, 0.0],
                    ydir: [0.0, 1.0, 0.0],
                    radius: r,
                    range,
                })),
                range,
                start,
                end,
                degenerate: false,
            };
            m.faces[0].loops[0].uses[k] = CurveUse {
                curve: CurveId(k as u32),
                forward: true,
                pcurve: Arc::new(Circle2d { center: [cx, 0.0], radius: r }),
                seam: false,
            };
        }
        m.faces[0].uv_bounds.umin = -h - r;
        m.faces[0].uv_bounds.umax = h + r;
        m
    }

    #[test]
    fn a_stadium_face_is_one_grid_with_no_irregular_interior_vertex() {
        // a 25 × 6 obround (shaft_key_d20's top): runs of 19, radius 3,
        // edges of about 1 (perimeter 38 + 6π = 56.8)
        let model = stadium_face(19.0, 3.0);
        let cms = discretize_all(&model, &plan_curves(&model, 1.0));
        let ring = boundary_ring(&model, FaceId(0), &cms).unwrap();
        let face = &model.faces[0];
        let nb = ring.nodes.len();
        let (p, name) = mesh_disk_o_grid(face, &ring).expect("a stadium is meshed");
        assert_eq!(name, PLAIN_GRID);
        let valences = p.valences();
        let interior = |want: bool| {
            valences
                .iter()
                .zip(&p.nodes)
                .filter(|(v, n)| n.node == crate::core::patch::NodeRef::Interior && (**v != 4) == want)
                .count()
        };
        assert_eq!(interior(true), 0, "irregular interior vertices");
        // one a × b grid, a + b = nb / 2: (a − 1)(b − 1) interior nodes
        let fitted = fitted_layout(&ring.pos).expect("elongated");
        assert_eq!(p.quads.len(), fitted.a * fitted.b);
        assert_eq!(interior(false), (fitted.a - 1) * (fitted.b - 1));
        assert_eq!(2 * (fitted.a + fitted.b), nb);
        // the worst quads are the four corners on the half circles: about
        // sin(e / R) = sin(0.32) = 0.31 before smoothing; the average beats
        // the ringed O-grid of the same middle grid (4 valence-3 vertices)
        let (worst, average) = patch_quality(face, &p);
        let ringed = mesh_o_grid(face, &ring, fitted).unwrap();
        let (_, ringed_average) = patch_quality(face, &ringed);
        assert!(worst >= PLAIN_MIN_SICN && worst < 0.35, "worst {worst:.3}");
        assert!(average > 0.95 && average > ringed_average, "{average:.3} vs {ringed_average:.3}");
    }
}
