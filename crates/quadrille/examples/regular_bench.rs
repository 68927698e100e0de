//! Benchmark of the regular method on CAD models: baseline mesh (triangle
//! split), then `regularize_mesh`; prints one Markdown row per model.
//!
//! Usage: `cargo run --release -p quadrille --example regular_bench -- [--pictures DIR] FILE...`
//!
//! Environment: `QR_ORDERS`, `QR_ORDER_BUDGET`, `QR_ORDER_PATIENCE`, `QR_QUAD_RATIO` (0: no quad
//! target, r > 0: r × input), `QR_DEPTH`, `QR_BUDGET`, `QR_TRANSLATION`,
//! `QR_PAIR_*`, `QR_WIDE_RADIUS`, `QR_WIDE_ORDERS`, `QR_WIDE_MIN` override the options, `QR_PREFER_INTERIOR` sets `prefer_interior`; `QR_VERBOSE` prints per-face reports,
//! `QR_DIAG` / `QR_DIAG_BEFORE` where the irregular vertices sit after / before,
//! `QR_INVALID` the quads left outside (5°, 175°), with their angles and corner classes,
//! `QR_FACES=DIR` one flat (u, v) picture per face, `QR_SIZE_FACTOR` the baseline's size factor.

use std::path::{Path, PathBuf};
use std::time::Instant;

use mesh::stats::MeshStats;
use quadrille::topology::{regularize_mesh, RegularizeOptions};
use quadrille::MeshOptions;

