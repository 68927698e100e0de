//! The body of an MSH 4.1 file, shared by the writers of [`crate::QuadMesh`]
//! and [`crate::HighOrderQuadMesh`]: each hands over its nodes and its
//! elements already in Gmsh's node order ([`FileMesh`]), and this module
//! writes `$MeshFormat`, `$Entities` (points, curves and surfaces with
//! bounding boxes and bounding entities), `$Nodes` in one block per entity
//! and `$Elements` in blocks per entity and type. Node tag = node index + 1,
//! entity tag = id + 1.
//!
//! Elements are grouped by entity in increasing id order (points, then lines,
//! then per face by element type), keeping their relative order within a
//! block.

use std::collections::{BTreeMap, BTreeSet, HashSet};
use std::io::{self, Write};

use geometry::{FaceId, Model, Vec3};

use super::write::{MshEncoding, MshWriteOptions};
use crate::quadmesh::NodeClass;

/// One element as the file holds it.
pub(super) struct FileElement {
    /// Dimension of its entity: 0 point, 1 line, 2 surface element.
    pub dim: i32,
    /// The id (tag − 1) of its corner, curve or face.
    pub entity: u32,
    /// MSH element type.
    pub ty: i32,
    /// Number of leading `nodes` that are its vertices (1, 2, 3 or 4), in
    /// cyclic order: Gmsh's orders put the vertices first.
    pub vertices: usize,
    /// Node indices in Gmsh's order.
    pub nodes: Vec<u32>,
}

/// A mesh as the file holds it: nodes, their classification, elements.
pub(super) struct FileMesh<'a> {
    pub nodes: &'a [Vec3],
    pub node_class: &'a [NodeClass],
    pub elements: Vec<FileElement>,
}

/// Refuses entity ids that do not fit an MSH tag (`id + 1` must be an `int`).
pub(super) fn check_entity_ids(
    node_class: &[NodeClass],
    element_entities: impl Iterator<Item = u32>,
) -> Result<(), String> {
    let ids = node_class
        .iter()
        .filter_map(|c| match c {
            NodeClass::Corner(k) => Some(k.0),
            NodeClass::Curve(k, _) => Some(k.0),
            NodeClass::Face(k, _) => Some(k.0),
            NodeClass::Unclassified => None,
        })
        .chain(element_entities);
    for id in ids {
        if id >= i32::MAX as u32 {
            return Err(format!("entity id {id} does not fit an MSH entity tag"));
        }
    }
    Ok(())
}

/// One entity of `$Entities`.
#[derive(Default)]
struct Entity {
    lo: Vec3,
    hi: Vec3,
    has_box: bool,
    bounding: Vec<i64>,
}

impl Entity {
    fn grow(&mut self, p: Vec3) {
        if !self.has_box {
            self.lo = p;
            self.hi = p;
            self.has_box = true;
        }
        for ((lo, hi), x) in self.lo.iter_mut().zip(&mut self.hi).zip(p) {
            *lo = lo.min(x);
            *hi = hi.max(x);
        }
    }
}

/// Everything the sections need, grouped by entity.
struct Layout {
    /// Entities by dimension (0, 1, 2), keyed by tag.
    entities: [BTreeMap<i64, Entity>; 3],
    /// Node blocks: (dim, tag) → node indices.
    node_blocks: BTreeMap<(i32, i64), Vec<u32>>,
}

fn entity_of(class: &NodeClass) -> Option<(i32, i64)> {
    match class {
        NodeClass::Corner(k) => Some((0, k.0 as i64 + 1)),
        NodeClass::Curve(k, _) => Some((1, k.0 as i64 + 1)),
        NodeClass::Face(k, _) => Some((2, k.0 as i64 + 1)),
        NodeClass::Unclassified => None,
    }
}

/// The elements of dimension `dim`.
fn of_dim<'a>(mesh: &'a FileMesh, dim: i32) -> impl Iterator<Item = &'a FileElement> + Clone {
    mesh.elements.iter().filter(move |e| e.dim == dim)
}

