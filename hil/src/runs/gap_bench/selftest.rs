//! The bench-backed diagnosis' self-test: "real" data made by the bench with one hidden
//! effect, as a person with a tape measure would record it (5 runs per group, floor noise
//! 1°/√m), the thesis' protocol (UMBmark both ways and a line for training, the
//! counter-clockwise triangle held out; a shuttle in training too when asked, see
//! [`SelfTestDesign::shuttle`]), diagnosed blind: the kinematic diagnosis' shortlist,
//! then [`super::diagnose_bench`]. Each group also has the telemetry of its first run, its
//! speeds from the encoder counts of each control period as a robot's firmware logs them
//! (whole counts: the resolution of a real robot's log); [`SelectOptions::series`] says
//! whether the diagnosis uses it.

use gap::data::{Dataset, Group, ObservedRun, SplitRule};
use gap::effects::FLOOR_NOISE;
use gap::model::{Experiment, Firmware, Model, TestKind};
use gap::{EffectParams, GapError};
use serde::Serialize;

use super::select::{training_score, HELDOUT_WORSE, MARKED_CHI2};
use super::{diagnose_bench, kinematic_shortlist, BenchDiagnosis, BenchModel, SelectOptions};

/// Runs per group, as the thesis recorded.
pub const RUNS_PER_GROUP: usize = 5;
/// The corner of the shuttle ([`SelfTestDesign::shuttle`]), degrees.
pub const SHUTTLE_CORNER_DEG: f64 = 180.0;
/// The shuttle's runs per run of the other groups: its centroid is what tells a coast from
/// a wheelbase. On the three-effect robot over 6 seeds, with as many runs as the others
/// the wheelbase ended more than 10 % off in 2, with twice as many within 5 % in all 6
/// (docs/guide/diagnose.md#joint-fits).
pub const SHUTTLE_RUNS_FACTOR: usize = 2;
/// The name of the shuttle's group (UMBmark's groups are "bench").
pub const SHUTTLE_GROUP: &str = "shuttle";

/// The floor's heading noise of the "real" data, degrees per √m.
pub const FLOOR_NOISE_DEG_PER_SQRT_M: f64 = 1.0;

/// What a self-test records: the legs, and whether the training data hold a shuttle too.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SelfTestDesign {
    /// Leg of every test, mm.
    pub leg_mm: f64,
    /// Train on a shuttle as well: UMBmark's counter-clockwise run with its corners set to
    /// [`SHUTTLE_CORNER_DEG`] (out and back twice, the firmware's `turn_umbmark_deg`),
    /// [`SHUTTLE_RUNS_FACTOR`] times as many runs as the other groups.
    /// UMBmark turns by one angle only, and a wheelbase (a turn short in proportion to its
    /// angle) and a coast (a turn long by what the wheels run on after the stop, whatever
    /// the angle) change those turns alike: a robot with both is not determined by UMBmark
    /// and a line. Turns of a second angle tell them apart.
    pub shuttle: bool,
}

impl SelfTestDesign {
    /// The thesis' protocol with legs of `leg_mm`, no shuttle.
    pub fn legs(leg_mm: f64) -> Self {
        SelfTestDesign {
            leg_mm,
            shuttle: false,
        }
    }

    /// The same with the shuttle in the training data.
    pub fn with_shuttle(self) -> Self {
        SelfTestDesign {
            shuttle: true,
            ..self
        }
    }
}

