//! One test of a described firmware: reset, wait until it is ready, start
//! the test as the description says, run until its end condition, analyse
//! as for any firmware (legs and turns from the bridge, pose from the plant).

use plant_model::{RobotConfig, Seconds};

use super::{analyse, limit_s, Shape, ShapeRule, TestName, TestOptions, TestRun};
use crate::bench::{
    serial_name, Bench, BenchError, Motion, Observer, SERIALS, USB_FRAME_S, USB_SERIAL,
};
use crate::firmware::description::{Description, DescriptionError, End, Start};
use crate::firmware::elf::Firmware;
use crate::runs::start::{contains, refuse_usb_without_usb, usb_note};

impl From<DescriptionError> for BenchError {
    fn from(e: DescriptionError) -> Self {
        BenchError::Description(e.to_string())
    }
}

/// Whether `m` drives a wheel (a leg, a turn, a pulse).
fn driven(m: Motion) -> bool {
    !matches!(m, Motion::Stopped | Motion::Brake)
}

/// Where the outputs stood at the start: what the end looks past.
#[derive(Clone, Copy)]
pub(crate) struct Mark {
    motions: usize,
    uart: [usize; SERIALS],
}

impl Mark {
    pub(crate) fn now(b: &Bench) -> Self {
        Mark {
            motions: b.core().motions().len(),
            uart: std::array::from_fn(|n| b.uart_output(n as u8).len()),
        }
    }
}

/// Cycles the end text's bytes take on the wire, at the board's baud for its
/// USART (9600, the Arduino examples' rate, for a USART the board does not
/// wire), 10 bits a byte.
fn wire_cycles(bench: &Bench, text: Option<&crate::firmware::description::UartText>) -> u64 {
    let Some(t) = text else { return 0 };
    if t.usart == USB_SERIAL {
        // A packet a frame: written a frame before the host read it, at most.
        return bench
            .clock()
            .cycles_in(Seconds(USB_FRAME_S * t.text.len().div_ceil(64) as f64));
    }
    let baud = bench
        .board()
        .uarts()
        .iter()
        .find(|(_, u)| u.usart == t.usart)
        .map_or(9600, |(_, u)| u.baud);
    let s = t.text.len() as f64 * 10.0 / f64::from(baud);
    bench.clock().cycles_in(Seconds(s))
}

/// The cycle of the first change of the motion since `mark` that drives a
/// wheel.
fn first_drive(b: &Bench, mark: Mark) -> Option<u64> {
    b.core().motions()[mark.motions..]
        .iter()
        .find(|m| driven(m.motion))
        .map(|m| m.at.cycle)
}

/// The test has ended by `end`'s rule (see [`End`]).
pub(crate) fn ended(b: &Bench, end: &End, idle_cycles: u64, mark: Mark) -> bool {
    if let Some(t) = &end.text {
        let out = b.uart_output(t.usart);
        return contains(&out[mark.uart[t.usart as usize].min(out.len())..], &t.text);
    }
    let motions = &b.core().motions()[mark.motions..];
    let Some(last) = motions.last() else {
        return false;
    };
    motions.iter().any(|m| driven(m.motion))
        && !driven(last.motion)
        && b.cycle() - last.at.cycle >= idle_cycles
}

/// Run `test` of the firmware `d` describes, from a fresh reset.
pub(crate) fn run_described(
    firmware: Firmware,
    robot: &RobotConfig,
    test: &TestName,
    opts: &TestOptions,
    d: &Description,
    observer: Option<Box<dyn Observer>>,
) -> Result<(TestRun, Option<Box<dyn Observer>>), BenchError> {
    // The USB cable is in only for a test that talks over it: a robot
    // driving its test is not tethered, and the host's frames and a
    // control transfer's waits inside the firmware's USB interrupt would
    // change its timing.
    let options = crate::bench::BenchOptions {
        usb_cable: d.usb_field().is_some(),
        ..opts.bench
    };
    let mut bench = Bench::new(firmware, robot, options)?;
    let run = run_described_on(&mut bench, test, opts, d, observer)?;
    Ok((run, bench.take_observer()))
}

