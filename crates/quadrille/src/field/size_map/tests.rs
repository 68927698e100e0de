use super::narrow::{width_evenness, NARROW_EVENNESS, NARROW_MIN_FRACTION};
use super::*;
use crate::core::options::Size;
use crate::curves::curve_mesh::{discretize_curve, plan_curves, plan_curves_sized};
use crate::field::field_report::{model_fields, FieldOptions, ModelFields};
use geometry::primitives;

/// A graph of `n × n` grid vertices with spacing 1, each joined to its right,
/// upper and upper-right neighbours.
fn grid_graph(n: usize) -> BackgroundGraph {
    let mut g = BackgroundGraph::default();
    for j in 0..n {
        for i in 0..n {
            g.positions.push([i as f64, j as f64, 0.0]);
            g.refs.push(NodeRef::Interior);
            g.neighbours.push(Vec::new());
        }
    }
    let id = |i: usize, j: usize| (j * n + i) as u32;
    for j in 0..n {
        for i in 0..n {
            for (di, dj) in [(1, 0), (0, 1), (1, 1)] {
                if i + di < n && j + dj < n {
                    let (a, b) = (id(i, j), id(i + di, j + dj));
                    g.neighbours[a as usize].push(b);
                    g.neighbours[b as usize].push(a);
                }
            }
        }
    }
    g
}

/// Deterministic pseudo-random numbers in [0, 1).
fn lcg(state: &mut u64) -> f64 {
    *state = state
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*state >> 11) as f64 / (1u64 << 53) as f64
}

#[test]
fn grading_matches_the_edge_relaxation_fixpoint() {
    let g = grid_graph(12);
    let mut seed = 7u64;
    let start: Vec<f64> = (0..g.len())
        .map(|_| {
            if lcg(&mut seed) < 0.3 {
                0.1 + 3.0 * lcg(&mut seed)
            } else {
                f64::INFINITY
            }
        })
        .collect();
    let gradient = 0.25;
    let mut dijkstra = start.clone();
    grade(&g, &mut dijkstra, gradient);
    // brute force: relax every edge until nothing changes
    let mut brute = start.clone();
    loop {
        let mut changed = false;
        for a in 0..g.len() {
            for &b in &g.neighbours[a] {
                let cand =
                    brute[a] + gradient * vec3::dist(g.positions[a], g.positions[b as usize]);
                if cand < brute[b as usize] {
                    brute[b as usize] = cand;
                    changed = true;
                }
            }
        }
        if !changed {
            break;
        }
    }
    for v in 0..g.len() {
        assert!(
            (dijkstra[v] - brute[v]).abs() < 1e-12,
            "vertex {v}: {} vs {}",
            dijkstra[v],
            brute[v]
        );
        assert!(dijkstra[v] <= start[v], "a size grew");
        for &w in &g.neighbours[v] {
            let d = vec3::dist(g.positions[v], g.positions[w as usize]);
            assert!(dijkstra[w as usize] <= dijkstra[v] + gradient * d + 1e-12);
        }
    }
    assert!(
        dijkstra.iter().all(|s| s.is_finite()),
        "a connected graph with a seed is finite everywhere"
    );
}

#[test]
fn one_small_size_spreads_as_a_cone() {
    let g = grid_graph(9);
    let mut s = vec![f64::INFINITY; g.len()];
    s[0] = 0.5; // at the origin
    grade(&g, &mut s, 0.2);
    // along the grid's diagonal edges the distance to the origin is exact
    for k in 0..9 {
        let v = k * 9 + k;
        let want = 0.5 + 0.2 * (2.0f64).sqrt() * k as f64;
        assert!((s[v] - want).abs() < 1e-12, "{} vs {want}", s[v]);
    }
}

fn fields(model: &Model, h: f64, sizing: SizeMapOptions) -> ModelFields {
    model_fields(
        model,
        &FieldOptions {
            size: Size::Absolute(h),
            sizing,
            ..Default::default()
        },
    )
    .expect("fields")
}

