//! The host's start of a test on the bench: the robot's parameters told
//! over the protocol, then the test started, as the station or a person's
//! host program would do it. Here, above the bench, and not in
//! `crate::firmware::params`, which says what to tell and stays below it.

use henrytwo_protocol::Param;
use plant_model::RobotConfig;

use crate::bench::{Bench, BenchError, UsbState, USB_SERIAL};
use crate::firmware::description::Description;
use crate::firmware::link::{frame, replies, Command};
use crate::firmware::params::{plan, refusals, Tell};

/// The host's start of `test`: the parameters as SET_PARAM frames, then a
/// framed START_TEST, when there is anything to set or `framed` asks for it;
/// else the test's single selector byte (what the thesis build takes).
pub fn start_test(
    bench: &mut Bench,
    params: &[(Param, f32)],
    framed: bool,
    test: henrytwo_protocol::Test,
) {
    use {frame, Command};
    let uart = bench.board().command_uart.usart;
    if framed || !params.is_empty() {
        send(bench, params);
        bench.send(uart, &frame(&Command::StartTest(test)));
    } else {
        bench.send(uart, &[test.command_byte()]);
    }
}

/// `params` as SET_PARAM frames on the board's command link.
fn send(bench: &mut Bench, params: &[(Param, f32)]) {
    let uart = bench.board().command_uart.usart;
    for (p, v) in params {
        bench.send(uart, &frame(&Command::SetParam(*p, *v)));
    }
}

/// Tells an idle, booted firmware on `bench` the robot's geometry (as
/// [`plan`] with [`Tell::Robot`]) and runs until it has answered every
/// SET_PARAM: for a session whose host is someone else (the station's
/// emulated robots), so that it starts on a robot the firmware knows. The
/// replies stay out of what the host is sent afterwards only if the caller
/// forwards output from here on. Returns the warning of a refusal or of a
/// firmware that cannot be told.
pub fn tell(bench: &mut Bench, robot: &RobotConfig) -> Result<Option<String>, BenchError> {
    let (params, _, warning) = plan(bench.firmware(), robot, bench.board(), Tell::Robot, &[]);
    if params.is_empty() {
        return Ok(warning);
    }
    // The board's command link: the one the firmware reads SET_PARAM on.
    let uart = bench.board().command_uart.usart;
    let before = bench.uart_output(uart).len();
    send(bench, &params);
    let set_param = Command::SetParam(Param::CorrLeft, 1.0).id().reply_id();
    let answered = |b: &Bench| {
        replies(&b.uart_output(uart)[before..])
            .iter()
            .filter(|r| r.id == set_param)
            .count()
            >= params.len()
    };
    // 9600 baud: about 10 ms per frame each way.
    bench.run_expect(
        "the firmware did not answer the SET_PARAMs of the robot's geometry",
        1.0 + 0.03 * params.len() as f64,
        answered,
    )?;
    Ok(refusals(&bench.uart_output(uart)[before..], params.len()).or(warning))
}

/// Run a freshly reset `bench` until its firmware is ready for a command: as
/// the test `description` says (a text on a USART, or a time), or, for a
/// firmware with the bench interface, until it reports idle. The one wait
/// every run, the harness, the station and the fuzzer start with.
pub fn wait_ready(bench: &mut Bench, description: Option<&Description>) -> Result<(), BenchError> {
    let Some(d) = description else {
        // A firmware without the interface never says it is idle: say so now.
        bench.vars()?;
        return bench.run_expect(
            "the firmware did not report idle (HT_STATE = 1) after reset",
            2.0,
            |b| b.is_idle(),
        );
    };
    refuse_usb_without_usb(bench, d)?;
    match &d.ready.text {
        Some(t) => {
            let text = t.clone();
            let seen = bench.run_until(d.ready.after_s, |b| {
                contains(b.uart_output(text.usart), &text.text)
            })?;
            if !seen {
                // On the USB serial, where the host got with the device.
                return Err(BenchError::Timeout {
                    what: format!(
                        "{}: the firmware did not send {:?} on {} after reset (ready.text){}",
                        d.path,
                        String::from_utf8_lossy(&text.text),
                        crate::bench::serial_name(text.usart),
                        usb_note(bench, text.usart)
                    ),
                    robot_s: d.ready.after_s,
                    at: bench.location(),
                });
            }
        }
        None => bench.run_for(d.ready.after_s)?,
    }
    Ok(())
}

/// A description that names the USB serial, for a board whose MCU has no
/// USB: refused before the run, in one line.
pub(crate) fn refuse_usb_without_usb(bench: &Bench, d: &Description) -> Result<(), BenchError> {
    d.check_usb(bench.board().mcu)
        .map_err(BenchError::Description)
}

/// Where the USB host stood, for a finding about text on the USB serial
/// that never came: "" for any other link.
pub(crate) fn usb_note(bench: &Bench, usart: u8) -> String {
    match bench.usb_state() {
        Some(s) if usart == USB_SERIAL && *s != UsbState::Open => format!("; USB: {s}"),
        _ => String::new(),
    }
}

/// Whether `needle` occurs in `hay`: a text a firmware printed, among its bytes.
pub(crate) fn contains(hay: &[u8], needle: &[u8]) -> bool {
    hay.windows(needle.len()).any(|w| w == needle)
}
