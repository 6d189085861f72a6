//! Corrections from measured end points (a real robot's, or the thesis'),
//! in the layouts of fixtures/thesis-data/*_endpoints.csv.

use std::path::Path;

use calib::csv::{read_triangle_file, read_umbmark_file, CsvOptions, TRIANGLE_HEADER};
use calib::{
    triangle_correction, umbmark_correction, Discrepancy, Frame, Mode, TriangleParams,
    TriangleResult, UmbmarkParams, UmbmarkResult,
};
use serde::Serialize;

/// Which test a table holds, from its header.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    Umbmark,
    Triangle,
}

/// How to read and compute.
#[derive(Debug, Clone)]
pub struct FromCsv {
    pub experiment: u32,
    pub thesis_compat: bool,
    /// None: the default frame, or in compat mode the frame the thesis' GUI used.
    pub frame: Option<Frame>,
    /// Side of the square / length of the line, cm (None: 200, the thesis' L).
    pub side_cm: Option<f64>,
    /// Wheelbase the robot's odometry used, mm (None: the thesis' value for the
    /// experiment in compat mode, else `calib::HENRYTWO_WHEELBASE_MM`, 130).
    pub wheelbase_mm: Option<f64>,
    /// The error model's solution (ignored in compat mode: the GUI is first order).
    pub solution: calib::Solution,
    /// Runs per direction (UMBmark) or per test (Triangular Path) in the table.
    pub runs_per_group: usize,
}

impl FromCsv {
    /// How to read the table of a test with legs of `side_cm`: no end error
    /// may be larger than the leg.
    fn csv_options(&self, side_cm: f64, triangle_y_optional: bool) -> CsvOptions {
        CsvOptions {
            runs_per_group: self.runs_per_group,
            triangle_y_optional,
            max_end_error_cm: side_cm,
        }
    }
}

/// A table's error as the command line's user meets it: a wrong run count
/// says which option expects another.
fn cli_words(e: calib::Error) -> anyhow::Error {
    match e {
        calib::Error::RunCount {
            line,
            experiment,
            group,
            found,
            expected,
        } => anyhow::anyhow!(
            "line {line}: experiment {experiment}, {group} has {found} runs, expected \
             {expected}; add the missing runs or remove the extra ones, or give \
             --runs-per-group {found}"
        ),
        e => e.into(),
    }
}

#[derive(Debug, Clone, Serialize)]
pub struct RunPoint {
    pub direction: String,
    pub run: usize,
    pub x_cm: f64,
    pub y_cm: Option<f64>,
}

/// The result, JSON-ready.
#[derive(Debug, Clone, Serialize)]
#[serde(untagged)]
pub enum Calibration {
    Umbmark {
        method: Method,
        experiment: u32,
        runs: Vec<RunPoint>,
        #[serde(flatten)]
        result: Box<UmbmarkResult>,
        /// In the correct mode: each thesis GUI formula that differs, and by how much.
        thesis_discrepancies: Vec<Discrepancy>,
    },
    Triangle {
        method: Method,
        experiment: u32,
        runs: Vec<RunPoint>,
        #[serde(flatten)]
        result: Box<TriangleResult>,
        thesis_discrepancies: Vec<Discrepancy>,
        notes: Vec<String>,
    },
}

/// Detect the table's layout from its header line.
pub fn detect(path: &Path) -> anyhow::Result<Method> {
    let text = input_file::read_text(path)
        .map_err(|e| anyhow::anyhow!("cannot read {}: {e}", path.display()))?;
    let header = text
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty() && !l.starts_with('#'))
        .unwrap_or("");
    Ok(if header.replace(' ', "") == TRIANGLE_HEADER {
        Method::Triangle
    } else {
        Method::Umbmark
    })
}

