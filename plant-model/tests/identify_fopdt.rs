//! The FOPDT least-squares fit against synthetic step responses with the thesis' sampling:
//! encoder counts in 15 ms windows (1.107 thesis RPM per count) and only rows 0-7 and
//! 127-129 kept.

use plant_model::identify::{
    count_quantum_thesis_rpm, fit_fopdt, identify_csv, FopdtBounds, Sampling,
};
use rstest::rstest;

const T: f64 = 0.015;

/// Thesis-RPM samples of a FOPDT step response as the firmware reports it: the encoder count
/// (`floor` of the angle in counts plus `phase`) differenced over each window; `phase: None`
/// gives the unquantised window mean.
fn firmware_samples(k: f64, tau: f64, l: f64, phase: Option<f64>, samples: &[u64]) -> Vec<f64> {
    let q = count_quantum_thesis_rpm(T);
    let counts_per_s = k / q / T;
    let counts = |t: f64| {
        let s = t - l;
        let angle = if s > 0.0 {
            counts_per_s * (s - tau * (1.0 - (-s / tau).exp()))
        } else {
            0.0
        };
        phase.map_or(angle, |p| (angle + p).floor())
    };
    samples
        .iter()
        .map(|&n| {
            let t = n as f64 * T;
            if n == 0 {
                0.0
            } else {
                (counts(t) - counts(t - T)) * q
            }
        })
        .collect()
}

fn thesis_rows() -> Vec<u64> {
    (0..8).chain(127..130).collect()
}

/// A CSV in the thesis' layout: five PWM columns with steady levels `levels`, the same `tau`
/// and `L`, each quantised with its own encoder phase, and their mean.
fn thesis_like_csv(levels: [f64; 5], tau: f64, l: f64, phase: f64) -> String {
    let rows = thesis_rows();
    let columns: Vec<Vec<f64>> = levels
        .iter()
        .enumerate()
        .map(|(i, &k)| {
            let p = (phase + 0.37 * i as f64).fract();
            firmware_samples(k, tau, l, Some(p), &rows)
        })
        .collect();
    let mut csv = String::from(
        "# synthetic\nsample,time_s,pwm170_rpm,pwm190_rpm,pwm210_rpm,pwm230_rpm,pwm250_rpm,mean_rpm\n",
    );
    for (r, &n) in rows.iter().enumerate() {
        let values: Vec<f64> = columns.iter().map(|c| c[r]).collect();
        let mean = values.iter().sum::<f64>() / 5.0;
        let fields: Vec<String> = values.iter().map(|v| format!("{v:.4}")).collect();
        csv += &format!("{n},{:.3},{},{mean:.4}\n", n as f64 * T, fields.join(","));
    }
    csv
}

/// Without quantisation the fit returns the generating K, tau and L (to 1e-6), gap and all.
#[test]
fn recovers_an_unquantised_fopdt_exactly() {
    let rows = thesis_rows();
    let times: Vec<f64> = rows.iter().map(|&n| n as f64 * T).collect();
    let values = firmware_samples(25.0, 0.0685, 0.03, None, &rows);
    let fit = fit_fopdt(
        &times,
        &values,
        T,
        &FopdtBounds::for_period(T),
        Sampling::WindowAverage,
    )
    .unwrap();
    assert!((fit.k - 25.0).abs() < 1e-5, "{fit:?}");
    assert!((fit.tau_s - 0.0685).abs() < 1e-6, "{fit:?}");
    assert!((fit.l_s - 0.03).abs() < 1e-6, "{fit:?}");
    assert!(fit.rms_residual < 1e-5);
    assert!(!fit.at_bound);
}

/// From the mean column of a thesis-like file (five quantised columns, rows 0-7 and
/// 127-129), `identify_csv` recovers K within 1 %, tau within 6 % and L within 1.5 ms, for
/// every one of 20 encoder phases.
#[rstest]
#[case(0.0685, 0.03)]
#[case(0.05, 0.02)]
#[case(0.045, 0.0)]
#[case(0.04, 0.045)]
fn recovers_k_tau_and_dead_time_from_quantised_thesis_like_data(#[case] tau: f64, #[case] l: f64) {
    let levels = [14.0, 18.0, 23.0, 31.0, 39.0];
    let k = levels.iter().sum::<f64>() / 5.0;
    for step in 0..20 {
        let csv = thesis_like_csv(levels, tau, l, 0.05 * step as f64);
        let id = identify_csv(csv.as_str(), None).unwrap();
        let f = &id.mean.fopdt;
        assert!((f.k - k).abs() / k < 0.01, "phase {step}: K {} vs {k}", f.k);
        assert!(
            (f.tau_s - tau).abs() / tau < 0.06,
            "phase {step}: tau {} vs {tau}",
            f.tau_s
        );
        assert!(
            (f.l_s - l).abs() < 0.0015,
            "phase {step}: L {} vs {l}",
            f.l_s
        );
        assert_eq!(
            id.delay_samples,
            (l / T).round() as u32,
            "phase {step}: z^-d"
        );
    }
}

/// A single quantised column (1.107 thesis RPM per count), all 130 rows: K within 0.5 %,
/// tau within 5 %, L within 2 ms, for every one of 10 encoder phases.
#[rstest]
#[case(14.0, 0.05, 0.02)]
#[case(25.0, 0.0685, 0.03)]
#[case(38.0, 0.045, 0.015)]
fn recovers_a_single_quantised_column(#[case] k: f64, #[case] tau: f64, #[case] l: f64) {
    let rows: Vec<u64> = (0..130).collect();
    let times: Vec<f64> = rows.iter().map(|&n| n as f64 * T).collect();
    for step in 0..10 {
        let values = firmware_samples(k, tau, l, Some(0.1 * step as f64), &rows);
        let f = fit_fopdt(
            &times,
            &values,
            T,
            &FopdtBounds::for_period(T),
            Sampling::WindowAverage,
        )
        .unwrap();
        assert!((f.k - k).abs() / k < 0.005, "phase {step}: {f:?}");
        assert!((f.tau_s - tau).abs() / tau < 0.05, "phase {step}: {f:?}");
        assert!((f.l_s - l).abs() < 0.002, "phase {step}: {f:?}");
    }
}
