//! Test support: the `n × n` grid on the unit square model's face
//! (`geometry::primitives::square(1.0)`: z = 0, uv = xy), shared by the
//! unit tests of the topology stages that edit a grid by hand; and a
//! model's fields and curve meshes at one size, shared by the tests of the
//! unstructured stages.

use geometry::{CornerId, CurveId, Model};

use crate::curves::curve_mesh::{discretize_all, plan_curves, CurveMesh};
use crate::field::field_report::{model_fields, FieldOptions, ModelFields};

use crate::core::patch::QuadPatch;
use crate::core::patch::{LocalNode, NodeRef};

/// Id of grid vertex `(x, y)` of an `n × n` grid.
pub fn grid_id(n: usize, x: usize, y: usize) -> u32 {
    (y * (n + 1) + x) as u32
}

/// The `n × n` grid on the unit square, with every cell a quad except those
/// `skip` rejects (by cell `(x, y)`); corners, curve and interior nodes
/// classified as a face mesh would classify them. `quad_tri` is left empty.
pub fn square_grid(n: usize, skip: impl Fn(usize, usize) -> bool) -> QuadPatch {
    let mut p = QuadPatch::default();
    let id = |x: usize, y: usize| grid_id(n, x, y);
    for y in 0..=n {
        for x in 0..=n {
            let on_x = x == 0 || x == n;
            let on_y = y == 0 || y == n;
            let node = match (on_x, on_y) {
                (true, true) => NodeRef::Corner(CornerId((x / n + 2 * (y / n)) as u32)),
                (false, false) => NodeRef::Interior,
                _ => NodeRef::Curve(CurveId(0), id(x, y)),
            };
            let uv = [x as f64 / n as f64, y as f64 / n as f64];
            p.nodes.push(LocalNode {
                uv,
                node,
                pole: None,
            });
            p.pos.push([uv[0], uv[1], 0.0]);
        }
    }
    for y in 0..n {
        for x in 0..n {
            if !skip(x, y) {
                p.quads
                    .push([id(x, y), id(x + 1, y), id(x + 1, y + 1), id(x, y + 1)]);
            }
        }
    }
    p
}

/// The fields of `model` at the absolute size `h` and its curve meshes for
/// that size (coarse points at `2h`).
pub fn fields_and_curves(model: &Model, h: f64) -> (ModelFields, Vec<CurveMesh>) {
    let fields = model_fields(
        model,
        &FieldOptions {
            size: crate::core::options::Size::Absolute(h),
            ..Default::default()
        },
    )
    .expect("fields");
    let cms = discretize_all(model, &plan_curves(model, h));
    (fields, cms)
}

/// The baseline method's mesh of `model` (a fixture for the stages that
/// start from it).
pub(crate) fn mesh_baseline(
    model: &geometry::Model,
    opts: &crate::MeshOptions,
) -> Result<mesh::QuadMesh, crate::MeshError> {
    crate::mesh_model_with(model, opts, crate::MeshMethod::Baseline).map(|(m, _)| m)
}
