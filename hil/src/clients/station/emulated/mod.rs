//! The emulated robot behind pseudo-terminals, paced to the wall clock:
//! `hil serve --pty` and the emulated robots of `hil ui`.
//!
//! The bench itself stays a pure function of the ELF, the config and the
//! seed: it runs in slices of robot time, and only [`Pacer`], outside it,
//! looks at the host clock and sleeps between slices. What the host writes
//! to a pty reaches its USART (the board's command USART, Henrytwo's USART1
//! to the HC-05; on a second pty, its USB serial: the Mega's USART0, a
//! 32U4's own USB CDC served by the bench as the host) at the start of
//! the next slice, at the line's baud in robot time; what the firmware sends
//! goes out on the pty after each slice. Which slice a host byte lands in
//! depends on the wall clock, so a served session is not reproducible bit
//! for bit; a run of `hil run` or `hil umbmark` still is.
//!
//! | file | what |
//! |---|---|
//! | `mod.rs` | [`EmulatedRobot`], [`ServeOptions`], [`Pacer`], the slice loop |
//! | `pty.rs` | one USART on a pty: one client at a time, the robot's bytes queued for the next ([`QUEUE_CAP`]) |

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use plant_model::RobotConfig;
use thiserror::Error;

use crate::bench::{Bench, BenchError, BenchOptions, SERIALS, USB_SERIAL};
use crate::firmware::description::Description;
use crate::firmware::elf::Firmware;
use crate::runs::start::wait_ready;

mod pty;

use self::pty::PtyPort;
pub use self::pty::QUEUE_CAP;

