//! What is fuzzed: one [`Target`] per reader, plus meshing of mutated but
//! loadable models; the seed files of each and how one case is run.

use std::path::{Path, PathBuf};

/// A fuzzing target: a reader, or the mesher.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    /// STL, ASCII and binary (`trimesh` read and import).
    Stl,
    /// Wavefront OBJ (`trimesh`).
    Obj,
    /// PLY, ASCII and binary (`trimesh`).
    Ply,
    /// MSH 4.1 ASCII and binary, MSH 2.2 ASCII: the quad reader, the
    /// high-order reader and the triangle import.
    Msh,
    /// STEP through OpenCASCADE.
    Step,
    /// IGES through OpenCASCADE.
    Iges,
    /// BREP through OpenCASCADE.
    Brep,
    /// The default method on mutated models (STL and STEP) that still load.
    Mesh,
}

/// Every target, in the order campaigns run them.
pub const ALL_TARGETS: [Target; 8] = [
    Target::Stl,
    Target::Obj,
    Target::Ply,
    Target::Msh,
    Target::Step,
    Target::Iges,
    Target::Brep,
    Target::Mesh,
];

impl Target {
    /// Its name on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            Target::Stl => "stl",
            Target::Obj => "obj",
            Target::Ply => "ply",
            Target::Msh => "msh",
            Target::Step => "step",
            Target::Iges => "iges",
            Target::Brep => "brep",
            Target::Mesh => "mesh",
        }
    }

    /// The target of a name.
    pub fn from_name(name: &str) -> Option<Target> {
        ALL_TARGETS.into_iter().find(|t| t.name() == name)
    }

    /// Seconds one case may take before it counts as a hang (the issue: 10 s
    /// for readers; meshing a mutated model gets more).
    pub fn hang_seconds(self) -> u64 {
        match self {
            Target::Mesh => 120,
            _ => 10,
        }
    }

    /// Cases per worker process (fewer where a case is slow).
    pub fn batch(self) -> u64 {
        match self {
            Target::Stl | Target::Obj | Target::Ply | Target::Msh => 2000,
            Target::Step | Target::Iges | Target::Brep => 200,
            Target::Mesh => 20,
        }
    }

    /// Writes this target's seed files into `dir` (created); returns their
    /// paths, sorted. `cad` is the folder of bundled STEP models.
    pub fn write_seeds(self, dir: &Path, cad: &Path) -> Result<Vec<PathBuf>, String> {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        let put = |name: &str, bytes: &[u8]| -> Result<PathBuf, String> {
            let p = dir.join(name);
            std::fs::write(&p, bytes).map_err(|e| format!("{}: {e}", p.display()))?;
            Ok(p)
        };
        let step = |name: &str| cad.join(name);
        let mut out = Vec::new();
        match self {
            Target::Stl => {
                out.push(put("cube.stl", stl_ascii().as_bytes())?);
                let (p, t) = cube_triangles();
                out.push(put(
                    "cube_binary.stl",
                    &trimesh::read::write_stl_binary(&p, &t),
                )?);
            }
            Target::Obj => out.push(put("cube.obj", obj_text().as_bytes())?),
            Target::Ply => {
                out.push(put("cube.ply", ply_ascii().as_bytes())?);
                out.push(put("cube_binary.ply", &ply_binary())?);
            }
            Target::Msh => {
                use mesh::msh::{write_msh_to, MshEncoding, MshWriteOptions};
                let (model, quads) = mesh::fixtures::cube(1.0, 2);
                for (name, enc) in [
                    ("cube.msh", MshEncoding::Ascii),
                    ("cube_binary.msh", MshEncoding::Binary),
                ] {
                    let mut buf = Vec::new();
                    write_msh_to(&mut buf, &quads, Some(&model), MshWriteOptions::new(enc))
                        .map_err(|e| e.to_string())?;
                    out.push(put(name, &buf)?);
                }
                let ho = mesh::fixtures::high_order_patch(3, 2, 1, |u, v| [u, v, 0.1 * u * v]);
                let mut buf = Vec::new();
                mesh::msh::write_high_order_msh_to(&mut buf, &ho, None, MshWriteOptions::default())
                    .map_err(|e| e.to_string())?;
                out.push(put("patch_order3.msh", &buf)?);
                out.push(put("square_v22.msh", MSH22_SQUARE.as_bytes())?);
            }
            Target::Step => {
                for name in [
                    "s16o_torus.stp",
                    "s15o_cylinder.stp",
                    "s10o_cyl_cutsphere.stp",
                ] {
                    let bytes = std::fs::read(step(name)).map_err(|e| format!("{name}: {e}"))?;
                    out.push(put(name, &bytes)?);
                }
            }
            Target::Iges | Target::Brep => {
                let ext = if self == Target::Iges { "igs" } else { "brep" };
                for name in ["s15o_cylinder", "s10o_cyl_cutsphere"] {
                    let p = dir.join(format!("{name}.{ext}"));
                    occt::convert(&step(&format!("{name}.stp")), &p).map_err(|e| e.to_string())?;
                    out.push(p);
                }
            }
            Target::Mesh => {
                out.push(put("cube.stl", stl_ascii().as_bytes())?);
                let bytes = std::fs::read(step("s16o_torus.stp"))
                    .map_err(|e| format!("s16o_torus.stp: {e}"))?;
                out.push(put("s16o_torus.stp", &bytes)?);
            }
        }
        out.sort();
        Ok(out)
    }

    /// Runs one case: the bytes of a file with extension `ext` (a seed's);
    /// `scratch` is a folder for the CAD readers, which read from a path.
    /// `Err` is a clean refusal and as good as `Ok`: only a panic, a crash or
    /// a hang is a defect.
    pub fn run(self, data: &[u8], ext: &str, scratch: &Path) -> Result<String, String> {
        let name = PathBuf::from(format!("case.{ext}"));
        match self {
            Target::Stl | Target::Obj | Target::Ply => {
                import_triangles(data, ext, &name).map(|m| summary(&m))
            }
            Target::Msh => {
                let quads = mesh::msh::read_msh_bytes(data, &name).map(|r| r.mesh.quads.len());
                let ho =
                    mesh::msh::read_high_order_msh_bytes(data, &name).map(|m| m.element_face.len());
                let tris = import_triangles(data, ext, &name).map(|m| summary(&m));
                let answer = format!("{quads:?} {ho:?} {tris:?}");
                if quads.is_ok() || ho.is_ok() || tris.is_ok() {
                    Ok(answer)
                } else {
                    Err(answer)
                }
            }
            Target::Step | Target::Iges | Target::Brep => {
                load_cad(data, ext, scratch).map(|m| summary(&m))
            }
            Target::Mesh => {
                let model = if trimesh::Format::from_extension(ext).is_some() {
                    import_triangles(data, ext, &name)?
                } else {
                    load_cad(data, ext, scratch)?
                };
                let opts = quadrille::MeshOptions {
                    threads: Some(1),
                    ..Default::default()
                };
                let m = quadrille::mesh_model(&model, &opts).map_err(|e| e.to_string())?;
                Ok(format!("{} quads", m.quads.len()))
            }
        }
    }
}

