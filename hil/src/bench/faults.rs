//! Fault scenarios on the bench: an [`Action`] (a fault starting or ending)
//! at a [`Trigger`] (a robot time, the n-th turn or leg, the n-th byte from
//! the host), as scenario files and the fault library schedule them
//! ([`ScheduledFault`]), and the schedule that holds them to their cycle
//! (the core applies them: an action may touch every part).
//!
//! An action the plant refuses (a slip outside [0, 1], ...) is not applied
//! and not logged as applied: the run ends with
//! [`BenchError::ActionRefused`](super::BenchError::ActionRefused).
//!
//! Cycle arithmetic saturates: a trigger or a duration beyond the 64-bit
//! cycle counter (1.2e12 s at 16 MHz) is due never, not at a wrapped cycle
//! (an undo before its fault). The schedule keeps which armed faults have
//! fired, so that a run can say which never did.

use plant_model::{Seconds, Side};
use serde::{Deserialize, Serialize};

use super::recorder::Motion;
use super::NEVER;
use crate::bench::inject::{Channel, EncoderFault, LinkFault};
use crate::mcu::clock::Clock;

/// A change the bench makes at a cycle: a fault starting or ending.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "action")]
pub enum Action {
    Encoder {
        side: Side,
        fault: EncoderFault,
    },
    Link {
        fault: LinkFault,
    },
    MotorDisconnected {
        side: Side,
        disconnected: bool,
    },
    /// Pull the MCU's reset line (the firmware restarts; the plant goes on).
    Reset,
    /// A fault of a motor and its wheel, in the plant (stall, load step, ...).
    Motor {
        side: Side,
        fault: plant_model::MotorFault,
    },
    /// The ground sees only (1 - slip) of a wheel's travel.
    SlipBurst {
        side: Side,
        slip: f64,
    },
    /// The battery's terminal voltage forced (None: the battery model again).
    /// Below the regulator's headroom VCC follows it; below the brown-out
    /// level the MCU is held in reset (see [`crate::mcu::supply`]).
    BatteryVolts {
        volts: Option<f64>,
    },
    /// A burst of glitch pulses on one encoder channel (EMI from the motor,
    /// a loose connector): `pulses` pulses `width_us` wide, one every
    /// `period_us`, each inverting the pin's level for its width.
    EncoderGlitch {
        side: Side,
        channel: Channel,
        pulses: u32,
        width_us: f64,
        period_us: f64,
    },
    /// The host sends these bytes on the Bluetooth link (a command, a retry),
    /// one per byte time, through the link's faults.
    HostSend {
        bytes: Vec<u8>,
    },
}

impl Action {
    /// The action's tag in a scenario file (`action = "encoder"`).
    pub fn name(&self) -> &'static str {
        match self {
            Action::Encoder { .. } => "encoder",
            Action::Link { .. } => "link",
            Action::MotorDisconnected { .. } => "motor_disconnected",
            Action::Reset => "reset",
            Action::Motor { .. } => "motor",
            Action::SlipBurst { .. } => "slip_burst",
            Action::BatteryVolts { .. } => "battery_volts",
            Action::EncoderGlitch { .. } => "encoder_glitch",
            Action::HostSend { .. } => "host_send",
        }
    }
}

/// When a scheduled action happens.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "at")]
pub enum Trigger {
    /// At a robot time (seconds since reset).
    Time { s: f64 },
    /// When the n-th spin turn (1-based) of the run starts.
    TurnStart { n: u32 },
    /// When the n-th straight leg (1-based) of the run starts.
    LegStart { n: u32 },
    /// When the n-th byte (1-based) from the host goes on the air on the
    /// Bluetooth link, before the link's faults apply to it.
    HostByte { n: u32 },
}

impl std::fmt::Display for Trigger {
    /// "at 3 s", "at the start of turn 3", "at host byte 2".
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Trigger::Time { s } => write!(f, "at {s} s"),
            Trigger::TurnStart { n } => write!(f, "at the start of turn {n}"),
            Trigger::LegStart { n } => write!(f, "at the start of leg {n}"),
            Trigger::HostByte { n } => write!(f, "at host byte {n}"),
        }
    }
}

/// A fault to inject: when, what, and what undoes it how long after (s).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ScheduledFault {
    pub trigger: Trigger,
    pub action: Action,
    pub undo: Option<(f64, Action)>,
}

impl ScheduledFault {
    pub fn new(trigger: Trigger, action: Action) -> Self {
        Self {
            trigger,
            action,
            undo: None,
        }
    }
}

