//! Readers: STL (ASCII and binary), OBJ, PLY (ASCII and binary little-endian)
//! and MSH (4.1 / 2.2, through `mesh::msh`) into a [`Soup`]: points and
//! triangles as the file numbers them, before any welding or repair.
//!
//! Every coordinate is checked: a NaN or infinite value is an error naming the
//! line (ASCII) or the triangle / vertex (binary). Indices out of range are
//! errors naming the line or element. Polygons of OBJ and PLY are
//! fan-triangulated.

use std::path::Path;

use geometry::Vec3;

use crate::error::TrimeshError;

/// Points and triangles as read from a file.
#[derive(Clone, Debug, Default)]
pub struct Soup {
    /// Vertex positions, in file order (STL: three per facet).
    pub points: Vec<Vec3>,
    /// Triangles on `points`, in file order (polygons fan-triangulated).
    pub tris: Vec<[u32; 3]>,
}

/// The triangle-mesh formats this crate reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// STL, ASCII or binary.
    Stl,
    /// Wavefront OBJ.
    Obj,
    /// PLY, ASCII or binary little-endian.
    Ply,
    /// Gmsh MSH 4.1 or 2.2 (its triangles).
    Msh,
}

impl Format {
    /// The format of a file extension (case-insensitive), `None` when unknown.
    pub fn from_extension(ext: &str) -> Option<Format> {
        match ext.to_ascii_lowercase().as_str() {
            "stl" => Some(Format::Stl),
            "obj" => Some(Format::Obj),
            "ply" => Some(Format::Ply),
            "msh" => Some(Format::Msh),
            _ => None,
        }
    }
}

/// Reads a file of the format its extension names.
pub fn read_file(path: &Path) -> Result<Soup, TrimeshError> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_string())
        .unwrap_or_default();
    let Some(format) = Format::from_extension(&ext) else {
        return Err(TrimeshError::Parse {
            path: path.into(),
            msg: format!(
                "unknown triangle-mesh extension '.{ext}' (expected .stl, .obj, .ply or .msh)"
            ),
        });
    };
    let data = std::fs::read(path).map_err(|source| TrimeshError::Io {
        path: path.into(),
        source,
    })?;
    read_bytes(&data, format, path)
}

/// Reads file content already in memory; `name` is used in messages.
pub fn read_bytes(data: &[u8], format: Format, name: &Path) -> Result<Soup, TrimeshError> {
    let err = |msg: String| TrimeshError::Parse {
        path: name.into(),
        msg,
    };
    if data.is_empty() {
        return Err(err("the file is empty".into()));
    }
    let soup = match format {
        Format::Stl => read_stl(data),
        Format::Obj => read_obj(data),
        Format::Ply => read_ply(data),
        Format::Msh => match mesh::msh::read_msh_bytes(data, name) {
            Ok(r) => {
                for (i, p) in r.mesh.nodes.iter().enumerate() {
                    if !p.iter().all(|x| x.is_finite()) {
                        return Err(err(format!(
                            "node {} has a non-finite coordinate {p:?}",
                            i + 1
                        )));
                    }
                }
                Ok(Soup {
                    points: r.mesh.nodes,
                    tris: r.mesh.triangles,
                })
            }
            Err(e) => return Err(err(e.to_string())),
        },
    }
    .map_err(err)?;
    if soup.tris.is_empty() {
        return Err(err("the file holds no triangle".into()));
    }
    Ok(soup)
}

fn finite(p: Vec3, what: impl FnOnce() -> String) -> Result<Vec3, String> {
    if p.iter().all(|x| x.is_finite()) {
        Ok(p)
    } else {
        Err(format!("{}: non-finite coordinate {:?}", what(), p))
    }
}

/// STL: binary when the size matches the count in the header, else ASCII
/// when it starts with `solid`; a binary file whose size does not match its
/// count is reported as truncated.
fn read_stl(data: &[u8]) -> Result<Soup, String> {
    let binary_len = |n: usize| 84 + 50 * n;
    let starts_solid = data.len() >= 5 && data[..5].eq_ignore_ascii_case(b"solid");
    if data.len() >= 84 {
        let n = u32::from_le_bytes([data[80], data[81], data[82], data[83]]) as usize;
        if data.len() == binary_len(n) {
            return read_stl_binary(data, n);
        }
        if !starts_solid {
            return Err(format!(
                "binary STL truncated or corrupt: the header announces {n} triangles ({} bytes) but the file has {} bytes (triangle {} is incomplete)",
                binary_len(n),
                data.len(),
                (data.len().saturating_sub(84)) / 50 + 1
            ));
        }
    } else if !starts_solid {
        return Err(format!(
            "binary STL truncated: {} bytes, less than the 84-byte header",
            data.len()
        ));
    }
    read_stl_ascii(data)
}