/// The hidden effects of the self-test, in order (`--cases N` runs the first N): first one
/// the kinematic model cannot represent (a left dead band) and one it can (coasting), then
/// more of each kind, until every effect of the library but the floor
/// noise (which every case has) is hidden once. No value is a point of its effect's search
/// grid ([`SelectOptions::grid`]), which would find it exactly, and each is large enough to
/// move the held-out end points beyond the floor's noise where the effect can at all
/// (glitches and gear play cannot in these tests).
pub const DEFAULT_CASES: [(&str, f64); 14] = [
    (gap::effects::DEAD_BAND, 0.18),
    (gap::effects::COAST, 0.12),
    // Turn slip is the same robot as a larger wheelbase in this plant (see
    // `params::equivalent`): the report names the winner with its other name.
    (gap::effects::WHEELBASE_RATIO, 1.05),
    (gap::effects::MOTOR_GAIN_ASYMMETRY, 0.25),
    (gap::effects::WHEEL_DIAMETER_RATIO, 1.02),
    (gap::effects::TURN_SLIP, 0.06),
    (gap::effects::ENCODER_MISSED_COUNTS, -0.02),
    (gap::effects::DISTANCE_SCALE, 1.02),
    (gap::effects::TOE, 4.5),
    (gap::effects::STRAIGHT_SLIP, 0.05),
    // 5 ohm already takes the pack to where a turn of the triangle fails outright (a
    // threshold the fit cannot follow): a sag a robot still runs with.
    (gap::effects::BATTERY_SAG, 3.0),
    (gap::effects::ENCODER_GLITCHES, 0.3),
    (gap::effects::CASTOR_DRAG, 2.2),
    (gap::effects::BACKLASH, 15.0),
];

/// The self-test's cases with two hidden effects at once (Borenstein's Ed and Eb, both
/// directions): no single effect fits them, so each must be found by a joint fit.
pub const TWO_EFFECT_CASES: [[(&str, f64); 2]; 2] = [
    [
        (gap::effects::WHEEL_DIAMETER_RATIO, 0.97),
        (gap::effects::WHEELBASE_RATIO, 1.05),
    ],
    [
        (gap::effects::WHEEL_DIAMETER_RATIO, 1.02),
        (gap::effects::WHEELBASE_RATIO, 0.95),
    ],
];

/// The self-test's case with three hidden effects at once: Borenstein's pair (the first of
/// [`TWO_EFFECT_CASES`]) and coasting, which changes UMBmark's turns as a wider wheelbase
/// does, against it here (a coast turns further, a wide wheelbase less far).
pub const THREE_EFFECT_CASE: [(&str, f64); 3] = [
    (gap::effects::WHEEL_DIAMETER_RATIO, 0.97),
    (gap::effects::WHEELBASE_RATIO, 1.05),
    (gap::effects::COAST, 0.12),
];

/// One case.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BenchCase {
    /// The (first) hidden effect and its value ([`REAL_ROBOT_CASE`] and NaN when the case
    /// hides nothing beyond a real robot's own differences).
    pub effect: String,
    pub injected: f64,
    /// Every hidden effect with its value, and the chosen model's value of each (None: not
    /// in the chosen model under its name or its other name).
    pub hidden: Vec<(String, f64)>,
    pub chosen: Vec<Option<f64>>,
    /// The effect ranked first by the bench's training residual.
    pub ranked_first: String,
    /// The chosen one (None: none taken): the effect the report names first.
    pub winner: Option<String>,
    /// The candidates the report declares it cannot tell from the winner.
    pub alike: Vec<String>,
    /// The hidden effect's fitted value, and |fitted − injected| / |injected − neutral|, %.
    pub fitted: Option<f64>,
    pub value_error_pct: Option<f64>,
    /// How much lower the hidden truth itself (at its injected value, no fit) scores the
    /// training data than the nominal robot, in the diagnosis' own measure: whether the
    /// data carry the effect's trace at all (see [`BenchCase::visible`]).
    pub truth_gain: f64,
    /// Held-out systematic gap before and after, cm.
    pub heldout_before_cm: f64,
    pub heldout_after_cm: f64,
    /// The same beyond the sampling error of the centroids, cm: what a model can cut.
    pub heldout_excess_before_cm: f64,
    pub heldout_excess_after_cm: f64,
    /// The diagnosis.
    #[serde(skip)]
    pub diagnosis: BenchDiagnosis,
}

/// What the criteria count as a fitted value close enough, and a held-out gap cut
/// far enough, %.
pub const VALUE_WITHIN_PCT: f64 = 10.0;
pub const HELDOUT_CUT_PCT: f64 = 80.0;