/// An action waiting for its trigger, its undo after so many cycles, and
/// the index of the fault it arms (in arming order).
type Armed = (Trigger, Action, Option<(u64, Action)>, usize);

/// A scheduled action: its cycle, itself, and the armed fault it starts
/// (None for an undo or an action scheduled directly).
type Due = (u64, Action, Option<usize>);

/// The actions to come, the events that trigger them, and those applied.
#[derive(Default)]
pub(super) struct FaultSchedule {
    /// Scheduled actions, sorted by cycle (stable for equal cycles).
    actions: Vec<Due>,
    /// Actions waiting for an event, with an optional duration in cycles
    /// after which `undo` runs.
    triggered: Vec<Armed>,
    turns_started: u32,
    legs_started: u32,
    /// Bytes from the host that went on the air on the Bluetooth link.
    host_bytes: u32,
    /// Glitch pulse edges to come: (cycle, side, channel, on), sorted.
    glitches: Vec<(u64, usize, usize, bool)>,
    /// Log of the actions applied: (cycle, action).
    applied: Vec<(u64, Action)>,
    /// Per fault armed, in arming order: whether its action has come due.
    fired: Vec<bool>,
}

impl FaultSchedule {
    /// The next scheduled action's cycle, or glitch edge's.
    pub(super) fn next_due(&self) -> u64 {
        let action = self.actions.first().map_or(NEVER, |a| a.0);
        let glitch = self.glitches.first().map_or(NEVER, |g| g.0);
        action.min(glitch)
    }

    /// Schedule `action` at `cycle` (kept sorted; equal cycles keep order).
    pub(super) fn at(&mut self, cycle: u64, action: Action) {
        self.at_for(cycle, action, None);
    }

    /// [`Self::at`], for armed fault `origin` when it starts one.
    fn at_for(&mut self, cycle: u64, action: Action, origin: Option<usize>) {
        let pos = self.actions.partition_point(|a| a.0 <= cycle);
        self.actions.insert(pos, (cycle, action, origin));
    }

    /// Schedule fault `id`'s action at `cycle` and its undo `undo.0` cycles
    /// later (never, when that is past the cycle counter).
    fn start_at(&mut self, cycle: u64, id: usize, action: Action, undo: Option<(u64, Action)>) {
        if let Some((d, u)) = undo {
            self.at(cycle.saturating_add(d), u);
        }
        self.at_for(cycle, action, Some(id));
    }

    /// Run `action` when `trigger` fires, and `undo` `duration` cycles later.
    pub(super) fn arm(
        &mut self,
        clock: Clock,
        trigger: Trigger,
        action: Action,
        undo: Option<(u64, Action)>,
    ) {
        let id = self.fired.len();
        self.fired.push(false);
        match trigger {
            Trigger::Time { s } => self.start_at(cycle_at(clock, s), id, action, undo),
            _ => self.triggered.push((trigger, action, undo, id)),
        }
    }

    /// The armed faults (indexes in arming order) whose action never came
    /// due: a time past the run's end, an event the run never reached.
    pub(super) fn never_fired(&self) -> Vec<usize> {
        (0..self.fired.len()).filter(|&i| !self.fired[i]).collect()
    }

    /// Schedule at `cycle` every action armed for `event`.
    fn fire(&mut self, event: Trigger, cycle: u64) {
        let mut i = 0;
        while i < self.triggered.len() {
            if self.triggered[i].0 == event {
                let (_, action, undo, id) = self.triggered.remove(i);
                self.start_at(cycle, id, action, undo);
            } else {
                i += 1;
            }
        }
    }

    pub(super) fn take_due_action(&mut self, when: u64) -> Option<Action> {
        if self.actions.first().is_none_or(|a| a.0 > when) {
            return None;
        }
        let (_, action, origin) = self.actions.remove(0);
        if let Some(id) = origin {
            self.fired[id] = true;
        }
        Some(action)
    }

    pub(super) fn take_due_glitch(&mut self, when: u64) -> Option<(usize, usize, bool)> {
        self.glitches.first().is_some_and(|g| g.0 <= when).then(|| {
            let (_, i, ch, on) = self.glitches.remove(0);
            (i, ch, on)
        })
    }

