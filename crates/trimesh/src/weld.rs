//! Welding: points closer than a tolerance become one vertex (a hash grid
//! with cells of the tolerance's size; a point near a cell wall also looks in
//! the neighbouring cells), and triangles are renumbered onto the welded
//! vertices.

use std::collections::HashMap;

use geometry::{vec3, Vec3};

/// Welds `points` closer than `tol`: returns the kept points and, for every
/// input point, the index of its kept point. The first point of a cluster is
/// kept; a point joins the first kept point within `tol` it finds.
pub fn weld(points: &[Vec3], tol: f64) -> (Vec<Vec3>, Vec<u32>) {
    let mut kept: Vec<Vec3> = Vec::new();
    let mut map = Vec::with_capacity(points.len());
    if !(tol > 0.0) {
        // exact duplicates only
        let mut seen: HashMap<[u64; 3], u32> = HashMap::with_capacity(points.len());
        for p in points {
            let key = p.map(|x| (x + 0.0).to_bits());
            let id = *seen.entry(key).or_insert_with(|| {
                kept.push(*p);
                kept.len() as u32 - 1
            });
            map.push(id);
        }
        return (kept, map);
    }
    let cell = |x: f64| (x / tol).floor() as i64;
    let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::with_capacity(points.len());
    for p in points {
        let c = [cell(p[0]), cell(p[1]), cell(p[2])];
        // neighbouring cells to look into, per axis: only those within tol
        let mut ranges = [[0i64; 2]; 3];
        for k in 0..3 {
            let lo = c[k] as f64 * tol;
            ranges[k] = [
                if p[k] - lo < tol { -1 } else { 0 },
                if lo + tol - p[k] < tol { 1 } else { 0 },
            ];
        }
        let mut found = None;
        'search: for dx in ranges[0][0]..=ranges[0][1] {
            for dy in ranges[1][0]..=ranges[1][1] {
                for dz in ranges[2][0]..=ranges[2][1] {
                    if let Some(list) = grid.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) {
                        for &q in list {
                            if vec3::dist(kept[q as usize], *p) <= tol {
                                found = Some(q);
                                break 'search;
                            }
                        }
                    }
                }
            }
        }
        let id = match found {
            Some(q) => q,
            None => {
                kept.push(*p);
                let id = kept.len() as u32 - 1;
                grid.entry(c).or_default().push(id);
                id
            }
        };
        map.push(id);
    }
    (kept, map)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn welds_close_points_across_cell_walls() {
        let tol = 1e-3;
        // 0.0009999 and 0.001 straddle a cell wall
        let pts = [
            [0.0009999, 0.0, 0.0],
            [0.0010001, 0.0, 0.0],
            [0.5, 0.0, 0.0],
            [0.5, 2e-3, 0.0],
        ];
        let (kept, map) = weld(&pts, tol);
        assert_eq!(kept.len(), 3);
        assert_eq!(map, vec![0, 0, 1, 2]);
        let (kept, _) = weld(&pts, 0.0);
        assert_eq!(kept.len(), 4);
    }
}
