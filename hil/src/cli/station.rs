//! `hil serve` and `hil ui`: the operator's station from the command line.

use std::io::Write;
use std::path::PathBuf;

use anyhow::{Context, Result};
use hil::clients::station::emulated::{EmulatedRobot, ServeOptions};
use hil::firmware::elf::Firmware;
use plant_model::RobotConfig;

use super::args::Common;

#[derive(clap::Args)]
pub struct Serve {
    /// Expose the command USART (USART1, the HC-05's) on a pseudo-terminal
    /// and the USB serial (USART0; a 32U4's own USB CDC) on a second one;
    /// their paths are printed.
    #[arg(long, required = true)]
    pty: bool,
    /// Robot seconds per wall-clock second (0.001 to 1000).
    #[arg(long, default_value_t = 1.0, value_parser = parse_speed)]
    speed: f64,
    #[command(flatten)]
    common: Common,
}

impl Serve {
    pub fn run(self) -> Result<()> {
        self.common.refuse_trace("serve")?;
        // A described firmware is served as it is: its client starts its
        // tests as the description says (printed below).
        refuse_params(&self.common, "serve")?;
        self.common
            .refuse_result_format("serve", "it serves the emulated robot until stopped")?;
        let target = &self.common.target;
        let options = ServeOptions {
            speed: self.speed,
            bench: target.bench(),
            usb_pty: true,
            ..Default::default()
        };
        let (robot, firmware) = target.load()?;
        serve(firmware, &robot, options, target.description.clone())
    }
}

#[derive(clap::Args)]
pub struct Ui {
    /// A serial port to offer first (a real robot, or `hil serve --pty`).
    #[arg(long, value_name = "DEVICE")]
    port: Option<String>,
    /// Baud rate of the serial port (the HC-05's is 9600; 50 to 4000000).
    #[arg(long, default_value_t = 9600,
          value_parser = clap::value_parser!(u32).range(50..=4_000_000))]
    baud: u32,
    /// TCP port of the page on 127.0.0.1 (0: any free port).
    #[arg(long, default_value_t = 8317)]
    listen_port: u16,
    /// Folder of the session files, one per robot.
    #[arg(long, value_name = "DIR", default_value = "station-sessions")]
    sessions: PathBuf,
    #[command(flatten)]
    common: Common,
}

impl Ui {
    pub fn run(self) -> Result<()> {
        self.common.refuse_trace("ui")?;
        // A described firmware's tests are started by the station itself,
        // as the description says (hil run's start, end and report).
        refuse_params(&self.common, "ui")?;
        let target = &self.common.target;
        if let Some((d, field)) = target
            .description
            .as_ref()
            .and_then(|d| Some((d, d.usb_field()?)))
        {
            return Err(super::BadInput(format!(
                "{}: {field} = \"usb\": the station does not bridge the MCU's USB serial; run \
                 its tests with hil run TEST --tests FILE, or serve them with hil serve --pty \
                 --tests FILE",
                d.path
            ))
            .into());
        }
        self.common
            .refuse_result_format("ui", "it serves the station's page until stopped")?;
        let options = hil::clients::station::ui::UiOptions {
            sessions_dir: self.sessions,
            robots: hil::clients::station::ui::robot_configs(
                &hil::paths::workspace_root().join("fixtures/robots"),
                target.robot.clone(),
            ),
            firmware: target.firmware()?,
            port: self.port,
            baud: self.baud,
            bench: target.bench(),
            description: target.description.clone(),
        };
        ui(options, self.listen_port)
    }
}

/// `--param` and `--keep-firmware-params` refused (exit 2): without `--tests`
/// the client sets the parameters over the link; with it, the firmware has
/// no protocol for them. `--tests` itself is taken.
fn refuse_params(common: &Common, command: &str) -> Result<()> {
    let t = &common.target;
    match &t.description {
        None => common.refuse_run_params(command),
        Some(d) if !t.params.is_empty() || t.keep_firmware_params => Err(super::BadInput(format!(
            "{}: --param and --keep-firmware-params: the firmware it describes has no \
                 protocol for parameters; drop them",
            d.path
        ))
        .into()),
        Some(_) => Ok(()),
    }
}

/// `--speed`: a pace the emulated robot can be served at.
fn parse_speed(s: &str) -> Result<f64, String> {
    let v: f64 = s
        .parse()
        .map_err(|_| format!("{s:?} is not a number (robot seconds per wall-clock second)"))?;
    hil::clients::station::emulated::check_speed(v).map_err(|e| e.to_string())
}

