//! Time series: the telemetry reader, segments, residual whiteness and input correlation,
//! and the statistics underneath.

use std::path::Path;

use gap::series::{read_telemetry, segments, series_gap, RpmUnit, SegmentKind, Telemetry};
use gap::stats::{chi2_sf, cross_correlation, ljung_box};
use plant_model::rng::{mix, unit, GOLDEN};

/// A fixed pseudo-random number in [−0.5, 0.5) for index `i`: the `i`-th draw of a
/// SplitMix64 stream from state 0, taken by index so each sample has its own.
fn uniform(i: u64) -> f64 {
    unit(mix(i.wrapping_add(1).wrapping_mul(GOLDEN))) - 0.5
}

/// A leg of 40 samples (rising over the first 5), a turn of 10, a stop of 5.
fn run(noise: impl Fn(usize) -> f64, gain_error: f64) -> String {
    let mut s = String::from("# synthetic\nt_s,rpm_left,rpm_right,pwm_left,pwm_right\n");
    for i in 0..55 {
        let t = i as f64 * 0.015;
        let (pl, pr, v) = if i < 40 {
            let pwm = 180.0 + 10.0 * ((i % 7) as f64);
            (
                pwm,
                pwm,
                (14.0 * (1.0 - (-(i as f64) / 1.5).exp())).min(14.0),
            )
        } else if i < 50 {
            (150.0, -150.0, 10.0)
        } else {
            (0.0, 0.0, 0.0)
        };
        let rl = v * (1.0 + gain_error * (pl - 180.0) / 60.0) + noise(i);
        s.push_str(&format!(
            "{t:.3},{rl:.4},{:.4},{pl},{pr}\n",
            if i < 40 { v } else { -v }
        ));
    }
    s
}

fn parse(text: &str) -> Telemetry {
    read_telemetry(text, Path::new("t.csv"), 0.015, RpmUnit::ThesisRpm).unwrap()
}

/// The reader accepts the layout (with and without the pose), converts wheel RPM to thesis
/// RPM, and names the line of every mistake.
#[test]
fn reader() {
    let t = parse(&run(|_| 0.0, 0.0));
    assert_eq!(t.samples.len(), 55);
    let wheel = read_telemetry(
        "t_s,rpm_left,rpm_right,pwm_left,pwm_right,x_mm,y_mm,theta_rad\n0,60,6,10,10,0,0,0\n",
        Path::new("w.csv"),
        0.015,
        RpmUnit::WheelRpm,
    )
    .unwrap();
    assert_eq!(wheel.samples[0].rpm_left, 10.0);
    assert_eq!(wheel.samples[0].pose, Some((0.0, 0.0, 0.0)));
    for (text, want) in [
        ("t,rpm\n", "line 1: header"),
        (
            "t_s,rpm_left,rpm_right,pwm_left,pwm_right\n0,1,2,3\n",
            "line 2: 4 fields",
        ),
        (
            "t_s,rpm_left,rpm_right,pwm_left,pwm_right\n0,1,2,300,0\n",
            "outside −255..255",
        ),
        (
            "t_s,rpm_left,rpm_right,pwm_left,pwm_right\n0,1,2,3,4\n0,1,2,3,4\n",
            "line 3: t_s",
        ),
        (
            "t_s,rpm_left,rpm_right,pwm_left,pwm_right\n0,x,2,3,4\n",
            "`rpm_left` = `x`",
        ),
        ("# only\n", "no header"),
    ] {
        let e = read_telemetry(text, Path::new("bad.csv"), 0.015, RpmUnit::ThesisRpm)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(want) && e.contains("bad.csv"),
            "{e} (want {want})"
        );
    }
}

/// Segments come from the duties: start-up while the wheels rise, then steady, the turn,
/// and the stop.
#[test]
fn segmentation() {
    let seg = segments(&parse(&run(|_| 0.0, 0.0)));
    assert_eq!(seg[0], SegmentKind::Startup);
    assert_eq!(seg[39], SegmentKind::Steady);
    let startup = seg.iter().filter(|s| **s == SegmentKind::Startup).count();
    assert!((2..=6).contains(&startup), "{startup}");
    assert!(seg[40..50].iter().all(|s| *s == SegmentKind::Turn));
    assert!(seg[50..].iter().all(|s| *s == SegmentKind::StopCoast));
}

/// A model that misses a duty-dependent gain leaves a residual correlated with the duty;
/// one that misses nothing but white noise passes both tests.
#[test]
fn residual_tests_tell_what_is_missing() {
    let sim = parse(&run(|_| 0.0, 0.0));
    // White measurement noise (a fixed pseudo-random sequence).
    let white = |i: usize| uniform(i as u64) * 0.4;
    let g = series_gap("white", &parse(&run(white, 0.0)), &sim).unwrap();
    let left = &g.wheels[0];
    // A quarter of the samples' lags, at most 10: here 10.
    assert!(g.n >= 40, "{}", g.n);
    assert_eq!(left.ljung_box.as_ref().unwrap().lags, 10);
    assert!(
        !left.ljung_box.as_ref().unwrap().rejected,
        "{}",
        left.verdict
    );
    let g = series_gap("gain", &parse(&run(white, 0.3)), &sim).unwrap();
    let left = &g.wheels[0];
    assert!(
        left.input_correlation.as_ref().unwrap().significant,
        "{}",
        left.verdict
    );
    assert!(left.verdict.contains("input-dependent"), "{}", left.verdict);
    let steady = g
        .segments
        .iter()
        .find(|s| s.segment == SegmentKind::Steady)
        .unwrap();
    assert!(steady.rms_left > steady.rms_right);
}

/// χ² survival values against tables, Ljung-Box on an AR(1) series and on white noise.
#[test]
fn statistics() {
    assert!((chi2_sf(3.841, 1) - 0.05).abs() < 1e-3);
    assert!((chi2_sf(18.307, 10) - 0.05).abs() < 1e-3);
    assert!((chi2_sf(2.0, 2) - (-1.0f64).exp()).abs() < 1e-12);
    let mut x = 0.3;
    let mut ar = Vec::new();
    let mut white = Vec::new();
    let mut state: u64 = 42;
    for _ in 0..300 {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let u = (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
        x = 0.8 * x + u;
        ar.push(x);
        white.push(u);
    }
    assert!(ljung_box(&ar, 10).unwrap().rejected);
    assert!(!ljung_box(&white, 10).unwrap().rejected);
    assert!(
        cross_correlation(&white, &[1.0; 300], 5).is_none(),
        "constant input"
    );
    let cc = cross_correlation(&ar, &ar, 3).unwrap();
    assert!((cc.r[0] - 1.0).abs() < 1e-9);
}