/// The baseline method's mesh of `model`.
fn mesh_baseline(
    model: &geometry::Model,
    opts: &quadrille::MeshOptions,
) -> Result<mesh::QuadMesh, quadrille::MeshError> {
    quadrille::mesh_model_with(model, opts, quadrille::MeshMethod::Baseline).map(|(m, _)| m)
}

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let mut pictures: Option<PathBuf> = None;
    if let Some(i) = args.iter().position(|a| a == "--pictures") {
        if i + 1 < args.len() {
            pictures = Some(PathBuf::from(args.remove(i + 1)));
        }
        args.remove(i);
    }
    println!("| model | quads before → after | nodes before → after | irregular interior % before → after | irregular incl. boundary % before → after | inverted quads before → after | invalid (5°,175°) after | min SICN before → after | window reached (median face) | mesh s | regularize s | skipped faces |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    for a in &args {
        let path = Path::new(a);
        let name = path
            .file_stem()
            .map(|s| s.to_string_lossy().to_string())
            .unwrap_or_default();
        let model = match occt::load(path) {
            Ok(m) => m,
            Err(e) => {
                println!("| {name} | import failed: {e} |");
                continue;
            }
        };
        let t0 = Instant::now();
        let size = std::env::var("QR_SIZE_FACTOR")
            .ok()
            .and_then(|s| s.parse::<f64>().ok())
            .map(quadrille::Size::Factor)
            .unwrap_or_default();
        let mut mesh = match mesh_baseline(
            &model,
            &MeshOptions {
                size,
                ..Default::default()
            },
        ) {
            Ok(m) => m,
            Err(e) => {
                println!("| {name} | baseline mesher failed: {e} |");
                continue;
            }
        };
        let t_mesh = t0.elapsed().as_secs_f64();
        let s0 = MeshStats::compute(&mesh, Some(&model));
        if std::env::var("QR_DIAG_BEFORE").is_ok() {
            eprintln!("  before regularization:");
            diagnose(&model, &mesh);
        }
        if let Some(dir) = &pictures {
            let _ = std::fs::create_dir_all(dir);
            let title = format!("{name}: triangle split (before)");
            let o = mesh::render::RenderOptions {
                title: Some(&title),
                ..Default::default()
            };
            if let Err(e) =
                mesh::render::render_png(&mesh, &o, &dir.join(format!("regular_{name}_before.png")))
            {
                eprintln!("{name}: picture failed: {e}");
            }
        }
        let t1 = Instant::now();
        let env = |k: &str, d: usize| {
            std::env::var(k)
                .ok()
                .and_then(|v| v.parse().ok())
                .unwrap_or(d)
        };
        let d = RegularizeOptions::default();
        let ropts = RegularizeOptions {
            max_sequence: env("QR_DEPTH", d.max_sequence),
            search_budget: env("QR_BUDGET", d.search_budget),
            translation_steps: env("QR_TRANSLATION", d.translation_steps),
            sweep_orders: env("QR_ORDERS", d.sweep_orders),
            order_budget: env("QR_ORDER_BUDGET", d.order_budget),
            order_patience: env("QR_ORDER_PATIENCE", d.order_patience),
            pair_radius: env("QR_PAIR_RADIUS", d.pair_radius),
            pair_depth: env("QR_PAIR_DEPTH", d.pair_depth),
            pair_beam: env("QR_PAIR_BEAM", d.pair_beam),
            pair_budget: env("QR_PAIR_BUDGET", d.pair_budget),
            wide_pair_radius: env("QR_WIDE_RADIUS", d.wide_pair_radius),
            wide_orders: env("QR_WIDE_ORDERS", d.wide_orders),
            wide_min_irregular: env("QR_WIDE_MIN", d.wide_min_irregular),
            quad_target: match std::env::var("QR_QUAD_RATIO")
                .ok()
                .and_then(|v| v.parse::<f64>().ok())
            {
                Some(r) if r > 0.0 => quadrille::topology::QuadTarget::Ratio(r),
                Some(_) => quadrille::topology::QuadTarget::Off,
                None => d.quad_target,
            },
            prefer_interior: std::env::var("QR_PREFER_INTERIOR").is_ok() || d.prefer_interior,
            ..d
        };
        let rep = match regularize_mesh(&model, &mut mesh, &ropts) {
            Ok(r) => r,
            Err(e) => {
                println!("| {name} | regularization failed: {e} |");
                continue;
            }
        };
        let t_reg = t1.elapsed().as_secs_f64();
        let s1 = MeshStats::compute(&mesh, Some(&model));
        if let Some(dir) = &pictures {
            let title = format!("{name}: regularized (after)");
            let o = mesh::render::RenderOptions {
                title: Some(&title),
                ..Default::default()
            };
            if let Err(e) =
                mesh::render::render_png(&mesh, &o, &dir.join(format!("regular_{name}_after.png")))
            {
                eprintln!("{name}: picture failed: {e}");
            }
        }
        let (ib, ia) = rep.irregular();
        let vb: usize = rep.faces.iter().map(|f| f.verts.0).sum();
        let va: usize = rep.faces.iter().map(|f| f.verts.1).sum();
        let invalid_after = rep.invalid().1;
        let mut wins: Vec<f64> = rep.faces.iter().map(|f| f.window.min_deg).collect();
        wins.sort_by(f64::total_cmp);
        let med = wins.get(wins.len() / 2).copied().unwrap_or(5.0);
        println!(
            "| {name} | {} → {} | {} → {} | {:.1} → {:.1} | {:.1} → {:.1} | {} → {} | {} | {:.3} → {:.3} | ({:.0}°, {:.0}°) | {:.2} | {:.2} | {} |",
            s0.quads,
            s1.quads,
            s0.nodes,
            s1.nodes,
            s0.irregular_percent,
            s1.irregular_percent,
            100.0 * ib as f64 / vb.max(1) as f64,
            100.0 * ia as f64 / va.max(1) as f64,
            s0.inverted_quads,
            s1.inverted_quads,
            invalid_after,
            s0.sicn.min,
            s1.sicn.min,
            med,
            180.0 - med,
            t_mesh,
            t_reg,
            rep.skipped.len()
        );
        if std::env::var("QR_INVALID").is_ok() {
            list_invalid(&model, &mesh);
        }
        if std::env::var("QR_VERBOSE").is_ok() {
            for f in &rep.faces {
                eprintln!("  face {}: quads {:?} verts {:?} irregular {:?} invalid {:?} window {:?} ops {:?}", f.face.0 + 1, f.quads, f.verts, f.irregular, f.invalid, f.window, f.ops);
            }
            eprintln!("  valence histogram after: {:?}", s1.valence_histogram);
        }
        if std::env::var("QR_DIAG").is_ok() {
            let sicn = mesh::stats::quad_sicn_values(&mesh, Some(&model));
            if let Some((q, s)) = sicn.iter().enumerate().min_by(|a, b| a.1.total_cmp(b.1)) {
                let classes: Vec<String> = mesh.quads[q]
                    .iter()
                    .map(|&n| format!("{:?}", mesh.node_class[n as usize]))
                    .collect();
                eprintln!(
                    "  worst quad {q} (face {}): SICN {s:.3}, nodes {classes:?}",
                    mesh.quad_face[q].0 + 1
                );
            }
            diagnose(&model, &mesh);
        }
        if let Ok(dir) = std::env::var("QR_FACES") {
            face_pictures(&model, &mesh, Path::new(&dir), &name);
        }
        for (f, why) in &rep.skipped {
            eprintln!("{name}: face {} skipped: {why}", f.0 + 1);
        }
        for f in rep.faces.iter().filter(|f| f.strict && !f.reverted) {
            eprintln!(
                "{name}: face {} redone in strict mode (the first result had more inverted quads)",
                f.face.0 + 1
            );
        }
        for f in rep.faces.iter().filter(|f| f.reverted) {
            eprintln!(
                "{name}: face {} reverted to its input (the result had more inverted quads)",
                f.face.0 + 1
            );
        }
        let o = rep.ops();
        eprintln!(
            "{name}: ops swaps {} collapses {} splits {} compositions {} rejected {} sweeps {}",
            o.swaps, o.collapses, o.splits, o.compositions, o.rejected, o.sweeps
        );
    }
}

