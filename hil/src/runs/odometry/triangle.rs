//! The Triangular Path's result: Ed from the lines, Eb from the triangles,
//! its table and plot.

use std::path::{Path, PathBuf};

use super::plan::Plan;
use super::runs::{RunRow, RunSet};
use super::ExperimentError;
use crate::output::OutputDir;

/// The Triangular Path's result: the runs' end errors and the correction.
#[derive(Debug, Clone, serde::Serialize)]
pub struct TriangleReport {
    pub plan: Plan,
    pub runs: Vec<RunRow>,
    #[serde(flatten)]
    pub result: calib::TriangleResult,
    pub robot_time_s: f64,
}

/// The lines' and the triangles' end points of a complete run set.
fn triangle_runs(full: &RunSet) -> Result<(calib::LineRuns, calib::TriangleRuns), ExperimentError> {
    let (lines, triangles) = full.endpoints();
    let line = calib::LineRuns::new(lines)?;
    let tri = calib::TriangleRuns::complete(triangles)?;
    Ok((line, tri))
}

/// The Triangular Path correction from a complete set of runs.
pub fn triangle_report(
    full: &RunSet,
    wheelbase_mm: f64,
    solution: calib::Solution,
) -> Result<TriangleReport, ExperimentError> {
    let (line, tri) = triangle_runs(full)?;
    let params = calib::TriangleParams {
        side_cm: full.plan.leg_mm / 10.0,
        wheelbase_mm,
        // The bench drives the lines and the triangles with the same
        // parameters: the triangles' legs bend as the lines do.
        line_correction_applied: false,
        solution,
        ..calib::TriangleParams::default()
    };
    let mut result = calib::triangle_correction(&line, &tri, &params);
    result.warnings.extend(full.warnings());
    Ok(TriangleReport {
        plan: full.plan.clone(),
        runs: full.rows(["line", "triangle"]),
        result,
        robot_time_s: full.robot_time_s(),
    })
}

impl TriangleReport {
    pub fn render(&self) -> String {
        use std::fmt::Write;
        let r = &self.result;
        let mut s = String::new();
        let _ = writeln!(
            s,
            "Triangular Path, L = {:.0} mm, {} lines and {} counter-clockwise triangles ({}, seed {})",
            self.plan.leg_mm, self.plan.runs_per_direction, self.plan.runs_per_direction, self.plan.firmware, self.plan.seed
        );
        let _ = writeln!(
            s,
            "  end errors (cm; x along the first leg, y to the left; the line's against its end):"
        );
        let _ = writeln!(s, "    run |   line x   line y |  trian x  trian y");
        let n = self.plan.runs_per_direction;
        for i in 0..n {
            let (a, b) = (&self.runs[i], &self.runs[n + i]);
            let _ = writeln!(
                s,
                "    {:>3} | {:8.2} {:8.2} | {:8.2} {:8.2}",
                i + 1,
                a.x_cm,
                a.y_cm,
                b.x_cm,
                b.y_cm
            );
        }
        let _ = writeln!(
            s,
            "  line centroid ({:.2}, {:.2}) cm -> beta {:.4} deg, Ed {:.5}, cL {:.5}, cR {:.5}",
            r.line_centroid.x_cm, r.line_centroid.y_cm, r.beta_deg, r.ed, r.cl, r.cr
        );
        let _ = writeln!(
            s,
            "  triangle centroid ({:.2}, {}) cm -> 120-degree turn error {:.4} deg, Eb {:.5}, wheelbase {:.2} mm",
            r.triangle_centroid.x_cm,
            r.triangle_centroid.y_cm.map_or("?".into(), |y| format!("{y:.2}")),
            r.alpha_deg,
            r.eb,
            r.wheelbase_mm
        );
        for w in &r.warnings {
            let _ = writeln!(s, "  warning: {w}");
        }
        let _ = writeln!(s, "  robot time {:.1} s in all", self.robot_time_s);
        s
    }
}

/// The files of a Triangular Path's `--out` folder, all of them and nothing else.
pub const TRIANGLE_FILES: &[&str] = &["triangle.svg", "triangle.png", "triangle.json"];

/// Write the triangle report and its plot ([`TRIANGLE_FILES`]) into `dir`,
/// a folder of their own that [`OutputDir::commit`] puts in place as a whole.
pub fn write_triangle_set(
    dir: &Path,
    full: &RunSet,
    report: &TriangleReport,
) -> anyhow::Result<()> {
    let (line, tri) = triangle_runs(full)?;
    calib::plot_triangle(
        &report.result,
        &line,
        &tri,
        dir.join("triangle.svg"),
        dir.join("triangle.png"),
    )?;
    std::fs::write(
        dir.join("triangle.json"),
        serde_json::to_string_pretty(report)?,
    )?;
    Ok(())
}

/// Replace the folder `dir` by the triangle report and its plot, as a
/// whole (see [`OutputDir`]); the paths written.
pub fn write_triangle_outputs(
    dir: &Path,
    full: &RunSet,
    report: &TriangleReport,
) -> anyhow::Result<Vec<PathBuf>> {
    let out = OutputDir::claim(dir, TRIANGLE_FILES)?;
    write_triangle_set(out.staging(), full, report)?;
    Ok(out.commit()?)
}
