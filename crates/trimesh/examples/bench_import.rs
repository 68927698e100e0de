//! Benchmark of the triangle-mesh import: a finely tessellated closed
//! sphere and a closed cylinder (about 1 M triangles each) written as binary
//! STL in memory, then read, welded, checked, feature-detected, cut and
//! parametrized, on one thread. Prints a Markdown table row per mesh.
//!
//! ```sh
//! cargo run --release -p trimesh --example bench_import [-- TRIANGLES]
//! ```

use std::path::Path;
use std::time::Instant;

use geometry::Vec3;

fn sphere(k: usize, l: usize) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let mut p = vec![[0.0, 0.0, -1.0]];
    for j in 1..l {
        let th = std::f64::consts::PI * j as f64 / l as f64 - std::f64::consts::FRAC_PI_2;
        for i in 0..k {
            let a = std::f64::consts::TAU * i as f64 / k as f64;
            p.push([th.cos() * a.cos(), th.cos() * a.sin(), th.sin()]);
        }
    }
    p.push([0.0, 0.0, 1.0]);
    let top = p.len() as u32 - 1;
    let id = |j: usize, i: usize| 1 + ((j - 1) * k + i % k) as u32;
    let mut t = Vec::new();
    for i in 0..k {
        t.push([0, id(1, i + 1), id(1, i)]);
        t.push([top, id(l - 1, i), id(l - 1, i + 1)]);
    }
    for j in 1..l - 1 {
        for i in 0..k {
            t.push([id(j, i), id(j, i + 1), id(j + 1, i + 1)]);
            t.push([id(j, i), id(j + 1, i + 1), id(j + 1, i)]);
        }
    }
    (p, t)
}

/// A closed cylinder (radius 1, height 2): `k` around, `h` rows, `r` cap rings.
fn cylinder(k: usize, h: usize, r: usize) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let mut p = Vec::new();
    let mut t = Vec::new();
    let ring = |rad: f64, z: f64, p: &mut Vec<Vec3>| -> u32 {
        let b = p.len() as u32;
        for i in 0..k {
            let a = i as f64 / k as f64 * std::f64::consts::TAU;
            p.push([rad * a.cos(), rad * a.sin(), z]);
        }
        b
    };
    let side: Vec<u32> = (0..=h)
        .map(|j| ring(1.0, 2.0 * j as f64 / h as f64, &mut p))
        .collect();
    for j in 0..h {
        for i in 0..k {
            let (a, b) = (side[j] + i as u32, side[j] + ((i + 1) % k) as u32);
            let (c, d) = (side[j + 1] + ((i + 1) % k) as u32, side[j + 1] + i as u32);
            t.push([a, b, c]);
            t.push([a, c, d]);
        }
    }
    for (z, up) in [(0.0, false), (2.0, true)] {
        let mut rings: Vec<u32> = (1..=r)
            .map(|q| ring(q as f64 / r as f64, z, &mut p))
            .collect();
        let c = p.len() as u32;
        p.push([0.0, 0.0, z]);
        rings.insert(0, c);
        let mut push = |tri: [u32; 3]| t.push(if up { tri } else { [tri[0], tri[2], tri[1]] });
        for i in 0..k {
            push([c, rings[1] + i as u32, rings[1] + ((i + 1) % k) as u32]);
        }
        for q in 1..r {
            for i in 0..k {
                let (a, b) = (rings[q] + i as u32, rings[q] + ((i + 1) % k) as u32);
                let (cc, d) = (rings[q + 1] + ((i + 1) % k) as u32, rings[q + 1] + i as u32);
                push([a, d, cc]);
                push([a, cc, b]);
            }
        }
    }
    (p, t)
}

fn run(name: &str, mesh: (Vec<Vec3>, Vec<[u32; 3]>)) {
    let bytes = trimesh::read::write_stl_binary(&mesh.0, &mesh.1);
    let t0 = Instant::now();
    let soup = trimesh::read::read_bytes(&bytes, trimesh::Format::Stl, Path::new(name)).unwrap();
    let read = t0.elapsed().as_secs_f64();
    let imp = trimesh::build(soup, &trimesh::Options::default(), Path::new(name)).unwrap();
    let total = t0.elapsed().as_secs_f64();
    let s = imp.report.seconds;
    let min = imp
        .report
        .faces
        .iter()
        .map(|f| f.min_uv_area)
        .fold(f64::INFINITY, f64::min);
    println!(
        "| {name} | {} | {} | {} | {} | {read:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {total:.2} | {min:.1e} |",
        imp.report.triangles,
        imp.report.vertices,
        imp.model.faces.len(),
        imp.model.curves.len(),
        s[1],
        s[2],
        s[3],
        s[4]
    );
}

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    println!("| mesh | triangles | vertices | faces | curves | read s | weld+topology s | features s | patches+cuts s | parametrize s | total s | min uv area |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    // sphere: 2k(l-1) triangles with l = k/2
    let k = ((n as f64).sqrt() * 1.0).round() as usize;
    run(
        "sphere (closed: seam map too distorted, split into charts)",
        sphere(k, k / 2),
    );
    // cylinder: 2kh side + 2·k(2r-1) caps
    let k = ((n as f64 / 4.0).sqrt()).round() as usize;
    run(
        "cylinder (3 faces, side cut by a seam)",
        cylinder(k, k, k / 2),
    );
}
