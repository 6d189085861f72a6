//! `hil bench` compares the bench with raw simavr replaying the bench run's
//! inputs; the comparison only means something if the replay executes the
//! same program path. These tests hold the replay to that.

#[path = "support/mod.rs"]
mod support;

use hil::runs::experiment::Test;
use hil::runs::perf::{bench_run, bench_run_described, raw_replay};

#[test]
fn a_raw_replay_ends_in_the_bench_runs_firmware_state() {
    let fw = support::firmware("robust");
    let rec = bench_run(&fw, &support::robot("henrytwo"), Test::Line, 400.0, true).unwrap();
    assert!(rec.completed, "the line did not complete on the bench");
    assert!(
        rec.edges.len() > 100,
        "too few edges recorded: {}",
        rec.edges.len()
    );
    for simavr_pwm_timers in [false, true] {
        let replay = raw_replay(&fw, &rec, simavr_pwm_timers).unwrap();
        assert!(
            replay.faithful,
            "replay (simavr PWM timers {simavr_pwm_timers}) diverged"
        );
        assert_eq!(replay.measured.robot_s, rec.measured.robot_s);
    }
}

/// The thesis sketch, run black-box from its description: the replay of
/// its bench run (one selector byte, no bench variables) ends in the same
/// SRAM, so `hil bench`'s black-box ratio compares the same instructions.
#[test]
fn a_black_box_runs_replay_ends_in_the_bench_runs_firmware_state() {
    let root = hil::paths::workspace_root();
    let d = hil::firmware::description::Description::load(
        root.join("firmware/arduino/henrytwo-thesis/tests.toml"),
    )
    .unwrap();
    let fw = hil::firmware::elf::Firmware::load(d.elf.as_ref().unwrap())
        .unwrap_or_else(|e| panic!("{e} (run tools/setup.sh)"));
    let board = hil::board::Board::default();
    let test = Test::Line.into();
    let rec =
        bench_run_described(&fw, &support::robot("henrytwo"), &test, &d, &board, true).unwrap();
    assert!(rec.completed, "the sketch's line did not end on the bench");
    assert!(rec.edges.len() > 100, "{} edges recorded", rec.edges.len());
    let replay = raw_replay(&fw, &rec, false).unwrap();
    assert!(replay.faithful, "the sketch's replay diverged");
    assert_eq!(replay.measured.robot_s, rec.measured.robot_s);
}

#[test]
fn a_replay_missing_an_input_is_caught() {
    let fw = support::firmware("robust");
    let mut rec = bench_run(&fw, &support::robot("henrytwo"), Test::Line, 400.0, true).unwrap();
    // Without the battery on A0 the firmware reads a flat battery.
    rec.analog.clear();
    assert!(!raw_replay(&fw, &rec, false).unwrap().faithful);
    // Without the last quarter of the encoder edges the counts fall short.
    let mut rec2 = bench_run(&fw, &support::robot("henrytwo"), Test::Line, 400.0, true).unwrap();
    let keep = rec2.edges.len() * 3 / 4;
    rec2.edges.truncate(keep);
    assert!(!raw_replay(&fw, &rec2, false).unwrap().faithful);
}

/// The callbacks of planned encoder edges leave the plant alone (the plan
/// knows the levels), and so do reads of a lazy B shortly after them: the
/// run is the one a bench that brings the plant to every edge gives, to the
/// cycle and the bit. With B raised lazily (only
/// when read) the B lines may be brought up to date at other cycles, which
/// the firmware cannot tell: then the A lines must match; with every
/// transition raised at its own cycle, all of them.
#[test]
fn edges_raised_from_the_plan_change_nothing() {
    use hil::bench::BenchOptions;
    use hil::runs::line::ready_bench;
    let robot = support::robot("henrytwo");
    let run = |lean: bool, true_waveforms: bool| {
        let (mut bench, before, _) = ready_bench(
            support::firmware("robust"),
            &robot,
            BenchOptions::default(),
            300.0,
        )
        .unwrap();
        if !lean {
            bench.advance_plant_at_every_edge();
        }
        if true_waveforms {
            bench.true_waveforms();
        }
        bench.start_recording();
        let vars = *bench.vars().expect("our builds have the bench interface");
        bench.send(1, &[Test::UmbmarkCw.command_byte()]);
        let done = bench
            .run_until(40.0, |b| {
                b.read_u16(vars.done_count) != before && b.is_idle()
            })
            .unwrap();
        assert!(done, "the square did not complete (lean {lean})");
        let core = bench.core();
        let pose = core.robot().pose();
        let sram: Vec<u8> = (0x200..0x2200).map(|a| bench.read_u8(a)).collect();
        let stats = core
            .pin_stats()
            .iter()
            .map(|p| (p.active_s.to_bits(), p.mean_active_duty.to_bits()))
            .collect::<Vec<_>>();
        let lines = core.recording().unwrap().to_vec();
        let a_lines: Vec<_> = lines.iter().copied().filter(|e| e.line % 2 == 0).collect();
        (
            bench.cycle(),
            sram,
            (a_lines, if true_waveforms { lines } else { Vec::new() }),
            [pose.x().0, pose.y().0, pose.theta().0].map(f64::to_bits),
            stats,
            core.edges_raised(),
            core.lean_edge_callbacks(),
            core.quiet_b_reads(),
        )
    };
    for true_waveforms in [false, true] {
        let lean = run(true, true_waveforms);
        let full = run(false, true_waveforms);
        assert_eq!(
            full.6, 0,
            "the bench raised edges from the plan when told not to"
        );
        let a_edges = lean.2 .0.len() as u64;
        assert!(
            lean.6 > a_edges / 2,
            "too few callbacks raised edges from the plan alone: {} for {a_edges} A edges",
            lean.6,
        );
        // Reads of a lazy B shortly after a planned A edge need no plant.
        assert_eq!(full.7, 0, "B read from the plan when told not to");
        if !true_waveforms {
            assert!(lean.7 > a_edges / 2, "only {} quiet B reads", lean.7);
        }
        assert_eq!(lean.0, full.0, "end cycle");
        assert!(lean.1 == full.1, "the firmware's memory differs");
        assert!(lean.2 == full.2, "the lines raised differ");
        assert_eq!(lean.3, full.3, "end pose");
        assert_eq!(lean.4, full.4, "PWM statistics");
        assert_eq!(lean.5, full.5, "edges raised");
    }
}