impl BenchCase {
    /// The training data carry the hidden effect's trace: the truth itself predicts them
    /// better than the nominal robot by the margin the diagnosis asks of a winner. Where it
    /// does not (gear play taken up in a spin and given back after it, bounces the
    /// quadrature decoding cancels), no method could name the effect from these data, and
    /// the right answer is the report's "no candidate is taken".
    pub fn visible(&self) -> bool {
        self.truth_gain >= MARKED_CHI2
    }

    /// The report names the hidden effect first: it is the winner, or the winner's other
    /// name when the plant makes the same robot under both (see
    /// [`BenchDiagnosis::winner_equivalent`]).
    pub fn named_first(&self) -> bool {
        self.winner.as_deref() == Some(self.effect.as_str())
            || self
                .diagnosis
                .winner_equivalent
                .as_ref()
                .is_some_and(|(n, _)| *n == self.effect)
    }

    /// The hidden effect is the winner or in the set the report says it cannot tell from
    /// the winner; or, when the data carry no trace of it, the report takes no effect.
    pub fn honest(&self) -> bool {
        if self.hidden.is_empty() {
            return self.took_nothing();
        }
        self.named_first()
            || self.alike.contains(&self.effect)
            || (!self.visible() && self.winner.is_none())
    }

    /// What the case hid, as a failing self-test names it: its effect, or every hidden
    /// effect joined by '+' (as `--hidden` takes them).
    pub fn label(&self) -> String {
        case_label(&self.effect, &self.hidden)
    }

    /// The report takes no effect: no winner, no chosen model.
    pub fn took_nothing(&self) -> bool {
        self.winner.is_none() && self.diagnosis.chosen.is_empty()
    }

    /// Its fitted value within [`VALUE_WITHIN_PCT`].
    pub fn value_close(&self) -> bool {
        self.value_error_pct.is_some_and(|e| e <= VALUE_WITHIN_PCT)
    }

    /// The held-out systematic gap beyond sampling error cut, % (negative: it grew; None:
    /// the nominal robot's was within the sampling error).
    pub fn heldout_cut_pct(&self) -> Option<f64> {
        self.diagnosis.heldout_cut().map(|c| 100.0 * c)
    }

    /// Cut by [`HELDOUT_CUT_PCT`] or more.
    pub fn heldout_cut_enough(&self) -> bool {
        self.heldout_cut_pct().is_some_and(|c| c >= HELDOUT_CUT_PCT)
    }

    /// The held-out gap grew and no note of the report says so.
    pub fn grew_unreported(&self) -> bool {
        grew_unreported(
            self.heldout_before_cm,
            self.heldout_after_cm,
            &self.diagnosis.notes,
        )
    }

    /// Every hidden effect is in the chosen model, each within [`VALUE_WITHIN_PCT`] of its
    /// deviation from neutral.
    pub fn all_named_close(&self) -> bool {
        let specs = super::bench_parameters();
        self.hidden
            .iter()
            .zip(&self.chosen)
            .all(|((name, injected), got)| {
                let neutral = specs
                    .iter()
                    .find(|s| s.name == *name)
                    .map_or(0.0, |s| s.neutral);
                got.is_some_and(|v| {
                    100.0 * (v - injected).abs() <= VALUE_WITHIN_PCT * (injected - neutral).abs()
                })
            })
    }

    /// Named first and fitted within 10 %; with no trace in the data, no effect taken. A
    /// case of several hidden effects: every one in the chosen model, each within 10 %.
    /// A case hiding nothing but a real robot's own differences, which no candidate
    /// holds: no effect taken.
    pub fn passed(&self) -> bool {
        if self.hidden.is_empty() {
            return self.took_nothing();
        }
        if self.hidden.len() > 1 {
            return self.all_named_close();
        }
        if self.visible() {
            self.named_first() && self.value_close()
        } else {
            self.winner.is_none()
        }
    }
}

