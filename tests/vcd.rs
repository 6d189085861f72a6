//! The VCD trace read by a real client (issue 22): sigrok-cli 0.7 reads the
//! whole trace (it stops at the first wire wider than a bit, which the UART
//! bytes once were) and its `uart` decoder decodes both directions of the
//! links from the bit-level lines: the robust build's greeting on USART0, the
//! host's test byte on USART1's RX and the firmware's framed replies on its
//! TX. A GTKWave save file lies beside the trace, naming it by its file name
//! (the pair opens when moved) and zoomed to the run; the firmware's text is
//! in a string variable GTKWave shows as text.
//!
//! The trace is written as the run makes it (issue 51): the same bytes as
//! the trace rendered after the run from its records, and what a run holds
//! for it does not grow with robot time.

#[path = "support/mod.rs"]
mod support;

use std::path::Path;
use std::process::Command;
use std::sync::{Arc, Mutex};

use henrytwo_protocol::Test;
use hil::bench::{Bench, SharedTap};
use hil::output::vcd::{VcdInput, VcdWriter};
use hil::runs::experiment::{run_test, TestOptions};

/// sigrok-cli with `args` on `vcd`: its stdout, or a failure that says why.
fn sigrok(vcd: &Path, args: &[&str]) -> String {
    let out = Command::new("sigrok-cli")
        .args(["-I", "vcd", "-i"])
        .arg(vcd)
        .args(args)
        .output()
        .expect("sigrok-cli runs (tools/setup.sh installs it)");
    assert!(
        out.status.success(),
        "sigrok-cli {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The bytes sigrok's UART decoder reads on `channel` at 9600 baud.
fn decoded(vcd: &Path, channel: &str) -> Vec<u8> {
    let spec = format!("uart:rx={channel}:baudrate=9600");
    sigrok(vcd, &["-P", &spec, "-A", "uart=rx-data"])
        .lines()
        .filter_map(|l| l.split_whitespace().nth(1))
        .map(|h| u8::from_str_radix(h, 16).expect("a hex byte"))
        .collect()
}

/// `hil run line` of 100 mm with `--vcd DIR/line.vcd` (and so its `.gtkw`
/// beside): the trace's path.
fn run_line_with_vcd(dir: &Path) -> std::path::PathBuf {
    let vcd = dir.join("line.vcd");
    let out = Command::new(env!("CARGO_BIN_EXE_hil"))
        .args(["run", "line", "--leg-mm", "100", "--deterministic", "--vcd"])
        .arg(&vcd)
        .output()
        .expect("hil runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    vcd
}

#[test]
fn sigrok_reads_the_whole_trace_and_decodes_both_uart_directions() {
    let _ = support::firmware_path("robust");
    let dir = std::env::temp_dir().join(format!("hil-vcd-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let vcd = run_line_with_vcd(&dir);
    let text = std::fs::read_to_string(&vcd).unwrap();

    // Every sample up to the last change is read.
    let last: u64 = text
        .lines()
        .filter_map(|l| l.strip_prefix('#'))
        .map(|t| t.parse().unwrap())
        .max()
        .unwrap();
    let show = sigrok(&vcd, &["--show"]);
    let samples: u64 = show
        .lines()
        .find_map(|l| l.strip_prefix("Logic sample count: "))
        .expect("sigrok counts the samples")
        .trim()
        .parse()
        .unwrap();
    assert!(samples >= last, "sigrok read {samples} of {last} samples");
    for line in [
        "left_A_D2",
        "right_B_D5",
        "D8_driven",
        "uart1_tx",
        "uart1_rx",
        "uart0_tx",
    ] {
        assert!(show.contains(&format!("- {line}: logic")), "{line}: {show}");
    }

    // The robust build's greeting on its debug link.
    let debug = decoded(&vcd, "uart0_tx");
    assert!(
        String::from_utf8_lossy(&debug).contains("henrytwo"),
        "{:?}",
        String::from_utf8_lossy(&debug)
    );
    // The host's single test byte (the line's, 0x04), and the firmware's
    // framed replies (each starts with 0xA5).
    assert_eq!(decoded(&vcd, "uart1_rx"), vec![0x04]);
    let replies = decoded(&vcd, "uart1_tx");
    assert_eq!(replies.first(), Some(&0xA5), "{replies:02X?}");

    let gtkw = std::fs::read_to_string(vcd.with_extension("gtkw")).expect("a .gtkw beside");
    assert!(gtkw.contains("[dumpfile] \"line.vcd\"\n"), "{gtkw}");
    assert!(gtkw.contains("uart.uart1_tx\n"), "{gtkw}");
    // Zoomed to the run: GTKWave's time per pixel is 2^-zoom / 200 (in ps,
    // the timescale's unit), over a wave pane of about 900 pixels.
    let zoom: f64 = gtkw
        .lines()
        .find_map(|l| l.strip_prefix('*'))
        .and_then(|l| l.split(' ').next())
        .and_then(|z| z.parse().ok())
        .expect("a zoom line");
    let shown_ps = 2f64.powf(-zoom) / 200.0 * 900.0;
    let run_ps = last as f64 * 62_500.0;
    assert!(
        shown_ps >= run_ps && shown_ps < 1.1 * run_ps,
        "shows {shown_ps} ps of a {run_ps} ps run"
    );
    // The greeting as text (escaped spaces), in a string variable.
    let id = text
        .lines()
        .find(|l| l.starts_with("$var string 1 ") && l.contains(" uart0_tx_text "))
        .and_then(|l| l.split(' ').nth(3))
        .expect("USART0's text variable");
    assert!(
        text.lines()
            .any(|l| l.starts_with("shenrytwo") && l.ends_with(&format!(" {id}"))),
        "the greeting as text"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// GTKWave itself (under xvfb, as a CI runner has no display) opens the
/// `.gtkw` of a pair moved away from where the run wrote it, and shows the
/// run from its start to its last change: its own Tcl interface reports
/// the window and the traces it loaded.
#[test]
fn gtkwave_opens_a_moved_pair_at_the_runs_extent() {
    let _ = support::firmware_path("robust");
    let dir = std::env::temp_dir().join(format!("hil-gtkw-{}", std::process::id()));
    let moved = dir.join("artifact");
    std::fs::create_dir_all(&moved).unwrap();
    run_line_with_vcd(&dir);
    for name in ["line.vcd", "line.gtkw"] {
        std::fs::rename(dir.join(name), moved.join(name)).unwrap();
    }
    let script = dir.join("window.tcl");
    std::fs::write(
        &script,
        "puts \"window [gtkwave::getWindowStartTime] [gtkwave::getWindowEndTime] \
         [gtkwave::getMaxTime] [gtkwave::getTotalNumTraces]\"\ngtkwave::/File/Quit\n",
    )
    .unwrap();
    let out = Command::new("xvfb-run")
        .args(["-a", "gtkwave", "-S"])
        .arg(&script)
        .arg("line.gtkw")
        .current_dir(&moved)
        .output()
        .expect("xvfb-run and gtkwave run (tools/setup.sh installs them)");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let window: Vec<f64> = stdout
        .lines()
        .find_map(|l| l.strip_prefix("window "))
        .unwrap_or_else(|| {
            panic!(
                "GTKWave printed no window: {stdout}{}",
                String::from_utf8_lossy(&out.stderr)
            )
        })
        .split(' ')
        .map(|v| v.parse().expect("a number"))
        .collect();
    let [start, end, last, traces] = window[..] else {
        panic!("{stdout}")
    };
    // From time 0 to just past the last change (the save file's zoom leaves
    // 2 % to spare over GTKWave's wave pane, which under xvfb is a little
    // wider than the save file's size assumes).
    assert_eq!(start, 0.0, "{stdout}");
    assert!(last > 0.0 && end >= last && end < 1.2 * last, "{stdout}");
    // Every signal and comment line of the save file is a trace GTKWave
    // found (a name it cannot find in the VCD is dropped).
    let listed = std::fs::read_to_string(moved.join("line.gtkw"))
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with(['[', '*', '@']))
        .count();
    assert_eq!(traces as usize, listed, "{stdout}");
    std::fs::remove_dir_all(&dir).ok();
}

/// FNV-1a of `bytes`: a digest whose algorithm is fixed (the standard
/// library's hasher may change between releases).
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// A VCD writer in memory, shared with the bench as its tap.
type Shared = Arc<Mutex<VcdWriter<Vec<u8>>>>;

fn writer(opts: &TestOptions) -> Shared {
    let clock = opts.bench.clock.hz();
    Arc::new(Mutex::new(VcdWriter::new(
        Vec::new(),
        clock,
        &opts.bench.board,
        false,
    )))
}

/// The 100 mm line, recorded: its trace written as the run went, and the
/// trace rendered after the run from the records of the same run without
/// the writer (the bench is deterministic) are the same bytes, and the
/// bytes pinned for this robust build (76160 bytes, their digest taken when
/// the stop timing became parameters; 75955 before, when traces were first
/// streamed): `hil run line --leg-mm 100 --vcd`.
#[test]
fn a_trace_written_as_the_run_goes_is_the_trace_rendered_after_it() {
    let robot = support::robot("henrytwo");
    let mut opts = TestOptions {
        leg_mm: 100.0,
        record: true,
        ..Default::default()
    };
    let kept = run_test(support::firmware("robust"), &robot, Test::Line, &opts).unwrap();
    let after = hil::output::vcd::render(&VcdInput {
        clock_hz: opts.bench.clock.hz(),
        board: &opts.bench.board,
        edges: &kept.edges,
        drive: &kept.drive,
        uart_tx: &kept.uart,
        uart_rx: &kept.uart_rx,
        samples: &kept.trace,
        pwm_edges: false,
    });
    assert_eq!(
        (after.len(), fnv1a(after.as_bytes())),
        (76_160, 0xaf6d_3e14_8a36_f54c),
        "the trace of the 100 mm line changed"
    );

    let w = writer(&opts);
    opts.tap = Some(SharedTap(w.clone()));
    let streamed = run_test(support::firmware("robust"), &robot, Test::Line, &opts).unwrap();
    assert!(
        streamed.edges.is_empty(),
        "the pin changes went to the trace"
    );
    drop(opts);
    let w = Arc::try_unwrap(w).ok().unwrap().into_inner().unwrap();
    assert_eq!(w.late(), 0, "a change came after its cycle was written");
    let bytes = w.finish().unwrap();
    assert!(bytes == after.as_bytes(), "the streamed trace differs");
}

/// What a run holds for its trace, counted (items, not the process's
/// memory): with the trace written as the run goes, no pin change is kept
/// and the writer holds the changes of the last moments, as many after
/// 20 robot seconds as after 2; with the pin changes kept (no writer),
/// they grow with the run.
#[test]
fn a_streamed_trace_holds_nothing_per_robot_second() {
    let robot = support::robot("henrytwo");
    let opts = TestOptions::default();
    let start = |tap: Option<&Shared>| {
        let mut bench = Bench::new(support::firmware("robust"), &robot, opts.bench).unwrap();
        hil::runs::start::wait_ready(&mut bench, None).unwrap();
        bench.true_waveforms();
        match tap {
            Some(w) => bench.stream_records(SharedTap(w.clone())),
            None => bench.start_recording(),
        }
        hil::runs::start::start_test(&mut bench, &[], true, Test::Line);
        bench
    };
    let w = writer(&opts);
    let mut streamed = start(Some(&w));
    let held = |bench: &Bench| (bench.core().retained().pins, w.lock().unwrap().pending());
    streamed.run_for(2.0).unwrap();
    let (pins_2, pending_2) = held(&streamed);
    streamed.run_for(18.0).unwrap();
    let (pins_20, pending_20) = held(&streamed);
    let written = w.lock().unwrap().end_cycle();
    assert!(
        written > 19 * 16_000_000,
        "the writer had the whole run: {written}"
    );
    assert_eq!((pins_2, pins_20), (0, 0), "pin changes kept");
    assert!(pending_2 > 0, "the writer holds the last moments");
    assert!(
        pending_20 <= 2 * pending_2,
        "held {pending_2} changes after 2 s, {pending_20} after 20 s"
    );

    // The same run keeping its pin changes: over a thousand a robot second
    // (the robot drives 14 s of the 20).
    let mut kept = start(None);
    kept.run_for(20.0).unwrap();
    assert!(
        kept.core().retained().pins > 20 * 1000,
        "{:?}",
        kept.core().retained()
    );
}
