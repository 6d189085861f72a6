//! The whole plant: two bridges, two motors, two wheels with encoders, the battery, the
//! floor, the pose; the effects of the robot's config and the faults the bench sets.
//!
//! # How the bench drives it
//!
//! ```text
//! loop {
//!     t = min(next_encoder_transition(Left), next_encoder_transition(Right),
//!             next_internal_change(), next firmware event)
//!     advance_to(t rounded up to an emulated cycle)
//!     raise the encoder levels that changed; on a PWM register write: set_bridge(...);
//!     at a scheduled fault: set_motor_fault(...), set_slip_burst(...), ...
//!     re-plan a wheel after its transition; both after an input change, a fault or an
//!     internal change
//! }
//! ```
//!
//! Time is the plant's own: it starts at 0 and moves only through [`Robot::advance_to`]; no
//! host clock is read, and the random effects draw from seeded streams per stretch of floor
//! or per encoder pulse (a SplitMix64 stream per effect), so the same calls give the same results bit for bit
//! and the same seed the same floor however the plant is stepped.
//!
//! # Two halves
//!
//! - **Dynamics** (what the encoders see): per wheel, the motor's motion since its last
//!   change, one closed-form [`Segment`]; the battery voltage; the faults. It changes only at
//!   input changes, at faults, and at the internal changes [`Robot::next_internal_change`]
//!   announces (the battery's piecewise-constant voltage under `battery_sag`).
//! - **Ground** (what the floor sees): from the shaft angles to the pose,
//!   through backlash, wheel sizes, slip, toe and floor noise. Nothing here feeds back into
//!   the dynamics, so no ground effect can move an encoder edge.
//!
//! # Exactness
//!
//! A wheel's angle at any time is its segment evaluated at that time, never a sum of small
//! steps, so [`Robot::next_encoder_transition`] and [`Robot::advance_to`] see the same angle
//! function; the encoder's levels are a function of that angle ([`crate::encoder`]). The pose
//! is integrated from the wheel-angle increments by exact arcs over steps of at most
//! [`MAX_POSE_STEP`] (the arc is exact while the ratio of the wheel speeds is constant; over
//! 1 ms with 55-69 ms time constants the error is far below a micrometre), split at internal
//! changes and, with backlash, at every reversal of a wheel.

use crate::bridge::DriveState;
use crate::config::RobotConfig;
use crate::effects::battery_sag::{MotorLoad, SagState};
use crate::encoder::{self, Encoder, Imperfections, Watch};
use crate::fault::MotorFault;
use crate::ground::{effective_radius_mm, Ground};
use crate::motor::{Around, Modifiers, MotorModel, Segment};
use crate::pose::{Pose, World};
use crate::side::{PerSide, Side};
use crate::units::{Millimetres, RadPerSec, Radians, Seconds, ThesisRpm, TimeGrid, Volts};
use crate::Duty;
use crate::Error;
use std::cell::Cell;

/// How far ahead [`Robot::next_encoder_transition`] looks. A wheel that will not change its
/// encoder state within this time (at rest, or creeping to a stop short of the next state)
/// gets `None`; ask again after the next input change or after advancing this far.
pub const TRANSITION_HORIZON: Seconds = Seconds(10.0);

/// Longest step of the pose integration; [`Robot::advance_to`] subdivides longer intervals.
pub const MAX_POSE_STEP: Seconds = Seconds(1e-3);

/// How far the ground may lag behind the wheels before [`Robot::advance_to`] steps it (on
/// the grid of [`MAX_POSE_STEP`] all the same, so the pose does not depend on it).
const POSE_BATCH: Seconds = Seconds(8e-3);

/// Resolution of [`Robot::next_encoder_transition`]: the time returned is at most this much
/// (or one `f64` step of the time, if that is larger) after a time at which the encoder state
/// has not changed yet.
pub const TRANSITION_RESOLUTION: Seconds = Seconds(1e-12);

/// The simulated robot: the plant the bench drives.
#[derive(Debug, Clone)]
pub struct Robot {
    config: RobotConfig,
    seed: u64,
    dynamics: Dynamics,
    ground: Ground,
    /// The time the ground has been stepped to: the last instant of the pose grid (multiples
    /// of [`MAX_POSE_STEP`]) or change of the motion, whichever is later, up to now.
    pose_time: Seconds,
    /// The thesis decoder's count per side, kept for flawed encoders.
    decoded: PerSide<Decoded>,
}

/// The decoder's net A-edge count at quadrature state `q`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct Decoded {
    q: i64,
    count: i64,
}

/// Everything that sets the encoders' timing.
#[derive(Debug, Clone)]
struct Dynamics {
    now: Seconds,
    wheels: PerSide<Wheel>,
    battery: Battery,
}