/// See [`BenchCase::label`].
fn case_label(effect: &str, hidden: &[(String, f64)]) -> String {
    if hidden.len() > 1 {
        hidden
            .iter()
            .map(|(e, _)| e.as_str())
            .collect::<Vec<_>>()
            .join("+")
    } else {
        effect.to_owned()
    }
}

/// Whether a held-out systematic gap grew from `before_cm` to `after_cm` with no note of
/// `notes` saying so.
fn grew_unreported(before_cm: f64, after_cm: f64, notes: &[String]) -> bool {
    after_cm > before_cm && !notes.iter().any(|n| n.starts_with(HELDOUT_WORSE))
}

/// The cases run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BenchSelfTest {
    /// Leg of every test, mm.
    pub leg_mm: f64,
    /// The training data held the shuttle ([`SelfTestDesign::shuttle`]).
    pub shuttle: bool,
    pub cases: Vec<BenchCase>,
}

impl BenchSelfTest {
    /// A table, one line per case.
    pub fn render(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let _ = writeln!(
            s,
            "Bench self-test: L = {:.0} mm, {RUNS_PER_GROUP} runs per group, floor noise \
             {FLOOR_NOISE_DEG_PER_SQRT_M}°/√m; train on umbmark_cw, umbmark_ccw, line{}; hold \
             out triangle_ccw",
            self.leg_mm,
            if self.shuttle {
                format!(
                    ", {SHUTTLE_GROUP} (umbmark_ccw, {SHUTTLE_CORNER_DEG}° corners, {} runs)",
                    SHUTTLE_RUNS_FACTOR * RUNS_PER_GROUP
                )
            } else {
                String::new()
            }
        );
        let _ = writeln!(
            s,
            "  {:<22} {:>9} {:>8} {:<22} {:<6} {:>9} {:>8} {:>9} {:>9} {:>9} {:>9} {:>7}  verdict",
            "hidden",
            "injected",
            "trace",
            "named first",
            "honest",
            "fitted",
            "err %",
            "held bef",
            "held aft",
            "sys bef",
            "sys aft",
            "cut %"
        );
        for c in &self.cases {
            let _ = writeln!(
                s,
                "  {:<22} {:>9} {:>8} {:<22} {:<6} {:>9} {:>8} {:>7.2}cm {:>7.2}cm {:>7.2}cm \
                 {:>7.2}cm {:>7}  {}{}",
                c.effect,
                // A real robot's own case has no injected value, and its truth no score.
                if c.hidden.is_empty() {
                    "-".to_owned()
                } else {
                    format!("{:.4}", c.injected)
                },
                if c.hidden.is_empty() {
                    "-".to_owned()
                } else {
                    format!("{:.1}", c.truth_gain)
                },
                c.winner.as_deref().unwrap_or("(none)"),
                if c.honest() { "yes" } else { "no" },
                c.fitted.map_or("-".to_owned(), |v| format!("{v:.4}")),
                c.value_error_pct
                    .map_or("-".to_owned(), |v| format!("{v:.1}")),
                c.heldout_before_cm,
                c.heldout_after_cm,
                c.heldout_excess_before_cm,
                c.heldout_excess_after_cm,
                c.heldout_cut_pct()
                    .map_or("-".to_owned(), |v| format!("{v:.0}")),
                if c.passed() { "pass" } else { "FAIL" },
                if c.grew_unreported() {
                    " (held-out gap grew, not reported)"
                } else {
                    ""
                }
            );
        }
        for c in self.cases.iter().filter(|c| c.hidden.len() > 1) {
            let each: Vec<String> = c
                .hidden
                .iter()
                .zip(&c.chosen)
                .map(|((e, v), got)| {
                    format!(
                        "{e} {v} -> {}",
                        got.map_or("not chosen".to_owned(), |g| format!("{g:.4}"))
                    )
                })
                .collect();
            let _ = writeln!(
                s,
                "  hidden together: {}; held-out gap beyond noise cut {}: {}",
                each.join(", "),
                c.heldout_cut_pct()
                    .map_or("-".to_owned(), |v| format!("{v:.0} %")),
                if c.passed() { "pass" } else { "FAIL" }
            );
        }
        let n = self.cases.len();
        let count = |f: &dyn Fn(&BenchCase) -> bool| self.cases.iter().filter(|c| f(c)).count();
        let v = count(&BenchCase::visible);
        let _ = writeln!(
            s,
            "  {v} of {n} cases leave a trace in the training data (the truth itself scores \
             {MARKED_CHI2} or more below the nominal robot: \"trace\"); of those, named first \
             {}, value within {VALUE_WITHIN_PCT} % {}, held-out gap beyond noise cut by \
             {HELDOUT_CUT_PCT} % or more {} ({} with none to cut); of the {} with no trace, no \
             effect taken in {}; honest {} of {n}; held-out gap grown without a note {}",
            count(&|c| c.visible() && c.named_first()),
            count(&|c| c.visible() && c.value_close()),
            count(&|c| c.visible() && c.heldout_cut_enough()),
            count(&|c| c.visible() && c.heldout_cut_pct().is_none()),
            n - v,
            count(&|c| !c.visible() && c.winner.is_none()),
            count(&BenchCase::honest),
            count(&BenchCase::grew_unreported),
        );
        s
    }
}

