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

use geometry::vec3::{self, Vec3};
use geometry::FaceId;
use mesh::stats::{quad_element_sicn_values, quad_sicn_values};
use quadrille::{default_size, mesh_model, MeshOptions};

/// The faces whose largest principal curvature at the middle of their
/// (u, v) box satisfies `pick`.
fn faces_curved(model: &geometry::Model, pick: impl Fn(f64) -> bool) -> Vec<FaceId> {
    (0..model.faces.len())
        .filter(|&f| {
            let face = &model.faces[f];
            let b = &face.uv_bounds;
            let mid = [0.5 * (b.umin + b.umax), 0.5 * (b.vmin + b.vmax)];
            face.max_curvature(mid).is_some_and(&pick)
        })
        .map(|f| FaceId(f as u32))
        .collect()
}

#[test]
fn root_fillets_of_a_spur_gear_get_quads_as_long_as_the_fillet_is_wide() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/industrial/spur_gear_m1_z20.step");
    let model = occt::load(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    // the root fillets: faces of curvature 1 / 0.2 at the middle of their (u, v) box
    let fillets = faces_curved(&model, |k| (k - 5.0).abs() < 0.05);
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

/// A turned shaft (radii 4.79, 4.92 and 5.29, a 2.05 bore) whose three
/// fillets of revolution have radius 0.025, under a size floor of half the
/// default size (0.67): the turn rule would lower the floor on them to
/// their 90° arc, 0.04, and each fillet circle got 834 edges, which the
/// cylinders and discs beside them carried over their whole area (187,390
/// quads). On a band the lowered floor stops at a quarter of the floor
/// (`field::size_map::TURN_MIN_FRACTION`), so no size is below it: the
/// quads are bounded by the surface area over that size squared, and each
/// fillet has two quads across by at most its circumference over that
/// size (with a quarter for the curve planner's rounding and balancing).
#[test]
fn tiny_fillets_of_revolution_do_not_refine_the_whole_shaft() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/necks/turned_shaft_tiny_fillets.step");
    let model = occt::load(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    // the fillets: faces of curvature 1 / 0.0253 at the middle of their box
    let fillets = faces_curved(&model, |k| k > 30.0);
    assert_eq!(fillets.len(), 3, "three tiny fillets");
    let opts = MeshOptions {
        threads: Some(1),
        ..Default::default()
    };
    let mesh = mesh_model(&model, &opts).expect("the shaft meshes");
    // the size map's floor at the default size is half of it
    // (`methods::quasi_structured::SIZE_MAP_MIN`), bounded at a quarter
    let smallest = 0.25 * 0.5 * default_size(&model);
    let quad_area = |q: &[u32; 4]| {
        let p = q.map(|i| mesh.nodes[i as usize]);
        let tri = |a: Vec3, b: Vec3, c: Vec3| {
            0.5 * vec3::norm(vec3::cross(vec3::sub(b, a), vec3::sub(c, a)))
        };
        tri(p[0], p[1], p[2]) + tri(p[0], p[2], p[3])
    };
    let area: f64 = mesh.quads.iter().map(quad_area).sum();
    let bound = area / (smallest * smallest);
    assert!(
        (mesh.quads.len() as f64) <= bound,
        "{} quads, at most {bound:.0} (area {area:.1}, smallest size {smallest:.3})",
        mesh.quads.len()
    );
    for &f in &fillets {
        let quads: Vec<usize> = (0..mesh.quads.len())
            .filter(|&q| mesh.quad_face[q] == f)
            .collect();
        // the fillet's radius about the shaft's axis (z), largest
        let radius = quads
            .iter()
            .flat_map(|&q| mesh.quads[q])
            .map(|i| {
                let p = mesh.nodes[i as usize];
                p[0].hypot(p[1])
            })
            .fold(0.0f64, f64::max);
        let along = std::f64::consts::TAU * radius / smallest;
        assert!(
            (quads.len() as f64) <= 2.0 * 1.25 * along,
            "fillet {}: {} quads, at most 2 × 1.25 × {along:.0}",
            f.idx() + 1,
            quads.len()
        );
    }
    let cad = quad_sicn_values(&mesh, Some(&model));
    let element = quad_element_sicn_values(&mesh);
    assert!(cad.iter().all(|&s| s > 0.0), "inverted by CAD normals");
    assert!(
        element.iter().all(|&s| s > 0.0),
        "inverted by element geometry"
    );
}
