//! Narrow fillets (issue 32 item 2): a fillet narrower than the size map's
//! floor gets quads of about a 45° turn across and along it
//! (`SizeMapOptions::floor_turn`), not one stretched row.
//!
//! The part is the corpus's spur gear (`data/industrial/spur_gear_m1_z20.step`,
//! module 1, 20 teeth, 5 thick): 40 root-fillet faces, cylinders of radius
//! 0.2 turning 90°, 0.31 wide, where the default size is 1.31 and the
//! floor 0.66. Before the floor was lowered each was 2 quads across (0.157)
//! by 8 along (0.625): 4:1 quads, average SICN 0.42 on those faces.

use std::path::PathBuf;

use geometry::FaceId;
use mesh::stats::quad_sicn_values;
use quadrille::{mesh_model, MeshOptions};

#[test]
fn root_fillets_of_a_spur_gear_get_square_quads_of_45_degrees() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/industrial/spur_gear_m1_z20.step");
    let model = occt::load(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    // the root fillets: faces of curvature 1 / 0.2 at the middle of their (u, v) box
    let fillets: Vec<FaceId> = (0..model.faces.len())
        .filter(|&f| {
            let face = &model.faces[f];
            let b = &face.uv_bounds;
            let mid = [0.5 * (b.umin + b.umax), 0.5 * (b.vmin + b.vmax)];
            face.max_curvature(mid)
                .is_some_and(|k| (k - 5.0).abs() < 0.05)
        })
        .map(|f| FaceId(f as u32))
        .collect();
    assert_eq!(fillets.len(), 40, "two root fillets per tooth");
    let opts = MeshOptions {
        threads: Some(1),
        ..Default::default()
    };
    let mesh = mesh_model(&model, &opts).expect("the gear meshes");
    let sicn = quad_sicn_values(&mesh, Some(&model));
    assert!(sicn.iter().all(|&s| s > 0.0), "no inverted quad");
    let on_fillets: Vec<f64> = (0..mesh.quads.len())
        .filter(|&q| fillets.contains(&mesh.quad_face[q]))
        .map(|q| sicn[q])
        .collect();
    // 45° of turn per quad: at most 90° / 45° = 2 rows across, and as many
    // quads along the 5-long face as 5 / (0.2 · π/4) ≈ 32, so at least
    // 40 faces × 2 × 24 (the grading of the neighbours may take a few)
    assert!(
        on_fillets.len() >= 40 * 2 * 24,
        "{} quads on the root fillets",
        on_fillets.len()
    );
    // a square quad bent over 45° has SICN cos 22.5° = 0.924 at its corners
    // (each corner normal 22.5° off the quad's plane); 0.85 allows quads up
    // to about 1.4 : 1 (2 · 1.4 / (1 + 1.4²) = 0.93 of it). One row across
    // would give at most cos 45° = 0.71, the old 4 : 1 quads 0.42.
    let avg = on_fillets.iter().sum::<f64>() / on_fillets.len() as f64;
    assert!(avg >= 0.85, "average SICN on the root fillets {avg}");
    let whole = sicn.iter().sum::<f64>() / sicn.len() as f64;
    assert!(whole >= 0.8, "average SICN of the gear {whole}");
}
