//! One candidate's bounded 1-D search on the bench: a grid over the effect's range (its
//! neutral value a point of it), then golden-section steps between the best point's
//! neighbours, every value's training χ² per group kept so the cross-validation's folds
//! reuse the whole fit's evaluations.

use std::collections::BTreeMap;

use gap::data::{Group, TrainSet};
use gap::fit::FitOptions;
use gap::{EffectParams, GapError, ParamSpec, Scorer};

use super::chi2;
use crate::runs::gap_bench::Batched;

/// The values of one candidate's search, each with every training group's χ².
pub(super) struct Search<'a> {
    pub(super) batched: &'a Batched<'a>,
    pub(super) train: &'a TrainSet,
    pub(super) fit: &'a FitOptions,
    pub(super) spec: ParamSpec,
    /// value (bits) -> χ² per training group.
    pub(super) seen: BTreeMap<u64, Vec<f64>>,
    /// value (bits) -> series χ² per training group (empty: no telemetry scored).
    pub(super) series: BTreeMap<u64, Vec<f64>>,
}

impl<'a> Search<'a> {
    pub(super) fn params(&self, v: f64) -> EffectParams {
        EffectParams::new().with(&self.spec.name, v)
    }

    /// Every training group's χ² at each of `values`, in one batch.
    pub(super) fn eval(&mut self, values: &[f64]) -> Result<(), GapError> {
        let todo: Vec<f64> = values
            .iter()
            .copied()
            .filter(|v| !self.seen.contains_key(&v.to_bits()))
            .collect();
        if todo.is_empty() {
            return Ok(());
        }
        let groups = self.train.groups();
        let got = self.batched.eval(|m| -> Result<Vec<Vec<f64>>, GapError> {
            let sc = Scorer::new(m, self.train, self.fit);
            todo.iter()
                .map(|&v| {
                    groups
                        .iter()
                        .map(|g| Ok(chi2(&sc.centroid_residuals(&self.params(v), g)?)))
                        .collect()
                })
                .collect()
        })?;
        for (v, c) in todo.iter().zip(got) {
            self.seen.insert(v.to_bits(), c);
        }
        self.eval_series(&todo)
    }

    /// χ² over the groups `keep` selects at `v` (evaluated before).
    pub(super) fn at(&self, v: f64, keep: &dyn Fn(&Group) -> bool) -> f64 {
        let c = &self.seen[&v.to_bits()];
        let ends = self
            .train
            .groups()
            .iter()
            .zip(c)
            .filter(|(g, _)| keep(g))
            .map(|(_, x)| x)
            .sum();
        self.series_at(v, keep).map_or(ends, |s| ends + s)
    }

    /// [`Search::at`], or infinity for a value not evaluated.
    pub(super) fn at_or_inf(&self, v: f64, keep: &dyn Fn(&Group) -> bool) -> f64 {
        if self.seen.contains_key(&v.to_bits()) {
            self.at(v, keep)
        } else {
            f64::INFINITY
        }
    }

    /// Every value evaluated so far, in order.
    pub(super) fn evaluated(&self) -> Vec<f64> {
        let mut v: Vec<f64> = self.seen.keys().map(|&b| f64::from_bits(b)).collect();
        v.sort_by(f64::total_cmp);
        v
    }

    /// The best value for the groups `keep` selects: the best grid point, then `steps` of
    /// golden section between its neighbours. Returns (value, χ²).
    pub(super) fn fit(
        &mut self,
        grid: &[f64],
        steps: usize,
        keep: &dyn Fn(&Group) -> bool,
    ) -> Result<(f64, f64), GapError> {
        let best = (0..grid.len())
            .min_by(|&a, &b| self.at(grid[a], keep).total_cmp(&self.at(grid[b], keep)))
            .expect("a grid has points");
        let (mut a, mut b) = (
            grid[best.saturating_sub(1)],
            grid[(best + 1).min(grid.len() - 1)],
        );
        let mut found = (grid[best], self.at(grid[best], keep));
        let r = (5f64.sqrt() - 1.0) / 2.0;
        let (mut c, mut d) = (b - r * (b - a), a + r * (b - a));
        if steps > 0 {
            self.eval(&[c, d])?;
        }
        let (mut fc, mut fd) = (self.at_or_inf(c, keep), self.at_or_inf(d, keep));
        // Each step keeps one of the two inner points: one new bench evaluation per step.
        for step in 0..steps {
            for (v, f) in [(c, fc), (d, fd)] {
                if f < found.1 {
                    found = (v, f);
                }
            }
            if step + 1 == steps {
                break;
            }
            if fc < fd {
                (b, d, fd) = (d, c, fc);
                c = b - r * (b - a);
                self.eval(&[c])?;
                fc = self.at(c, keep);
            } else {
                (a, c, fc) = (c, d, fd);
                d = a + r * (b - a);
                self.eval(&[d])?;
                fd = self.at(d, keep);
            }
        }
        Ok(found)
    }
}

/// `n` points over `spec`'s range (at least 3), with its neutral value, in order, each
/// once.
pub(super) fn grid(s: &ParamSpec, n: usize) -> Vec<f64> {
    let n = n.max(3);
    // A point that rounding put a hair beside the neutral value is the neutral value:
    // two points with one answer would leave the search a bracket on one side of it.
    let tie = 1e-9 * (s.upper - s.lower);
    let mut g: Vec<f64> = (0..n)
        .map(|i| {
            let v =
                (s.lower + (s.upper - s.lower) * i as f64 / (n - 1) as f64).clamp(s.lower, s.upper);
            if (v - s.neutral).abs() <= tie {
                s.neutral
            } else {
                v
            }
        })
        .collect();
    if !g.contains(&s.neutral) {
        g.push(s.neutral);
    }
    g.sort_by(f64::total_cmp);
    g.dedup();
    g
}

#[cfg(test)]
mod tests {
    use super::grid;
    use crate::runs::gap_bench::bench_parameters;

    /// Every parameter's grid holds its neutral value once, each point once, in order, none a
    /// hair beside another: the middle point of a signed range computed as `-0.2 + 0.4 · 3/6`
    /// is 2.8e-17, not 0, and beside the added neutral value it left the search a bracket on
    /// the positive side only. With an odd number of points over a range centred on the
    /// neutral value, the neutral value has neighbours on both sides.
    #[test]
    fn each_grid_holds_the_neutral_value_once_with_neighbours_on_both_sides() {
        for s in bench_parameters() {
            for n in [3, 5, 7, 9] {
                let g = grid(&s, n);
                let range = s.upper - s.lower;
                assert_eq!(
                    g.iter().filter(|&&v| v == s.neutral).count(),
                    1,
                    "{} {g:?}",
                    s.name
                );
                assert!(
                    g.windows(2).all(|w| w[1] - w[0] > 1e-6 * range),
                    "{}: {g:?}",
                    s.name
                );
                assert!(g.first() == Some(&s.lower) && g.last() == Some(&s.upper));
                if (s.upper - s.neutral - (s.neutral - s.lower)).abs() < 1e-12 {
                    let at = g.iter().position(|&v| v == s.neutral).unwrap();
                    assert!(at > 0 && at + 1 < g.len(), "{}: {g:?}", s.name);
                    assert_eq!(g.len(), n, "{}: {g:?}", s.name);
                }
            }
        }
    }
}
