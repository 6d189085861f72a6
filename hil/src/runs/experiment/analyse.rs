//! What a run did, from outside the firmware: legs and turns from the
//! H-bridge inputs ([`Motion`] events, debounced), distances and angles from
//! the plant, the firmware's counters where the bench knows them.

use plant_model::Side;

use super::{FinalPose, Fragments, Leg, Shape, TestName, TestOptions, TestRun, Turn};
use crate::bench::{Bench, Motion, MotionEvent, Snapshot};
use crate::firmware::params::Believed;

/// How a run is judged by its shape.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum ShapeRule {
    /// More legs or turns than the shape is a fragmented run (the bench's
    /// own builds, the thesis' tests).
    Fragments,
    /// Any other count of legs or turns, or a turn the other way, is a run
    /// that did not drive the test (a described test's own `shape`).
    Exact,
    /// The shape is only lent (a described firmware's test under a thesis
    /// name): fragments are a warning.
    Lent,
}

#[allow(clippy::too_many_arguments)]
pub(crate) fn analyse(
    bench: &Bench,
    test: TestName,
    shape: Option<(Shape, ShapeRule)>,
    firmware: String,
    opts: &TestOptions,
    span: std::ops::Range<u64>,
    mut completed: bool,
    mut finding: Option<String>,
) -> TestRun {
    let core = bench.core();
    let motions: Vec<MotionEvent> = core
        .motions()
        .iter()
        .filter(|m| span.contains(&m.at.cycle))
        .copied()
        .collect();
    let end = bench_now(bench);
    let clock = bench.clock();
    let pulse_cycles = clock.cycles_in(plant_model::Seconds(PULSE_MAX_S));
    let stale = core.stale_level_cycles();
    let motions = debounced(&motions, stale);
    let segments = segments(&motions, pulse_cycles);
    let mut legs = Vec::new();
    let mut turns = Vec::new();
    for (k, seg) in segments.iter().enumerate() {
        let start = motions[seg.start].at;
        let stop = motions.get(seg.stop).map(|e| e.at).unwrap_or(end);
        tracing::debug!(
            motion = ?motions[seg.start].motion,
            from_s = clock.seconds(start.cycle).0,
            to_s = clock.seconds(stop.cycle).0,
            "segment: the bridge inputs drove the motors"
        );
        // At rest: when the next segment starts (after braking and waits),
        // or at the end of the run.
        let rest = segments
            .get(k + 1)
            .map(|n| motions[n.start].at)
            .unwrap_or(end);
        match motions[seg.start].motion {
            Motion::Forward => legs.push(Leg {
                plant_distance_mm: (rest.x_mm - start.x_mm).hypot(rest.y_mm - start.y_mm),
                plant_arc_mm: ((rest.left_mm - start.left_mm) + (rest.right_mm - start.right_mm))
                    / 2.0,
                plant_heading_change_deg: (rest.theta_rad - start.theta_rad).to_degrees(),
                firmware_count_left: diff(stop.left_count, start.left_count),
                firmware_count_right: diff(stop.right_count, start.right_count),
                plant_edges_left: stop.left_edges - start.left_edges,
                plant_edges_right: stop.right_edges - start.right_edges,
                start_cycle: start.cycle,
                cutoff_cycle: stop.cycle,
            }),
            Motion::SpinCw | Motion::SpinCcw => {
                // A motor's cut-off may come after the other's braking pulse
                // has begun: look until the next segment starts.
                let until = segments
                    .get(k + 1)
                    .map_or(u64::MAX, |n| motions[n.start].at.cycle);
                let cutoff = |side: Side| {
                    core.cutoffs()
                        .iter()
                        .find(|c| {
                            c.side == side
                                && c.at.cycle >= start.cycle
                                && c.at.cycle < until
                                && c.lasted(stale)
                        })
                        .map(|c| c.at)
                };
                let left = cutoff(Side::Left);
                let right = cutoff(Side::Right);
                turns.push(Turn {
                    count_left_at_cutoff: left.and_then(|c| diff(c.left_count, start.left_count)),
                    count_right_at_cutoff: right
                        .and_then(|c| diff(c.right_count, start.right_count)),
                    plant_angle_deg: (rest.theta_rad - start.theta_rad).to_degrees(),
                    plant_left_mm: rest.left_mm - start.left_mm,
                    plant_right_mm: rest.right_mm - start.right_mm,
                    start_cycle: start.cycle,
                    cutoff_left_cycle: left.map(|c| c.cycle),
                    cutoff_right_cycle: right.map(|c| c.cycle),
                });
            }
            _ => {}
        }
    }
    // Only a run that finished can be judged by its shape: a hung one has
    // its own finding.
    let fragments = shape
        .filter(|_| completed)
        .and_then(|(s, _)| Fragments::of(&s, legs.len(), turns.len(), &motions));
    let mut warnings = never_fired(bench, opts);
    let angles: Vec<f64> = turns.iter().map(|t| t.plant_angle_deg).collect();
    let differs = match shape {
        Some((s, ShapeRule::Exact)) if completed => s.differs(legs.len(), &angles),
        _ => None,
    };
    // An injected fault may cut a leg by design: its case judges the run.
    // A described firmware's test under a thesis name only borrows the
    // thesis' name, not its shape (a sketch's "line" may end in a spin).
    // Either way what differs is named, not made the run's end.
    let lent = matches!(shape, Some((_, ShapeRule::Lent)));
    let judged = opts.faults.is_empty() && !lent;
    let why = differs
        .map(|d| format!("did not drive the shape of {test}: {d}"))
        .or_else(|| fragments.as_ref().map(|f| f.describe(test.name())));
    let mut off_shape = None;
    if let Some(why) = why {
        if judged {
            completed = false;
            finding = Some(why.clone());
            off_shape = Some(why);
        } else {
            warnings.push(why);
        }
    }
    let (ix, iy) = shape.map_or((0.0, 0.0), |(s, _)| s.ideal_end(opts.leg_mm));
    TestRun {
        test,
        shape: shape.map(|(s, _)| s),
        firmware,
        seed: opts.bench.seed,
        completed,
        finding,
        hang: None,
        legs,
        turns,
        fragments,
        off_shape,
        final_pose: FinalPose {
            x_mm: end.x_mm,
            y_mm: end.y_mm,
            theta_deg: end.theta_rad.to_degrees(),
        },
        x_cm: (end.x_mm - ix) / 10.0,
        y_cm: (end.y_mm - iy) / 10.0,
        robot_time_s: bench.robot_time_s(),
        awake_fraction: bench.awake_fraction(),
        skipped_cycles: bench.skipped_cycles(),
        trace: core.trace().to_vec(),
        motions,
        applied: core.applied().to_vec(),
        fault_code: bench
            .firmware()
            .variable("HT_FAULT", 1)
            .ok()
            .map(|a| bench.read_u8(a)),
        bluetooth_out: bench.uart_output(bench.board().command_uart.usart).to_vec(),
        uarts: super::uarts::outputs(bench),
        edges: core.recording().unwrap_or_default().to_vec(),
        drive: core.drive_log().to_vec(),
        uart: core.uart_log().to_vec(),
        uart_rx: core.uart_rx_log().to_vec(),
        leds: core.leds().to_vec(),
        brownouts: core
            .brownouts()
            .iter()
            .map(|(on, off)| {
                let s = |c: u64| bench.clock().seconds(c).0;
                (s(*on), off.map(s))
            })
            .collect(),
        believed: Believed::factory(),
        warnings: warnings.into_iter().chain(core.record_notices()).collect(),
        faults_never_fired: bench.faults_never_fired(),
    }
}

