//! The VCD trace read by a real client (issue 22): sigrok-cli 0.7 reads the
//! whole trace (it stops at the first wire wider than a bit, which the UART
//! bytes once were) and its `uart` decoder decodes both directions of the
//! links from the bit-level lines: the robust build's greeting on USART0, the
//! host's test byte on USART1's RX and the firmware's framed replies on its
//! TX. A GTKWave save file lies beside the trace, naming it by its file name
//! (the pair opens when moved) and zoomed to the run; the firmware's text is
//! in a string variable GTKWave shows as text.

#[path = "support/mod.rs"]
mod support;

use std::path::Path;
use std::process::Command;

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

#[test]
fn sigrok_reads_the_whole_trace_and_decodes_both_uart_directions() {
    let _ = support::firmware_path("robust");
    let dir = std::env::temp_dir().join(format!("hil-vcd-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
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
