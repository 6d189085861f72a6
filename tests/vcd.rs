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