pub fn from_csv(path: &Path, method: Method, opts: &FromCsv) -> anyhow::Result<Calibration> {
    let mode = if opts.thesis_compat {
        Mode::ThesisCompat
    } else {
        Mode::Correct
    };
    match method {
        Method::Umbmark => {
            let mut params = if opts.thesis_compat {
                calib::thesis::umbmark_params_for_experiment(opts.experiment)
                    .unwrap_or_else(calib::thesis::umbmark_params_as_printed)
            } else {
                UmbmarkParams::default()
            };
            params.mode = mode;
            params.solution = opts.solution;
            if let Some(f) = opts.frame {
                params.frame = f;
            }
            if let Some(l) = opts.side_cm {
                params.side_cm = l;
            }
            // Else calib's default (Henrytwo's 130 mm), or the thesis' in compat mode.
            if let Some(b) = opts.wheelbase_mm {
                params.wheelbase_mm = b;
            }
            let csv_opts = opts.csv_options(params.side_cm, false);
            let runs = read_umbmark_file(path, opts.experiment, &csv_opts).map_err(cli_words)?;
            let result = umbmark_correction(&runs, &params);
            let discrepancies = if opts.thesis_compat {
                Vec::new()
            } else {
                calib::thesis::umbmark_discrepancies(&runs, &params)
            };
            let mut points = Vec::new();
            for (dir, list) in [("cw", runs.cw()), ("ccw", runs.ccw())] {
                for (i, p) in list.iter().enumerate() {
                    points.push(RunPoint {
                        direction: dir.into(),
                        run: i + 1,
                        x_cm: p.x_cm,
                        y_cm: Some(p.y_cm),
                    });
                }
            }
            Ok(Calibration::Umbmark {
                method,
                experiment: opts.experiment,
                runs: points,
                result: Box::new(result),
                thesis_discrepancies: discrepancies,
            })
        }
        Method::Triangle => {
            let mut params = if opts.thesis_compat {
                calib::thesis::triangle_params_for_experiment(opts.experiment)
                    .unwrap_or_else(calib::thesis::triangle_params_as_printed)
            } else {
                TriangleParams::default()
            };
            params.mode = mode;
            params.solution = opts.solution;
            if let Some(f) = opts.frame {
                params.frame = f;
            }
            if let Some(l) = opts.side_cm {
                params.side_cm = l;
            }
            if let Some(b) = opts.wheelbase_mm {
                params.wheelbase_mm = b;
            }
            let csv_opts = opts.csv_options(params.side_cm, true);
            let exp = read_triangle_file(path, opts.experiment, &csv_opts).map_err(cli_words)?;
            let result = triangle_correction(&exp.line, &exp.triangle, &params);
            let discrepancies = if opts.thesis_compat {
                Vec::new()
            } else {
                calib::thesis::triangle_discrepancies(&exp.line, &exp.triangle, &params)
            };
            let mut points = Vec::new();
            for (i, p) in exp.line.runs().iter().enumerate() {
                points.push(RunPoint {
                    direction: "line".into(),
                    run: i + 1,
                    x_cm: p.x_cm,
                    y_cm: Some(p.y_cm),
                });
            }
            for (i, p) in exp.triangle.runs().iter().enumerate() {
                points.push(RunPoint {
                    direction: "triangle".into(),
                    run: i + 1,
                    x_cm: p.x_cm,
                    y_cm: p.y_cm,
                });
            }
            Ok(Calibration::Triangle {
                method,
                experiment: opts.experiment,
                runs: points,
                result: Box::new(result),
                thesis_discrepancies: discrepancies,
                notes: exp.notes,
            })
        }
    }
}

impl Calibration {
    pub fn render(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let disc = match self {
            Calibration::Umbmark {
                experiment,
                runs,
                result: r,
                thesis_discrepancies,
                ..
            } => {
                let _ = writeln!(
                    s,
                    "UMBmark, experiment {experiment}, {} mode, {:?} frame, L = {} cm, b = {} mm",
                    mode_name(r.mode),
                    r.frame,
                    r.side_cm,
                    r.wheelbase_nominal_mm
                );
                for p in runs {
                    let _ = writeln!(
                        s,
                        "  {:<4} {}: x {:8.2} cm, y {:8.2} cm",
                        p.direction,
                        p.run,
                        p.x_cm,
                        p.y_cm.unwrap_or(f64::NAN)
                    );
                }
                let _ = writeln!(
                    s,
                    "  centroids CW ({:.2}, {:.2}) CCW ({:.2}, {:.2}) cm; r_cg CW {:.2}, CCW {:.2}, E_max {:.2} cm",
                    r.centroid_cw.x_cm,
                    r.centroid_cw.y_cm,
                    r.centroid_ccw.x_cm,
                    r.centroid_ccw.y_cm,
                    r.r_cg_cw_cm,
                    r.r_cg_ccw_cm,
                    r.e_max_cm
                );
                let _ = writeln!(
                    s,
                    "  alpha {:.4} deg, beta {:.4} deg, Ed {:.6}, Eb {:.6}",
                    r.alpha_deg, r.beta_deg, r.ed, r.eb
                );
                let _ = writeln!(
                    s,
                    "  cL {:.6}, cR {:.6}, wheelbase {:.2} mm",
                    r.cl, r.cr, r.wheelbase_mm
                );
                for w in &r.warnings {
                    let _ = writeln!(s, "  warning: {w}");
                }
                thesis_discrepancies
            }
            Calibration::Triangle {
                experiment,
                result: r,
                thesis_discrepancies,
                notes,
                ..
            } => {
                let _ = writeln!(
                    s,
                    "Triangular Path, experiment {experiment}, {} mode, L = {} cm, b = {} mm",
                    mode_name(r.mode),
                    r.side_cm,
                    r.wheelbase_nominal_mm
                );
                let _ = writeln!(
                    s,
                    "  line centroid ({:.2}, {:.2}) cm; triangle centroid ({:.2}, {}) cm",
                    r.line_centroid.x_cm,
                    r.line_centroid.y_cm,
                    r.triangle_centroid.x_cm,
                    r.triangle_centroid
                        .y_cm
                        .map_or("unknown".to_string(), |y| format!("{y:.2}"))
                );
                let _ = writeln!(
                    s,
                    "  beta {:.4} deg, Ed {:.6}, cL {:.6}, cR {:.6}; alpha {:.4} deg, Eb {:.6}, wheelbase {:.2} mm",
                    r.beta_deg, r.ed, r.cl, r.cr, r.alpha_deg, r.eb, r.wheelbase_mm
                );
                for n in notes {
                    let _ = writeln!(s, "  note: {n}");
                }
                thesis_discrepancies
            }
        };
        if !disc.is_empty() {
            let _ = writeln!(s, "  thesis GUI formulas that differ:");
            for d in disc {
                let _ = writeln!(
                    s,
                    "    {}: thesis {:.6}, correct {:.6} ({})",
                    d.formula, d.thesis_value, d.correct_value, d.note
                );
            }
        }
        s
    }
}

fn mode_name(m: Mode) -> &'static str {
    match m {
        Mode::Correct => "correct",
        Mode::ThesisCompat => "thesis-compat",
    }
}