fn read_stl_binary(data: &[u8], n: usize) -> Result<Soup, String> {
    let mut soup = Soup {
        points: Vec::with_capacity(3 * n),
        tris: Vec::with_capacity(n),
    };
    let f = |o: usize| f32::from_le_bytes([data[o], data[o + 1], data[o + 2], data[o + 3]]) as f64;
    for t in 0..n {
        let base = 84 + 50 * t + 12;
        for k in 0..3 {
            let o = base + 12 * k;
            let p = finite([f(o), f(o + 4), f(o + 8)], || {
                format!("triangle {} vertex {}", t + 1, k + 1)
            })?;
            soup.points.push(p);
        }
        let b = 3 * t as u32;
        soup.tris.push([b, b + 1, b + 2]);
    }
    Ok(soup)
}

fn text(data: &[u8]) -> Result<&str, String> {
    std::str::from_utf8(data).map_err(|e| {
        let line = data[..e.valid_up_to()].iter().filter(|&&c| c == b'\n').count() + 1;
        format!("line {line}: not valid text (a binary file with a wrong extension or a truncated binary STL?)")
    })
}

fn parse_f(tok: Option<&str>, line: usize, what: &str) -> Result<f64, String> {
    let t = tok.ok_or_else(|| format!("line {line}: missing {what}"))?;
    let x: f64 = t
        .parse()
        .map_err(|_| format!("line {line}: `{t}` is not a number ({what})"))?;
    if !x.is_finite() {
        return Err(format!("line {line}: non-finite coordinate `{t}`"));
    }
    Ok(x)
}

fn read_stl_ascii(data: &[u8]) -> Result<Soup, String> {
    let s = text(data)?;
    let mut soup = Soup::default();
    let mut in_facet = 0usize; // vertices of the current facet
    let mut facet_line = 0;
    let mut ended = false;
    for (i, line) in s.lines().enumerate() {
        let ln = i + 1;
        let mut it = line.split_whitespace();
        match it.next() {
            Some(w) if w.eq_ignore_ascii_case("vertex") => {
                let p = [
                    parse_f(it.next(), ln, "x")?,
                    parse_f(it.next(), ln, "y")?,
                    parse_f(it.next(), ln, "z")?,
                ];
                if in_facet >= 3 {
                    return Err(format!(
                        "line {ln}: facet of line {facet_line} has more than 3 vertices"
                    ));
                }
                soup.points.push(p);
                in_facet += 1;
            }
            Some(w) if w.eq_ignore_ascii_case("facet") => {
                in_facet = 0;
                facet_line = ln;
            }
            Some(w) if w.eq_ignore_ascii_case("endfacet") => {
                if in_facet != 3 {
                    return Err(format!(
                        "line {ln}: facet of line {facet_line} has {in_facet} vertices, not 3"
                    ));
                }
                let b = soup.points.len() as u32 - 3;
                soup.tris.push([b, b + 1, b + 2]);
                in_facet = 0;
            }
            Some(w) if w.eq_ignore_ascii_case("endsolid") => ended = true,
            _ => {}
        }
    }
    if in_facet != 0 {
        return Err(format!(
            "ASCII STL truncated: the facet of line {facet_line} is not finished"
        ));
    }
    if !ended && !soup.tris.is_empty() {
        return Err("ASCII STL truncated: no `endsolid` line".into());
    }
    Ok(soup)
}

fn read_obj(data: &[u8]) -> Result<Soup, String> {
    let s = text(data)?;
    let mut soup = Soup::default();
    for (i, line) in s.lines().enumerate() {
        let ln = i + 1;
        let mut it = line.split_whitespace();
        match it.next() {
            Some("v") => {
                let p = [
                    parse_f(it.next(), ln, "x")?,
                    parse_f(it.next(), ln, "y")?,
                    parse_f(it.next(), ln, "z")?,
                ];
                soup.points.push(p);
            }
            Some("f") => {
                let n = soup.points.len() as i64;
                let mut idx = Vec::new();
                for tok in it {
                    let first = tok.split('/').next().unwrap_or("");
                    let k: i64 = first
                        .parse()
                        .map_err(|_| format!("line {ln}: `{tok}` is not a vertex index"))?;
                    let k = if k < 0 { n + k } else { k - 1 };
                    if k < 0 || k >= n {
                        return Err(format!("line {ln}: vertex index {tok} out of range (there are {n} vertices so far)"));
                    }
                    idx.push(k as u32);
                }
                if idx.len() < 3 {
                    return Err(format!(
                        "line {ln}: a face needs at least 3 vertices, this one has {}",
                        idx.len()
                    ));
                }
                for j in 1..idx.len() - 1 {
                    soup.tris.push([idx[0], idx[j], idx[j + 1]]);
                }
            }
            _ => {}
        }
    }
    Ok(soup)
}

