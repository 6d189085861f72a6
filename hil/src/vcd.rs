//! Value Change Dump traces of a run, for GTKWave or Surfer.
//!
//! Written after the run from what the bench recorded, so tracing costs the
//! simulation nothing but the recording: the encoder lines as raised on the
//! pins, each H-bridge input's duty as the PWM model produced it (and, on
//! request, the 31 kHz waveform itself, generated from the timer model), the
//! motion the bridge commands, the bytes on the UARTs, and the plant's pose
//! and edge counts at the trace samples. Time unit: one CPU cycle (62.5 ns).

use std::fmt::Write as _;

use crate::bench::{DriveEvent, PinEvent, Sample};
use crate::board::Board;
use plant_model::Side;

/// Everything a trace is made of.
pub struct VcdInput<'a> {
    pub clock_hz: u32,
    /// The board the run was wired by: which pins the lines are.
    pub board: &'a Board,
    pub edges: &'a [PinEvent],
    pub drive: &'a [DriveEvent],
    pub uart: &'a [(u64, u8, u8)],
    pub samples: &'a [Sample],
    /// Write each bridge input's PWM waveform edge by edge (large files).
    pub pwm_edges: bool,
}

struct Var {
    id: String,
    name: String,
    kind: &'static str,
    width: u32,
}

/// Render the VCD text.
pub fn render(input: &VcdInput) -> String {
    let mut vars: Vec<Var> = Vec::new();
    let id = |name: &str, kind: &'static str, width: u32, vars: &mut Vec<Var>| {
        let n = vars.len();
        let code = format!("!{}", char::from(b'a' + (n % 26) as u8)) + &"z".repeat(n / 26);
        vars.push(Var {
            id: code.clone(),
            name: name.replace(' ', "_"),
            kind,
            width,
        });
        code
    };
    // The recorder's lines: left A, left B, right A, right B.
    let enc: Vec<String> = [Side::Left, Side::Right]
        .iter()
        .flat_map(|&side| {
            let e = input.board.encoder(side);
            [("A", e.a), ("B", e.b)].map(|(ch, pin)| (side, ch, pin.arduino))
        })
        .map(|(side, ch, pin)| {
            let side = match side {
                Side::Left => "left",
                Side::Right => "right",
            };
            id(&format!("{side}_{ch}_D{pin}"), "wire", 1, &mut vars)
        })
        .collect();
    let bridge: Vec<u8> = input
        .board
        .bridge_inputs()
        .iter()
        .map(|b| b.pin.arduino)
        .collect();
    let pins: Vec<(u8, String, String)> = bridge
        .iter()
        .map(|p| {
            (
                *p,
                id(&format!("D{p}_duty"), "real", 64, &mut vars),
                id(&format!("D{p}_pwm"), "wire", 1, &mut vars),
            )
        })
        .collect();
    let uart: Vec<String> = ["uart0_tx_byte", "uart1_tx_byte"]
        .iter()
        .map(|n| id(n, "wire", 8, &mut vars))
        .collect();
    let plant: Vec<String> = ["x_mm", "y_mm", "theta_rad", "left_edges", "right_edges"]
        .iter()
        .map(|n| id(n, "real", 64, &mut vars))
        .collect();

    let mut out = String::new();
    let _ = writeln!(out, "$comment Henrytwo HIL bench trace $end");
    let _ = writeln!(
        out,
        "$timescale {} ps $end",
        1_000_000_000_000u64 / input.clock_hz as u64
    );
    let b = 4 + 2 * pins.len();
    for (scope, range) in [
        ("encoders", 0..4),
        ("bridge", 4..b),
        ("uart", b..b + 2),
        ("plant", b + 2..b + 7),
    ] {
        let _ = writeln!(out, "$scope module {scope} $end");
        for v in &vars[range] {
            let _ = writeln!(out, "$var {} {} {} {} $end", v.kind, v.width, v.id, v.name);
        }
        let _ = writeln!(out, "$upscope $end");
    }
    let _ = writeln!(out, "$enddefinitions $end");

    // Changes: (cycle, text), sorted stably.
    let mut changes: Vec<(u64, String)> = Vec::new();
    changes.push((
        0,
        format!("$dumpvars\n{}$end", {
            let mut s = String::new();
            for e in &enc {
                let _ = writeln!(s, "0{e}");
            }
            for (_, d, w) in &pins {
                let _ = writeln!(s, "r0 {d}\n0{w}");
            }
            s
        }),
    ));
    for e in input.edges {
        changes.push((
            e.cycle,
            format!("{}{}", u8::from(e.level), enc[e.line as usize]),
        ));
    }
    // Duty per pin, and the waveform from the timer model when asked (mode
    // 1 at clock/1: high for 2*OCR of every 510 cycles, centred on BOTTOM).
    for (pin, duty_id, wave_id) in &pins {
        let events: Vec<&DriveEvent> = input.drive.iter().filter(|e| e.pin == *pin).collect();
        for (i, e) in events.iter().enumerate() {
            changes.push((e.cycle, format!("r{} {duty_id}", e.duty)));
            let until = events.get(i + 1).map_or(e.cycle, |n| n.cycle);
            if e.duty <= 0.0 {
                changes.push((e.cycle, format!("0{wave_id}")));
            } else if e.duty >= 1.0 || !input.pwm_edges {
                changes.push((e.cycle, format!("1{wave_id}")));
            } else if let Some(wave) = e.wave {
                changes.push((
                    e.cycle,
                    format!("{}{wave_id}", u8::from(wave.level(e.cycle))),
                ));
                for (c, level) in wave.edges(e.cycle, until) {
                    changes.push((c, format!("{}{wave_id}", u8::from(level))));
                }
            }
        }
    }
    for &(cycle, n, byte) in input.uart {
        if let Some(u) = uart.get(n as usize) {
            changes.push((cycle, format!("b{byte:08b} {u}")));
        }
    }
    for s in input.samples {
        let c = (s.t_s * input.clock_hz as f64).round() as u64;
        let vals = [
            s.x_mm,
            s.y_mm,
            s.theta_rad,
            s.left_edges as f64,
            s.right_edges as f64,
        ];
        for (v, idv) in vals.iter().zip(&plant) {
            changes.push((c, format!("r{v} {idv}")));
        }
    }
    changes.sort_by_key(|c| c.0);
    let mut last = None;
    for (cycle, text) in changes {
        if last != Some(cycle) {
            let _ = writeln!(out, "#{cycle}");
            last = Some(cycle);
        }
        let _ = writeln!(out, "{text}");
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_and_changes_are_well_formed() {
        let edges = [PinEvent {
            cycle: 100,
            line: 0,
            level: true,
        }];
        let drive = [DriveEvent {
            cycle: 50,
            pin: 7,
            duty: 170.0 / 255.0,
            wave: None,
        }];
        let text = render(&VcdInput {
            clock_hz: 16_000_000,
            board: &Board::default(),
            edges: &edges,
            drive: &drive,
            uart: &[(200, 1, b'A')],
            samples: &[],
            pwm_edges: false,
        });
        assert!(text.contains("$timescale 62500 ps $end"));
        assert!(text.contains("$var wire 1 !a left_A_D2 $end"));
        assert!(text.contains("#100\n1!a"));
        assert!(text.contains("b01000001"));
        // Timestamps increase.
        let stamps: Vec<u64> = text
            .lines()
            .filter_map(|l| l.strip_prefix('#'))
            .map(|t| t.parse().unwrap())
            .collect();
        assert!(stamps.windows(2).all(|w| w[0] < w[1]));
    }
}