/// The "real" data of one case: every test of `design`, `runs_per_group` runs each (the
/// self-test's [`RUNS_PER_GROUP`]), on the bench with `hidden` and floor noise. The
/// shuttle comes last, with the next seed: the other groups are the same with it or without.
pub(super) fn make_data(
    bench: &BenchModel,
    hidden: &EffectParams,
    design: SelfTestDesign,
    seed: u64,
    runs_per_group: usize,
) -> Result<Dataset, GapError> {
    let reference = bench.reference();
    let nominal = Firmware::nominal(&reference, design.leg_mm);
    // (group name, test, firmware, runs)
    let mut planned: Vec<(&str, TestKind, Firmware, usize)> = [
        TestKind::UmbmarkCw,
        TestKind::UmbmarkCcw,
        TestKind::Line,
        TestKind::TriangleCcw,
    ]
    .iter()
    .map(|&t| ("bench", t, nominal.clone(), runs_per_group))
    .collect();
    if design.shuttle {
        let shuttle = Firmware {
            turn_umbmark_deg: SHUTTLE_CORNER_DEG,
            ..nominal.clone()
        };
        let runs = SHUTTLE_RUNS_FACTOR * runs_per_group;
        planned.push((SHUTTLE_GROUP, TestKind::UmbmarkCcw, shuttle, runs));
    }
    let (names, experiments): (Vec<&str>, Vec<Experiment>) = planned
        .into_iter()
        .enumerate()
        .map(|(i, (name, test, firmware, runs))| {
            let seed = seed.wrapping_add(i as u64 + 1);
            let exp = Experiment {
                test,
                firmware,
                reference,
                runs,
                seed,
            };
            (name, exp)
        })
        .unzip();
    let mut noisy = hidden.clone();
    noisy.set(FLOOR_NOISE, FLOOR_NOISE_DEG_PER_SQRT_M);
    let requests: Vec<_> = experiments
        .iter()
        .map(|e| (noisy.clone(), e.clone()))
        .collect();
    let mut groups = Vec::new();
    let answers = bench.run_many(&requests, true);
    for ((name, exp), answer) in names.into_iter().zip(experiments).zip(answers) {
        let (ends, series) = answer?;
        let runs = ends
            .into_iter()
            .map(|r| ObservedRun {
                x_cm: r.x_cm,
                y_cm: Some(r.y_cm),
                theta_rad: Some(r.theta_rad),
            })
            .collect();
        let group = Group::new(name, exp, runs)?;
        // The first run's log, its speeds from the encoder counts as the firmware's.
        groups.push(match series.into_iter().next() {
            Some(s) => group.with_telemetry(s.counted),
            None => group,
        });
    }
    Dataset::new(groups)
}

