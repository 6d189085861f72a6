//! The identification of the thesis' step responses gives the figures the module docs of
//! `plant_model::identify` tabulate (mean curves, Ziegler-Nichols, ZOH) and say about the
//! gain `K` (a step response to PWM 210, not a gain per count), and falls back to the FOPDT
//! `tau` when the 63.2 % point lies where the thesis printed no rows.

use plant_model::identify::{
    count_quantum_thesis_rpm, identify_csv, Identification, StepData, TauMethod,
    CONTROLLER_PWM_PER_UNIT, THESIS_LEFT_CSV, THESIS_RIGHT_CSV,
};

fn at(v: f64, decimals: usize) -> String {
    format!("{v:.decimals$}")
}

/// One motor's row of the docs' table, and the docs' gain figures.
struct Documented {
    k: &'static str,
    tau: &'static str,
    tau_resolution: &'static str,
    zn: [&'static str; 3],
    zoh: [&'static str; 2],
    per_count: &'static str,
    per_unit: &'static str,
    dead_band_pwm: &'static str,
    k_per_count: &'static str,
    kp_with_gain: &'static str,
}

fn assert_documented(id: &Identification, d: &Documented) {
    assert_eq!(at(id.k, 2), d.k);
    assert_eq!(id.tau_method, TauMethod::Crossing632);
    assert_eq!(at(id.tau_s, 4), d.tau);
    assert_eq!(at(id.tau_resolution_s, 4), d.tau_resolution);
    // The thesis' L: two sample periods, and Ogata's table from it.
    assert_eq!(id.zn_dead_time_s, 0.03);
    assert_eq!(
        (at(id.ti_s, 4), at(id.td_s, 4)),
        ("0.0600".into(), "0.0150".into())
    );
    assert_eq!([at(id.kp, 2), at(id.ki, 1), at(id.kd, 4)], d.zn);
    assert_eq!([at(id.numerator, 3), at(id.pole, 4)], d.zoh);
    assert_eq!((id.dead_time_s, id.delay_samples), (0.0, 0));
    let g = &id.gain;
    assert_eq!(g.step_pwm, 210.0);
    assert_eq!(at(g.k_per_pwm_count, 4), d.k_per_count);
    assert_eq!(at(g.incremental_per_pwm_count.unwrap(), 3), d.per_count);
    assert_eq!(at(g.dead_band_pwm.unwrap(), 1), d.dead_band_pwm);
    assert_eq!(
        at(g.incremental_per_controller_unit.unwrap(), 3),
        d.per_unit
    );
    assert_eq!(at(id.kp_with_process_gain.unwrap(), 3), d.kp_with_gain);
}

#[test]
fn the_documented_results_of_the_right_motor() {
    let id = identify_csv(THESIS_RIGHT_CSV, None).unwrap();
    assert_documented(
        &id,
        &Documented {
            k: "24.98",
            tau: "0.0672",
            tau_resolution: "0.0021",
            zn: ["2.69", "44.8", "0.0403"],
            zoh: ["4.995", "0.8000"],
            per_count: "0.310",
            per_unit: "1.645",
            dead_band_pwm: "129.3",
            k_per_count: "0.1189",
            // 1.2 T / (K L) with our tau and the per-unit gain.
            kp_with_gain: "1.635",
        },
    );
}

#[test]
fn the_documented_results_of_the_left_motor() {
    let id = identify_csv(THESIS_LEFT_CSV, None).unwrap();
    assert_documented(
        &id,
        &Documented {
            k: "21.81",
            tau: "0.0490",
            tau_resolution: "0.0017",
            zn: ["1.96", "32.6", "0.0294"],
            zoh: ["5.756", "0.7361"],
            per_count: "0.354",
            per_unit: "1.879",
            dead_band_pwm: "148.3",
            k_per_count: "0.1039",
            kp_with_gain: "1.042",
        },
    );
}

/// One count in one 15 ms window is 1.107 thesis RPM (the docs' units section), and half that
/// in a window twice as long; the controller's output moves the PWM by 255/48 per unit.
#[test]
fn the_count_quantum_and_the_controller_unit() {
    assert_eq!(at(count_quantum_thesis_rpm(0.015), 4), "1.1070");
    assert_eq!(at(count_quantum_thesis_rpm(0.030), 4), "0.5535");
    assert_eq!(CONTROLLER_PWM_PER_UNIT, 5.3125);
}

/// The report's header names the printed rows and the step the mean answers, and its gain
/// line the steady line and `K / 210`.
#[test]
fn the_report_names_the_rows_the_step_and_the_gain() {
    let text = identify_csv(THESIS_RIGHT_CSV, None).unwrap().render();
    for needle in [
        "right motor, T = 0.015 s, 11 rows (samples 0-7, 127-129)",
        "step 0 -> PWM 210/255",
        "L = 0.03 s: Kp = 2.689",
        "with the process gain (1.645 thesis RPM per unit of the firmware output): Kp = 1.635",
        "steady levels vs PWM: 0.3096 thesis RPM per count, zero at PWM 129.3; K / 210 = 0.1189 per count",
        "4.9949 / (z - 0.8000)\n",
    ] {
        assert!(text.contains(needle), "`{needle}` missing from\n{text}");
    }
    // The per-column table ends each row with the tangent's L and T (the docs' 0.0045 s
    // and 0.0627 s for the mean).
    let mean_row = text.lines().find(|l| l.starts_with("  mean_rpm")).unwrap();
    assert!(mean_row.ends_with("0.0045  0.0627"), "{mean_row}");
}

/// Without rows 3-126 the mean curve crosses 63.2 % of its level between 0.03 s and 1.905 s:
/// `tau` is then the FOPDT fit's, good to half a sample period, and the report says so.
#[test]
fn a_crossing_in_a_gap_takes_tau_from_the_fopdt_fit() {
    let csv: String = THESIS_RIGHT_CSV
        .lines()
        .filter(|l| {
            let row = l.split(',').next().and_then(|s| s.parse::<u32>().ok());
            !matches!(row, Some(3..=7))
        })
        .map(|l| format!("{l}\n"))
        .collect();
    let id = identify_csv(csv.as_str(), None).unwrap();
    assert_eq!(id.tau_method, TauMethod::Fopdt);
    assert_eq!(id.mean.first_order.tau_s, None);
    assert_eq!(id.tau_s, id.mean.fopdt.tau_s);
    assert_eq!(id.tau_resolution_s, 0.0075);
    let text = id.render();
    assert!(text.contains("6 rows (samples 0-2, 127-129)"), "{text}");
    assert!(
        text.contains("[63.2 % point in a gap: tau from the FOPDT fit]"),
        "{text}"
    );
}

/// The thesis' right-motor file with only the PWM columns named, under the given headers (the
/// mean column is then computed).
fn right_columns(columns: &[(&str, &str)]) -> String {
    let mut lines = THESIS_RIGHT_CSV.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let index: Vec<usize> = columns
        .iter()
        .map(|(from, _)| header.iter().position(|h| h == from).unwrap())
        .collect();
    let mut out = String::from("sample,time_s");
    for (_, to) in columns {
        out += &format!(",{to}");
    }
    out.push('\n');
    for line in lines {
        let f: Vec<&str> = line.split(',').collect();
        out += &format!("{},{}", f[0], f[1]);
        for &i in &index {
            out += &format!(",{}", f[i]);
        }
        out.push('\n');
    }
    out
}

/// One PWM level has no steady line through the levels (no incremental gain, no dead band,
/// no Kp with the process gain) and no physical model; `K` per count is `K` over that PWM.
#[test]
fn one_level_gives_no_steady_line_and_no_physical_model() {
    let csv = right_columns(&[("pwm250_rpm", "pwm250_rpm")]);
    let id = identify_csv(csv.as_str(), None).unwrap();
    assert_eq!(id.step_pwm, 250.0);
    assert_eq!(id.gain.k_per_pwm_count, id.k / 250.0);
    assert_eq!(id.gain.incremental_per_pwm_count, None);
    assert_eq!(id.gain.dead_band_pwm, None);
    assert_eq!(id.gain.incremental_per_controller_unit, None);
    assert_eq!(id.kp_with_process_gain, None);
    assert!(id.physical.is_none());
    // Two levels do have both.
    let csv = right_columns(&[("pwm210_rpm", "pwm210_rpm"), ("pwm250_rpm", "pwm250_rpm")]);
    let id = identify_csv(csv.as_str(), None).unwrap();
    assert!(id.gain.incremental_per_pwm_count.unwrap() > 0.0);
    assert!(id.physical.is_some());
}

/// A column that never leaves 0 is refused as a motor that did not turn.
#[test]
fn a_level_that_never_turns_is_refused() {
    let csv = right_columns(&[("pwm210_rpm", "pwm210_rpm"), ("pwm250_rpm", "pwm250_rpm")]);
    let zeroed: String = csv
        .lines()
        .enumerate()
        .map(|(i, l)| {
            if i == 0 {
                format!("{l}\n")
            } else {
                let f: Vec<&str> = l.split(',').collect();
                format!("{},{},0,{}\n", f[0], f[1], f[3])
            }
        })
        .collect();
    let e = identify_csv(zeroed.as_str(), None).unwrap_err().to_string();
    assert!(
        e.contains("pwm210_rpm") && e.contains("did not turn"),
        "{e}"
    );
}

/// A header that names a column twice is refused, naming the column and the line.
#[test]
fn a_column_named_twice_is_refused() {
    let csv = right_columns(&[("pwm210_rpm", "pwm210_rpm"), ("pwm250_rpm", "pwm250_rpm")]);
    let (header, rows) = csv.split_once('\n').unwrap();
    for twice in ["sample", "time_s", "pwm210_rpm"] {
        let text = format!("{header},{twice}\n{}", rows.replace('\n', ",0\n"));
        let e = StepData::parse(&text).unwrap_err().to_string();
        assert!(e.contains(twice) && e.contains("appears twice"), "{e}");
    }
    let text = format!(
        "{header},mean_rpm,mean_rpm\n{}",
        rows.replace('\n', ",0,0\n")
    );
    let e = StepData::parse(&text).unwrap_err().to_string();
    assert!(e.contains("mean_rpm") && e.contains("appears twice"), "{e}");
}

/// Times printed to 1 ms of a 15.2 ms period (0.015, 0.030, 0.046, ...): the period fitted
/// through them is off by rounding and is snapped to the 0.1 ms it was, since every row
/// lies within rounding of that grid.
#[test]
fn the_sample_period_is_snapped_to_what_the_times_were_printed_from() {
    let csv = right_columns(&[("pwm210_rpm", "pwm210_rpm")]);
    let (header, rows) = csv.split_once('\n').unwrap();
    let mut text = format!("{header}\n");
    for line in rows.lines() {
        let (sample, rest) = line.split_once(',').unwrap();
        let (_, value) = rest.split_once(',').unwrap();
        let k: f64 = sample.parse().unwrap();
        text += &format!("{sample},{:.3},{value}\n", k * 0.0152);
    }
    let data = StepData::parse(&text).unwrap();
    assert_eq!(data.sample_period_s, 0.0152);
}
