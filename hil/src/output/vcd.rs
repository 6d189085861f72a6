//! Value Change Dump traces of a run, for GTKWave, Surfer and sigrok.
//!
//! Written as the run makes it ([`VcdWriter`], given the bench's records as
//! they are made: `hil run --vcd`) or after the run from what the bench
//! recorded ([`write`]), the same bytes either way: the encoder lines as raised on the
//! pins, each H-bridge input's duty as the PWM model produced it (and, on
//! request, the 31 kHz waveform itself, generated from the timer model), the
//! board's UARTs as the bit-level waveforms on their pins in both directions
//! (8N1 at the board's baud rate: sigrok's `uart` decoder reads them), each
//! byte's value beside them, the USB serial's bytes on an MCU with USB
//! (values and text: USB has no 8N1 line to draw), and the plant's pose and edge counts at the
//! trace samples. Time unit: one CPU cycle (62.5 ns).
//!
//! Every digital line is a 1-bit wire and every value a `real`: sigrok-cli's
//! VCD input reads only 1-bit wires and skips reals, and stops at the first
//! change of a wider wire; GTKWave and Surfer read both. Each UART direction
//! also has a `string` variable (GTKWave's extension, shown as text; sigrok
//! skips it): the line of text so far, unprintable bytes as `\xNN`. Every
//! variable has a value in `$dumpvars` (a UART line idles high; a byte value
//! is 0 until the first byte). A bridge input's 1-bit trace is its PWM
//! waveform (`Dn_pwm`) only when the edges were asked for; otherwise it is a
//! level, high while the input is driven at all, and named so (`Dn_driven`).
//! [`gtkw`] writes a GTKWave save file that opens the trace beside it zoomed
//! to the whole run, each wheel's drive beside its encoder.

use std::fmt::Write as _;
use std::io::Write;

use crate::bench::{DriveEvent, PinEvent, Sample};
use crate::board::Board;
use plant_model::Side;

/// Everything a trace is made of.
pub struct VcdInput<'a> {
    pub clock_hz: u32,
    /// The board the run was wired by: which pins the lines are, the UARTs'
    /// baud rates.
    pub board: &'a Board,
    pub edges: &'a [PinEvent],
    pub drive: &'a [DriveEvent],
    /// Bytes the firmware sent: (cycle its frame started on the TX pin,
    /// USART, byte).
    pub uart_tx: &'a [(u64, u8, u8)],
    /// Bytes the host sent: (cycle the receiver had the byte, its stop bit
    /// done; USART, byte).
    pub uart_rx: &'a [(u64, u8, u8)],
    pub samples: &'a [Sample],
    /// Write each bridge input's PWM waveform edge by edge (large files).
    pub pwm_edges: bool,
}

mod stream;

pub use stream::VcdWriter;

/// A variable of the trace, as declared.
struct Var {
    id: String,
    name: String,
    kind: &'static str,
}

/// The variables of a trace: their identifiers and declarations by scope,
/// and which variable is which line or value (indices into `ids`).
struct Layout {
    clock_hz: u32,
    pwm_edges: bool,
    scopes: Vec<(&'static str, Vec<Var>)>,
    ids: Vec<String>,
    /// The encoder lines: left A, left B, right A, right B (None: a
    /// one-channel encoder's B, on no pin).
    encoders: [Option<u32>; 4],
    /// Per bridge input: (pin, duty, 1-bit trace).
    pins: Vec<(u8, u32, u32)>,
    /// Per UART: (USART, cycles per bit, [TX line, RX line, TX byte, RX
    /// byte, TX text, RX text]).
    uarts: Vec<(u8, f64, [u32; 6])>,
    /// The USB serial, on an MCU with USB: [TX byte, RX byte, TX text, RX
    /// text]. Its bytes travel in USB packets on D+/D-, not as 8N1 frames
    /// on a pin: a trace has their values and text, and no line.
    usb: Option<[u32; 4]>,
    /// x, y, theta, left and right edge counts.
    plant: [u32; 5],
}

impl Layout {
    /// A new variable in `scope` (the last one opened): its index.
    fn add(&mut self, scope: &'static str, name: &str, kind: &'static str) -> u32 {
        let n = self.ids.len();
        let id = format!("!{}", char::from(b'a' + (n % 26) as u8)) + &"z".repeat(n / 26);
        if self.scopes.last().map(|s| s.0) != Some(scope) {
            self.scopes.push((scope, Vec::new()));
        }
        self.scopes.last_mut().expect("just pushed").1.push(Var {
            id: id.clone(),
            name: name.replace(' ', "_"),
            kind,
        });
        self.ids.push(id);
        n as u32
    }

