//! Replacement of a cavity by its pattern (spec §10.4, the acceptance
//! rules of the parent module's documentation): the matched pattern
//! refined and fitted to the cavity's boundary loop, no doubled edge and
//! fewer irregular vertices, the new vertices placed by a harmonic map in
//! (u, v) and smoothed with the region around, the quality check, and the
//! exact undo of a replacement that is not kept.

use std::collections::HashMap;

use geometry::vec3::{self, Vec3};

use crate::combinatorics::patterns::{library, refine};
use crate::core::patch::QuadPatch;
use crate::core::patch::{LocalNode, NodeRef};
use crate::core::quality::quad_quality;

use super::growth::Candidate;
use super::work::{unknown_neighbours, Kind, Work};
use super::{CavityReport, AVG_SLACK};

/// Sweeps of the kernels on a replaced cavity. 8 rather than 30: on the 26
/// shared models the same replacements are kept except on i16o_s9, whose
/// irregular share falls (2.9 → 2.1 %) while its average SICN drops by
/// 0.012; at size factor 0.0625 the cavity stage of i01o_m1 takes a quarter
/// less time (BENCHMARKS.md).
const CAVITY_KERNEL_SWEEPS: usize = 8;
/// Work units charged per vertex of a smoothed cavity (the per-face cap,
/// [`default_work_cap`](super::default_work_cap), was calibrated with this charge).
const SMOOTHING_WORK: usize = 30;
/// Work units charged per star evaluation of the untangler (a few surface
/// evaluations each; a smoothed vertex costs [`SMOOTHING_WORK`]).
const UNTANGLE_EVALUATION_WORK: u64 = 1;
/// The most the kernels are assumed to raise the average SICN of a
/// replacement's region after its Laplacian smoothing. Measured on the 26
/// bundled models and 47 corpus parts (2026-12-07, fourth session): over 2,544
/// smoothed cavities, the 357 kept gained at most 0.021 from the kernels;
/// 1,868 regions started more than 0.03 below the floor and all were undone
/// (BENCHMARKS.md).
const KERNEL_AVG_GAIN: f64 = 0.03;
/// Quads below this SICN after the kernels get the untangler.
const CAVITY_UNTANGLE_BELOW: f64 = 0.2;
/// The most the untangler is assumed to raise the average SICN of a
/// replacement's region. Measured on the 26 bundled models and 12 corpus
/// parts (2026-12-07): over 767 untangled cavities it raised that average
/// by 0.0104 at most (it lifts the worst quads and mostly lowers the
/// average), and none of the 56 kept had an average below the acceptance
/// floor before untangling; 0.05 leaves a wide margin (BENCHMARKS.md).
const UNTANGLE_AVG_GAIN: f64 = 0.05;

