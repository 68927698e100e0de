//! Shells with interior cones (issue 31 S2): the geometric core with the
//! cones (one-rings of interior cones refined, Ricci flow, cut, immersion,
//! the cut transitions), the layout energy (S6–S7) on it, the tracing of
//! its separatrices and the patches (S8, `trace`), and the refusal of the
//! spline output while splines on a traced layout (S9 across the cuts'
//! charts) are not built.

use std::time::Instant;

use super::SplineMethodError;
use crate::cones::{check_cones, ConeSummary};
use crate::cut::{cut_to_disk, CutMesh, CutTarget};
use crate::immersion::{immerse, CutTransition, Immersion};
use crate::layout_energy::{minimise, LayoutEnergyError, LayoutEnergyOptions, LayoutMap};
use crate::ricci::{
    boundary_corner_cones, refine_cone_rings, ricci_flow, Cone, RicciMetric, RicciOptions,
};
use crate::shell::{Shell, ShellTopology};
use crate::trace::{trace_patches, TraceOptions};

/// Which cones [`super::splines_from_shell`] uses.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum ConeChoice {
    /// The boundary corners only (the cone-free path).
    #[default]
    CornersOnly,
    /// These cones (a checked proposal or a cone file).
    Given(Vec<Cone>),
}

/// The geometric core run with cones: the refined shell and everything
/// the flow, the cut and the immersion made on it.
#[derive(Clone, Debug)]
pub struct ConeCore {
    /// The shell with the one-rings of interior cones refined (old vertex
    /// indices kept, new vertices appended).
    pub shell: Shell,
    /// Its topology.
    pub topo: ShellTopology,
    /// The cones (same vertices as given).
    pub cones: Vec<Cone>,
    /// Their counts.
    pub summary: ConeSummary,
    /// The flat cone metric.
    pub metric: RicciMetric,
    /// The cut mesh Ω.
    pub cut: CutMesh,
    /// ψ_R with one transition per cut path.
    pub immersion: Immersion,
    /// Wall times of its stages.
    pub times: CoreTimes,
}

/// Wall times (seconds) of the stages of [`cone_core`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CoreTimes {
    /// Cone checks and the refinement of the cones' one-rings.
    pub refine: f64,
    /// Ricci flow.
    pub ricci: f64,
    /// Cut graph and cut mesh Ω.
    pub cut: f64,
    /// Immersion with the cut transitions.
    pub immersion: f64,
    /// Layout energy (S6–S7), when it ran.
    pub energy: f64,
    /// Separatrix tracing and patches (S8), when it ran.
    pub trace: f64,
}

/// What the layout energy reported on a shell with cones (the `--json`
/// report of a refusal).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EnergySummary {
    /// Q1–Q4 passed.
    pub converged: bool,
    /// Largest constraint residual (plane units); when the energy failed,
    /// the value of the check that failed.
    pub residual: f64,
    /// Its tolerance (1e-7 × the diagonal of ψ for residuals).
    pub tolerance: f64,
    /// Smallest det J (NaN when the energy failed).
    pub min_det: f64,
    /// Newton iterations over all stages.
    pub iterations: usize,
    /// Outer (penalty) stages.
    pub stages: usize,
    /// S8: separatrices traced (0 when it did not run or failed).
    pub separatrices: usize,
    /// S8: faces of the layout.
    pub patches: usize,
    /// S8: faces with four corners.
    pub quads: usize,
}

impl EnergySummary {
    fn of(map: &LayoutMap) -> EnergySummary {
        EnergySummary {
            converged: true,
            residual: map.residuals.max(),
            tolerance: map.tolerance,
            min_det: map.min_det,
            iterations: map.iterations,
            stages: map.stages.len(),
            separatrices: 0,
            patches: 0,
            quads: 0,
        }
    }
}

impl ConeCore {
    /// The transitions of the cut paths that end at `vertex` (a cone).
    pub fn transitions_at(&self, vertex: usize) -> Vec<CutTransition> {
        self.immersion
            .transitions
            .iter()
            .filter(|t| {
                let v = &self.cut.paths[t.path].vertices;
                v.first() == Some(&vertex) || v.last() == Some(&vertex)
            })
            .copied()
            .collect()
    }

