//! Disk quadrangulations (paper §6.3.1, spec §11.3): every quad mesh of a
//! topological disk with a given number of boundary vertices `b` and
//! interior vertices `n_int`, up to rotation and reflection, with interior
//! valences 3–5 and boundary quad counts 1–3 — the replacements the local
//! cavity remeshing chooses from.
//!
//! **Enumeration** by shelling: start from one quad and attach a new quad
//! along 1, 2 or 3 consecutive boundary edges of the current disk
//! (2, 1 or 0 new vertices). Every quad disk can be built that way (2-balls
//! are shellable), and every intermediate disk is a sub-disk of the result,
//! so pruning is exact: a vertex that becomes interior has its final valence
//! (must be 3–5); no vertex may ever have more than 5 quads; quads and
//! interior vertices never decrease. With `F = (b − 2)/2 + n_int` quads, the
//! enumeration to `b ≤ B`, `n_int ≤ I` runs all disks with at most
//! `(B − 2)/2 + I` quads and `I` interior vertices.
//!
//! **Canonical form** (instead of Nauty): for each boundary vertex as root and
//! each direction (the other is the mirror image), vertices are relabelled by
//! a traversal that is unique for a rooted planar map — boundary vertices
//! first, in boundary order from the root, then interior vertices in the order
//! quads are reached from the boundary edges; the code is the list of quads
//! in that order. The smallest code over the `2b` roots identifies the disk.
//!
//! The table up to `b ≤ 12`, `n_int ≤ 4` ([`table`]) is stored in
//! `disk_quads/table.txt`, written by this module's enumerator (the
//! `disk_table` example with `--write`); a test checks that the stored table
//! is exactly the enumerator's output, so it stays reproducible.

use std::collections::HashSet;
use std::sync::OnceLock;

/// Largest boundary size of [`table`].
pub const TABLE_MAX_BOUNDARY: usize = 12;
/// Largest interior vertex count of [`table`].
pub const TABLE_MAX_INTERIOR: usize = 4;
/// Largest number of quads at a vertex during enumeration (interior
/// valences above 5 are never useful).
const MAX_VALENCE: u8 = 5;
/// Smallest interior valence kept.
const MIN_INTERIOR_VALENCE: u8 = 3;
/// Largest boundary quad count `n^in` of a stored disk.
const MAX_BOUNDARY_QUADS: u8 = 3;

/// One disk quadrangulation in canonical labelling: vertices `0..b` are the
/// boundary, counter-clockwise; `b..b + n_int` are interior.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct DiskQuadrangulation {
    /// Number of boundary vertices `b` (even).
    pub boundary: usize,
    /// Number of interior vertices.
    pub interior: usize,
    /// Quads, counter-clockwise, in local vertex indices.
    pub quads: Vec<[u8; 4]>,
    /// Quads at each boundary vertex (`n^in`), in boundary order.
    pub boundary_quads: Vec<u8>,
}

impl DiskQuadrangulation {
    /// Quads at each vertex (boundary then interior).
    pub fn valences(&self) -> Vec<u8> {
        let mut v = vec![0u8; self.boundary + self.interior];
        for q in &self.quads {
            for &x in q {
                v[x as usize] += 1;
            }
        }
        v
    }
}

/// A disk under construction: quads on vertex ids, its boundary cycle
/// (counter-clockwise: the disk on the left) and the quads at each vertex.
#[derive(Clone, Debug)]
struct Disk {
    quads: Vec<[u16; 4]>,
    boundary: Vec<u16>,
    quads_at: Vec<u8>,
    interior: usize,
}

impl Disk {
    fn single_quad() -> Disk {
        Disk {
            quads: vec![[0, 1, 2, 3]],
            boundary: vec![0, 1, 2, 3],
            quads_at: vec![1; 4],
            interior: 0,
        }
    }

    /// True when an edge joins `a` and `b`.
    fn adjacent(&self, a: u16, b: u16) -> bool {
        self.quads.iter().any(|q| {
            (0..4).any(|k| (q[k] == a && q[(k + 1) % 4] == b) || (q[k] == b && q[(k + 1) % 4] == a))
        })
    }