/// A 10 × 0.1 strip: its long sides are 0.1 apart and share no corner, and
/// its short sides are 0.1 long, so the small-feature size is at most 0.1 on
/// every curve although the requested size is 1.
#[test]
fn close_curves_and_short_curves_get_small_sizes() {
    let model = primitives::rectangle(10.0, 0.1);
    let f = fields(&model, 1.0, SizeMapOptions::default());
    let map = f.size_map.as_ref().expect("size map");
    let mut on_curves = 0;
    for (v, r) in map.graph.refs.iter().enumerate() {
        if *r != NodeRef::Interior {
            on_curves += 1;
            assert!(
                map.feature[v] <= 0.1 + 1e-9,
                "vertex {v} ({r:?}): feature size {}",
                map.feature[v]
            );
            assert!(map.size[v] <= 0.1 + 1e-9);
        }
    }
    assert!(on_curves > 20);
    // everything is within 0.05 of a long side, so the whole map is ≤ 0.1 + 0.2·0.05
    assert!(
        map.size.iter().all(|&s| s <= 0.11 + 1e-9),
        "max {}",
        map.size.iter().cloned().fold(0.0, f64::max)
    );
    // the long sides are quantized against it: ≈ 10 / (2·0.1) coarse segments, not 10 / 2
    let plan = f.curve_plan(&model);
    for c in [0, 2] {
        assert!(
            plan.counts[c] >= 45 && plan.counts[c] <= 55,
            "curve {c}: {} coarse segments",
            plan.counts[c]
        );
    }
    assert_eq!(
        plan.counts[0], plan.counts[2],
        "opposite sides of a 4-sided face"
    );
    // without small-feature adaptation the long sides follow the requested size
    let plain = fields(
        &model,
        1.0,
        SizeMapOptions {
            small_features: false,
            ..Default::default()
        },
    );
    let plan = plain.curve_plan(&model);
    assert!(plan.counts[0] <= 6, "{} coarse segments", plan.counts[0]);
}

/// On a square whose features are all larger than the size, the map is the
/// requested size (the conformal scaling of a square is uniform).
#[test]
fn a_square_without_small_features_keeps_the_requested_size() {
    let model = primitives::square(2.0);
    let f = fields(&model, 0.25, SizeMapOptions::default());
    let map = f.size_map.as_ref().unwrap();
    assert!(
        map.size.iter().all(|&s| (s - 0.25).abs() < 0.01),
        "range {:?}",
        map.size
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, b), &s| (a.min(s), b.max(s)))
    );
    assert_eq!(
        f.curve_plan(&model).counts,
        plan_curves(&model, 0.25).counts
    );
    // the face's own copy is the model map
    let face = f.faces[0].outcome.as_ref().unwrap();
    assert_eq!(face.size.as_ref().unwrap(), &map.face_sizes(0));
}

/// A user size on one side of a square is honoured on that side and spreads
/// into the face no faster than the gradient allows.
#[test]
fn a_curve_size_is_honoured_and_graded() {
    let model = primitives::square(2.0);
    let sizing = SizeMapOptions {
        gradient: 0.3,
        entity_sizes: vec![(Entity::Curve(CurveId(0)), 0.05)],
        ..Default::default()
    };
    let f = fields(&model, 0.25, sizing);
    let map = f.size_map.as_ref().unwrap();
    for (v, p) in map.graph.positions.iter().enumerate() {
        // Eq. 10 holds on every edge
        for &w in &map.graph.neighbours[v] {
            let d = vec3::dist(*p, map.graph.positions[w as usize]);
            assert!(map.size[w as usize] <= map.size[v] + 0.3 * d + 1e-12);
        }
        // curve 0 is the side y = 0; grading runs along edges, whose paths are
        // a little longer than the straight distance y (plus one background
        // edge, 2 · 0.25 / 8, near the side)
        let bound = 0.05 + 0.3 * (1.25 * p[1] + 0.0625);
        assert!(
            map.size[v] <= bound + 1e-9,
            "vertex at {p:?}: size {} above {bound}",
            map.size[v]
        );
        if p[1] < 1e-12 {
            assert!((map.size[v] - 0.05).abs() < 1e-12);
        }
        if p[1] > 1.2 {
            assert!(
                (map.size[v] - 0.25).abs() < 0.01,
                "far from the side the requested size returns: {}",
                map.size[v]
            );
        }
    }
    let plan = f.curve_plan(&model);
    // side 0: 2 / (2·0.05) = 20 coarse segments; its opposite side is ideal 4
    // (more than 2:1 apart, so not forced equal)
    assert_eq!(plan.counts[0], 20);
    assert_eq!(plan.counts[2], 4);
    // sides 1 and 3 are graded: denser near y = 0
    let cm = discretize_curve(&model, &plan, CurveId(1));
    let first = vec3::dist(cm.points[0], cm.points[2]);
    let last = vec3::dist(
        cm.points[cm.points.len() - 3],
        cm.points[cm.points.len() - 1],
    );
    assert!(
        first < 0.5 * last,
        "graded side: first coarse segment {first}, last {last}"
    );
}

