//! Benchmark of the cross-field stage (issue 4): the cross field of a disk
//! face triangulated with ~100k triangles (and smaller sizes) and of an
//! irregular pentagon of about as many triangles, against one Cholesky
//! factorization + solve of the same operator (`M + α K`, the
//! Crouzeix–Raviart connection Laplacian the field is diffused with, with the
//! solver's ordering and triangular solves) and of the real scalar CR
//! Laplacian on the same edges. Single-threaded. Times are the best of
//! `--runs` runs (default 3).
//!
//! Run: `cargo run --release -p quadrille --example bench_crossfield -- [rings...]
//! [--levels N] [--max-iterations N] [--tolerance C] [--runs N] [--verbose]`
//! (a disk of `r` rings has `6 r²` triangles; default 40 80 130). `--verbose`
//! prints every singularity. `--solvers` instead compares faer's orderings
//! (AMD, the geometric nested dissection of `linsolve`) and factorization
//! kinds (supernodal, simplicial) on the two 100k faces.

use std::time::Instant;

use faer::c64;
use quadrille::field::conformal_scaling;
use quadrille::field::extract_singularities;
use quadrille::field::NONE;
use quadrille::field::{assemble, cr_stiffness};
use quadrille::field::{compute_cross_field, CrossFieldOptions, FaceTopology};
use quadrille::field::{LowerPattern, SparseSpd};
use quadrille::fixtures::crossfield_meshes as fixtures;

/// Best time of `runs` runs of `f`, with the output of that run.
fn best_of<T>(runs: usize, mut f: impl FnMut() -> T) -> (f64, T) {
    let mut best: Option<(f64, T)> = None;
    for _ in 0..runs.max(1) {
        let t = Instant::now();
        let r = f();
        let el = t.elapsed().as_secs_f64();
        if best.as_ref().is_none_or(|(b, _)| el < *b) {
            best = Some((el, r));
        }
    }
    best.unwrap()
}

fn free_coords(topo: &FaceTopology, free: &[u32]) -> Vec<[f64; 3]> {
    free.iter()
        .map(|&e| {
            let [a, b] = topo.edges[e as usize];
            let (p, q) = (topo.positions[a as usize], topo.positions[b as usize]);
            [
                (p[0] + q[0]) / 2.0,
                (p[1] + q[1]) / 2.0,
                (p[2] + q[2]) / 2.0,
            ]
        })
        .collect()
}

/// One-shot factorization + solve of the cross-field operator `M + α K`
/// (complex, free edges only) at the finest α: (symbolic, numeric, solve) seconds.
fn reference_complex(topo: &FaceTopology, fixed: &[bool]) -> (f64, f64, f64) {
    let u = vec![[1.0, 0.0]; topo.edges.len()];
    let active = vec![true; topo.triangles.len()];
    let sys = assemble(topo, &active, fixed, &u).unwrap();
    let alpha = (3.0 * topo.h_min).powi(2);
    let mut vals: Vec<c64> = sys.stiffness.iter().map(|k| k * alpha).collect();
    for j in 0..sys.free.len() {
        vals[sys.spd.pattern.diag(j)] += c64::new(sys.mass[j], 0.0);
    }
    let pattern = sys.spd.pattern.clone();
    let t = Instant::now();
    // the ordering of the cross-field solver (faer's AMD)
    let spd = SparseSpd::analyze(pattern, None).unwrap();
    let t_sym = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let f = spd.factor(&vals).unwrap();
    let t_num = t.elapsed().as_secs_f64();
    let mut rhs: Vec<c64> = sys.mass.iter().map(|&m| c64::new(m, 0.0)).collect();
    let t = Instant::now();
    f.solve_in_place(&mut rhs);
    let t_solve = t.elapsed().as_secs_f64();
    (t_sym, t_num, t_solve)
}

