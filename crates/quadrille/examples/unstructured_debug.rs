//! Developer aid: meshes a model with the unstructured method and prints its
//! inverted quads (face, SICN, node classes). Usage: unstructured_debug MODEL
fn main() {
    let path = std::env::args()
        .nth(1)
        .expect("usage: unstructured_debug MODEL");
    let model = occt::load(std::path::Path::new(&path)).expect("loads");
    let opts = quadrille::MeshOptions {
        threads: Some(1),
        ..Default::default()
    };
    let (m, rep) = quadrille::mesh_model_with(&model, &opts, quadrille::MeshMethod::Unstructured)
        .expect("meshes");
    println!(
        "fallback {:?}",
        rep.fallback.iter().map(|f| f.0 .0 + 1).collect::<Vec<_>>()
    );
    let s = mesh::stats::quad_sicn_values(&m, Some(&model));
    for (q, v) in s.iter().enumerate() {
        if *v < 0.0 {
            println!(
                "quad {q} face {} sicn {v:.3} {:?}",
                m.quad_face[q].0 + 1,
                m.quads[q].map(|i| m.node_class[i as usize])
            );
        }
    }
}