/// Eq. 11: consecutive points split ∫ dl / s into equal parts.
#[test]
fn points_split_the_size_integral_equally() {
    let model = primitives::square(1.0);
    // curve 0 runs t ∈ [0, 1] along x; size grows linearly from 0.02 to 0.1
    let profile = vec![[0.0, 0.02], [1.0, 0.1]];
    let sizes = vec![Some(profile), None, None, None];
    let plan = plan_curves_sized(&model, 0.5, &sizes);
    // ∫ dx / (2 s(x)) with s = 0.02 + 0.08 x: ln(5) / 0.16 ≈ 10.06 → 10
    assert!(
        (plan.ideal(CurveId(0)) - (5.0f64).ln() / 0.16).abs() < 0.02,
        "ideal {}",
        plan.ideal(CurveId(0))
    );
    assert_eq!(plan.counts[0], 10);
    let cm = discretize_curve(&model, &plan, CurveId(0));
    let primitive = |x: f64| (0.02 + 0.08 * x).ln() / 0.08;
    let steps: Vec<f64> = cm
        .points
        .windows(2)
        .map(|w| primitive(w[1][0]) - primitive(w[0][0]))
        .collect();
    let mean = steps.iter().sum::<f64>() / steps.len() as f64;
    for s in &steps {
        assert!((s - mean).abs() < 0.01 * mean, "step {s} vs mean {mean}");
    }
}

#[test]
fn bad_options_are_refused() {
    let model = primitives::square(1.0);
    let bad = [
        SizeMapOptions {
            gradient: 0.0,
            ..Default::default()
        },
        SizeMapOptions {
            gradient: f64::NAN,
            ..Default::default()
        },
        SizeMapOptions {
            min_size: Some(-1.0),
            ..Default::default()
        },
        SizeMapOptions {
            min_size: Some(2.0),
            max_size: Some(1.0),
            ..Default::default()
        },
        SizeMapOptions {
            entity_sizes: vec![(Entity::Curve(CurveId(9)), 0.1)],
            ..Default::default()
        },
        SizeMapOptions {
            entity_sizes: vec![(Entity::Face(FaceId(0)), 0.0)],
            ..Default::default()
        },
    ];
    for sizing in bad {
        let r = model_fields(
            &model,
            &FieldOptions {
                size: Size::Absolute(0.5),
                sizing: sizing.clone(),
                ..Default::default()
            },
        );
        assert!(
            matches!(r, Err(crate::core::error::MeshError::Sizing(_))),
            "{sizing:?} accepted"
        );
    }
}

/// Bounds clamp the map; a face size sets the face's quad target.
#[test]
fn bounds_and_face_sizes() {
    let model = primitives::rectangle(10.0, 0.1);
    let f = fields(
        &model,
        1.0,
        SizeMapOptions {
            min_size: Some(0.3),
            ..Default::default()
        },
    );
    assert!(f.size_map.unwrap().size.iter().all(|&s| s >= 0.3));
    let model = primitives::square(2.0);
    let f = fields(
        &model,
        0.5,
        SizeMapOptions {
            entity_sizes: vec![(Entity::Face(FaceId(0)), 0.2)],
            max_size: Some(0.15),
            ..Default::default()
        },
    );
    let map = f.size_map.unwrap();
    assert!(
        map.conformal.iter().all(|&s| (s - 0.2).abs() < 0.01),
        "the face asks for 0.2"
    );
    assert!(
        map.size.iter().all(|&s| s == 0.15),
        "clamped to the maximum"
    );
}

