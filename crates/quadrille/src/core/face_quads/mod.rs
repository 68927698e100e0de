//! [`FaceQuads`]: the editable quads of **one CAD face**, shared by the
//! methods that change quad-mesh topology (the regular method's swaps,
//! collapses and splits; later the quasi-structured cavity remeshing).
//!
//! What it holds, per face:
//! - vertices with (u, v) (authoritative), xyz = S(u, v) (derived), their
//!   classification on the model ([`NodeClass`]), whether they are fixed (face
//!   boundary: corners, curve nodes, poles, seam copies) and their fan (the
//!   incident quads, unordered);
//! - quads as 4 vertex ids, counter-clockwise seen from the oriented face
//!   normal (the [`mesh::QuadMesh`] convention);
//! - a journal of every change since the last [`FaceQuads::checkpoint`], so that
//!   a region can be rolled back exactly ([`FaceQuads::rollback`]) when an
//!   operation cannot be made geometrically valid.
//!
//! Why per face: faces are independent once their boundary nodes are fixed, so
//! every topological edit stays inside one face and the global mesh remains
//! watertight. Seam nodes appear once per side (two local vertices), so the
//! (u, v) of every local vertex is single-valued and continuous inside the face.
//!
//! Deleted quads and vertices stay in the arrays with `alive == false` (ids are
//! stable during an edit); [`extract`] writes only live ones back.

pub mod extract;

use crate::core::valence::{ideal_boundary_valence, ideal_pole_valence};
use geometry::vec3::{self, Vec3};
use geometry::Face;
use mesh::NodeClass;

/// Fans up to this many quads get [`FaceQuads::ordered_star`]'s plain scan
/// (k² rotations, cheapest when small); larger ones a sorted index.
const STAR_SCAN_MAX: usize = 12;

/// One vertex of a [`FaceQuads`].
#[derive(Clone, Debug, PartialEq)]
pub struct QVertex {
    /// (u, v) in the face's parameter plane (for a pole: a point of its segment).
    pub uv: [f64; 2],
    /// Position on the surface, S(uv) (for fixed vertices: the input position, bit-identical).
    pub xyz: Vec3,
    /// Classification on the model (kept for writing back).
    pub class: NodeClass,
    /// True for vertices that never move and are never removed (face boundary).
    pub fixed: bool,
    /// Index in the global mesh this vertex came from, if any.
    pub global: Option<u32>,
    /// For a vertex on a degenerate curve (a pole): the (u, v) segment that maps to it.
    pub pole: Option<[[f64; 2]; 2]>,
    /// Ideal valence (number of edges): 4 inside, from the corner angle on the boundary.
    pub ideal: u32,
    /// Edges minus incident quads, constant under every operation (0 inside, 1 on an open fan).
    pub edge_offset: u32,
    /// Incident live quads (unordered).
    pub fan: Vec<u32>,
    /// False once the vertex has been merged away.
    pub alive: bool,
}

impl QVertex {
    /// A movable face-interior vertex at `uv` / `xyz` (ideal valence 4, closed fan).
    pub fn interior(uv: [f64; 2], xyz: Vec3, class: NodeClass) -> Self {
        QVertex {
            uv,
            xyz,
            class,
            fixed: false,
            global: None,
            pole: None,
            ideal: 4,
            edge_offset: 0,
            fan: Vec::new(),
            alive: true,
        }
    }

    /// The vertex's (u, v) as seen from `other`: itself, except for a pole,
    /// which is the point of its degenerate segment nearest to `other`.
    pub fn uv_toward(&self, other: [f64; 2]) -> [f64; 2] {
        match self.pole {
            None => self.uv,
            // the nearest point of the pole's segment, as the CAD normals take it
            Some(seg) => geometry::CornerUv::Pole(seg).toward(other),
        }
    }
}

#[derive(Clone, Debug)]
enum Undo {
    Vertex(u32, QVertex),
    Quad(u32, [u32; 4], bool),
    VertsLen(usize),
    QuadsLen(usize),
}

/// A position in the journal: what [`FaceQuads::rollback`] returns to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Checkpoint {
    log: usize,
    nv: usize,
    nq: usize,
}

impl Checkpoint {
    /// Number of vertex slots at the checkpoint (ids at or past it were created later).
    pub fn verts_len(&self) -> usize {
        self.nv
    }
}