/// One-shot factorization + solve of the real scalar CR Laplacian `M + α K`
/// on the same free edges: total seconds.
fn reference_scalar(topo: &FaceTopology, fixed: &[bool]) -> f64 {
    let ne = topo.edges.len();
    let mut index = vec![NONE; ne];
    let mut n = 0usize;
    for e in 0..ne {
        if !fixed[e] {
            index[e] = n as u32;
            n += 1;
        }
    }
    let mut below = vec![Vec::new(); n];
    for t in 0..topo.triangles.len() {
        for &a in &topo.tri_edges[t] {
            for &b in &topo.tri_edges[t] {
                let (i, j) = (index[a as usize], index[b as usize]);
                if i != NONE && j != NONE && i > j {
                    below[j as usize].push(i as usize);
                }
            }
        }
    }
    let pattern = LowerPattern::from_columns(n, below);
    let alpha = (3.0 * topo.h_min).powi(2);
    let mut vals = vec![0.0f64; pattern.nnz()];
    for t in 0..topo.triangles.len() {
        let k = cr_stiffness(topo, t);
        let te = topo.tri_edges[t];
        for a in 0..3 {
            for b in 0..3 {
                let (i, j) = (index[te[a] as usize], index[te[b] as usize]);
                if i != NONE && j != NONE && i >= j {
                    vals[pattern.position(i as usize, j as usize).unwrap()] += alpha * k[a][b];
                }
            }
            let i = index[te[a] as usize];
            if i != NONE {
                vals[pattern.diag(i as usize)] += topo.areas[t] / 3.0;
            }
        }
    }
    let t = Instant::now();
    let spd = SparseSpd::analyze(pattern, None).unwrap();
    let f = spd.factor(&vals).unwrap();
    let mut rhs = vec![1.0f64; n];
    f.solve_in_place(&mut rhs);
    t.elapsed().as_secs_f64()
}

/// Linear-algebra micro benchmark on `mesh` (operator `M + αK` at the final
/// α): fill, symbolic, numeric and solve times (best of 3 / 3 / 30 runs) for
/// each ordering (geometric nested dissection, AMD) and factorization kind.
fn solve_bench(mesh: &quadrille::field::FaceMesh) {
    use faer::sparse::linalg::SupernodalThreshold;
    let field = compute_cross_field(
        mesh,
        &CrossFieldOptions {
            max_iterations: 1,
            levels: 1,
            ..Default::default()
        },
    )
    .unwrap();
    let topo = &field.topology;
    let u = vec![[1.0, 0.0]; topo.edges.len()];
    let sys = assemble(topo, &vec![true; topo.triangles.len()], &field.fixed, &u).unwrap();
    let alpha = (3.0 * topo.h_min).powi(2);
    let mut vals: Vec<c64> = sys.stiffness.iter().map(|k| k * alpha).collect();
    for j in 0..sys.free.len() {
        vals[sys.spd.pattern.diag(j)] += c64::new(sys.mass[j], 0.0);
    }
    let coords = free_coords(topo, &sys.free);
    for (oname, ord) in [("ND", Some(&coords[..])), ("AMD", None)] {
        for (kname, th) in [
            ("supernodal", SupernodalThreshold::FORCE_SUPERNODAL),
            ("simplicial", SupernodalThreshold::FORCE_SIMPLICIAL),
        ] {
            let (t_sym, spd) = best_of(3, || {
                SparseSpd::analyze_with(sys.spd.pattern.clone(), ord, th).unwrap()
            });
            let (t_num, f) = best_of(3, || spd.factor(&vals).unwrap());
            let mut rhs: Vec<c64> = sys.mass.iter().map(|&m| c64::new(m, 0.0)).collect();
            let (t_solve, _) = best_of(30, || f.solve_in_place(&mut rhs));
            println!(
                "{oname} {kname}: nnz(L) {} sym {t_sym:.4} num {t_num:.4} solve {t_solve:.4}",
                spd.factor_entries()
            );
        }
    }
}

