//! What the unit tests build by hand: an experiment on a plain reference robot and a
//! candidate fit that says only which effects it holds.

use crate::effects::EffectParams;
use crate::fit::{CandidateFit, Estimate, Gap};
use crate::model::{Experiment, Firmware, Reference, TestKind};

/// `test` with legs of `leg_mm`, `runs` runs, on a robot of 150 mm wheelbase and 0.2 mm per
/// count with its nominal firmware.
pub(crate) fn experiment(test: TestKind, leg_mm: f64, runs: usize) -> Experiment {
    let reference = Reference {
        wheelbase_mm: 150.0,
        mm_per_count: 0.2,
    };
    Experiment {
        test,
        firmware: Firmware::nominal(&reference, leg_mm),
        reference,
        runs,
        seed: 1,
    }
}

/// A fit of `effects` with nothing else filled in: no estimates, χ² and BIC 0, a
/// condition number of 1 and no correlation matrix.
pub(crate) fn candidate_fit(effects: &[&str]) -> CandidateFit {
    let nothing = Gap {
        systematic_cm: 0.0,
        scatter_cm: 0.0,
        total_cm: 0.0,
        systematic_excess_cm: 0.0,
        scatter_excess_cm: 0.0,
        groups: vec![],
    };
    CandidateFit {
        effects: effects.iter().map(|e| (*e).to_owned()).collect(),
        estimates: vec![],
        k: effects.len(),
        n_residuals: 0,
        chi2: 0.0,
        aic: 0.0,
        bic: 0.0,
        share_explained: 0.0,
        train: nothing,
        heldout: None,
        correlation: None,
        condition_number: 1.0,
        iterations: 0,
        converged: true,
        params: EffectParams::new(),
    }
}

/// An estimate of `name` at `value` with `std_err`, no symbol or unit, not at a bound.
pub(crate) fn estimate(name: &str, value: f64, std_err: Option<f64>) -> Estimate {
    Estimate {
        name: name.to_owned(),
        symbol: String::new(),
        unit: String::new(),
        value,
        std_err,
        bootstrap_sd: None,
        at_bound: false,
    }
}
