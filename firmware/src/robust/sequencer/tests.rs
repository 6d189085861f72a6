//! The sequencer's host tests: segments, stop rules, braking and faults on
//! the fake hardware.

use std::vec::Vec;

use henrytwo_protocol::{Command, FaultNotice, TestDoneNotice};

use super::*;
use crate::robust::fake::{self, Fake};
use crate::settings::Settings;

/// Another robot: 0.567 mm per count on both wheels, 360 counts per
/// wheel turn, a 180 mm wheelbase.
fn other_robot(app: &mut App<Fake>) {
    app.set_param(Param::MmPerCountLeft, 0.567);
    app.set_param(Param::MmPerCountRight, 0.567);
    app.set_param(Param::CountsPerWheelRev, 360.0);
    app.set_param(Param::WheelbaseMm, 180.0);
}

/// Drives the running leg edge by edge, both wheels alike, until it is
/// cut: the count sum at the cut.
fn drive_leg_to_its_end(app: &mut App<Fake>) -> i32 {
    for _ in 0..100_000 {
        if app.drive.left.stage != Stage::Driving {
            let c = app.drive.encoders.counts;
            return c.left + c.right;
        }
        app.drive.encoders.edge(Side::Left, 1);
        app.poll();
        if app.drive.left.stage == Stage::Driving {
            app.drive.encoders.edge(Side::Right, 1);
            app.poll();
        }
    }
    panic!("the leg never ended");
}

#[test]
fn a_leg_ends_at_the_count_of_the_robots_geometry() {
    let _bench = fake::lock();
    let mut app = App::fake();
    app.start_test(Test::Line).unwrap();
    assert_eq!(drive_leg_to_its_end(&mut app), 23962, "Henrytwo: 4000 mm / 0.16693");
    let mut app = App::fake();
    other_robot(&mut app);
    app.start_test(Test::Line).unwrap();
    assert_eq!(drive_leg_to_its_end(&mut app), 7055, "4000 mm / 0.567 = 7054.67");
}

#[test]
fn another_geometry_turns_by_its_own_count() {
    let _bench = fake::lock();
    let mut app = App::fake();
    other_robot(&mut app);
    app.start_segment(Test::UmbmarkCw, 1);
    // 90 degrees on b = 180 mm: a 141.37 mm arc / 0.567 = 249.3 -> 250.
    app.drive.encoders.move_by(Side::Left, 249);
    app.poll();
    assert_eq!(app.drive.left.stage, Stage::Driving);
    app.drive.encoders.edge(Side::Left, 1);
    app.poll();
    assert_eq!((app.drive.left.stage, bench::cut_left()), (Stage::Coast, 250));
}

#[test]
fn the_time_out_counts_at_the_robots_speed() {
    let _bench = fake::lock();
    let mut app = App::fake();
    other_robot(&mut app);
    app.start_test(Test::Line).unwrap();
    // 3527.3 counts per wheel at 14.47 / 1.8518 = 7.81 counts per period:
    // 451.4 periods, four times that and 2 s.
    let per_count = crate::pid::thesis_rpm(1, 0.015) * (602.22 / 360.0);
    let nominal = 2000.0 / 0.567 / (robot::ROBUST_SETPOINT / per_count);
    assert_eq!(app.segment_limit, (4.0 * nominal) as u32 + 134);
    assert!((1800..1950).contains(&app.segment_limit), "{}", app.segment_limit);
}