    /// The motors began `motion` at `cycle`: a turn or a leg starts.
    pub(super) fn motion_started(&mut self, cycle: u64, motion: Motion) {
        let event = match motion {
            Motion::SpinCw | Motion::SpinCcw => {
                self.turns_started += 1;
                Trigger::TurnStart {
                    n: self.turns_started,
                }
            }
            Motion::Forward => {
                self.legs_started += 1;
                Trigger::LegStart {
                    n: self.legs_started,
                }
            }
            _ => return,
        };
        self.fire(event, cycle);
    }

    /// A byte from the host goes on the air on the Bluetooth link at `when`:
    /// the actions armed for it are due (the caller applies them before the
    /// link's faults).
    pub(super) fn host_byte(&mut self, when: u64) {
        self.host_bytes += 1;
        self.fire(Trigger::HostByte { n: self.host_bytes }, when);
    }

    /// A burst of `pulses` glitch pulses on channel `ch` of encoder `i` from
    /// `cycle`, `width` cycles wide, one every `period` cycles.
    pub(super) fn glitch_burst(
        &mut self,
        cycle: u64,
        (i, ch): (usize, usize),
        pulses: u32,
        width: u64,
        period: u64,
    ) {
        for k in 0..pulses as u64 {
            let on = cycle.saturating_add(k.saturating_mul(period));
            self.glitches.push((on, i, ch, true));
            self.glitches.push((on.saturating_add(width), i, ch, false));
        }
        self.glitches.sort_by_key(|g| g.0);
    }

    /// `action` was applied at `cycle`.
    pub(super) fn log_applied(&mut self, cycle: u64, action: Action) {
        self.applied.push((cycle, action));
    }

    /// The actions applied so far: (cycle, action).
    pub(super) fn applied(&self) -> &[(u64, Action)] {
        &self.applied
    }
}

/// The first cycle at or after robot time `s`; [`NEVER`] for a time the
/// cycle counter cannot reach (or not a number), so nothing wraps.
fn cycle_at(clock: Clock, s: f64) -> u64 {
    // Half the counter's range: far beyond any run, and where the grid's
    // rounding cannot step past u64::MAX.
    let limit = (u64::MAX / 2) as f64 / clock.hz() as f64;
    if s.is_nan() || s >= limit {
        NEVER
    } else {
        clock.cycle_at_or_after(Seconds(s))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reset_at(s: f64, undo_after: Option<u64>) -> FaultSchedule {
        let mut f = FaultSchedule::default();
        f.arm(
            Clock::MEGA_16MHZ,
            Trigger::Time { s },
            Action::Reset,
            undo_after.map(|d| (d, Action::Reset)),
        );
        f
    }

    /// A trigger past the cycle counter (1.2e12 s at 16 MHz) is due never,
    /// at once: no loop, no wrap.
    #[test]
    fn a_time_past_the_counter_is_never_due() {
        for s in [1.2e12, 1e300, f64::INFINITY, f64::NAN] {
            let f = reset_at(s, None);
            assert_eq!(f.next_due(), NEVER, "{s}");
            assert_eq!(f.never_fired(), vec![0], "{s}");
        }
    }

    /// An undo a huge number of cycles after its fault comes after it (at
    /// the end of time), not one cycle before it by wrapping.
    #[test]
    fn an_undo_never_precedes_its_fault() {
        let mut f = reset_at(1.0, Some(u64::MAX));
        assert_eq!(f.actions.len(), 2);
        assert_eq!(f.next_due(), 16_000_000, "the fault first");
        assert!(f.take_due_action(16_000_000).is_some());
        assert_eq!(f.next_due(), NEVER, "the undo saturates");
        assert!(f.never_fired().is_empty());
    }

    /// A fault armed for an event that never happens, and one whose time
    /// has not come, are reported; one that fired is not.
    #[test]
    fn faults_that_never_fired_are_named_by_index() {
        let mut f = FaultSchedule::default();
        let clock = Clock::MEGA_16MHZ;
        f.arm(clock, Trigger::Time { s: 0.5 }, Action::Reset, None);
        f.arm(clock, Trigger::TurnStart { n: 3 }, Action::Reset, None);
        f.arm(clock, Trigger::Time { s: 100.0 }, Action::Reset, None);
        while f
            .take_due_action(clock.cycle_at_or_after(Seconds(1.0)))
            .is_some()
        {}
        assert_eq!(f.never_fired(), vec![1, 2]);
        f.motion_started(20_000_000, Motion::SpinCw);
        f.motion_started(21_000_000, Motion::SpinCw);
        f.motion_started(22_000_000, Motion::SpinCcw);
        while f.take_due_action(22_000_000).is_some() {}
        assert_eq!(f.never_fired(), vec![2]);
    }
}
