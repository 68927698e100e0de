//! [`HighOrderStats`]: what `quadrille stats` reports for a high-order quad
//! mesh — validity (det J at the nodes and Gauss points, with the CAD normals
//! when the model is given), the Jacobian ratio, and the distance of the
//! nodes and of the Gauss points to the CAD.

use super::{gauss_legendre, HighOrderQuadMesh};
use crate::quadmesh::{NodeClass, QuadMesh};
use crate::stats::node_cad_distances;
use geometry::{vec3, Model, Vec3};
use serde::Serialize;
use std::fmt;

/// Validity and accuracy figures of a high-order quad mesh.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct HighOrderStats {
    /// Lagrange order N.
    pub order: usize,
    /// Elements.
    pub elements: usize,
    /// Nodes.
    pub nodes: usize,
    /// Elements whose det J is not positive at some node or Gauss point
    /// (with the CAD normal of its face when the model is given, else the
    /// element's own normal at its centre).
    pub invalid_elements: usize,
    /// Smallest Jacobian ratio `min det J / max |det J|` over the elements.
    pub min_jacobian_ratio: f64,
    /// Average Jacobian ratio.
    pub avg_jacobian_ratio: f64,
    /// Whether CAD normals judged the elements (a model was given).
    pub cad_normals: bool,
    /// Largest distance of a node to its CAD entity (with a model).
    pub max_node_cad_distance: Option<f64>,
    /// Largest distance of a Gauss point ((N + 1)² per element) to its face
    /// (with a model).
    pub max_gauss_cad_distance: Option<f64>,
    /// Root-mean-square distance of the Gauss points to their faces.
    pub rms_gauss_cad_distance: Option<f64>,
}

impl HighOrderStats {
    /// Computes the figures; with `model`, det J uses the CAD normals and the
    /// CAD distances are measured. A mesh that fails
    /// [`HighOrderQuadMesh::validate`] gives the default (all zero) figures.
    pub fn compute(mesh: &HighOrderQuadMesh, model: Option<&Model>) -> HighOrderStats {
        let mut s = HighOrderStats {
            order: mesh.order,
            elements: mesh.num_elements(),
            nodes: mesh.nodes.len(),
            cad_normals: model.is_some(),
            ..HighOrderStats::default()
        };
        if mesh.validate().is_err() {
            return s;
        }
        let (mut min_ratio, mut sum_ratio) = (f64::INFINITY, 0.0);
        for e in 0..mesh.num_elements() {
            let face = model.and_then(|m| m.faces.get(mesh.element_face[e].idx()));
            let own = mesh.element_normal(e).ok();
            let judged = match face {
                Some(f) => mesh.element_jacobian_with(e, |p| {
                    f.surface
                        .project(p, None)
                        .and_then(|(uv, _)| f.normal(uv))
                        .or(own)
                        .unwrap_or([0.0, 0.0, 1.0])
                }),
                None => mesh.element_jacobian(e, None),
            };
            let Ok(j) = judged else { continue };
            if !(j.min_det > 0.0) {
                s.invalid_elements += 1;
            }
            min_ratio = min_ratio.min(j.ratio);
            sum_ratio += j.ratio;
        }
        s.min_jacobian_ratio = if min_ratio.is_finite() { min_ratio } else { 0.0 };
        s.avg_jacobian_ratio = sum_ratio / mesh.num_elements().max(1) as f64;
        if let Some(model) = model {
            let as_mesh = QuadMesh {
                nodes: mesh.nodes.clone(),
                node_class: mesh.node_class.clone(),
                ..QuadMesh::default()
            };
            s.max_node_cad_distance =
                Some(node_cad_distances(&as_mesh, model).into_iter().flatten().fold(0.0, f64::max));
            let (max, rms) = gauss_distances(mesh, model);
            s.max_gauss_cad_distance = Some(max);
            s.rms_gauss_cad_distance = Some(rms);
        }
        s
    }
}

/// Largest and RMS distance of the (N + 1)² Gauss points of every element to
/// the element's CAD face (projected from the nearest node's face parameters).
fn gauss_distances(mesh: &HighOrderQuadMesh, model: &Model) -> (f64, f64) {
    let (xs, _) = gauss_legendre(mesh.order + 1);
    let (mut max, mut sum, mut n) = (0.0f64, 0.0, 0usize);
    for e in 0..mesh.num_elements() {
        let Some(face) = model.faces.get(mesh.element_face[e].idx()) else { continue };
        let hint = mesh.element(e).iter().find_map(|&v| match mesh.node_class[v as usize] {
            NodeClass::Face(_, uv) => uv,
            _ => None,
        });
        for &a in &xs {
            for &b in &xs {
                let Ok(p) = mesh.point_at(e, a, b) else { continue };
                let d = face
                    .surface
                    .project(p, hint)
                    .map(|(_, q): ([f64; 2], Vec3)| vec3::dist(p, q))
                    .unwrap_or(0.0);
                max = max.max(d);
                sum += d * d;
                n += 1;
            }
        }
    }
    (max, (sum / n.max(1) as f64).sqrt())
}

impl fmt::Display for HighOrderStats {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "  order {} Lagrange quads: {} elements, {} nodes", self.order, self.elements, self.nodes)?;
        writeln!(
            f,
            "  invalid elements (det J <= 0 at a node or Gauss point, {} normals): {}",
            if self.cad_normals { "CAD" } else { "element" },
            self.invalid_elements
        )?;
        writeln!(
            f,
            "  Jacobian ratio min {:.3} avg {:.3}",
            self.min_jacobian_ratio, self.avg_jacobian_ratio
        )?;
        if let (Some(n), Some(g), Some(r)) =
            (self.max_node_cad_distance, self.max_gauss_cad_distance, self.rms_gauss_cad_distance)
        {
            writeln!(f, "  CAD distance: nodes max {n:.3e}; Gauss points max {g:.3e} rms {r:.3e}")?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::{high_order_patch, square_grid};

    #[test]
    fn flat_patch_is_valid_with_ratio_one_and_on_its_plane() {
        // the unit square of `square_grid`'s model, 2 × 2 elements of order 3
        let (model, _) = square_grid(1.0, 1);
        let ho = high_order_patch(3, 2, 2, |u, v| [u / 2.0, v / 2.0, 0.0]);
        let s = HighOrderStats::compute(&ho, Some(&model));
        assert_eq!((s.order, s.elements, s.invalid_elements), (3, 4, 0));
        assert!((s.min_jacobian_ratio - 1.0).abs() < 1e-12, "{s:?}");
        assert!(s.max_gauss_cad_distance.unwrap() < 1e-12, "{s:?}");
    }

    #[test]
    fn a_folded_element_is_counted_and_a_lifted_one_is_off_the_cad() {
        let (model, _) = square_grid(1.0, 1);
        let mut ho = high_order_patch(2, 1, 1, |u, v| [u, v, 0.0]);
        // the centre node (1, 1) pushed past the corner (2, 2): det J < 0 near it
        let c = ho.node_at(0, 1, 1) as usize;
        ho.nodes[c] = [1.6, 1.6, 0.0];
        let s = HighOrderStats::compute(&ho, Some(&model));
        assert_eq!(s.invalid_elements, 1, "{s:?}");
        assert!(s.min_jacobian_ratio < 0.0);
        ho.nodes[c] = [0.5, 0.5, 0.1];
        let s = HighOrderStats::compute(&ho, Some(&model));
        assert_eq!(s.invalid_elements, 0, "{s:?}");
        assert!(s.max_gauss_cad_distance.unwrap() > 0.01, "{s:?}");
    }
}
