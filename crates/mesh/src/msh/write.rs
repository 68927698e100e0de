//! The MSH 4.1 writer (ASCII and binary).
//!
//! Layout written: `$MeshFormat`, `$Entities` (points, curves and surfaces
//! with bounding boxes and bounding entities), `$Nodes` in one block per
//! entity, `$Elements` in blocks per entity and type (points on corners, lines
//! on curves, quads and triangles on faces). Node tag = node index + 1.
//!
//! Elements are grouped by entity in increasing id order (points, then lines,
//! then per face quads and triangles), keeping their relative order within an
//! entity: a mesh whose element lists are already grouped that way reads back
//! with the same order.
//!
//! Parametric coordinates (the curve parameter of a curve node, the (u, v)
//! of a face node) are written only when [`MshWriteOptions::parametric`] asks
//! for them, and then on the blocks whose every node has them: Gmsh itself
//! writes them only with `Mesh.SaveParametric`, and some readers (meshio)
//! refuse files that have them. Without them the entities and the
//! classification of every node are still written.

use std::collections::{BTreeMap, BTreeSet, HashSet};
use std::io::{self, Write};
use std::path::Path;

use geometry::{FaceId, Model, Vec3};

use super::MshError;
use crate::atomic::write_atomically;
use crate::quadmesh::{NodeClass, QuadMesh};

/// ASCII or binary MSH 4.1.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MshEncoding {
    /// Human-readable text.
    Ascii,
    /// Binary (little-endian on the usual machines, with 8-byte `size_t`): smaller and faster.
    Binary,
}

/// How [`write_msh`] and [`write_msh_to`] write a file: ASCII or binary, with
/// or without parametric coordinates. The default (ASCII, no parametric
/// coordinates) is the file every MSH reader takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MshWriteOptions {
    /// ASCII or binary.
    pub encoding: MshEncoding,
    /// Write the parametric coordinates of curve and face nodes (parametric
    /// flag 1 on the node blocks whose every node has finite parameters). Off
    /// by default: meshio, for one, cannot read such files.
    pub parametric: bool,
}

impl Default for MshWriteOptions {
    fn default() -> Self {
        MshWriteOptions::new(MshEncoding::Ascii)
    }
}

impl MshWriteOptions {
    /// `encoding`, without parametric coordinates.
    pub const fn new(encoding: MshEncoding) -> Self {
        MshWriteOptions {
            encoding,
            parametric: false,
        }
    }

    /// The same options with parametric coordinates on or off.
    pub const fn with_parametric(self, parametric: bool) -> Self {
        MshWriteOptions { parametric, ..self }
    }
}

/// Writes `mesh` to `path` as MSH 4.1. With `model`, every model entity is
/// listed in `$Entities` with its true bounding entities (curve ends, face
/// loops); without it, the entities and their adjacency are derived from the
/// mesh. The file is written atomically: on any error no partial file is left.
///
/// Nodes that are `Unclassified` are written on the surface of the first
/// element using them (a file format needs an entity per node); a reader then
/// sees them as face nodes without parameters.
pub fn write_msh(
    path: &Path,
    mesh: &QuadMesh,
    model: Option<&Model>,
    options: MshWriteOptions,
) -> Result<(), MshError> {
    validate(mesh).map_err(|message| MshError::InvalidMesh {
        path: path.to_path_buf(),
        message,
    })?;
    write_atomically::<io::Error, _>(path, |w| write_body(w, mesh, model, options)).map_err(
        |source| MshError::Io {
            path: path.to_path_buf(),
            source,
        },
    )
}

/// Writes `mesh` as MSH 4.1 to any writer (see [`write_msh`]). An
/// inconsistent mesh gives an `InvalidInput` error before anything is written.
pub fn write_msh_to<W: Write>(
    w: &mut W,
    mesh: &QuadMesh,
    model: Option<&Model>,
    options: MshWriteOptions,
) -> io::Result<()> {
    validate(mesh).map_err(|m| io::Error::new(io::ErrorKind::InvalidInput, m))?;
    write_body(w, mesh, model, options)
}

