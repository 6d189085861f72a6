//! Forward selection over the bench's candidates (see `joint.rs`): pairs from the kinematic
//! surrogate, Borenstein's Ed + Eb, and from the best single fits, the best pair taken when
//! it earns its place over the single choice, then a third effect on top of it; the chosen
//! model's numbers replace the single choice's in the report.

use gap::data::{HeldOutSet, TrainSet};
use gap::GapError;

use super::choose::{heldout_worse_note, HELDOUT_WORSE, NO_EXPLANATION};
use super::joint::{earns_place, fit_joint, JointFit};
use super::{BenchDiagnosis, ChosenValue, FitPlan, SelectOptions};
use crate::runs::gap_bench::params::equivalent;
use crate::runs::gap_bench::Batched;

/// Single effects taken two at a time for the pairs, and as third effects.
const SINGLES_FOR_PAIRS: usize = 3;
const THIRDS: usize = 2;

/// Whether two effects are one robot in the plant (turn slip and wheelbase): fitting both
/// at once has no determined answer.
fn same_robot(a: &str, b: &str) -> bool {
    equivalent(a, 0.05).is_some_and(|(o, _)| o == b)
        || equivalent(a, 1.05).is_some_and(|(o, _)| o == b)
}

/// Borenstein's two systematic errors of a differential drive (Ed, the wheels' diameter
/// ratio, and Eb, the wheelbase): the pair the kinematic surrogate suggests for UMBmark
/// data, tried whether or not it ranked it, since each of the two compensates the other in
/// a single fit and neither may rank high alone.
pub(super) const BORENSTEIN_PAIR: [&str; 2] = [
    gap::effects::WHEEL_DIAMETER_RATIO,
    gap::effects::WHEELBASE_RATIO,
];

/// The third effects to try on the taken pair `pair`, with their single fits' values
/// (neutral where not fitted), [`THIRDS`] in all: Borenstein's other error first when the
/// pair holds one of them, then the best ranked single fits not in it. A robot has both of
/// Borenstein's errors, and the other's single fit can stay at neutral, compensated by the
/// pair's: on a robot hiding Ed, Eb and coasting the pair Ed + coast is taken, the wheelbase
/// fitted alone moved nothing, and the ranked singles offered two effects the robot lacks.
fn third_effects(d: &BenchDiagnosis, pair: &[String]) -> Vec<(String, f64)> {
    let outside = |e: &str| !pair.iter().any(|p| p == e || same_robot(p, e));
    let mut out: Vec<(String, f64)> = Vec::new();
    let held = BORENSTEIN_PAIR
        .iter()
        .filter(|e| pair.iter().any(|p| p == *e))
        .count();
    if held == 1 {
        let other = BORENSTEIN_PAIR.iter().find(|e| outside(e)).and_then(|e| {
            let fitted = d
                .candidates
                .iter()
                .find(|c| c.effect == *e)
                .map(|c| c.value);
            let neutral = crate::runs::gap_bench::bench_parameters()
                .into_iter()
                .find(|s| s.name == *e)
                .map(|s| s.neutral);
            Some(((*e).to_owned(), fitted.or(neutral)?))
        });
        out.extend(other);
    }
    for c in d.ranked_singles() {
        if out.len() >= THIRDS {
            break;
        }
        if outside(&c.effect) && !out.iter().any(|(e, _)| *e == c.effect) {
            out.push((c.effect.clone(), c.value));
        }
    }
    out
}