fn summary(m: &geometry::Model) -> String {
    format!("{} faces", m.faces.len())
}

fn import_triangles(data: &[u8], ext: &str, name: &Path) -> Result<geometry::Model, String> {
    let format = trimesh::Format::from_extension(ext)
        .ok_or_else(|| format!("not a triangle format: {ext}"))?;
    let soup = trimesh::read::read_bytes(data, format, name).map_err(|e| e.to_string())?;
    trimesh::build(soup, &trimesh::Options::default(), name)
        .map(|i| i.model)
        .map_err(|e| e.to_string())
}

fn load_cad(data: &[u8], ext: &str, scratch: &Path) -> Result<geometry::Model, String> {
    let p = scratch.join(format!("case.{ext}"));
    std::fs::write(&p, data).map_err(|e| format!("{}: {e}", p.display()))?;
    let r = occt::load(&p).map_err(|e| e.to_string());
    let _ = std::fs::remove_file(&p);
    r
}

/// The 8 corners and 12 triangles of the unit cube, outward.
fn cube_triangles() -> (Vec<geometry::Vec3>, Vec<[u32; 3]>) {
    let p: Vec<geometry::Vec3> = (0..8)
        .map(|i| [(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64])
        .collect();
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let t = quads
        .iter()
        .flat_map(|q: &[u32; 4]| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect();
    (p, t)
}

fn stl_ascii() -> String {
    let (p, t) = cube_triangles();
    let mut s = String::from("solid cube\n");
    for tri in &t {
        s += "  facet normal 0 0 0\n    outer loop\n";
        for &v in tri {
            let q = p[v as usize];
            s += &format!("      vertex {} {} {}\n", q[0], q[1], q[2]);
        }
        s += "    endloop\n  endfacet\n";
    }
    s + "endsolid cube\n"
}

fn obj_text() -> String {
    let (p, t) = cube_triangles();
    let mut s = String::from("# cube\no cube\n");
    for q in &p {
        s += &format!("v {} {} {}\nvt 0.5 0.5\nvn 0 0 1\n", q[0], q[1], q[2]);
    }
    for (i, tri) in t.iter().enumerate() {
        if i % 2 == 0 {
            s += &format!("f {} {} {}\n", tri[0] + 1, tri[1] + 1, tri[2] + 1);
        } else {
            s += &format!("f {}/1/1 {}//2 -{}\n", tri[0] + 1, tri[1] + 1, 8 - tri[2]);
        }
    }
    s
}

fn ply_header(format: &str, nv: usize, nf: usize) -> String {
    format!(
        "ply\nformat {format} 1.0\ncomment cube\nelement vertex {nv}\nproperty float x\nproperty float y\nproperty float z\nelement face {nf}\nproperty list uchar int vertex_indices\nend_header\n"
    )
}

fn ply_ascii() -> String {
    let (p, t) = cube_triangles();
    let mut s = ply_header("ascii", p.len(), t.len());
    for q in &p {
        s += &format!("{} {} {}\n", q[0], q[1], q[2]);
    }
    for tri in &t {
        s += &format!("3 {} {} {}\n", tri[0], tri[1], tri[2]);
    }
    s
}

fn ply_binary() -> Vec<u8> {
    let (p, t) = cube_triangles();
    let mut b = ply_header("binary_little_endian", p.len(), t.len()).into_bytes();
    for q in &p {
        for c in q {
            b.extend_from_slice(&(*c as f32).to_le_bytes());
        }
    }
    for tri in &t {
        b.push(3);
        for &v in tri {
            b.extend_from_slice(&(v as i32).to_le_bytes());
        }
    }
    b
}

/// A unit square in two triangles, MSH 2.2 ASCII.
const MSH22_SQUARE: &str = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n$EndNodes\n$Elements\n6\n1 1 2 1 1 1 2\n2 1 2 1 2 2 3\n3 1 2 1 3 3 4\n4 1 2 1 4 4 1\n5 2 2 1 1 1 2 3\n6 2 2 1 1 1 3 4\n$EndElements\n";