/// A scalar type of a PLY property.
#[derive(Clone, Copy, Debug)]
enum PlyType {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl PlyType {
    fn parse(s: &str) -> Option<PlyType> {
        Some(match s {
            "char" | "int8" => PlyType::I8,
            "uchar" | "uint8" => PlyType::U8,
            "short" | "int16" => PlyType::I16,
            "ushort" | "uint16" => PlyType::U16,
            "int" | "int32" => PlyType::I32,
            "uint" | "uint32" => PlyType::U32,
            "float" | "float32" => PlyType::F32,
            "double" | "float64" => PlyType::F64,
            _ => return None,
        })
    }
    fn size(self) -> usize {
        match self {
            PlyType::I8 | PlyType::U8 => 1,
            PlyType::I16 | PlyType::U16 => 2,
            PlyType::I32 | PlyType::U32 | PlyType::F32 => 4,
            PlyType::F64 => 8,
        }
    }
    fn read_le(self, b: &[u8]) -> f64 {
        match self {
            PlyType::I8 => b[0] as i8 as f64,
            PlyType::U8 => b[0] as f64,
            PlyType::I16 => i16::from_le_bytes([b[0], b[1]]) as f64,
            PlyType::U16 => u16::from_le_bytes([b[0], b[1]]) as f64,
            PlyType::I32 => i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            PlyType::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            PlyType::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            PlyType::F64 => f64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]),
        }
    }
}

/// A PLY property: a scalar, or a list (count type, item type).
#[derive(Clone, Debug)]
struct PlyProp {
    name: String,
    scalar: PlyType,
    list: Option<PlyType>,
}

#[derive(Clone, Debug)]
struct PlyElement {
    name: String,
    count: usize,
    props: Vec<PlyProp>,
}

