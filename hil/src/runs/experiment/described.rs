//! One test of a described firmware: reset, wait until it is ready, start
//! the test as the description says, run until its end condition, analyse
//! as for any firmware (legs and turns from the bridge, pose from the plant).

use plant_model::{RobotConfig, Seconds};

use super::{analyse, limit_s, Test, TestOptions, TestRun};
use crate::bench::{Bench, BenchError, Motion, Observer};
use crate::firmware::description::{Description, DescriptionError, End, Start};
use crate::firmware::elf::Firmware;
use crate::runs::start::contains;

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
    uart: [usize; 4],
}

impl Mark {
    pub(crate) fn now(b: &Bench) -> Self {
        Mark {
            motions: b.core().motions().len(),
            uart: [0, 1, 2, 3].map(|n| b.uart_output(n).len()),
        }
    }
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
    test: Test,
    opts: &TestOptions,
    d: &Description,
    observer: Option<Box<dyn Observer>>,
) -> Result<(TestRun, Option<Box<dyn Observer>>), BenchError> {
    let mut bench = Bench::new(firmware, robot, opts.bench)?;
    let run = run_described_on(&mut bench, test, opts, d, observer)?;
    Ok((run, bench.take_observer()))
}

/// [`run_described`]'s run on a bench fresh from reset (one a debugger may
/// drive: the same run, step for step); the observer stays on the bench.
pub(crate) fn run_described_on(
    bench: &mut Bench,
    test: Test,
    opts: &TestOptions,
    d: &Description,
    observer: Option<Box<dyn Observer>>,
) -> Result<TestRun, BenchError> {
    let start = d.start(test)?.clone();
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
    if opts.record {
        bench.true_waveforms();
        bench.start_recording();
    }
    let start_cycle = bench.cycle();
    let mark = Mark::now(bench);
    match &start {
        Start::Uart { usart, bytes } => bench.send(*usart, bytes),
        Start::Pin { pin, high } => bench.drive_pin(*pin, *high)?,
    }
    let limit = opts
        .limit_s
        .or(d.end.limit_s)
        .unwrap_or_else(|| limit_s(test, opts) + d.end.idle_s);
    let idle_cycles = bench.clock().cycles_in(Seconds(d.end.idle_s));
    bench.set_hang_after(opts.hang_after_s);
    let outcome = bench.run_until(limit, |b| ended(b, &d.end, idle_cycles, mark));
    bench.set_hang_after(None);
    let (completed, hang) = match outcome {
        Ok(done) => (done, None),
        Err(BenchError::Hang(report)) => (false, Some(report)),
        Err(e) => return Err(e),
    };
    if completed && d.end.text.is_some() {
        // Ended by a text: let the last coast end (the motors idle for
        // half a second, at most 5 s more).
        let half = bench.clock().cycles_in(Seconds(0.5));
        let after_text = End {
            text: None,
            ..d.end.clone()
        };
        bench.run_until(5.0, |b| ended(b, &after_text, half, mark))?;
    }
    if completed {
        // Let the UARTs drain, as for the bench's own builds: the end
        // text's line end is still on the wire when the text ends the test.
        bench.run_for(0.1)?;
    }
    let finding = match &hang {
        Some(h) => Some(format!(
            "hung: no wheel motion and no change of the motor drive for {:.1} s of robot time, {h}",
            h.still_s
        )),
        None => (!completed).then(|| {
            format!(
                "did not end ({}) within {limit:.0} s of robot time; the firmware is {}",
                end_rule(&d.end),
                bench.location()
            )
        }),
    };
    let mut run = analyse(bench, test, name, opts, start_cycle, completed, finding);
    run.hang = hang;
    Ok(run)
}

/// The end rule in words, for findings.
fn end_rule(end: &End) -> String {
    match &end.text {
        Some(t) => format!(
            "no {:?} on USART {}",
            String::from_utf8_lossy(&t.text),
            t.usart
        ),
        None => format!("the motors never idle for {} s after driving", end.idle_s),
    }
}
