//! Boot and start: how the harness gets a firmware ready and starts its
//! tests, without writing to its memory anything it was not told to take.
//!
//! - With a test description: ready as its `[ready]` says, each test
//!   started as it describes (bytes on a USART, a pin held), the leg
//!   written only to the variable its `leg.variable` names.
//! - The bench's own builds: ready when `HT_STATE` says idle; a firmware
//!   that speaks the framed protocol is told the robot's geometry and the
//!   leg by SET_PARAM, then START_TEST; the thesis build, which takes no
//!   parameters, gets its leg in `HT_LEG_LENGTH_MM` (its bench interface)
//!   and its selector byte.
//! - Anything else is refused in one line that says to give a description.

use plant_model::Seconds;

use super::{Harness, HarnessError, Param, Test, TestName, TestRun};
use crate::bench::Bench;
use crate::firmware::description::{End, Start};
use crate::runs::experiment::described::{ended, Mark};

/// What names a test for [`Harness::start`]: a thesis [`Test`], a
/// [`TestName`], or a description's name as text (`"leg-and-spin"`).
pub trait IntoTestName {
    /// The name, or why it is none.
    fn into_test_name(self) -> Result<TestName, HarnessError>;
}

impl IntoTestName for Test {
    fn into_test_name(self) -> Result<TestName, HarnessError> {
        Ok(self.into())
    }
}

impl IntoTestName for TestName {
    fn into_test_name(self) -> Result<TestName, HarnessError> {
        Ok(self)
    }
}

impl IntoTestName for &str {
    fn into_test_name(self) -> Result<TestName, HarnessError> {
        TestName::parse(self).map_err(|e| HarnessError::Start(format!("test {self:?}: {e}")))
    }
}

/// The test started last, and how its end is seen.
pub(super) struct Started {
    test: TestName,
    how: Ends,
}

enum Ends {
    /// As its description says, looking past what came before the start.
    Described { end: End, mark: Mark },
    /// The bench interface's done count moved on and the firmware is idle.
    Interface { done_count: u16, before: u16 },
}

/// The leg of a run when none is given (`hil run`'s default).
pub(super) const DEFAULT_LEG_MM: f64 = 2000.0;

impl Harness {
    /// Run until the firmware is ready for a test after reset: as the
    /// test description's `[ready]` says (a text, or a time), else, for the
    /// bench's own builds, until `HT_STATE` reports idle (within 2 s of
    /// robot time). Does nothing when it already was.
    pub fn boot(&mut self) -> Result<(), HarnessError> {
        if self.booted() {
            return Ok(());
        }
        if self.description.is_none() && self.bench.vars().is_err() {
            return Err(no_interface(&self.bench));
        }
        crate::runs::start::wait_ready(&mut self.bench, self.description.as_deref())?;
        self.ready = true;
        Ok(())
    }

    fn booted(&self) -> bool {
        self.ready || (self.description.is_none() && self.bench.is_idle())
    }

    /// Start `test` (a thesis [`Test`], or a described test's name) with
    /// legs of `leg_mm` (10 to 5000 mm; `None`: the description's fixed
    /// leg, else 2000 mm), booting first if not yet ready: through the
    /// description when the harness has one, else as the module docs say.
    /// Returns at once: run it with [`Harness::run_until`] or
    /// [`Harness::run_until_done`].
    pub fn start(
        &mut self,
        test: impl IntoTestName,
        leg_mm: impl Into<Option<f64>>,
    ) -> Result<(), HarnessError> {
        let test = test.into_test_name()?;
        let asked = leg_mm.into();
        let leg_mm = match &self.description {
            Some(d) => d.leg_mm(asked, DEFAULT_LEG_MM)?,
            None => asked.unwrap_or(DEFAULT_LEG_MM),
        };
        let r = Param::LegLengthMm.range();
        if Param::LegLengthMm.check(leg_mm as f32).is_err() || !leg_mm.is_finite() {
            return Err(HarnessError::Leg {
                leg_mm,
                min: r.min,
                max: r.max,
            });
        }
        match self.description.clone() {
            Some(d) => {
                let start = d.start(test.clone())?.clone();
                let end = d.end_of(&test).clone();
                self.boot()?;
                if let Some(addr) = d.resolve(self.bench.firmware())?.leg {
                    self.bench.write_f32(addr, leg_mm as f32);
                }
                let mark = Mark::now(&self.bench);
                match start {
                    Start::Uart { usart, bytes } => self.bench.send(usart, &bytes),
                    Start::Pin { pin, high } => {
                        let mcu = self.bench.board().mcu;
                        let p = crate::board::pin_named(mcu, &pin).ok_or_else(|| {
                            HarnessError::Start(format!(
                                "{}: pin {pin:?} is no pin of the board's {mcu}",
                                d.path
                            ))
                        })?;
                        self.bench.drive_pin(p, high)?;
                    }
                }
                self.started = Some(Started {
                    test,
                    how: Ends::Described { end, mark },
                });
            }
            None => {
                let Some(thesis) = test.thesis() else {
                    return Err(HarnessError::Start(format!(
                        "{test} is no test of the bench's own builds (umbmark-cw, umbmark-ccw, \
                         line, triangle); a test of the firmware's own needs its description (.tests(path))"
                    )));
                };
                self.boot()?;
                let vars = *self.bench.vars()?;
                let before = self.bench.read_u16(vars.done_count);
                let firmware = self.bench.firmware();
                let framed = crate::firmware::params::takes_params(firmware);
                let leg = [(Param::LegLengthMm, leg_mm as f32)];
                let (params, _, _) = crate::firmware::params::plan(
                    firmware,
                    &self.robot,
                    self.bench.board(),
                    crate::firmware::params::Tell::Robot,
                    if framed { &leg } else { &[] },
                );
                if !framed {
                    // The thesis build takes no parameters: its bench
                    // interface is where its host puts the leg.
                    self.bench.write_f32(vars.leg_length_mm, leg_mm as f32);
                }
                // A firmware that speaks the framed protocol gets a framed
                // start: its raw selector byte counts only after 50 ms of
                // quiet on the line, which a test that just sent a command
                // does not leave.
                crate::runs::start::start_test(&mut self.bench, &params, framed, thesis);
                self.started = Some(Started {
                    test,
                    how: Ends::Interface {
                        done_count: vars.done_count,
                        before,
                    },
                });
            }
        }
        Ok(())
    }

