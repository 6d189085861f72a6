//! `hil serve` and `hil ui`: the operator's station from the command line.

use std::io::Write;

use anyhow::{Context, Result};
use hil::bench::BenchOptions;
use hil::elf::Firmware;
use hil::station::emulated::{EmulatedRobot, ServeOptions};
use plant_model::RobotConfig;

/// Serve the emulated robot's USART1 on a pty until the emulator stops.
pub fn serve(firmware: Firmware, robot: &RobotConfig, seed: u64, speed: f64) -> Result<()> {
    let options = ServeOptions {
        speed,
        bench: BenchOptions {
            seed,
            ..Default::default()
        },
        ..Default::default()
    };
    let name = firmware.name();
    let emu =
        EmulatedRobot::spawn(firmware, robot, options).context("starting the emulated robot")?;
    // The path first and alone on stdout, for scripts and tests.
    println!("pty: {}", emu.path().display());
    let _ = std::io::stdout().flush();
    eprintln!(
        "the emulated robot ({name} firmware) runs at {speed}x real time; its Bluetooth UART \
         (9600 baud 8N1) is {}: open it with a serial client (screen {} 9600) or \
         `hil ui --port {}`; Ctrl-C stops it",
        emu.path().display(),
        emu.path().display(),
        emu.path().display()
    );
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

/// Run the station's web page on loopback until interrupted.
pub fn ui(
    firmware: Firmware,
    robot: Option<std::path::PathBuf>,
    port: Option<String>,
    baud: u32,
    listen_port: u16,
    sessions: std::path::PathBuf,
    seed: u64,
) -> Result<()> {
    let options = hil::station::ui::UiOptions {
        sessions_dir: sessions,
        robots: hil::station::ui::robot_configs(
            &hil::paths::workspace_root().join("fixtures/robots"),
            robot,
        ),
        firmware,
        port,
        baud,
        seed,
    };
    let runtime = tokio::runtime::Runtime::new().context("starting the async runtime")?;
    runtime.block_on(async {
        let server = hil::station::ui::serve(options, listen_port, |addr| {
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