/// The battery: a constant voltage, or the `battery_sag` model; and the bench's override.
#[derive(Debug, Clone)]
struct Battery {
    /// The model's voltage (constant, or the sag model's at its last update).
    modelled: Volts,
    sag: Option<SagState>,
    override_v: Option<Volts>,
}

/// One side: bridge inputs, motor, wheel, encoder.
#[derive(Debug, Clone)]
struct Wheel {
    motor: MotorModel,
    /// What the config's effects change in the motor.
    modifiers: Modifiers,
    /// Back-EMF constant, V per wheel rad/s (for the battery's load).
    back_emf: f64,
    fault: MotorFault,
    encoder: Encoder,
    in1: Duty,
    in2: Duty,
    /// Motion since the last change of input, fault or battery voltage.
    segment: Segment,
    /// The segment's last two evaluations, (time, angle, exponential): the bench asks for
    /// the same instants several times (a transition's search, the advance to it, the
    /// levels there), and the segment's exponential is the cost. Same bits as evaluating
    /// again.
    memo: Cell<[(f64, f64, f64); 2]>,
}

/// A memo that matches no time.
const NO_MEMO: [(f64, f64, f64); 2] = [(f64::NAN, 0.0, 0.0); 2];

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
    fn angle_at(&self, t: Seconds) -> f64 {
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
    fn replan(&mut self, now: Seconds, battery: Volts) {
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
    fn rests_whatever_the_voltage(&self, now: Seconds) -> bool {
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
    fn load(&self, at: Seconds, since: Seconds) -> MotorLoad {
        MotorLoad {
            drive: self.drive_state().drive(),
            back_emf: self.back_emf,
            speed: self.segment.speed_at(at).0,
            angle_change: self.angle_at(at) - self.angle_at(since),
        }
    }

    /// Encoder position `s` at `t` (see [`crate::encoder`]).
    fn position(&self, t: Seconds) -> f64 {
        self.encoder.position(Radians(self.angle_at(t)))
    }

    fn levels(&self, t: Seconds) -> (bool, bool) {
        self.encoder.levels_at(self.position(t))
    }

    /// Earliest time in `(now, until]` at which the encoder levels differ from `from` (the
    /// levels at `now`), under this segment, to `resolution`.
    fn next_transition(
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

/// How finely a transition time is wanted.
#[derive(Debug, Clone, Copy)]
enum Resolution {
    /// To [`TRANSITION_RESOLUTION`].
    Continuous,
    /// The first instant of the grid.
    Grid(TimeGrid),
}

impl Resolution {
    /// How closely Newton's method must locate the crossing first.
    fn tolerance(self) -> f64 {
        match self {
            Resolution::Continuous => TRANSITION_RESOLUTION.0,
            // A twentieth of a step: the grid search then checks one or two instants.
            Resolution::Grid(grid) => 0.05 / grid.hz() as f64,
        }
    }
}

/// The first time in `[a, b]` at which `crossed` holds, to [`TRANSITION_RESOLUTION`], given
/// that it does not at `a`, does at `b`, is monotone between, and changes near `guess`:
/// a bracket widening around the guess, then bisection on `crossed` itself, so the answer
/// agrees exactly with evaluating the segment.
fn first_crossed_near(
    a: Seconds,
    b: Seconds,
    guess: Seconds,
    crossed: &impl Fn(Seconds) -> bool,
) -> Seconds {
    let mut lo = a;
    let mut hi;
    let mut eps = TRANSITION_RESOLUTION.0;
    loop {
        let above = Seconds((guess.0 + eps).min(b.0));
        if crossed(above) {
            hi = above;
            break;
        }
        lo = Seconds(lo.0.max(above.0));
        eps *= 4.0;
    }
    let mut eps = TRANSITION_RESOLUTION.0;
    loop {
        let below = Seconds((guess.0 - eps).max(lo.0));
        if !crossed(below) {
            lo = below;
            break;
        }
        hi = Seconds(hi.0.min(below.0));
        eps *= 4.0;
    }
    while hi.0 - lo.0 > TRANSITION_RESOLUTION.0 {
        let mid = Seconds(lo.0 + 0.5 * (hi.0 - lo.0));
        if mid <= lo || mid >= hi {
            break;
        }
        if crossed(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

/// The first instant of `grid` in `[a, b]` at which `crossed` holds, under the same
/// conditions as [`first_crossed_near`]; the first instant after `b` if none in it does (the
/// crossing fell within the last step before `b`). Galloping from the instant after
/// `guess`, then bisection: with a good guess, two evaluations.
fn first_crossed_on_grid(
    grid: TimeGrid,
    a: Seconds,
    b: Seconds,
    guess: Seconds,
    crossed: &impl Fn(Seconds) -> bool,
) -> Seconds {
    let first = grid.index_at_or_after(a);
    let last = grid.index_at_or_after(b);
    let k = grid.index_at_or_after(guess).clamp(first, last);
    first_crossed_from(grid, first, last, k, crossed)
}

/// [`first_crossed_on_grid`] with the indices of `a`, `b` and the guess (clamped to them)
/// worked out: `first`, `last`, `k`.
fn first_crossed_from(
    grid: TimeGrid,
    first: u64,
    last: u64,
    k: u64,
    crossed: &impl Fn(Seconds) -> bool,
) -> Seconds {
    let holds = |k: u64| k >= last || crossed(grid.time(k));
    if holds(k) {
        // Every instant below `k` is below `last`: there `holds` is `crossed`.
        return first_crossed_below(grid, first, k, crossed);
    }
    // Invariant of the bisection: !holds(lo), holds(hi).
    let mut lo = k;
    let mut step = 1;
    let hi = loop {
        let above = (lo + step).min(last);
        if holds(above) {
            break above;
        }
        lo = above;
        step *= 2;
    };
    bisect(grid, lo, hi, &holds)
}

/// The first instant from `first` to `hi` at which `crossed` holds, given that it holds at
/// `hi` (and, being monotone, from there on): a search down from `hi`.
fn first_crossed_below(
    grid: TimeGrid,
    first: u64,
    mut hi: u64,
    crossed: &impl Fn(Seconds) -> bool,
) -> Seconds {
    let holds = |k: u64| crossed(grid.time(k));
    let mut step = 1;
    let lo = loop {
        if hi == first {
            return grid.time(first);
        }
        let below = hi.saturating_sub(step).max(first);
        if !holds(below) {
            break below;
        }
        hi = below;
        step *= 2;
    };
    bisect(grid, lo, hi, &holds)
}

/// Bisection to the first instant that holds, given `!holds(lo)` and `holds(hi)`.
fn bisect(grid: TimeGrid, mut lo: u64, mut hi: u64, holds: &impl Fn(u64) -> bool) -> Seconds {
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if holds(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    grid.time(hi)
}

/// The index `k` (an integer) of the last instant `k * MAX_POSE_STEP` of the pose grid at or
/// before `t`.
fn pose_grid_index(t: Seconds) -> f64 {
    let step = MAX_POSE_STEP.0;
    let mut k = (t.0 / step).floor().max(0.0);
    // The division rounds: make sure the instant is not after `t`, and the next one is.
    while k > 0.0 && k * step > t.0 {
        k -= 1.0;
    }
    while (k + 1.0) * step <= t.0 {
        k += 1.0;
    }
    k
}

/// The last instant of the pose grid at or before `t`.
fn pose_grid_at_or_before(t: Seconds) -> Seconds {
    Seconds(pose_grid_index(t) * MAX_POSE_STEP.0)
}

/// Steps `ground` from `from` to `to` under the wheels' current segments: at the pose grid's
/// instants in between, at the wheels' turning points when the ground needs them
/// (backlash), and at `to`.
fn integrate(ground: &mut Ground, wheels: &PerSide<Wheel>, from: Seconds, to: Seconds) {
    if to <= from {
        return;
    }
    let mut turns = [to; 4];
    let mut n = 0;
    if ground.needs_turning_points() {
        for side in Side::BOTH {
            for t in wheels.get(side).segment.turning_points(from, to) {
                turns[n] = t;
                n += 1;
            }
        }
        turns[..n].sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    let step = MAX_POSE_STEP.0;
    let mut k = pose_grid_index(from) + 1.0;
    let mut turn = 0;
    let mut at = from;
    while at < to {
        let next_turn = if turn < n { turns[turn].0 } else { to.0 };
        let next = Seconds((k * step).min(next_turn).min(to.0));
        ground.step(PerSide {
            left: wheels.left.angle_at(next),
            right: wheels.right.angle_at(next),
        });
        at = next;
        while k * step <= at.0 {
            k += 1.0;
        }
        while turn < n && turns[turn] <= at {
            turn += 1;
        }
    }
}

impl Battery {
    fn voltage(&self) -> Volts {
        self.override_v.unwrap_or(self.modelled)
    }
}

impl Dynamics {
    fn voltage(&self) -> Volts {
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
    fn account(&mut self) {
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
    fn sag_voltage(&self) -> Option<Volts> {
        let sag = self.battery.sag.as_ref()?;
        Some(Volts(sag.terminal_voltage(&self.loads(self.now, self.now))))
    }

    fn replan_all(&mut self) {
        let (now, volts) = (self.now, self.voltage());
        for side in Side::BOTH {
            self.wheels.get_mut(side).replan(now, volts);
        }
    }

    fn next_internal_change(&self) -> Option<Seconds> {
        if self.battery.override_v.is_some() {
            return None;
        }
        self.battery.sag.as_ref().map(|s| Seconds(s.next_update()))
    }

    /// The internal change due at `self.now`: a new battery voltage.
    fn apply_internal_change(&mut self) {
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
    fn advance_to(&mut self, t: Seconds) {
        while let Some(change) = self.next_internal_change().filter(|&c| c <= t) {
            self.now = change;
            self.apply_internal_change();
        }
        self.now = t;
    }
}

impl Robot {
    /// The robot of `config` at rest at the origin of [`World`], bridges coasting, time 0.
    /// `seed` seeds the random effects (`floor_noise`, `encoder_missed_counts`,
    /// `encoder_glitches`); without them nothing is random.
    pub fn new(config: &RobotConfig, seed: u64) -> Result<Robot, Error> {
        config.validate()?;
        let effects = &config.effects;
        let ground = Ground::new(config, seed);
        let battery = match &effects.battery_sag {
            Some(sag) => {
                let state = SagState::new(sag.clone());
                let idle = state.terminal_voltage(&[]);
                Battery {
                    modelled: Volts(idle),
                    sag: Some(state),
                    override_v: None,
                }
            }
            None => Battery {
                modelled: Volts(config.battery.voltage_v),
                sag: None,
                override_v: None,
            },
        };
        let make_wheel = |side: Side, index: u64| {
            let flaws = Imperfections {
                seed,
                side_index: index,
                missed_pulse_fraction: effects
                    .encoder_missed_counts
                    .as_ref()
                    .map_or(0.0, |e| e.fraction(side)),
                glitch_fraction: effects
                    .encoder_glitches
                    .as_ref()
                    .map_or(0.0, |e| e.fraction(side)),
                glitch_width_states: effects.encoder_glitches.as_ref().map_or(0.0, |e| {
                    e.width_states(config.encoder.a_edges_per_motor_rev)
                }),
            };
            let encoder = Encoder::new(
                config.encoder.gear_ratio,
                config.encoder.a_edges_per_motor_rev,
                config.encoder.reversed(side),
            )
            .with_imperfections(flaws);
            let mut friction_duty = effects.dead_band.as_ref().map_or(0.0, |e| e.extra(side));
            if let Some(castor) = &effects.castor_drag {
                let wheelbase = config.geometry.wheelbase_mm
                    * effects
                        .wheelbase_ratio
                        .as_ref()
                        .map_or(1.0, |e| e.actual_over_nominal_ratio);
                friction_duty +=
                    castor.friction_duty(side, wheelbase, effective_radius_mm(config, side));
            }
            let gain_ratio = effects
                .motor_gain_asymmetry
                .as_ref()
                .map_or(1.0, |e| e.ratio(side));
            let modifiers = Modifiers {
                gain_ratio,
                friction_duty,
                coast_tau: effects.coast.as_ref().map(|c| c.tau(side)),
            };
            let motor = config.motor.get(side).clone();
            let mut wheel = Wheel {
                back_emf: motor.back_emf_v_per_rad_s(gain_ratio),
                motor,
                modifiers,
                fault: MotorFault::None,
                encoder,
                in1: Duty::OFF,
                in2: Duty::OFF,
                segment: Segment::held(Seconds::ZERO, Radians::ZERO),
                memo: Cell::new(NO_MEMO),
            };
            wheel.replan(Seconds::ZERO, battery.voltage());
            wheel
        };
        let wheels = PerSide {
            left: make_wheel(Side::Left, 0),
            right: make_wheel(Side::Right, 1),
        };
        Ok(Robot {
            config: config.clone(),
            seed,
            dynamics: Dynamics {
                now: Seconds::ZERO,
                wheels,
                battery,
            },
            ground,
            pose_time: Seconds::ZERO,
            decoded: PerSide::default(),
        })
    }

    /// The config the robot was made from.
    pub fn config(&self) -> &RobotConfig {
        &self.config
    }

    /// The seed given to [`Robot::new`].
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// Plant time.
    pub fn now(&self) -> Seconds {
        self.dynamics.now
    }

    /// Battery voltage the motors see now: the override if set, else the constant
    /// `battery.voltage_v`, or the `battery_sag` model's voltage at its last update.
    pub fn battery_voltage(&self) -> Volts {
        self.dynamics.voltage()
    }

    /// State of charge under `battery_sag` (as of the last input change or update), in
    /// `[0, 1]`; `None` without the effect.
    pub fn battery_charge_fraction(&self) -> Option<f64> {
        self.dynamics
            .battery
            .sag
            .as_ref()
            .map(SagState::charge_fraction)
    }

    /// Sets the H-bridge inputs of `side` from now on (advance to the time of the change
    /// first). Both inputs are duties of PWM signals assumed to start their high time
    /// together; `in1` high alone drives the wheel forward (see [`crate::bridge`]). Setting the
    /// inputs a bridge already has changes nothing. Only this wheel's motion changes (the
    /// battery's voltage follows the load at its next update, not at once).
    pub fn set_bridge(&mut self, side: Side, in1: Duty, in2: Duty) {
        let wheel = self.dynamics.wheels.get(side);
        if (wheel.in1, wheel.in2) == (in1, in2) {
            return;
        }
        self.settle_pose();
        self.dynamics.account();
        let (now, volts) = (self.dynamics.now, self.dynamics.voltage());
        let wheel = self.dynamics.wheels.get_mut(side);
        wheel.in1 = in1;
        wheel.in2 = in2;
        wheel.replan(now, volts);
    }

    /// The bridge inputs `(in1, in2)` of `side`.
    pub fn bridge_inputs(&self, side: Side) -> (Duty, Duty) {
        let wheel = self.dynamics.wheels.get(side);
        (wheel.in1, wheel.in2)
    }

    /// The averaged bridge state of `side` (from its inputs, whatever the motor's fault).
    pub fn drive_state(&self, side: Side) -> DriveState {
        let (in1, in2) = self.bridge_inputs(side);
        DriveState::from_inputs(in1, in2)
    }

    /// Sets a fault of `side`'s motor from now on (advance to its time first); re-plan both
    /// wheels' transitions afterwards. See [`MotorFault`] for what each does to the encoder
    /// and the pose. An invalid fault (a load outside `[0, 1]`) is refused and changes
    /// nothing.
    pub fn set_motor_fault(&mut self, side: Side, fault: MotorFault) -> Result<(), Error> {
        fault.validate()?;
        if self.dynamics.wheels.get(side).fault == fault {
            return Ok(());
        }
        self.settle_pose();
        self.dynamics.account();
        let (now, volts) = (self.dynamics.now, self.dynamics.voltage());
        let wheel = self.dynamics.wheels.get_mut(side);
        wheel.fault = fault;
        wheel.replan(now, volts);
        Ok(())
    }

    /// The motor fault of `side`.
    pub fn motor_fault(&self, side: Side) -> MotorFault {
        self.dynamics.wheels.get(side).fault
    }

    /// From now on the ground sees `1 - slip_fraction` of `side`'s wheel travel (a patch of
    /// oil, a wheel lifted over a bump): the encoder is unaffected (the wheel turns as
    /// before), the pose curves towards the slipping side. `0` ends the burst; `1` is a wheel
    /// spinning in place. A fraction outside `[0, 1]` is refused.
    pub fn set_slip_burst(&mut self, side: Side, slip_fraction: f64) -> Result<(), Error> {
        if !(slip_fraction.is_finite() && (0.0..=1.0).contains(&slip_fraction)) {
            return Err(Error::InvalidFault {
                what: "slip_fraction",
                value: slip_fraction,
                allowed: "a slip fraction must lie in [0, 1]",
            });
        }
        self.settle_pose();
        self.ground.set_burst(side, slip_fraction);
        Ok(())
    }

    /// The slip burst of `side` (0 when none).
    pub fn slip_burst(&self, side: Side) -> f64 {
        self.ground.burst(side)
    }

    /// Forces the battery voltage the motors see (a brown-out scenario) from now on, or
    /// gives it back to the model with `None`; re-plan both wheels afterwards. Every driven
    /// wheel's steady speed scales with the voltage ([`crate::motor`]); the encoders follow.
    /// While an override is set the `battery_sag` model keeps counting the charge but does
    /// not change the voltage, and [`Robot::next_internal_change`] is `None`. A negative or
    /// non-finite voltage is refused.
    pub fn set_battery_voltage_override(&mut self, volts: Option<Volts>) -> Result<(), Error> {
        if let Some(v) = volts {
            if !(v.0.is_finite() && v.0 >= 0.0) {
                return Err(Error::InvalidFault {
                    what: "battery voltage override (V)",
                    value: v.0,
                    allowed: "a voltage must be finite and not negative",
                });
            }
        }
        if self.dynamics.battery.override_v == volts {
            return Ok(());
        }
        self.settle_pose();
        self.dynamics.account();
        self.dynamics.battery.override_v = volts;
        if volts.is_none() {
            let now = self.dynamics.now.0;
            if let Some(sag) = &mut self.dynamics.battery.sag {
                sag.skip_updates_to(now);
            }
            if let Some(v) = self.dynamics.sag_voltage() {
                self.dynamics.battery.modelled = v;
            }
        }
        self.dynamics.replan_all();
        Ok(())
    }

    /// The battery voltage override, if set.
    pub fn battery_voltage_override(&self) -> Option<Volts> {
        self.dynamics.battery.override_v
    }

    /// The next time after [`Robot::now`] at which the plant's own dynamics change without
    /// an input change: under `battery_sag`, the next voltage update (every
    /// `update_interval_s`); otherwise (or while the voltage is overridden) `None`.
    ///
    /// The bench schedules it as an event: `advance_to` it, then re-plan both wheels.
    /// `advance_to` applies the change at exactly this time even when asked to go past it,
    /// and [`Robot::next_encoder_transition`] already looks across it, so a transition
    /// planned before it stays right; re-planning after it is cheap and keeps the plan
    /// simple.
    pub fn next_internal_change(&self) -> Option<Seconds> {
        self.dynamics.next_internal_change()
    }

    /// Moves the plant to time `t` under the current inputs: wheel angles and speeds in closed
    /// form, internal changes at their exact times, the pose by arcs on a fixed grid of
    /// [`MAX_POSE_STEP`] (see [`Robot::pose`]).
    ///
    /// `t == now` does nothing. `t < now` (or a `t` that is not finite) is an error,
    /// [`Error::TimeWentBackwards`], and leaves the plant unchanged.
    pub fn advance_to(&mut self, t: Seconds) -> Result<(), Error> {
        if !t.0.is_finite() || t < self.dynamics.now {
            return Err(Error::TimeWentBackwards {
                now: self.dynamics.now,
                requested: t,
            });
        }
        while let Some(change) = self.dynamics.next_internal_change().filter(|&c| c <= t) {
            self.dynamics.now = change;
            self.settle_pose();
            self.dynamics.apply_internal_change();
        }
        self.dynamics.now = t;
        // The steps fall on the grid whenever they are taken: take them in batches.
        let grid = pose_grid_at_or_before(t);
        if grid.0 - self.pose_time.0 >= POSE_BATCH.0 {
            integrate(
                &mut self.ground,
                &self.dynamics.wheels,
                self.pose_time,
                grid,
            );
            self.pose_time = grid;
        }
        self.sync_decoded();
        Ok(())
    }

    /// Steps the ground to now, before the motion changes.
    fn settle_pose(&mut self) {
        let now = self.dynamics.now;
        integrate(&mut self.ground, &self.dynamics.wheels, self.pose_time, now);
        self.pose_time = now;
    }

    /// Brings the decoder counts of flawed encoders to the current states.
    fn sync_decoded(&mut self) {
        for side in Side::BOTH {
            let wheel = self.dynamics.wheels.get(side);
            if !wheel.encoder.is_flawed() {
                continue;
            }
            let q = wheel
                .encoder
                .quadrature_index(Radians(wheel.angle_at(self.dynamics.now)));
            let decoded = self.decoded.get_mut(side);
            decoded.count += wheel.encoder.decoded_between(decoded.q, q);
            decoded.q = q;
        }
    }

    /// The earliest time after [`Robot::now`] at which the encoder levels of `side` change
    /// under the current inputs, or `None` if they do not change within
    /// [`TRANSITION_HORIZON`] (ask again after the next input change, or after advancing).
    ///
    /// The answer takes the announced internal changes ([`Robot::next_internal_change`])
    /// into account: the search continues past each on a copy of the dynamics advanced to it.
    ///
    /// # Guarantee
    ///
    /// With `t_next` the answer and no input change or fault before it:
    /// - `advance_to(t)` for any `t` from `t_next` up to the following transition (one state
    ///   is about 210 us at the top speed of the nominal robot, 24.5 rad/s; a glitch of the
    ///   `encoder_glitches` effect is as short as its width at the wheel's speed) leaves
    ///   [`Robot::encoder_levels`] changed in exactly one channel, and without encoder
    ///   effects [`Robot::quadrature_index`] changed by exactly one. So the bench may round
    ///   `t_next` up to its next emulated cycle (62.5 ns).
    /// - There is a time `t_lo` with `t_next - t_lo <= max(1e-12 s, one f64 step of t_next)`
    ///   at which the levels have not changed yet: `advance_to(t_next - 1e-9)` leaves them
    ///   unchanged.
    ///
    /// Both hold bit for bit because the answer is found by bisection on the very function
    /// `advance_to` evaluates (the wheel's closed-form angle, through the encoder's level
    /// function), after Newton's method has located the boundary crossing. The angle is split
    /// at the speed's zero crossing (a wheel driven against its motion turns round) and at a
    /// Coulomb stop, so a boundary reached only after turning back is found too; boundaries
    /// where no level changes (a missed pulse) are skipped.
    pub fn next_encoder_transition(&self, side: Side) -> Option<Seconds> {
        self.next_encoder_transition_watching(side, Watch::Both)
    }

    /// [`Robot::next_encoder_transition`] for the channels in `watch` only. Watching A
    /// alone, a search that meets only missed pulses for [`crate::encoder::WATCH_A_STATES`]
    /// states returns the time it got there, at which nothing on A changes.
    pub fn next_encoder_transition_watching(&self, side: Side, watch: Watch) -> Option<Seconds> {
        self.search_transition(side, watch, Resolution::Continuous)
    }

    /// [`Robot::next_encoder_transition_watching`] for a reader that samples the levels on
    /// `grid` (the bench: at its CPU cycles): the index `k` of the first instant after now
    /// at which the levels differ, found without solving for the time to
    /// [`TRANSITION_RESOLUTION`]. Exact on the grid: the levels at `grid.time(k)` differ
    /// from now's, and at `grid.time(k - 1)` (if after now) they do not. Now must be an
    /// instant of the grid, or the answer may be an instant before now's next.
    pub fn next_encoder_transition_on(
        &self,
        side: Side,
        watch: Watch,
        grid: TimeGrid,
    ) -> Option<u64> {
        self.search_transition(side, watch, Resolution::Grid(grid))
            .map(|t| grid.index_at_or_after(t))
    }

    /// [`Robot::next_encoder_transition_on`] as if the robot had been advanced to instant
    /// `after` of the grid with its inputs unchanged: the transition after that one, for a
    /// reader that plans several ahead. `after` must lie from now up to the next internal
    /// change ([`Robot::next_internal_change`]); the answer is the one
    /// [`Robot::next_encoder_transition_on`] gives once the robot is there.
    pub fn next_encoder_transition_on_after(
        &self,
        side: Side,
        watch: Watch,
        grid: TimeGrid,
        after: u64,
    ) -> Option<u64> {
        let start = grid.time(after);
        debug_assert!(start >= self.dynamics.now, "plans ahead only");
        debug_assert!(
            self.dynamics
                .next_internal_change()
                .is_none_or(|c| start <= c),
            "plans beyond the next internal change"
        );
        self.search_transition_from(side, watch, Resolution::Grid(grid), start)
            .map(|t| grid.index_at_or_after(t))
    }

    fn search_transition(
        &self,
        side: Side,
        watch: Watch,
        resolution: Resolution,
    ) -> Option<Seconds> {
        self.search_transition_from(side, watch, resolution, self.dynamics.now)
    }

    /// The search from `start` (from now up to the next internal change).
    fn search_transition_from(
        &self,
        side: Side,
        watch: Watch,
        resolution: Resolution,
        start: Seconds,
    ) -> Option<Seconds> {
        let wheel = self.dynamics.wheels.get(side);
        let from = wheel.levels(start);
        let end = start + TRANSITION_HORIZON;
        let change = self.dynamics.next_internal_change().filter(|&c| c < end);
        if let Some(t) =
            wheel.next_transition(start, change.unwrap_or(end), from, watch, resolution)
        {
            return Some(t);
        }
        let change = change?;
        if wheel.rests_whatever_the_voltage(start) {
            return None;
        }
        self.search_transition_past(side, watch, resolution, from, change, end)
    }

    /// The search past the internal change at `change` (the levels there `from`), up to
    /// `end`: on a copy of the dynamics advanced to each change in turn.
    #[cold]
    fn search_transition_past(
        &self,
        side: Side,
        watch: Watch,
        resolution: Resolution,
        from: (bool, bool),
        change: Seconds,
        end: Seconds,
    ) -> Option<Seconds> {
        let mut dynamics = self.dynamics.clone();
        dynamics.advance_to(change);
        let mut at = change;
        loop {
            let change = dynamics.next_internal_change().filter(|&c| c < end);
            let until = change.unwrap_or(end);
            let wheel = dynamics.wheels.get(side);
            if let Some(t) = wheel.next_transition(at, until, from, watch, resolution) {
                return Some(t);
            }
            let change = change?;
            if wheel.rests_whatever_the_voltage(at) {
                return None;
            }
            dynamics.advance_to(change);
            at = change;
        }
    }

    /// Encoder levels `(A, B)` of `side` now, with the encoder effects.
    pub fn encoder_levels(&self, side: Side) -> (bool, bool) {
        self.dynamics.wheels.get(side).levels(self.dynamics.now)
    }

    /// Encoder levels `(A, B)` of `side` at `t`, without advancing the robot: exact for
    /// `t` from now up to the next change of the inputs or of the plant's own dynamics
    /// ([`Robot::next_internal_change`]), over which the wheels' closed forms hold. For a
    /// reader that samples a channel between the robot's events.
    pub fn encoder_levels_at(&self, side: Side, t: Seconds) -> (bool, bool) {
        debug_assert!(t >= self.dynamics.now, "encoder_levels_at looks ahead only");
        debug_assert!(
            self.dynamics.next_internal_change().is_none_or(|c| t <= c),
            "encoder_levels_at beyond the next internal change"
        );
        self.dynamics.wheels.get(side).levels(t)
    }

    /// A time within which `side`'s encoder position cannot move by `states` quadrature
    /// states, from any instant up to the next change of the inputs or of the plant's own
    /// dynamics: the distance over the largest speed of the wheel's present motion (infinite
    /// for a wheel at rest). For a reader that knows the levels at an instant: a level that
    /// changes only a state or more away from there cannot have changed that much later.
    pub fn encoder_travel_time_bound(&self, side: Side, states: f64) -> Seconds {
        let wheel = self.dynamics.wheels.get(side);
        let speed = wheel.segment.speed_bound();
        if speed == 0.0 {
            return Seconds(f64::INFINITY);
        }
        // A hair under the quotient, so that its rounding cannot make the bound late.
        Seconds(states * wheel.encoder.state_angle().0 / speed * (1.0 - 1e-9))
    }

    /// Quadrature state index `q` of `side` now (see [`crate::encoder`]): the shaft's
    /// position, whatever the encoder effects make of it.
    pub fn quadrature_index(&self, side: Side) -> i64 {
        let wheel = self.dynamics.wheels.get(side);
        wheel
            .encoder
            .quadrature_index(Radians(wheel.angle_at(self.dynamics.now)))
    }

    /// Net signed channel-A edges of `side` since time 0 as the thesis' decoder counts the
    /// levels (on every A change: `+1` if A differs from B, else `-1`), encoder effects
    /// included (missed pulses count nothing; a glitch counts `-1` while it lasts).
    pub fn a_edges(&self, side: Side) -> i64 {
        let wheel = self.dynamics.wheels.get(side);
        if wheel.encoder.is_flawed() {
            let s = wheel.position(self.dynamics.now);
            self.decoded.get(side).count + wheel.encoder.glitch_count_offset(s)
        } else {
            encoder::net_a_edges(self.quadrature_index(side))
        }
    }

    /// The encoder of `side`.
    pub fn encoder(&self, side: Side) -> &Encoder {
        &self.dynamics.wheels.get(side).encoder
    }

    /// Wheel speed of `side` now, positive rolling forward (the shaft's, before backlash and
    /// slip).
    pub fn wheel_speed(&self, side: Side) -> RadPerSec {
        self.dynamics
            .wheels
            .get(side)
            .segment
            .speed_at(self.dynamics.now)
    }

    /// Wheel speed of `side` now in the thesis' "RPM" (true RPM / 6).
    pub fn wheel_speed_thesis_rpm(&self, side: Side) -> ThesisRpm {
        self.wheel_speed(side).to_thesis_rpm()
    }

    /// Wheel angle of `side` since time 0, positive rolling forward: the angle the encoder
    /// measures (the motor shaft's over the gear ratio).
    pub fn wheel_angle(&self, side: Side) -> Radians {
        self.dynamics
            .wheels
            .get(side)
            .segment
            .angle_at(self.dynamics.now)
    }

    /// Signed arc rolled by the wheel of `side` since time 0: [`Robot::wheel_angle`] times the
    /// wheel's effective radius (with `wheel_diameter_ratio` and `distance_scale`), before
    /// backlash and slip.
    pub fn distance_travelled(&self, side: Side) -> Millimetres {
        Millimetres(self.ground.radius_mm(side) * self.wheel_angle(side).0)
    }

    /// The robot's pose in the [`World`] frame (origin and axes at the start pose).
    ///
    /// The pose is stepped at the instants of a fixed grid (multiples of [`MAX_POSE_STEP`])
    /// and at the changes of the motion (inputs, faults, the battery's steps), which are the
    /// same however the plant is advanced: so is the pose, bit for bit. Between them it is
    /// the last step's pose plus the arc to now, computed here and not kept.
    pub fn pose(&self) -> Pose<World> {
        if self.pose_time == self.dynamics.now {
            return self.ground.pose();
        }
        let mut ground = self.ground.clone();
        integrate(
            &mut ground,
            &self.dynamics.wheels,
            self.pose_time,
            self.dynamics.now,
        );
        ground.pose()
    }
}