/// The self-test's split: UMBmark both ways (the shuttle among them) and the line for
/// training, the triangle held out.
pub(super) fn split_rule() -> SplitRule {
    SplitRule::TrainOnTests(vec![
        TestKind::UmbmarkCw,
        TestKind::UmbmarkCcw,
        TestKind::Line,
    ])
}

/// The self-test's data of `hidden` (with its floor noise, [`RUNS_PER_GROUP`] runs per
/// group), split as the self-test splits them: for checks of one step of the diagnosis.
pub fn self_test_split(
    bench: &BenchModel,
    hidden: &EffectParams,
    design: SelfTestDesign,
    seed: u64,
) -> Result<(gap::data::TrainSet, gap::data::HeldOutSet), GapError> {
    make_data(bench, hidden, design, seed, RUNS_PER_GROUP)?.split(&split_rule())
}

/// Runs one case per `(effect, value)` of `cases`.
pub fn bench_self_test(
    bench: &BenchModel,
    cases: &[(&str, f64)],
    leg_mm: f64,
    seed: u64,
    opts: &SelectOptions,
    progress: &dyn Fn(&str),
) -> Result<BenchSelfTest, GapError> {
    let sets: Vec<Vec<(&str, f64)>> = cases.iter().map(|&c| vec![c]).collect();
    bench_self_test_of(bench, &sets, leg_mm, seed, opts, progress)
}

/// Runs one case per set of hidden effects of `cases` (each effect once in a set).
pub fn bench_self_test_of(
    bench: &BenchModel,
    cases: &[Vec<(&str, f64)>],
    leg_mm: f64,
    seed: u64,
    opts: &SelectOptions,
    progress: &dyn Fn(&str),
) -> Result<BenchSelfTest, GapError> {
    let design = SelfTestDesign::legs(leg_mm);
    bench_self_test_on(bench, bench, cases, design, seed, opts, progress)
}

/// The label of a case that hides no effect of the candidate list: its "real" data come
/// from another robot config (see [`bench_self_test_on`]).
pub const REAL_ROBOT_CASE: &str = "(real robot's own)";