fn layout(mesh: &FileMesh, model: Option<&Model>) -> Layout {
    let mut ents: [BTreeMap<i64, Entity>; 3] = Default::default();
    if let Some(m) = model {
        for (i, c) in m.corners.iter().enumerate() {
            ents[0].entry(i as i64 + 1).or_default().grow(c.point);
        }
        for (i, c) in m.curves.iter().enumerate() {
            let e = ents[1].entry(i as i64 + 1).or_default();
            e.bounding = vec![c.start.0 as i64 + 1, -(c.end.0 as i64 + 1)];
        }
        for (i, f) in m.faces.iter().enumerate() {
            let e = ents[2].entry(i as i64 + 1).or_default();
            for u in f.curve_uses() {
                let t = u.curve.0 as i64 + 1;
                e.bounding.push(if u.forward { t } else { -t });
            }
        }
    }
    // Unclassified nodes go on the face of the first element using them.
    let mut home: Vec<Option<FaceId>> = vec![None; mesh.nodes.len()];
    for el in of_dim(mesh, 2) {
        for &v in &el.nodes {
            home[v as usize].get_or_insert(FaceId(el.entity));
        }
    }
    let mut node_blocks: BTreeMap<(i32, i64), Vec<u32>> = BTreeMap::new();
    for (v, class) in mesh.node_class.iter().enumerate() {
        let key = entity_of(class).unwrap_or_else(|| (2, home[v].map_or(1, |f| f.0 as i64 + 1)));
        node_blocks.entry(key).or_default().push(v as u32);
        let p = mesh.nodes[v];
        let e = ents[key.0 as usize].entry(key.1).or_default();
        if key.0 > 0 || !e.has_box {
            e.grow(p);
        }
    }
    for el in &mesh.elements {
        let e = ents[el.dim as usize]
            .entry(el.entity as i64 + 1)
            .or_default();
        if el.dim > 0 {
            for &v in &el.nodes {
                e.grow(mesh.nodes[v as usize]);
            }
        } else if !e.has_box {
            e.grow(mesh.nodes[el.nodes[0] as usize]);
        }
    }
    if let Some(m) = model {
        // entities of the mesh that the model lacks keep an empty box otherwise
        for (tag, e) in ents[1].iter_mut() {
            if !e.has_box {
                if let Some(c) = m.curves.get((*tag - 1) as usize) {
                    for i in 0..=8 {
                        e.grow(c.eval(m, c.range.0 + (c.range.1 - c.range.0) * i as f64 / 8.0));
                    }
                }
            }
        }
    } else {
        derive_adjacency(mesh, &mut ents);
    }
    Layout {
        entities: ents,
        node_blocks,
    }
}

/// Without a model: curve ends from corner nodes at the ends of line
/// elements, face boundaries from line elements whose ends are the two ends
/// of an element edge of the face.
fn derive_adjacency(mesh: &FileMesh, ents: &mut [BTreeMap<i64, Entity>; 3]) {
    let mut ends: BTreeMap<i64, Vec<i64>> = BTreeMap::new();
    for el in of_dim(mesh, 1) {
        for v in &el.nodes[..el.vertices] {
            if let NodeClass::Corner(k) = mesh.node_class[*v as usize] {
                let list = ends.entry(el.entity as i64 + 1).or_default();
                if !list.contains(&(k.0 as i64 + 1)) {
                    list.push(k.0 as i64 + 1);
                }
            }
        }
    }
    for (tag, list) in ends {
        let e = ents[1].entry(tag).or_default();
        e.bounding = list
            .iter()
            .enumerate()
            .map(|(i, &k)| if i == 0 { k } else { -k })
            .collect();
    }
    let key = |a: u32, b: u32| (a.min(b), a.max(b));
    let mut face_edges: HashSet<(u32, u32, i64)> = HashSet::new();
    for el in of_dim(mesh, 2) {
        let m = el.vertices;
        for k in 0..m {
            let (a, b) = key(el.nodes[k], el.nodes[(k + 1) % m]);
            face_edges.insert((a, b, el.entity as i64 + 1));
        }
    }
    let mut bounds: BTreeMap<i64, BTreeSet<i64>> = BTreeMap::new();
    let faces: Vec<i64> = ents[2].keys().copied().collect();
    for el in of_dim(mesh, 1) {
        let (a, b) = key(el.nodes[0], el.nodes[1]);
        for &f in &faces {
            if face_edges.contains(&(a, b, f)) {
                bounds.entry(f).or_default().insert(el.entity as i64 + 1);
            }
        }
    }
    for (f, set) in bounds {
        if let Some(e) = ents[2].get_mut(&f) {
            e.bounding = set.into_iter().collect();
        }
    }
}

