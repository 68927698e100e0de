//! Builds the disk-quadrangulation table ([`quadrille::combinatorics::disk_quads`]) and
//! prints its size per (boundary, interior) vertex count and the build time.
//!
//! Run: `cargo run --release -p quadrille --example disk_table [max_boundary] [max_interior]`
//! (default 12 and 4, the table the mesher uses). With `--write` (default
//! sizes only) it also rewrites `crates/quadrille/src/combinatorics/disk_quads/table.txt`.

use std::collections::BTreeMap;
use std::time::Instant;

fn main() {
    let write = std::env::args().any(|a| a == "--write");
    let args: Vec<String> = std::env::args().filter(|a| a != "--write").collect();
    let arg = |i: usize, d: usize| args.get(i).and_then(|a| a.parse().ok()).unwrap_or(d);
    let (b, i) = (
        arg(1, quadrille::combinatorics::TABLE_MAX_BOUNDARY),
        arg(2, quadrille::combinatorics::TABLE_MAX_INTERIOR),
    );
    let t = Instant::now();
    let disks = quadrille::combinatorics::enumerate(b, i);
    let secs = t.elapsed().as_secs_f64();
    let mut counts: BTreeMap<(usize, usize), usize> = BTreeMap::new();
    for d in &disks {
        *counts.entry((d.boundary, d.interior)).or_default() += 1;
    }
    let interiors: Vec<usize> = (0..=i).collect();
    print!("| boundary \\ interior |");
    for n in &interiors {
        print!(" {n} |");
    }
    println!();
    println!("|---|{}", "---:|".repeat(interiors.len()));
    for bb in (4..=b).step_by(2) {
        print!("| {bb} |");
        for n in &interiors {
            print!(" {} |", counts.get(&(bb, *n)).copied().unwrap_or(0));
        }
        println!();
    }
    println!(
        "\n{} disk quadrangulations (b ≤ {b}, n_int ≤ {i}) in {secs:.2} s",
        disks.len()
    );
    if write {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/src/combinatorics/disk_quads/table.txt"
        );
        if (b, i)
            != (
                quadrille::combinatorics::TABLE_MAX_BOUNDARY,
                quadrille::combinatorics::TABLE_MAX_INTERIOR,
            )
        {
            eprintln!("--write needs the default sizes");
            std::process::exit(2);
        }
        if let Err(e) = std::fs::write(path, quadrille::combinatorics::format_table(&disks)) {
            eprintln!("{path}: {e}");
            std::process::exit(1);
        }
        println!("wrote {path}");
    }
}
