//! The MSH reader: MSH 4.1 (ASCII and binary) and MSH 2.2 (ASCII).
//!
//! Classification is restored from the file: a node of a 4.1 block on an
//! entity of dimension 0 / 1 / 2 becomes `Corner` / `Curve` / `Face` of
//! `tag − 1` (with its parametric coordinates when the block has them); in
//! MSH 2.2, which has no node entities, a node takes the lowest-dimensional
//! entity among the point, line and surface elements that use it. Point
//! elements (type 15) become `corner_nodes`, 2-node lines `curve_edges`,
//! 3-node triangles and 4-node quads the surface elements. Other element types
//! are skipped and counted in [`MshRead::skipped_elements`].
//!
//! Malformed input never panics: it gives an [`MshError::Parse`] naming the
//! file, the line (or byte, in binary data), the section and the problem.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use geometry::{CornerId, CurveId, FaceId, Vec3};

use super::{element_dim, nodes_per_element, MshError};
use crate::quadmesh::{NodeClass, QuadMesh};

/// What [`read_msh`] returns: the mesh and what the file said about itself.
#[derive(Clone, Debug, Default)]
pub struct MshRead {
    /// The mesh, nodes in increasing order of their file tags.
    pub mesh: QuadMesh,
    /// The format version as written in the file (`"4.1"`, `"2.2"`).
    pub version: String,
    /// True for a binary file.
    pub binary: bool,
    /// Number of point, curve, surface and volume entities in `$Entities`
    /// (all zero when the file has no such section).
    pub entity_counts: [usize; 4],
    /// Element type → number of elements of that type that were skipped
    /// (types other than points, lines, triangles and quads, or elements on
    /// an entity of an unexpected dimension).
    pub skipped_elements: BTreeMap<i32, usize>,
}

/// Reads an MSH 4.1 (ASCII or binary) or MSH 2.2 (ASCII) file.
pub fn read_msh(path: &Path) -> Result<MshRead, MshError> {
    let data = std::fs::read(path).map_err(|source| MshError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    read_msh_bytes(&data, path)
}

/// Reads MSH content already in memory; `name` is used in error messages.
pub fn read_msh_bytes(data: &[u8], name: &Path) -> Result<MshRead, MshError> {
    let mut r = Reader::new(data, name);
    let raw = r.read_raw()?;
    r.build(raw)
}

/// A node as read, before tags are turned into indices.
pub(super) struct RawNode {
    pub tag: u64,
    pub pos: Vec3,
    pub class: NodeClass,
}

/// An element as read: its tag, entity dimension and tag, type, node tags.
pub(super) struct RawElement {
    pub tag: u64,
    pub dim: i64,
    pub entity: i64,
    pub ty: i32,
    pub nodes: Vec<u64>,
}

/// A whole file as read, before the elements are interpreted.
pub(super) struct RawFile {
    /// What the file said about itself (the mesh left empty).
    pub info: MshRead,
    /// The nodes, sorted by tag, no tag twice.
    pub nodes: Vec<RawNode>,
    /// The elements in file order.
    pub elements: Vec<RawElement>,
    /// True for MSH 2 (classification then comes from the elements).
    pub v2: bool,
}

impl RawFile {
    /// The index of the node of tag `tag`.
    pub fn index(&self, tag: u64) -> Option<u32> {
        self.nodes
            .binary_search_by_key(&tag, |n| n.tag)
            .ok()
            .map(|i| i as u32)
    }
}

/// The MSH parser: sections, tokens, ASCII or binary data.
pub(super) struct Reader<'a> {
    data: &'a [u8],
    pos: usize,
    path: PathBuf,
    pub section: String,
    binary: bool,
    in_binary_data: bool,
    little: bool,
    size_t: usize,
}

pub(super) type R<T> = Result<T, MshError>;

