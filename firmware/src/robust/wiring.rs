//! The motor driver's wiring at START_TEST: the wiring in the settings is
//! checked and applied before a test runs, so pins moved one at a time by
//! SET_PARAM take effect together, and a wiring that cannot be driven is
//! refused (with a debug line naming the pin and why) instead of driven.

use henrytwo_protocol::{Param, Status};

use crate::driver::check::settable_pin;
use crate::io::Bridges;

use super::{App, Hardware};

/// Whether SET_PARAM may set `p` to `v` (already in the protocol's range):
/// a driver pin must be a Mega pin or `NO_PIN`; the rest of the wiring rules
/// wait for START_TEST.
pub(crate) fn settable(p: Param, v: f32) -> bool {
    match p {
        Param::LeftPin1
        | Param::LeftPin2
        | Param::LeftPin3
        | Param::RightPin1
        | Param::RightPin2
        | Param::RightPin3 => settable_pin(v as u8),
        _ => true,
    }
}

impl<H: Hardware> App<H> {
    /// Makes the settings' wiring the driver's, or refuses it
    /// ([`Status::OutOfRange`]) with a debug line; the wiring the driver has
    /// already passes without a check.
    pub(crate) fn apply_wiring(&mut self) -> Result<(), Status> {
        let w = self.stored.settings.driver;
        if self.drive.motors.drives(&w) {
            return Ok(());
        }
        if let Err(e) = w.check() {
            let _ = ufmt::uwrite!(&mut self.debug, "wiring refused: {}\r\n", e);
            return Err(Status::OutOfRange);
        }
        self.drive.motors.rewire(&w);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use std::vec;
    use std::vec::Vec;

    use henrytwo_protocol::{Command, CommandId, Param, Status, Test};

    use crate::robust::fake::{self, Fake, Sent};
    use crate::robust::sequencer::Mode;
    use crate::robust::App;

    fn ask(app: &mut App<Fake>, cmd: Command) -> Vec<Sent> {
        app.receive(cmd);
        app.poll();
        app.sent()
    }

    fn status(id: CommandId, s: Status) -> Vec<Sent> {
        vec![(id.reply_id(), s as u8, vec![])]
    }

    #[test]
    fn start_test_refuses_a_wiring_that_cannot_be_driven_and_says_why() {
        let _bench = fake::lock();
        let mut app = App::fake();
        // Right pin 1 on D13 (timer 0): each pin is a Mega pin, so SET_PARAM
        // takes it ...
        let r = ask(&mut app, Command::SetParam(Param::RightPin1, 13.0));
        assert_eq!(r[0].1, Status::Ok as u8);
        // ... and START_TEST refuses the whole wiring.
        assert_eq!(ask(&mut app, Command::StartTest(Test::Line)), status(CommandId::StartTest, Status::OutOfRange));
        assert_eq!(app.mode, Mode::Idle);
        assert!(app.drive.motors.log.is_empty(), "no motor driven");
        assert_eq!(app.debug.text(), "wiring refused: right pin 1 = 13: no PWM of timer 2-5\r\n");
        // Moved back, the test starts.
        ask(&mut app, Command::SetParam(Param::RightPin1, 7.0));
        let r = ask(&mut app, Command::StartTest(Test::Line));
        assert_eq!(r[0].1, Status::Ok as u8);
    }

    #[test]
    fn set_param_takes_a_mega_pin_or_none_for_a_driver_pin() {
        let _bench = fake::lock();
        let mut app = App::fake();
        for v in [0.0, 69.0, 255.0] {
            let r = ask(&mut app, Command::SetParam(Param::LeftPin3, v));
            assert_eq!(r[0].1, Status::Ok as u8, "{v}");
            assert_eq!(app.stored.settings.driver.left[2], v as u8);
        }
        for v in [70.0, 254.0] {
            let r = ask(&mut app, Command::SetParam(Param::LeftPin3, v));
            assert_eq!(r, status(CommandId::SetParam, Status::OutOfRange), "{v}");
            assert_eq!(app.stored.settings.driver.left[2], 255, "unchanged");
        }
        // Other parameters keep the protocol's range only.
        let r = ask(&mut app, Command::SetParam(Param::StallDuty, 254.0));
        assert_eq!(r[0].1, Status::Ok as u8);
    }
}