/// The editable quad mesh of one face (see the module documentation).
#[derive(Clone, Debug, Default)]
pub struct FaceQuads {
    /// Vertices (dead ones keep their slot).
    pub verts: Vec<QVertex>,
    /// Quads, counter-clockwise seen from the oriented face normal.
    pub quads: Vec<[u32; 4]>,
    /// False for deleted quads.
    pub quad_alive: Vec<bool>,
    log: Vec<Undo>,
}

impl FaceQuads {
    /// Builds the structure from vertices (their `fan`s are recomputed) and quads.
    /// Returns `None` when a quad refers to a missing vertex or repeats one.
    pub fn new(mut verts: Vec<QVertex>, quads: Vec<[u32; 4]>) -> Option<Self> {
        for v in &mut verts {
            v.fan.clear();
        }
        for (qi, q) in quads.iter().enumerate() {
            for i in 0..4 {
                if q[i] as usize >= verts.len() || (0..i).any(|j| q[j] == q[i]) {
                    return None;
                }
                verts[q[i] as usize].fan.push(qi as u32);
            }
        }
        let n = quads.len();
        Some(FaceQuads {
            verts,
            quads,
            quad_alive: vec![true; n],
            log: Vec::new(),
        })
    }

    /// Number of live quads.
    pub fn num_quads(&self) -> usize {
        self.quad_alive.iter().filter(|&&a| a).count()
    }

    /// Number of live vertices.
    pub fn num_verts(&self) -> usize {
        self.verts.iter().filter(|v| v.alive).count()
    }