    /// Attaches a quad along the `k` boundary edges that start at boundary
    /// position `at`; `None` when that is not allowed (double edge, a new
    /// interior vertex off 3–5 quads, a vertex above 5 quads).
    fn attach(&self, at: usize, k: usize) -> Option<Disk> {
        let b = self.boundary.len();
        if k == 3 && b < 6 {
            return None;
        }
        let path: Vec<u16> = (0..=k).map(|i| self.boundary[(at + i) % b]).collect();
        let mut d = self.clone();
        let fresh = |d: &mut Disk| {
            d.quads_at.push(0);
            (d.quads_at.len() - 1) as u16
        };
        let (quad, replacement): ([u16; 4], Vec<u16>) = match k {
            1 => {
                let (a, c) = (fresh(&mut d), fresh(&mut d));
                ([path[1], path[0], a, c], vec![path[0], a, c, path[1]])
            }
            2 => {
                let a = fresh(&mut d);
                ([path[2], path[1], path[0], a], vec![path[0], a, path[2]])
            }
            3 => {
                if self.adjacent(path[0], path[3]) {
                    return None;
                }
                ([path[3], path[2], path[1], path[0]], vec![path[0], path[3]])
            }
            _ => return None,
        };
        for &v in &quad {
            d.quads_at[v as usize] += 1;
            if d.quads_at[v as usize] > MAX_VALENCE {
                return None;
            }
        }
        // vertices strictly inside the path become interior with their final valence
        for &v in &path[1..k] {
            if d.quads_at[v as usize] < MIN_INTERIOR_VALENCE {
                return None;
            }
            d.interior += 1;
        }
        d.quads.push(quad);
        // new boundary: path[0] .. replacement .. path[k], then the rest
        let mut nb = replacement;
        for i in k + 1..b {
            nb.push(self.boundary[(at + i) % b]);
        }
        d.boundary = nb;
        Some(d)
    }

    /// The canonical code: the smallest rooted code over every boundary
    /// vertex as root, read counter-clockwise and clockwise (the mirror).
    ///
    /// A rooted code lists `b`, `n_int`, then the quads in the order a
    /// breadth-first walk reaches them — first across the boundary edges in
    /// order from the root, then across each visited quad's other edges —
    /// each quad as its labels from its entry edge; boundary vertices are
    /// labelled `0..b` in order from the root, interior vertices as first met.
    fn canonical(&self) -> Vec<u16> {
        let b = self.boundary.len();
        let nv = self.quads_at.len();
        const NONE: u16 = u16::MAX;
        let mut best: Option<Vec<u16>> = None;
        let mut label = vec![NONE; nv];
        let mut seen = vec![false; self.quads.len()];
        let mut queue: std::collections::VecDeque<(u16, u16)> = std::collections::VecDeque::new();
        let mut code = Vec::with_capacity(2 + 4 * self.quads.len());
        for mirror in [false, true] {
            let quads: Vec<[u16; 4]> = if mirror {
                self.quads
                    .iter()
                    .map(|q| [q[0], q[3], q[2], q[1]])
                    .collect()
            } else {
                self.quads.clone()
            };
            // the quad (and local edge) on the left of each directed edge
            let mut left = vec![(u16::MAX, 0u8); nv * nv];
            for (qi, q) in quads.iter().enumerate() {
                for k in 0..4 {
                    left[q[k] as usize * nv + q[(k + 1) % 4] as usize] = (qi as u16, k as u8);
                }
            }
            for root in 0..b {
                let bnd = |i: usize| {
                    if mirror {
                        self.boundary[(root + b - i) % b]
                    } else {
                        self.boundary[(root + i) % b]
                    }
                };
                label.iter_mut().for_each(|l| *l = NONE);
                seen.iter_mut().for_each(|x| *x = false);
                for i in 0..b {
                    label[bnd(i) as usize] = i as u16;
                }
                let mut next = b as u16;
                queue.clear();
                queue.extend((0..b).map(|i| (bnd(i), bnd(i + 1))));
                code.clear();
                code.push(b as u16);
                code.push(self.interior as u16);
                let mut worse = false;
                while let Some((u, v)) = queue.pop_front() {
                    let (qi, k) = left[u as usize * nv + v as usize];
                    if qi == u16::MAX || seen[qi as usize] {
                        continue;
                    }
                    seen[qi as usize] = true;
                    let q = quads[qi as usize];
                    let k = k as usize;
                    let r = [q[k], q[(k + 1) % 4], q[(k + 2) % 4], q[(k + 3) % 4]];
                    for &x in &r {
                        if label[x as usize] == NONE {
                            label[x as usize] = next;
                            next += 1;
                        }
                        code.push(label[x as usize]);
                    }
                    for j in 1..4 {
                        queue.push_back((r[(j + 1) % 4], r[j]));
                    }
                    // stop early once this code is already larger than the best
                    if let Some(bst) = &best {
                        let n = code.len();
                        match code[..].cmp(&bst[..n]) {
                            std::cmp::Ordering::Greater => {
                                worse = true;
                                break;
                            }
                            std::cmp::Ordering::Less => {}
                            std::cmp::Ordering::Equal => {}
                        }
                    }
                }
                if !worse && best.as_ref().is_none_or(|x| code < *x) {
                    best = Some(code.clone());
                }
            }
        }
        best.expect("a disk has a boundary")
    }
}

