//! The bench-backed diagnosis' report as text, and the figures it is read by.

use super::{BenchCandidate, BenchDiagnosis};
use crate::runs::gap_bench::reading::shown;

impl BenchDiagnosis {
    /// The winner's candidate.
    pub fn winner_candidate(&self) -> Option<&BenchCandidate> {
        let (name, _) = self.winner.as_ref()?;
        self.candidates.iter().find(|c| c.effect == *name)
    }

    /// The single candidates fitted away from their neutral value, best first by the score
    /// the choice compares (cross-validated, else training).
    pub fn ranked_singles(&self) -> Vec<&BenchCandidate> {
        let specs = crate::runs::gap_bench::bench_parameters();
        let mut v: Vec<&BenchCandidate> = self
            .candidates
            .iter()
            .filter(|c| {
                specs
                    .iter()
                    .any(|s| s.name == c.effect && s.neutral != c.value)
            })
            .collect();
        let score = |c: &BenchCandidate| c.cv_chi2.unwrap_or(c.train_score());
        v.sort_by(|a, b| score(a).total_cmp(&score(b)));
        v
    }

    /// 1 − held-out systematic gap after / before, both beyond the sampling error of the
    /// centroids (`Gap::systematic_excess_cm`): the share of the systematic gap the model
    /// explains, not of the real centroids' own noise, which no model can. None when the
    /// nominal robot's gap is within that error already (nothing systematic to cut).
    pub fn heldout_cut(&self) -> Option<f64> {
        let (b, a) = (
            self.heldout_before.systematic_excess_cm,
            self.heldout_after.systematic_excess_cm,
        );
        (b > 0.0).then(|| 1.0 - a / b)
    }

    /// The report as text.
    pub fn render(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let _ = writeln!(s, "Bench-backed diagnosis ({}; {})", self.model, self.rule);
        let _ = writeln!(
            s,
            "  nominal bench robot: training χ² {:.1} over {} centroid residuals{}",
            self.nominal_train_chi2,
            self.residuals,
            self.nominal_cv_chi2
                .map_or(String::new(), |c| format!(", cross-validated {c:.1}"))
        );
        let _ = writeln!(
            s,
            "  cross-validation: leave one {} out ({}){}",
            self.fold_by,
            self.folds.join(", "),
            if self.folds_kept_out.is_empty() {
                String::new()
            } else {
                format!(
                    "; never left out: {} (no turn would remain to train on)",
                    self.folds_kept_out.join(", ")
                )
            }
        );
        let _ = writeln!(
            s,
            "  {:<3} {:<22} {:>10} {:>10} {:>10}  value (source)",
            "#", "effect", "train χ²", "CV χ²", "held sys"
        );
        for (i, c) in self.candidates.iter().enumerate() {
            let _ = writeln!(
                s,
                "  {:<3} {:<22} {:>10.1} {:>10} {:>8.2}cm  {} [{}]",
                i + 1,
                c.effect,
                c.train_chi2,
                c.cv_chi2.map_or("-".to_owned(), |v| format!("{v:.1}")),
                c.heldout_systematic_cm,
                shown(&c.effect, c.value, &c.unit, None),
                c.source
            );
        }
        self.render_series(&mut s);
        self.render_joint(&mut s);
        if self.chosen.is_empty() {
            let _ = writeln!(
                s,
                "  no effect taken: the nominal bench robot stays the model ({} single effects{} \
                 tried, each above with how far it got)",
                self.candidates.len(),
                if self.joint.is_empty() {
                    String::new()
                } else {
                    format!(" and {} joint fits", self.joint.len())
                }
            );
            let _ = writeln!(
                s,
                "  held out: systematic gap {:.2} cm with the nominal bench robot ({:.2} cm beyond \
                 the centroids' sampling error)",
                self.heldout_before.systematic_cm, self.heldout_before.systematic_excess_cm
            );
        } else {
            let values: Vec<String> = self
                .chosen
                .iter()
                .map(|c| {
                    format!(
                        "{} = {}",
                        c.effect,
                        shown(&c.effect, c.value, &c.unit, c.std_err)
                    )
                })
                .collect();
            let same = self
                .winner_equivalent
                .as_ref()
                .map_or(String::new(), |(other, w)| {
                    format!(" (in this plant the same robot as {other} = {w:.4})")
                });
            let head = if self.at_noise_level {
                "chosen model"
            } else {
                "best model found, which leaves a residual beyond noise"
            };
            let _ = writeln!(s, "  {head}: {}{same}", values.join("; "));
            let _ = writeln!(
                s,
                "  held out, this model: systematic gap {:.2} cm before, {:.2} cm after; beyond \
                 the centroids' sampling error {:.2} cm before, {:.2} cm after ({})",
                self.heldout_before.systematic_cm,
                self.heldout_after.systematic_cm,
                self.heldout_before.systematic_excess_cm,
                self.heldout_after.systematic_excess_cm,
                self.heldout_cut()
                    .map_or("nothing beyond the noise to cut".to_owned(), |c| {
                        format!("{:+.0} %", -100.0 * c)
                    }),
            );
        }
        for n in &self.notes {
            let _ = writeln!(s, "  note: {n}");
        }
        let _ = writeln!(
            s,
            "  {} bench runs{}",
            self.bench_runs,
            if self.joint_runs > 0 {
                format!(", {} of them for the joint fits", self.joint_runs)
            } else {
                String::new()
            }
        );
        s
    }

    /// The joint fits tried, one line each: their scores, held-out gap and values.
    fn render_joint(&self, s: &mut String) {
        use std::fmt::Write;
        if self.joint.is_empty() {
            return;
        }
        let _ = writeln!(
            s,
            "  joint fits (forward selection; {} bench runs):",
            self.joint_runs
        );
        for j in &self.joint {
            let specs = crate::runs::gap_bench::bench_parameters();
            let values: Vec<String> = j
                .effects
                .iter()
                .zip(&j.values)
                .zip(&j.std_err)
                .map(|((e, &v), &se)| {
                    let unit = specs
                        .iter()
                        .find(|p| p.name == *e)
                        .map_or("", |p| p.unit.as_str());
                    format!("{e} = {}", shown(e, v, unit, se))
                })
                .collect();
            let _ = writeln!(
                s,
                "      {:<40} {:>10.1} {:>10} {:>8.2}cm  {}{} [from the {}; {} runs]",
                j.label(),
                j.train_score(),
                j.cv_chi2.map_or("-".to_owned(), |v| format!("{v:.1}")),
                j.heldout.systematic_cm,
                values.join("; "),
                if j.determined {
                    ""
                } else {
                    " (not determined)"
                },
                j.start,
                j.bench_runs
            );
        }
    }
}