fn main() {
    faer::set_global_parallelism(faer::Par::Seq);
    let pentagon = [[0.0, 0.0], [3.0, 0.0], [3.5, 2.0], [1.0, 3.0], [-0.5, 1.5]];
    let mut opts = CrossFieldOptions::default();
    let (mut rings, mut runs, mut verbose) = (Vec::new(), 3usize, false);
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = || {
            args.next()
                .and_then(|v| v.parse::<f64>().ok())
                .unwrap_or_else(|| {
                    eprintln!("bench_crossfield: {a} needs a number");
                    std::process::exit(2)
                })
        };
        match a.as_str() {
            "--levels" => opts.levels = value() as usize,
            "--max-iterations" => opts.max_iterations = value() as usize,
            "--tolerance" => opts.tolerance = value(),
            "--runs" => runs = value() as usize,
            "--verbose" => verbose = true,
            "--solvers" => {
                println!("disk 130 rings");
                solve_bench(&fixtures::disk(130));
                println!("irregular pentagon");
                solve_bench(&fixtures::convex_polygon(&pentagon, 142));
                return;
            }
            _ => match a.parse::<usize>() {
                Ok(r) => rings.push(r),
                Err(_) => {
                    eprintln!("usage: bench_crossfield [RINGS...] [--levels N] [--max-iterations N] [--tolerance C] [--runs N] [--verbose] [--solvers]");
                    std::process::exit(if a == "--help" || a == "-h" { 0 } else { 2 });
                }
            },
        }
    }
    if rings.is_empty() {
        rings = vec![40, 80, 130];
    }
    println!("| face | triangles | edges solved | levels (iterations) | cross field (s) [setup / levels] | factor+solve of M+αK (s) [sym / num / solve] | ratio | scalar CR factor+solve (s) | singularities | singularity radius / position | scaling (s) |");
    println!("|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|");
    let mut faces = Vec::new();
    for &r in &rings {
        faces.push((format!("disk {r} rings"), fixtures::disk(r)));
    }
    if let Some(&r) = rings.last() {
        // irregular pentagon with about as many triangles as the largest disk
        let n = ((6 * r * r) as f64 / 5.0).sqrt().round() as usize;
        faces.push((
            "irregular pentagon".to_string(),
            fixtures::convex_polygon(&pentagon, n),
        ));
    }
    for (name, mesh) in faces {
        let (t_field, field) = best_of(runs, || compute_cross_field(&mesh, &opts).unwrap());
        let topo = &field.topology;
        let (t_sym, t_num, t_solve) = (0..runs.max(1))
            .map(|_| reference_complex(topo, &field.fixed))
            .fold((f64::INFINITY, f64::INFINITY, f64::INFINITY), |a, b| {
                (a.0.min(b.0), a.1.min(b.1), a.2.min(b.2))
            });
        let t_ref = t_sym + t_num + t_solve;
        let (t_scalar, _) = best_of(runs, || reference_scalar(topo, &field.fixed));
        let sing = extract_singularities(&field);
        let (t_scale, _) = best_of(runs, || conformal_scaling(&field).unwrap());
        // disks are centred on the origin: mean distance of the singularities to it
        let place = if name.starts_with("disk") && !sing.list.is_empty() {
            let r: f64 = sing
                .list
                .iter()
                .map(|s| s.position[0].hypot(s.position[1]))
                .sum::<f64>()
                / sing.list.len() as f64;
            format!("r = {r:.3}")
        } else if let [s] = &sing.list[..] {
            format!("({:.3}, {:.3})", s.position[0], s.position[1])
        } else {
            "—".to_string()
        };
        if verbose {
            for s in &sing.list {
                eprintln!(
                    "{name}: index {} at ({:.4}, {:.4}, {:.4})",
                    s.index, s.position[0], s.position[1], s.position[2]
                );
            }
        }
        let t_levels: f64 = field.levels.iter().map(|l| l.seconds).sum();
        let its: Vec<String> = field
            .levels
            .iter()
            .map(|l| l.iterations.to_string())
            .collect();
        println!(
            "| {} | {} | {} | {} ({}) | {:.3} [{:.3} / {:.3}] | {:.3} [{:.3} / {:.3} / {:.4}] | {:.2} | {:.3} | {} (sum {}) | {} | {:.3} |",
            name,
            topo.triangles.len(),
            field.free_edges(),
            field.levels.len(),
            its.join("+"),
            t_field,
            t_field - t_levels,
            t_levels,
            t_ref,
            t_sym,
            t_num,
            t_solve,
            t_field / t_ref,
            t_scalar,
            sing.list.len(),
            sing.index_sum(),
            place,
            t_scale
        );
    }
}
