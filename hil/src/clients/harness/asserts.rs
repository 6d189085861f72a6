//! Asserts that panic at the test's own line (`#[track_caller]`) with the
//! condition, what the bench saw instead and the robot time: a failing
//! test says what happened without a debugger.

use super::{until, Condition, Harness, Var};

impl Harness {
    /// Assert that `condition` holds now: a state (motors, pin, variable,
    /// pose) as it stands, bytes and frames among all the firmware sent
    /// since reset. Panics naming the condition and what was seen.
    #[track_caller]
    pub fn assert_holds(&self, condition: &Condition) {
        let mut probe = match until::Probe::since(condition, &self.bench, 0) {
            Ok(p) => p,
            Err(message) => panic!("assert_holds: the condition {message}"),
        };
        if !probe.holds(&self.bench) {
            panic!(
                "assertion failed at {:.3} s of robot time: {}; seen: {}",
                self.robot_time_s(),
                probe.what(),
                probe.seen
            );
        }
    }

    /// Run until `condition` holds, for at most `within_s` of robot time,
    /// as [`Harness::run_until`] does; panics at the caller's line with
    /// the condition, the window and what was seen when it did not hold
    /// (or when the run itself failed). Returns the robot time it held at.
    #[track_caller]
    pub fn assert_within(&mut self, condition: &Condition, within_s: f64) -> f64 {
        match self.run_until(condition, within_s) {
            Ok(t) => t,
            Err(e) => panic!("assertion failed: {e}"),
        }
    }

    /// Assert that the firmware variable `symbol`, read as `T`, is
    /// `expected`; panics with the value it holds (or why it cannot be
    /// read).
    #[track_caller]
    pub fn assert_var<T: Var>(&self, symbol: &str, expected: T) {
        match self.var::<T>(symbol) {
            Ok(v) if v == expected => {}
            Ok(v) => panic!(
                "assertion failed at {:.3} s of robot time: {symbol} = {expected:?}; seen: {symbol} = {v:?}",
                self.robot_time_s()
            ),
            Err(e) => panic!("assert_var: {e}"),
        }
    }

    /// Assert that the robot stands `distance_mm` from where it was at
    /// reset, within `tol_mm`; panics with where it stands.
    #[track_caller]
    pub fn assert_distance(&self, distance_mm: f64, tol_mm: f64) {
        let pose = self.pose();
        let d = pose.distance_from_origin();
        if (d.get() - distance_mm).abs() > tol_mm || !d.get().is_finite() {
            panic!(
                "assertion failed at {:.3} s of robot time: {distance_mm} mm +- {tol_mm} mm from the start; seen: {:.1} mm (x = {:.1} mm, y = {:.1} mm, heading {:.1} deg)",
                self.robot_time_s(),
                d.get(),
                pose.x().get(),
                pose.y().get(),
                pose.theta().to_degrees()
            );
        }
    }
}