fn read_ply(data: &[u8]) -> Result<Soup, String> {
    // header: text lines up to `end_header`
    let mut pos = 0;
    let mut lines = Vec::new();
    loop {
        let Some(nl) = data[pos..].iter().position(|&c| c == b'\n') else {
            return Err("PLY header has no `end_header` line".into());
        };
        let line = String::from_utf8_lossy(&data[pos..pos + nl])
            .trim()
            .to_string();
        pos += nl + 1;
        let done = line == "end_header";
        lines.push(line);
        if done {
            break;
        }
    }
    if lines.first().map(|l| l.as_str()) != Some("ply") {
        return Err("line 1: not a PLY file (no `ply` magic)".into());
    }
    let mut binary = false;
    let mut elements: Vec<PlyElement> = Vec::new();
    for (i, l) in lines.iter().enumerate() {
        let ln = i + 1;
        let w: Vec<&str> = l.split_whitespace().collect();
        match w.first().copied() {
            Some("format") => match w.get(1).copied() {
                Some("ascii") => binary = false,
                Some("binary_little_endian") => binary = true,
                Some(other) => {
                    return Err(format!(
                    "line {ln}: PLY format `{other}` not supported (ascii or binary_little_endian)"
                ))
                }
                None => return Err(format!("line {ln}: format line without a format")),
            },
            Some("element") => {
                let count = w
                    .get(2)
                    .and_then(|c| c.parse().ok())
                    .ok_or_else(|| format!("line {ln}: bad element line `{l}`"))?;
                elements.push(PlyElement {
                    name: w.get(1).unwrap_or(&"").to_string(),
                    count,
                    props: Vec::new(),
                });
            }
            Some("property") => {
                let el = elements
                    .last_mut()
                    .ok_or_else(|| format!("line {ln}: property before any element"))?;
                let bad = || format!("line {ln}: bad property line `{l}`");
                if w.get(1) == Some(&"list") {
                    let c = w.get(2).and_then(|s| PlyType::parse(s)).ok_or_else(bad)?;
                    let t = w.get(3).and_then(|s| PlyType::parse(s)).ok_or_else(bad)?;
                    el.props.push(PlyProp {
                        name: w.get(4).unwrap_or(&"").to_string(),
                        scalar: t,
                        list: Some(c),
                    });
                } else {
                    let t = w.get(1).and_then(|s| PlyType::parse(s)).ok_or_else(bad)?;
                    el.props.push(PlyProp {
                        name: w.get(2).unwrap_or(&"").to_string(),
                        scalar: t,
                        list: None,
                    });
                }
            }
            _ => {}
        }
    }
    let header_lines = lines.len();
    let mut soup = Soup::default();
    // an element's records as lists of numbers, passed to `take`
    let mut take = |el: &PlyElement,
                    rec: usize,
                    values: &[Vec<f64>],
                    at: &dyn Fn() -> String|
     -> Result<(), String> {
        if el.name == "vertex" {
            let get = |n: &str| {
                el.props
                    .iter()
                    .position(|p| p.name == n)
                    // a list property (empty, say) named x is no coordinate
                    .and_then(|k| values[k].first().copied())
            };
            let (Some(x), Some(y), Some(z)) = (get("x"), get("y"), get("z")) else {
                return Err("PLY vertex element has no x, y, z properties".into());
            };
            soup.points.push(finite([x, y, z], || {
                format!("{} (vertex {})", at(), rec + 1)
            })?);
        } else if el.name == "face" {
            let k = el
                .props
                .iter()
                .position(|p| {
                    p.list.is_some() && (p.name == "vertex_indices" || p.name == "vertex_index")
                })
                .ok_or("PLY face element has no vertex_indices list")?;
            let idx = &values[k];
            if idx.len() < 3 {
                return Err(format!(
                    "{} (face {}): a face needs at least 3 vertices",
                    at(),
                    rec + 1
                ));
            }
            let nverts = soup.points.len();
            let mut ids = Vec::with_capacity(idx.len());
            for &v in idx {
                if !(v >= 0.0 && (v as usize) < nverts) {
                    return Err(format!(
                        "{} (face {}): vertex index {v} out of range (0..{nverts})",
                        at(),
                        rec + 1
                    ));
                }
                ids.push(v as u32);
            }
            for j in 1..ids.len() - 1 {
                soup.tris.push([ids[0], ids[j], ids[j + 1]]);
            }
        }
        Ok(())
    };
    if binary {
        for el in &elements {
            // a record's least size: a count that the rest of the file cannot
            // hold is refused before the loop (a damaged count of an element
            // of empty records would otherwise spin billions of times)
            let least: usize = el.props.iter().map(|p| p.list.unwrap_or(p.scalar).size()).sum();
            if least == 0 && el.name != "vertex" && el.name != "face" {
                continue;
            }
            if el.count.saturating_mul(least) > data.len() - pos {
                return Err(format!(
                    "binary PLY truncated: element `{}` declares {} records of at least {least} bytes, {} bytes remain",
                    el.name,
                    el.count,
                    data.len() - pos
                ));
            }
            for rec in 0..el.count {
                let mut values = Vec::with_capacity(el.props.len());
                for p in &el.props {
                    let mut read = |t: PlyType| -> Result<f64, String> {
                        if pos + t.size() > data.len() {
                            return Err(format!(
                                "binary PLY truncated in element `{}` record {} (byte {pos})",
                                el.name,
                                rec + 1
                            ));
                        }
                        let v = t.read_le(&data[pos..]);
                        pos += t.size();
                        Ok(v)
                    };
                    match p.list {
                        None => values.push(vec![read(p.scalar)?]),
                        Some(c) => {
                            let n = read(c)?;
                            if !(0.0..1e6).contains(&n) {
                                return Err(format!(
                                    "element `{}` record {}: bad list length {n}",
                                    el.name,
                                    rec + 1
                                ));
                            }
                            let mut v = Vec::with_capacity(n as usize);
                            for _ in 0..n as usize {
                                v.push(read(p.scalar)?);
                            }
                            values.push(v);
                        }
                    }
                }
                let at = pos;
                take(el, rec, &values, &|| format!("byte {at}"))?;
            }
        }
    } else {
        let body = text(&data[pos..])?;
        let mut rows = body
            .lines()
            .enumerate()
            .filter(|(_, l)| !l.trim().is_empty());
        for el in &elements {
            for rec in 0..el.count {
                let Some((i, row)) = rows.next() else {
                    return Err(format!(
                        "ASCII PLY truncated: element `{}` has {} of its {} records",
                        el.name, rec, el.count
                    ));
                };
                let ln = header_lines + i + 1;
                let mut toks = row.split_whitespace();
                let mut values = Vec::with_capacity(el.props.len());
                for p in &el.props {
                    let mut next = || -> Result<f64, String> {
                        let t = toks
                            .next()
                            .ok_or_else(|| format!("line {ln}: missing value for `{}`", p.name))?;
                        t.parse::<f64>()
                            .map_err(|_| format!("line {ln}: `{t}` is not a number"))
                    };
                    match p.list {
                        None => values.push(vec![next()?]),
                        Some(_) => {
                            let n = next()?;
                            if !(0.0..1e6).contains(&n) {
                                return Err(format!("line {ln}: bad list length {n}"));
                            }
                            let mut v = Vec::new();
                            for _ in 0..n as usize {
                                v.push(next()?);
                            }
                            values.push(v);
                        }
                    }
                }
                take(el, rec, &values, &|| format!("line {ln}"))?;
            }
        }
    }
    Ok(soup)
}

