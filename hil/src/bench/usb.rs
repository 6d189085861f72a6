//! The bench as the USB host of an MCU with USB (the ATmega32U4): it plugs
//! the cable in (VBUS), waits for the firmware to attach, resets the bus,
//! enumerates the device (GET_DESCRIPTOR device and configuration,
//! SET_ADDRESS, SET_CONFIGURATION), opens its CDC serial port as a terminal
//! program does (SET_LINE_CODING, SET_CONTROL_LINE_STATE with DTR and RTS:
//! what `while (!Serial)` waits for), then polls the bulk IN endpoint for
//! the firmware's output and sends the host's bytes on the bulk OUT one.
//!
//! Everything happens at simulated cycles fixed by the frame clock: a start
//! of frame every millisecond at the frame's start, and at most one
//! transaction per endpoint at its middle (the firmware's USB interrupts run
//! in between). The same firmware gives the same bytes at the same cycles.
//! The timings are the USB 2.0 specification's: 100 ms from attach to the
//! bus reset (TATTDB), 10 ms of reset (TDRST), 10 ms of recovery (TRSTRCY).

use std::collections::VecDeque;

use crate::bench::NEVER;
use crate::mcu::clock::Clock;
use crate::mcu::sim::{Core, UsbAnswer, UsbPort};
use plant_model::Seconds;

/// A full-speed frame.
pub const FRAME_S: f64 = 1e-3;
/// From attach to the bus reset (USB 2.0, 7.1.7.3 TATTDB).
const DEBOUNCE_S: f64 = 0.1;
/// The bus reset (7.1.7.5 TDRST) and the recovery after it (9.2.6.2 TRSTRCY).
const RESET_S: f64 = 0.01;
const RECOVERY_S: f64 = 0.01;
/// The address the host gives the device.
const ADDRESS: u8 = 1;
/// The line coding the host sets: 115200 baud, 8N1 (USB ignores it).
const LINE_CODING: [u8; 7] = [0x00, 0xc2, 0x01, 0x00, 0, 0, 8];
/// A bulk packet of a full-speed device at most.
const PACKET: usize = 64;

/// Where the host is with the device.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum UsbState {
    /// The firmware has not attached to the bus (UDCON.DETACH still set).
    Detached,
    /// Attached; the bus reset follows the debounce.
    Attached,
    /// Enumerating: the request in progress.
    Enumerating(&'static str),
    /// Configured, the serial port open (DTR set): the bulk endpoints run.
    Open,
    /// The device refused a request (STALL) or answered nonsense: the host
    /// gave up on it.
    Failed(String),
}