/// The stored form of a disk from its canonical code.
fn table_entry(code: &[u16]) -> DiskQuadrangulation {
    let b = code[0] as usize;
    let interior = code[1] as usize;
    let quads: Vec<[u8; 4]> = code[2..]
        .chunks(4)
        .map(|c| [c[0] as u8, c[1] as u8, c[2] as u8, c[3] as u8])
        .collect();
    let mut d = DiskQuadrangulation {
        boundary: b,
        interior,
        quads,
        boundary_quads: Vec::new(),
    };
    d.boundary_quads = d.valences()[..b].to_vec();
    d
}

/// Every disk quadrangulation with `4 ≤ b ≤ max_boundary` boundary vertices
/// and `n_int ≤ max_interior` interior vertices, interior valences 3–5 and
/// 1–3 quads at each boundary vertex, once each up to rotation and
/// reflection; sorted by (b, n_int, code).
pub fn enumerate(max_boundary: usize, max_interior: usize) -> Vec<DiskQuadrangulation> {
    if max_boundary < 4 {
        return Vec::new();
    }
    let max_quads = (max_boundary - 2) / 2 + max_interior;
    let first = Disk::single_quad();
    let mut level: Vec<(Disk, Vec<u16>)> = vec![(first.clone(), first.canonical())];
    let mut out: Vec<(Vec<u16>, DiskQuadrangulation)> = Vec::new();
    let keep = |d: &Disk, code: &[u16], out: &mut Vec<(Vec<u16>, DiskQuadrangulation)>| {
        if d.boundary.len() <= max_boundary
            && d.boundary
                .iter()
                .all(|&v| d.quads_at[v as usize] <= MAX_BOUNDARY_QUADS)
        {
            out.push((code.to_vec(), table_entry(code)));
        }
    };
    keep(&level[0].0, &level[0].1, &mut out);
    for _ in 1..max_quads {
        let mut seen: HashSet<Vec<u16>> = HashSet::new();
        let mut next = Vec::new();
        for (d, _) in &level {
            for k in 1..=3 {
                for at in 0..d.boundary.len() {
                    let Some(n) = d.attach(at, k) else { continue };
                    if n.interior > max_interior {
                        continue;
                    }
                    let code = n.canonical();
                    if seen.insert(code.clone()) {
                        next.push((n, code));
                    }
                }
            }
        }
        for (d, code) in &next {
            keep(d, code, &mut out);
        }
        level = next;
    }
    out.sort_by(|a, b| (a.1.boundary, a.1.interior, &a.0).cmp(&(b.1.boundary, b.1.interior, &b.0)));
    out.into_iter().map(|(_, d)| d).collect()
}

/// The stored table: [`format_table`] of `enumerate(TABLE_MAX_BOUNDARY,
/// TABLE_MAX_INTERIOR)`, written by `cargo run --release -p quadrille
/// --example disk_table -- --write` (a test checks it is the enumerator's
/// output). Reading it takes microseconds; enumerating takes half a second.
const STORED_TABLE: &str = include_str!("disk_quads/table.txt");

/// The table as text: one disk per line, `b n_int` then its quads' vertices.
pub fn format_table(disks: &[DiskQuadrangulation]) -> String {
    let mut out = String::new();
    for d in disks {
        out.push_str(&format!("{} {}", d.boundary, d.interior));
        for q in &d.quads {
            for v in q {
                out.push_str(&format!(" {v}"));
            }
        }
        out.push('\n');
    }
    out
}

/// Reads [`format_table`]'s text; `None` on any malformed line or an empty text.
pub fn parse_table(text: &str) -> Option<Vec<DiskQuadrangulation>> {
    if text.trim().is_empty() {
        return None;
    }
    text.lines()
        .filter(|l| !l.trim().is_empty())
        .map(|line| {
            let v: Vec<usize> = line
                .split_whitespace()
                .map(|x| x.parse().ok())
                .collect::<Option<_>>()?;
            let (b, ni) = (*v.first()?, *v.get(1)?);
            let rest = &v[2..];
            if rest.len() % 4 != 0
                || rest.len() / 4 != (b.checked_sub(2)?) / 2 + ni
                || rest.iter().any(|&x| x >= b + ni)
            {
                return None;
            }
            let quads: Vec<[u8; 4]> = rest
                .chunks(4)
                .map(|c| [c[0] as u8, c[1] as u8, c[2] as u8, c[3] as u8])
                .collect();
            let mut d = DiskQuadrangulation {
                boundary: b,
                interior: ni,
                quads,
                boundary_quads: Vec::new(),
            };
            d.boundary_quads = d.valences()[..b].to_vec();
            Some(d)
        })
        .collect()
}