/// [`bench_self_test_of`] with the "real" data made by `real` (its robot config, with each
/// case's hidden effects on top) and diagnosed by `bench`'s nominal robot. A case may hide
/// nothing: the real robot's differences from the nominal one are then the only ones, and
/// when the candidates hold none of them the case passes only if the report takes no
/// effect.
pub fn bench_self_test_on(
    bench: &BenchModel,
    real: &BenchModel,
    cases: &[Vec<(&str, f64)>],
    design: SelfTestDesign,
    seed: u64,
    opts: &SelectOptions,
    progress: &dyn Fn(&str),
) -> Result<BenchSelfTest, GapError> {
    let specs = bench.parameters();
    let mut out = Vec::new();
    for (k, set) in cases.iter().enumerate() {
        let mut hidden = EffectParams::new();
        for &(effect, injected) in set {
            if !specs.iter().any(|s| s.name == effect) {
                return Err(GapError::Fit(format!(
                    "the bench has no parameter `{effect}`"
                )));
            }
            hidden.set(effect, injected);
        }
        let (effect, injected) = match set.first() {
            Some(&first) => first,
            None if !std::ptr::eq(real, bench) => (REAL_ROBOT_CASE, f64::NAN),
            None => {
                return Err(GapError::Fit("a self-test case hides no effect".to_owned()));
            }
        };
        let neutral = specs.iter().find(|s| s.name == effect).map(|s| s.neutral);
        let mut label: Vec<String> = set.iter().map(|(e, v)| format!("{e} = {v}")).collect();
        if label.is_empty() {
            label.push("nothing beyond the real robot's own".to_owned());
        }
        progress(&format!(
            "self-test case {}/{}: hidden {}",
            k + 1,
            cases.len(),
            label.join(", ")
        ));
        let data = make_data(
            real,
            &hidden,
            design,
            seed ^ (k as u64) << 32,
            RUNS_PER_GROUP,
        )?;
        let (train, held) = data.split(&split_rule())?;
        let shortlist = kinematic_shortlist(&train, &held, &gap::selftest::self_test_options())?;
        let d = diagnose_bench(bench, &shortlist, &train, &held, opts, progress)?;
        let nominal_score = d.nominal_train_chi2 + d.nominal_series_chi2.unwrap_or(0.0);
        let truth_gain = nominal_score - training_score(bench, &train, &hidden, opts)?;
        // The case's whole report with the progress, for a person reading why it went as
        // it did.
        progress(d.render().trim_end());
        let fitted = d
            .candidates
            .iter()
            .find(|c| c.effect == effect)
            .map(|c| c.value);
        let chosen = set
            .iter()
            .map(|(e, _)| {
                d.chosen.iter().find_map(|c| {
                    if c.effect == *e {
                        Some(c.value)
                    } else {
                        super::params::equivalent(&c.effect, c.value)
                            .filter(|(o, _)| o == e)
                            .map(|(_, v)| v)
                    }
                })
            })
            .collect();
        out.push(BenchCase {
            effect: effect.to_owned(),
            injected,
            hidden: set.iter().map(|(e, v)| ((*e).to_owned(), *v)).collect(),
            chosen,
            ranked_first: d
                .candidates
                .first()
                .map_or(String::new(), |c| c.effect.clone()),
            winner: d.winner.as_ref().map(|w| w.0.clone()),
            alike: d.alike.clone(),
            fitted,
            value_error_pct: fitted
                .zip(neutral)
                .map(|(f, n)| 100.0 * (f - injected).abs() / (injected - n).abs()),
            truth_gain,
            heldout_before_cm: d.heldout_before.systematic_cm,
            heldout_after_cm: d.heldout_after.systematic_cm,
            heldout_excess_before_cm: d.heldout_before.systematic_excess_cm,
            heldout_excess_after_cm: d.heldout_after.systematic_excess_cm,
            diagnosis: d,
        });
    }
    Ok(BenchSelfTest {
        leg_mm: design.leg_mm,
        shuttle: design.shuttle,
        cases: out,
    })
}

#[cfg(test)]
mod tests {
    use super::super::select::heldout_worse_note;
    use super::*;

    /// A case of several hidden effects is named by all of them, as `--hidden` takes them;
    /// a case of one by its effect (and the real-robot case by its own name).
    #[test]
    fn a_case_is_named_by_every_effect_it_hides() {
        let h = |names: &[&str]| -> Vec<(String, f64)> {
            names.iter().map(|n| ((*n).to_owned(), 1.0)).collect()
        };
        assert_eq!(
            case_label(
                "wheel_diameter_ratio",
                &h(&["wheel_diameter_ratio", "wheelbase_ratio", "coast"])
            ),
            "wheel_diameter_ratio+wheelbase_ratio+coast"
        );
        assert_eq!(case_label("coast", &h(&["coast"])), "coast");
        assert_eq!(case_label(REAL_ROBOT_CASE, &[]), REAL_ROBOT_CASE);
    }

    /// A held-out gap that grew is unreported only without the diagnosis' own note: the
    /// note for 1.00 -> 1.50 cm clears it, another note does not, and a gap that shrank or
    /// stayed needs no note (and gets none).
    #[test]
    fn a_grown_held_out_gap_is_reported_by_the_diagnosis_note() {
        let note = heldout_worse_note(1.0, 1.5).expect("a note when it grew");
        assert!(note.contains("1.00 cm before, 1.50 cm after"), "{note}");
        assert!(!grew_unreported(1.0, 1.5, std::slice::from_ref(&note)));
        let other = vec!["no candidate explains the gap".to_owned()];
        assert!(grew_unreported(1.0, 1.5, &other));
        assert!(grew_unreported(1.0, 1.5, &[]));
        for (before, after) in [(1.5, 1.0), (1.0, 1.0)] {
            assert_eq!(heldout_worse_note(before, after), None);
            assert!(!grew_unreported(before, after, &[]));
        }
    }
}