/// Emits tokens as ASCII (space-separated lines) or binary (native-endian
/// `int` = i32, `size_t` = u64, `double` = f64).
struct Emitter<'a, W: Write> {
    w: &'a mut W,
    binary: bool,
    line_start: bool,
}

impl<W: Write> Emitter<'_, W> {
    fn sep(&mut self) -> io::Result<()> {
        if !self.line_start {
            self.w.write_all(b" ")?;
        }
        self.line_start = false;
        Ok(())
    }
    fn int(&mut self, x: i64) -> io::Result<()> {
        if self.binary {
            self.w.write_all(&(x as i32).to_ne_bytes())
        } else {
            self.sep()?;
            write!(self.w, "{x}")
        }
    }
    fn size(&mut self, x: u64) -> io::Result<()> {
        if self.binary {
            self.w.write_all(&x.to_ne_bytes())
        } else {
            self.sep()?;
            write!(self.w, "{x}")
        }
    }
    fn float(&mut self, x: f64) -> io::Result<()> {
        if self.binary {
            self.w.write_all(&x.to_ne_bytes())
        } else {
            self.sep()?;
            // shortest representation that reads back to the same f64
            if x == 0.0 || (1e-5..1e15).contains(&x.abs()) {
                write!(self.w, "{x}")
            } else {
                write!(self.w, "{x:e}")
            }
        }
    }
    fn nl(&mut self) -> io::Result<()> {
        if !self.binary {
            self.w.write_all(b"\n")?;
        }
        self.line_start = true;
        Ok(())
    }
    /// `$Name` line opening a section.
    fn open(&mut self, name: &str) -> io::Result<()> {
        writeln!(self.w, "${name}")?;
        self.line_start = true;
        Ok(())
    }
    /// `$EndName` line; binary data is followed by a newline first.
    fn close(&mut self, name: &str) -> io::Result<()> {
        if self.binary {
            self.w.write_all(b"\n")?;
        }
        writeln!(self.w, "$End{name}")?;
        self.line_start = true;
        Ok(())
    }
}

/// Writes the whole file: every section, from `mesh` (already checked).
pub(super) fn write_file<W: Write>(
    w: &mut W,
    mesh: &FileMesh,
    model: Option<&Model>,
    options: MshWriteOptions,
) -> io::Result<()> {
    let binary = options.encoding == MshEncoding::Binary;
    let lay = layout(mesh, model);
    let mut e = Emitter {
        w,
        binary,
        line_start: true,
    };

    e.open("MeshFormat")?;
    writeln!(e.w, "4.1 {} 8", binary as u8)?;
    if binary {
        e.w.write_all(&1i32.to_ne_bytes())?;
        e.w.write_all(b"\n")?;
    }
    writeln!(e.w, "$EndMeshFormat")?;
    write_entities(&mut e, &lay)?;
    write_nodes(&mut e, &lay, mesh, options.parametric)?;
    write_elements(&mut e, mesh)
}