/// One pair to fit: its effects, the starts its fit chooses from (the best on the training
/// data is where Levenberg-Marquardt begins) and where they came from.
pub(super) type PairStart = (Vec<String>, Vec<Vec<f64>>, &'static str);

/// The starts of a pair's fit from the single fits `a` and `b` (None: not fitted alone,
/// taken at neutral): both at their single values, and each at its single value with the
/// other at neutral. A single fit of a robot with two errors compensates the one it lacks,
/// so both at their single values can start far from the truth while one of them alone
/// starts near it.
fn single_starts(a: (f64, Option<f64>), b: (f64, Option<f64>)) -> Vec<Vec<f64>> {
    let mut out: Vec<Vec<f64>> = Vec::new();
    for v in [
        vec![a.1.unwrap_or(a.0), b.1.unwrap_or(b.0)],
        vec![a.1.unwrap_or(a.0), b.0],
        vec![a.0, b.1.unwrap_or(b.0)],
    ] {
        if v != [a.0, b.0] && !out.contains(&v) {
            out.push(v);
        }
    }
    if out.is_empty() {
        out.push(vec![a.0, b.0]);
    }
    out
}

/// The starts of a triple's fit: the pair at its values (`pair`) with the third effect
/// `third` at its single fit's value `single`, at neutral, and at each point of its search
/// grid ([`SelectOptions::grid`]). A single fit of a robot with several errors compensates
/// those it lacks, so its value can be far from the third's own (coasting fitted alone
/// takes the part of a wide wheelbase, whose turns it shortens the other way), and so can
/// neutral; one of the grid's points is near it. All are evaluated in one batch, and the
/// best on the training data begins.
pub fn third_starts(pair: &[f64], third: &str, single: f64, opts: &SelectOptions) -> Vec<Vec<f64>> {
    let Some(spec) = crate::runs::gap_bench::bench_parameters()
        .into_iter()
        .find(|s| s.name == third)
    else {
        return vec![pair.iter().copied().chain([single]).collect()];
    };
    let mut out: Vec<Vec<f64>> = Vec::new();
    for x in [single, spec.neutral]
        .into_iter()
        .chain(super::search::grid(&spec, opts.grid))
    {
        let v: Vec<f64> = pair.iter().copied().chain([x]).collect();
        if !out.contains(&v) {
            out.push(v);
        }
    }
    out
}

/// The pairs to fit: the surrogate's (effects, values) first, then Borenstein's pair
/// ([`BORENSTEIN_PAIR`]), then the best single fits two at a time; each set of effects
/// once, at most `opts.joint_pairs`.
fn pair_starts(
    d: &BenchDiagnosis,
    surrogate: &[(Vec<String>, Vec<f64>)],
    opts: &SelectOptions,
) -> Vec<PairStart> {
    // The surrogate's pairs may hold effects the bench's shortlist left out: it ranks
    // single effects, and a pair's effects can rank low alone (each compensates the other).
    let specs = crate::runs::gap_bench::bench_parameters();
    let spec = |e: &str| {
        specs
            .iter()
            .find(|s| s.name == e && s.kind == gap::effects::ParamKind::Systematic)
    };
    // An effect's neutral value and its single fit's value (None: not fitted alone).
    let single = |e: &str| -> Option<(f64, Option<f64>)> {
        let neutral = spec(e)?.neutral;
        let fitted = d.candidates.iter().find(|c| c.effect == e).map(|c| c.value);
        Some((neutral, fitted))
    };
    let mut out: Vec<PairStart> = Vec::new();
    let mut push = |effects: Vec<String>, starts: Vec<Vec<f64>>, from: &'static str| {
        let mut key = effects.clone();
        key.sort();
        let fresh = !out.iter().any(|(e, _, _)| {
            let mut k = e.clone();
            k.sort();
            k == key
        });
        if fresh && !same_robot(&effects[0], &effects[1]) && out.len() < opts.joint_pairs {
            out.push((effects, starts, from));
        }
    };
    for (effects, values) in surrogate {
        if effects.len() == 2 && effects.iter().all(|e| spec(e).is_some()) {
            let (Some(a), Some(b)) = (single(&effects[0]), single(&effects[1])) else {
                continue;
            };
            let mut starts = vec![values.clone()];
            starts.extend(single_starts(a, b).into_iter().filter(|v| v != values));
            push(effects.clone(), starts, "kinematic surrogate");
        }
    }
    if let (Some(a), Some(b)) = (single(BORENSTEIN_PAIR[0]), single(BORENSTEIN_PAIR[1])) {
        push(
            BORENSTEIN_PAIR.iter().map(|e| (*e).to_owned()).collect(),
            single_starts(a, b),
            "Borenstein's pair",
        );
    }
    let best = d.ranked_singles();
    for i in 0..best.len().min(SINGLES_FOR_PAIRS) {
        for j in i + 1..best.len().min(SINGLES_FOR_PAIRS) {
            let (a, b) = (best[i], best[j]);
            let (Some(sa), Some(sb)) = (single(&a.effect), single(&b.effect)) else {
                continue;
            };
            push(
                vec![a.effect.clone(), b.effect.clone()],
                single_starts(sa, sb),
                "single fits",
            );
        }
    }
    out
}

