//! S0 for CAD and triangle-mesh models (spec §3): the chosen faces
//! triangulated in their parameter planes against shared curve meshes
//! (the background triangulation of the field and the size map), welded
//! along the curves and corners they share, and oriented consistently.

use std::collections::{HashMap, VecDeque};

use geometry::{FaceId, Model};

use super::Shell;
use crate::core::patch::NodeRef;
use crate::curves::{discretize_all, plan_curves};
use crate::triangulate::FaceTriangulation;

/// Triangulates `faces` (0-based; all when empty) of `model` with triangle
/// edges of about `size`, welds them by their CAD identity (corners and curve
/// points are one vertex for every face using them) and flips whole
/// triangle fans so that neighbours agree on orientation (the first face's
/// CAD orientation wins). Errors name the face that failed.
pub fn shell_from_model(model: &Model, faces: &[usize], size: f64) -> Result<Shell, String> {
    if !(size > 0.0 && size.is_finite()) {
        return Err(format!("triangle size {size} must be a positive number"));
    }
    let chosen: Vec<usize> = if faces.is_empty() {
        (0..model.faces.len()).collect()
    } else {
        faces.to_vec()
    };
    if let Some(&bad) = chosen.iter().find(|&&f| f >= model.faces.len()) {
        return Err(format!(
            "face {} is out of range: the model has faces 1 to {}",
            bad + 1,
            model.faces.len()
        ));
    }
    let cms = discretize_all(model, &plan_curves(model, 0.5 * size));
    let mut vertices: Vec<[f64; 3]> = Vec::new();
    let mut triangles: Vec<[usize; 3]> = Vec::new();
    let mut shared: HashMap<NodeRef, usize> = HashMap::new();
    for &f in &chosen {
        let mut ft = FaceTriangulation::new(model, FaceId(f as u32), &cms, size)
            .map_err(|e| format!("face {}: no triangulation ({e:?})", f + 1))?;
        ft.refine()
            .map_err(|e| format!("face {}: triangulation refinement failed ({e:?})", f + 1))?;
        let mut tris = ft.triangles();
        ft.merge_poles(&mut tris);
        let ids: Vec<usize> = ft
            .nodes
            .iter()
            .zip(&ft.pos)
            .map(|(n, p)| {
                let fresh = vertices.len();
                let id = match n.node {
                    NodeRef::Interior => fresh,
                    r => *shared.entry(r).or_insert(fresh),
                };
                if id == fresh {
                    vertices.push(*p);
                }
                id
            })
            .collect();
        for t in tris {
            let t = t.map(|v| ids[v as usize]);
            if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] {
                triangles.push(t);
            }
        }
    }
    orient_consistently(&mut triangles);
    // vertices no triangle uses (poles merged away) are dropped
    Ok(Shell::from_used_vertices(&vertices, triangles))
}

/// Flips triangles breadth-first so that every manifold edge is run in
/// opposite directions by its two triangles (faces of one CAD model may
/// disagree on orientation). Non-manifold or non-orientable input is left
/// for [`Shell::check`] to report.
pub(crate) fn orient_consistently(triangles: &mut [[usize; 3]]) {
    let mut by_edge: HashMap<[usize; 2], Vec<usize>> = HashMap::new();
    for (f, t) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            by_edge.entry([a.min(b), a.max(b)]).or_default().push(f);
        }
    }
    let mut done = vec![false; triangles.len()];
    for seed in 0..triangles.len() {
        if done[seed] {
            continue;
        }
        done[seed] = true;
        let mut queue = VecDeque::from([seed]);
        while let Some(f) = queue.pop_front() {
            let t = triangles[f];
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let Some(list) = by_edge.get(&[a.min(b), a.max(b)]) else {
                    continue;
                };
                if list.len() != 2 {
                    continue;
                }
                let g = if list[0] == f { list[1] } else { list[0] };
                if done[g] {
                    continue;
                }
                let u = triangles[g];
                let same = (0..3).any(|m| u[m] == a && u[(m + 1) % 3] == b);
                if same {
                    triangles[g].swap(1, 2);
                }
                done[g] = true;
                queue.push_back(g);
            }
        }
    }
}
