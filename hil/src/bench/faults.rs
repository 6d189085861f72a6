//! Fault scenarios on the bench: an [`Action`] (a fault starting or ending)
//! at a [`Trigger`] (a robot time, the n-th turn or leg, the n-th byte from
//! the host), as scenario files and the fault library schedule them
//! ([`ScheduledFault`]), and the schedule that holds them to their cycle
//! (the core applies them: an action may touch every part).
//!
//! An action the plant refuses (a slip outside [0, 1], ...) is not applied
//! and not logged as applied: the run ends with
//! [`BenchError::ActionRefused`](super::BenchError::ActionRefused).

use plant_model::{Seconds, Side};
use serde::{Deserialize, Serialize};

use super::recorder::Motion;
use super::NEVER;
use crate::inject::{Channel, EncoderFault, LinkFault};
use crate::time::Clock;

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
    /// level the MCU is held in reset (see [`crate::supply`]).
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

/// An action waiting for its trigger, and its undo after so many cycles.
type Armed = (Trigger, Action, Option<(u64, Action)>);

/// The actions to come, the events that trigger them, and those applied.
#[derive(Default)]
pub(super) struct FaultSchedule {
    /// Scheduled actions, sorted by cycle (stable for equal cycles).
    actions: Vec<(u64, Action)>,
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
        let pos = self.actions.partition_point(|a| a.0 <= cycle);
        self.actions.insert(pos, (cycle, action));
    }

    /// Run `action` when `trigger` fires, and `undo` `duration` cycles later.
    pub(super) fn arm(
        &mut self,
        clock: Clock,
        trigger: Trigger,
        action: Action,
        undo: Option<(u64, Action)>,
    ) {
        match trigger {
            Trigger::Time { s } => {
                let at = clock.cycle_at_or_after(Seconds(s));
                if let Some((d, u)) = undo {
                    self.at(at + d, u);
                }
                self.at(at, action);
            }
            _ => self.triggered.push((trigger, action, undo)),
        }
    }

    /// Schedule at `cycle` every action armed for `event`.
    fn fire(&mut self, event: Trigger, cycle: u64) {
        let mut i = 0;
        while i < self.triggered.len() {
            if self.triggered[i].0 == event {
                let (_, action, undo) = self.triggered.remove(i);
                if let Some((d, u)) = undo {
                    self.at(cycle + d, u);
                }
                self.at(cycle, action);
            } else {
                i += 1;
            }
        }
    }

    pub(super) fn take_due_action(&mut self, when: u64) -> Option<Action> {
        self.actions
            .first()
            .is_some_and(|a| a.0 <= when)
            .then(|| self.actions.remove(0).1)
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
            let on = cycle + k * period;
            self.glitches.push((on, i, ch, true));
            self.glitches.push((on + width, i, ch, false));
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