    /// Run until the test [`Harness::start`] started last has ended, for
    /// at most `within_s` of robot time: as its description's end says
    /// (a text, the motors idle), else when the bench's own build counts it
    /// done and is idle. Ok(the robot time it ended at), else
    /// [`HarnessError::Timeout`] naming the test and what was seen.
    pub fn run_until_done(&mut self, within_s: f64) -> Result<f64, HarnessError> {
        super::check_time("run_until_done within_s", within_s)?;
        let Some(started) = &self.started else {
            return Err(HarnessError::Start(
                "run_until_done: no test was started (call start first)".into(),
            ));
        };
        let from_s = self.bench.robot_time_s();
        let done = match &started.how {
            Ends::Described { end, mark } => {
                let idle = self.bench.clock().cycles_in(Seconds(end.idle_s));
                let (end, mark) = (end.clone(), *mark);
                self.bench
                    .run_until(within_s, |b| ended(b, &end, idle, mark))?
            }
            Ends::Interface { done_count, before } => {
                let (count, before) = (*done_count, *before);
                self.bench
                    .run_until(within_s, |b| b.read_u16(count) != before && b.is_idle())?
            }
        };
        if done {
            return Ok(self.bench.robot_time_s());
        }
        let started = self.started.as_ref().expect("checked above");
        Err(HarnessError::Timeout {
            what: format!("the end of test {}", started.test),
            within_s,
            from_s,
            to_s: self.bench.robot_time_s(),
            seen: format!(
                "motors {:?}/{:?}, the firmware {}",
                self.motor_state(plant_model::Side::Left),
                self.motor_state(plant_model::Side::Right),
                self.bench.location()
            )
            .to_lowercase(),
        })
    }

    /// Run `test` whole, as `hil run` does, and analyse it: legs, turns,
    /// the end pose, the firmware's counts, every USART's text. Only on a
    /// harness fresh from its build (robot time 0): the run boots, starts
    /// and ends the test itself. `leg_mm` as for [`Harness::start`].
    pub fn run_test(
        &mut self,
        test: impl IntoTestName,
        leg_mm: impl Into<Option<f64>>,
    ) -> Result<TestRun, HarnessError> {
        let test = test.into_test_name()?;
        if self.bench.cycle() != 0 {
            return Err(HarnessError::Start(format!(
                "run_test {test}: the harness has run {:.3} s; run_test runs from reset, on a harness fresh from build()",
                self.bench.robot_time_s()
            )));
        }
        let asked = leg_mm.into();
        let leg_mm = match &self.description {
            Some(d) => d.leg_mm(asked, DEFAULT_LEG_MM)?,
            None => asked.unwrap_or(DEFAULT_LEG_MM),
        };
        let opts = crate::runs::experiment::TestOptions {
            leg_mm,
            description: self.description.clone(),
            ..Default::default()
        };
        let run = crate::runs::experiment::run_fresh(&mut self.bench, &self.robot, &test, &opts)?;
        self.ready = true;
        Ok(run)
    }
}

/// The refusal of a firmware the harness cannot start without a description.
fn no_interface(bench: &Bench) -> HarnessError {
    HarnessError::Start(format!(
        "{} has no bench interface (no HT_STATE): give its test description with .tests(path) \
         (docs/reference/test-description.md)",
        bench.firmware().name()
    ))
}
