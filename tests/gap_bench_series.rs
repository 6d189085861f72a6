//! The bench's time series (`hil::runs::gap_bench`, `BenchModel::predict_series`): one row per
//! control period, the segments of the test in their order at the firmware's set-point, a
//! dead band seen in the duties, and a run that records its series is the run that does not.

#[path = "support/mod.rs"]
mod support;

use gap::effects::DEAD_BAND;
use gap::model::{Experiment, Firmware, Model, TestKind};
use gap::series::{segments, SegmentKind, Telemetry};
use gap::EffectParams;
use hil::runs::gap_bench::{series_chi2, series_chi2_of_runs, BenchModel, CONTROL_PERIOD_S};
use plant_model::RobotConfig;

const LEG_MM: f64 = 300.0;
/// The robust build's set-point of both wheels, thesis RPM.
const SETPOINT_RPM: f64 = 14.47;

fn bench() -> BenchModel {
    BenchModel::new(support::firmware("robust"), RobotConfig::default(), 2)
}

fn experiment(bench: &BenchModel, test: TestKind) -> Experiment {
    let reference = bench.reference();
    Experiment {
        test,
        firmware: Firmware::nominal(&reference, LEG_MM),
        reference,
        runs: 1,
        seed: 3,
    }
}

/// The segments in order, a leg's start-up and steady part as one leg, stops left out.
fn shape(t: &Telemetry) -> Vec<&'static str> {
    let mut v: Vec<&'static str> = Vec::new();
    for k in segments(t) {
        let name = match k {
            SegmentKind::Startup | SegmentKind::Steady => "leg",
            SegmentKind::Turn => "turn",
            SegmentKind::StopCoast => continue,
        };
        if v.last() != Some(&name) {
            v.push(name);
        }
    }
    v
}