    /// The header, with each variable's value before its first change: the
    /// encoder lines' `levels`, the plant's first sample (0 without one);
    /// a UART line idles high, every other value is 0 (a text empty).
    fn header(&self, levels: [bool; 4], sample: Option<[f64; 5]>) -> String {
        let mut initial: Vec<String> = Vec::with_capacity(self.ids.len());
        for (_, list) in &self.scopes {
            for v in list {
                initial.push(match v.kind {
                    "real" => format!("r0 {}", v.id),
                    "string" => format!("s {}", v.id),
                    _ if v.name.starts_with("uart") => format!("1{}", v.id),
                    _ => format!("0{}", v.id),
                });
            }
        }
        for (line, var) in self.encoders.iter().enumerate() {
            let Some(var) = *var else { continue };
            initial[var as usize] = format!("{}{}", u8::from(levels[line]), self.ids[var as usize]);
        }
        let sample = sample.unwrap_or_default();
        for (v, &var) in sample.iter().zip(&self.plant) {
            initial[var as usize] = format!("r{v} {}", self.ids[var as usize]);
        }
        let mut out = String::new();
        let _ = writeln!(out, "$comment Henrytwo HIL bench trace $end");
        if !self.pwm_edges {
            let _ = writeln!(
                out,
                "$comment bridge.Dn_driven is a level (high while the input's duty is above 0), not the PWM waveform: hil run --vcd-pwm writes that as Dn_pwm $end"
            );
        }
        let _ = writeln!(
            out,
            "$timescale {} ps $end",
            1_000_000_000_000u64 / self.clock_hz as u64
        );
        for (scope, list) in &self.scopes {
            let _ = writeln!(out, "$scope module {scope} $end");
            for v in list {
                let width = if v.kind == "real" { 64 } else { 1 };
                // GTKWave reads a string variable's width as 1.
                let _ = writeln!(out, "$var {} {width} {} {} $end", v.kind, v.id, v.name);
            }
            let _ = writeln!(out, "$upscope $end");
        }
        let _ = writeln!(out, "$enddefinitions $end");
        let _ = writeln!(out, "#0\n$dumpvars");
        for v in &initial {
            let _ = writeln!(out, "{v}");
        }
        let _ = writeln!(out, "$end");
        out
    }
}

/// The variables of a trace of a run on `board`, in the order they are
/// declared.
fn layout(board: &Board, clock_hz: u32, pwm_edges: bool) -> Layout {
    let mut l = Layout {
        clock_hz,
        pwm_edges,
        scopes: Vec::new(),
        ids: Vec::new(),
        encoders: [None; 4],
        pins: Vec::new(),
        uarts: Vec::new(),
        usb: None,
        plant: [0; 5],
    };
    // The recorder's lines: left A, left B, right A, right B.
    for side in [Side::Left, Side::Right] {
        let s = match side {
            Side::Left => "left",
            Side::Right => "right",
        };
        for (ch, (name, pin)) in board.encoder(side).lines().into_iter().enumerate() {
            let var = l.add("encoders", &format!("{s}_{name}_{}", pin.name()), "wire");
            l.encoders[2 * side.index() + ch] = Some(var);
        }
    }
    for p in board.bridge_inputs().iter().map(|b| b.number()) {
        let duty = l.add("bridge", &format!("D{p}_duty"), "real");
        let wave = l.add("bridge", &wave_name(p, pwm_edges), "wire");
        l.pins.push((p, duty, wave));
    }
    for (n, baud) in uarts(board) {
        let ids = [
            ("tx", "wire"),
            ("rx", "wire"),
            ("tx_byte", "real"),
            ("rx_byte", "real"),
            ("tx_text", "string"),
            ("rx_text", "string"),
        ]
        .map(|(what, kind)| l.add("uart", &format!("uart{n}_{what}"), kind));
        l.uarts
            .push((n, f64::from(clock_hz) / f64::from(baud), ids));
    }
    if board.mcu.chip().usb.is_some() {
        let ids = USB_VARS.map(|(what, kind)| l.add("usb", &format!("usb_serial_{what}"), kind));
        l.usb = Some(ids);
    }
    for (i, n) in ["x_mm", "y_mm", "theta_rad", "left_edges", "right_edges"]
        .iter()
        .enumerate()
    {
        l.plant[i] = l.add("plant", n, "real");
    }
    l
}

/// The USB serial's variables, by name and kind, in [`Layout::usb`]'s order.
const USB_VARS: [(&str, &str); 4] = [
    ("tx_byte", "real"),
    ("rx_byte", "real"),
    ("tx_text", "string"),
    ("rx_text", "string"),
];

/// The board's UARTs in USART order, each once: (USART, baud).
fn uarts(board: &Board) -> Vec<(u8, u32)> {
    board
        .uarts()
        .iter()
        .map(|(_, u)| (u.usart, u.baud))
        .collect()
}

/// The level changes of an 8N1 frame of `byte` logged at `cycle` at
/// `cycles_per_bit`, the line at `level` and free from `free` on: start bit
/// low, bits LSB first, stop bit high. A frame never starts before the one
/// before it has ended. The changes, and when this frame ends.
fn frame_bits(
    cycle: u64,
    byte: u8,
    free: u64,
    level: &mut bool,
    cycles_per_bit: f64,
) -> (Vec<(u64, bool)>, u64) {
    let mut out = Vec::new();
    let start = cycle.max(free);
    let at = |k: u32| start + (f64::from(k) * cycles_per_bit).round() as u64;
    let bits = std::iter::once(false)
        .chain((0..8).map(|i| byte >> i & 1 == 1))
        .chain(std::iter::once(true));
    for (k, bit) in (0u32..).zip(bits) {
        if bit != *level {
            out.push((at(k), bit));
            *level = bit;
        }
    }
    (out, at(10))
}

/// The level changes of 8N1 frames of `bytes` (start cycle, byte), the
/// line idle (high) before the first.
#[cfg(test)]
fn frames(bytes: impl Iterator<Item = (u64, u8)>, cycles_per_bit: f64) -> Vec<(u64, bool)> {
    let (mut free, mut level, mut out) = (0, true, Vec::new());
    for (cycle, byte) in bytes {
        let (edges, end) = frame_bits(cycle, byte, free, &mut level, cycles_per_bit);
        out.extend(edges);
        free = end;
    }
    out
}

/// A bridge input's 1-bit trace: named for what it shows.
fn wave_name(pin: u8, pwm_edges: bool) -> String {
    if pwm_edges {
        format!("D{pin}_pwm")
    } else {
        format!("D{pin}_driven")
    }
}

/// The longest text a UART's string variable shows before it starts anew
/// (framed binary has no newline to end a line on).
const TEXT_MAX: usize = 48;

/// `line` with `byte` added, as the UART's string variable shows it: the
/// text of the line so far, printable ASCII as itself and anything else
/// escaped (a VCD value holds no whitespace); after a newline the next byte
/// starts a new line.
fn line_text(line: &mut String, byte: u8) -> String {
    if line.ends_with("\\n") || line.len() >= TEXT_MAX {
        line.clear();
    }
    match byte {
        b'\n' => line.push_str("\\n"),
        b'\r' => line.push_str("\\r"),
        b'\\' => line.push_str("\\\\"),
        b'!'..=b'~' => line.push(char::from(byte)),
        _ => {
            let _ = write!(line, "\\x{byte:02X}");
        }
    }
    line.clone()
}

/// The last cycle anything in `input` changes at (0 for an empty trace).
pub fn end_cycle(input: &VcdInput) -> u64 {
    let sample_cycle = |s: &Sample| (s.t_s * input.clock_hz as f64).round() as u64;
    [
        input.edges.iter().map(|e| e.cycle).max(),
        input.drive.iter().map(|e| e.cycle).max(),
        input.uart_tx.iter().map(|b| b.0).max(),
        input.uart_rx.iter().map(|b| b.0).max(),
        input.samples.iter().map(sample_cycle).max(),
    ]
    .into_iter()
    .flatten()
    .max()
    .unwrap_or(0)
}

/// Write the trace of a run's records to `out` (the same bytes a
/// [`VcdWriter`] writes when it is given them as the run makes them).
pub fn write(input: &VcdInput, out: impl Write) -> std::io::Result<()> {
    let mut w = VcdWriter::new(out, input.clock_hz, input.board, input.pwm_edges);
    for e in input.edges {
        w.pin(*e);
    }
    for e in input.drive {
        w.drive(e);
    }
    for (received, log) in [(false, input.uart_tx), (true, input.uart_rx)] {
        for &(cycle, usart, byte) in log {
            w.uart(received, cycle, usart, byte);
        }
    }
    for s in input.samples {
        w.sample(s);
    }
    w.finish().map(drop)
}

/// Render the VCD text.
pub fn render(input: &VcdInput) -> String {
    let mut out = Vec::new();
    write(input, &mut out).expect("writing to memory does not fail");
    String::from_utf8(out).expect("the trace is ASCII")
}

/// GTKWave's wave pane, in pixels, as the save file sizes the window
/// ([`GTKW_SIZE`] less the signal and tree panes); the zoom fits the run
/// into it.
const GTKW_WAVE_PX: f64 = 900.0;
const GTKW_SIZE: (u32, u32) = (1400, 800);

/// GTKWave's zoom that shows `span_ps` picoseconds across [`GTKW_WAVE_PX`]:
/// its time per pixel is `2^-zoom / 200` (zoom base 2, 200 pixels a frame),
/// as its own Zoom Fit computes it.
/// With 2 % to spare, rounded down to the save file's six decimals, so the
/// run's last change is on screen.
pub fn gtkw_zoom(span_ps: f64) -> f64 {
    let z = -(span_ps.max(1.0) * 1.02 * 200.0 / GTKW_WAVE_PX).log2();
    (z * 1e6).floor() / 1e6
}

/// A GTKWave save file for the trace [`render`] writes of `input`, to lie
/// beside it as `vcd_name` (a bare file name, so that the pair opens
/// wherever it is moved: GTKWave looks for a relative dump file beside the
/// save file), zoomed to the whole run. Signals in the order a run is read
/// in: each wheel's bridge inputs (duty, then the waveform or level) above
/// its encoder's lines, then each UART's text, bytes and bit lines, then the
/// plant; a comment line heads each group.
pub fn gtkw(vcd_name: &str, input: &VcdInput) -> String {
    let trace = Traced {
        clock_hz: input.clock_hz,
        board: input.board,
        pwm_edges: input.pwm_edges,
        end_cycle: end_cycle(input),
    };
    gtkw_of(vcd_name, &trace)
}

/// What a GTKWave save file needs of a trace.
pub struct Traced<'a> {
    pub clock_hz: u32,
    pub board: &'a Board,
    pub pwm_edges: bool,
    /// The last cycle anything changed at.
    pub end_cycle: u64,
}