/// On a curved face the curvature bounds the size: a cylinder of radius 0.5
/// with 16 quads per turn asks for 2π · 0.5 / 16 ≈ 0.196 although the
/// requested size is 1. Without the bound, or with a size given to the
/// face, the face keeps the size it was asked for.
#[test]
fn curvature_bounds_the_size_of_curved_faces() {
    let model = primitives::cylinder(0.5, 3.0);
    let conformal_range = |quads_per_turn: Option<f64>, entity_sizes: Vec<(Entity, f64)>| {
        let f = fields(
            &model,
            1.0,
            SizeMapOptions {
                small_features: false,
                quads_per_turn,
                entity_sizes,
                ..Default::default()
            },
        );
        let k = f.faces[0].outcome.as_ref().unwrap().curvature.unwrap();
        assert!((k - 2.0).abs() < 1e-6, "curvature {k}");
        let map = f.size_map.unwrap();
        map.graph.face_vertices[0]
            .iter()
            .map(|&g| map.conformal[g as usize])
            .fold((f64::INFINITY, 0.0f64), |(a, b), s| (a.min(s), b.max(s)))
    };
    let turn = std::f64::consts::TAU * 0.5 / 16.0;
    let (lo, hi) = conformal_range(Some(16.0), Vec::new());
    assert!(lo > 0.97 * turn && hi < 1.03 * turn, "{lo} .. {hi}");
    // the circles it shares with the planar caps take the caps' smaller
    // conformal sizes, still well above the curvature size
    let (lo, hi) = conformal_range(None, Vec::new());
    assert!(lo > 3.0 * turn && (hi - 1.0).abs() < 0.03, "{lo} .. {hi}");
    let (lo, hi) = conformal_range(Some(16.0), vec![(Entity::Face(FaceId(0)), 0.8)]);
    assert!(lo > 2.0 * turn && (hi - 0.8).abs() < 0.03, "{lo} .. {hi}");
}

/// The typical curvature is an area quantile: a sphere reads 1/R wherever it
/// is sampled, a plane 0.
#[test]
fn typical_curvature_of_a_sphere_and_a_plane() {
    let sphere = primitives::sphere(2.0);
    let face = &sphere.faces[0];
    let b = &face.uv_bounds;
    let uvs: Vec<[f64; 2]> = (0..25)
        .map(|i| {
            let (s, t) = ((i % 5) as f64 / 4.0, (i / 5) as f64 / 4.0);
            [
                b.umin + s * (b.umax - b.umin),
                b.vmin + 0.1 + t * 0.8 * (b.vmax - b.vmin - 0.2),
            ]
        })
        .collect();
    let xyz: Vec<Vec3> = uvs.iter().map(|&uv| face.surface.eval(uv)).collect();
    let tris: Vec<[u32; 3]> = (0..4u32)
        .flat_map(|j| {
            (0..4u32).flat_map(move |i| {
                let a = j * 5 + i;
                [[a, a + 1, a + 6], [a, a + 6, a + 5]]
            })
        })
        .collect();
    let k = typical_curvature(face, &uvs, &xyz, &tris).unwrap();
    assert!((k - 0.5).abs() < 1e-6, "{k}");
    let plane = primitives::square(1.0);
    let k = typical_curvature(
        &plane.faces[0],
        &uvs.iter()
            .map(|p| [p[0].rem_euclid(1.0), p[1].rem_euclid(1.0)])
            .collect::<Vec<_>>(),
        &xyz,
        &tris,
    );
    assert_eq!(k, Some(0.0));
}

