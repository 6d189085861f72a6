//! The identification against the thesis' printed figures, and the CSV reader's errors.

use plant_model::identify::{
    identify_csv, ziegler_nichols, CheckBasis, DiscreteModel, Identification, IdentifyError,
    ThesisCheck, Verdict, THESIS_LEFT_CSV, THESIS_RIGHT_CSV,
};
use plant_model::Side;

const RIGHT_PATH: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../fixtures/thesis-data/motor_step_right.csv"
);
const LEFT_PATH: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../fixtures/thesis-data/motor_step_left.csv"
);

fn check<'a>(id: &'a Identification, basis: CheckBasis, starts_with: &str) -> &'a ThesisCheck {
    id.checks
        .iter()
        .find(|c| c.basis == basis && c.quantity.starts_with(starts_with))
        .unwrap_or_else(|| panic!("no {basis:?} check `{starts_with}`"))
}

/// The thesis' right-motor chain (K 25, tau 0.0685 s, L 0.03 s) through our ZOH and
/// Ziegler-Nichols code gives exactly its printed Kp 2.74, Ti 0.06, Td 0.015, pole 0.8033 and
/// numerator 4.917, and the data themselves give K and tau within their resolution.
#[test]
fn reproduces_the_right_motor_numbers_to_the_printed_precision() {
    let zn = ziegler_nichols(0.0685, 0.03, None).unwrap();
    assert_eq!(format!("{:.2}", zn.kp), "2.74");
    assert_eq!(format!("{:.2}", zn.ti_s), "0.06");
    assert_eq!(format!("{:.3}", zn.td_s), "0.015");
    assert_eq!(format!("{:.4}", zn.kd), "0.0411");
    let zoh = DiscreteModel::zoh(25.0, 0.0685, 0.0, 0.015);
    assert_eq!(format!("{:.4}", zoh.pole), "0.8033");
    assert_eq!(format!("{:.3}", zoh.numerator), "4.917");

    let id = identify_csv(RIGHT_PATH, None).unwrap();
    assert_eq!(
        id.side,
        Some(Side::Right),
        "side read from the file's comments"
    );
    for quantity in [
        "discrete pole",
        "discrete numerator",
        "Kp = 1.2 T/L",
        "Ti",
        "Td",
    ] {
        let c = check(&id, CheckBasis::Arithmetic, quantity);
        assert_eq!(c.verdict, Verdict::Reproduces, "{c:?}");
    }
    // From the data: K rounds to the thesis' 25, tau is within one count's resolution of
    // 0.0685 s, and so are the pole, numerator and Kp computed from them.
    assert_eq!(format!("{:.0}", id.k), "25");
    assert!(
        (id.tau_s - 0.0685).abs() < id.tau_resolution_s,
        "{}",
        id.tau_s
    );
    for quantity in [
        "K:",
        "tau:",
        "discrete pole",
        "discrete numerator",
        "Kp = 1.2 T/L",
    ] {
        let c = check(&id, CheckBasis::Data, quantity);
        assert_eq!(c.verdict, Verdict::Reproduces, "{c:?}");
    }
    assert_eq!(id.ti_s, 0.06);
    assert_eq!(id.td_s, 0.015);
    assert!((id.kp - 2.74).abs() < 0.06, "Kp from our tau: {}", id.kp);
    assert!(
        (id.pole - 0.8033).abs() < 0.005,
        "pole from our tau: {}",
        id.pole
    );
}

/// The left motor's printed discrete model 0.5919/(z - 0.9731) is flagged: it is the ZOH of
/// tau = 0.55 s, not of the thesis' own 0.055 s; the printed 0.33 s^2 of eq. (126) too.
#[test]
fn detects_the_left_discrete_model_contradiction() {
    let id = identify_csv(LEFT_PATH, Some(Side::Left)).unwrap();
    let pole = check(&id, CheckBasis::Arithmetic, "discrete pole");
    assert_eq!(pole.verdict, Verdict::Contradicts);
    assert!(pole.note.contains("0.55"), "{}", pole.note);
    assert_eq!(format!("{:.4}", pole.ours), "0.7613");
    let tau_of_printed_pole = DiscreteModel {
        sample_period_s: 0.015,
        numerator: 0.5919,
        pole: 0.9731,
        delay_samples: 0,
    };
    assert_eq!(format!("{:.2}", tau_of_printed_pole.tau_s()), "0.55");
    assert_eq!(format!("{:.0}", tau_of_printed_pole.gain()), "22");
    let numerator = check(&id, CheckBasis::Arithmetic, "discrete numerator");
    assert_eq!(numerator.verdict, Verdict::Contradicts);
    // What is right on the left: K, and the PID arithmetic from tau = 0.055 s.
    assert_eq!(
        check(&id, CheckBasis::Data, "K:").verdict,
        Verdict::Reproduces
    );
    for quantity in ["Kp = 1.2 T/L", "Ti", "Td", "Ki", "Kd"] {
        let c = check(&id, CheckBasis::Arithmetic, quantity);
        assert_eq!(c.verdict, Verdict::Reproduces, "{c:?}");
    }
    let eq126 = check(&id, CheckBasis::Arithmetic, "s^2 coefficient");
    assert_eq!(eq126.verdict, Verdict::Contradicts);
}