/// [`gtkw`] of a trace written as the run went ([`VcdWriter`]).
pub fn gtkw_of(vcd_name: &str, input: &Traced) -> String {
    let board = input.board;
    // GTKWave's time is the VCD's times the timescale's number (ps here).
    let ps_per_cycle = 1_000_000_000_000u64 / input.clock_hz as u64;
    let span_ps = (input.end_cycle * ps_per_cycle) as f64;
    let mut out = String::new();
    let _ = writeln!(out, "[*] GTKWave save file of a Henrytwo HIL bench trace");
    let _ = writeln!(out, "[dumpfile] \"{vcd_name}\"");
    let _ = writeln!(out, "[size] {} {}", GTKW_SIZE.0, GTKW_SIZE.1);
    let _ = writeln!(out, "[signals_width] 260");
    let _ = writeln!(out, "[sst_expanded] 0");
    let _ = writeln!(out, "[timestart] 0");
    // The zoom, then the primary marker and GTKWave's 26 named markers
    // (none set).
    let _ = writeln!(out, "*{:.6} -1{}", gtkw_zoom(span_ps), " -1".repeat(26));
    for scope in ["encoders", "bridge", "uart", "usb", "plant"] {
        let _ = writeln!(out, "[treeopen] {scope}.");
    }
    let comment = |out: &mut String, text: &str| {
        let _ = writeln!(out, "@200\n-{text}");
    };
    let bits = |out: &mut String, names: &[String]| {
        let _ = writeln!(out, "@28");
        for n in names {
            let _ = writeln!(out, "{n}");
        }
    };
    // Real-valued traces as analog steps (GTKWave's flags: real, analog
    // step, right-justified).
    let values = |out: &mut String, names: &[String]| {
        for n in names {
            let _ = writeln!(out, "@8420\n{n}");
        }
    };
    for side in [Side::Left, Side::Right] {
        let s = match side {
            Side::Left => "left",
            Side::Right => "right",
        };
        comment(&mut out, &format!("{s} wheel: bridge inputs, encoder"));
        for b in board.motor(side).inputs() {
            let p = b.number();
            values(&mut out, &[format!("bridge.D{p}_duty")]);
            bits(
                &mut out,
                &[format!("bridge.{}", wave_name(p, input.pwm_edges))],
            );
        }
        let lines: Vec<String> = board
            .encoder(side)
            .lines()
            .iter()
            .map(|(ch, pin)| format!("encoders.{s}_{ch}_{}", pin.name()))
            .collect();
        bits(&mut out, &lines);
    }
    for (n, baud) in uarts(board) {
        comment(
            &mut out,
            &format!("USART{n} at {baud} baud: text, bytes, lines"),
        );
        // Strings need no flags of their own: GTKWave shows them as text.
        bits(
            &mut out,
            &[
                format!("uart.uart{n}_tx_text"),
                format!("uart.uart{n}_rx_text"),
            ],
        );
        values(
            &mut out,
            &[
                format!("uart.uart{n}_tx_byte"),
                format!("uart.uart{n}_rx_byte"),
            ],
        );
        bits(
            &mut out,
            &[format!("uart.uart{n}_tx"), format!("uart.uart{n}_rx")],
        );
    }
    if board.mcu.chip().usb.is_some() {
        comment(&mut out, "USB serial (USB CDC): text, bytes");
        bits(
            &mut out,
            &["tx_text", "rx_text"].map(|w| format!("usb.usb_serial_{w}")),
        );
        values(
            &mut out,
            &["tx_byte", "rx_byte"].map(|w| format!("usb.usb_serial_{w}")),
        );
    }
    comment(&mut out, "plant: pose, edge counts");
    let plant: Vec<String> = ["x_mm", "y_mm", "theta_rad", "left_edges", "right_edges"]
        .iter()
        .map(|n| format!("plant.{n}"))
        .collect();
    values(&mut out, &plant);
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
            uart_tx: &[(200, 1, b'A')],
            uart_rx: &[],
            samples: &[],
            pwm_edges: false,
        });
        assert!(text.contains("$timescale 62500 ps $end"));
        assert!(text.contains("$var wire 1 !a left_A_D2 $end"));
        assert!(text.contains("#100\n1!a"));
        // No wire wider than a bit (sigrok stops at the first).
        for l in text.lines().filter(|l| l.starts_with("$var wire")) {
            assert!(l.starts_with("$var wire 1 "), "{l}");
        }
        assert!(text.contains("uart1_tx_byte"));
        assert!(text.contains("r65 "), "the byte's value as a real");
        // Timestamps increase.
        let stamps: Vec<u64> = text
            .lines()
            .filter_map(|l| l.strip_prefix('#'))
            .map(|t| t.parse().unwrap())
            .collect();
        assert!(stamps.windows(2).all(|w| w[0] < w[1]));
    }
}