/// Checks lengths, node references, ids and coordinates.
fn validate(mesh: &QuadMesh) -> Result<(), String> {
    let nn = mesh.nodes.len();
    if nn > u32::MAX as usize {
        return Err(format!("{nn} nodes is more than the writer supports"));
    }
    if mesh.node_class.len() != nn {
        return Err(format!(
            "{} node classifications for {} nodes",
            mesh.node_class.len(),
            nn
        ));
    }
    if mesh.quad_face.len() != mesh.quads.len() {
        return Err(format!(
            "{} quad faces for {} quads",
            mesh.quad_face.len(),
            mesh.quads.len()
        ));
    }
    if mesh.triangle_face.len() != mesh.triangles.len() {
        return Err(format!(
            "{} triangle faces for {} triangles",
            mesh.triangle_face.len(),
            mesh.triangles.len()
        ));
    }
    let bad = |what: &str, i: usize| format!("{what} {i} refers to a missing node");
    for (i, q) in mesh.quads.iter().enumerate() {
        if q.iter().any(|&v| v as usize >= nn) {
            return Err(bad("quad", i));
        }
    }
    for (i, t) in mesh.triangles.iter().enumerate() {
        if t.iter().any(|&v| v as usize >= nn) {
            return Err(bad("triangle", i));
        }
    }
    for (i, (e, _)) in mesh.curve_edges.iter().enumerate() {
        if e.iter().any(|&v| v as usize >= nn) {
            return Err(bad("curve edge", i));
        }
    }
    for (i, (v, _)) in mesh.corner_nodes.iter().enumerate() {
        if *v as usize >= nn {
            return Err(bad("corner node", i));
        }
    }
    if let Some(i) = mesh
        .nodes
        .iter()
        .position(|p| p.iter().any(|x| !x.is_finite()))
    {
        return Err(format!("node {i} has a non-finite coordinate"));
    }
    let too_big = |id: u32| id >= i32::MAX as u32;
    let ids = mesh
        .node_class
        .iter()
        .filter_map(|c| match c {
            NodeClass::Corner(k) => Some(k.0),
            NodeClass::Curve(k, _) => Some(k.0),
            NodeClass::Face(k, _) => Some(k.0),
            NodeClass::Unclassified => None,
        })
        .chain(
            mesh.quad_face
                .iter()
                .chain(&mesh.triangle_face)
                .map(|f| f.0),
        );
    for id in ids {
        if too_big(id) {
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

fn layout(mesh: &QuadMesh, model: Option<&Model>) -> Layout {
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
    let elems = mesh.quads.iter().map(|q| &q[..]).zip(&mesh.quad_face);
    let elems = elems.chain(
        mesh.triangles
            .iter()
            .map(|t| &t[..])
            .zip(&mesh.triangle_face),
    );
    for (nodes, &f) in elems.clone() {
        for &v in nodes {
            home[v as usize].get_or_insert(f);
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
    for (nodes, &f) in elems {
        let e = ents[2].entry(f.0 as i64 + 1).or_default();
        for &v in nodes {
            e.grow(mesh.nodes[v as usize]);
        }
    }
    for ([a, b], c) in &mesh.curve_edges {
        let e = ents[1].entry(c.0 as i64 + 1).or_default();
        e.grow(mesh.nodes[*a as usize]);
        e.grow(mesh.nodes[*b as usize]);
    }
    for (v, k) in &mesh.corner_nodes {
        let e = ents[0].entry(k.0 as i64 + 1).or_default();
        if !e.has_box {
            e.grow(mesh.nodes[*v as usize]);
        }
    }
    if model.is_none() {
        derive_adjacency(mesh, &mut ents);
    } else if let Some(m) = model {
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
    }
    Layout {
        entities: ents,
        node_blocks,
    }
}

/// Without a model: curve ends from corner nodes on curve edges, face
/// boundaries from curve edges that are element edges of the face.
fn derive_adjacency(mesh: &QuadMesh, ents: &mut [BTreeMap<i64, Entity>; 3]) {
    let mut ends: BTreeMap<i64, Vec<i64>> = BTreeMap::new();
    for ([a, b], c) in &mesh.curve_edges {
        for v in [a, b] {
            if let NodeClass::Corner(k) = mesh.node_class[*v as usize] {
                let list = ends.entry(c.0 as i64 + 1).or_default();
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
    let mut face_edges: HashSet<(u32, u32, i64)> = HashSet::new();
    let key = |a: u32, b: u32| (a.min(b), a.max(b));
    for (q, f) in mesh.quads.iter().zip(&mesh.quad_face) {
        for k in 0..4 {
            let (a, b) = key(q[k], q[(k + 1) % 4]);
            face_edges.insert((a, b, f.0 as i64 + 1));
        }
    }
    for (t, f) in mesh.triangles.iter().zip(&mesh.triangle_face) {
        for k in 0..3 {
            let (a, b) = key(t[k], t[(k + 1) % 3]);
            face_edges.insert((a, b, f.0 as i64 + 1));
        }
    }
    let mut bounds: BTreeMap<i64, BTreeSet<i64>> = BTreeMap::new();
    let faces: Vec<i64> = ents[2].keys().copied().collect();
    for ([a, b], c) in &mesh.curve_edges {
        let (a, b) = key(*a, *b);
        for &f in &faces {
            if face_edges.contains(&(a, b, f)) {
                bounds.entry(f).or_default().insert(c.0 as i64 + 1);
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

fn write_body<W: Write>(
    w: &mut W,
    mesh: &QuadMesh,
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
    e.close("Entities")?;

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
        let parametric = options.parametric
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
    e.close("Nodes")?;

    // Element blocks: (dim, tag, type) → node lists.
    let mut blocks: BTreeMap<(i32, i64, i32), Vec<Vec<u32>>> = BTreeMap::new();
    for (v, k) in &mesh.corner_nodes {
        blocks
            .entry((0, k.0 as i64 + 1, 15))
            .or_default()
            .push(vec![*v]);
    }
    for (ed, c) in &mesh.curve_edges {
        blocks
            .entry((1, c.0 as i64 + 1, 1))
            .or_default()
            .push(ed.to_vec());
    }
    for (q, f) in mesh.quads.iter().zip(&mesh.quad_face) {
        blocks
            .entry((2, f.0 as i64 + 1, 3))
            .or_default()
            .push(q.to_vec());
    }
    for (t, f) in mesh.triangles.iter().zip(&mesh.triangle_face) {
        blocks
            .entry((2, f.0 as i64 + 1, 2))
            .or_default()
            .push(t.to_vec());
    }
    let ne: u64 = blocks.values().map(|b| b.len() as u64).sum();
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
            for &v in el {
                e.size(v as u64 + 1)?;
            }
            e.nl()?;
        }
    }
    e.close("Elements")?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures;

    #[test]
    fn ascii_layout_of_a_square() {
        let (model, mesh) = fixtures::square_grid(1.0, 1);
        let mut out = Vec::new();
        write_msh_to(&mut out, &mesh, Some(&model), MshWriteOptions::default()).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert!(
            text.starts_with("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n4 4 1 0\n"),
            "{text}"
        );
        // the face is bounded by its four curves, all forward
        assert!(text.contains("\n1 0 0 0 1 1 0 0 4 1 2 3 4\n"), "{text}");
        // 4 corner nodes in 4 blocks, no curve or face nodes
        assert!(text.contains("$Nodes\n4 4 1 4\n"), "{text}");
        assert!(text.contains("$Elements\n9 9 1 9\n"), "{text}");
        assert!(text.contains("2 1 3 1\n9 1 2 4 3\n"), "{text}");
    }

    #[test]
    fn invalid_mesh_is_refused_and_nothing_written() {
        let (_, mut mesh) = fixtures::square_grid(1.0, 1);
        mesh.quads[0][2] = 99;
        let dir = std::env::temp_dir().join(format!("quadrille-msh-bad-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("bad.msh");
        let err = write_msh(&path, &mesh, None, MshWriteOptions::default()).unwrap_err();
        assert!(
            err.to_string().contains("quad 0 refers to a missing node"),
            "{err}"
        );
        assert!(!path.exists());
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// `(dim, tag, parametric flag)` of every node block of an ASCII file.
    fn node_block_flags(text: &str) -> Vec<(i32, i64, i32)> {
        let nodes = text
            .split("$Nodes\n")
            .nth(1)
            .and_then(|s| s.split("$EndNodes").next())
            .expect("a $Nodes section");
        let mut lines = nodes.lines();
        let head: Vec<usize> = lines
            .next()
            .unwrap()
            .split(' ')
            .map(|t| t.parse().unwrap())
            .collect();
        let mut out = Vec::new();
        for _ in 0..head[0] {
            let b: Vec<i64> = lines
                .next()
                .unwrap()
                .split(' ')
                .map(|t| t.parse().unwrap())
                .collect();
            out.push((b[0] as i32, b[1], b[2] as i32));
            // tags, then coordinates (and parameters)
            for _ in 0..2 * b[3] {
                lines.next().unwrap();
            }
        }
        out
    }

    #[test]
    fn parametric_coordinates_only_on_request() {
        let (model, mesh) = fixtures::cube(2.0, 3);
        let write = |opts: MshWriteOptions| {
            let mut out = Vec::new();
            write_msh_to(&mut out, &mesh, Some(&model), opts).unwrap();
            out
        };
        let plain = String::from_utf8(write(MshWriteOptions::default())).unwrap();
        let flags = node_block_flags(&plain);
        // corners, curves and faces all have node blocks, none with parameters
        for dim in 0..3 {
            assert!(flags.iter().any(|f| f.0 == dim), "{flags:?}");
        }
        assert!(flags.iter().all(|f| f.2 == 0), "{flags:?}");
        // every node line holds its three coordinates only
        let param = MshWriteOptions::default().with_parametric(true);
        let with = String::from_utf8(write(param)).unwrap();
        let flags = node_block_flags(&with);
        for (dim, tag, flag) in &flags {
            assert_eq!(*flag, (*dim > 0) as i32, "block {dim}:{tag}");
        }
        assert!(with.len() > plain.len());
        // both encodings: the reader sees parameters exactly when asked for
        for enc in [MshEncoding::Ascii, MshEncoding::Binary] {
            for parametric in [false, true] {
                let opts = MshWriteOptions::new(enc).with_parametric(parametric);
                let r = crate::msh::read_msh_bytes(&write(opts), Path::new("p.msh")).unwrap();
                assert_eq!(r.mesh.nodes, mesh.nodes);
                for (got, want) in r.mesh.node_class.iter().zip(&mesh.node_class) {
                    let expected = match *want {
                        NodeClass::Curve(c, t) => NodeClass::Curve(c, t.filter(|_| parametric)),
                        NodeClass::Face(f, uv) => NodeClass::Face(f, uv.filter(|_| parametric)),
                        other => other,
                    };
                    assert_eq!(*got, expected, "{enc:?} parametric {parametric}");
                }
            }
        }
    }

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