/// Neither curve has the two samples of dead time the thesis' Ti = 0.06 s implies: the FOPDT
/// fit starts both mean responses before t = 0 (within one sample), so the dead time is 0.
#[test]
fn the_dead_time_of_the_pid_gains_is_not_in_the_data() {
    for (csv, side) in [
        (THESIS_RIGHT_CSV, Side::Right),
        (THESIS_LEFT_CSV, Side::Left),
    ] {
        let id = identify_csv(csv, Some(side)).unwrap();
        let c = check(&id, CheckBasis::Data, "dead time");
        assert_eq!(c.verdict, Verdict::Contradicts, "{c:?}");
        let l = id.mean.fopdt.l_s;
        assert!(-0.015 < l && l <= 0.0, "{side}: L = {l}");
        assert_eq!(id.dead_time_s, 0.0);
        assert_eq!(id.delay_samples, 0);
    }
}

/// Identification of both thesis files renders every section and serialises.
#[test]
fn renders_and_serialises() {
    for (csv, side) in [
        (THESIS_RIGHT_CSV, Side::Right),
        (THESIS_LEFT_CSV, Side::Left),
    ] {
        let id = identify_csv(csv, None).unwrap();
        assert_eq!(id.side, Some(side));
        let text = id.render();
        println!("{text}");
        for needle in [
            "63.2 % method",
            "FOPDT",
            "Ziegler-Nichols",
            "ZOH",
            "Physical model",
            "Thesis checks",
            "CONTRADICTS",
        ] {
            assert!(text.contains(needle), "`{needle}` missing from\n{text}");
        }
        assert_eq!(id.levels.len(), 5);
        let toml = toml::to_string(&id).unwrap();
        assert!(toml.contains("kp = "), "{toml}");
    }
}

fn parse_error(text: &str) -> String {
    match identify_csv(text, None) {
        Err(e) => e.to_string(),
        Ok(_) => panic!("accepted:\n{text}"),
    }
}

const HEADER: &str = "# comment\nsample,time_s,pwm170_rpm,pwm250_rpm,mean_rpm\n";

/// Malformed rows are refused with an error naming the line of the file.
#[test]
fn csv_errors_name_the_line() {
    let good_rows = "0,0.000,0,0,0\n1,0.015,1.11,8.84,4.975\n2,0.030,3.32,18.8,11.06\n";
    let steady = "127,1.905,14.36,38.71,26.535\n";
    let cases = [
        (
            format!("{HEADER}{good_rows}3,0.045,3.32,oops,13.835\n{steady}"),
            "line 6: column `pwm250_rpm` is `oops`",
        ),
        (
            format!("{HEADER}{good_rows}3,0.045,3.32\n{steady}"),
            "line 6: 3 comma-separated fields, but the header has 5",
        ),
        (
            format!("{HEADER}{good_rows}2,0.045,3.32,24.35,13.835\n{steady}"),
            "line 6: sample 2 does not come after sample 2",
        ),
        (
            format!("{HEADER}{good_rows}3,0.060,3.32,24.35,13.835\n{steady}"),
            "line 6: time_s = 0.06",
        ),
        (
            format!("{HEADER}{good_rows}3,0.045,3.32,24.35,99\n{steady}"),
            "line 6: mean_rpm = 99",
        ),
        (
            format!("{HEADER}{good_rows}x,0.045,3.32,24.35,13.835\n{steady}"),
            "line 6: column `sample` is `x`, which is not a non-negative integer",
        ),
        (
            format!("{HEADER}1,0.015,1.11,8.84,4.975\n{steady}"),
            "line 3: the first data row is sample 1",
        ),
        (
            "# c\nsample,time_s,pwm300_rpm\n0,0,0\n".to_owned(),
            "line 2: header column `pwm300_rpm`",
        ),
        (
            "sample,time_s,speed\n0,0,0\n".to_owned(),
            "line 1: header column `speed`",
        ),
    ];
    for (text, expected) in &cases {
        let message = parse_error(text);
        assert!(
            message.contains(expected),
            "expected `{expected}` in `{message}`"
        );
    }
    assert!(matches!(
        identify_csv("# only comments\n", None),
        Err(IdentifyError::NoHeader)
    ));
    let missing = identify_csv("/nonexistent/step.csv", None).unwrap_err();
    assert!(matches!(missing, IdentifyError::Read { .. }), "{missing}");
}