/// The time-out of a leg counts the wheel that makes the most counts (the
/// shortest corrected distance per count) at the slower corrected set-point,
/// whichever wheel that is; a turn's counts the wheel with the larger target.
#[test]
fn the_time_out_follows_the_wheel_that_counts_most() {
    let _bench = fake::lock();
    let limit = |counts: f32, app: &App<Fake>| {
        let s = app.stored.settings;
        let set_min = (s.setpoint.left / s.correction.left).min(s.setpoint.right / s.correction.right);
        (TIMEOUT_FACTOR * (counts / (set_min / app.drive.speeds.per_count))) as u32 + TIMEOUT_EXTRA_TICKS
    };
    for (left, right) in [(0.9, 1.0), (1.0, 0.9)] {
        let mut app = App::fake();
        app.set_param(Param::CorrLeft, left);
        app.set_param(Param::CorrRight, right);
        app.start_test(Test::Line).unwrap();
        let m = Settings::DEFAULT.mm_per_count;
        let counts = robot::DEFAULT_LEG_MM / (left * m.left).min(right * m.right);
        assert_eq!(app.segment_limit, limit(counts, &app), "c_L {left}, c_R {right}");
        // Segment 1 of a square: a right turn.
        assert!(matches!(plan::segment(Test::UmbmarkCw, 1), Some(Segment::Turn { .. })));
        app.start_segment(Test::UmbmarkCw, 1);
        let s = app.stored.settings;
        let n = |c: f32, m: f32| spin_target_counts(s.turn_umbmark_deg, s.wheelbase_mm, c, m);
        let counts = n(left, m.left).max(n(right, m.right)) as f32;
        assert_eq!(app.segment_limit, limit(counts, &app), "c_L {left}, c_R {right}");
    }
}

/// Which input of each wheel is driven: +1 forward, -1 reverse, 0 none.
fn directions(app: &App<Fake>) -> (i8, i8) {
    let dir = |(f, r): (u8, u8)| match (f > 0, r > 0) {
        (true, false) => 1,
        (false, true) => -1,
        _ => 0,
    };
    (dir(app.drive.motors.left), dir(app.drive.motors.right))
}

/// A segment's start: its index, `HT_PHASE`, the [`directions`].
type Start = (u8, u8, (i8, i8));

/// Runs `test` on the fake plant (`per_tick` counts per period) until it
/// ends; each segment's start.
fn run(test: Test, leg_mm: f32, per_tick: i32) -> (App<Fake>, Vec<Start>) {
    let mut app = App::fake();
    bench::set_leg_length_mm(leg_mm);
    app.receive(Command::StartTest(test));
    app.poll();
    let mut starts = Vec::new();
    for _ in 0..20_000 {
        if let Mode::Segment { index, .. } = app.mode {
            if starts.last().map(|s: &Start| s.0) != Some(index) {
                starts.push((index, bench::phase_code(), directions(&app)));
            }
        }
        if app.mode == Mode::Idle {
            break;
        }
        app.tick_plant(per_tick);
    }
    (app, starts)
}

const LEG: u8 = Phase::Leg as u8;
const TURN: u8 = Phase::Turn as u8;

#[test]
fn umbmark_cw_drives_four_legs_and_four_right_turns_then_reports() {
    let _bench = fake::lock();
    let (mut app, starts) = run(Test::UmbmarkCw, 50.0, 13);
    let expected: Vec<_> = (0..8).map(|i| if i % 2 == 0 { (i, LEG, (1, 1)) } else { (i, TURN, (1, -1)) }).collect();
    assert_eq!(starts, expected);
    let done = TestDoneNotice { test: Test::UmbmarkCw as u8, tests_done: 1 };
    assert!(app.sent().contains(&(NOTIFY_TEST_DONE, 0, done.to_bytes().to_vec())));
    assert_eq!((bench::done_count(), bench::phase_code(), bench::state_code()), (1, 0, RunState::Idle as u8));
}

#[test]
fn ccw_and_triangle_turn_left_and_a_line_is_one_leg() {
    let _bench = fake::lock();
    let (_, starts) = run(Test::UmbmarkCcw, 50.0, 13);
    assert_eq!(starts.len(), 8);
    assert!(starts.iter().all(|s| s.2 == if s.1 == LEG { (1, 1) } else { (-1, 1) }), "{starts:?}");
    let (_, starts) = run(Test::Triangle, 50.0, 13);
    assert_eq!(starts.iter().map(|s| s.1).collect::<Vec<_>>(), [LEG, TURN, LEG, TURN, LEG, TURN]);
    assert!(starts.iter().all(|s| s.2 == if s.1 == LEG { (1, 1) } else { (-1, 1) }), "{starts:?}");
    let (_, starts) = run(Test::Line, 50.0, 13);
    assert_eq!(starts, [(0, LEG, (1, 1))]);
}