/// [`run_described`]'s run on a bench fresh from reset (one a debugger may
/// drive: the same run, step for step); the observer stays on the bench.
pub(crate) fn run_described_on(
    bench: &mut Bench,
    test: &TestName,
    opts: &TestOptions,
    d: &Description,
    observer: Option<Box<dyn Observer>>,
) -> Result<TestRun, BenchError> {
    let described = d.test(test.clone())?;
    refuse_usb_without_usb(bench, d)?;
    let start = described.start.clone();
    // Its own end, else the description's: one end for every test stopped
    // a square at a text its other test prints midway.
    let end = d.end_of(test).clone();
    // Its own shape is judged exactly; a thesis name lends its shape.
    let shape = match (described.shape, test.thesis()) {
        (Some(s), _) => Some((s, ShapeRule::Exact)),
        (None, Some(t)) => Some((Shape::of(t), ShapeRule::Lent)),
        (None, None) => None,
    };
    let resolved = d.resolve(bench.firmware())?;
    if !opts.params.is_empty() {
        return Err(BenchError::Description(format!(
            "{}: the firmware it describes has no protocol to set parameters with; drop --param",
            d.path
        )));
    }
    let name = d.firmware_name(bench.firmware());
    if let Some(c) = resolved.counts {
        bench.set_count_variables(c);
    }
    crate::runs::start::wait_ready(bench, Some(d))?;
    if let Some(addr) = resolved.leg {
        bench.write_f32(addr, opts.leg_mm as f32);
    }
    bench.set_observer(observer);
    for f in &opts.faults {
        bench.schedule(f.trigger, f.action.clone(), f.undo.clone());
    }
    super::record(bench, opts);
    let start_cycle = bench.cycle();
    let mark = Mark::now(bench);
    match &start {
        Start::Uart { usart, bytes } => bench.send(*usart, bytes),
        Start::Pin { pin, high } => {
            let mcu = bench.board().mcu;
            let p = crate::board::pin_named(mcu, pin).ok_or_else(|| {
                BenchError::Description(format!(
                    "{}: pin {pin:?} is no pin of the board's {mcu}",
                    d.path
                ))
            })?;
            bench.drive_pin(p, *high)?
        }
    }
    let limit = opts
        .limit_s
        .or(end.limit_s)
        .unwrap_or_else(|| limit_s(shape.as_ref().map(|(s, _)| s), opts) + end.idle_s);
    let idle_cycles = bench.clock().cycles_in(Seconds(end.idle_s));
    bench.set_hang_after(opts.hang_after_s);
    let outcome = bench.run_until(limit, |b| ended(b, &end, idle_cycles, mark));
    bench.set_hang_after(None);
    let (completed, hang) = match outcome {
        Ok(done) => (done, None),
        Err(BenchError::Hang(report)) => (false, Some(report)),
        Err(e) => return Err(e),
    };
    // Where what the firmware does after the test begins: a drive that
    // starts after the end text belongs to what comes next, not to the test.
    let mut cut = None;
    if completed && end.text.is_some() {
        // Ended by a text: let the last coast end (the motors idle for
        // half a second, at most 5 s more), and the UARTs drain (the end
        // text's line end is still on the wire), unless the firmware
        // drives again first.
        let half = bench.clock().cycles_in(Seconds(0.5));
        let after_text = End {
            text: None,
            ..end.clone()
        };
        // The firmware wrote the text before its last byte arrived: a drive
        // it started once it had written it (the bytes still on the wire)
        // is after the test too.
        let since = bench
            .cycle()
            .saturating_sub(wire_cycles(bench, end.text.as_ref()));
        let text_mark = Mark {
            motions: bench
                .core()
                .motions()
                .partition_point(|m| m.at.cycle < since),
            ..Mark::now(bench)
        };
        let drives = |b: &Bench| first_drive(b, text_mark);
        bench.run_until(5.0, |b| {
            ended(b, &after_text, half, mark) || drives(b).is_some()
        })?;
        if drives(bench).is_none() {
            bench.run_until(0.1, |b| drives(b).is_some())?;
        }
        cut = drives(bench);
    } else if completed {
        // Let the UARTs drain, as for the bench's own builds.
        bench.run_for(0.1)?;
    }
    let finding = match &hang {
        Some(h) => Some(format!(
            "hung: no wheel motion and no change of the motor drive for {:.1} s of robot time, {h}",
            h.still_s
        )),
        None => (!completed).then(|| {
            format!(
                "did not end ({}{}) within {limit:.0} s of robot time; the firmware is {}",
                end_rule(&end),
                end.text
                    .as_ref()
                    .map_or(String::new(), |t| usb_note(bench, t.usart)),
                bench.location()
            )
        }),
    };
    let mut run = analyse(
        bench,
        test.clone(),
        shape,
        name,
        opts,
        start_cycle..cut.unwrap_or(u64::MAX),
        completed,
        finding,
    );
    run.hang = hang;
    Ok(run)
}

/// The end rule in words, for findings.
fn end_rule(end: &End) -> String {
    match &end.text {
        Some(t) => format!(
            "no {:?} on {}",
            String::from_utf8_lossy(&t.text),
            serial_name(t.usart)
        ),
        None => format!("the motors never idle for {} s after driving", end.idle_s),
    }
}
