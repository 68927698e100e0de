//! Removal of very irregular interior vertices by disk quadrangulations
//! (paper §6.3, spec §11): the quads around an interior vertex of valence ≥ 6
//! (or ≤ 2) form a disk; its interior is replaced by the table disk
//! ([`crate::combinatorics::disk_quads`]) with the same boundary size that makes the
//! valences most regular (Eq. 15) without pushing any boundary vertex out of
//! its allowed range. The new vertices start at the centre of the cavity and
//! are smoothed, with the interior vertices of the cavity boundary, by a uv
//! Laplacian; the change is kept only if every quad it touches stays valid
//! (SICN > 0 with CAD normals, and at least half the previous worst),
//! otherwise it is undone exactly.
//!
//! Curve and corner vertices of the cavity boundary keep their valence
//! (a curve vertex may move toward 2 quads, never away).
//!
//! A CAD corner off the valence its angle asks for (paper §6.3.2) is
//! treated the same way: its star, a fan bounded by the loop of the fan's
//! outer edges through the corner, is replaced by the table disk that gives
//! the corner a valence closer to its ideal, when Eq. 15's irregularity of
//! the cavity strictly falls and its count of irregular vertices does not
//! grow (without that count, i13o_s6 ended with 72 irregular vertices
//! instead of 68). The same for curve vertices without 2 quads was tried:
//! i01o_m1 went from 41 to 51 irregular vertices, as the cavities then
//! removed fewer.

use geometry::Face;

use crate::combinatorics::disk_quads::{best_replacement, table, CavityVertex};
use crate::core::patch::QuadPatch;
use crate::core::patch::{LocalNode, NodeRef};
use crate::core::quality::quad_quality;
use crate::smoothing::kernels::one_ring;

/// Laplacian sweeps over the moved vertices after a replacement.
const REPLACEMENT_LAPLACIAN_SWEEPS: usize = 30;
/// A replacement must keep the worst quad around it at least this share of the previous worst.
const KEEP_QUALITY: f64 = 0.5;

/// Counts of [`remove_defects`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DefectReport {
    /// Interior vertices of valence ≥ 6 or ≤ 2 before.
    pub found: usize,
    /// Cavities replaced.
    pub replaced: usize,
    /// Replacements undone because the geometry was not valid.
    pub undone: usize,
    /// Corners off their ideal valence, before.
    pub boundary_found: usize,
    /// Their stars replaced.
    pub boundary_replaced: usize,
}

impl DefectReport {
    /// The counts of `self` and `o` added.
    pub fn add(&self, o: &DefectReport) -> DefectReport {
        DefectReport {
            found: self.found + o.found,
            replaced: self.replaced + o.replaced,
            undone: self.undone + o.undone,
            boundary_found: self.boundary_found + o.boundary_found,
            boundary_replaced: self.boundary_replaced + o.boundary_replaced,
        }
    }
}

/// The ideal number of quads at corner vertex `v` of `p`: from the sum of
/// its quads' angles there (`star`, its quads).
fn corner_ideal(p: &QuadPatch, star: &[u32], v: u32) -> u8 {
    let x = p.pos[v as usize];
    let mut angle = 0.0;
    for &q in star {
        let quad = p.quads[q as usize];
        let Some(k) = quad.iter().position(|&w| w == v) else {
            continue;
        };
        let a = geometry::vec3::sub(p.pos[quad[(k + 1) % 4] as usize], x);
        let b = geometry::vec3::sub(p.pos[quad[(k + 3) % 4] as usize], x);
        let c = geometry::vec3::dot(a, b) / (geometry::vec3::norm(a) * geometry::vec3::norm(b));
        if c.is_finite() {
            angle += c.clamp(-1.0, 1.0).acos();
        }
    }
    crate::core::valence::ideal_corner_valence(angle) as u8
}

