//! The telemetry's part of the bench-backed diagnosis (see the parent's docs): the series
//! score of the training groups under one set of parameters, its place in a candidate's
//! search, and its lines in the report.

use gap::data::{Group, TrainSet};
use gap::fit::FitOptions;
use gap::{EffectParams, GapError, Scorer};

use super::super::series::SeriesScore;
use super::super::Batched;
use super::{BenchDiagnosis, Search, SelectOptions};

/// Whether the diagnosis scores telemetry: asked for, and a training group has some.
pub(super) fn scores_series(train: &TrainSet, opts: &SelectOptions) -> bool {
    opts.series && train.groups().iter().any(|g| g.telemetry.is_some())
}

/// The training groups' series under one set of parameters.
#[derive(Debug, Clone)]
pub(super) struct SeriesTotal {
    /// The series' deviance ([`SeriesScore::deviance`]: χ² and the spread's term), summed.
    pub(super) chi2: f64,
    pub(super) rms_rpm: f64,
    pub(super) residuals: usize,
    /// The deviance of every training group (0 without telemetry).
    pub(super) per_group: Vec<f64>,
    /// The score of every group with telemetry.
    pub(super) gaps: Vec<SeriesScore>,
}

/// The series of every training group with telemetry under `params`, each against the
/// bench's run of that group's centroid (None: this batch records no series).
pub(super) fn series_total(
    batched: &Batched,
    train: &TrainSet,
    fit: &FitOptions,
    params: &EffectParams,
) -> Result<Option<SeriesTotal>, GapError> {
    if !batched.records_series() {
        return Ok(None);
    }
    let sc = Scorer::new(batched, train, fit);
    let mut t = SeriesTotal {
        chi2: 0.0,
        rms_rpm: 0.0,
        residuals: 0,
        per_group: Vec::new(),
        gaps: Vec::new(),
    };
    let (mut sq, mut n) = (0.0, 0usize);
    for g in train.groups() {
        let Some(real) = &g.telemetry else {
            t.per_group.push(0.0);
            continue;
        };
        let sim = batched
            .series(params, &sc.centroid_experiment(g))
            .ok_or_else(|| GapError::Fit(format!("{}: the bench recorded no series", g.id)))?;
        // A robot's log holds what its firmware measured: the bench's counted speeds are
        // the like of it (an encoder that loses counts makes a wheel turn faster than its
        // log says, on the robot as on the bench).
        let counted: Vec<_> = sim.into_iter().map(|r| r.counted).collect();
        let s = super::super::series_chi2_of_runs(&g.id.to_string(), real, &counted)?;
        t.chi2 += s.deviance();
        t.residuals += s.residuals;
        sq += s.rms_rpm.powi(2) * (2 * s.gap.n) as f64;
        n += 2 * s.gap.n;
        t.per_group.push(s.deviance());
        t.gaps.push(s);
    }
    t.rms_rpm = (sq / n.max(1) as f64).sqrt();
    Ok(Some(t))
}

/// The series deviance of one training group under `params`, and its residuals (each
/// segment kind's [`super::super::SegmentFit::z`], whose squares are the deviance's χ²):
/// (0, none) when the group has no telemetry, or this batch records none. Its runs were
/// made with its centroid.
pub(super) fn group_series(
    batched: &Batched,
    train: &TrainSet,
    fit: &FitOptions,
    params: &EffectParams,
    g: &Group,
) -> Result<(f64, Vec<f64>), GapError> {
    let Some(real) = &g.telemetry else {
        return Ok((0.0, Vec::new()));
    };
    if !batched.records_series() {
        return Ok((0.0, Vec::new()));
    }
    let sc = Scorer::new(batched, train, fit);
    let sim = batched
        .series(params, &sc.centroid_experiment(g))
        .ok_or_else(|| GapError::Fit(format!("{}: the bench recorded no series", g.id)))?;
    let counted: Vec<_> = sim.into_iter().map(|r| r.counted).collect();
    let s = super::super::series_chi2_of_runs(&g.id.to_string(), real, &counted)?;
    let z = s.segments.iter().flat_map(|f| f.z).collect();
    Ok((s.deviance(), z))
}

impl Search<'_> {
    /// Every training group's series χ² at each of `values` (their runs made by
    /// [`Search::eval`], which recorded the series).
    pub(super) fn eval_series(&mut self, values: &[f64]) -> Result<(), GapError> {
        for &v in values {
            if let Some(t) = series_total(self.batched, self.train, self.fit, &self.params(v))? {
                self.series.insert(v.to_bits(), t.per_group);
            }
        }
        Ok(())
    }

    /// The series χ² over the groups `keep` selects at `v` (None: no telemetry scored).
    pub(super) fn series_at(&self, v: f64, keep: &dyn Fn(&Group) -> bool) -> Option<f64> {
        let c = self.series.get(&v.to_bits())?;
        Some(
            self.train
                .groups()
                .iter()
                .zip(c)
                .filter(|(g, _)| keep(g))
                .map(|(_, x)| x)
                .sum(),
        )
    }

    /// The end points' χ² and the series' at `v`, over every training group.
    pub(super) fn parts(&self, v: f64) -> (f64, Option<f64>) {
        let ends = self.seen[&v.to_bits()].iter().sum();
        (ends, self.series_at(v, &|_| true))
    }
}

impl BenchDiagnosis {
    /// The telemetry's part of [`BenchDiagnosis::render`] (nothing without telemetry).
    pub(super) fn render_series(&self, s: &mut String) {
        use std::fmt::Write;
        let (Some(chi2), Some(rms)) = (self.nominal_series_chi2, self.nominal_series_rms_rpm)
        else {
            return;
        };
        let _ = writeln!(
            s,
            "  series: {} residuals (segment × wheel × speed, duty of each training group with telemetry), \
             scored as χ² + Σ ln(v/v₀) for the variance the bench runs' spread adds; \
             nominal bench robot {chi2:.1}, RMS {rms:.2} RPM",
            self.series_residuals
        );
        for (i, c) in self.candidates.iter().enumerate() {
            let _ = writeln!(
                s,
                "  {:<3} {:<22} series χ² {:>10} RMS {:>6} RPM  total {:.1}",
                i + 1,
                c.effect,
                c.series_chi2.map_or("-".to_owned(), |v| format!("{v:.1}")),
                c.series_rms_rpm
                    .map_or("-".to_owned(), |v| format!("{v:.2}")),
                c.train_score()
            );
        }
        let _ = writeln!(
            s,
            "  {}'s series by segment (mean real − bench: speed, thesis RPM; duty, of 255):",
            self.winner
                .as_ref()
                .map_or("the nominal robot", |w| w.0.as_str())
        );
        for g in &self.series {
            for seg in &g.segments {
                let _ = writeln!(
                    s,
                    "    {:<22} {:<11} n {:>4}  speed L {:+6.2} R {:+6.2}  duty L {:+6.1} R {:+6.1}",
                    g.label,
                    serde_json::to_string(&seg.segment)
                        .unwrap_or_default()
                        .trim_matches('"'),
                    seg.n,
                    seg.bias_rpm[0],
                    seg.bias_rpm[1],
                    seg.bias_pwm[0],
                    seg.bias_pwm[1]
                );
            }
        }
    }
}
