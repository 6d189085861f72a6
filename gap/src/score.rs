//! [`Scorer`]: the diagnosis' own measures of a model on groups, for searches that live
//! outside this crate (the bench-backed diagnosis runs its own bounded 1-D fits and its
//! cross-validation, but must score exactly as [`crate::diagnose()`] does).

use crate::data::{Group, TrainSet};
use crate::effects::EffectParams;
use crate::fit::{Evaluator, FitOptions, Gap};
use crate::model::Model;
use crate::GapError;

/// Scores a model's predictions against measured groups, weighted by the pooled scatter of
/// a training set (the weights [`crate::diagnose()`] uses).
pub struct Scorer<'a> {
    ev: Evaluator<'a>,
}

impl<'a> Scorer<'a> {
    /// Weighted by the scatter of `train`.
    pub fn new(model: &'a dyn Model, train: &TrainSet, opts: &FitOptions) -> Self {
        Scorer {
            ev: Evaluator::new(model, train, opts),
        }
    }

    /// The weighted centroid residuals (x, and y when recorded) of `group` under `params`:
    /// real − model over the centroid's standard error (the pooled within-group scatter of
    /// the group's test over √n, with the floor). Their squares sum to the group's χ².
    pub fn centroid_residuals(
        &self,
        params: &EffectParams,
        group: &Group,
    ) -> Result<Vec<f64>, GapError> {
        let p = self.ev.predict(params, group)?;
        Ok(self.ev.centroid_part(&p, &group.stats(), group.id.test))
    }

    /// The experiment of the runs `group`'s centroid is predicted from (its seed made from
    /// the group's name; [`crate::FitOptions::centroid_runs`] runs): run 0's telemetry goes
    /// with that centroid.
    pub fn centroid_experiment(&self, group: &Group) -> crate::model::Experiment {
        self.ev
            .centroid_experiment(&group.experiment, &group.id.to_string())
    }

    /// All weighted residuals of `groups` (centroids and spreads), as the fits use them.
    pub fn residuals(&self, params: &EffectParams, groups: &[Group]) -> Result<Vec<f64>, GapError> {
        self.ev.residuals(params, groups)
    }

    /// The gap in cm of `groups` under `params`.
    pub fn gap(&self, params: &EffectParams, groups: &[Group]) -> Result<Gap, GapError> {
        self.ev.gap(params, groups)
    }
}