#[test]
fn a_leg_ends_on_the_edge_that_reaches_the_weighted_target() {
    let _bench = fake::lock();
    let mut app = App::fake();
    app.stored.settings.correction = PerWheel { left: 1.02, right: 0.97 };
    bench::set_leg_length_mm(100.0);
    app.start_test(Test::Line).unwrap();
    let m = Settings::DEFAULT.mm_per_count.left;
    let (wl, wr, target) = (leg_weight(1.02, m, m), leg_weight(0.97, m, m), leg_target(100.0, m));
    // The right wheel makes two edges for each of the left's three.
    let mut k = 0;
    loop {
        let side = if k % 5 < 3 { Side::Left } else { Side::Right };
        k += 1;
        let c = app.drive.encoders.counts;
        let before = leg_progress(wl, wr, c.left, c.right);
        app.drive.encoders.edge(side, 1);
        app.poll();
        let c = app.drive.encoders.counts;
        if app.drive.left.stage != Stage::Driving {
            assert!(before < target && leg_progress(wl, wr, c.left, c.right) >= target);
            break;
        }
        assert!(k < 10_000, "the leg never ended");
    }
    let c = app.drive.encoders.counts;
    assert_eq!((app.drive.motors.left, app.drive.motors.right), ((0, 0), (0, 0)));
    assert_eq!((app.drive.left.stage, app.drive.right.stage), (Stage::Coast, Stage::Coast));
    assert_eq!((bench::stop_left(), bench::stop_right()), (c.left, c.right));
    assert_eq!((bench::cut_mask(), bench::phase_code()), (3, Phase::Braking as u8));
}

#[test]
fn a_turn_cuts_each_wheel_at_its_own_target() {
    let _bench = fake::lock();
    let mut app = App::fake();
    app.stored.settings.correction = PerWheel { left: 1.0, right: 0.9 };
    app.mode = Mode::Idle;
    app.start_segment(Test::UmbmarkCw, 1);
    let s = app.stored.settings;
    let m = s.mm_per_count.left;
    let nl = spin_target_counts(s.turn_umbmark_deg, s.wheelbase_mm, 1.0, m);
    let nr = spin_target_counts(s.turn_umbmark_deg, s.wheelbase_mm, 0.9, m);
    assert!(nr > nl);
    // Left forward, right backward (clockwise); the left gets there first.
    app.drive.encoders.move_by(Side::Left, nl - 1);
    app.drive.encoders.move_by(Side::Right, -(nl - 1));
    app.poll();
    assert_eq!((app.drive.left.stage, bench::cut_mask()), (Stage::Driving, 0));
    app.drive.encoders.edge(Side::Left, 1);
    app.poll();
    assert_eq!((app.drive.left.stage, app.drive.right.stage), (Stage::Coast, Stage::Driving));
    assert_eq!((app.drive.motors.left.0, bench::cut_left(), bench::cut_mask()), (0, nl, 1));
    assert!(app.drive.motors.right.1 > 0);
    app.drive.encoders.move_by(Side::Right, -(nr - nl));
    app.poll();
    assert_eq!(app.drive.right.stage, Stage::Driving, "one count short");
    app.drive.encoders.edge(Side::Right, -1);
    app.poll();
    assert_eq!(app.drive.right.stage, Stage::Coast);
    assert_eq!((app.drive.motors.right.1, bench::cut_right(), bench::cut_mask()), (0, -nr, 3));
    assert_eq!(bench::phase_code(), Phase::Braking as u8);
}

