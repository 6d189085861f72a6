//! Everything that sets the encoders' timing: the two wheels' motions and the battery
//! (a constant voltage, the `battery_sag` model, or the bench's override), with the plant's
//! own changes (the battery's piecewise-constant voltage) at their announced times.

use super::wheel::Wheel;
use crate::effects::battery_sag::{MotorLoad, SagState};
use crate::side::{PerSide, Side};
use crate::units::{Seconds, Volts};

/// Everything that sets the encoders' timing.
#[derive(Debug, Clone)]
pub(super) struct Dynamics {
    pub(super) now: Seconds,
    pub(super) wheels: PerSide<Wheel>,
    pub(super) battery: Battery,
}

/// The battery: a constant voltage, or the `battery_sag` model; and the bench's override.
#[derive(Debug, Clone)]
pub(super) struct Battery {
    /// The model's voltage (constant, or the sag model's at its last update).
    pub(super) modelled: Volts,
    pub(super) sag: Option<SagState>,
    pub(super) override_v: Option<Volts>,
}

impl Battery {
    pub(super) fn voltage(&self) -> Volts {
        self.override_v.unwrap_or(self.modelled)
    }
}

impl Dynamics {
    pub(super) fn voltage(&self) -> Volts {
        self.battery.voltage()
    }

    /// Both motors' loads at `at`, with the angles travelled since `since`.
    fn loads(&self, at: Seconds, since: Seconds) -> [MotorLoad; 2] {
        [
            self.wheels.left.load(at, since),
            self.wheels.right.load(at, since),
        ]
    }

    /// Brings the battery's charge up to `now` (before any segment or voltage changes).
    pub(super) fn account(&mut self) {
        let volts = self.voltage().0;
        let now = self.now;
        if let Some(since) = self.battery.sag.as_ref().map(|s| Seconds(s.accounted_to())) {
            let loads = self.loads(now, since);
            if let Some(sag) = &mut self.battery.sag {
                sag.account(now.0, volts, &loads);
            }
        }
    }

    /// The sag model's terminal voltage under the load now.
    pub(super) fn sag_voltage(&self) -> Option<Volts> {
        let sag = self.battery.sag.as_ref()?;
        Some(Volts(sag.terminal_voltage(&self.loads(self.now, self.now))))
    }

    pub(super) fn replan_all(&mut self) {
        let (now, volts) = (self.now, self.voltage());
        for side in Side::BOTH {
            self.wheels.get_mut(side).replan(now, volts);
        }
    }

    pub(super) fn next_internal_change(&self) -> Option<Seconds> {
        if self.battery.override_v.is_some() {
            return None;
        }
        self.battery.sag.as_ref().map(|s| Seconds(s.next_update()))
    }

    /// The internal change due at `self.now`: a new battery voltage.
    pub(super) fn apply_internal_change(&mut self) {
        self.account();
        if let Some(sag) = &mut self.battery.sag {
            sag.count_update();
        }
        if let Some(volts) = self.sag_voltage() {
            self.battery.modelled = volts;
        }
        self.replan_all();
    }

    /// Moves to `t`, applying the internal changes on the way (no pose).
    pub(super) fn advance_to(&mut self, t: Seconds) {
        while let Some(change) = self.next_internal_change().filter(|&c| c <= t) {
            self.now = change;
            self.apply_internal_change();
        }
        self.now = t;
    }
}
