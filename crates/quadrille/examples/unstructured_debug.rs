//! Developer aid: meshes a model with the quasi-structured method (all stages)
//! and prints its poor quads (face, SICN, corner SICNs, node classes).
//! Usage: unstructured_debug MODEL [THRESHOLD] (default 0: the inverted ones);
//! `QD_SIZE_FACTOR` sets the size factor.
fn main() {
    let mut args = std::env::args().skip(1);
    let path = args
        .next()
        .expect("usage: unstructured_debug MODEL [THRESHOLD]");
    let threshold: f64 = args.next().map_or(0.0, |t| t.parse().expect("a number"));
    let model = occt::load(std::path::Path::new(&path)).expect("loads");
    // QD_SIZE_FACTOR: the size factor (default 1)
    let size = std::env::var("QD_SIZE_FACTOR")
        .ok()
        .and_then(|s| s.parse::<f64>().ok())
        .map(quadrille::Size::Factor)
        .unwrap_or_default();
    let opts = quadrille::MeshOptions {
        size,
        threads: Some(1),
        ..Default::default()
    };
    let (m, rep) = quadrille::mesh_model_with(&model, &opts, quadrille::MeshMethod::default())
        .expect("meshes");
    println!(
        "fallback {:?}",
        rep.fallback.iter().map(|f| f.0 .0 + 1).collect::<Vec<_>>()
    );
    let normals = mesh::stats::quad_corner_normals(&m, Some(&model));
    for (q, quad) in m.quads.iter().enumerate() {
        let p = quad.map(|i| m.nodes[i as usize]);
        let corners = mesh::quality::corner_sicn(&p, &normals[q]);
        let v = corners.iter().copied().fold(f64::INFINITY, f64::min);
        if v < threshold {
            println!(
                "quad {q} face {} sicn {v:.3} corners {:.3?} at {:.3?} {:?}",
                m.quad_face[q].0 + 1,
                corners,
                p[0],
                quad.map(|i| m.node_class[i as usize])
            );
        }
    }
}