impl Work<'_> {
    // ---- replacement --------------------------------------------------

    /// Replaces the cavity by its refined pattern if every acceptance rule
    /// holds (see the module documentation); otherwise leaves the patch as it was.
    pub(super) fn replace(
        &mut self,
        cand: &Candidate,
        keep: f64,
        report: &mut CavityReport,
    ) -> Option<Vec<u32>> {
        let mut key: Vec<u32> = cand.quads.clone();
        key.sort_unstable();
        key.extend([
            u32::MAX,
            cand.found.pattern as u32,
            cand.found.shift as u32,
            cand.found.mirror as u32,
        ]);
        key.extend_from_slice(&cand.found.subdivisions);
        if self.undone.contains(&key) {
            return None;
        }
        let pattern = &library()[cand.found.pattern];
        let refined = refine(pattern, &cand.found.subdivisions);
        let (ring, corners) = (&cand.ring, &cand.corners);
        let (nb, m) = (ring.len(), corners.len());
        if refined.boundary.len() != nb {
            return None;
        }
        let f = &cand.found;
        let ring_of = |k: usize| {
            if f.mirror {
                (corners[(f.shift + 1) % m] + nb - k % nb) % nb
            } else {
                (corners[f.shift] + k) % nb
            }
        };
        let nv = refined.coords.len();
        let first_new = self.p.nodes.len() as u32;
        let mut local = vec![u32::MAX; nv];
        let mut fixed = vec![false; nv];
        for (k, &v) in refined.boundary.iter().enumerate() {
            local[v as usize] = ring[ring_of(k)];
            fixed[v as usize] = true;
        }
        let mut fresh = 0u32;
        for v in 0..nv {
            if !fixed[v] {
                local[v] = first_new + fresh;
                fresh += 1;
            }
        }
        let new_quads: Vec<[u32; 4]> = refined
            .quads
            .iter()
            .map(|q| {
                let l = q.map(|v| local[v as usize]);
                if f.mirror {
                    [l[0], l[3], l[2], l[1]]
                } else {
                    l
                }
            })
            .collect();
        // (a) no new edge between two boundary vertices already linked outside
        let pos_in_ring: HashMap<u32, usize> =
            ring.iter().enumerate().map(|(i, &v)| (v, i)).collect();
        let mut sorted_quads = cand.quads.clone();
        sorted_quads.sort_unstable();
        let in_cav = |q: u32| sorted_quads.binary_search(&q).is_ok();
        for q in &new_quads {
            for k in 0..4 {
                let (a, b) = (q[k], q[(k + 1) % 4]);
                if a == b {
                    return None;
                }
                if let (Some(&i), Some(&j)) = (pos_in_ring.get(&a), pos_in_ring.get(&b)) {
                    let d = (i + nb - j) % nb;
                    if d == 1 || d == nb - 1 {
                        continue;
                    }
                    let linked = self.at[a as usize].iter().any(|&r| {
                        !in_cav(r) && {
                            let o = self.p.quads[r as usize];
                            let i = o.iter().position(|&x| x == a).unwrap_or(0);
                            o[(i + 1) % 4] == b || o[(i + 3) % 4] == b
                        }
                    });
                    if linked {
                        return None;
                    }
                }
            }
        }
        // (d) fewer irregular vertices in the closure
        let mut closure: Vec<u32> = cand
            .quads
            .iter()
            .flat_map(|&q| self.p.quads[q as usize])
            .collect();
        closure.sort_unstable();
        closure.dedup();
        let before = closure.iter().filter(|&&v| self.irregular(v)).count();
        let mut new_count: HashMap<u32, usize> = HashMap::new();
        for q in &new_quads {
            for &v in q {
                *new_count.entry(v).or_insert(0) += 1;
            }
        }
        let mut after = 0;
        for &v in ring {
            let d = self.deg(v) - self.nin(v) + new_count.get(&v).copied().unwrap_or(0);
            if self.irregular_with(v, d) {
                after += 1;
            }
        }
        for v in first_new..first_new + fresh {
            if new_count.get(&v).copied().unwrap_or(0) != 4 {
                after += 1;
            }
        }
        if after >= before {
            return None;
        }
        // the quads whose quality the replacement can change, and their worst before
        // the smoothing region (spec §11.5): the face-interior vertices of the
        // cavity boundary and of the quads around it
        let mut movable_ring: Vec<u32> = Vec::new();
        for &v in ring.iter() {
            for &q in &self.at[v as usize] {
                if !in_cav(q) {
                    movable_ring.extend(
                        self.p.quads[q as usize]
                            .iter()
                            .copied()
                            .filter(|&x| self.kind[x as usize] == Kind::Inner),
                    );
                }
            }
        }
        movable_ring.sort_unstable();
        movable_ring.dedup();
        let mut region_old: Vec<u32> = cand.quads.clone();
        for &v in &movable_ring {
            region_old.extend_from_slice(&self.at[v as usize]);
        }
        region_old.sort_unstable();
        region_old.dedup();
        let old_quality: Vec<f64> = region_old.iter().map(|&q| self.quality(q)).collect();
        let old_worst = old_quality.iter().copied().fold(f64::INFINITY, f64::min);
        let region_old_avg =
            old_quality.iter().sum::<f64>() / region_old.len().max(1) as f64;
        // apply
        let saved_quads = self.p.quads.len();
        let saved_nodes = self.p.nodes.len();
        let saved_ring: Vec<([f64; 2], Vec3)> = movable_ring
            .iter()
            .map(|&v| (self.p.nodes[v as usize].uv, self.p.pos[v as usize]))
            .collect();
        let mut uv: Vec<[f64; 2]> = vec![[0.0, 0.0]; nv];
        let centre = {
            let s = ring.iter().fold([0.0, 0.0], |a, &v| {
                [
                    a[0] + self.p.nodes[v as usize].uv[0],
                    a[1] + self.p.nodes[v as usize].uv[1],
                ]
            });
            [s[0] / nb as f64, s[1] / nb as f64]
        };
        for v in 0..nv {
            uv[v] = if fixed[v] {
                self.p.nodes[local[v] as usize].uv
            } else {
                centre
            };
        }
        crate::direct::pattern_face::harmonic_uv(&refined.quads, &mut uv, &fixed);
        let mut ok = true;
        let mut new_nodes = vec![
            (
                LocalNode {
                    uv: centre,
                    node: NodeRef::Interior,
                    pole: None
                },
                [0.0; 3]
            );
            fresh as usize
        ];
        for v in 0..nv {
            if !fixed[v] {
                let x = self.face.surface.eval(uv[v]);
                ok &= x.iter().all(|c| c.is_finite()) && uv[v].iter().all(|c| c.is_finite());
                new_nodes[(local[v] - first_new) as usize] = (
                    LocalNode {
                        uv: uv[v],
                        node: NodeRef::Interior,
                        pole: None,
                    },
                    x,
                );
            }
        }
        if !ok {
            return None;
        }
        let origin = self
            .p
            .quad_tri
            .get(cand.quads[0] as usize)
            .copied()
            .unwrap_or(0);
        for &q in &cand.quads {
            self.alive[q as usize] = false;
            for &v in &self.p.quads[q as usize] {
                self.at[v as usize].retain(|&r| r != q);
            }
        }
        for (n, x) in new_nodes {
            self.p.nodes.push(n);
            self.p.pos.push(x);
            self.at.push(Vec::new());
            self.kind.push(Kind::Inner);
            self.singular.push(false);
            self.nin.push((0, 0));
        }
        for q in &new_quads {
            let id = self.p.quads.len() as u32;
            for &v in q {
                self.at[v as usize].push(id);
            }
            self.p.quads.push(*q);
            self.p.quad_tri.push(origin);
            self.alive.push(true);
            self.in_c.push(0);
            self.queued.push(0);
            self.barred.push(0);
            self.nbr.push(unknown_neighbours());
        }
        self.forget_neighbours(&cand.quads);
        // geometry: the new vertices and the boundary's face-interior ones
        let movable: Vec<u32> = (first_new..first_new + fresh)
            .chain(movable_ring.iter().copied())
            .collect();
        let region_new = self.smooth_region(
            &movable,
            saved_quads as u32..self.p.quads.len() as u32,
            region_old_avg - AVG_SLACK,
        );
        let mut region_new = region_new;
        region_new.extend(saved_quads as u32..self.p.quads.len() as u32);
        region_new.sort_unstable();
        region_new.dedup();
        let new_quality: Vec<f64> = region_new.iter().map(|&q| self.quality(q)).collect();
        let new_worst = new_quality.iter().copied().fold(f64::INFINITY, f64::min);
        let target = if old_worst > 0.0 {
            keep * old_worst.min(1.0)
        } else {
            0.0
        };
        let new_avg = new_quality.iter().sum::<f64>() / region_new.len().max(1) as f64;
        let accept =
            new_worst > 0.0 && new_worst >= target && new_avg >= region_old_avg - AVG_SLACK;
        if tracing::enabled!(tracing::Level::DEBUG) {
            let avg = |qs: &[u32]| {
                qs.iter().map(|&q| self.quality(q)).sum::<f64>() / qs.len().max(1) as f64
            };
            tracing::debug!(
                "  cavity {} {:?} sides {:?}: {} → {} quads, irregular {before} → {after}, worst {old_worst:.3} → {new_worst:.3}, avg region {:.3} → {:.3}: {}",
                library()[cand.found.pattern].name,
                cand.found.subdivisions,
                cand.corners.iter().enumerate().map(|(i, &c)| (cand.corners[(i + 1) % m] + nb - c) % nb).collect::<Vec<_>>(),
                cand.quads.len(),
                new_quads.len(),
                region_old_avg,
                avg(&region_new),
                if accept { "kept" } else { "undone" }
            );
        }
        if accept {
            self.undone.clear();
            let centre = self.p.pos[ring[0] as usize];
            let radius = region_new
                .iter()
                .flat_map(|&q| self.p.quads[q as usize])
                .map(|v| vec3::dist(self.p.pos[v as usize], centre))
                .fold(0.0, f64::max);
            self.kept_balls.push((centre, radius));
            return Some((first_new..first_new + fresh).collect());
        }
        // undo, exactly
        report.rejected += 1;
        self.undone.insert(key);
        for q in saved_quads..self.p.quads.len() {
            for &v in &self.p.quads[q] {
                if (v as usize) < saved_nodes {
                    self.at[v as usize].retain(|&r| (r as usize) < saved_quads);
                }
            }
        }
        self.p.quads.truncate(saved_quads);
        self.p.quad_tri.truncate(saved_quads);
        self.alive.truncate(saved_quads);
        self.in_c.truncate(saved_quads);
        self.queued.truncate(saved_quads);
        self.barred.truncate(saved_quads);
        for &q in &cand.quads {
            self.alive[q as usize] = true;
            for &v in &self.p.quads[q as usize] {
                let l = &mut self.at[v as usize];
                l.push(q);
                l.sort_unstable();
            }
        }
        self.nbr.truncate(saved_quads);
        self.forget_neighbours(&cand.quads);
        self.p.nodes.truncate(saved_nodes);
        self.p.pos.truncate(saved_nodes);
        self.at.truncate(saved_nodes);
        self.kind.truncate(saved_nodes);
        self.singular.truncate(saved_nodes);
        self.nin.truncate(saved_nodes);
        for (&v, &(uv, x)) in movable_ring.iter().zip(&saved_ring) {
            self.p.nodes[v as usize].uv = uv;
            self.p.pos[v as usize] = x;
        }
        None
    }

    fn quality(&self, q: u32) -> f64 {
        quad_quality(
            self.face,
            &self.p.nodes,
            &self.p.pos,
            &self.p.quads[q as usize],
        )
    }

    /// Smooths the vertices `movable` on a copy of the quads around them
    /// (the other vertices fixed) and writes their new positions back;
    /// returns those quads.
    ///
    /// The untangler runs on a region still below [`CAVITY_UNTANGLE_BELOW`]
    /// after the kernels, unless [`Work::may_reach`] shows the replacement
    /// will be undone anyway (its new quads are `fresh_quads`; `avg_floor`
    /// is the lowest region average the acceptance keeps): the untangler
    /// lifts the worst quads and does not raise the average, so that costly
    /// search would be wasted.
    fn smooth_region(
        &mut self,
        movable: &[u32],
        fresh_quads: std::ops::Range<u32>,
        avg_floor: f64,
    ) -> Vec<u32> {
        let mut quads: Vec<u32> = movable
            .iter()
            .flat_map(|&v| self.at[v as usize].iter().copied())
            .collect();
        quads.sort_unstable();
        quads.dedup();
        let mut map: HashMap<u32, u32> = HashMap::new();
        let mut sub = QuadPatch::default();
        let mut is_movable = vec![false; self.p.nodes.len()];
        for &v in movable {
            is_movable[v as usize] = true;
        }
        let mut back: Vec<u32> = Vec::new();
        for &q in &quads {
            let quad = self.p.quads[q as usize];
            let mut l = [0u32; 4];
            for k in 0..4 {
                let v = quad[k];
                l[k] = *map.entry(v).or_insert_with(|| {
                    let mut n = self.p.nodes[v as usize];
                    if !is_movable[v as usize] {
                        // fixed in the copy: anything but a face-interior node
                        n.node = NodeRef::Corner(geometry::CornerId(u32::MAX));
                    }
                    sub.nodes.push(n);
                    sub.pos.push(self.p.pos[v as usize]);
                    back.push(v);
                    (sub.nodes.len() - 1) as u32
                });
            }
            sub.quads.push(l);
            sub.quad_tri.push(q);
        }
        crate::smoothing::smooth(self.face, &mut sub, 8);
        // the kernels cannot lift a region this far below the floor: the
        // replacement will be undone, so its costliest smoothing is skipped
        // (the work is charged alike, so the budget and the output do not change)
        self.write_back(&sub, &back, &is_movable);
        let charge = (movable.len() * SMOOTHING_WORK) as u64 + quads.len() as u64;
        if !self.may_reach(&quads, fresh_quads.clone(), avg_floor, KERNEL_AVG_GAIN) {
            self.units += charge;
            return quads;
        }
        crate::smoothing::optimize(
            self.face,
            &mut sub,
            &crate::smoothing::OptimizeOptions {
                max_sweeps: CAVITY_KERNEL_SWEEPS,
                ..Default::default()
            },
        );
        let worst = sub
            .quads
            .iter()
            .map(|q| quad_quality(self.face, &sub.nodes, &sub.pos, q))
            .fold(f64::INFINITY, f64::min);
        self.write_back(&sub, &back, &is_movable);
        if worst < CAVITY_UNTANGLE_BELOW
            && self.may_reach(&quads, fresh_quads, avg_floor, UNTANGLE_AVG_GAIN)
        {
            let untangled = crate::smoothing::untangle_counted(
                self.face,
                &mut sub,
                CAVITY_UNTANGLE_BELOW,
                4,
                5000,
                &[],
            );
            // the untangler's star evaluations are the cavity step's costliest
            // work: charged to the face's cap, so the cap bounds them
            self.units += UNTANGLE_EVALUATION_WORK * untangled.evaluations;
            self.write_back(&sub, &back, &is_movable);
        }
        self.units += charge;
        quads
    }

    /// Copies the positions of the movable nodes of `sub` (a copy made by
    /// [`Work::smooth_region`]; `back` maps its nodes to the patch's) to the patch.
    fn write_back(&mut self, sub: &QuadPatch, back: &[u32], is_movable: &[bool]) {
        for (i, &v) in back.iter().enumerate() {
            if is_movable[v as usize] {
                self.p.nodes[v as usize].uv = sub.nodes[i].uv;
                self.p.pos[v as usize] = sub.pos[i];
            }
        }
    }

    /// False when the replacement cannot be kept whatever the next
    /// smoothing step does: the average SICN of the quads the acceptance
    /// judges (`quads` and the new quads `fresh`) is already more than
    /// `gain` (the most that step was measured to add) below `avg_floor`,
    /// the lowest average kept.
    fn may_reach(
        &self,
        quads: &[u32],
        fresh: std::ops::Range<u32>,
        avg_floor: f64,
        gain: f64,
    ) -> bool {
        let mut region: Vec<u32> = quads.iter().copied().chain(fresh).collect();
        region.sort_unstable();
        region.dedup();
        let avg =
            region.iter().map(|&q| self.quality(q)).sum::<f64>() / region.len().max(1) as f64;
        avg + gain >= avg_floor
    }
}