/// The boundary loop of the quads `star` around boundary vertex `v`, in
/// the quads' orientation, starting at `v` (which it passes once): the
/// cavity of a curve or corner vertex. `None` when the star's outer edges
/// do not form one simple loop through `v`.
fn boundary_star_loop(quads: &[[u32; 4]], v: u32, star: &[u32]) -> Option<Vec<u32>> {
    use std::collections::HashMap;
    let mut count: HashMap<(u32, u32), u32> = HashMap::new();
    for &q in star {
        let quad = quads[q as usize];
        for k in 0..4 {
            let (a, b) = (quad[k], quad[(k + 1) % 4]);
            *count.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    let mut next: HashMap<u32, u32> = HashMap::new();
    for &q in star {
        let quad = quads[q as usize];
        for k in 0..4 {
            let (a, b) = (quad[k], quad[(k + 1) % 4]);
            if count[&(a.min(b), a.max(b))] == 1 && next.insert(a, b).is_some() {
                return None;
            }
        }
    }
    let mut out = vec![v];
    let mut cur = *next.get(&v)?;
    while cur != v {
        if out.len() > next.len() {
            return None;
        }
        out.push(cur);
        cur = *next.get(&cur)?;
    }
    (out.len() == next.len()).then_some(out)
}

/// True for an interior vertex of valence `k` that the method removes.
fn is_defect(k: usize) -> bool {
    k >= 6 || (1..=2).contains(&k)
}

/// Quads at each node.
fn incidence(p: &QuadPatch) -> Vec<Vec<u32>> {
    let mut at = vec![Vec::new(); p.nodes.len()];
    for (qi, q) in p.quads.iter().enumerate() {
        for &v in q {
            at[v as usize].push(qi as u32);
        }
    }
    at
}

/// Replaces the stars of very irregular interior vertices of `p` (see the
/// module documentation). Deterministic: vertices are visited in index order.
pub fn remove_defects(face: &Face, p: &mut QuadPatch) -> DefectReport {
    let mut report = DefectReport::default();
    // vertices placed or moved by kept replacements (smoothed again at the end)
    let mut changed: Vec<u32> = Vec::new();
    let mut at = incidence(p);
    let mut alive = vec![true; p.quads.len()];
    // very irregular interior vertices, then corners off the valence their
    // angle asks for (paper §6.3.2)
    let mut candidates: Vec<(u32, u8)> = (0..p.nodes.len() as u32)
        .filter(|&v| {
            p.nodes[v as usize].node == NodeRef::Interior && is_defect(at[v as usize].len())
        })
        .map(|v| (v, 4))
        .collect();
    report.found = candidates.len();
    for v in 0..p.nodes.len() as u32 {
        let nd = &p.nodes[v as usize];
        let ideal = match nd.node {
            _ if nd.pole.is_some() || at[v as usize].is_empty() => continue,
            NodeRef::Interior => continue,
            // curve vertices: tried, and i01o_m1 went from 41 to 51
            // irregular vertices (the cavities then removed fewer)
            NodeRef::Curve(..) => continue,
            NodeRef::Corner(_) => corner_ideal(p, &at[v as usize], v),
        };
        if at[v as usize].len() != ideal as usize {
            candidates.push((v, ideal));
            report.boundary_found += 1;
        }
    }
    let quality =
        |p: &QuadPatch, q: u32| quad_quality(face, &p.nodes, &p.pos, &p.quads[q as usize]);
    for (v, ideal_v) in candidates {
        let star = at[v as usize].clone();
        let interior = p.nodes[v as usize].node == NodeRef::Interior;
        if star.len() == ideal_v as usize || (interior && !is_defect(star.len())) {
            continue;
        }
        // the cavity boundary: the ring around an interior vertex; around a
        // boundary vertex, the loop of the star's outer edges through it
        let ring = if interior {
            one_ring(&p.quads, v, &star)
        } else {
            boundary_star_loop(&p.quads, v, &star)
        };
        let Some(ring) = ring else {
            continue;
        };
        if ring.len() > crate::combinatorics::disk_quads::TABLE_MAX_BOUNDARY {
            continue;
        }
        // the cavity as Eq. 15 sees it
        let cavity: Vec<CavityVertex> = ring
            .iter()
            .map(|&w| {
                let total = at[w as usize].len() as u8;
                let inside = star
                    .iter()
                    .filter(|&&q| p.quads[q as usize].contains(&w))
                    .count() as u8;
                let (ideal, allowed) = match p.nodes[w as usize].node {
                    // the vertex itself moves toward its ideal, never away
                    _ if w == v => (ideal_v, (total.min(ideal_v), total.max(ideal_v))),
                    NodeRef::Interior => (4, (3, 5)),
                    NodeRef::Curve(..) => (2, (total.min(2), total.max(2))),
                    NodeRef::Corner(_) => (total, (total, total)),
                };
                CavityVertex {
                    ideal,
                    outside: total - inside,
                    allowed,
                }
            })
            .collect();
        let current: u32 = cavity
            .iter()
            .zip(&ring)
            .map(|(c, &w)| (c.ideal as i32 - at[w as usize].len() as i32).pow(2) as u32)
            .sum::<u32>()
            + if interior {
                (4 - star.len() as i32).pow(2) as u32
            } else {
                0
            };
        let Some(best) = best_replacement(table(), &cavity) else {
            continue;
        };
        if best.irregularity >= current {
            continue;
        }
        let disk = &table()[best.disk];
        // a corner's fix must not add irregular vertices: Eq. 15 squares the
        // deviations, so one corner two quads off could become two
        // irregular vertices one off each
        if !interior {
            let b = ring.len();
            let before = cavity
                .iter()
                .zip(&ring)
                .filter(|(c, &w)| at[w as usize].len() != c.ideal as usize)
                .count();
            let mut after = disk.valences()[b..].iter().filter(|&&k| k != 4).count();
            for (i, &n_in) in disk.boundary_quads.iter().enumerate() {
                let c = cavity[best.position(i, b)];
                after += usize::from(n_in + c.outside != c.ideal);
            }
            if after > before {
                continue;
            }
        }
        // the enlarged cavity (quads around the ring) and its worst quad, before
        let mut region: Vec<u32> = ring
            .iter()
            .flat_map(|&w| at[w as usize].iter().copied())
            .collect();
        region.sort_unstable();
        region.dedup();
        let old_worst = region
            .iter()
            .map(|&q| quality(p, q))
            .fold(f64::INFINITY, f64::min);
        // what an undo restores
        let saved_nodes = p.nodes.len();
        let saved_quads = p.quads.len();
        let movable_ring: Vec<u32> = ring
            .iter()
            .copied()
            .filter(|&w| p.nodes[w as usize].node == NodeRef::Interior)
            .collect();
        let saved_ring: Vec<([f64; 2], geometry::vec3::Vec3)> = movable_ring
            .iter()
            .map(|&w| (p.nodes[w as usize].uv, p.pos[w as usize]))
            .collect();
        let centre = {
            let uv0 = p.nodes[v as usize].uv;
            let s = ring.iter().fold([0.0, 0.0], |a, &w| {
                let uv = p.nodes[w as usize].uv_toward(uv0);
                [a[0] + uv[0], a[1] + uv[1]]
            });
            [s[0] / ring.len() as f64, s[1] / ring.len() as f64]
        };
        let fresh: Vec<u32> = (0..disk.interior)
            .map(|_| {
                p.nodes.push(LocalNode {
                    uv: centre,
                    node: NodeRef::Interior,
                    pole: None,
                });
                p.pos.push(face.surface.eval(centre));
                at.push(Vec::new());
                (p.nodes.len() - 1) as u32
            })
            .collect();
        // swap the star for the disk
        let origin = p.quad_tri.get(star[0] as usize).copied().unwrap_or(0);
        for &q in &star {
            alive[q as usize] = false;
            for &x in &p.quads[q as usize] {
                at[x as usize].retain(|&y| y != q);
            }
        }
        for q in best.quads(disk, &ring, &fresh) {
            let id = p.quads.len() as u32;
            for &x in &q {
                at[x as usize].push(id);
            }
            p.quads.push(q);
            p.quad_tri.push(origin);
            alive.push(true);
        }
        // smooth the new vertices and the ring's interior vertices in (u, v)
        let movable: Vec<u32> = fresh
            .iter()
            .copied()
            .chain(movable_ring.iter().copied())
            .collect();
        let neighbours = |p: &QuadPatch, at: &[Vec<u32>], m: u32| -> Vec<u32> {
            let mut ns = Vec::new();
            for &q in &at[m as usize] {
                let quad = p.quads[q as usize];
                let k = quad.iter().position(|&x| x == m).unwrap_or(0);
                ns.push(quad[(k + 1) % 4]);
                ns.push(quad[(k + 3) % 4]);
            }
            ns.sort_unstable();
            ns.dedup();
            ns
        };
        let nbrs: Vec<Vec<u32>> = movable.iter().map(|&m| neighbours(p, &at, m)).collect();
        for _ in 0..REPLACEMENT_LAPLACIAN_SWEEPS {
            for (&m, ns) in movable.iter().zip(&nbrs) {
                if ns.is_empty() {
                    continue;
                }
                let here = p.nodes[m as usize].uv;
                let s = ns.iter().fold([0.0, 0.0], |a, &w| {
                    let uv = p.nodes[w as usize].uv_toward(here);
                    [a[0] + uv[0], a[1] + uv[1]]
                });
                p.nodes[m as usize].uv = [s[0] / ns.len() as f64, s[1] / ns.len() as f64];
            }
        }
        let mut finite = true;
        for &m in &movable {
            let x = face.surface.eval(p.nodes[m as usize].uv);
            finite &= x.iter().all(|c| c.is_finite());
            p.pos[m as usize] = x;
        }
        let mut touched: Vec<u32> = movable
            .iter()
            .flat_map(|&m| at[m as usize].iter().copied())
            .collect();
        touched.sort_unstable();
        touched.dedup();
        let new_worst = touched
            .iter()
            .map(|&q| quality(p, q))
            .fold(f64::INFINITY, f64::min);
        if finite && new_worst > 0.0 && new_worst >= KEEP_QUALITY * old_worst.min(1.0) {
            if interior {
                report.replaced += 1;
            } else {
                report.boundary_replaced += 1;
            }
            changed.extend_from_slice(&movable);
            continue;
        }
        // undo: drop the disk, bring the star back, restore the ring
        for q in saved_quads..p.quads.len() {
            for &x in &p.quads[q] {
                at[x as usize].retain(|&y| y != q as u32);
            }
        }
        p.quads.truncate(saved_quads);
        p.quad_tri.truncate(saved_quads);
        alive.truncate(saved_quads);
        for &q in &star {
            alive[q as usize] = true;
            for &x in &p.quads[q as usize] {
                at[x as usize].push(q);
            }
        }
        p.nodes.truncate(saved_nodes);
        p.pos.truncate(saved_nodes);
        at.truncate(saved_nodes);
        for (&w, &(uv, x)) in movable_ring.iter().zip(&saved_ring) {
            p.nodes[w as usize].uv = uv;
            p.pos[w as usize] = x;
        }
        report.undone += 1;
    }
    // drop the replaced quads, keeping the order of the others
    drop_dead_quads(p, &alive);
    // the new disks smoothed with the quads around them (Winslow / angle-based, with rollback)
    crate::smoothing::optimize_around(face, p, &changed);
    report
}

/// Drops the quads (and their source triangles) whose `alive` flag is false,
/// keeping the order of the others: the last step of a local replacement.
pub(crate) fn drop_dead_quads(p: &mut QuadPatch, alive: &[bool]) {
    let mut k = 0;
    p.quads.retain(|_| {
        k += 1;
        alive[k - 1]
    });
    let mut k = 0;
    p.quad_tri.retain(|_| {
        k += 1;
        alive[k - 1]
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use geometry::primitives;

    /// A planar patch: an interior vertex of valence 6 at the origin, its six
    /// quads, and a layer of quads around them whose outer vertices are on a
    /// curve (fixed). Positions in the z = 0 plane of the unit square model's face.
    fn valence_six_patch() -> QuadPatch {
        let mut p = QuadPatch::default();
        let add = |uv: [f64; 2], node: NodeRef, p: &mut QuadPatch| {
            p.nodes.push(LocalNode {
                uv,
                node,
                pole: None,
            });
            p.pos.push([uv[0], uv[1], 0.0]);
            (p.nodes.len() - 1) as u32
        };
        let c = add([0.0, 0.0], NodeRef::Interior, &mut p);
        let polar = |r: f64, deg: f64| [r * deg.to_radians().cos(), r * deg.to_radians().sin()];
        // ring: edge neighbours at radius 1 (angles 0, 60, …), diagonals at radius 1.6 (30, 90, …)
        let ring: Vec<u32> = (0..12)
            .map(|j| {
                add(
                    polar(if j % 2 == 0 { 1.0 } else { 1.6 }, 30.0 * j as f64),
                    NodeRef::Interior,
                    &mut p,
                )
            })
            .collect();
        let outer: Vec<u32> = (0..12)
            .map(|j| {
                add(
                    polar(3.0, 30.0 * j as f64),
                    NodeRef::Curve(geometry::CurveId(0), j as u32 + 1),
                    &mut p,
                )
            })
            .collect();
        for i in 0..6 {
            p.quads
                .push([c, ring[2 * i], ring[2 * i + 1], ring[(2 * i + 2) % 12]]);
        }
        for j in 0..12 {
            p.quads
                .push([ring[(j + 1) % 12], ring[j], outer[j], outer[(j + 1) % 12]]);
        }
        p.quad_tri = (0..p.quads.len() as u32).collect();
        p
    }

    #[test]
    fn a_valence_six_vertex_is_removed_and_the_mesh_stays_valid() {
        let model = primitives::square(1.0);
        let face = &model.faces[0];
        let mut p = valence_six_patch();
        for q in &p.quads {
            assert!(
                quad_quality(face, &p.nodes, &p.pos, q) > 0.0,
                "the test patch is valid"
            );
        }
        let outer_before: Vec<([f64; 2], [f64; 3])> =
            (13..25).map(|i| (p.nodes[i].uv, p.pos[i])).collect();
        let r = remove_defects(face, &mut p);
        assert_eq!(r.found, 1);
        assert_eq!(r.replaced, 1, "{r:?}");
        let at = incidence(&p);
        let interior_valences: Vec<usize> = (0..p.nodes.len())
            .filter(|&i| p.nodes[i].node == NodeRef::Interior && !at[i].is_empty())
            .map(|i| at[i].len())
            .collect();
        assert!(
            interior_valences.iter().all(|&k| (3..=5).contains(&k)),
            "{interior_valences:?}"
        );
        for q in &p.quads {
            assert!(
                quad_quality(face, &p.nodes, &p.pos, q) > 0.0,
                "quad {q:?} invalid after the replacement"
            );
        }
        // fixed curve vertices did not move
        let outer_after: Vec<([f64; 2], [f64; 3])> =
            (13..25).map(|i| (p.nodes[i].uv, p.pos[i])).collect();
        assert_eq!(outer_before, outer_after);
        // Euler characteristic of the disk patch is still 1
        let used = at.iter().filter(|a| !a.is_empty()).count();
        let mut edges = std::collections::HashSet::new();
        for q in &p.quads {
            for k in 0..4 {
                edges.insert((q[k].min(q[(k + 1) % 4]), q[k].max(q[(k + 1) % 4])));
            }
        }
        assert_eq!(used as i64 - edges.len() as i64 + p.quads.len() as i64, 1);
    }

    #[test]
    fn an_invalid_result_is_undone_exactly() {
        // the same patch on a face whose normal points the other way: every
        // quad is inverted there, so no replacement can be kept
        let mut model = primitives::square(1.0);
        model.faces[0].reversed = true;
        let face = &model.faces[0];
        let mut p = valence_six_patch();
        let before = (
            p.quads.clone(),
            p.nodes.iter().map(|n| n.uv).collect::<Vec<_>>(),
            p.pos.clone(),
            p.nodes.len(),
        );
        let r = remove_defects(face, &mut p);
        assert_eq!((r.found, r.replaced, r.undone), (1, 0, 1));
        assert_eq!(
            before,
            (
                p.quads.clone(),
                p.nodes.iter().map(|n| n.uv).collect::<Vec<_>>(),
                p.pos.clone(),
                p.nodes.len()
            )
        );
    }

    /// A 4 × 4 grid on the unit square whose corner (0, 0) has two quads:
    /// the edge between the first two cells of the bottom row turned so
    /// that it ends at the corner. Returns the patch and the corner's id.
    fn corner_with_two_quads() -> (QuadPatch, u32) {
        let n = 4;
        let id = |x: usize, y: usize| crate::fixtures::grids::grid_id(n, x, y);
        let mut p = crate::fixtures::grids::square_grid(n, |x, y| y == 0 && x < 2);
        let (a, b, e) = (id(0, 0), id(1, 0), id(2, 0));
        let (d, c, f) = (id(0, 1), id(1, 1), id(2, 1));
        p.quads.push([a, b, e, f]);
        p.quads.push([a, f, c, d]);
        p.quad_tri = (0..p.quads.len() as u32).collect();
        (p, a)
    }

    #[test]
    fn a_corner_with_too_many_quads_gets_its_ideal_valence_back() {
        let model = primitives::square(1.0);
        let face = &model.faces[0];
        let (mut p, corner) = corner_with_two_quads();
        let star = incidence(&p)[corner as usize].clone();
        assert_eq!(star.len(), 2);
        // the fan's outer loop runs through the corner: a, b, e, f, c, d
        let ring = boundary_star_loop(&p.quads, corner, &star).unwrap();
        assert_eq!(ring, vec![0, 1, 2, 7, 6, 5]);
        assert_eq!(corner_ideal(&p, &star, corner), 1);
        let quads_before = p.quads.len();
        let r = remove_defects(face, &mut p);
        assert_eq!(
            (r.found, r.boundary_found, r.boundary_replaced),
            (0, 1, 1),
            "{r:?}"
        );
        let at = incidence(&p);
        // the corner has one quad, the bottom curve vertex two, every interior vertex four
        assert_eq!(at[corner as usize].len(), 1);
        assert_eq!(at[1].len(), 2);
        for (v, nd) in p.nodes.iter().enumerate() {
            if nd.node == NodeRef::Interior {
                assert_eq!(at[v].len(), 4, "vertex {v}");
            }
        }
        assert_eq!(p.quads.len(), quads_before);
        for q in &p.quads {
            assert!(
                quad_quality(face, &p.nodes, &p.pos, q) > 0.0,
                "quad {q:?} invalid"
            );
        }
    }

    #[test]
    fn a_star_whose_outer_edges_pinch_has_no_boundary_loop() {
        // two quads meeting only at vertex 0: the outer edges pass 0 twice
        let quads = [[0, 1, 2, 3], [0, 4, 5, 6]];
        assert_eq!(boundary_star_loop(&quads, 0, &[0, 1]), None);
        // one quad: its own four vertices from 0
        assert_eq!(boundary_star_loop(&quads, 2, &[0]), Some(vec![2, 3, 0, 1]));
    }
}