#[test]
fn a_cut_wheel_coasts_gets_its_counter_pulse_then_both_waits_pass() {
    let _bench = fake::lock();
    let mut app = App::fake();
    bench::set_leg_length_mm(10.0);
    app.start_test(Test::UmbmarkCw).unwrap();
    while app.drive.left.stage == Stage::Driving {
        app.drive.encoders.edge(Side::Left, 1);
        app.drive.encoders.edge(Side::Right, 1);
        app.poll();
    }
    // The end of the coast is the deadline armed on timer 1's alarm.
    assert!(app.clock.alarm.is_some());
    assert_eq!(app.clock.alarm, app.next_deadline());
    let off = ((0, 0), (0, 0));
    let motors = |app: &App<Fake>| (app.drive.motors.left, app.drive.motors.right);
    app.wait(BRAKE_COAST - 1);
    assert_eq!(motors(&app), off);
    app.wait(1);
    assert_eq!(motors(&app), ((0, 255), (0, 255)), "the counter-pulse is on the reverse inputs");
    app.wait(BRAKE_PULSE - 1);
    assert_eq!(motors(&app), ((0, 255), (0, 255)));
    app.wait(1);
    assert_eq!(motors(&app), off);
    assert!(matches!(app.mode, Mode::Wait { index: 0, stop_general: false, .. }));
    app.wait(INERTIA_WAIT);
    assert!(matches!(app.mode, Mode::Wait { index: 0, stop_general: true, .. }));
    app.wait(STOP_WAIT - 1);
    assert!(matches!(app.mode, Mode::Wait { .. }));
    app.wait(1);
    assert!(matches!(app.mode, Mode::Segment { index: 1, .. }));
    assert_eq!(directions(&app), (1, -1));
}

/// Once one wheel is cut the other's control ticks go on, and so does the
/// segment's time-out, until that wheel is cut too.
#[test]
fn the_ticks_go_on_while_one_wheel_still_drives() {
    let _bench = fake::lock();
    let mut app = App::fake();
    // A turn whose right wheel has the larger target (as in the test above).
    app.stored.settings.correction = PerWheel { left: 1.0, right: 0.9 };
    app.mode = Mode::Idle;
    app.start_segment(Test::UmbmarkCw, 1);
    let s = app.stored.settings;
    let nl = spin_target_counts(s.turn_umbmark_deg, s.wheelbase_mm, 1.0, s.mm_per_count.left);
    app.drive.encoders.move_by(Side::Left, nl);
    app.drive.encoders.move_by(Side::Right, -nl);
    app.poll();
    assert_eq!((app.drive.left.stage, app.drive.right.stage), (Stage::Coast, Stage::Driving));
    let before = app.segment_ticks;
    app.tick_plant(0);
    app.tick_plant(0);
    assert_eq!(app.segment_ticks, before + 2);
}

/// The period the bench reads is that of the control step: one tick's, or
/// the ticks' a late step covers at once.
#[test]
fn the_bench_reads_the_period_of_each_control_step() {
    let _bench = fake::lock();
    let mut app = App::fake();
    app.mode = Mode::Idle;
    app.start_segment(Test::Line, 0);
    app.on_tick(1);
    assert_eq!(bench::period_us(), PERIOD_US);
    app.on_tick(3);
    assert_eq!(bench::period_us(), 3.0 * PERIOD_US);
    app.on_tick(1);
    assert_eq!(bench::period_us(), PERIOD_US);
}

/// A segment clears each wheel's other input before it drives the one it
/// needs (both inputs of a DRV8833 high is a brake), whatever was left on.
#[test]
fn a_segment_clears_the_other_input_before_driving() {
    let _bench = fake::lock();
    let mut app = App::fake();
    app.mode = Mode::Idle;
    app.drive.set(Side::Left, false, 255);
    app.drive.set(Side::Right, false, 255);
    app.start_segment(Test::UmbmarkCw, 0);
    let duty = robot::START_DUTY;
    assert_eq!((app.drive.motors.left, app.drive.motors.right), ((duty, 0), (duty, 0)));
    // The spin after it: left forward, right reverse.
    app.drive.set(Side::Left, false, 255);
    app.drive.set(Side::Right, true, 255);
    app.start_segment(Test::UmbmarkCw, 1);
    assert_eq!((app.drive.motors.left, app.drive.motors.right), ((duty, 0), (0, duty)));
}