/// The table of disk quadrangulations up to [`TABLE_MAX_BOUNDARY`] boundary
/// and [`TABLE_MAX_INTERIOR`] interior vertices: the stored copy, or the
/// enumerator's output should the stored copy ever fail to read.
pub fn table() -> &'static [DiskQuadrangulation] {
    static TABLE: OnceLock<Vec<DiskQuadrangulation>> = OnceLock::new();
    TABLE.get_or_init(|| {
        parse_table(STORED_TABLE)
            .unwrap_or_else(|| enumerate(TABLE_MAX_BOUNDARY, TABLE_MAX_INTERIOR))
    })
}

/// One vertex of a cavity boundary, as the choice of a replacement sees it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CavityVertex {
    /// Ideal valence `n̄` (4 inside a face, 2 on a curve, a corner's ideal).
    pub ideal: u8,
    /// Quads outside the cavity at this vertex (`n^out`, fixed).
    pub outside: u8,
    /// Allowed total valence `n^in + n^out` after the replacement (inclusive).
    pub allowed: (u8, u8),
}

/// A table disk placed on a cavity boundary: table boundary vertex `i` goes
/// to cavity position `(rotation + i) mod b`, or `(rotation − i) mod b` when
/// `mirror` (then the disk's quads are reversed).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Placement {
    /// Index of the disk in the table searched.
    pub disk: usize,
    /// Cavity position of the disk's boundary vertex 0.
    pub rotation: usize,
    /// Read the disk clockwise.
    pub mirror: bool,
    /// Eq. 15's irregularity `I_r` of the result.
    pub irregularity: u32,
}

impl Placement {
    /// Cavity position of the disk's boundary vertex `i` (`b` boundary vertices).
    pub fn position(&self, i: usize, b: usize) -> usize {
        if self.mirror {
            (self.rotation + b - i % b) % b
        } else {
            (self.rotation + i) % b
        }
    }

    /// The replacement quads on mesh vertex ids: `boundary` the cavity's
    /// vertices (counter-clockwise), `interior` ids for the disk's interior
    /// vertices (as many as it has). Quads come out counter-clockwise.
    pub fn quads(
        &self,
        disk: &DiskQuadrangulation,
        boundary: &[u32],
        interior: &[u32],
    ) -> Vec<[u32; 4]> {
        let b = boundary.len();
        let id = |v: u8| {
            let v = v as usize;
            if v < disk.boundary {
                boundary[self.position(v, b)]
            } else {
                interior[v - disk.boundary]
            }
        };
        disk.quads
            .iter()
            .map(|q| {
                let m = q.map(id);
                if self.mirror {
                    [m[0], m[3], m[2], m[1]]
                } else {
                    m
                }
            })
            .collect()
    }
}

/// The best replacement of a cavity by a disk of `disks` (Eq. 15 of the
/// paper): over every disk with as many boundary vertices as the cavity, in
/// every rotation and both directions, whose boundary valences stay in each
/// vertex's allowed range, the one with the smallest irregularity
/// `I_r = Σ_boundary (n̄ − n^out − n^in)² + Σ_interior (4 − n^in)²`; ties go to
/// the fewest interior vertices, then to the first found. `None` when no
/// disk fits.
pub fn best_replacement(
    disks: &[DiskQuadrangulation],
    cavity: &[CavityVertex],
) -> Option<Placement> {
    let b = cavity.len();
    let mut best: Option<(u32, usize, Placement)> = None;
    for (di, d) in disks.iter().enumerate().filter(|(_, d)| d.boundary == b) {
        let inner: u32 = d.valences()[b..]
            .iter()
            .map(|&k| (4 - k as i32).pow(2) as u32)
            .sum();
        for mirror in [false, true] {
            'rot: for rotation in 0..b {
                let p = Placement {
                    disk: di,
                    rotation,
                    mirror,
                    irregularity: 0,
                };
                let mut ir = inner;
                for (i, &n_in) in d.boundary_quads.iter().enumerate() {
                    let c = cavity[p.position(i, b)];
                    let total = n_in + c.outside;
                    if total < c.allowed.0 || total > c.allowed.1 {
                        continue 'rot;
                    }
                    ir += (c.ideal as i32 - total as i32).pow(2) as u32;
                }
                let key = (ir, d.interior);
                if best.as_ref().is_none_or(|(bi, bn, _)| key < (*bi, *bn)) {
                    best = Some((
                        ir,
                        d.interior,
                        Placement {
                            irregularity: ir,
                            ..p
                        },
                    ));
                }
            }
        }
    }
    best.map(|(_, _, p)| p)
}

#[cfg(test)]
mod tests;