/// The median of `f` over the steady samples of `t`.
fn steady_median(t: &Telemetry, f: &dyn Fn(&gap::series::Sample) -> f64) -> f64 {
    let seg = segments(t);
    median(
        t.samples
            .iter()
            .zip(&seg)
            .filter(|(_, k)| **k == SegmentKind::Steady)
            .map(|(s, _)| f(s))
            .collect(),
    )
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The nominal robot's UMBmark: rows one period apart, four legs and four spins in turn,
/// the steady legs at the set-point, the end of the series where the run ends.
#[test]
fn the_nominal_series_has_the_tests_segments_at_the_set_point() {
    let b = bench();
    let exp = experiment(&b, TestKind::UmbmarkCw);
    let t = b.predict_series(&EffectParams::new(), &exp).unwrap();
    assert_eq!(t.period_s, CONTROL_PERIOD_S);
    assert!(t.samples.len() > 100, "{} rows", t.samples.len());
    for w in t.samples.windows(2) {
        let dt = w[1].t_s - w[0].t_s;
        // Rows end at the run loop's checks: within one check (64 us) of the period.
        assert!(
            (dt - CONTROL_PERIOD_S).abs() < 1e-4,
            "rows {dt} s apart at t = {}",
            w[1].t_s
        );
    }
    assert_eq!(
        shape(&t),
        ["leg", "turn", "leg", "turn", "leg", "turn", "leg", "turn"],
        "{:?}",
        shape(&t)
    );
    let steady = |f: &dyn Fn(&gap::series::Sample) -> f64| steady_median(&t, f);
    for (side, rpm) in [
        ("left", steady(&|s| s.rpm_left)),
        ("right", steady(&|s| s.rpm_right)),
    ] {
        assert!(
            (rpm - SETPOINT_RPM).abs() < 0.05 * SETPOINT_RPM,
            "{side} wheel's steady speed {rpm:.2} thesis RPM, set-point {SETPOINT_RPM}"
        );
    }
    // In a spin the wheels turn against each other.
    let turn: Vec<_> = t
        .samples
        .iter()
        .zip(&segments(&t))
        .filter(|(_, k)| **k == SegmentKind::Turn)
        .map(|(s, _)| s.rpm_left * s.rpm_right)
        .collect();
    assert!(median(turn) < 0.0, "the wheels of a spin turn the same way");
    // The pose of the last row is the run's end (the end point in cm, before the frame's
    // heading correction: the UMBmark's commanded heading change is a full turn).
    let end = b.predict(&EffectParams::new(), &exp).unwrap()[0];
    let (x, y, _) = t.samples.last().unwrap().pose.unwrap();
    assert!(
        (x / 10.0 - end.x_cm).abs() < 0.05 && (y / 10.0 - end.y_cm).abs() < 0.05,
        "series ends at ({:.2}, {:.2}) cm, the run at ({:.2}, {:.2}) cm",
        x / 10.0,
        y / 10.0,
        end.x_cm,
        end.y_cm
    );
}

/// A left dead band of 0.12: the controller needs more left duty for the same steady
/// speed, and the left wheel starts later than the nominal robot's.
#[test]
fn a_left_dead_band_shows_in_the_left_duty() {
    let b = bench();
    let exp = experiment(&b, TestKind::Line);
    let of = |v: f64| {
        b.predict_series(&EffectParams::new().with(DEAD_BAND, v), &exp)
            .unwrap()
    };
    let (nominal, banded) = (of(0.0), of(0.12));
    let steady = steady_median;
    let (pwm_n, pwm_b) = (
        steady(&nominal, &|s| s.pwm_left),
        steady(&banded, &|s| s.pwm_left),
    );
    let (rpm_n, rpm_b) = (
        steady(&nominal, &|s| s.rpm_left),
        steady(&banded, &|s| s.rpm_left),
    );
    let right = (
        steady(&nominal, &|s| s.pwm_right),
        steady(&banded, &|s| s.pwm_right),
    );
    assert!(
        pwm_b > pwm_n + 10.0 && (rpm_b - rpm_n).abs() < 0.05 * rpm_n,
        "steady left duty {pwm_n:.1} -> {pwm_b:.1} at {rpm_n:.2} -> {rpm_b:.2} thesis RPM"
    );
    assert!(
        (right.1 - right.0).abs() < 5.0,
        "steady right duty {:.1} -> {:.1}",
        right.0,
        right.1
    );
    // The first rows: the left wheel behind the nominal one.
    let first = |t: &Telemetry| t.samples[..4].iter().map(|s| s.rpm_left).sum::<f64>();
    assert!(
        first(&banded) < first(&nominal),
        "first rows' left speed {:.2} (dead band) vs {:.2}",
        first(&banded),
        first(&nominal)
    );
}

/// Recording the series changes nothing in the run: its end is the unrecorded run's, bit for
/// bit; the counted series (the firmware's view, what `predict_series` gives, as a robot's
/// log has it) follows the exact one to within one count per period.
#[test]
fn a_recorded_run_is_the_unrecorded_run() {
    let b = bench();
    let exp = experiment(&b, TestKind::TriangleCcw);
    let p = EffectParams::new().with(DEAD_BAND, -0.05);
    let plain = b.predict(&p, &exp).unwrap();
    let (ends, series) = b
        .run_many(&[(p.clone(), exp.clone())], true)
        .pop()
        .unwrap()
        .unwrap();
    assert_eq!(plain, ends);
    assert_eq!(series.len(), 1);
    let s = series.into_iter().next().unwrap();
    assert_eq!(s.counted, b.predict_series(&p, &exp).unwrap());
    assert_eq!(s.exact.samples.len(), s.counted.samples.len());
    // One count per 15 ms is 60 / 602.22 / 0.015 / 6 = 1.107 thesis RPM.
    let count_rpm = 60.0 / (6.0 * 100.37) / CONTROL_PERIOD_S / 6.0;
    for (e, c) in s.exact.samples.iter().zip(&s.counted.samples) {
        assert!((e.rpm_left - c.rpm_left).abs() <= 1.01 * count_rpm);
        assert!((e.rpm_right - c.rpm_right).abs() <= 1.01 * count_rpm);
        assert_eq!((e.pwm_left, e.pwm_right), (c.pwm_left, c.pwm_right));
    }
}

/// Every run of a request records its series, each from its own start phase (so the two
/// differ); scored together against a real log, the bias is their mean and its variance
/// holds their spread: two copies of one run score as that run alone, and a second run whose
/// steady left duty is 2 higher moves that bias by 1 and weighs it by
/// `σ²/n + s²(1 + 1/2)`, s² the two runs' variance (2). What the spread widens is charged
/// back (`ln` of the variance over its real part): two runs that scatter about the one
/// run's series have a smaller χ² than it and a larger deviance.
#[test]
fn the_series_of_several_runs_score_by_their_mean_and_their_spread() {
    let b = bench();
    let exp = Experiment {
        runs: 2,
        ..experiment(&b, TestKind::Line)
    };
    let (_, series) = b
        .run_many(&[(EffectParams::new(), exp)], true)
        .pop()
        .unwrap()
        .unwrap();
    assert_eq!(series.len(), 2);
    assert_ne!(series[0].counted, series[1].counted);
    let real = &series[0].counted;
    let sim = &series[1].counted;
    let one = series_chi2("line", real, sim).unwrap();
    let twice = series_chi2_of_runs("line", real, &[sim.clone(), sim.clone()]).unwrap();
    assert_eq!(one.chi2, twice.chi2);
    assert_eq!((one.spread_penalty, twice.spread_penalty), (0.0, 0.0));
    let kinds = segments(real);
    let raised = |by: f64| {
        let mut r = sim.clone();
        for (s, k) in r.samples.iter_mut().zip(&kinds) {
            if *k == SegmentKind::Steady {
                s.pwm_left += by;
            }
        }
        r
    };
    let both = series_chi2_of_runs("line", real, &[sim.clone(), raised(2.0)]).unwrap();
    let steady = |s: &hil::runs::gap_bench::SeriesScore| {
        s.segments
            .iter()
            .find(|f| f.segment == SegmentKind::Steady)
            .cloned()
            .unwrap()
    };
    let (a, c) = (steady(&one), steady(&both));
    assert!(
        (c.bias_pwm[0] - (a.bias_pwm[0] - 1.0)).abs() < 1e-9,
        "{a:?} {c:?}"
    );
    let n = a.n as f64;
    let sigma = one.noise.pwm[0];
    let z = c.bias_pwm[0] / (sigma * sigma / n + 2.0 * 1.5).sqrt();
    assert!((c.z[2] - z).abs() < 1e-9, "{} vs {z}", c.z[2]);
    let penalty = (1.0 + 2.0 * 1.5 / (sigma * sigma / n)).ln();
    assert!(
        (both.spread_penalty - penalty).abs() < 1e-9,
        "{} vs {penalty}",
        both.spread_penalty
    );
    let wide = series_chi2_of_runs("line", real, &[raised(10.0), raised(-10.0)]).unwrap();
    assert!(wide.chi2 < one.chi2, "{} vs {}", wide.chi2, one.chi2);
    assert!(
        wide.deviance() > one.deviance(),
        "{} vs {}",
        wide.deviance(),
        one.deviance()
    );
    // The other three series of the steady part are the same in both runs: unchanged.
    for i in [0, 1, 3] {
        assert!((c.z[i] - a.z[i]).abs() < 1e-9, "{i}: {a:?} {c:?}");
    }
}

/// Runs start at phases of the control period spread evenly from an offset drawn from
/// their experiment's seed: runs of the nominal robot (nothing random in its plant) end
/// apart from one another, and the same seed gives the same runs.
#[test]
fn runs_start_at_a_phase_drawn_from_their_seed() {
    let b = bench();
    let exp = Experiment {
        runs: 4,
        ..experiment(&b, TestKind::UmbmarkCcw)
    };
    let ends = b.predict(&EffectParams::new(), &exp).unwrap();
    let mut xs: Vec<u64> = ends.iter().map(|e| e.x_cm.to_bits()).collect();
    xs.sort_unstable();
    xs.dedup();
    assert!(xs.len() >= 2, "{ends:?}");
    assert_eq!(ends, b.predict(&EffectParams::new(), &exp).unwrap());
    // Four runs spread evenly over the period, from an offset drawn from the seed.
    let phase = hil::runs::gap_bench::start_phase_s;
    let mut offsets = Vec::new();
    for seed in 0..64 {
        let phases: Vec<f64> = (0..4).map(|run| phase(seed, run, 4)).collect();
        assert!(
            phases.iter().all(|p| (0.0..CONTROL_PERIOD_S).contains(p)),
            "{phases:?}"
        );
        for w in phases.windows(2) {
            assert!(
                (w[1] - w[0] - CONTROL_PERIOD_S / 4.0).abs() < 1e-12,
                "{phases:?}"
            );
        }
        offsets.push(phases[0] * 4.0);
    }
    let mean = offsets.iter().sum::<f64>() / 64.0;
    assert!(
        (mean - CONTROL_PERIOD_S / 2.0).abs() < 0.15 * CONTROL_PERIOD_S,
        "{mean}"
    );
}
