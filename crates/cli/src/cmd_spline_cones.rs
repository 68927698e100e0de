//! The cones of `quadrille spline` (issue 31 S2): `--cones FILE` read and
//! snapped, or the cross-field proposal; `--cones-out FILE` written
//! (atomically) before the spline stage, which refuses shells with interior
//! cones until the layout energy (S6–S7) is built.

use anyhow::{anyhow, Context, Result};
use quadrille::cones::{format_cones, parse_cones, propose_cones, write_cones, ConeSummary};
use quadrille::methods::spline::{is_cone_free, ConeChoice};
use quadrille::ricci::boundary_corner_cones;
use quadrille::shell::{Shell, ShellTopology};

use crate::SplineArgs;

/// The cones for `shell` of topology `topo` (its one [`Shell::check`], which
/// the spline stage uses too): the file's, else the proposal's. A disk whose
/// boundary corners alone sum to 4, or an annulus without corners, keeps the
/// cone-free path (its proposal is only computed for `--cones-out`; interior
/// ± pairs it has are noted). A shell of several components is left to the
/// spline stage's error.
pub fn choose_cones(
    args: &SplineArgs,
    shell: &Shell,
    topo: &ShellTopology,
    name: &str,
) -> Result<ConeChoice> {
    if topo.components != 1 {
        return Ok(ConeChoice::CornersOnly);
    }
    let write_out = |cones: &[quadrille::ricci::Cone]| -> Result<()> {
        if let Some(out) = &args.cones_out {
            write_cones(out, &format_cones(shell, topo, cones))
                .with_context(|| format!("--cones-out {}", out.display()))?;
        }
        Ok(())
    };
    if let Some(path) = &args.cones {
        let text =
            std::fs::read_to_string(path).with_context(|| format!("--cones {}", path.display()))?;
        let cones = parse_cones(&text, &path.display().to_string(), shell, topo)?;
        write_out(&cones)?;
        return Ok(ConeChoice::Given(cones));
    }
    let cone_free = is_cone_free(topo, &boundary_corner_cones(shell, topo));
    if cone_free && args.cones_out.is_none() {
        return Ok(ConeChoice::CornersOnly);
    }
    let cones = propose_cones(shell, topo).map_err(|e| anyhow!("{name}: {e}"))?;
    write_out(&cones)?;
    let summary = ConeSummary::of(topo, &cones);
    if summary.interior() == 0 {
        return Ok(ConeChoice::CornersOnly);
    }
    if cone_free {
        eprintln!(
            "note: {name}: the cross field proposes {} interior cones (Σ I = {}); the shell needs none, so they are not used",
            summary.interior(),
            summary.interior_sum
        );
        return Ok(ConeChoice::CornersOnly);
    }
    Ok(ConeChoice::Given(cones))
}