#[cfg(test)]
mod uart_tests {
    use super::*;

    #[test]
    fn a_frame_is_start_bit_data_lsb_first_stop_bit() {
        // 0x41 = 0b0100_0001 at 10 cycles per bit: start 0 at 100, bit0 = 1
        // at 110, bits 1-5 = 0 from 120, bit 6 = 1 at 170, bit 7 = 0 at 180,
        // stop 1 at 190.
        let f = frames([(100, 0x41)].into_iter(), 10.0);
        assert_eq!(
            f,
            vec![
                (100, false),
                (110, true),
                (120, false),
                (170, true),
                (180, false),
                (190, true)
            ]
        );
        // A byte logged before the frame before it ended waits for it.
        let f = frames([(0, 0xff), (50, 0x00)].into_iter(), 10.0);
        assert_eq!(f, vec![(0, false), (10, true), (100, false), (190, true)]);
    }

    #[test]
    fn every_variable_starts_with_a_value() {
        let input = VcdInput {
            clock_hz: 16_000_000,
            board: &Board::default(),
            edges: &[PinEvent {
                cycle: 0,
                line: 2,
                level: true,
            }],
            drive: &[],
            uart_tx: &[],
            uart_rx: &[(1000, 1, b'g')],
            samples: &[],
            pwm_edges: false,
        };
        let text = render(&input);
        let defined = text.lines().filter(|l| l.starts_with("$var")).count();
        let dump: Vec<&str> = text
            .split("$dumpvars\n")
            .nth(1)
            .and_then(|t| t.split("$end").next())
            .expect("a $dumpvars section")
            .lines()
            .collect();
        assert_eq!(dump.len(), defined, "{dump:?}");
        assert!(dump.contains(&"1!c"), "right A starts high: {dump:?}");
        assert!(text.contains("uart1_rx"), "the host's bytes are traced");
        let gtkw = gtkw("t.vcd", &input);
        for l in text.lines().filter(|l| l.starts_with("$var")) {
            let name = l.split(' ').nth(4).unwrap();
            assert!(
                gtkw.contains(&format!(".{name}\n")),
                "{name} in the save file"
            );
        }
    }