/// Runs the forward selection and, when a joint model earns its place, makes it the
/// diagnosis' chosen model. `surrogate`: the kinematic diagnosis' fitted sets of effects.
#[allow(clippy::too_many_arguments)]
pub(super) fn forward(
    batched: &Batched,
    plan: &FitPlan,
    train: &TrainSet,
    held: &HeldOutSet,
    opts: &SelectOptions,
    surrogate: &[(Vec<String>, Vec<f64>)],
    d: &mut BenchDiagnosis,
    progress: &dyn Fn(&str),
) -> Result<(), GapError> {
    if opts.max_effects < 2 {
        return Ok(());
    }
    let before = batched.runs();
    // The model so far: the single winner, or the nominal robot.
    let (mut base_train, mut base_score) = match d.winner_candidate() {
        Some(c) => (c.train_score(), c.cv_chi2.unwrap_or(c.train_score())),
        None => {
            let n = d.nominal_train_chi2 + d.nominal_series_chi2.unwrap_or(0.0);
            (n, n)
        }
    };
    let mut chosen: Option<JointFit> = None;
    let mut tried = Vec::new();
    let starts = pair_starts(d, surrogate, opts);
    for (effects, values, from) in &starts {
        let f = fit_joint(batched, plan, train, held, opts, effects, values, from)?;
        progress(&format!(
            "bench: pair {} from the {from}: training χ² {:.1}{} ({} bench runs)",
            f.label(),
            f.train_score(),
            f.cv_chi2
                .map_or(String::new(), |c| format!(", cross-validated {c:.1}")),
            f.bench_runs
        ));
        tried.push(f);
    }
    let best_pair = tried
        .iter()
        .filter(|f| f.determined)
        .min_by(|a, b| a.score().total_cmp(&b.score()))
        .cloned();
    if let Some(p) = best_pair.filter(|p| earns_place(p, base_train, base_score)) {
        (base_train, base_score) = (p.train_score(), p.score());
        if opts.max_effects >= 3 {
            let thirds = third_effects(d, &p.effects);
            let mut best_triple: Option<JointFit> = None;
            for (e, v) in thirds {
                let effects: Vec<String> = p.effects.iter().cloned().chain([e.clone()]).collect();
                let values = third_starts(&p.values, &e, v, opts);
                let f = fit_joint(
                    batched,
                    plan,
                    train,
                    held,
                    opts,
                    &effects,
                    &values,
                    "pair and single fit",
                )?;
                progress(&format!(
                    "bench: triple {}: training χ² {:.1}{} ({} bench runs)",
                    f.label(),
                    f.train_score(),
                    f.cv_chi2
                        .map_or(String::new(), |c| format!(", cross-validated {c:.1}")),
                    f.bench_runs
                ));
                if f.determined && best_triple.as_ref().is_none_or(|b| f.score() < b.score()) {
                    best_triple = Some(f.clone());
                }
                tried.push(f);
            }
            chosen = Some(
                match best_triple.filter(|t| earns_place(t, base_train, base_score)) {
                    Some(t) => t,
                    None => p,
                },
            );
        } else {
            chosen = Some(p);
        }
    }
    d.joint = tried;
    d.joint_runs = batched.runs() - before;
    d.bench_runs = batched.runs();
    if let Some(j) = chosen {
        adopt(d, &j);
    }
    Ok(())
}