/// `hil bench --tests FILE --board BOARD [--robot ROBOT]`, once, without
/// simavr's own PWM timers: its output.
fn hil_bench(tests: &str, board: &str, robot: Option<&str>) -> std::process::Output {
    let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_hil"));
    cmd.current_dir(hil::paths::workspace_root())
        .args(["bench", "--tests", tests, "--board", board])
        .args(["--repeats", "1", "--without-simavr-pwm"]);
    if let Some(robot) = robot {
        cmd.args(["--robot", robot]);
    }
    cmd.output().unwrap()
}

/// `hil bench --tests` on a busy Arduino sketch of `name` on its board's
/// MCU: the bench run and the raw simavr replay of the same ELF and inputs
/// end in the same SRAM (or it exits 1), and the ratio is printed. A
/// benchmark: the ratio itself is not held to a bound.
#[track_caller]
fn hil_bench_prints_a_ratio(name: &str, test: &str, board: &str, robot: Option<&str>) {
    let tests = format!("fixtures/arduino/{name}/tests.toml");
    let out = hil_bench(&tests, board, robot);
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{name}: {stderr}");
    assert!(stdout.starts_with(&format!("speed of {test}")), "{stdout}");
    let ratio = stdout
        .lines()
        .find_map(|l| {
            l.trim()
                .strip_prefix("bench overhead over raw simavr (no PWM timers): ")
        })
        .and_then(|l| l.strip_suffix(&format!("x {name}")))
        .unwrap_or_else(|| panic!("no ratio: {stdout}"));
    assert!(ratio.parse::<f64>().unwrap() > 0.0, "{stdout}");
}

/// The Uno robot's own sketch (a busy loop on the ATmega328P, its board's
/// encoders and USART).
#[test]
fn hil_bench_times_the_uno_robots_sketch_against_raw_simavr() {
    hil_bench_prints_a_ratio(
        "uno-l298n",
        "leg-and-spin",
        "fixtures/boards/uno-l298n.toml",
        Some("fixtures/robots/uno-l298n.toml"),
    );
}

/// The Romi's own sketch on the ATmega32U4: xor-wired encoders, timer 1's
/// PWM, Serial1; its USB cable out, as `hil run` runs it (the replay has no
/// USB host).
#[test]
fn hil_bench_times_the_romis_sketch_against_raw_simavr() {
    hil_bench_prints_a_ratio(
        "romi-32u4",
        "leg-and-spin",
        "fixtures/boards/romi-32u4.toml",
        Some("fixtures/robots/romi-32u4.toml"),
    );
}

/// A busy sketch on the ATmega2560 with INPUT_PULLUP encoders on a port it
/// writes every control period.
#[test]
fn hil_bench_times_a_mega_sketch_against_raw_simavr() {
    hil_bench_prints_a_ratio(
        "pullup-encoders",
        "line",
        "fixtures/boards/mega-l298n.toml",
        None,
    );
}

/// A test talking over the USB serial cannot be replayed in raw simavr (no
/// USB host): refused in one line before anything runs.
#[test]
fn hil_bench_refuses_a_test_on_the_usb_serial() {
    let out = hil_bench(
        "fixtures/arduino/usb-serial/tests.toml",
        "fixtures/boards/leonardo-usb.toml",
        None,
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains("ready.uart names the USB serial") && stderr.contains("no USB host"),
        "{stderr}"
    );
    assert!(out.stdout.is_empty());
}
