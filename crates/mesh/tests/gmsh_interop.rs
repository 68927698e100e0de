//! Interop with Gmsh and meshio: our MSH 4.1 files (ASCII and binary, with
//! and without parametric coordinates) of a hand-built classified cube,
//! opened by Gmsh's Python API, must show the same nodes, elements, entities,
//! entity adjacency, node classification and parameters; the file Gmsh
//! writes back (with parameters) must read as the same mesh; and meshio must
//! read our default files (no parametric coordinates) with the same counts.
//!
//! Without the `gmsh` (or `meshio`) Python module a test prints a skip
//! message and passes, unless `QUADRILLE_REQUIRE_GMSH=1` (set in CI), where it
//! fails.

mod common;

use std::collections::BTreeMap;
use std::process::Command;

use common::{python, python_module_available, script_json};
use mesh::fixtures::cube;
use mesh::msh::{read_msh, write_msh, MshEncoding, MshWriteOptions};
use mesh::NodeClass;

const SCRIPT: &str = r#"
import sys, json
import gmsh
gmsh.initialize(["-noenv"])
gmsh.option.setNumber("General.Terminal", 0)
gmsh.open(sys.argv[1])
out = {}
tags, _, _ = gmsh.model.mesh.getNodes()
out["nodes"] = len(tags)
types, etags, _ = gmsh.model.mesh.getElements()
out["elements"] = {str(int(t)): len(e) for t, e in zip(types, etags)}
out["entities"] = [len(gmsh.model.getEntities(d)) for d in range(4)]
ents = {}
for d, t in gmsh.model.getEntities():
    nt, _, par = gmsh.model.mesh.getNodes(d, t, includeBoundary=False, returnParametricCoord=True)
    up, down = gmsh.model.getAdjacencies(d, t)
    ents["%d:%d" % (d, t)] = {"nodes": [int(x) for x in nt], "params": [float(x) for x in par],
                              "down": sorted(abs(int(x)) for x in down)}
out["ents"] = ents
gmsh.option.setNumber("Mesh.SaveParametric", 1)
gmsh.option.setNumber("Mesh.Binary", int(sys.argv[3]))
gmsh.write(sys.argv[2])
gmsh.finalize()
print("JSON" + json.dumps(out))
"#;