/// Makes `j` the diagnosis' chosen model: its values, the held-out gap after, the residual
/// left and the notes that depend on them.
fn adopt(d: &mut BenchDiagnosis, j: &JointFit) {
    let units = crate::runs::gap_bench::bench_parameters();
    d.chosen = j
        .effects
        .iter()
        .zip(&j.values)
        .zip(&j.std_err)
        .map(|((e, &value), &std_err)| ChosenValue {
            effect: e.clone(),
            value,
            std_err,
            unit: units
                .iter()
                .find(|s| s.name == *e)
                .map_or(String::new(), |s| s.unit.clone()),
        })
        .collect();
    d.heldout_after = j.heldout.clone();
    d.heldout_after_range_cm = None;
    d.alike.clear();
    d.winner_equivalent = None;
    let dof = d.residuals.saturating_sub(j.effects.len()).max(1);
    d.p_value = gap::stats::chi2_sf(j.train_chi2, dof);
    d.at_noise_level = d.p_value >= super::choose::NOISE_P;
    d.notes.retain(|n| {
        !n.starts_with(NO_EXPLANATION)
            && !n.starts_with(HELDOUT_WORSE)
            && !n.contains("cannot be told apart")
            && !n.contains("the same robot as")
    });
    d.notes.push(format!(
        "{} fitted jointly improve markedly on the single choice, predict the left-out data \
         better and are each determined: the chosen model",
        j.label()
    ));
    if !d.at_noise_level {
        d.notes.push(format!(
            "{NO_EXPLANATION}: the training residual left is beyond noise (χ² {:.1} over {dof} \
             degrees of freedom, p = {:.2e})",
            j.train_chi2, d.p_value
        ));
    }
    d.notes.extend(heldout_worse_note(
        d.heldout_before.systematic_cm,
        d.heldout_after.systematic_cm,
    ));
}

#[cfg(test)]
mod tests {
    use super::super::choose::tests::choose_against;
    use super::*;
    use gap::effects::{CASTOR_DRAG, WHEELBASE_RATIO, WHEEL_DIAMETER_RATIO};

    fn names(p: &PairStart) -> Vec<&str> {
        p.0.iter().map(String::as_str).collect()
    }

    /// A triple starts from the pair with its third effect at its single value, at neutral
    /// and at each point of its grid, each once: coasting (0..0.3 s, 7 points) fitted alone
    /// at 0.12 s gives 8 starts; fitted at neutral, 7.
    #[test]
    fn a_third_effect_starts_from_its_single_value_neutral_and_its_grid() {
        use gap::effects::COAST;
        let opts = SelectOptions::default();
        let spec = crate::runs::gap_bench::bench_parameters()
            .into_iter()
            .find(|s| s.name == COAST)
            .unwrap();
        let grid = super::super::search::grid(&spec, opts.grid);
        assert_eq!(grid.len(), 7, "{grid:?}");
        let starts = third_starts(&[0.97, 1.05], COAST, 0.12, &opts);
        let thirds: Vec<f64> = starts.iter().map(|v| v[2]).collect();
        assert_eq!(thirds[..2], [0.12, 0.0], "{starts:?}");
        assert_eq!(thirds[2..], grid[1..], "{starts:?}");
        assert!(starts.iter().all(|v| v[..2] == [0.97, 1.05]), "{starts:?}");
        assert_eq!(third_starts(&[0.97, 1.05], COAST, 0.0, &opts).len(), 7);
    }