/// Where the irregular vertices left after regularization sit (`QR_DIAG=1`):
/// interior ones by valence and by hop distance to the face boundary, boundary
/// ones by sign of (valence − ideal), and how many interior valence-3 vertices
/// have a boundary-excess vertex among their links.
fn diagnose(model: &geometry::Model, mesh: &mesh::QuadMesh) {
    use quadrille::core::{extract_face, quads_by_face};
    use std::collections::BTreeMap;
    let mut hist: BTreeMap<String, usize> = BTreeMap::new();
    let (mut floor, mut irr, mut nv) = (0i64, 0usize, 0usize);
    for (fid, qids) in quads_by_face(mesh) {
        let Ok(fq) = extract_face(model, mesh, fid, &qids) else {
            continue;
        };
        let n = fq.verts.len() as u32;
        // the index sum Σ (ideal − valence) is invariant under every operation:
        // at least |Σ| / 2 irregular vertices remain (a vertex rarely carries more than 2)
        let index: i64 = (0..n)
            .filter(|&v| fq.verts[v as usize].alive)
            .map(|v| fq.verts[v as usize].ideal as i64 - fq.valence(v) as i64)
            .sum();
        let face_irr = fq.irregular_count();
        floor += index.abs();
        irr += face_irr;
        nv += fq.num_verts();
        if std::env::var("QR_DIAG").as_deref() == Ok("2") {
            let interior = (0..n)
                .filter(|&v| !fq.verts[v as usize].fixed && fq.is_irregular(v))
                .count();
            let movable = (0..n)
                .filter(|&v| fq.verts[v as usize].alive && !fq.verts[v as usize].fixed)
                .count();
            eprintln!(
                "  face {}: quads {} verts {} interior {} irregular {} interior irregular {} index sum {} loops {} target {}",
                fid.0 + 1,
                fq.num_quads(),
                fq.num_verts(),
                movable,
                face_irr,
                interior,
                index,
                boundary_loops(&fq),
                quadrille::topology::QuadTarget::BoundarySpacing.quads_for(&fq)
            );
            if let Some(sides) = four_sides(&fq) {
                eprintln!("     sides {sides:?}");
            } else if let Some(lp) = quadrille::topology::single_boundary_loop(&fq) {
                let ideals: String = lp
                    .iter()
                    .map(|&v| {
                        let x = &fq.verts[v as usize];
                        char::from_digit(x.ideal.min(9), 10).unwrap_or('?')
                    })
                    .collect();
                eprintln!("     loop ideals {ideals}");
            }
            // mean 3D edge length on the boundary and inside
            let (mut bl, mut bn, mut il, mut inn) = (0.0, 0usize, 0.0, 0usize);
            for q in fq.live_quads() {
                let r = fq.quads[q as usize];
                for i in 0..4 {
                    let (a, b) = (r[i], r[(i + 1) % 4]);
                    let d =
                        geometry::vec3::dist(fq.verts[a as usize].xyz, fq.verts[b as usize].xyz);
                    if fq.edge_quads(a, b).len() == 1 {
                        bl += d;
                        bn += 1;
                    } else {
                        il += d / 2.0;
                        inn += 1;
                    }
                }
            }
            eprintln!(
                "     boundary edges {} mean {:.4}; interior edges {} mean {:.4}",
                bn,
                bl / bn.max(1) as f64,
                inn / 2,
                2.0 * il / inn.max(1) as f64
            );
            for v in 0..n {
                let x = &fq.verts[v as usize];
                if x.alive && x.fixed && (fq.valence(v) > 4 || fq.is_irregular(v)) {
                    eprintln!("     fixed {v}: class {:?} pole {} valence {} ideal {} offset {} angle {:.0}", x.class, x.pole.is_some(), fq.valence(v), x.ideal, x.edge_offset, fq.angle_sum(v));
                }
            }
        }
        // hop distance to the boundary
        let mut dist = vec![u32::MAX; n as usize];
        let mut front: Vec<u32> = (0..n)
            .filter(|&v| fq.verts[v as usize].alive && fq.verts[v as usize].fixed)
            .collect();
        for &v in &front {
            dist[v as usize] = 0;
        }
        let mut d = 0;
        while !front.is_empty() {
            d += 1;
            let mut next = Vec::new();
            for &v in &front {
                for l in fq.links(v) {
                    if dist[l as usize] == u32::MAX {
                        dist[l as usize] = d;
                        next.push(l);
                    }
                }
            }
            front = next;
        }
        for v in 0..n {
            if !fq.is_irregular(v) {
                continue;
            }
            let x = &fq.verts[v as usize];
            let val = fq.valence(v);
            let key = if x.fixed {
                let kind = match x.class {
                    mesh::NodeClass::Corner(_) => "corner",
                    _ => "curve",
                };
                format!("boundary {kind} {:+}", val as i64 - x.ideal as i64)
            } else {
                let near_excess = fq.links(v).into_iter().any(|l| {
                    fq.verts[l as usize].fixed && fq.valence(l) > fq.verts[l as usize].ideal
                });
                let near_irr = fq
                    .links(v)
                    .into_iter()
                    .filter(|&l| fq.is_irregular(l))
                    .count();
                // hop distance to the nearest vertex of opposite index
                let sign = |w: u32| -> i64 {
                    let y = &fq.verts[w as usize];
                    let ideal = if y.fixed { y.ideal } else { 4 };
                    (ideal as i64 - fq.valence(w) as i64).signum()
                };
                let s0 = sign(v);
                let mut seen = vec![v];
                let mut fr = vec![v];
                let mut partner = 9;
                'bfs: for h in 1..=8 {
                    let mut nx = Vec::new();
                    for &a in &fr {
                        for l in fq.links(a) {
                            if seen.contains(&l) {
                                continue;
                            }
                            seen.push(l);
                            if sign(l) == -s0 {
                                partner = h;
                                break 'bfs;
                            }
                            nx.push(l);
                        }
                    }
                    fr = nx;
                }
                format!(
                    "interior val {val} hops {} partner {partner} {}{}",
                    dist[v as usize].min(3),
                    if near_excess {
                        "next to bdry excess"
                    } else {
                        ""
                    },
                    if near_irr > 0 {
                        format!(" irr-links {near_irr}")
                    } else {
                        String::new()
                    }
                )
            };
            *hist.entry(key).or_default() += 1;
        }
    }
    for (k, c) in hist {
        eprintln!("  {c:5}  {k}");
    }
    eprintln!("  irregular {irr} of {nv} face-local vertices ({:.1} %); sum of |index sum| over faces {floor} ({:.1} %)", 100.0 * irr as f64 / nv.max(1) as f64, 100.0 * floor as f64 / nv.max(1) as f64);
}