    /// Cut branches made for boundary loops.
    pub fn loop_cuts(&self) -> usize {
        self.cut
            .branches
            .iter()
            .filter(|b| matches!(b.target, CutTarget::Loop(_)))
            .count()
    }

    /// One line: cones, flow, cut paths and their quarter turns.
    pub fn describe(&self) -> String {
        let turns = quarter_turn_list(self.immersion.transitions.iter().map(|t| t.quarter_turns));
        let angle = self
            .immersion
            .transitions
            .iter()
            .map(|t| t.angle_error)
            .fold(0.0, f64::max);
        format!(
            "placed {}; Ricci converged in {} iterations (max |K̄−K| {:.1e}) on {} triangles; {} cut paths, quarter turns {turns} (max angle error {angle:.1e})",
            self.summary,
            self.metric.iterations,
            self.metric.max_error,
            self.shell.triangles.len(),
            self.cut.paths.len(),
        )
    }
}

/// The cut paths' quarter turns for one line: listed when there are at most
/// [`LISTED_TURNS`], else counted per value (a shell with 800 cones has as
/// many paths; the list made a 5,000-character error line).
fn quarter_turn_list(turns: impl Iterator<Item = u8>) -> String {
    let turns: Vec<u8> = turns.collect();
    if turns.len() <= LISTED_TURNS {
        return format!("{turns:?}");
    }
    let mut counts = [0usize; 4];
    for &k in &turns {
        counts[usize::from(k % 4)] += 1;
    }
    format!(
        "0: {}, 1: {}, 2: {}, 3: {} (of {})",
        counts[0],
        counts[1],
        counts[2],
        counts[3],
        turns.len()
    )
}

/// Quarter turns listed one by one in [`ConeCore::describe`] up to this
/// many paths; more are counted.
pub const LISTED_TURNS: usize = 12;

/// Runs the core with `cones` (checked by [`check_cones`]) on `shell` of
/// topology `topo` (its [`Shell::check`]): interior cones' one-rings refined
/// ([`refine_cone_rings`]), Ricci flow, cut to a disk (cuts to every
/// interior cone), immersion with the cut transitions.
pub fn cone_core(
    shell: &Shell,
    topo: &ShellTopology,
    cones: &[Cone],
) -> Result<ConeCore, SplineMethodError> {
    let t0 = Instant::now();
    if topo.components != 1 {
        return Err(SplineMethodError::Components(topo.components));
    }
    check_cones(shell, topo, cones, "cones")?;
    let interior: Vec<usize> = cones
        .iter()
        .filter(|c| c.index != 0 && !topo.on_boundary[c.vertex])
        .map(|c| c.vertex)
        .collect();
    let refined = refine_cone_rings(shell, topo, &interior);
    let rtopo = refined.check()?;
    let cones: Vec<Cone> = cones.iter().copied().filter(|c| c.index != 0).collect();
    let summary = check_cones(&refined, &rtopo, &cones, "cones")?;
    let refine = t0.elapsed().as_secs_f64();
    let t1 = Instant::now();
    let metric = ricci_flow(&refined, &rtopo, &cones, &RicciOptions::default())?;
    let ricci = t1.elapsed().as_secs_f64();
    let t2 = Instant::now();
    let cut = cut_to_disk(&refined, &rtopo, &cones)?;
    let cut_time = t2.elapsed().as_secs_f64();
    let t3 = Instant::now();
    let immersion = immerse(&refined, &rtopo, &cut, &metric)?;
    let times = CoreTimes {
        refine,
        ricci,
        cut: cut_time,
        immersion: t3.elapsed().as_secs_f64(),
        energy: 0.0,
        trace: 0.0,
    };
    Ok(ConeCore {
        shell: refined,
        topo: rtopo,
        cones,
        summary,
        metric,
        cut,
        immersion,
        times,
    })
}