/// "scenario fault 2 (encoder at 90 s) never fired", for each fault of
/// `opts` the run did not reach: its numbers show no fault, not a firmware
/// that survived one.
fn never_fired(bench: &Bench, opts: &TestOptions) -> Vec<String> {
    bench
        .faults_never_fired()
        .into_iter()
        .filter_map(|i| {
            let f = opts.faults.get(i)?;
            Some(format!(
                "scenario fault {} ({} {}) never fired",
                i + 1,
                f.action.name(),
                f.trigger
            ))
        })
        .collect()
}

/// A counter's change between two snapshots, when the bench reads it.
fn diff(to: Option<i32>, from: Option<i32>) -> Option<i32> {
    Some(to? - from?)
}

/// `motions` without the changes that lasted less than `stale` cycles
/// (a stale level while the firmware writes a bridge's inputs one after the
/// other is no cut-off), and with repeats merged.
fn debounced(motions: &[MotionEvent], stale: u64) -> Vec<MotionEvent> {
    let mut out: Vec<MotionEvent> = Vec::with_capacity(motions.len());
    for (i, m) in motions.iter().enumerate() {
        let lasted = motions
            .get(i + 1)
            .is_none_or(|next| next.at.cycle - m.at.cycle >= stale);
        if lasted && out.last().is_none_or(|l| l.motion != m.motion) {
            out.push(*m);
        }
    }
    out
}

/// Driven phases shorter than this are braking pulses, not legs or turns
/// (the thesis brakes with 5 ms of full reverse).
const PULSE_MAX_S: f64 = 0.03;

/// A leg or turn: motion events `start..stop`, where `stop` is the first
/// event at which no motor drives any more (or the end).
#[derive(Debug, Clone, Copy)]
struct Segment {
    start: usize,
    stop: usize,
}

fn segments(motions: &[MotionEvent], pulse_cycles: u64) -> Vec<Segment> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < motions.len() {
        let driven = matches!(
            motions[i].motion,
            Motion::Forward | Motion::SpinCw | Motion::SpinCcw | Motion::Reverse
        );
        if !driven {
            i += 1;
            continue;
        }
        // A turn goes on through phases where one motor is already cut; a
        // leg through a control period or two where one wheel's drive is
        // zero (the thesis' PID clamps a negative output to 0) and back.
        let mut j = i + 1;
        while j < motions.len()
            && (motions[j].motion == Motion::OneWheel
                || (motions[j].motion == motions[i].motion
                    && motions[j - 1].motion == Motion::OneWheel
                    && motions[i].motion == Motion::Forward))
        {
            j += 1;
        }
        let long = motions
            .get(j)
            .is_none_or(|e| e.at.cycle - motions[i].at.cycle > pulse_cycles);
        if long && motions[i].motion != Motion::Reverse {
            out.push(Segment { start: i, stop: j });
        }
        i = j;
    }
    out
}

fn bench_now(bench: &Bench) -> Snapshot {
    let core = bench.core();
    let pose = core.robot().pose();
    let counts = bench.counts();
    Snapshot {
        cycle: bench.cycle(),
        x_mm: pose.x().0,
        y_mm: pose.y().0,
        theta_rad: pose.theta().0,
        left_count: counts.map(|c| c[0]),
        right_count: counts.map(|c| c[1]),
        left_edges: core.robot().counted_edges(plant_model::Side::Left),
        right_edges: core.robot().counted_edges(plant_model::Side::Right),
        left_mm: core.robot().distance_travelled(plant_model::Side::Left).0,
        right_mm: core.robot().distance_travelled(plant_model::Side::Right).0,
    }
}

#[cfg(test)]
pub(super) mod tests;