/// The size map of a cylinder of radius 0.5 and height 3 (κ = 2) with 16
/// quads per turn, floor `min_size` and turn floor `floor_turn`, without
/// small features (the turn-rule tests).
fn cylinder_turn_map(min_size: f64, floor_turn: Option<f64>) -> SizeMap {
    fields(
        &primitives::cylinder(0.5, 3.0),
        1.0,
        SizeMapOptions {
            small_features: false,
            quads_per_turn: Some(16.0),
            min_size: Some(min_size),
            floor_turn,
            ..Default::default()
        },
    )
    .size_map
    .expect("size map")
}

/// The smallest and largest size on the first face's vertices.
fn side(m: &SizeMap) -> (f64, f64) {
    m.graph.face_vertices[0]
        .iter()
        .map(|&g| m.size[g as usize])
        .fold((f64::INFINITY, 0.0f64), |(a, b), s| (a.min(s), b.max(s)))
}

/// A curved face whose curvature size falls below the floor lowers the floor
/// to `floor_turn / κ` ([`SizeMapOptions::floor_turn`]): a cylinder of
/// radius 0.5 (κ = 2) with 16 quads per turn asks for 0.196, which a floor
/// of 1 raised to 1 (a quad spanning 115° of turn); with a floor turn of
/// 90° its vertices get π/2 / 2 = 0.785. The caps' vertices keep at least
/// the lowered floor, graded from the cylinder (Eq. 10), and where the floor
/// is already below `turn / κ` nothing changes.
#[test]
fn a_narrow_curved_face_lowers_the_floor_to_its_turn() {
    let turn = std::f64::consts::FRAC_PI_2;
    let map = cylinder_turn_map;
    let floor = turn / 2.0;
    let (lo, hi) = side(&map(1.0, None));
    assert!(lo >= 1.0 && hi <= 1.0 + 1e-12, "clamped: {lo} .. {hi}");
    let lowered = map(1.0, Some(turn));
    let (lo, hi) = side(&lowered);
    assert!(
        (lo - floor).abs() < 1e-12 && (hi - floor).abs() < 1e-12,
        "lowered: {lo} .. {hi}, want {floor}"
    );
    for (v, p) in lowered.graph.positions.iter().enumerate() {
        let s = lowered.size[v];
        assert!(s >= floor - 1e-12 && s <= 1.0 + 1e-12, "{p:?}: {s}");
        // the lowered floor is graded: a cap vertex next to a cylinder
        // vertex is at most the gradient above it
        if s <= floor + 1e-12 {
            for &w in &lowered.graph.neighbours[v] {
                let d = vec3::dist(*p, lowered.graph.positions[w as usize]);
                assert!(lowered.size[w as usize] <= floor + DEFAULT_GRADIENT * d + 1e-9);
            }
        }
    }
    // a floor already below the turn's size: the same map with or without
    assert_eq!(map(0.5, Some(turn)).size, map(0.5, None).size);
}

/// The turn rule never lowers the floor of a band below
/// [`TURN_MIN_FRACTION`] of it: the cylinder of radius 0.5 (two loops) (90° arc π/4 = 0.785, curvature size
/// 2π · 0.5 / 16 = 0.196) under a floor of 4 gets exactly 4 / 4 = 1 on its
/// vertices, not 0.785 (a fillet 5 times narrower than the floor gets quads
/// longer along it than wide rather than tiny squares). Under a floor of 2
/// the quarter, 0.5, is below the arc, which the cylinder keeps.
#[test]
fn the_turn_rule_lowers_the_floor_to_at_most_a_quarter() {
    let turn = std::f64::consts::FRAC_PI_2;
    let band = |min_size: f64| side(&cylinder_turn_map(min_size, Some(turn)));
    let (lo, hi) = band(4.0);
    assert!(
        (lo - 1.0).abs() < 1e-12 && (hi - 1.0).abs() < 1e-12,
        "bounded: {lo} .. {hi}, want {}",
        TURN_MIN_FRACTION * 4.0
    );
    let arc = turn / 2.0;
    let (lo, hi) = band(2.0);
    assert!(
        (lo - arc).abs() < 1e-12 && (hi - arc).abs() < 1e-12,
        "not bounded: {lo} .. {hi}, want {arc}"
    );
}