fn write_entities<W: Write>(e: &mut Emitter<W>, lay: &Layout) -> io::Result<()> {
    e.open("Entities")?;
    for d in 0..3 {
        e.size(lay.entities[d].len() as u64)?;
    }
    e.size(0)?;
    e.nl()?;
    for (d, ents) in lay.entities.iter().enumerate() {
        for (&tag, ent) in ents {
            e.int(tag)?;
            let n = if d == 0 { 3 } else { 6 };
            for k in 0..n {
                e.float(if k < 3 { ent.lo[k] } else { ent.hi[k - 3] })?;
            }
            e.size(0)?; // physical tags
            if d > 0 {
                e.size(ent.bounding.len() as u64)?;
                for &b in &ent.bounding {
                    e.int(b)?;
                }
            }
            e.nl()?;
        }
    }
    e.close("Entities")
}

fn write_nodes<W: Write>(
    e: &mut Emitter<W>,
    lay: &Layout,
    mesh: &FileMesh,
    with_parameters: bool,
) -> io::Result<()> {
    e.open("Nodes")?;
    let nn = mesh.nodes.len() as u64;
    e.size(lay.node_blocks.len() as u64)?;
    e.size(nn)?;
    e.size(if nn == 0 { 0 } else { 1 })?;
    e.size(nn)?;
    e.nl()?;
    for (&(dim, tag), nodes) in &lay.node_blocks {
        let params = |v: u32| -> Option<Vec<f64>> {
            match (dim, mesh.node_class[v as usize]) {
                (1, NodeClass::Curve(_, Some(t))) => Some(vec![t]),
                (2, NodeClass::Face(_, Some(uv))) => Some(uv.to_vec()),
                _ => None,
            }
        };
        let parametric = with_parameters
            && dim > 0
            && nodes
                .iter()
                .all(|&v| params(v).is_some_and(|p| p.iter().all(|x| x.is_finite())));
        e.int(dim as i64)?;
        e.int(tag)?;
        e.int(parametric as i64)?;
        e.size(nodes.len() as u64)?;
        e.nl()?;
        for &v in nodes {
            e.size(v as u64 + 1)?;
            e.nl()?;
        }
        for &v in nodes {
            for x in mesh.nodes[v as usize] {
                e.float(x)?;
            }
            if parametric {
                for x in params(v).unwrap_or_default() {
                    e.float(x)?;
                }
            }
            e.nl()?;
        }
    }
    e.close("Nodes")
}

fn write_elements<W: Write>(e: &mut Emitter<W>, mesh: &FileMesh) -> io::Result<()> {
    // blocks: (dim, tag, type) → elements
    let mut blocks: BTreeMap<(i32, i64, i32), Vec<&[u32]>> = BTreeMap::new();
    for el in &mesh.elements {
        blocks
            .entry((el.dim, el.entity as i64 + 1, el.ty))
            .or_default()
            .push(&el.nodes);
    }
    let ne = mesh.elements.len() as u64;
    e.open("Elements")?;
    e.size(blocks.len() as u64)?;
    e.size(ne)?;
    e.size(if ne == 0 { 0 } else { 1 })?;
    e.size(ne)?;
    e.nl()?;
    let mut tag = 0u64;
    for (&(dim, etag, ty), elems) in &blocks {
        e.int(dim as i64)?;
        e.int(etag)?;
        e.int(ty as i64)?;
        e.size(elems.len() as u64)?;
        e.nl()?;
        for el in elems {
            tag += 1;
            e.size(tag)?;
            for &v in *el {
                e.size(v as u64 + 1)?;
            }
            e.nl()?;
        }
    }
    e.close("Elements")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn float_format_round_trips() {
        let mut out = Vec::new();
        let mut e = Emitter {
            w: &mut out,
            binary: false,
            line_start: true,
        };
        for x in [0.1, 1e-300, -2.5e20, 123456.789, 1.0 / 3.0, -0.0] {
            e.float(x).unwrap();
        }
        let text = String::from_utf8(out).unwrap();
        let back: Vec<f64> = text.split(' ').map(|t| t.parse().unwrap()).collect();
        assert_eq!(back, vec![0.1, 1e-300, -2.5e20, 123456.789, 1.0 / 3.0, 0.0]);
    }
}
