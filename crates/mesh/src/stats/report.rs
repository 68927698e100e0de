//! The human-readable table of [`MeshStats`] that `quadrille stats` prints.

use std::fmt;

use super::{MeshStats, SHARP_CORNER_DEG};

impl fmt::Display for MeshStats {
    /// A two-column human-readable table.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let row = |f: &mut fmt::Formatter<'_>, k: &str, v: String| writeln!(f, "  {k:<34} {v}");
        writeln!(f, "mesh statistics")?;
        row(f, "nodes", self.nodes.to_string())?;
        row(f, "quads", self.quads.to_string())?;
        row(f, "triangles", self.triangles.to_string())?;
        row(f, "edges", self.edges.to_string())?;
        row(
            f,
            "Euler characteristic (V-E+F)",
            self.euler_characteristic.to_string(),
        )?;
        row(
            f,
            "face-interior nodes",
            self.face_interior_nodes.to_string(),
        )?;
        let hist: Vec<String> = self
            .valence_histogram
            .iter()
            .map(|(v, n)| format!("{v}:{n}"))
            .collect();
        row(f, "valence histogram (face interior)", hist.join(" "))?;
        row(
            f,
            "irregular nodes",
            format!("{} ({:.2} %)", self.irregular_nodes, self.irregular_percent),
        )?;
        if self.curve_nodes > 0 {
            row(
                f,
                "curve nodes off 2 quads per side",
                format!(
                    "{} of {} ({:.2} %)",
                    self.irregular_curve_nodes,
                    self.curve_nodes,
                    100.0 * self.irregular_curve_nodes as f64 / self.curve_nodes as f64
                ),
            )?;
        }
        let normals = if self.cad_normals {
            "CAD normals"
        } else {
            "mesh normals"
        };
        row(
            f,
            &format!("SICN min / p1 / avg ({normals})"),
            format!(
                "{:.3} / {:.3} / {:.3}",
                self.sicn.min, self.sicn.p1, self.sicn.avg
            ),
        )?;
        row(
            f,
            "scaled Jacobian min / p1 / avg",
            format!(
                "{:.3} / {:.3} / {:.3}",
                self.scaled_jacobian.min, self.scaled_jacobian.p1, self.scaled_jacobian.avg
            ),
        )?;
        row(
            f,
            &format!("inverted ({normals})"),
            self.inverted_quads.to_string(),
        )?;
        row(
            f,
            "inverted (element geometry)",
            self.inverted_quads_element_geometry.to_string(),
        )?;
        if self.fold_corners > 0 {
            row(
                f,
                "corners on a fold (centre normal)",
                self.fold_corners.to_string(),
            )?;
        }
        row(f, "open edges", self.open_edges.to_string())?;
        row(f, "non-manifold edges", self.non_manifold_edges.to_string())?;
        if let Some(d) = &self.cad_distance {
            row(
                f,
                "CAD distance max",
                format!("{:.3e} ({:.3e} of diagonal)", d.max, d.max_relative),
            )?;
            row(
                f,
                "CAD distance mean",
                format!("{:.3e} ({:.3e} of diagonal)", d.mean, d.mean_relative),
            )?;
            if d.failed > 0 {
                row(f, "CAD projections failed", d.failed.to_string())?;
            }
        }
        if !self.sharp_corners.is_empty() {
            row(
                f,
                &format!("CAD corners below {SHARP_CORNER_DEG}°"),
                self.sharp_corners.len().to_string(),
            )?;
            row(
                f,
                "quads touching them (excused)",
                self.excused_quads.len().to_string(),
            )?;
            row(
                f,
                "inverted excluding them (CAD / element)",
                format!(
                    "{} / {}",
                    self.inverted_quads_outside_sharp,
                    self.inverted_quads_element_geometry_outside_sharp
                ),
            )?;
            row(
                f,
                "min SICN excluding them",
                format!("{:.3}", self.min_sicn_excluding_sharp),
            )?;
            for e in &self.excused_quads {
                writeln!(
                    f,
                    "    quad {} at corner {} ({:.2}°): SICN {:.3}",
                    e.quad,
                    e.corner + 1,
                    e.angle_deg,
                    e.sicn
                )?;
            }
        }
        Ok(())
    }
}