    #[test]
    fn uart_text_is_the_line_so_far_and_the_save_file_fits_the_run() {
        let sent: Vec<(u64, u8, u8)> = b"ok 1\nA\xA5"
            .iter()
            .enumerate()
            .map(|(i, b)| (1000 + 20_000 * i as u64, 0, *b))
            .collect();
        let input = VcdInput {
            clock_hz: 16_000_000,
            board: &Board::default(),
            edges: &[],
            drive: &[],
            uart_tx: &sent,
            uart_rx: &[],
            samples: &[],
            pwm_edges: false,
        };
        let text = render(&input);
        let id = text
            .lines()
            .find(|l| l.contains(" uart0_tx_text "))
            .and_then(|l| l.split(' ').nth(3))
            .expect("a string variable for USART0's text");
        let shown: Vec<&str> = text
            .lines()
            .filter(|l| l.starts_with('s') && l.ends_with(&format!(" {id}")))
            .map(|l| l[1..].split(' ').next().unwrap())
            .collect();
        assert_eq!(
            shown,
            [
                "",
                "o",
                "ok",
                "ok\\x20",
                "ok\\x201",
                "ok\\x201\\n",
                "A",
                "A\\xA5"
            ]
        );
        // Without --vcd-pwm the bridge trace says it is a level.
        let vars: Vec<&str> = text.lines().filter(|l| l.starts_with("$var")).collect();
        assert!(
            vars.iter().any(|l| l.ends_with(" D7_driven $end")),
            "{vars:?}"
        );
        assert!(!vars.iter().any(|l| l.contains("_pwm")), "{vars:?}");

        let save = gtkw("run.vcd", &input);
        assert!(save.contains("[dumpfile] \"run.vcd\"\n"), "{save}");
        // The zoom shows the whole run (the last byte at cycle 121000),
        // and not much more.
        let zoom: f64 = save
            .lines()
            .find_map(|l| l.strip_prefix('*'))
            .and_then(|l| l.split(' ').next())
            .and_then(|z| z.parse().ok())
            .expect("a zoom line");
        let shown_ps = 2f64.powf(-zoom) / 200.0 * GTKW_WAVE_PX;
        let run_ps = 121_000.0 * 62_500.0;
        assert!(
            shown_ps >= run_ps && shown_ps < 1.1 * run_ps,
            "{shown_ps} vs {run_ps}"
        );
        // Each wheel's drive above its encoder.
        let at = |n: &str| save.find(n).unwrap_or_else(|| panic!("{n} in {save}"));
        assert!(at("bridge.D9_duty") < at("encoders.left_A_D2"));
        assert!(at("encoders.left_B_D4") < at("bridge.D7_duty"));
        assert!(at("bridge.D7_duty") < at("encoders.right_A_D3"));
    }
}
