//! Fuzzing the robust firmware's UART parser inside the emulator: seeded
//! random and mutated invalid frames, sent at the link's real pace, with
//! checks that the firmware never hangs, never resets, answers afterwards and
//! keeps its state (no invalid frame may change anything).

use plant_model::RobotConfig;
use serde::Serialize;

use crate::bench::inject::Dice;
use crate::bench::{Bench, BenchError, BenchOptions};
use crate::firmware::elf::Firmware;
use crate::firmware::link::{frame, replies, Command, Param};
use crate::runs::start::wait_ready;

/// How one invalid frame is made.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Mutation {
    /// A valid command with one byte after the start flipped: the CRC fails
    /// (or the length no longer fits).
    FlippedByte,
    /// A valid command cut short: the inter-byte timeout ends it.
    Truncated,
    /// A well-formed frame with an unknown command id.
    UnknownCommand,
    /// A well-formed SET_PARAM with a value outside its range (or NaN).
    OutOfRange,
    /// Random bytes that never contain the raw selectors 2..5 on their own.
    Noise,
}

const MUTATIONS: [Mutation; 5] = [
    Mutation::FlippedByte,
    Mutation::Truncated,
    Mutation::UnknownCommand,
    Mutation::OutOfRange,
    Mutation::Noise,
];

/// One invalid frame, and whether the line must then stay quiet for the
/// parser's inter-byte timeout (a truncated frame only ends with silence).
pub fn invalid_frame(d: &mut Dice) -> (Mutation, Vec<u8>, bool) {
    let m = MUTATIONS[(d.next_u64() % MUTATIONS.len() as u64) as usize];
    match m {
        Mutation::FlippedByte => {
            let mut f = frame(&Command::SetParam(Param::WheelbaseMm, 111.0));
            let i = 1 + (d.next_u64() as usize % (f.len() - 1));
            f[i] ^= 1 << (d.next_u64() % 8);
            (m, f, true)
        }
        Mutation::Truncated => {
            let f = frame(&Command::SetParam(Param::CorrLeft, 1.1));
            let keep = 1 + (d.next_u64() as usize % (f.len() - 1));
            (m, f[..keep].to_vec(), true)
        }
        Mutation::UnknownCommand => {
            let id = 0x40 + (d.next_u64() % 0x3F) as u8;
            let payload = [id, d.next_u64() as u8];
            let mut f = vec![0xA5, payload.len() as u8];
            f.extend(payload);
            f.push(henrytwo_protocol::crc::crc8(
                &[&[payload.len() as u8][..], &payload[..]].concat(),
            ));
            (m, f, false)
        }
        Mutation::OutOfRange => {
            let (p, v) = match d.next_u64() % 4 {
                0 => (Param::WheelbaseMm, 1.0e6),
                1 => (Param::CorrLeft, 0.01),
                2 => (Param::SetpointRight, -3.0),
                _ => (Param::LegLengthMm, f32::NAN),
            };
            (m, frame(&Command::SetParam(p, v)), false)
        }
        Mutation::Noise => {
            let n = 1 + d.next_u64() as usize % 12;
            let bytes = (0..n)
                .map(|_| loop {
                    let b = d.next_u64() as u8;
                    if !(2..=5).contains(&b) {
                        break b;
                    }
                })
                .collect();
            (m, bytes, true)
        }
    }
}

#[derive(Debug, Clone, Serialize)]
pub struct FuzzReport {
    pub frames: usize,
    pub seed: u64,
    pub by_mutation: Vec<(Mutation, usize)>,
    pub error_replies: usize,
    pub ok_replies: usize,
    pub resets: usize,
    pub hung: bool,
    pub state_changed: bool,
    pub robot_time_s: f64,
}

impl FuzzReport {
    pub fn passed(&self) -> bool {
        self.resets == 0 && !self.hung && !self.state_changed && self.ok_replies == 0
    }
}

fn state(b: &mut Bench) -> Result<Vec<u8>, BenchError> {
    // Every parameter the protocol can set, read back over the protocol.
    let cmd = b.board().command_uart.usart;
    let before = b.uart_output(cmd).len();
    for p in [
        Param::CorrLeft,
        Param::CorrRight,
        Param::WheelbaseMm,
        Param::LegLengthMm,
    ] {
        b.send(cmd, &frame(&Command::GetParam(p)));
    }
    b.run_for(0.2)?;
    let mut out: Vec<u8> = replies(&b.uart_output(cmd)[before..])
        .into_iter()
        .flat_map(|r| r.data)
        .collect();
    out.extend(b.read_u16(b.vars()?.done_count).to_le_bytes());
    Ok(out)
}

/// Send `frames` invalid frames into the robust firmware.
pub fn fuzz(
    firmware: Firmware,
    robot: &RobotConfig,
    frames: usize,
    seed: u64,
    progress: &dyn Fn(usize),
) -> Result<FuzzReport, BenchError> {
    let mut b = Bench::new(firmware, robot, BenchOptions::default())?;
    wait_ready(&mut b, None)?;
    let before = state(&mut b)?;
    // The board's links: the protocol's, and the one the firmware prints on.
    let (cmd, debug) = (b.board().command_uart.usart, b.board().debug_uart.usart);
    let boot_lines = |b: &Bench| {
        String::from_utf8_lossy(b.uart_output(debug))
            .matches("ready")
            .count()
    };
    let boots = boot_lines(&b);
    let mut dice = Dice::new(seed);
    let mut counts = [0usize; 5];
    let start = b.uart_output(cmd).len();
    for i in 0..frames {
        let (m, bytes, quiet) = invalid_frame(&mut dice);
        counts[MUTATIONS.iter().position(|x| *x == m).unwrap_or(0)] += 1;
        b.send(cmd, &bytes);
        // Let the bytes go out (about 1.04 ms each), the reply come back, and
        // for a frame that ends only in silence, the 50 ms timeout pass.
        let wait = bytes.len() as f64 * 1.1e-3 + if quiet { 0.06 } else { 0.02 };
        b.run_for(wait)?;
        if i % 1000 == 0 {
            progress(i);
        }
    }
    b.run_for(0.2)?;
    let got = replies(&b.uart_output(cmd)[start..]);
    let after = state(&mut b)?;
    // The firmware still answers.
    let ping_from = b.uart_output(cmd).len();
    b.send(cmd, &frame(&Command::Ping));
    b.run_for(0.1)?;
    let hung = !replies(&b.uart_output(cmd)[ping_from..])
        .iter()
        .any(|r| r.ok);
    Ok(FuzzReport {
        frames,
        seed,
        by_mutation: MUTATIONS.iter().copied().zip(counts).collect(),
        error_replies: got.iter().filter(|r| !r.ok).count(),
        ok_replies: got.iter().filter(|r| r.ok).count(),
        resets: boot_lines(&b) - boots,
        hung,
        state_changed: before != after,
        robot_time_s: b.robot_time_s(),
    })
}