/// Writes one picture per face (`QR_FACES=DIR`): the quads flat in (u, v),
/// irregular vertices as dots (blue: fewer edges than ideal, red: one more,
/// magenta: two or more more).
fn face_pictures(model: &geometry::Model, mesh: &mesh::QuadMesh, dir: &Path, name: &str) {
    use mesh::render::{Overlay, OverlayPoint, RenderOptions};
    use quadrille::core::{extract_face, quads_by_face};
    let _ = std::fs::create_dir_all(dir);
    for (fid, qids) in quads_by_face(mesh) {
        let Ok(fq) = extract_face(model, mesh, fid, &qids) else {
            continue;
        };
        let mut m = mesh::QuadMesh::default();
        for v in &fq.verts {
            m.nodes.push([v.uv[0], v.uv[1], 0.0]);
            m.node_class
                .push(mesh::NodeClass::Curve(geometry::CurveId(0), None));
        }
        for q in fq.live_quads() {
            m.quads.push(fq.quads[q as usize]);
            m.quad_face.push(fid);
        }
        let mut ov = Overlay::default();
        for v in 0..fq.verts.len() as u32 {
            if !fq.is_irregular(v) {
                continue;
            }
            let x = &fq.verts[v as usize];
            let d = fq.valence(v) as i64 - x.ideal as i64;
            let color = if d < 0 {
                [30, 80, 255]
            } else if d == 1 {
                [230, 20, 20]
            } else {
                [220, 0, 220]
            };
            ov.points.push(OverlayPoint {
                position: [x.uv[0], x.uv[1], 0.0],
                color,
            });
        }
        let title = format!(
            "{name} face {}: {} irregular",
            fid.0 + 1,
            fq.irregular_count()
        );
        let o = RenderOptions {
            eye_dir: [0.0, 0.0, 1.0],
            up: [0.0, 1.0, 0.0],
            title: Some(&title),
            overlay: Some(&ov),
            show_irregular: false,
            ..Default::default()
        };
        let _ = mesh::render::render_png(&m, &o, &dir.join(format!("{name}_f{}.png", fid.0 + 1)));
    }
}

