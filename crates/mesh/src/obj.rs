//! Wavefront OBJ writer: `v x y z` lines for every node, then the elements
//! grouped by CAD face, one `g face_N` group per face (N = face id + 1, the
//! tag MSH files use), quads as 4-vertex and triangles as 3-vertex `f` lines
//! (1-based indices, in the mesh's orientation).

use std::io::{self, Write};
use std::path::{Path, PathBuf};

use crate::atomic::write_atomically;
use crate::quadmesh::QuadMesh;

/// Why an `.obj` file could not be written.
#[derive(Debug, thiserror::Error)]
pub enum ObjError {
    /// The mesh is inconsistent; nothing was written.
    #[error("cannot write {}: {reason}", path.display())]
    Invalid {
        /// The file that was to be written.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// Writing failed; nothing was left at `path`.
    #[error("cannot write {}: {source}", path.display())]
    Io {
        /// The file that could not be written.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: io::Error,
    },
}

/// Writes `mesh` to `path` as Wavefront OBJ (atomically).
pub fn write_obj(mesh: &QuadMesh, path: &Path) -> Result<(), ObjError> {
    crate::vtu::check_mesh(mesh).map_err(|reason| ObjError::Invalid {
        path: path.to_path_buf(),
        reason,
    })?;
    write_atomically(path, |w| write_body(mesh, w)).map_err(|source| ObjError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// The file body.
fn write_body<W: Write>(mesh: &QuadMesh, w: &mut W) -> io::Result<()> {
    writeln!(
        w,
        "# written by Quadrille: {} nodes, {} quads, {} triangles",
        mesh.nodes.len(),
        mesh.quads.len(),
        mesh.triangles.len()
    )?;
    for p in &mesh.nodes {
        writeln!(w, "v {} {} {}", p[0], p[1], p[2])?;
    }
    // elements sorted by face, quads before triangles within a face, mesh order kept
    let mut order: Vec<(u32, usize)> = mesh
        .quad_face
        .iter()
        .enumerate()
        .map(|(i, f)| (f.0, i))
        .collect();
    let nq = mesh.quads.len();
    order.extend(
        mesh.triangle_face
            .iter()
            .enumerate()
            .map(|(i, f)| (f.0, nq + i)),
    );
    order.sort_by_key(|&(f, i)| (f, i));
    let mut current = None;
    for (f, i) in order {
        if current != Some(f) {
            writeln!(w, "g face_{}", f as u64 + 1)?;
            current = Some(f);
        }
        if i < nq {
            let q = mesh.quads[i];
            writeln!(
                w,
                "f {} {} {} {}",
                q[0] as u64 + 1,
                q[1] as u64 + 1,
                q[2] as u64 + 1,
                q[3] as u64 + 1
            )?;
        } else {
            let t = mesh.triangles[i - nq];
            writeln!(
                w,
                "f {} {} {}",
                t[0] as u64 + 1,
                t[1] as u64 + 1,
                t[2] as u64 + 1
            )?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vtu::tests::small_mixed_mesh;
    use geometry::FaceId;

    #[test]
    fn reads_back_counts_groups_and_faces() {
        let dir = std::env::temp_dir().join(format!("quadrille-obj-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("m.obj");
        let mut mesh = small_mixed_mesh();
        mesh.quad_face = vec![FaceId(4), FaceId(0)];
        write_obj(&mesh, &path).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        let verts: Vec<Vec<f64>> = lines
            .iter()
            .filter(|l| l.starts_with("v "))
            .map(|l| {
                l[2..]
                    .split_whitespace()
                    .map(|s| s.parse().unwrap())
                    .collect()
            })
            .collect();
        assert_eq!(verts.len(), 7);
        assert_eq!(verts[6], [3.0, 0.5, 0.0]);
        let faces: Vec<Vec<usize>> = lines
            .iter()
            .filter(|l| l.starts_with("f "))
            .map(|l| {
                l[2..]
                    .split_whitespace()
                    .map(|s| s.parse().unwrap())
                    .collect()
            })
            .collect();
        assert_eq!(faces.len(), 3);
        assert_eq!(faces.iter().filter(|f| f.len() == 4).count(), 2);
        assert!(faces.iter().flatten().all(|&i| (1..=7).contains(&i)));
        let groups: Vec<&str> = lines
            .iter()
            .filter(|l| l.starts_with("g "))
            .copied()
            .collect();
        assert_eq!(groups, ["g face_1", "g face_2", "g face_5"]);
        // face 0 (group face_1) holds quad 1, written 1-based
        let g1 = lines.iter().position(|l| *l == "g face_1").unwrap();
        assert_eq!(lines[g1 + 1], "f 2 3 6 5");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn errors_name_the_file_and_leave_nothing() {
        let dir = std::env::temp_dir().join(format!("quadrille-obj-bad-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mut mesh = small_mixed_mesh();
        mesh.triangles[0][1] = 7;
        let path = dir.join("bad.obj");
        let e = write_obj(&mesh, &path).unwrap_err();
        assert!(
            e.to_string().contains("bad.obj") && e.to_string().contains("triangle 0"),
            "{e}"
        );
        let e = write_obj(&small_mixed_mesh(), &dir.join("missing/x.obj")).unwrap_err();
        assert!(matches!(e, ObjError::Io { .. }) && e.to_string().contains("x.obj"));
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