/// A strip narrower than the floor lowers it to its width
/// ([`SizeMapOptions::floor_narrow`]): the 10 × 0.1 rectangle has width
/// 2 A / P = 2 · 1 / 20.2 = 0.099, and a floor of 0.3 held every size at
/// 0.3 or above (three times the strip's width along it); with the option,
/// every size lies between the width and the small-feature size 0.1. Under
/// a floor of 0.5 the strip is below a quarter of it: a sliver, left alone.
#[test]
fn a_narrow_strip_lowers_the_floor_to_its_width() {
    let model = primitives::rectangle(10.0, 0.1);
    let sizes = |min_size: f64, floor_narrow: bool| {
        fields(
            &model,
            1.0,
            SizeMapOptions {
                min_size: Some(min_size),
                floor_narrow,
                ..Default::default()
            },
        )
        .size_map
        .expect("size map")
        .size
    };
    assert!(sizes(0.3, false).iter().all(|&s| s >= 0.3));
    let width = 2.0 * 1.0 / 20.2;
    for s in sizes(0.3, true) {
        assert!(s >= width - 1e-3 && s <= 0.1 + 1e-9, "size {s}, width {width}");
    }
    // a strip below a quarter of the floor is a sliver: left at the floor
    assert!(width < NARROW_MIN_FRACTION * 0.5);
    assert!(sizes(0.5, true).iter().all(|&s| s >= 0.5));
}

/// A two-sided face for the width rule: bottom vertices `(x, 0)` for
/// x = 0..=10 and top vertices `(x, top(x))` for x = `first_top`..=10 (with
/// `first_top` = 1 the face starts at the point (0, 0)), triangulated
/// between the two sides.
fn two_sided(first_top: usize, top: impl Fn(f64) -> f64) -> FaceTopology {
    use crate::field::crossfield::{FaceMesh, VertexClass};
    let mut xyz: Vec<Vec3> = (0..=10).map(|x| [x as f64, 0.0, 0.0]).collect();
    let t0 = xyz.len() as u32;
    xyz.extend((first_top..=10).map(|x| [x as f64, top(x as f64), 0.0]));
    // top vertex at x (x ≥ 1 when the face starts at a point: there the top
    // side starts at the bottom's first vertex)
    let top_at = |x: usize| -> u32 {
        if x < first_top {
            0
        } else {
            t0 + (x - first_top) as u32
        }
    };
    let mut triangles = Vec::new();
    for k in 0..10u32 {
        let (b0, b1) = (k, k + 1);
        let (u0, u1) = (top_at(k as usize), top_at(k as usize + 1));
        triangles.push([b0, b1, u1]);
        if u0 != b0 {
            triangles.push([b0, u1, u0]);
        }
    }
    let mesh = FaceMesh {
        vertex_class: vec![VertexClass::Interior; xyz.len()],
        xyz,
        triangles,
        ..Default::default()
    };
    FaceTopology::build(&mesh).expect("topology")
}

/// The local widths of a 10 × 1 strip sampled every 1: each of the 18
/// vertices along its sides has the other side 1 away (the way round the
/// nearer end is at least 3, over twice that), each of its 4 corners has no
/// point across (every boundary point is at most √2 times farther round
/// than in space); each stands for boundary length 1. Evenness 1.
#[test]
fn a_constant_width_strip_reads_even() {
    let topo = two_sided(0, |_| 1.0);
    let mut widths = super::narrow::local_widths(&topo).expect("simple loop");
    widths.sort_by(|a, b| a.0.total_cmp(&b.0));
    assert_eq!(widths.len(), 22);
    for (i, &(w, weight)) in widths.iter().enumerate() {
        let want = if i < 18 { 1.0 } else { f64::INFINITY };
        assert!(w == want || (w - want).abs() < 1e-12, "{i}: {w}, want {want}");
        assert!((weight - 1.0).abs() < 1e-12);
    }
    assert_eq!(width_evenness(&topo), Some(1.0));
}