impl<'a> Reader<'a> {
    /// A reader of `data`; `name` is used in error messages.
    pub fn new(data: &'a [u8], name: &Path) -> Reader<'a> {
        Reader {
            data,
            pos: 0,
            path: name.to_path_buf(),
            section: "-".into(),
            binary: false,
            in_binary_data: false,
            little: cfg!(target_endian = "little"),
            size_t: 8,
        }
    }
}

impl Reader<'_> {
    /// A parse error at the current position, in the current section.
    pub fn err<T>(&self, message: impl Into<String>) -> R<T> {
        let location = if self.in_binary_data {
            format!("byte {}", self.pos)
        } else {
            let end = self.pos.min(self.data.len());
            format!(
                "line {}",
                self.data[..end].iter().filter(|&&b| b == b'\n').count() + 1
            )
        };
        Err(MshError::Parse {
            path: self.path.clone(),
            location,
            section: self.section.clone(),
            message: message.into(),
        })
    }

    fn skip_ws(&mut self) {
        while self.pos < self.data.len() && self.data[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
    }

    fn at_eof(&mut self) -> bool {
        self.skip_ws();
        self.pos >= self.data.len()
    }

    /// The next whitespace-separated token.
    fn token(&mut self) -> R<&str> {
        self.skip_ws();
        let start = self.pos;
        while self.pos < self.data.len() && !self.data[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        if start == self.pos {
            return self.err("unexpected end of file");
        }
        match std::str::from_utf8(&self.data[start..self.pos]) {
            Ok(s) => Ok(s),
            Err(_) => {
                self.pos = start;
                self.err("unreadable (non-text) characters where a number was expected")
            }
        }
    }

    /// The next token parsed as `T`, `what` naming it in the error.
    fn parse<T: std::str::FromStr>(&mut self, what: &str) -> R<T> {
        let start = self.pos;
        let t = self.token()?;
        match t.parse::<T>() {
            Ok(v) => Ok(v),
            Err(_) => {
                let msg = format!("expected {what}, found {:?}", truncate(t));
                self.pos = start;
                self.skip_ws();
                self.err(msg)
            }
        }
    }

    /// The rest of the current line (after skipping blank space and lines).
    fn line_tokens(&mut self) -> R<Vec<&str>> {
        self.skip_ws();
        if self.pos >= self.data.len() {
            return self.err("unexpected end of file");
        }
        let start = self.pos;
        while self.pos < self.data.len() && self.data[self.pos] != b'\n' {
            self.pos += 1;
        }
        match std::str::from_utf8(&self.data[start..self.pos]) {
            Ok(s) => Ok(s.split_ascii_whitespace().collect()),
            Err(_) => self.err("unreadable (non-text) line"),
        }
    }

    fn bytes<const N: usize>(&mut self) -> R<[u8; N]> {
        match self.data.get(self.pos..self.pos + N) {
            Some(b) => {
                self.pos += N;
                let mut out = [0u8; N];
                out.copy_from_slice(b);
                Ok(out)
            }
            None => self.err("unexpected end of file in binary data"),
        }
    }

    /// An `int` (i32 in binary).
    fn int(&mut self, what: &str) -> R<i64> {
        if self.in_binary_data {
            let b = self.bytes::<4>()?;
            Ok(if self.little {
                i32::from_le_bytes(b)
            } else {
                i32::from_be_bytes(b)
            } as i64)
        } else {
            self.parse(what)
        }
    }

    /// A `size_t` (4 or 8 bytes in binary, as the header says).
    fn size(&mut self, what: &str) -> R<u64> {
        if self.in_binary_data {
            if self.size_t == 4 {
                let b = self.bytes::<4>()?;
                Ok(if self.little {
                    u32::from_le_bytes(b)
                } else {
                    u32::from_be_bytes(b)
                } as u64)
            } else {
                let b = self.bytes::<8>()?;
                Ok(if self.little {
                    u64::from_le_bytes(b)
                } else {
                    u64::from_be_bytes(b)
                })
            }
        } else {
            self.parse(what)
        }
    }

    /// A `double`.
    fn float(&mut self, what: &str) -> R<f64> {
        if self.in_binary_data {
            let b = self.bytes::<8>()?;
            Ok(if self.little {
                f64::from_le_bytes(b)
            } else {
                f64::from_be_bytes(b)
            })
        } else {
            self.parse(what)
        }
    }

    /// A count of items that each take at least `min_bytes` (ASCII: 2 per
    /// token): refuses counts the rest of the file cannot hold.
    fn count(&mut self, what: &str, min_bytes: usize) -> R<usize> {
        let n = self.size(what)?;
        let left = self.data.len().saturating_sub(self.pos) as u64;
        if n.saturating_mul(min_bytes.max(1) as u64) > left + 1 {
            return self.err(format!(
                "{what} {n} is more than the rest of the file can hold"
            ));
        }
        Ok(n as usize)
    }

    fn expect_end(&mut self, name: &str) -> R<()> {
        self.in_binary_data = false;
        let start = self.pos;
        let want = format!("$End{name}");
        if self.at_eof() {
            return self.err(format!("unexpected end of file: expected {want}"));
        }
        let t = self.token()?;
        if t != want {
            let msg = format!(
                "expected {want}, found {:?} (wrong counts or truncated section?)",
                truncate(t)
            );
            self.pos = start;
            self.skip_ws();
            return self.err(msg);
        }
        Ok(())
    }

    /// Skips an unknown section up to and including its `$EndName` line.
    fn skip_section(&mut self, name: &str) -> R<()> {
        let want = format!("$End{name}");
        let hay = &self.data[self.pos..];
        match hay.windows(want.len()).position(|w| w == want.as_bytes()) {
            Some(i) => {
                self.pos += i + want.len();
                Ok(())
            }
            None => self.err(format!("section ${name} has no {want}")),
        }
    }

    /// Reads every section: the nodes (sorted by tag) and the elements as
    /// the file holds them.
    pub fn read_raw(&mut self) -> R<RawFile> {
        let mut out = MshRead::default();
        let mut nodes: Option<Vec<RawNode>> = None;
        let mut elements: Vec<RawElement> = Vec::new();
        let mut have_elements = false;
        let mut v2 = false;
        while !self.at_eof() {
            self.section = "-".into();
            let start = self.pos;
            let t = self.token()?.to_string();
            let Some(name) = t.strip_prefix('$') else {
                self.pos = start;
                return self.err(format!("expected a $Section, found {:?}", truncate(&t)));
            };
            let name = name.to_string();
            self.section = format!("${name}");
            // the data starts on the next line (binary data may begin with
            // bytes that look like blank space, so skip exactly one line end)
            while self.pos < self.data.len() && self.data[self.pos] != b'\n' {
                self.pos += 1;
            }
            self.pos = (self.pos + 1).min(self.data.len());
            if out.version.is_empty() && name != "MeshFormat" {
                return self.err("the file does not start with $MeshFormat");
            }
            match name.as_str() {
                "MeshFormat" => {
                    v2 = self.mesh_format(&mut out)?;
                    self.expect_end(&name)?;
                }
                "Entities" if !v2 => {
                    self.in_binary_data = self.binary;
                    out.entity_counts = self.entities()?;
                    self.expect_end(&name)?;
                }
                "Nodes" => {
                    self.in_binary_data = self.binary;
                    nodes = Some(if v2 {
                        self.nodes_v2()?
                    } else {
                        self.nodes_v41()?
                    });
                    self.expect_end(&name)?;
                }
                "Elements" => {
                    if nodes.is_none() {
                        return self.err("$Elements comes before $Nodes");
                    }
                    self.in_binary_data = self.binary;
                    elements = if v2 {
                        self.elements_v2()?
                    } else {
                        self.elements_v41()?
                    };
                    have_elements = true;
                    self.expect_end(&name)?;
                }
                _ => self.skip_section(&name)?,
            }
        }
        self.section = "-".into();
        if out.version.is_empty() {
            return self.err("empty file: no $MeshFormat");
        }
        let Some(nodes) = nodes else {
            return self.err("no $Nodes section");
        };
        if !have_elements {
            return self.err("no $Elements section");
        }
        let mut nodes = nodes;
        nodes.sort_by_key(|n| n.tag);
        if let Some(w) = nodes.windows(2).find(|w| w[0].tag == w[1].tag) {
            self.section = "$Nodes".into();
            return self.err(format!("node tag {} is defined twice", w[0].tag));
        }
        Ok(RawFile {
            info: out,
            nodes,
            elements,
            v2,
        })
    }

    /// Parses `$MeshFormat`; returns true for MSH 2.x.
    fn mesh_format(&mut self, out: &mut MshRead) -> R<bool> {
        let version = self.token()?.to_string();
        let file_type: i64 = self.parse("the file type (0 or 1)")?;
        let data_size: usize = self.parse("the data size")?;
        let v2 = match version.as_str() {
            "4.1" => false,
            "2.2" | "2.1" | "2" | "2.0" => true,
            other => {
                return self.err(format!(
                    "unsupported MSH version {other} (this reader reads 4.1 and 2.2)"
                ))
            }
        };
        match file_type {
            0 => {}
            1 if v2 => {
                return self.err("binary MSH 2 is not supported (write MSH 4.1 or ASCII 2.2)")
            }
            1 => {
                // the rest of the line, then an int 1 telling the endianness
                while self.pos < self.data.len() && self.data[self.pos] != b'\n' {
                    self.pos += 1;
                }
                self.pos = (self.pos + 1).min(self.data.len());
                self.in_binary_data = true;
                let b = self.bytes::<4>()?;
                self.little = match (i32::from_le_bytes(b), i32::from_be_bytes(b)) {
                    (1, _) => true,
                    (_, 1) => false,
                    _ => return self.err("the binary header's one is not 1 in either byte order"),
                };
                self.in_binary_data = false;
                if data_size != 4 && data_size != 8 {
                    return self.err(format!(
                        "unsupported data size {data_size} (4 or 8 expected)"
                    ));
                }
                self.size_t = data_size;
            }
            other => {
                return self.err(format!(
                    "file type {other} is neither 0 (ASCII) nor 1 (binary)"
                ))
            }
        }
        self.binary = file_type == 1;
        out.binary = self.binary;
        out.version = version;
        Ok(v2)
    }

    fn entities(&mut self) -> R<[usize; 4]> {
        let mut counts = [0usize; 4];
        for (d, c) in counts.iter_mut().enumerate() {
            *c = self.count(&format!("number of dimension-{d} entities"), 4)?;
        }
        for (d, &n) in counts.iter().enumerate() {
            for _ in 0..n {
                self.int("an entity tag")?;
                for _ in 0..if d == 0 { 3 } else { 6 } {
                    self.float("a coordinate")?;
                }
                let np = self.count("number of physical tags", 1)?;
                for _ in 0..np {
                    self.int("a physical tag")?;
                }
                if d > 0 {
                    let nb = self.count("number of bounding entities", 1)?;
                    for _ in 0..nb {
                        self.int("a bounding entity tag")?;
                    }
                }
            }
        }
        Ok(counts)
    }

    fn nodes_v41(&mut self) -> R<Vec<RawNode>> {
        let blocks = self.count("number of node blocks", 4)?;
        let total = self.count("number of nodes", 4)?;
        self.size("the minimum node tag")?;
        self.size("the maximum node tag")?;
        let mut nodes = Vec::with_capacity(total);
        for _ in 0..blocks {
            let dim = self.int("an entity dimension")?;
            let tag = self.int("an entity tag")?;
            let parametric = self.int("the parametric flag")?;
            let n = self.count("number of nodes in the block", 4)?;
            if !(0..=3).contains(&dim) {
                return self.err(format!("entity dimension {dim} is not 0, 1, 2 or 3"));
            }
            let entity = self.entity_id(tag)?;
            let npar = if parametric != 0 { dim as usize } else { 0 };
            let first = nodes.len();
            for _ in 0..n {
                let t = self.size("a node tag")?;
                nodes.push(RawNode {
                    tag: t,
                    pos: [0.0; 3],
                    class: NodeClass::Unclassified,
                });
            }
            for node in &mut nodes[first..] {
                for k in 0..3 {
                    node.pos[k] = self.float("a node coordinate")?;
                }
                let mut par = [0.0f64; 3];
                for p in par.iter_mut().take(npar) {
                    *p = self.float("a parametric coordinate")?;
                }
                let has = npar > 0;
                node.class = match dim {
                    0 => NodeClass::Corner(CornerId(entity)),
                    1 => NodeClass::Curve(CurveId(entity), has.then_some(par[0])),
                    2 => NodeClass::Face(FaceId(entity), has.then_some([par[0], par[1]])),
                    _ => NodeClass::Unclassified,
                };
            }
        }
        if nodes.len() != total {
            return self.err(format!(
                "the header announces {total} nodes, the blocks hold {}",
                nodes.len()
            ));
        }
        Ok(nodes)
    }

    /// `tag − 1` as an entity id; tags must be positive.
    fn entity_id(&self, tag: i64) -> R<u32> {
        if tag < 1 || tag > u32::MAX as i64 {
            return self.err(format!("entity tag {tag} is not a positive 32-bit number"));
        }
        Ok((tag - 1) as u32)
    }

    fn elements_v41(&mut self) -> R<Vec<RawElement>> {
        let blocks = self.count("number of element blocks", 4)?;
        let total = self.count("number of elements", 4)?;
        self.size("the minimum element tag")?;
        self.size("the maximum element tag")?;
        let mut out = Vec::with_capacity(total);
        let mut seen = 0usize;
        for _ in 0..blocks {
            let dim = self.int("an entity dimension")?;
            let entity = self.int("an entity tag")?;
            let ty = self.int("an element type")? as i32;
            let known = nodes_per_element(ty);
            let n = self.count(
                "number of elements in the block",
                2 * (1 + known.unwrap_or(1)),
            )?;
            for _ in 0..n {
                let tag;
                let nodes: Vec<u64> = match known {
                    Some(k) => {
                        tag = self.size("an element tag")?;
                        (0..k).map(|_| self.size("a node tag")).collect::<R<_>>()?
                    }
                    None if self.in_binary_data => {
                        return self.err(format!(
                            "unknown element type {ty} in binary data (its size is unknown)"
                        ));
                    }
                    None => {
                        // ASCII: one element per line, skipped below
                        let line = self.line_tokens()?;
                        tag = line.first().and_then(|t| t.parse().ok()).unwrap_or(0);
                        Vec::new()
                    }
                };
                out.push(RawElement {
                    tag,
                    dim,
                    entity,
                    ty,
                    nodes,
                });
                seen += 1;
            }
        }
        if seen != total {
            return self.err(format!(
                "the header announces {total} elements, the blocks hold {seen}"
            ));
        }
        Ok(out)
    }

    fn nodes_v2(&mut self) -> R<Vec<RawNode>> {
        let n = self.count("number of nodes", 8)?;
        let mut nodes = Vec::with_capacity(n);
        for _ in 0..n {
            let tag = self.parse("a node tag")?;
            let mut pos = [0.0; 3];
            for p in &mut pos {
                *p = self.parse("a node coordinate")?;
            }
            nodes.push(RawNode {
                tag,
                pos,
                class: NodeClass::Unclassified,
            });
        }
        Ok(nodes)
    }

    fn elements_v2(&mut self) -> R<Vec<RawElement>> {
        let n = self.count("number of elements", 8)?;
        let mut out = Vec::with_capacity(n);
        for _ in 0..n {
            let toks = self.line_tokens()?;
            let nums: Result<Vec<i64>, _> = toks.iter().map(|t| t.parse::<i64>()).collect();
            let Ok(nums) = nums else {
                let msg = format!(
                    "an element line must hold integers: {:?}",
                    truncate(&toks.join(" "))
                );
                return self.err(msg);
            };
            if nums.len() < 3 {
                return self.err("an element line needs a tag, a type and a number of tags");
            }
            let ty = nums[1] as i32;
            let ntags = nums[2];
            if ntags < 0 || 3 + ntags as usize > nums.len() {
                return self.err(format!(
                    "element {} announces {ntags} tags, the line is too short",
                    nums[0]
                ));
            }
            let tags = &nums[3..3 + ntags as usize];
            // tags: physical, elementary entity, …; with one tag take it as the entity
            let entity = tags.get(1).or(tags.first()).copied().unwrap_or(1);
            let rest = &nums[3 + ntags as usize..];
            if let Some(k) = nodes_per_element(ty) {
                if rest.len() != k {
                    return self.err(format!(
                        "element {} of type {ty} has {} nodes, {k} expected",
                        nums[0],
                        rest.len()
                    ));
                }
            }
            if rest.iter().any(|&v| v < 0) {
                return self.err(format!("element {} has a negative node tag", nums[0]));
            }
            let dim = element_dim(ty).unwrap_or(-1);
            out.push(RawElement {
                tag: nums[0].max(0) as u64,
                dim,
                entity,
                ty,
                nodes: rest.iter().map(|&v| v as u64).collect(),
            });
        }
        Ok(out)
    }

    /// Turns tags into indices and fills the linear mesh.
    fn build(&mut self, mut raw: RawFile) -> R<MshRead> {
        self.section = "$Elements".into();
        let mut out = std::mem::take(&mut raw.info);
        let raw = &raw;
        let (nodes, elements, v2) = (&raw.nodes, &raw.elements, raw.v2);
        let index = |t: u64| raw.index(t);
        let mesh = &mut out.mesh;
        mesh.nodes = nodes.iter().map(|n| n.pos).collect();
        mesh.node_class = nodes.iter().map(|n| n.class).collect();
        // MSH 2: a node takes the lowest-dimensional entity of its elements.
        let mut dim_of = vec![u8::MAX; if v2 { nodes.len() } else { 0 }];
        for el in elements {
            let mut idx = [0u32; 4];
            let keep = matches!((el.ty, el.dim), (15, 0) | (1, 1) | (2, 2) | (3, 2));
            if !keep {
                *out.skipped_elements.entry(el.ty).or_insert(0) += 1;
                continue;
            }
            for (k, &t) in el.nodes.iter().enumerate() {
                match index(t) {
                    Some(i) => idx[k] = i,
                    None => {
                        return self.err(format!(
                            "an element of type {} refers to node {t}, which is not defined",
                            el.ty
                        ))
                    }
                }
            }
            let e = self.entity_id(el.entity)?;
            match el.ty {
                15 => mesh.corner_nodes.push((idx[0], CornerId(e))),
                1 => mesh.curve_edges.push(([idx[0], idx[1]], CurveId(e))),
                2 => {
                    mesh.triangles.push([idx[0], idx[1], idx[2]]);
                    mesh.triangle_face.push(FaceId(e));
                }
                _ => {
                    mesh.quads.push(idx);
                    mesh.quad_face.push(FaceId(e));
                }
            }
            if v2 {
                let n = el.nodes.len();
                for &i in &idx[..n] {
                    let d = el.dim as u8;
                    if d < dim_of[i as usize] {
                        dim_of[i as usize] = d;
                        mesh.node_class[i as usize] = match d {
                            0 => NodeClass::Corner(CornerId(e)),
                            1 => NodeClass::Curve(CurveId(e), None),
                            _ => NodeClass::Face(FaceId(e), None),
                        };
                    }
                }
            }
        }
        Ok(out)
    }
}

fn truncate(s: &str) -> String {
    if s.chars().count() > 40 {
        format!("{}…", s.chars().take(40).collect::<String>())
    } else {
        s.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<MshRead, MshError> {
        read_msh_bytes(text.as_bytes(), Path::new("test.msh"))
    }

    const V22: &str = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 0.5 0.5 0\n$EndNodes\n\
$Elements\n8\n1 15 2 0 1 1\n2 1 2 0 1 1 2\n3 1 2 0 2 2 3\n4 1 2 0 3 3 4\n5 1 2 0 4 4 1\n6 3 2 0 1 1 2 3 4\n7 2 2 0 1 1 2 5\n8 4 2 0 1 1 2 3 5\n$EndElements\n";

    #[test]
    fn reads_msh22_and_derives_classification() {
        let r = read(V22).unwrap();
        assert_eq!(r.version, "2.2");
        let m = &r.mesh;
        assert_eq!(m.nodes.len(), 5);
        assert_eq!(m.quads, vec![[0, 1, 2, 3]]);
        assert_eq!(m.triangles, vec![[0, 1, 4]]);
        assert_eq!(m.curve_edges.len(), 4);
        assert_eq!(m.corner_nodes, vec![(0, CornerId(0))]);
        assert_eq!(m.node_class[0], NodeClass::Corner(CornerId(0)));
        assert_eq!(m.node_class[1], NodeClass::Curve(CurveId(0), None));
        assert_eq!(m.node_class[2], NodeClass::Curve(CurveId(1), None));
        assert_eq!(m.node_class[4], NodeClass::Face(FaceId(0), None));
        assert_eq!(r.skipped_elements, BTreeMap::from([(4, 1)]));
    }

    #[test]
    fn malformed_files_give_clear_errors() {
        let cases: Vec<(String, &str)> = vec![
            (String::new(), "empty file"),
            ("hello".into(), "expected a $Section"),
            ("$Nodes\n1\n$EndNodes\n".into(), "does not start with $MeshFormat"),
            ("$MeshFormat\n3.0 0 8\n$EndMeshFormat\n".into(), "unsupported MSH version 3.0"),
            ("$MeshFormat\n2.2 1 8\n$EndMeshFormat\n".into(), "binary MSH 2"),
            (V22.replace("$Nodes\n5\n", "$Nodes\n6\n"), "expected a node tag"),
            (V22.replace("$Nodes\n5\n", "$Nodes\n99999999999\n"), "more than the rest of the file"),
            (V22.replace("6 3 2 0 1 1 2 3 4", "6 3 2 0 1 1 2 3"), "has 3 nodes, 4 expected"),
            (V22.replace("6 3 2 0 1 1 2 3 4", "6 3 2 0 1 1 2 3 9"), "refers to node 9"),
            (V22.replace("2 1 0 0\n", "2 1 x 0\n"), "expected a node coordinate, found \"x\""),
            (V22[..V22.find("8 4 2 0 1").unwrap()].to_string(), "unexpected end of file"),
            (V22.replace("$EndElements\n", ""), "expected $EndElements"),
            (V22.replace("5 0.5 0.5 0\n", "1 0.5 0.5 0\n"), "defined twice"),
            ("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 1 1 1\n2 0 0 1\n1\n0 0 0\n$EndNodes\n".into(), "entity tag 0"),
            ("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 2 1 2\n2 1 0 1\n1\n0 0 0\n$EndNodes\n$Elements\n0 0 0 0\n$EndElements\n".into(), "announces 2 nodes"),
            ("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n0 0 0 0\n$EndNodes\n".into(), "no $Elements"),
            ("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Foo\n1 2 3\n".into(), "has no $EndFoo"),
        ];
        for (text, want) in cases {
            let err = read(&text).expect_err(want).to_string();
            assert!(err.contains(want), "expected {want:?} in {err:?}");
            assert!(err.starts_with("test.msh: "), "{err}");
        }
        // the line number points at the bad line
        let err = read(&V22.replace("2 1 0 0\n", "2 1 x 0\n"))
            .unwrap_err()
            .to_string();
        assert!(err.contains("line 7") && err.contains("$Nodes"), "{err}");
    }

    #[test]
    fn unknown_sections_and_types_are_skipped_in_ascii_41() {
        let text = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n2 1 \"x\"\n$EndPhysicalNames\n\
$Nodes\n1 3 1 3\n2 1 1 3\n1\n2\n3\n0 0 0 0.1 0.2\n1 0 0 0.3 0.4\n0 1 0 0.5 0.6\n$EndNodes\n\
$Elements\n2 2 1 2\n2 1 2 1\n1 1 2 3\n2 1 99 1\n2 1 2 3 3 3 3\n$EndElements\n";
        let r = read(text).unwrap();
        assert_eq!(r.mesh.triangles, vec![[0, 1, 2]]);
        assert_eq!(
            r.mesh.node_class[1],
            NodeClass::Face(FaceId(0), Some([0.3, 0.4]))
        );
        assert_eq!(r.skipped_elements, BTreeMap::from([(99, 1)]));
    }
}