/// A wheel cut while the other still drives goes through its own coast and
/// counter-pulse on time (its deadline the one armed); the other drives on,
/// with its control ticks, and the segment goes on until both are done.
/// Either wheel may be the one cut first.
#[test]
fn a_cut_wheel_brakes_on_time_while_the_other_drives() {
    for cut in [Side::Left, Side::Right] {
        let _bench = fake::lock();
        let mut app = App::fake();
        app.mode = Mode::Idle;
        assert_eq!(app.next_deadline(), None);
        // The wheel with the larger factor counts fewer counts to its end.
        app.stored.settings.correction =
            if cut == Side::Left { PerWheel { left: 1.0, right: 0.9 } } else { PerWheel { left: 0.9, right: 1.0 } };
        app.start_segment(Test::UmbmarkCw, 1);
        let s = app.stored.settings;
        let m = if cut == Side::Left { s.mm_per_count.left } else { s.mm_per_count.right };
        let n = spin_target_counts(s.turn_umbmark_deg, s.wheelbase_mm, 1.0, m);
        // A clockwise spin: left forward, right reverse.
        app.drive.encoders.move_by(Side::Left, n);
        app.drive.encoders.move_by(Side::Right, -n);
        app.poll();
        let stages = |app: &App<Fake>| (app.drive.left.stage, app.drive.right.stage);
        let want = |st: Stage| if cut == Side::Left { (st, Stage::Driving) } else { (Stage::Driving, st) };
        let cut_motor =
            |app: &App<Fake>| if cut == Side::Left { app.drive.motors.left } else { app.drive.motors.right };
        assert_eq!(stages(&app), want(Stage::Coast), "{cut:?}");
        let until = app.drive.wheel(cut).until;
        assert_eq!(until.wrapping_sub(app.clock.now), BRAKE_COAST);
        assert_eq!(app.next_deadline(), Some(until));
        // Still a turn to the bench (and its run state driving) until both are cut.
        assert_eq!((bench::phase_code(), bench::state_code()), (TURN, RunState::Driving as u8));
        let ticks = app.segment_ticks;
        app.wait(BRAKE_COAST);
        assert_eq!(stages(&app), want(Stage::Pulse), "{cut:?}");
        // The counter-pulse, on the input opposite to the wheel's way.
        let pulse = if cut == Side::Left { (0, 255) } else { (255, 0) };
        assert_eq!(cut_motor(&app), pulse, "{cut:?}");
        app.wait(BRAKE_PULSE);
        assert_eq!(stages(&app), want(Stage::Done), "{cut:?}");
        assert_eq!(cut_motor(&app), (0, 0));
        assert_eq!(bench::phase_code(), TURN);
        assert!(matches!(app.mode, Mode::Segment { index: 1, .. }), "{cut:?}");
        app.tick_plant(0);
        assert!(app.segment_ticks > ticks, "{cut:?}: the other wheel's ticks go on");
    }
}

#[test]
fn a_segment_that_overruns_its_time_is_a_fault() {
    let _bench = fake::lock();
    // Two counts per period: slow, but enough progress for the stall
    // watchdog.
    let (mut app, _) = run(Test::Line, 2000.0, 2);
    // Four times the nominal time of the leg (in periods), and 2 s.
    let counts = 2000.0 / Settings::DEFAULT.mm_per_count.left;
    let nominal = counts / (robot::ROBUST_SETPOINT / crate::pid::thesis_rpm(1, robot::SAMPLE_PERIOD_S));
    assert_eq!(app.segment_limit, (4.0 * nominal) as u32 + 134);
    let faults: Vec<_> = app.sent().into_iter().filter(|s| s.0 == NOTIFY_FAULT).collect();
    assert_eq!(faults.len(), 1, "{faults:?}");
    let notice = FaultNotice::decode(&faults[0].2).unwrap();
    assert_eq!(notice.fault, Fault::SegmentTimeout as u8);
    assert_eq!(app.segment_ticks, app.segment_limit + 1);
    assert_eq!((app.drive.motors.left, app.drive.motors.right), ((0, 0), (0, 0)));
    assert_eq!((bench::phase_code(), bench::fault()), (Phase::Fault as u8, Fault::SegmentTimeout as u8));
    let line = std::format!("fault {} in test 4 segment 0:", Fault::SegmentTimeout as u8);
    assert!(app.debug.text().contains(&line), "{}", app.debug.text());
}