/// Writes triangles as a binary STL (for tests and examples).
pub fn write_stl_binary(points: &[Vec3], tris: &[[u32; 3]]) -> Vec<u8> {
    let mut out = vec![0u8; 80];
    out.extend_from_slice(&(tris.len() as u32).to_le_bytes());
    for t in tris {
        let [a, b, c] = t.map(|i| points[i as usize]);
        let n = geometry::vec3::normalize(geometry::vec3::cross(
            geometry::vec3::sub(b, a),
            geometry::vec3::sub(c, a),
        ))
        .unwrap_or([0.0; 3]);
        for v in [n, a, b, c] {
            for x in v {
                out.extend_from_slice(&(x as f32).to_le_bytes());
            }
        }
        out.extend_from_slice(&[0, 0]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rd(s: &str, f: Format) -> Result<Soup, TrimeshError> {
        read_bytes(s.as_bytes(), f, Path::new("t"))
    }

    #[test]
    fn ascii_stl_and_errors() {
        let ok = "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid x\n";
        let s = rd(ok, Format::Stl).unwrap();
        assert_eq!((s.points.len(), s.tris.len()), (3, 1));
        let nan = ok.replace("vertex 1 0 0", "vertex nan 0 0");
        let e = rd(&nan, Format::Stl).unwrap_err().to_string();
        assert!(e.contains("line 5") && e.contains("non-finite"), "{e}");
        let e = rd("solid x\nendsolid x\n", Format::Stl)
            .unwrap_err()
            .to_string();
        assert!(e.contains("no triangle"), "{e}");
    }

    #[test]
    fn binary_stl_round_trip_and_truncation() {
        let pts = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        let b = write_stl_binary(&pts, &[[0, 1, 2], [0, 3, 1]]);
        let s = read_bytes(&b, Format::Stl, Path::new("t")).unwrap();
        assert_eq!(s.tris.len(), 2);
        assert_eq!(s.points[4], [0.0, 0.0, 1.0]);
        let e = read_bytes(&b[..b.len() - 7], Format::Stl, Path::new("t"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("truncated") && e.contains("triangle 2"), "{e}");
    }

    #[test]
    fn obj_polygons_and_bad_index() {
        let s = rd(
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1/1 2/2 3/3 4/4\n",
            Format::Obj,
        )
        .unwrap();
        assert_eq!(s.tris, vec![[0, 1, 2], [0, 2, 3]]);
        let s = rd("v 0 0 0\nv 1 0 0\nv 1 1 0\nf -3 -2 -1\n", Format::Obj).unwrap();
        assert_eq!(s.tris, vec![[0, 1, 2]]);
        let e = rd("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 7\n", Format::Obj)
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 4") && e.contains("out of range"), "{e}");
    }

    #[test]
    fn ply_ascii_and_binary() {
        let a = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";
        let s = rd(a, Format::Ply).unwrap();
        assert_eq!((s.points.len(), s.tris.len()), (4, 2));
        let mut b = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\nelement face 1\nproperty list uchar uint vertex_indices\nend_header\n".to_vec();
        for p in [[0.0f64, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
            for x in p {
                b.extend_from_slice(&x.to_le_bytes());
            }
        }
        b.push(3);
        for i in [0u32, 1, 2] {
            b.extend_from_slice(&i.to_le_bytes());
        }
        let s = read_bytes(&b, Format::Ply, Path::new("t")).unwrap();
        assert_eq!(s.tris, vec![[0, 1, 2]]);
        let e = read_bytes(&b[..b.len() - 2], Format::Ply, Path::new("t"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("truncated"), "{e}");
    }
}