/// The layout energy (S6–S7, [`minimise`]) on a core's Ω from its ψ_R,
/// with no feature edges (the spline path has none yet).
pub fn layout_energy(core: &ConeCore) -> Result<LayoutMap, LayoutEnergyError> {
    minimise(
        &core.shell,
        &core.topo,
        &core.cut,
        &core.cones,
        &core.metric,
        &core.immersion,
        &[],
        &LayoutEnergyOptions::default(),
    )
}

/// `Ok` when `cones` are exactly the boundary corners of `shell` (of
/// topology `topo`; the cone-free path can go on); otherwise runs
/// [`cone_core`], the layout energy and the tracing (S8) with them and
/// refuses with one line saying what was placed, how the energy and the
/// tracing ended and that splines on a traced layout are not built yet.
pub fn refuse_unless_corner_cones(
    shell: &Shell,
    topo: &ShellTopology,
    cones: &[Cone],
) -> Result<(), SplineMethodError> {
    let mut given: Vec<Cone> = cones.iter().copied().filter(|c| c.index != 0).collect();
    given.sort_by_key(|c| c.vertex);
    let mut corners = boundary_corner_cones(shell, topo);
    corners.sort_by_key(|c| c.vertex);
    if given == corners {
        return Ok(());
    }
    let core = cone_core(shell, topo, &given)?;
    let what = if core.summary.interior() > 0 {
        "interior cones"
    } else {
        "boundary cones other than the shell's corners"
    };
    let t = Instant::now();
    let energy = layout_energy(&core);
    let mut times = core.times;
    times.energy = t.elapsed().as_secs_f64();
    let (stage, summary) = match &energy {
        Ok(map) => {
            let mut summary = EnergySummary::of(map);
            let t = Instant::now();
            let traced = trace_patches(
                &core.shell,
                &core.topo,
                &core.cut,
                &core.cones,
                &map.uv,
                &TraceOptions::default(),
            );
            times.trace = t.elapsed().as_secs_f64();
            let s8 = match &traced {
                Ok(layout) => {
                    summary.separatrices = layout.traces.len();
                    summary.patches = layout.patches.len();
                    summary.quads = layout.quads();
                    match layout.check() {
                        Ok(()) => layout.describe(),
                        Err(e) => format!("{}, refused: {e}", layout.describe()),
                    }
                }
                Err(e) => e.to_string(),
            };
            (
                format!(
                    "{}; {s8}; spline patches on a traced layout (S9 across the cuts' charts) are not built yet",
                    map.describe()
                ),
                summary,
            )
        }
        Err(e) => {
            let mut summary = EnergySummary::default();
            if let LayoutEnergyError::Violated {
                value,
                limit,
                stages,
                iterations,
                ..
            } = e
            {
                summary = EnergySummary {
                    converged: false,
                    residual: *value,
                    tolerance: *limit,
                    min_det: f64::NAN,
                    iterations: *iterations,
                    stages: *stages,
                    ..EnergySummary::default()
                };
            }
            (
                format!("{e}; no separatrix traced (S8 needs Q1–Q4)"),
                summary,
            )
        }
    };
    Err(SplineMethodError::NeedsLayoutEnergy {
        message: format!(
            "{what}: {}; S6–S7 {stage} (boundary Σ I = {}, interior Σ I = {})",
            core.describe(),
            core.summary.boundary_sum,
            core.summary.interior_sum,
        ),
        times,
        energy: summary,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A few paths are listed; many are counted per quarter turn, so the
    /// refusal line stays short.
    #[test]
    fn quarter_turns_are_listed_or_counted() {
        assert_eq!(quarter_turn_list([1u8, 3, 0].into_iter()), "[1, 3, 0]");
        let many = (0..LISTED_TURNS as u8 + 8).map(|i| i % 3);
        // 20 paths: i % 3 gives 0 seven times, 1 seven times, 2 six times
        assert_eq!(quarter_turn_list(many), "0: 7, 1: 7, 2: 6, 3: 0 (of 20)");
    }
}
