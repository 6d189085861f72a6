//! A bench run recorded for replay: the inputs the firmware was given, at
//! their cycles, and the state it ended in.

use std::time::Instant;

use plant_model::RobotConfig;

use super::Measured;
use crate::bench::{AnalogEvent, BenchError, BenchOptions, PinEvent};
use crate::board::Board;
use crate::firmware::description::Description;
use crate::firmware::elf::Firmware;
use crate::mcu::chip::Chip;
use crate::runs::experiment::{Shape, Test, TestName};
use crate::runs::line::ready_bench;

/// A bench run recorded for replay.
pub struct Recorded {
    pub measured: Measured,
    pub awake_fraction: f64,
    pub callbacks: u64,
    /// Callbacks that raised planned edges from the plan alone.
    pub lean_edge_callbacks: u64,
    /// Reads of a lazy B answered from the last A edge.
    pub quiet_b_reads: u64,
    /// Reads of a lazy B in all.
    pub b_reads: u64,
    pub command_cycle: u64,
    /// The start: one byte on this USART.
    pub command_usart: u8,
    pub command: u8,
    /// RAM the bench wrote before the command (the leg length), written by
    /// the replay at the command's cycle too.
    pub pokes: Vec<(u16, u8)>,
    pub end_cycle: u64,
    pub edges: Vec<PinEvent>,
    pub analog: Vec<AnalogEvent>,
    pub completed: bool,
    /// SRAM at the end, which a faithful replay must reach.
    pub fingerprint: Vec<u8>,
    /// The board the run was wired as: the replay's MCU, encoder pins,
    /// USARTs and timers.
    pub board: Board,
}

/// The state a replay must end in: all of the MCU's internal SRAM,
/// variables and stack alike (the IO registers differ with simavr's own PWM
/// timers, which is the point of that replay).
pub(super) fn fingerprint(chip: &Chip, read: impl Fn(u16) -> u8) -> Vec<u8> {
    chip.sram_range().map(read).collect()
}

/// Run `test` on the bench; with `record`, recording the inputs a replay
/// needs (which costs the bench time and memory no scenario spends: the
/// timed runs do not record).
#[inline(never)] // profiled by name: see docs/design/performance.md
pub fn bench_run(
    fw: &Firmware,
    robot: &RobotConfig,
    test: Test,
    leg_mm: f64,
    record: bool,
) -> Result<Recorded, BenchError> {
    let wall = Instant::now();
    let (mut bench, before, command_cycle) =
        ready_bench(fw.clone(), robot, BenchOptions::default(), leg_mm)?;
    let vars = *bench.vars()?;
    if record {
        bench.start_recording();
    }
    let usart = bench.board().command_uart.usart;
    bench.send(usart, &[test.command_byte()]);
    let (legs, turns, _) = test.shape();
    let limit = legs as f64 * (leg_mm / 50.0 + 3.0) + turns as f64 * 8.0 + 5.0;
    let completed = bench.run_until(limit, |b| {
        b.read_u16(vars.done_count) != before && b.is_idle()
    })?;
    let start = Start {
        cycle: command_cycle,
        usart,
        byte: test.command_byte(),
        pokes: (vars.leg_length_mm..)
            .zip((leg_mm as f32).to_le_bytes())
            .collect(),
    };
    Ok(recorded(&bench, wall, start, completed))
}

/// The one byte on a USART that starts `test` of `d`, which a raw simavr
/// replay can give: refused otherwise (said before anything runs).
pub fn replayable_start(d: &Description, test: &TestName) -> Result<(u8, u8), BenchError> {
    // Raw simavr has no USB host to replay, so a test that talks over the
    // USB serial cannot be timed against it; any other runs with the cable
    // out, as `hil run` runs it (the host's frames would change its timing).
    if let Some(field) = d.usb_field() {
        return Err(BenchError::Description(format!(
            "{}: {field} names the USB serial; hil bench replays the run in raw simavr, which \
             has no USB host: time a test started and ended on a USART",
            d.path
        )));
    }
    match &d.test(test.clone())?.start {
        crate::firmware::description::Start::Uart { usart, bytes } if bytes.len() == 1 => {
            Ok((*usart, bytes[0]))
        }
        _ => Err(BenchError::Description(format!(
            "{}: hil bench replays a test started by one byte on a USART; {} is not",
            d.path,
            test.name()
        ))),
    }
}

/// Run `test` of a firmware without the bench interface, as `d` describes
/// it (started by one byte on a USART), on `board`, recording as
/// [`bench_run`] does.
pub fn bench_run_described(
    fw: &Firmware,
    robot: &RobotConfig,
    test: &TestName,
    d: &Description,
    board: &Board,
    record: bool,
) -> Result<Recorded, BenchError> {
    let described = d.test(test.clone())?;
    let (usart, byte) = replayable_start(d, test)?;
    let wall = Instant::now();
    let opts = BenchOptions {
        board: *board,
        usb_cable: false, // see `replayable_start`
        ..Default::default()
    };
    let mut bench = crate::bench::Bench::new(fw.clone(), robot, opts)?;
    if let Some(c) = d.resolve(fw)?.counts {
        bench.set_count_variables(c);
    }
    crate::runs::start::wait_ready(&mut bench, Some(d))?;
    if record {
        bench.start_recording();
    }
    let command_cycle = bench.cycle();
    let mark = crate::runs::experiment::Mark::now(&bench);
    bench.send(usart, &[byte]);
    let leg_mm = d.leg_mm(None, 2000.0)?;
    // The test's own end and limit, as a run of it has.
    let end = d.end_of(test);
    let shape = described.shape.or(test.thesis().map(Shape::of));
    let limit = end.limit_s.unwrap_or_else(|| {
        let opts = crate::runs::experiment::TestOptions {
            leg_mm,
            ..Default::default()
        };
        crate::runs::experiment::limit_s(shape.as_ref(), &opts) + end.idle_s
    });
    let idle = bench.clock().cycles_in(plant_model::Seconds(end.idle_s));
    let completed = bench.run_until(limit, |b| {
        crate::runs::experiment::ended(b, end, idle, mark)
    })?;
    let start = Start {
        cycle: command_cycle,
        usart,
        byte,
        pokes: Vec::new(),
    };
    Ok(recorded(&bench, wall, start, completed))
}

/// How a recorded run was started.
struct Start {
    cycle: u64,
    usart: u8,
    byte: u8,
    pokes: Vec<(u16, u8)>,
}

fn recorded(bench: &crate::bench::Bench, wall: Instant, start: Start, completed: bool) -> Recorded {
    let wall_s = wall.elapsed().as_secs_f64();
    let end_cycle = bench.cycle();
    let fingerprint = fingerprint(bench.board().mcu.chip(), |a| bench.read_u8(a));
    let board = *bench.board();
    let core = bench.core();
    Recorded {
        measured: Measured::new(bench.robot_time_s(), wall_s),
        awake_fraction: bench.awake_fraction(),
        callbacks: core.callbacks(),
        lean_edge_callbacks: core.lean_edge_callbacks(),
        quiet_b_reads: core.quiet_b_reads(),
        b_reads: core.quiet_b_reads() + core.b_reads_evaluated(),
        command_cycle: start.cycle,
        command_usart: start.usart,
        command: start.byte,
        pokes: start.pokes,
        end_cycle,
        edges: core.recording().unwrap_or_default().to_vec(),
        analog: core.analog_log().to_vec(),
        completed,
        fingerprint,
        board,
    }
}
