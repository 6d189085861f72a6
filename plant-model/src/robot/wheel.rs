//! One side of the plant: its bridge inputs, motor, fault and encoder, the wheel's
//! closed-form motion since its last change, and the search for the next encoder
//! transition on that motion.

use std::cell::Cell;

use super::crossing::{first_crossed_below, first_crossed_near, first_crossed_on_grid, Resolution};
use crate::bridge::DriveState;
use crate::effects::battery_sag::MotorLoad;
use crate::encoder::{Encoder, Watch};
use crate::fault::MotorFault;
use crate::motor::{Around, Modifiers, MotorModel, Segment};
use crate::units::{RadPerSec, Radians, Seconds, TimeGrid, Volts};
use crate::Duty;

/// One side: bridge inputs, motor, wheel, encoder.
#[derive(Debug, Clone)]
pub(super) struct Wheel {
    pub(super) motor: MotorModel,
    /// What the config's effects change in the motor.
    pub(super) modifiers: Modifiers,
    /// Back-EMF constant, V per wheel rad/s (for the battery's load).
    pub(super) back_emf: f64,
    pub(super) fault: MotorFault,
    pub(super) encoder: Encoder,
    pub(super) in1: Duty,
    pub(super) in2: Duty,
    /// Motion since the last change of input, fault or battery voltage.
    pub(super) segment: Segment,
    /// The segment's last two evaluations, (time, angle, exponential): the bench asks for
    /// the same instants several times (a transition's search, the advance to it, the
    /// levels there), and the segment's exponential is the cost. Same bits as evaluating
    /// again.
    pub(super) memo: Cell<[(f64, f64, f64); 2]>,
}

/// A memo that matches no time.
pub(super) const NO_MEMO: [(f64, f64, f64); 2] = [(f64::NAN, 0.0, 0.0); 2];

impl Wheel {
    fn set_segment(&mut self, segment: Segment) {
        self.segment = segment;
        self.memo.set(NO_MEMO);
    }

    /// [`Segment::evaluate`] through the memo.
    fn evaluate(&self, t: Seconds) -> (Radians, f64) {
        let memo = self.memo.get();
        for (at, angle, decay_m1) in memo {
            if at == t.0 {
                return (Radians(angle), decay_m1);
            }
        }
        let (angle, decay_m1) = self.segment.evaluate(t);
        self.memo.set([(t.0, angle.0, decay_m1), memo[0]]);
        (angle, decay_m1)
    }

    /// The segment's angle at `t` (rad), through the memo.
    pub(super) fn angle_at(&self, t: Seconds) -> f64 {
        self.evaluate(t).0 .0
    }

    /// What the motor sees of the bridge: its averaged state, or coasting if disconnected.
    fn drive_state(&self) -> DriveState {
        if self.fault == MotorFault::Disconnected {
            DriveState::COAST
        } else {
            DriveState::from_inputs(self.in1, self.in2)
        }
    }

    /// The effects' modifiers plus a load-step fault.
    fn modifiers(&self) -> Modifiers {
        let mut modifiers = self.modifiers;
        let load = self.fault.load_duty();
        if load != 0.0 {
            modifiers.friction_duty += load;
        }
        modifiers
    }

    /// A new segment from `now` on: inputs, fault or voltage changed.
    pub(super) fn replan(&mut self, now: Seconds, battery: Volts) {
        let angle = Radians(self.angle_at(now));
        if self.fault == MotorFault::Stall {
            self.set_segment(Segment::held(now, angle));
            return;
        }
        let speed = self.segment.speed_at(now);
        let relaxation =
            self.motor
                .relaxation_with(self.drive_state(), battery, &self.modifiers(), speed);
        self.set_segment(Segment::new(now, angle, speed, relaxation));
    }

    /// Whether the wheel is still at `now` and no voltage change can start it (stalled, or
    /// not driven beyond its dead band).
    pub(super) fn rests_whatever_the_voltage(&self, now: Seconds) -> bool {
        self.segment.is_at_rest_from(now)
            && (self.fault == MotorFault::Stall
                || self
                    .motor
                    .relaxation_with(
                        self.drive_state(),
                        Volts(1.0),
                        &self.modifiers(),
                        RadPerSec::ZERO,
                    )
                    .target
                    == RadPerSec::ZERO)
    }

    /// The load on the battery at `at`, with the angle travelled since `since`.
    pub(super) fn load(&self, at: Seconds, since: Seconds) -> MotorLoad {
        MotorLoad {
            drive: self.drive_state().drive(),
            back_emf: self.back_emf,
            speed: self.segment.speed_at(at).0,
            angle_change: self.angle_at(at) - self.angle_at(since),
        }
    }

    /// Encoder position `s` at `t` (see [`crate::encoder`]).
    pub(super) fn position(&self, t: Seconds) -> f64 {
        self.encoder.position(Radians(self.angle_at(t)))
    }

    pub(super) fn levels(&self, t: Seconds) -> (bool, bool) {
        self.encoder.levels_at(self.position(t))
    }

    /// Earliest time in `(now, until]` at which the encoder levels differ from `from` (the
    /// levels at `now`), under this segment, to `resolution`.
    pub(super) fn next_transition(
        &self,
        now: Seconds,
        until: Seconds,
        from: (bool, bool),
        watch: Watch,
        resolution: Resolution,
    ) -> Option<Seconds> {
        if self.segment.is_at_rest_from(now) {
            return None;
        }
        // The angle is monotone between the speed's zero crossing (a wheel driven against
        // its motion turns round) and the Coulomb stop, so the levels change on each piece
        // if and only if the next level boundary in its direction is reached by its end.
        let mut cuts = [until; 3];
        let mut n = 0;
        for t in self.segment.turning_points(now, until) {
            cuts[n] = t;
            n += 1;
        }
        cuts[..n].sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut a = now;
        let mut sa = self.position(a);
        for &b in &cuts[..=n] {
            if b > a {
                if let Resolution::Grid(grid) = resolution {
                    if let Some(t) = self.transition_on_grid_early((a, sa), b, from, watch, grid) {
                        return Some(t);
                    }
                }
                let sb = self.position(b);
                if let Some(t) = self.transition_on((a, sa), (b, sb), from, watch, resolution) {
                    return Some(t);
                }
                sa = sb;
            }
            a = b;
        }
        None
    }