/// Number of boundary loops of a face's quads (edges of a single live quad).
fn boundary_loops(fq: &quadrille::core::FaceQuads) -> usize {
    use std::collections::{BTreeMap, BTreeSet};
    let mut directed = BTreeSet::new();
    for q in fq.live_quads() {
        let r = fq.quads[q as usize];
        for i in 0..4 {
            directed.insert((r[i], r[(i + 1) % 4]));
        }
    }
    let mut next: BTreeMap<u32, Vec<u32>> = BTreeMap::new();
    for &(a, b) in &directed {
        if !directed.contains(&(b, a)) {
            next.entry(a).or_default().push(b);
        }
    }
    let mut seen = BTreeSet::new();
    let mut loops = 0;
    let keys: Vec<u32> = next.keys().copied().collect();
    for s in keys {
        if seen.contains(&s) {
            continue;
        }
        loops += 1;
        let mut v = s;
        while seen.insert(v) {
            v = match next.get(&v).and_then(|n| n.first()) {
                Some(&w) => w,
                None => break,
            };
        }
    }
    loops
}

/// Edge counts of the 4 sides of a single-loop face with 4 corners (ideal 2).
fn four_sides(fq: &quadrille::core::FaceQuads) -> Option<[usize; 4]> {
    quadrille::topology::four_side_counts(fq)
}

/// The quads of the regularized mesh outside the base angle window
/// (`QR_INVALID`): face, angles, and the classification of each corner.
fn list_invalid(model: &geometry::Model, mesh: &mesh::QuadMesh) {
    use quadrille::core::{extract_face, quads_by_face};
    use quadrille::topology::AngleWindow;
    use quadrille::topology::{quad_angles, quad_valid};
    for (fid, qids) in quads_by_face(mesh) {
        let Ok(fq) = extract_face(model, mesh, fid, &qids) else {
            continue;
        };
        let face = &model.faces[fid.idx()];
        for q in fq.live_quads() {
            if quad_valid(&fq, face, q, AngleWindow::BASE) {
                continue;
            }
            let angles = quad_angles(&fq, face, q).map(|a| a.0.map(|x| x.round()));
            let classes: Vec<String> = fq.quads[q as usize]
                .iter()
                .map(|&v| match &fq.verts[v as usize].class {
                    mesh::NodeClass::Corner(c) => format!("corner {}", c.0 + 1),
                    mesh::NodeClass::Curve(c, _) => format!("curve {}", c.0 + 1),
                    mesh::NodeClass::Face(..) => "face".to_string(),
                    other => format!("{other:?}"),
                })
                .collect();
            eprintln!(
                "  invalid quad, face {}: angles {angles:?} corners {classes:?}",
                fid.0 + 1
            );
        }
    }
}