/// Serve the emulated robot's USARTs on ptys until the emulator stops.
fn serve(
    firmware: Firmware,
    robot: &RobotConfig,
    options: ServeOptions,
    description: Option<std::sync::Arc<hil::firmware::description::Description>>,
) -> Result<()> {
    let speed = options.speed;
    let board = options.bench.board;
    let usb_serial = hil::clients::station::emulated::usb_pty_serial(&options.bench);
    let name = match &description {
        Some(d) => d.firmware_name(&firmware),
        None => firmware.name(),
    };
    let starts = description
        .as_deref()
        .map(|d| how_tests_start(d, &board, usb_serial))
        .unwrap_or_default();
    let emu = EmulatedRobot::spawn_described(firmware, robot, options, description)
        .context("starting the emulated robot")?;
    let pty = emu.path().display();
    let usb = emu
        .usb_path()
        .context("the emulated robot serves no USB serial")?
        .display();
    // The paths first and alone on stdout, for scripts and tests: the
    // command pty's line first, as before the USB serial had one. One
    // write: a reader that takes the first line and closes the pipe must
    // not kill the robot with the second.
    let _ = std::io::stdout()
        .lock()
        .write_all(format!("pty: {pty}\nusb pty: {usb}\n").as_bytes());
    let _ = std::io::stdout().flush();
    let usb_line = if usb_serial == hil::bench::USB_SERIAL {
        "the MCU's USB CDC, the bench its USB host".to_string()
    } else {
        format!(
            "USART{}, {} baud",
            board.debug_uart.usart, board.debug_uart.baud
        )
    };
    eprintln!(
        "the emulated robot ({name} firmware) runs at {speed}x real time; its Bluetooth UART \
         (USART{}, {} baud 8N1) is {pty}: open it with a serial client (screen {pty} {}) or \
         `hil ui --port {pty}`; its USB serial ({usb_line}) is {usb}; one client at a \
         time on each, the robot's bytes kept for the next (up to {} KiB); Ctrl-C stops it",
        board.command_uart.usart,
        board.command_uart.baud,
        board.command_uart.baud,
        hil::clients::station::emulated::QUEUE_CAP / 1024,
    );
    eprint!("{starts}");
    let mut warned = false;
    while !emu.finished() {
        std::thread::sleep(std::time::Duration::from_millis(200));
        let lag = emu.view().lag_s;
        if lag > 1.0 && !warned {
            eprintln!("warning: this machine cannot keep {speed}x real time (behind by {lag:.1} s of robot time); try a lower --speed");
            warned = true;
        }
    }
    match emu.join() {
        Some(e) => anyhow::bail!("the emulated robot stopped: {e}"),
        None => Ok(()),
    }
}

/// How a client of `hil serve` starts each of the description's tests, one
/// line each: the bytes to send on which pty (the USB pty serving serial
/// channel `usb_serial`), or why a pty cannot.
fn how_tests_start(
    d: &hil::firmware::description::Description,
    board: &hil::board::Board,
    usb_serial: u8,
) -> String {
    use hil::firmware::description::Start;
    let mut s = String::new();
    for (test, described) in &d.tests {
        let line = match &described.start {
            Start::Uart { usart, bytes } => {
                let pty = if *usart == board.command_uart.usart {
                    "the pty"
                } else if *usart == usb_serial {
                    "the usb pty"
                } else {
                    if usb_serial == hil::bench::USB_SERIAL {
                        "no pty (only the board's command_uart and the USB serial are served)"
                    } else {
                        "no pty (only the board's command_uart and debug_uart are served)"
                    }
                };
                let shown = match std::str::from_utf8(bytes) {
                    Ok(t) if !t.chars().any(char::is_control) => format!("{t:?}"),
                    _ => format!("the bytes {bytes:?}"),
                };
                let on = if *usart == hil::bench::USB_SERIAL {
                    "the USB serial".to_string()
                } else {
                    format!("USART{usart}")
                };
                format!("send {shown} on {on}: {pty}")
            }
            Start::Pin { pin, high } => format!(
                "{} held {}: a pin no pty can hold; hil run {} --tests {} runs it",
                pin,
                if *high { "high" } else { "low" },
                test.name(),
                d.path
            ),
        };
        s.push_str(&format!(
            "test {} ({}) starts: {line}\n",
            test.name(),
            d.path
        ));
    }
    s
}

/// Run the station's web page on loopback until interrupted.
fn ui(options: hil::clients::station::ui::UiOptions, listen_port: u16) -> Result<()> {
    let runtime = tokio::runtime::Runtime::new().context("starting the async runtime")?;
    runtime.block_on(async {
        let server = hil::clients::station::ui::serve(options, listen_port, |addr| {
            // The address first and alone on stdout, for scripts and tests.
            println!("http://{addr}/");
            let _ = std::io::stdout().flush();
            eprintln!("the station listens on http://{addr}/ (loopback only); Ctrl-C stops it");
        });
        tokio::select! {
            r = server => r.context("the station's web server"),
            _ = tokio::signal::ctrl_c() => Ok(()),
        }
    })
}
