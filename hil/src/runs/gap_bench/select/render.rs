//! The bench-backed diagnosis' report as text, and the figures it is read by.

use super::{BenchCandidate, BenchDiagnosis};

impl BenchDiagnosis {
    /// The winner's candidate.
    pub fn winner_candidate(&self) -> Option<&BenchCandidate> {
        let (name, _) = self.winner.as_ref()?;
        self.candidates.iter().find(|c| c.effect == *name)
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
            "  cross-validation: leave one {} out ({})",
            self.fold_by,
            self.folds.join(", ")
        );
        let _ = writeln!(
            s,
            "  {:<3} {:<22} {:>12} {:>10} {:>10} {:>10}  source",
            "#", "effect", "value", "train χ²", "CV χ²", "held sys"
        );
        for (i, c) in self.candidates.iter().enumerate() {
            let _ = writeln!(
                s,
                "  {:<3} {:<22} {:>8.4} {:<3} {:>10.1} {:>10} {:>8.2}cm  {}",
                i + 1,
                c.effect,
                c.value,
                c.unit,
                c.train_chi2,
                c.cv_chi2.map_or("-".to_owned(), |v| format!("{v:.1}")),
                c.heldout_systematic_cm,
                c.source
            );
        }
        self.render_series(&mut s);
        match &self.winner {
            Some((name, v)) => {
                let unit = self.winner_candidate().map_or("", |c| c.unit.as_str());
                let same = self
                    .winner_equivalent
                    .as_ref()
                    .map_or(String::new(), |(other, w)| {
                        format!(" (in this plant the same robot as {other} = {w:.4})")
                    });
                let _ = writeln!(s, "  winner: {name} = {v:.4} {unit}{same}");
            }
            None => {
                let _ = writeln!(s, "  winner: none (the nominal bench robot)");
            }
        }
        let _ = writeln!(
            s,
            "  held out: systematic gap {:.2} cm before, {:.2} cm after; beyond the centroids' \
             sampling error {:.2} cm before, {:.2} cm after ({}){}",
            self.heldout_before.systematic_cm,
            self.heldout_after.systematic_cm,
            self.heldout_before.systematic_excess_cm,
            self.heldout_after.systematic_excess_cm,
            self.heldout_cut()
                .map_or("nothing beyond the noise to cut".to_owned(), |c| {
                    format!("{:+.0} %", -100.0 * c)
                }),
            self.heldout_after_range_cm
                .map_or(String::new(), |(lo, hi)| format!(
                    "; {lo:.2} to {hi:.2} cm with the candidates alike to the winner ({})",
                    self.alike.join(", ")
                ))
        );
        for n in &self.notes {
            let _ = writeln!(s, "  note: {n}");
        }
        let _ = writeln!(s, "  {} bench runs", self.bench_runs);
        s
    }
}