/// The moments of the enumeration, for reports: (cycle, what).
pub type UsbEvents = Vec<(u64, &'static str)>;

/// A control transfer and where it is.
struct Control {
    name: &'static str,
    setup: [u8; 8],
    /// The data stage's bytes, host to device.
    out: Vec<u8>,
    stage: Stage,
    /// The data stage's bytes, device to host, so far.
    got: Vec<u8>,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Stage {
    Setup,
    DataIn,
    DataOut,
    StatusIn,
    StatusOut,
}

impl Control {
    fn new(
        name: &'static str,
        request_type: u8,
        request: u8,
        value: u16,
        index: u16,
        length: u16,
    ) -> Self {
        let [vl, vh] = value.to_le_bytes();
        let [il, ih] = index.to_le_bytes();
        let [ll, lh] = length.to_le_bytes();
        Self {
            name,
            setup: [request_type, request, vl, vh, il, ih, ll, lh],
            out: Vec::new(),
            stage: Stage::Setup,
            got: Vec::new(),
        }
    }

    fn get_descriptor(name: &'static str, kind: u8, length: u16) -> Self {
        Self::new(name, 0x80, 6, u16::from(kind) << 8, 0, length)
    }

    fn length(&self) -> usize {
        usize::from(u16::from_le_bytes([self.setup[6], self.setup[7]]))
    }

    fn device_to_host(&self) -> bool {
        self.setup[0] & 0x80 != 0
    }
}

/// The CDC serial's endpoints and interface, from the configuration
/// descriptor.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Serial {
    configuration: u8,
    /// The communication interface (class 2), which takes the line requests.
    interface: u8,
    bulk_in: u8,
    bulk_out: u8,
}

/// The host (see the module docs).
pub(super) struct UsbHost {
    port: UsbPort,
    frame: u64,
    state: UsbState,
    /// When the bus reset starts and ends, and the first frame after it.
    reset_at: u64,
    reset_end: u64,
    /// The next start of frame (its transactions come half a frame later).
    next_sof: u64,
    sof_due: bool,
    requests: VecDeque<Control>,
    current: Option<Control>,
    serial: Option<Serial>,
    /// The host's bytes for the firmware, not yet sent.
    tx: VecDeque<u8>,
    events: UsbEvents,
}

/// What a host step gave the caller: bytes from the firmware, bytes it took.
#[derive(Default)]
pub(super) struct Traffic {
    pub(super) received: Vec<u8>,
    pub(super) delivered: Vec<u8>,
}

impl UsbHost {
    pub(super) fn new(port: UsbPort, clock: Clock) -> Self {
        Self {
            port,
            frame: clock.cycles_in(Seconds(FRAME_S)).max(2),
            state: UsbState::Detached,
            reset_at: NEVER,
            reset_end: NEVER,
            next_sof: NEVER,
            sof_due: false,
            requests: VecDeque::new(),
            current: None,
            serial: None,
            tx: VecDeque::new(),
            events: Vec::new(),
        }
    }

    pub(super) fn state(&self) -> &UsbState {
        &self.state
    }

    pub(super) fn events(&self) -> &[(u64, &'static str)] {
        &self.events
    }

    /// The cable is in: VBUS on. Also after the MCU's reset, which clears
    /// the controller's registers and detaches the device.
    pub(super) fn plug(&mut self, core: &mut Core) {
        core.usb_vbus(&self.port, true);
        if self.state != UsbState::Detached {
            self.events.push((core.cycle(), "detached (MCU reset)"));
        }
        self.state = UsbState::Detached;
        self.reset_at = NEVER;
        self.reset_end = NEVER;
        self.next_sof = NEVER;
        self.current = None;
        self.requests.clear();
        self.serial = None;
    }

    /// The firmware attached (or detached) at `cycle`.
    pub(super) fn attach(&mut self, cycle: u64, attached: bool, clock: Clock) {
        if !attached {
            return;
        }
        self.events.push((cycle, "attached"));
        self.state = UsbState::Attached;
        self.reset_at = cycle + clock.cycles_in(Seconds(DEBOUNCE_S));
        self.reset_end = self.reset_at + clock.cycles_in(Seconds(RESET_S));
        self.next_sof = self.reset_end + clock.cycles_in(Seconds(RECOVERY_S));
        self.sof_due = true;
    }

    /// Queue the host's bytes for the firmware.
    pub(super) fn queue(&mut self, bytes: &[u8]) {
        self.tx.extend(bytes.iter().copied());
    }

    /// The host's next action.
    pub(super) fn next_due(&self) -> u64 {
        match self.state {
            UsbState::Detached | UsbState::Failed(_) => NEVER,
            _ => {
                let frame = if self.sof_due {
                    self.next_sof
                } else {
                    self.next_sof - self.frame / 2
                };
                self.reset_end.min(frame)
            }
        }
    }

    /// Do what is due at `when`.
    pub(super) fn step(&mut self, core: &mut Core, when: u64) -> Traffic {
        let mut traffic = Traffic::default();
        if self.reset_end <= when {
            self.reset_end = NEVER;
            core.usb_bus_reset(&self.port);
            self.events.push((self.reset_at, "bus reset"));
            self.enumerate();
        }
        if matches!(self.state, UsbState::Detached | UsbState::Failed(_)) {
            return traffic;
        }
        if self.sof_due && self.next_sof <= when {
            core.usb_vbus(&self.port, true);
            core.usb_start_of_frame(&self.port);
            self.sof_due = false;
            self.next_sof += self.frame;
        } else if !self.sof_due && self.next_sof - self.frame / 2 <= when {
            self.transactions(core, &mut traffic);
            self.sof_due = true;
        }
        traffic
    }

    fn enumerate(&mut self) {
        self.requests = [
            Control::get_descriptor("GET_DESCRIPTOR (device)", 1, 18),
            Control::new("SET_ADDRESS", 0x00, 5, u16::from(ADDRESS), 0, 0),
            Control::get_descriptor("GET_DESCRIPTOR (configuration, 9 bytes)", 2, 9),
        ]
        .into();
        self.current = None;
        self.serial = None;
        self.state = UsbState::Enumerating("GET_DESCRIPTOR (device)");
    }

    /// One frame's transactions: the control transfer's next stage, then
    /// the serial's bulk endpoints.
    fn transactions(&mut self, core: &mut Core, traffic: &mut Traffic) {
        if self.current.is_none() {
            self.current = self.requests.pop_front();
            if let Some(c) = &self.current {
                self.state = UsbState::Enumerating(c.name);
            }
        }
        if let Some(mut c) = self.current.take() {
            match self.control_stage(core, &mut c) {
                Ok(true) => self.done(core.cycle(), c),
                Ok(false) => self.current = Some(c),
                Err(e) => {
                    self.events.push((core.cycle(), "failed"));
                    self.state = UsbState::Failed(e);
                    return;
                }
            }
        }
        if self.state != UsbState::Open {
            return;
        }
        let Some(s) = self.serial else { return };
        if core.usb_endpoint(&self.port, s.bulk_in).enabled {
            let mut buf = [0u8; PACKET];
            if let UsbAnswer::Ack(n) = core.usb_in(&self.port, s.bulk_in, &mut buf) {
                traffic.received.extend_from_slice(&buf[..n]);
            }
        }
        if !self.tx.is_empty() && core.usb_endpoint(&self.port, s.bulk_out).enabled {
            let n = self.tx.len().min(PACKET);
            let packet: Vec<u8> = self.tx.iter().take(n).copied().collect();
            if core.usb_out(&self.port, s.bulk_out, &packet) == UsbAnswer::Ack(n) {
                self.tx.drain(..n);
                traffic.delivered = packet;
            }
        }
    }

    /// The next stage of `c`; Ok(true) when the transfer is complete.
    fn control_stage(&mut self, core: &mut Core, c: &mut Control) -> Result<bool, String> {
        let stalled = |c: &Control| Err(format!("the device stalled {}", c.name));
        match c.stage {
            Stage::Setup => {
                // Endpoint 0 is the firmware's to enable after the reset.
                if !core.usb_endpoint(&self.port, 0).enabled {
                    return Ok(false);
                }
                match core.usb_setup(&self.port, &c.setup) {
                    UsbAnswer::Ack(_) => {
                        c.stage = match (c.device_to_host(), c.length()) {
                            (_, 0) => Stage::StatusIn,
                            (true, _) => Stage::DataIn,
                            (false, _) => Stage::DataOut,
                        };
                    }
                    UsbAnswer::Nak => {}
                    UsbAnswer::Stall => return stalled(c),
                }
            }
            Stage::DataIn => {
                let mut buf = [0u8; PACKET];
                match core.usb_in(&self.port, 0, &mut buf) {
                    UsbAnswer::Ack(n) => {
                        c.got.extend_from_slice(&buf[..n]);
                        if n < PACKET || c.got.len() >= c.length() {
                            c.stage = Stage::StatusOut;
                        }
                    }
                    UsbAnswer::Nak => {}
                    UsbAnswer::Stall => return stalled(c),
                }
            }
            Stage::DataOut => {
                // The SETUP and the data share the FIFO: wait until the
                // firmware has read the SETUP (a device NAKs meanwhile).
                if core.usb_endpoint(&self.port, 0).setup_pending {
                    return Ok(false);
                }
                match core.usb_out(&self.port, 0, &c.out) {
                    UsbAnswer::Ack(_) => c.stage = Stage::StatusIn,
                    UsbAnswer::Nak => {}
                    UsbAnswer::Stall => return stalled(c),
                }
            }
            Stage::StatusIn => {
                let mut buf = [0u8; PACKET];
                match core.usb_in(&self.port, 0, &mut buf) {
                    UsbAnswer::Ack(_) => return Ok(true),
                    UsbAnswer::Nak => {}
                    UsbAnswer::Stall => return stalled(c),
                }
            }
            Stage::StatusOut => match core.usb_out(&self.port, 0, &[]) {
                UsbAnswer::Ack(_) => return Ok(true),
                UsbAnswer::Nak => {}
                UsbAnswer::Stall => return stalled(c),
            },
        }
        Ok(false)
    }

    /// `c` completed at `cycle`: what follows from its answer.
    fn done(&mut self, cycle: u64, c: Control) {
        self.events.push((cycle, c.name));
        let fail = |s: &mut Self, why: String| {
            s.state = UsbState::Failed(why);
            s.requests.clear();
        };
        match c.setup[1] {
            // GET_DESCRIPTOR
            6 if c.setup[3] == 1 && (c.got.len() < 8 || c.got[1] != 1) => {
                fail(self, format!("the device descriptor is {:02x?}", c.got));
            }
            6 if c.setup[3] == 2 && c.length() == 9 => {
                if c.got.len() < 9 || c.got[1] != 2 {
                    fail(self, format!("the configuration descriptor is {:02x?}", c.got));
                    return;
                }
                let total = u16::from_le_bytes([c.got[2], c.got[3]]);
                self.requests.push_back(Control::get_descriptor(
                    "GET_DESCRIPTOR (configuration)",
                    2,
                    total,
                ));
            }
            6 if c.setup[3] == 2 => match serial(&c.got) {
                Some(s) => {
                    self.serial = Some(s);
                    let iface = u16::from(s.interface);
                    let mut coding =
                        Control::new("SET_LINE_CODING", 0x21, 0x20, 0, iface, LINE_CODING.len() as u16);
                    coding.out = LINE_CODING.to_vec();
                    self.requests.extend([
                        Control::new("SET_CONFIGURATION", 0x00, 9, u16::from(s.configuration), 0, 0),
                        coding,
                        // DTR and RTS, as a terminal program opening the port.
                        Control::new("SET_CONTROL_LINE_STATE (DTR)", 0x21, 0x22, 0x03, iface, 0),
                    ]);
                }
                None => fail(
                    self,
                    format!(
                        "its configuration has no CDC serial (a class 2 interface and a bulk IN and OUT endpoint): {:02x?}",
                        c.got
                    ),
                ),
            },
            // SET_CONTROL_LINE_STATE: the port is open.
            0x22 => self.state = UsbState::Open,
            _ => {}
        }
    }
}

/// The CDC serial in a configuration descriptor: its value, the first
/// communication interface (class 2) and the first bulk IN and OUT
/// endpoints (of its data interface).
fn serial(config: &[u8]) -> Option<Serial> {
    let configuration = *config.get(5)?;
    let (mut interface, mut bulk_in, mut bulk_out) = (None, None, None);
    let mut at = 0;
    while at + 2 <= config.len() {
        let len = usize::from(config[at]);
        if len < 2 || at + len > config.len() {
            break;
        }
        let d = &config[at..at + len];
        match d[1] {
            4 if len >= 9 && d[5] == 2 && interface.is_none() => interface = Some(d[2]),
            5 if len >= 7 && d[3] & 3 == 2 => {
                let ep = d[2] & 0x0f;
                if d[2] & 0x80 != 0 {
                    bulk_in = bulk_in.or(Some(ep));
                } else {
                    bulk_out = bulk_out.or(Some(ep));
                }
            }
            _ => {}
        }
        at += len;
    }
    let (bulk_in, bulk_out) = (bulk_in?, bulk_out?);
    (bulk_in < 5 && bulk_out < 5).then_some(Serial {
        configuration,
        interface: interface?,
        bulk_in,
        bulk_out,
    })
}

impl std::fmt::Display for UsbState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            UsbState::Detached => {
                f.write_str("the firmware never attached to the bus (UDCON.DETACH never cleared)")
            }
            UsbState::Attached => f.write_str("attached, waiting for the bus reset"),
            UsbState::Enumerating(r) => write!(f, "enumeration stopped at {r} (no answer)"),
            UsbState::Open => f.write_str("configured, serial port open (DTR set)"),
            UsbState::Failed(why) => write!(f, "enumeration failed: {why}"),
        }
    }
}