    /// Ids of the live quads, in increasing order.
    pub fn live_quads(&self) -> impl Iterator<Item = u32> + '_ {
        (0..self.quads.len() as u32).filter(move |&q| self.quad_alive[q as usize])
    }

    /// Valence of `v`: its number of edges (incident quads + the constant offset).
    pub fn valence(&self, v: u32) -> u32 {
        let x = &self.verts[v as usize];
        x.fan.len() as u32 + x.edge_offset
    }

    /// True when `v` is live and its valence differs from its ideal valence.
    pub fn is_irregular(&self, v: u32) -> bool {
        let x = &self.verts[v as usize];
        x.alive && self.valence(v) != x.ideal
    }

    /// Number of live vertices whose valence differs from the ideal one.
    pub fn irregular_count(&self) -> usize {
        (0..self.verts.len() as u32)
            .filter(|&v| self.is_irregular(v))
            .count()
    }

    /// Position of `v` inside quad `q` (`None` when absent).
    pub fn index_in(&self, q: u32, v: u32) -> Option<usize> {
        self.quads[q as usize].iter().position(|&x| x == v)
    }

    /// Quad `q` rotated so that it starts at `v`.
    pub fn rotated(&self, q: u32, v: u32) -> Option<[u32; 4]> {
        let i = self.index_in(q, v)?;
        let a = self.quads[q as usize];
        Some([a[i], a[(i + 1) % 4], a[(i + 2) % 4], a[(i + 3) % 4]])
    }

    /// The live quad other than `q` holding the directed edge `b → a` (the
    /// neighbour of `q` across its edge `a → b`), if any.
    pub fn across(&self, q: u32, a: u32, b: u32) -> Option<u32> {
        self.verts[a as usize]
            .fan
            .iter()
            .copied()
            .find(|&p| p != q && self.rotated(p, b).is_some_and(|r| r[1] == a))
    }

    /// The quads holding the undirected edge `a`–`b` (one on the boundary, two inside).
    pub fn edge_quads(&self, a: u32, b: u32) -> Vec<u32> {
        self.verts[a as usize]
            .fan
            .iter()
            .copied()
            .filter(|&p| self.rotated(p, a).is_some_and(|r| r[1] == b || r[3] == b))
            .collect()
    }

    /// The edge neighbours of `v`, sorted.
    pub fn links(&self, v: u32) -> Vec<u32> {
        let mut out = Vec::new();
        for &q in &self.verts[v as usize].fan {
            if let Some(r) = self.rotated(q, v) {
                out.push(r[1]);
                out.push(r[3]);
            }
        }
        out.sort_unstable();
        out.dedup();
        out
    }

    /// True when `a` and `b` share a mesh edge.
    pub fn linked(&self, a: u32, b: u32) -> bool {
        self.verts[a as usize]
            .fan
            .iter()
            .any(|&q| self.rotated(q, a).is_some_and(|r| r[1] == b || r[3] == b))
    }

    /// The cyclic star of a vertex with a closed fan: sectors `(c, n_i, o_i, n_{i+1})`
    /// in counter-clockwise order, as quad ids (each rotated to start at `c`).
    /// `None` when the fan is not one closed disk (boundary vertices).
    ///
    /// Each sector's successor is the fan's first quad (in fan order) whose
    /// first link is the sector's last. A fan of more than
    /// [`STAR_SCAN_MAX`] quads finds it in a sorted index (k log k instead
    /// of k² rotations: a vertex of valence 100–300 in a triangle split of a
    /// toothed face made the star 71 % of t_gear_60_teeth's regularization),
    /// with the same ties, so the same star.
    pub fn ordered_star(&self, c: u32) -> Option<Vec<(u32, [u32; 4])>> {
        let fan = &self.verts[c as usize].fan;
        let first = *fan.iter().min()?;
        // (first link, position in the fan, quad), sorted, for large fans
        let index: Option<Vec<(u32, usize, u32)>> = (fan.len() > STAR_SCAN_MAX).then(|| {
            let mut ix: Vec<(u32, usize, u32)> = fan
                .iter()
                .enumerate()
                .filter_map(|(i, &p)| self.rotated(p, c).map(|s| (s[1], i, p)))
                .collect();
            ix.sort_unstable_by_key(|e| (e.0, e.1));
            ix
        });
        let successor = |q: u32, link: u32| -> Option<u32> {
            match &index {
                Some(ix) => {
                    let start = ix.partition_point(|e| e.0 < link);
                    ix[start..]
                        .iter()
                        .take_while(|e| e.0 == link)
                        .find(|e| e.2 != q)
                        .map(|e| e.2)
                }
                None => fan
                    .iter()
                    .copied()
                    .find(|&p| p != q && self.rotated(p, c).is_some_and(|s| s[1] == link)),
            }
        };
        let mut out = Vec::with_capacity(fan.len());
        let mut q = first;
        loop {
            let r = self.rotated(q, c)?;
            out.push((q, r));
            if out.len() > fan.len() {
                return None;
            }
            // next sector: the quad holding c → r[3]
            let next = successor(q, r[3])?;
            if next == first {
                break;
            }
            q = next;
        }
        (out.len() == fan.len()).then_some(out)
    }

    /// The quads incident to any of `vs`, sorted and deduplicated.
    pub fn quads_around(&self, vs: &[u32]) -> Vec<u32> {
        let mut out: Vec<u32> = vs
            .iter()
            .filter(|&&v| self.verts[v as usize].alive)
            .flat_map(|&v| self.verts[v as usize].fan.iter().copied())
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    }

    // ----- journaled edits -------------------------------------------------

    /// Marks the current state; [`FaceQuads::rollback`] returns to it.
    pub fn checkpoint(&self) -> Checkpoint {
        Checkpoint {
            log: self.log.len(),
            nv: self.verts.len(),
            nq: self.quads.len(),
        }
    }

    /// Restores the state of `cp` exactly (topology, (u, v), xyz), undoing every later edit.
    pub fn rollback(&mut self, cp: Checkpoint) {
        while self.log.len() > cp.log {
            match self.log.pop() {
                Some(Undo::Vertex(v, old)) => self.verts[v as usize] = old,
                Some(Undo::Quad(q, old, alive)) => {
                    self.quads[q as usize] = old;
                    self.quad_alive[q as usize] = alive;
                }
                Some(Undo::VertsLen(n)) => self.verts.truncate(n),
                Some(Undo::QuadsLen(n)) => {
                    self.quads.truncate(n);
                    self.quad_alive.truncate(n);
                }
                None => break,
            }
        }
        debug_assert_eq!((self.verts.len(), self.quads.len()), (cp.nv, cp.nq));
    }

    /// Forgets the journal (the current state becomes the only one); call when
    /// no checkpoint is outstanding, to bound memory.
    pub fn commit(&mut self) {
        self.log.clear();
    }

    /// Vertices changed or created since `cp` (sorted; dead ones included).
    pub fn touched_since(&self, cp: Checkpoint) -> Vec<u32> {
        let mut out: Vec<u32> = self.log[cp.log.min(self.log.len())..]
            .iter()
            .filter_map(|u| {
                if let Undo::Vertex(v, _) = u {
                    Some(*v)
                } else {
                    None
                }
            })
            .filter(|&v| (v as usize) < cp.nv)
            .collect();
        out.extend(cp.nv as u32..self.verts.len() as u32);
        out.sort_unstable();
        out.dedup();
        out
    }

    /// Quads changed, created or deleted since `cp` (sorted).
    pub fn quads_touched_since(&self, cp: Checkpoint) -> Vec<u32> {
        let mut out: Vec<u32> = self.log[cp.log.min(self.log.len())..]
            .iter()
            .filter_map(|u| {
                if let Undo::Quad(q, _, _) = u {
                    Some(*q)
                } else {
                    None
                }
            })
            .collect();
        out.extend(cp.nq as u32..self.quads.len() as u32);
        out.sort_unstable();
        out.dedup();
        out
    }

    fn save_vertex(&mut self, v: u32) {
        let old = self.verts[v as usize].clone();
        self.log.push(Undo::Vertex(v, old));
    }

    fn save_quad(&mut self, q: u32) {
        self.log.push(Undo::Quad(
            q,
            self.quads[q as usize],
            self.quad_alive[q as usize],
        ));
    }

    /// Adds a vertex; returns its id.
    pub fn add_vertex(&mut self, mut v: QVertex) -> u32 {
        self.log.push(Undo::VertsLen(self.verts.len()));
        v.fan.clear();
        self.verts.push(v);
        (self.verts.len() - 1) as u32
    }

    /// Marks a vertex (which must have an empty fan) as deleted.
    pub fn kill_vertex(&mut self, v: u32) {
        self.save_vertex(v);
        self.verts[v as usize].alive = false;
    }

    /// Adds a quad (fans updated); returns its id.
    pub fn add_quad(&mut self, q: [u32; 4]) -> u32 {
        self.log.push(Undo::QuadsLen(self.quads.len()));
        self.quads.push(q);
        self.quad_alive.push(true);
        let id = (self.quads.len() - 1) as u32;
        for &v in &q {
            self.save_vertex(v);
            self.verts[v as usize].fan.push(id);
        }
        id
    }

    /// Deletes a quad (fans updated).
    pub fn kill_quad(&mut self, q: u32) {
        self.save_quad(q);
        self.quad_alive[q as usize] = false;
        for v in self.quads[q as usize] {
            self.save_vertex(v);
            self.verts[v as usize].fan.retain(|&p| p != q);
        }
    }

    /// Replaces the vertices of quad `q` (fans updated).
    pub fn set_quad(&mut self, q: u32, new: [u32; 4]) {
        let old = self.quads[q as usize];
        self.save_quad(q);
        for v in old {
            if !new.contains(&v) {
                self.save_vertex(v);
                self.verts[v as usize].fan.retain(|&p| p != q);
            }
        }
        for v in new {
            if !old.contains(&v) {
                self.save_vertex(v);
                self.verts[v as usize].fan.push(q);
            }
        }
        self.quads[q as usize] = new;
    }

    /// Moves a movable vertex to `uv` (xyz = S(uv)); fixed vertices are left untouched.
    /// Returns false (and does nothing) when the vertex is fixed or S(uv) is not finite.
    pub fn move_vertex(&mut self, face: &Face, v: u32, uv: [f64; 2]) -> bool {
        if self.verts[v as usize].fixed || !(uv[0].is_finite() && uv[1].is_finite()) {
            return false;
        }
        let xyz = face.surface.eval(uv);
        if !xyz.iter().all(|c| c.is_finite()) {
            return false;
        }
        self.save_vertex(v);
        let x = &mut self.verts[v as usize];
        x.uv = uv;
        x.xyz = xyz;
        if let NodeClass::Face(f, _) = x.class {
            x.class = NodeClass::Face(f, Some(uv));
        }
        true
    }

    /// (u, v) centre of quad `q` (poles taken toward the other vertices).
    pub fn quad_uv_centre(&self, q: u32) -> [f64; 2] {
        let vs = self.quads[q as usize];
        let mut s = [0.0, 0.0];
        let mut k = 0.0;
        for &v in &vs {
            let x = &self.verts[v as usize];
            if x.pole.is_none() {
                s[0] += x.uv[0];
                s[1] += x.uv[1];
                k += 1.0;
            }
        }
        let c = if k > 0.0 {
            [s[0] / k, s[1] / k]
        } else {
            self.verts[vs[0] as usize].uv
        };
        let mut t = [0.0, 0.0];
        for &v in &vs {
            let p = self.verts[v as usize].uv_toward(c);
            t[0] += 0.25 * p[0];
            t[1] += 0.25 * p[1];
        }
        t
    }

    /// The 3D positions of quad `q`'s vertices.
    pub fn quad_xyz(&self, q: u32) -> [Vec3; 4] {
        let vs = self.quads[q as usize];
        [0, 1, 2, 3].map(|i| self.verts[vs[i] as usize].xyz)
    }

    /// Sum over the quads of `v`'s fan of the 3D angle at `v` (degrees): the
    /// face's interior angle at a boundary vertex, 360° inside.
    pub fn angle_sum(&self, v: u32) -> f64 {
        let mut s = 0.0;
        for &q in &self.verts[v as usize].fan {
            if let Some(r) = self.rotated(q, v) {
                let p = self.verts[v as usize].xyz;
                let a = vec3::sub(self.verts[r[1] as usize].xyz, p);
                let b = vec3::sub(self.verts[r[3] as usize].xyz, p);
                let den = vec3::norm(a) * vec3::norm(b);
                if den > 0.0 {
                    s += (vec3::dot(a, b) / den).clamp(-1.0, 1.0).acos().to_degrees();
                }
            }
        }
        s
    }

    /// Completes the classification once fans are known: a movable vertex whose
    /// fan is not a closed disk becomes fixed; every fixed vertex gets its
    /// constant edge offset and its ideal valence: from the interior angle for
    /// curve and corner nodes with an open fan; from the cone angle for a pole
    /// with a closed fan (a sphere pole, a cone apex: [`ideal_pole_valence`]);
    /// its current valence for other odd fixed vertices, which are then never
    /// counted irregular.
    pub fn classify_fixed(&mut self) {
        for v in 0..self.verts.len() as u32 {
            if !self.verts[v as usize].alive {
                continue;
            }
            let closed = self.ordered_star(v).is_some();
            let links = self.links(v).len() as u32;
            let nfan = self.verts[v as usize].fan.len() as u32;
            let angle = self.angle_sum(v);
            let x = &mut self.verts[v as usize];
            if !x.fixed && !closed {
                x.fixed = true;
            }
            if x.fixed {
                x.edge_offset = links.saturating_sub(nfan);
                let odd = x.pole.is_some()
                    || matches!(x.class, NodeClass::Face(..) | NodeClass::Unclassified)
                    || x.edge_offset != 1;
                x.ideal = if x.pole.is_some() && x.edge_offset == 0 && closed {
                    ideal_pole_valence(angle)
                } else if odd {
                    links
                } else {
                    ideal_boundary_valence(angle)
                };
            }
        }
    }

    /// Checks the internal consistency (fans match quads, live quads use live
    /// distinct vertices, every edge has at most 2 quads with opposite
    /// directions). Returns a description of the first problem found.
    pub fn check(&self) -> Result<(), String> {
        for (qi, q) in self.quads.iter().enumerate() {
            if !self.quad_alive[qi] {
                continue;
            }
            for i in 0..4 {
                let v = &self.verts[q[i] as usize];
                if !v.alive {
                    return Err(format!("quad {qi} uses dead vertex {}", q[i]));
                }
                if !v.fan.contains(&(qi as u32)) {
                    return Err(format!("vertex {} misses quad {qi} in its fan", q[i]));
                }
                if (0..i).any(|j| q[j] == q[i]) {
                    return Err(format!("quad {qi} repeats vertex {}", q[i]));
                }
                let (a, b) = (q[i], q[(i + 1) % 4]);
                let same = self.verts[a as usize]
                    .fan
                    .iter()
                    .filter(|&&p| self.rotated(p, a).is_some_and(|r| r[1] == b))
                    .count();
                if same != 1 {
                    return Err(format!("directed edge {a}->{b} used {same} times"));
                }
                if self.edge_quads(a, b).len() > 2 {
                    return Err(format!("edge {a}-{b} is non-manifold"));
                }
            }
        }
        for (vi, v) in self.verts.iter().enumerate() {
            for &q in &v.fan {
                if !self.quad_alive[q as usize] || !self.quads[q as usize].contains(&(vi as u32)) {
                    return Err(format!("vertex {vi} fan lists quad {q} wrongly"));
                }
            }
            if v.alive && !v.fixed && !v.fan.is_empty() && self.ordered_star(vi as u32).is_none() {
                return Err(format!("movable vertex {vi} has an open fan"));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests;
