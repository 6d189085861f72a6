//! A scenario [`Condition`] judged live, at the run loop's checks, for
//! [`super::Harness::run_until`]: the same meanings as a scenario file's
//! `[[expect]]` (`hil::runs::scenario`), on the bench's state now instead of on a
//! finished run's logs. Bytes and frames count from the cycle the wait
//! began (all of a pattern's bytes at or after it), as an expectation's
//! window does.

use plant_model::Side;

use crate::bench::Bench;
use crate::board::Pin;
use crate::runs::scenario::judge::{
    describe, find_frame, find_pattern, motor_holds, pose_holds, var_holds,
};
use crate::runs::scenario::{Condition, Direction, Level, VarType};

/// A condition resolved against the bench: its pin, its variable's address.
pub(super) struct Probe<'c> {
    condition: &'c Condition,
    /// The cycle the wait began.
    open: u64,
    pin: Option<Pin>,
    var: Option<(u16, VarType)>,
    /// The bytes logged when last looked at: bytes and frames are judged
    /// again only when more have come.
    logged: usize,
    /// What was seen at the last check, for the timeout's message.
    pub(super) seen: String,
}

impl<'c> Probe<'c> {
    /// `condition` checked and resolved on `bench`, the wait opening now.
    pub(super) fn new(condition: &'c Condition, bench: &Bench) -> Result<Self, String> {
        Self::since(condition, bench, bench.cycle())
    }

    /// `condition` checked and resolved on `bench`, bytes and frames
    /// counted from cycle `open`.
    pub(super) fn since(
        condition: &'c Condition,
        bench: &Bench,
        open: u64,
    ) -> Result<Self, String> {
        condition.validate()?;
        let mut pin = None;
        let mut var = None;
        match condition {
            Condition::Pin { pin: name, .. } => {
                pin = crate::board::pin_named(bench.board().mcu, name);
            }
            Condition::Var { symbol, ty, .. } => {
                let addr = bench.firmware().variable(symbol, ty.size()).map_err(|e| {
                    format!(
                        "var {symbol}: {e} (type {ty:?} reads {} byte(s))",
                        ty.size()
                    )
                })?;
                var = Some((addr, *ty));
            }
            _ => {}
        }
        Ok(Self {
            condition,
            open,
            pin,
            var,
            logged: usize::MAX,
            seen: "nothing yet".into(),
        })
    }

    /// The condition in words.
    pub(super) fn what(&self) -> String {
        describe(self.condition)
    }

    /// Whether the condition holds at this check of the run loop.
    pub(super) fn holds(&mut self, bench: &Bench) -> bool {
        let command = bench.board().command_uart.usart;
        let core = bench.core();
        let now = bench.cycle();
        match self.condition {
            Condition::Uart {
                usart,
                text,
                bytes,
                dir,
            } => {
                let log = match dir {
                    Direction::Tx => core.uart_log(),
                    Direction::Rx => core.uart_rx_log(),
                };
                if log.len() == self.logged {
                    return false;
                }
                self.logged = log.len();
                let pattern = text.as_ref().map_or_else(
                    || bytes.clone().unwrap_or_default(),
                    |t| t.as_bytes().to_vec(),
                );
                let n = usart.unwrap_or(command);
                self.judged(find_pattern(log, n, &pattern, self.open, now))
            }
            Condition::Frame {
                usart,
                id,
                status,
                data,
            } => {
                let log = core.uart_log();
                if log.len() == self.logged {
                    return false;
                }
                self.logged = log.len();
                let n = usart.unwrap_or(command);
                let found = find_frame(
                    log,
                    n,
                    *id,
                    *status,
                    data.as_deref(),
                    self.open,
                    now,
                    bench.clock(),
                );
                self.judged(found)
            }
            Condition::Motor {
                side,
                state,
                duty_min,
                duty_max,
            } => {
                let mut holds = true;
                let mut seen = Vec::new();
                for s in side.sides() {
                    let (a, b) = core.robot().bridge_inputs(*s);
                    let (h, what) =
                        motor_holds(*state, *duty_min, *duty_max, *s, (a.get(), b.get()));
                    holds &= h;
                    seen.push(what);
                }
                self.seen = seen.join(", ");
                holds
            }
            Condition::Pin { pin: name, level } => {
                let Some(pin) = self.pin else {
                    return false;
                };
                let high = bench.read_u8(pin.pin_register()) & (1 << pin.bit) != 0;
                self.seen = format!("{name} {}", if high { "high" } else { "low" });
                high == (*level == Level::High)
            }
            Condition::Var { symbol, .. } => {
                let Some((addr, ty)) = self.var else {
                    return false;
                };
                let v = read_var(bench, addr, ty);
                self.seen = format!("{symbol} = {v}");
                var_holds(self.condition, v)
            }
            Condition::Pose { .. } => {
                let pose = core.robot().pose();
                let (holds, seen) =
                    pose_holds(self.condition, pose.x().0, pose.y().0, pose.theta().0);
                self.seen = seen;
                holds
            }
        }
    }

    fn judged(&mut self, found: Result<u64, String>) -> bool {
        match found {
            Ok(_) => true,
            Err(seen) => {
                self.seen = seen;
                false
            }
        }
    }
}

/// The firmware variable at `addr`, read as `ty`.
pub(super) fn read_var(bench: &Bench, addr: u16, ty: VarType) -> f64 {
    ty.value(read_bytes(bench, addr, ty))
}

/// The bytes of the variable at `addr` of type `ty`, the rest 0.
pub(super) fn read_bytes(bench: &Bench, addr: u16, ty: VarType) -> [u8; 4] {
    let mut b = [0u8; 4];
    for (k, byte) in b.iter_mut().enumerate().take(ty.size() as usize) {
        *byte = bench.read_u8(addr + k as u16);
    }
    b
}

/// A motor's signed drive duty (forward positive), from its bridge inputs.
pub(super) fn drive_duty(bench: &Bench, side: Side) -> f64 {
    let (a, b) = bench.core().robot().bridge_inputs(side);
    a.get() - b.get()
}
