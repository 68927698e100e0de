//! Narrow fillets (issue 32 item 2): a fillet narrower than the size map's
//! floor lowers the floor to the length of its 90° arc
//! (`SizeMapOptions::floor_turn`), so its two quads across are about 1 : 2,
//! not stretched along it to the floor.
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
fn root_fillets_of_a_spur_gear_get_quads_as_long_as_the_fillet_is_wide() {
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
    // two quads across (the arcs' smallest count), and along the 5-long
    // face quads of about the 90° arc, π · 0.2 / 2 = 0.314: 16 ideally, 12
    // after the long curves' counts are averaged with their chords' (the old
    // floor gave 8); at least 11
    assert!(
        on_fillets.len() >= 40 * 2 * 11,
        "{} quads on the root fillets",
        on_fillets.len()
    );
    // a quad bent over 45° has SICN at most cos 22.5° = 0.924 at its corners
    // (each corner normal 22.5° off the quad's plane); 2 : 1 multiplies that
    // by 2 · 2 / (1 + 4) = 0.8, 3 : 1 by 0.6 (0.55). The old 4 : 1 quads
    // gave 0.47 · 0.924 = 0.43 at best (0.42 measured).
    let avg = on_fillets.iter().sum::<f64>() / on_fillets.len() as f64;
    assert!(avg >= 0.55, "average SICN on the root fillets {avg}");
    // the whole gear: 0.738 with the old floor, Gmsh quadqs 0.88
    let whole = sicn.iter().sum::<f64>() / sicn.len() as f64;
    assert!(whole >= 0.85, "average SICN of the gear {whole}");
}
