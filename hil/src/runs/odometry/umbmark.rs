//! The reduced UMBmark's result: Borenstein's correction from a complete run
//! set, the thesis-style table, its Markdown and the plots.

use std::path::{Path, PathBuf};

use calib::{Direction, UmbmarkParams, UmbmarkResult, UmbmarkRuns};

use super::plan::Plan;
use super::runs::{RunRow, RunSet};
use super::ExperimentError;
use crate::output::OutputDir;

/// The experiment's result: the runs' end errors and Borenstein's correction.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Report {
    pub plan: Plan,
    pub runs: Vec<RunRow>,
    #[serde(flatten)]
    pub result: UmbmarkResult,
    pub robot_time_s: f64,
}

/// The CW and CCW end points of a complete UMBmark run set.
fn umbmark_runs(full: &RunSet) -> Result<UmbmarkRuns, calib::Error> {
    let (cw, ccw) = full.endpoints();
    UmbmarkRuns::new(cw, ccw)
}

/// Borenstein's correction from a complete set of runs.
pub fn report(
    full: &RunSet,
    wheelbase_mm: f64,
    solution: calib::Solution,
) -> Result<Report, ExperimentError> {
    let runs = umbmark_runs(full)?;
    let params = UmbmarkParams {
        side_cm: full.plan.leg_mm / 10.0,
        wheelbase_mm,
        solution,
        ..UmbmarkParams::default()
    };
    let mut result = calib::umbmark_correction(&runs, &params);
    result.warnings.extend(full.warnings());
    Ok(Report {
        plan: full.plan.clone(),
        runs: full.rows([Direction::Cw.as_str(), Direction::Ccw.as_str()]),
        result,
        robot_time_s: full.robot_time_s(),
    })
}

impl Report {
    /// The thesis-style table and the correction.
    pub fn render(&self) -> String {
        use std::fmt::Write;
        let r = &self.result;
        let mut s = String::new();
        let _ = writeln!(
            s,
            "Reduced UMBmark, L = {:.0} mm, {} runs per direction ({}, seed {})",
            self.plan.leg_mm, self.plan.runs_per_direction, self.plan.firmware, self.plan.seed
        );
        let _ = writeln!(
            s,
            "  end errors (cm; x along the first leg, y to the left):"
        );
        let _ = writeln!(s, "    run |     CW x     CW y |    CCW x    CCW y");
        let n = self.plan.runs_per_direction;
        for i in 0..n {
            let cw = &self.runs[i];
            let ccw = &self.runs[n + i];
            let _ = writeln!(
                s,
                "    {:>3} | {:8.2} {:8.2} | {:8.2} {:8.2}{}",
                i + 1,
                cw.x_cm,
                cw.y_cm,
                ccw.x_cm,
                ccw.y_cm,
                if cw.completed && ccw.completed {
                    ""
                } else {
                    "  (incomplete run)"
                }
            );
        }
        let _ = writeln!(
            s,
            "    c.g.| {:8.2} {:8.2} | {:8.2} {:8.2}",
            r.centroid_cw.x_cm, r.centroid_cw.y_cm, r.centroid_ccw.x_cm, r.centroid_ccw.y_cm
        );
        let _ = writeln!(
            s,
            "  r_cg CW {:.2} cm, r_cg CCW {:.2} cm, E_max,syst {:.2} cm",
            r.r_cg_cw_cm, r.r_cg_ccw_cm, r.e_max_cm
        );
        let _ = writeln!(
            s,
            "  alpha {:+.4} deg (from y {:+.4}), beta {:+.4} deg (from y {:+.4})",
            r.alpha_deg, r.alpha_y_deg, r.beta_deg, r.beta_y_deg
        );
        let _ = writeln!(
            s,
            "  R {}, Ed {:.5}, Eb {:.5}",
            r.radius_cm
                .map_or("infinite".to_string(), |v| format!("{v:.1} cm")),
            r.ed,
            r.eb
        );
        let _ = writeln!(
            s,
            "  correction: cL {:.5}, cR {:.5}, wheelbase {:.2} mm (was {:.2} mm)",
            r.cl, r.cr, r.wheelbase_mm, r.wheelbase_nominal_mm
        );
        for w in &r.warnings {
            let _ = writeln!(s, "  warning: {w}");
        }
        let _ = writeln!(s, "  robot time {:.1} s in all", self.robot_time_s);
        s
    }

    /// The report as Markdown, with the plots next to it.
    pub fn markdown(&self) -> String {
        format!(
            "# Reduced UMBmark on the emulated robot\n\n\
             Firmware `{}` ({}), L = {:.0} mm, seed {} (run seeds derived from it).\n\n\
             ```text\n{}```\n\n\
             ![end errors](umbmark.svg)\n\n![trajectories](trajectories.svg)\n",
            self.plan.firmware,
            self.plan.firmware_hash,
            self.plan.leg_mm,
            self.plan.seed,
            self.render()
        )
    }
}

/// The files of a UMBmark's `--out` folder, all of them and nothing else.
pub const UMBMARK_FILES: &[&str] = &[
    "umbmark.svg",
    "umbmark.png",
    "trajectories.svg",
    "trajectories.png",
    "report.json",
    "report.md",
];

/// Write the report, its Markdown rendering and the plots ([`UMBMARK_FILES`])
/// into `dir`, a folder of their own that [`OutputDir::commit`] puts in
/// place as a whole.
pub fn write_set(dir: &Path, full: &RunSet, report: &Report) -> anyhow::Result<()> {
    let runs = umbmark_runs(full)?;
    calib::plot_umbmark(
        &report.result,
        &runs,
        dir.join("umbmark.svg"),
        dir.join("umbmark.png"),
    )?;
    // The title in the axes' unit; the squares the runs were commanded to drive.
    let side_cm = full.plan.leg_mm / 10.0;
    let square = |turn_deg: f64| calib::plot::IdealPath {
        label: format!("ideal squares, L = {side_cm} cm"),
        points: calib::plot::ideal_path(4, turn_deg, side_cm),
    };
    calib::plot::plot_trajectories(
        &format!("UMBmark trajectories, L = {side_cm} cm"),
        &[square(-90.0), square(90.0)],
        &full.paths(["clockwise", "counter-clockwise"]),
        dir.join("trajectories.svg"),
        dir.join("trajectories.png"),
    )?;
    std::fs::write(
        dir.join("report.json"),
        serde_json::to_string_pretty(report)?,
    )?;
    std::fs::write(dir.join("report.md"), report.markdown())?;
    Ok(())
}

/// Replace the folder `dir` by the report, its Markdown rendering and the
/// plots, as a whole (see [`OutputDir`]); the paths written. A caller that
/// runs the experiment first claims the folder before it runs instead.
pub fn write_outputs(dir: &Path, full: &RunSet, report: &Report) -> anyhow::Result<Vec<PathBuf>> {
    let out = OutputDir::claim(dir, UMBMARK_FILES)?;
    write_set(out.staging(), full, report)?;
    Ok(out.commit()?)
}