#[derive(Debug, Error)]
pub enum EmulatorError {
    #[error(transparent)]
    Bench(#[from] BenchError),
    #[error("cannot create a pseudo-terminal: {0}; check /dev/ptmx is there and usable")]
    Pty(nix::Error),
    #[error("cannot watch the pseudo-terminal {} for its clients (inotify): {source}", path.display())]
    Watch { path: PathBuf, source: nix::Error },
    #[error("the emulator thread ended before the firmware was ready")]
    Lost,
    #[error("speed {}: give a factor from {SPEED_MIN} to {SPEED_MAX} (1 = real time, 10 = ten times faster)", shown(*.0))]
    Speed(f64),
}

/// The slowest pace served: a robot second in about 17 wall minutes. Slower
/// (1e-300) is no pace a client can use, and its wall durations overflow.
pub const SPEED_MIN: f64 = 0.001;
/// The fastest pace asked of the pacer: beyond what a core runs (about
/// 100x real time), where the robot is simply run as fast as it goes.
pub const SPEED_MAX: f64 = 1000.0;

/// `v` as a person would write it: 1e-300, not three hundred zeros.
fn shown(v: f64) -> String {
    if v != 0.0 && v.is_finite() && !(1e-4..1e16).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// Whether `speed` is a pace [`EmulatedRobot::spawn`] serves.
pub fn check_speed(speed: f64) -> Result<f64, EmulatorError> {
    if speed.is_finite() && (SPEED_MIN..=SPEED_MAX).contains(&speed) {
        Ok(speed)
    } else {
        Err(EmulatorError::Speed(speed))
    }
}

/// What `hil serve` runs.
#[derive(Debug, Clone, Copy)]
pub struct ServeOptions {
    /// Robot seconds per wall-clock second.
    pub speed: f64,
    /// Robot time per slice: how often host bytes are taken in and the
    /// firmware's bytes sent out. Short against the firmware's 50 ms
    /// inter-byte timeout, so a frame written in two pieces is not torn.
    pub slice_s: f64,
    pub bench: BenchOptions,
    /// Serve the USB serial on a second pty (see [`usb_pty_serial`]).
    pub usb_pty: bool,
}

impl Default for ServeOptions {
    fn default() -> Self {
        Self {
            speed: 1.0,
            slice_s: 0.005,
            bench: BenchOptions::default(),
            usb_pty: false,
        }
    }
}

/// What the emulator shows of itself while it runs (the plant's pose is
/// what a camera over the floor would see; a real robot has none).
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct EmulatorView {
    pub robot_time_s: f64,
    pub x_mm: f64,
    pub y_mm: f64,
    pub theta_rad: f64,
    /// How far robot time is behind the requested pace, in robot seconds
    /// (the host is too slow for the speed asked).
    pub lag_s: f64,
    /// Why the emulator stopped, when it did.
    pub error: Option<String>,
}

/// Keeps a slice loop at `speed` times real time: the one reader of the
/// host clock, outside the simulation.
pub struct Pacer {
    start: Instant,
    speed: f64,
}

impl Pacer {
    pub fn new(speed: f64) -> Self {
        Self {
            start: Instant::now(),
            speed,
        }
    }

    /// Sleep until `robot_elapsed_s` is due; returns the lag in robot
    /// seconds when the loop is behind (0 when on time).
    pub fn wait(&self, robot_elapsed_s: f64) -> f64 {
        // Saturated, not a panic, should a pace outside SPEED_MIN reach here.
        let due =
            Duration::try_from_secs_f64(robot_elapsed_s / self.speed).unwrap_or(Duration::MAX);
        let now = self.start.elapsed();
        if due > now {
            std::thread::sleep(due - now);
            0.0
        } else {
            (now - due).as_secs_f64() * self.speed
        }
    }
}

/// The serial channel the USB pty serves: on an MCU with USB, the cable
/// in, the USB serial itself ([`USB_SERIAL`], the bench as the USB host);
/// else the board's debug USART (where the thesis build prints, through
/// the Mega's USB-serial converter).
pub fn usb_pty_serial(bench: &BenchOptions) -> u8 {
    if bench.board.mcu.chip().usb.is_some() && bench.usb_cable {
        USB_SERIAL
    } else {
        bench.board.debug_uart.usart
    }
}

/// An emulated robot running on its own thread (the simulator is not
/// `Send`), its USARTs on pseudo-terminals. Stops when dropped.
pub struct EmulatedRobot {
    path: PathBuf,
    usb_path: Option<PathBuf>,
    view: Arc<Mutex<EmulatorView>>,
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
}

impl EmulatedRobot {
    /// Boot the firmware on the bench and serve its command USART (the
    /// board's, Henrytwo's USART1) on a new pty, and its USB serial when
    /// [`ServeOptions::usb_pty`] asks.
    pub fn spawn(
        firmware: Firmware,
        robot: &RobotConfig,
        options: ServeOptions,
    ) -> Result<Self, EmulatorError> {
        Self::spawn_described(firmware, robot, options, None)
    }

    /// [`EmulatedRobot::spawn`] for a firmware that knows nothing of the
    /// bench, when `description` is given: ready as the description says,
    /// told nothing (it has no protocol for it), its command USART's boot
    /// bytes kept for the host (they are its own, not answers to the bench).
    pub fn spawn_described(
        firmware: Firmware,
        robot: &RobotConfig,
        options: ServeOptions,
        description: Option<Arc<Description>>,
    ) -> Result<Self, EmulatorError> {
        check_speed(options.speed)?;
        let board = options.bench.board;
        let command = PtyPort::open("pty")?;
        let usb = options
            .usb_pty
            .then(|| PtyPort::open("usb pty"))
            .transpose()?;
        let path = command.path().to_path_buf();
        let usb_path = usb.as_ref().map(|p| p.path().to_path_buf());
        let mut ports = vec![(board.command_uart.usart, command)];
        ports.extend(usb.map(|p| (usb_pty_serial(&options.bench), p)));
        let view = Arc::new(Mutex::new(EmulatorView::default()));
        let stop = Arc::new(AtomicBool::new(false));
        let (ready_tx, ready_rx) = std::sync::mpsc::channel();
        let robot = robot.clone();
        let thread = {
            let view = view.clone();
            let stop = stop.clone();
            std::thread::Builder::new()
                .name("emulated-robot".into())
                .spawn(move || {
                    let told = description.is_none();
                    let bench = Bench::new(firmware, &robot, options.bench).and_then(|mut b| {
                        match &description {
                            Some(d) => {
                                if let Some(c) = d.resolve(b.firmware())?.counts {
                                    b.set_count_variables(c);
                                }
                                wait_ready(&mut b, Some(d))?;
                            }
                            None => {
                                wait_ready(&mut b, None)?;
                                // Told its robot before the host comes: as a real
                                // robot keeps what it was told in its EEPROM.
                                if let Some(w) = crate::runs::start::tell(&mut b, &robot)? {
                                    eprintln!("warning: {w}");
                                }
                            }
                        }
                        Ok(b)
                    });
                    let bench = match bench {
                        Ok(b) => {
                            let _ = ready_tx.send(Ok(()));
                            b
                        }
                        Err(e) => {
                            let _ = ready_tx.send(Err(e));
                            return;
                        }
                    };
                    let result = serve_loop(bench, ports, options, told, &view, &stop);
                    if let Err(e) = result {
                        if let Ok(mut v) = view.lock() {
                            v.error = Some(e.to_string());
                        }
                    }
                })
                .map_err(|_| EmulatorError::Lost)?
        };
        match ready_rx.recv() {
            Ok(Ok(())) => {}
            Ok(Err(e)) => return Err(e.into()),
            Err(_) => return Err(EmulatorError::Lost),
        }
        Ok(Self {
            path,
            usb_path,
            view,
            stop,
            thread: Some(thread),
        })
    }

    /// The pty to open as a serial port: the command USART (the HC-05's).
    pub fn path(&self) -> &std::path::Path {
        &self.path
    }

    /// The pty of the USB serial ([`usb_pty_serial`]), when served.
    pub fn usb_path(&self) -> Option<&std::path::Path> {
        self.usb_path.as_deref()
    }

    /// The latest view of the emulator.
    pub fn view(&self) -> EmulatorView {
        self.view.lock().map(|v| v.clone()).unwrap_or_default()
    }

    /// True once the emulator stopped on its own (see `view().error`).
    pub fn finished(&self) -> bool {
        self.thread.as_ref().is_none_or(|t| t.is_finished())
    }

    /// Wait for the emulator to stop on its own (an error).
    pub fn join(mut self) -> Option<String> {
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
        self.view().error
    }
}

impl Drop for EmulatedRobot {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// Run the bench slice by slice, each port's client bytes into its USART
/// and the USART's bytes out to the port, until `stop`.
fn serve_loop(
    mut bench: Bench,
    mut ports: Vec<(u8, PtyPort)>,
    options: ServeOptions,
    told: bool,
    view: &Mutex<EmulatorView>,
    stop: &AtomicBool,
) -> Result<(), BenchError> {
    let t0 = bench.robot_time_s();
    // A served robot runs for days: the bench keeps nothing of its past
    // (no trace, no logs), and the firmware's bytes are taken as they come.
    bench.keep_latest_records();
    // The command USART's bytes at boot answered the bench telling the
    // robot its parameters: not the host's (unless nothing was told). The
    // USB serial's (a greeting, a menu) are what a terminal user opens it
    // for: kept.
    let command = bench.board().command_uart.usart;
    for n in 0..SERIALS as u8 {
        let bytes = bench.take_uart_output(n);
        if n == command && told {
            continue;
        }
        if let Some((_, port)) = ports.iter_mut().find(|(u, _)| *u == n) {
            port.queue(&bytes);
        }
    }
    let mut host = Vec::new();
    let pacer = Pacer::new(options.speed);
    while !stop.load(Ordering::Relaxed) {
        // Clients come and go between slices; host to robot: everything
        // written since the last slice.
        for (n, port) in &mut ports {
            port.follow_clients();
            host.clear();
            port.take_host_bytes(&mut host);
            if !host.is_empty() {
                bench.send(*n, &host);
            }
        }
        bench.run_for(options.slice_s)?;
        for n in 0..SERIALS as u8 {
            let bytes = bench.take_uart_output(n);
            // A USART not served (a debug port of `hil ui`'s robot) has no
            // listener here.
            if let Some((_, port)) = ports.iter_mut().find(|(u, _)| *u == n) {
                port.queue(&bytes);
                port.deliver();
            }
        }
        let elapsed = bench.robot_time_s() - t0;
        let pose = bench.core().robot().pose();
        if let Ok(mut v) = view.lock() {
            v.robot_time_s = bench.robot_time_s();
            v.x_mm = pose.x().0;
            v.y_mm = pose.y().0;
            v.theta_rad = pose.theta().0;
        }
        let lag = pacer.wait(elapsed);
        if let Ok(mut v) = view.lock() {
            v.lag_s = lag;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pacer_holds_robot_time_to_speed_times_wall_time() {
        let pacer = Pacer::new(10.0);
        let t0 = Instant::now();
        // 0.5 s of robot time at 10x: due 50 ms after the start.
        assert_eq!(pacer.wait(0.5), 0.0);
        let waited = t0.elapsed();
        assert!(
            waited >= Duration::from_millis(50) && waited < Duration::from_secs(2),
            "{waited:?}"
        );
        // Asking for a time long past reports the lag instead of sleeping.
        std::thread::sleep(Duration::from_millis(100));
        let lag = pacer.wait(0.5);
        assert!(lag >= 1.0 - 1e-9, "lag {lag}");
    }
}