#[test]
fn a_still_wheel_is_stopped_as_stalled() {
    let _bench = fake::lock();
    let (mut app, _) = run(Test::Line, 50.0, 0);
    let faults: Vec<_> = app.sent().into_iter().filter(|s| s.0 == NOTIFY_FAULT).collect();
    assert_eq!(faults.len(), 1, "{faults:?}");
    assert_eq!(FaultNotice::decode(&faults[0].2).unwrap().fault, Fault::StallLeft as u8);
    assert_eq!((app.drive.motors.left, app.drive.motors.right), ((0, 0), (0, 0)));
    assert_eq!(app.mode, Mode::Idle);
    assert!(app.segment_ticks < 40, "stopped after {} ticks", app.segment_ticks);
}

#[test]
fn each_tick_reads_the_battery_and_shows_its_colour() {
    let _bench = fake::lock();
    let mut app = App::fake();
    app.tick_plant(0);
    assert_eq!(app.adc.started, 1);
    assert_eq!(app.leds.shown, None, "no conversion was running before the first tick");
    app.adc.value = 900;
    app.tick_plant(0);
    assert_eq!((app.leds.shown, bench::battery_adc()), (Some(battery::Colour::Red), 900));
    app.tick_plant(0);
    assert_eq!(app.leds.writes, 1, "an unchanged colour is not written again");
}

/// A stop lead ends a leg the distance earlier both wheels cover in it at
/// their set-points: 150 ms is 10 periods of 13.07 counts (14.47 thesis
/// RPM / 1.107) on Henrytwo, 21.82 mm, 261 counts of the two wheels'
/// sum; lead 0 is the target to the count.
#[test]
fn a_stop_lead_ends_a_leg_earlier_by_the_set_point_distance() {
    let _bench = fake::lock();
    let mut app = App::fake();
    app.set_param(Param::StopLeadMs, 150.0);
    app.start_test(Test::Line).unwrap();
    let sum = drive_leg_to_its_end(&mut app);
    assert!((23962 - 262..=23962 - 260).contains(&sum), "{sum}");
    let mut app = App::fake();
    app.set_param(Param::StopLeadMs, 0.0);
    app.start_test(Test::Line).unwrap();
    assert_eq!(drive_leg_to_its_end(&mut app), 23962);
}

/// A turn wheel with a stop lead is looked at twice the lead at its
/// set-point before its target, and cut the lead at its measured speed
/// before it: at twice the set-point speed, 261 counts before 612.
#[test]
fn a_turn_wheel_with_a_lead_is_cut_by_its_measured_speed() {
    let _bench = fake::lock();
    let mut app = App::fake();
    app.set_param(Param::StopLeadMs, 150.0);
    app.start_segment(Test::UmbmarkCw, 1);
    // Look-ahead at 612 - 2 * 131 = 350.
    app.drive.encoders.move_by(Side::Left, 349);
    app.poll();
    assert_eq!(app.drive.left.stage, Stage::Driving);
    bench::set_speed_left(2.0 * 14.47);
    app.drive.encoders.edge(Side::Left, 1);
    app.poll();
    assert_eq!(app.drive.left.stage, Stage::Driving);
    app.drive.encoders.edge(Side::Left, 1);
    app.poll();
    assert_eq!((app.drive.left.stage, bench::cut_left()), (Stage::Coast, 351));
}

/// The brake's coast and pulse are the settings'.
#[test]
fn the_brake_timing_is_the_settings() {
    let _bench = fake::lock();
    let mut app = App::fake();
    app.set_param(Param::BrakeCoastMs, 40.0);
    other_robot(&mut app);
    app.start_segment(Test::UmbmarkCw, 1);
    app.drive.encoders.move_by(Side::Left, 250);
    app.poll();
    assert_eq!(app.drive.left.stage, Stage::Coast);
    assert_eq!(app.drive.left.until.wrapping_sub(app.clock.now), time::ms(40));
}