    /// On a pair holding one of Borenstein's errors the other is the first third effect,
    /// though its single fit stayed at neutral (and so does not rank), then the best ranked
    /// single not in the pair; on Borenstein's pair, the two best ranked singles not in it;
    /// on a pair holding the wheelbase's other name (turn slip), no wheelbase.
    #[test]
    fn borenstein_other_error_is_tried_first_as_a_third() {
        use gap::effects::{COAST, DISTANCE_SCALE, TURN_SLIP};
        let d = choose_against(
            100.0,
            &[
                (COAST, 0.1, 10.0, 1.0, 0.5),
                (WHEEL_DIAMETER_RATIO, 0.97, 20.0, 1.0, 0.5),
                (CASTOR_DRAG, 2.0, 30.0, 1.0, 0.5),
                (DISTANCE_SCALE, 0.98, 40.0, 1.0, 0.5),
                (WHEELBASE_RATIO, 1.0, 100.0, 1.0, 0.5),
            ],
        );
        let pair = |a: &str, b: &str| vec![a.to_owned(), b.to_owned()];
        let thirds = third_effects(&d, &pair(WHEEL_DIAMETER_RATIO, COAST));
        assert_eq!(
            thirds,
            vec![
                (WHEELBASE_RATIO.to_owned(), 1.0),
                (CASTOR_DRAG.to_owned(), 2.0)
            ]
        );
        let thirds = third_effects(&d, &pair(WHEEL_DIAMETER_RATIO, WHEELBASE_RATIO));
        assert_eq!(
            thirds,
            vec![(COAST.to_owned(), 0.1), (CASTOR_DRAG.to_owned(), 2.0)]
        );
        let thirds = third_effects(&d, &pair(WHEEL_DIAMETER_RATIO, TURN_SLIP));
        assert_eq!(
            thirds,
            vec![(COAST.to_owned(), 0.1), (CASTOR_DRAG.to_owned(), 2.0)]
        );
    }

    /// Borenstein's pair is fitted though neither of its effects ranks first alone, from
    /// both single values and from each with the other at neutral; the single fits' pairs
    /// follow it, and the surrogate's own Ed + Eb pair (with its values as the first start)
    /// takes its place rather than a second copy.
    #[test]
    fn borenstein_pair_is_always_tried_from_single_and_neutral_starts() {
        let d = choose_against(
            100.0,
            &[
                (CASTOR_DRAG, 2.0, 10.0, 1.0, 0.5),
                (WHEELBASE_RATIO, 1.03, 20.0, 1.0, 0.5),
                (WHEEL_DIAMETER_RATIO, 0.99, 30.0, 1.0, 0.5),
            ],
        );
        let opts = SelectOptions::default();
        let pairs = pair_starts(&d, &[], &opts);
        assert_eq!(names(&pairs[0]), BORENSTEIN_PAIR, "{pairs:?}");
        assert_eq!(
            pairs[0].1,
            vec![vec![0.99, 1.03], vec![0.99, 1.0], vec![1.0, 1.03]]
        );
        assert_eq!(
            names(&pairs[1]),
            [CASTOR_DRAG, WHEELBASE_RATIO],
            "{pairs:?}"
        );
        assert_eq!(
            pairs[1].1,
            vec![vec![2.0, 1.03], vec![2.0, 1.0], vec![0.0, 1.03]]
        );
        assert_eq!(pairs.len(), 3, "each set of effects once: {pairs:?}");

        let surrogate = vec![(
            vec![WHEELBASE_RATIO.to_owned(), WHEEL_DIAMETER_RATIO.to_owned()],
            vec![1.05, 0.97],
        )];
        let pairs = pair_starts(&d, &surrogate, &opts);
        assert_eq!(names(&pairs[0]), [WHEELBASE_RATIO, WHEEL_DIAMETER_RATIO]);
        assert_eq!(pairs[0].1[0], vec![1.05, 0.97], "{pairs:?}");
        assert_eq!(pairs[0].2, "kinematic surrogate");
        assert_eq!(
            pairs
                .iter()
                .filter(|p| p.0.contains(&WHEEL_DIAMETER_RATIO.to_owned())
                    && p.0.contains(&WHEELBASE_RATIO.to_owned()))
                .count(),
            1,
            "{pairs:?}"
        );
    }
}