/// A wedge tapering linearly to nothing, the top side y = 0.1 x over the
/// bottom y = 0 (x from 0 to 10, closed by the side x = 10): the bottom
/// vertex at x has width 0.1 x / √1.01 (to the top line), the top vertex
/// 0.1 x (boundary length 1 and √1.01 each), the point and the two far
/// corners none across. Sorted, the pairs of x = 1, 2, … make 2.005 x of
/// the total 21.05: the 10 % quantile is the bottom vertex at x = 2 and the
/// 40 % quantile the one at x = 5, so the evenness is 0.2 / 0.5 = 0.4,
/// below [`NARROW_EVENNESS`], although the wedge is long and narrow.
#[test]
fn a_tapering_wedge_reads_uneven() {
    let topo = two_sided(1, |x| 0.1 * x);
    let widths = super::narrow::local_widths(&topo).expect("simple loop");
    assert_eq!(widths.len(), 21);
    let slant = 1.01f64.sqrt();
    let total: f64 = widths.iter().map(|w| w.1).sum();
    assert!((total - (10.0 + 10.0 * slant + 1.0)).abs() < 1e-9, "{total}");
    assert_eq!(widths.iter().filter(|w| w.0.is_infinite()).count(), 3);
    for x in 1..10 {
        let bottom = 0.1 * x as f64 / slant;
        assert!(
            widths.iter().any(|w| (w.0 - bottom).abs() < 1e-12),
            "bottom {x}"
        );
    }
    let even = width_evenness(&topo).expect("evenness");
    assert!((even - 0.4).abs() < 1e-12, "{even}");
    assert!(even < NARROW_EVENNESS);
    assert!(super::narrow::narrow_width(&topo).is_some());
}

/// A tapering face keeps the floor under the width rule: the lens between
/// (0, 0) and (10, 0) through (5, ±0.15) is long and narrow (mean width
/// 2 A / P = 3 / 20.009 = 0.150, above a quarter of the floor 0.4, so the
/// rule's other conditions hold) and its small-feature sizes reach 0.3
/// (its opposite sides are 0.3 apart in the middle), but its width tapers
/// to nothing at both ends: the size map is the same with or without the
/// rule, every size at the floor or above. The 10 × 0.1 strip (previous
/// test) is lowered under the same rule.
#[test]
fn a_tapering_lens_keeps_the_floor() {
    let model = primitives::polygon(&[[0.0, 0.0], [5.0, -0.15], [10.0, 0.0], [5.0, 0.15]]);
    let map = |floor_narrow: bool| {
        fields(
            &model,
            1.0,
            SizeMapOptions {
                min_size: Some(0.4),
                floor_narrow,
                ..Default::default()
            },
        )
        .size_map
        .expect("size map")
    };
    let width = 2.0 * 1.5 / (4.0 * (25.0f64 + 0.0225).sqrt());
    assert!((NARROW_MIN_FRACTION * 0.4..0.4).contains(&width), "{width}");
    let with = map(true);
    let below: f64 = with.feature.iter().copied().fold(f64::INFINITY, f64::min);
    assert!(below < 0.31, "smallest feature size {below}");
    assert!(with.size.iter().all(|&s| s >= 0.4));
    assert_eq!(with.size, map(false).size);
}

/// A band around an axis keeps the floor under the width rule: the side of
/// a cylinder of radius 2 and height 0.3 is long (its circles 4π each) and
/// evenly 0.3 wide (2 A / P = 2 · 1.2π / 8π = 0.3, above a quarter of the
/// floor 1), and its circles are 0.3 apart (small-feature sizes 0.3), but
/// it has two boundary loops: the size map is the same with or without the
/// rule, every size at the floor or above.
#[test]
fn a_band_of_revolution_keeps_the_floor() {
    let model = primitives::cylinder(2.0, 0.3);
    let map = |floor_narrow: bool| {
        fields(
            &model,
            2.0,
            SizeMapOptions {
                min_size: Some(1.0),
                floor_narrow,
                ..Default::default()
            },
        )
        .size_map
        .expect("size map")
    };
    let with = map(true);
    let below: f64 = with.feature.iter().copied().fold(f64::INFINITY, f64::min);
    assert!(below < 0.31, "smallest feature size {below}");
    assert!(with.size.iter().all(|&s| s >= 1.0));
    assert_eq!(with.size, map(false).size);
}