/// The vendored CSVs parse with T = 15 ms, the gap kept, the mean column the mean of the
/// PWM columns, and the 63.2 % points of the slow curves reported as lying in the gap.
#[test]
fn the_thesis_files_parse_with_their_gap() {
    let id = identify_csv(THESIS_RIGHT_CSV, None).unwrap();
    assert_eq!(id.sample_period_s, 0.015);
    assert_eq!(id.samples, [0, 1, 2, 3, 4, 5, 6, 7, 127, 128, 129]);
    assert_eq!(id.step_pwm, 210.0);
    let pwm170 = &id.levels[0];
    assert_eq!(pwm170.pwm, Some(170));
    assert_eq!(pwm170.first_order.tau_s, None);
    assert_eq!(pwm170.first_order.crossing_between_s, [0.105, 1.905]);
}

/// The data's discrete pole exp(-T/tau) is checked to the resolution tau has, carried
/// through: d(pole)/d(tau) = pole T / tau^2 times tau's resolution.
#[test]
fn the_pole_from_the_data_carries_the_resolution_of_tau() {
    for (path, side) in [(RIGHT_PATH, Side::Right), (LEFT_PATH, Side::Left)] {
        let id = identify_csv(path, Some(side)).unwrap();
        let pole = check(&id, CheckBasis::Data, "discrete pole");
        let (t, tau) = (id.sample_period_s, id.tau_s);
        assert_eq!(pole.ours, (-t / tau).exp());
        let want = pole.ours * t / (tau * tau) * id.tau_resolution_s;
        assert!((pole.tolerance / want - 1.0).abs() < 1e-12, "{pole:?}");
    }
}

/// The note on tau reads the mean curve at the thesis' tau by linear interpolation between
/// the two rows around it.
#[test]
fn the_mean_curve_is_read_at_the_thesis_tau_between_its_rows() {
    let id = identify_csv(RIGHT_PATH, Some(Side::Right)).unwrap();
    let text = std::fs::read_to_string(RIGHT_PATH).unwrap();
    let mut rows = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = rows.next().unwrap().split(',').collect();
    let mean = header.iter().position(|h| *h == "mean_rpm").unwrap();
    let points: Vec<(f64, f64)> = rows
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (f[1].parse().unwrap(), f[mean].parse().unwrap())
        })
        .collect();
    let tau = 0.0685;
    let i = points.iter().position(|p| p.0 >= tau).unwrap();
    let ((t0, v0), (t1, v1)) = (points[i - 1], points[i]);
    let v = v0 + (v1 - v0) * (tau - t0) / (t1 - t0);
    let says = format!(
        "At the thesis' {tau} s the mean curve is at {:.1} % of K.",
        100.0 * v / id.k
    );
    assert!(
        id.checks.iter().any(|c| c.note.contains(&says)),
        "no check says `{says}`"
    );
}

/// The unit of the physical model: motor rad/s per thesis RPM is the units' own conversion
/// (6 wheel RPM) times the gear ratio.
#[test]
fn the_physical_unit_is_six_wheel_rpm_through_the_gear() {
    use plant_model::identify::motor_rad_s_per_thesis_rpm;
    use plant_model::units::{RadPerSec, ThesisRpm};
    let wheel = RadPerSec::from(ThesisRpm(1.0)).0;
    assert!((motor_rad_s_per_thesis_rpm(100.37) / (wheel * 100.37) - 1.0).abs() < 1e-15);
}