#[test]
fn gmsh_reads_our_msh_with_the_same_counts_entities_and_classification() {
    if !python_module_available("gmsh") {
        return;
    }
    let (model, mesh) = cube(2.0, 3);
    let dir = std::env::temp_dir().join(format!("quadrille-gmsh-interop-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let encodings = [MshEncoding::Ascii, MshEncoding::Binary];
    for (enc, parametric) in encodings.into_iter().flat_map(|e| [(e, false), (e, true)]) {
        let path = dir.join(format!("cube-{enc:?}-{parametric}.msh"));
        let opts = MshWriteOptions::new(enc).with_parametric(parametric);
        write_msh(&path, &mesh, Some(&model), opts).unwrap();
        let back = dir.join(format!("cube-{enc:?}-{parametric}-by-gmsh.msh"));
        let binary = if enc == MshEncoding::Binary { "1" } else { "0" };
        let v = script_json(
            "gmsh",
            SCRIPT,
            &[path.as_os_str(), back.as_os_str(), binary.as_ref()],
        );
        println!(
            "{enc:?} (parametric {parametric}): gmsh sees {} nodes, elements {}, entities {}",
            v["nodes"], v["elements"], v["entities"]
        );

        assert_eq!(v["nodes"], mesh.nodes.len());
        let mut want = BTreeMap::new();
        want.insert("15", mesh.corner_nodes.len());
        want.insert("1", mesh.curve_edges.len());
        want.insert("3", mesh.quads.len());
        for (ty, n) in want {
            assert_eq!(v["elements"][ty], n, "element type {ty}");
        }
        assert_eq!(v["elements"].as_object().unwrap().len(), 3);
        assert_eq!(
            v["entities"],
            serde_json::json!([
                model.corners.len(),
                model.curves.len(),
                model.faces.len(),
                0
            ])
        );

        // every node on the entity it is classified on, with its parameters
        let ents = &v["ents"];
        for (i, class) in mesh.node_class.iter().enumerate() {
            let (key, params): (String, Vec<f64>) = match *class {
                NodeClass::Corner(c) => (format!("0:{}", c.0 + 1), vec![]),
                NodeClass::Curve(c, t) => (format!("1:{}", c.0 + 1), t.into_iter().collect()),
                NodeClass::Face(f, uv) => (
                    format!("2:{}", f.0 + 1),
                    uv.map(|p| p.to_vec()).unwrap_or_default(),
                ),
                NodeClass::Unclassified => unreachable!("the cube is fully classified"),
            };
            let e = &ents[&key];
            let tags: Vec<u64> = e["nodes"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_u64().unwrap())
                .collect();
            let pos = tags
                .iter()
                .position(|&t| t == i as u64 + 1)
                .unwrap_or_else(|| panic!("node {} not on {key}", i + 1));
            let k = params.len();
            if !parametric {
                // the file has none: Gmsh has none either
                assert_eq!(e["params"], serde_json::json!([]), "{key}");
            } else if k > 0 {
                let got: Vec<f64> = e["params"].as_array().unwrap()[pos * k..pos * k + k]
                    .iter()
                    .map(|x| x.as_f64().unwrap())
                    .collect();
                assert_eq!(got, params, "parameters of node {}", i + 1);
            }
        }
        // adjacency: curve → its two corners, face → its four curves
        for (ci, c) in model.curves.iter().enumerate() {
            let down = &ents[&format!("1:{}", ci + 1)]["down"];
            let mut want = vec![c.start.0 + 1, c.end.0 + 1];
            want.sort();
            assert_eq!(*down, serde_json::json!(want), "curve {}", ci + 1);
        }
        for (fi, f) in model.faces.iter().enumerate() {
            let down = &ents[&format!("2:{}", fi + 1)]["down"];
            let mut want: Vec<u32> = f.curve_uses().map(|u| u.curve.0 + 1).collect();
            want.sort();
            assert_eq!(*down, serde_json::json!(want), "face {}", fi + 1);
        }

        // and Gmsh's own rewrite of the file reads back as the same mesh
        // (Gmsh's ASCII keeps 16 significant digits: compare to 1e-14)
        let r = read_msh(&back).unwrap();
        let near = |a: f64, b: f64| (a - b).abs() <= 1e-14 * (1.0 + a.abs());
        assert_eq!(r.mesh.nodes.len(), mesh.nodes.len());
        for (a, b) in r.mesh.nodes.iter().zip(&mesh.nodes) {
            assert!((0..3).all(|k| near(a[k], b[k])), "{a:?} vs {b:?}");
        }
        for (a, b) in r.mesh.node_class.iter().zip(&mesh.node_class) {
            let same = match (a, b) {
                // no parameters in our file: the same entity is all Gmsh can keep
                (NodeClass::Curve(c, _), NodeClass::Curve(d, _)) if !parametric => c == d,
                (NodeClass::Face(f, _), NodeClass::Face(g, _)) if !parametric => f == g,
                (NodeClass::Curve(c, Some(s)), NodeClass::Curve(d, Some(t))) => {
                    c == d && near(*s, *t)
                }
                (NodeClass::Face(f, Some(p)), NodeClass::Face(g, Some(q))) => {
                    f == g && near(p[0], q[0]) && near(p[1], q[1])
                }
                _ => a == b,
            };
            assert!(same, "{a:?} vs {b:?}");
        }
        let sorted = |mut v: Vec<[u32; 4]>| {
            v.sort();
            v
        };
        assert_eq!(sorted(r.mesh.quads.clone()), sorted(mesh.quads.clone()));
        assert_eq!(r.mesh.curve_edges.len(), mesh.curve_edges.len());
        assert_eq!(r.mesh.corner_nodes.len(), mesh.corner_nodes.len());
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

const MESHIO_SCRIPT: &str = r#"
import sys, json
import meshio
m = meshio.read(sys.argv[1])
cells = {}
faces = {}
for block, tags in zip(m.cells, m.cell_data.get("gmsh:geometrical", [None] * len(m.cells))):
    cells[block.type] = cells.get(block.type, 0) + len(block.data)
    if block.type == "quad" and tags is not None:
        for t in tags:
            faces[str(int(t))] = faces.get(str(int(t)), 0) + 1
# the first quad's corner points, to check the node numbering
first = m.cells_dict["quad"][0].tolist()
print("JSON" + json.dumps({"points": len(m.points), "cells": cells, "faces": faces,
                           "first_quad": [m.points[i].tolist() for i in first]}))
"#;

#[test]
fn meshio_reads_our_default_msh() {
    if !python_module_available("meshio") {
        return;
    }
    let (model, mesh) = cube(2.0, 3);
    let dir = std::env::temp_dir().join(format!("quadrille-meshio-interop-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for enc in [MshEncoding::Ascii, MshEncoding::Binary] {
        let path = dir.join(format!("cube-{enc:?}.msh"));
        write_msh(&path, &mesh, Some(&model), MshWriteOptions::new(enc)).unwrap();
        let v = script_json("meshio", MESHIO_SCRIPT, &[path.as_os_str()]);
        println!(
            "{enc:?}: meshio sees {} points, cells {}",
            v["points"], v["cells"]
        );
        assert_eq!(v["points"], mesh.nodes.len());
        assert_eq!(v["cells"]["quad"], mesh.quads.len());
        assert_eq!(v["cells"]["line"], mesh.curve_edges.len());
        assert_eq!(v["cells"]["vertex"], mesh.corner_nodes.len());
        // quads per CAD face, from meshio's gmsh:geometrical tags
        let mut per_face: BTreeMap<String, usize> = BTreeMap::new();
        for f in &mesh.quad_face {
            *per_face.entry((f.0 + 1).to_string()).or_default() += 1;
        }
        assert_eq!(v["faces"], serde_json::json!(per_face));
        let first: Vec<[f64; 3]> = mesh.quads[0]
            .iter()
            .map(|&n| mesh.nodes[n as usize])
            .collect();
        assert_eq!(v["first_quad"], serde_json::json!(first));
    }
    // the same file with parametric coordinates is the one meshio refuses
    // (why they are off by default); if a meshio release learns to read
    // them, this says so and the default can be revisited
    let path = dir.join("cube-parametric.msh");
    let opts = MshWriteOptions::default().with_parametric(true);
    write_msh(&path, &mesh, Some(&model), opts).unwrap();
    let out = Command::new(python())
        .arg("-c")
        .arg(MESHIO_SCRIPT)
        .arg(&path)
        .output()
        .expect("python runs");
    println!(
        "meshio on the parametric file: {}",
        if out.status.success() {
            "read".to_string()
        } else {
            String::from_utf8_lossy(&out.stderr)
                .lines()
                .last()
                .unwrap_or("")
                .to_string()
        }
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