    /// [`Wheel::transition_on`]'s answer on the grid, found without evaluating the piece's
    /// end `b` (usually the search's horizon, far away) when the levels are seen to change
    /// at the grid instant of Newton's guess: the position is monotone on the piece, so it
    /// is past the boundary at `b` too, and the answer is the one the full search gives.
    /// `None` when that cannot be seen (the caller then searches in full).
    fn transition_on_grid_early(
        &self,
        (a, sa): (Seconds, f64),
        b: Seconds,
        from: (bool, bool),
        watch: Watch,
        grid: TimeGrid,
    ) -> Option<Seconds> {
        if self.segment.is_at_rest_from(a) {
            return None;
        }
        // The direction of the motion from its speed at `a`, in the encoder's sense.
        let around = self.segment.around(a, self.evaluate(a));
        let (_, speed) = around.state(0.0);
        let seen = if self.encoder.is_reversed() {
            -speed
        } else {
            speed
        };
        if seen == 0.0 || seen.is_nan() {
            return None;
        }
        let upward = seen > 0.0;
        let boundary = self.encoder.next_level_change(sa, upward, from, watch);
        let passed = |s: f64| if upward { s >= boundary } else { s < boundary };
        let crossed = |t: Seconds| passed(self.position(t));
        let resolution = Resolution::Grid(grid);
        // The guess lies in [a, b], so its instant is at or after a's.
        let guess = self.boundary_crossing(around, a, b, upward, boundary, resolution.tolerance());
        let k = grid.index_at_or_after(guess);
        let at = grid.time(k);
        if at < b && crossed(at) {
            let first = grid.index_at_or_after(a);
            // All instants from `first` to `k` are before b: no need for its index.
            Some(first_crossed_below(grid, first, k, &crossed))
        } else {
            None
        }
    }

    /// The transition on the monotone piece `[a, b]` (with the encoder positions there), if
    /// the levels change on it.
    fn transition_on(
        &self,
        (a, sa): (Seconds, f64),
        (b, sb): (Seconds, f64),
        from: (bool, bool),
        watch: Watch,
        resolution: Resolution,
    ) -> Option<Seconds> {
        if sa == sb {
            return None;
        }
        let upward = sb > sa;
        let boundary = self.encoder.next_level_change(sa, upward, from, watch);
        let passed = |s: f64| if upward { s >= boundary } else { s < boundary };
        if !passed(sb) {
            return None;
        }
        let crossed = |t: Seconds| passed(self.position(t));
        let around = self.segment.around(a, self.evaluate(a));
        let guess = self.boundary_crossing(around, a, b, upward, boundary, resolution.tolerance());
        Some(match resolution {
            Resolution::Continuous => first_crossed_near(a, b, guess, &crossed),
            Resolution::Grid(grid) => first_crossed_on_grid(grid, a, b, guess, &crossed),
        })
    }

    /// Where the continuous angle passes `boundary` on the monotone piece `[a, b]`, to about
    /// `tolerance`: Newton's method, safeguarded by bisection, on `around` (the motion
    /// expanded about `a`).
    fn boundary_crossing(
        &self,
        around: Around,
        a: Seconds,
        b: Seconds,
        upward: bool,
        boundary: f64,
        tolerance: f64,
    ) -> Seconds {
        let dq = self.encoder.state_angle().0;
        // Work in the encoder's sense of rotation.
        let sense = if self.encoder.is_reversed() {
            -1.0
        } else {
            1.0
        };
        let dir = if upward { 1.0 } else { -1.0 };
        let boundary_angle = (boundary - 0.5) * dq;
        // g(a + u) >= 0 once the boundary is passed; g is increasing on the piece. The
        // motion expanded about `a` is cheap to evaluate: the answer is only a guess, which
        // the caller checks on the closed form.
        let g = |u: f64| {
            let (angle, speed) = around.state(u);
            (
                dir * (sense * angle - boundary_angle),
                dir * sense * speed,
                dir * sense * around.acceleration(speed),
            )
        };
        let span = b.0 - a.0;
        let (value_a, speed_a, accel_a) = g(0.0);
        // First guess: where the angle's Taylor parabola at `a` gets there.
        let discriminant = speed_a * speed_a - 2.0 * accel_a * value_a;
        let mut u = if speed_a > 0.0 && discriminant >= 0.0 {
            -2.0 * value_a / (speed_a + discriminant.sqrt())
        } else if speed_a > 0.0 {
            -value_a / speed_a
        } else {
            0.5 * span
        };
        let (mut lo, mut hi) = (0.0, span);
        for _ in 0..200 {
            if !(u > lo && u < hi) {
                u = lo + 0.5 * (hi - lo);
            }
            let (value, slope, _) = g(u);
            if value >= 0.0 {
                hi = u;
            } else {
                lo = u;
            }
            if hi - lo <= tolerance {
                break;
            }
            let next = u - value / slope;
            if (next - u).abs() <= 0.25 * tolerance {
                u = next;
                break;
            }
            u = next;
        }
        let t = a + Seconds(u);
        Seconds(t.0.clamp(a.0, b.0))
    }
}
