//! Where an encoder edge is born: the plant says when each wheel's next
//! transitions happen (solved from the motor's analytic response), the bench
//! plans them several at a time with the plant's levels at each, puts the
//! next one on the event queue, and raises it on the MCU pins at its cycle,
//! through the encoder faults and glitches of `crate::bench::inject`.
//!
//! Two economies, both exact for what the firmware can see:
//! - A planned edge with nothing else due is raised from the plan alone;
//!   the plant is left where it is and catches up at the next event that
//!   needs it ([`Encoders::raise_planned_edges`]).
//! - Channel B on a pin that can interrupt nothing is raised lazily: only
//!   when the firmware reads its PIN register, or with an A edge
//!   ([`Encoders::lazy_b_change`]); shortly after a planned A edge such a
//!   read is answered from the plan (B cannot have changed yet).

use plant_model::encoder::Watch;
use plant_model::{Robot, Seconds, Side};

use super::recorder::Recorder;
use super::NEVER;
use crate::bench::inject::{EncoderFault, Injection};
use crate::board::{Board, EncoderKind, EncoderWiring};
use crate::mcu::clock::Clock;
use crate::mcu::sim::{Core, DrivenPin};

/// Transitions planned per wheel beyond the next when nothing tells how
/// long the inputs will last (see `Encoders::plan_edge`).
const EDGES_PLANNED: usize = 8;

/// At most this many transitions planned beyond the next up to the time
/// the inputs are expected to change (see `Encoders::plan_edge`).
const EDGES_PLANNED_TO_CHANGE: usize = 32;

/// A planned transition of an encoder: its cycle, and the plant's levels
/// `(A, B)` there when they are known from the plan (up to the plant's next
/// internal change).
#[derive(Debug, Clone, Copy)]
struct PlannedEdge {
    cycle: u64,
    levels: Option<(bool, bool)>,
}

/// The thesis' encoder ISR: the count change for an A edge to level `a`
/// while B is at `b`.
pub fn decode_a_edge(a: bool, b: bool) -> i64 {
    match (a, b) {
        (true, false) | (false, true) => 1,
        _ => -1,
    }
}

/// A decoder of all four edges (Pololu's on an xor wiring): the count
/// change from channel levels `(a, b)` to `(na, nb)`: +1 for a step with A
/// leading B (the plant's forward), -1 the other way, 0 for no step or a
/// jump of both lines (undecodable).
pub fn decode_step((a, b): (bool, bool), (na, nb): (bool, bool)) -> i64 {
    i64::from(na ^ b) - i64::from(a ^ nb)
}

/// Both encoders' pins and their plans, indexed by side (`Side::index`),
/// then channel (A, B).
pub(super) struct Encoders {
    wiring: [EncoderWiring; 2],
    irq: [[Option<DrivenPin>; 2]; 2],
    /// The levels on the pins: the interrupt pin (A, or A xor B), B.
    level: [[bool; 2]; 2],
    /// Encoder levels after the encoder faults, before glitches.
    base: [[bool; 2]; 2],
    /// Per side: channel B is raised only when the firmware reads its PIN
    /// register (or with an A edge), not at its own transitions. Exact while
    /// nothing but a read can see B (see `lazy_b_change`).
    lazy_b: [bool; 2],
    /// Lazy B is allowed at all (off when the true waveform is wanted, e.g.
    /// for a VCD).
    lazy_b_allowed: bool,
    /// A planned edge may be raised from the plan alone, the plant left
    /// where it is, and a lazy B read right after an A edge answered
    /// without it (off only to check that this changes nothing).
    lean_edges: bool,
    /// The analog comparator's interrupt or input capture is on (ACSR): a
    /// B line on AIN1 is then watched by hardware.
    comparator_on: bool,
    /// Callbacks that raised planned edges from the plan alone.
    lean_edge_callbacks: u64,
    /// PIN reads that brought a lazy B up to date.
    lazy_b_reads: u64,
    /// PIN reads of a lazy B answered from the last A edge, the plant not
    /// looked at.
    quiet_b_reads: u64,
    /// PIN reads of a lazy B that evaluated the plant.
    b_reads_evaluated: u64,
    /// Edges raised on the pins, signed as the wiring's decoder counts
    /// them: A edges as the thesis' does (A/B quadrature), every edge of
    /// either channel (xor).
    edges_raised: [i64; 2],
    /// Cycle at which the last A edge of each encoder was due (the plant's
    /// edge time; simavr raises it at the first instruction boundary after).
    last_a_edge: [u64; 2],
    next_edge: [u64; 2],
    /// The transitions planned after `next_edge` under the present inputs,
    /// latest first: an edge's callback pops the next one instead of
    /// searching (any change re-plans from scratch).
    planned: [Vec<PlannedEdge>; 2],
    /// Cycle of each wheel's last input change, and the cycles between its
    /// last two (0: not seen yet): a controller changes them at its own
    /// period, and a plan made at a change reaches about that far.
    input_changed_at: [u64; 2],
    input_period: [u64; 2],
    /// The plant's levels `(A, B)` at `next_edge`, when known in advance.
    next_levels: [Option<(bool, bool)>; 2],
    /// Cycles after a planned A edge during which the wheel cannot reach a
    /// B boundary (half a state at its present motion's top speed), and
    /// the cycle up to which a read of a lazy B needs no look at the plant.
    b_quiet_cycles: [u64; 2],
    b_quiet_until: [u64; 2],
    /// Next change of the plant's own dynamics.
    next_internal: u64,
}

impl Encoders {
    pub(super) fn new(wiring: &Board) -> Self {
        Self {
            wiring: Side::BOTH.map(|side| *wiring.encoder(side)),
            irq: [[None; 2]; 2],
            level: [[false; 2]; 2],
            base: [[false; 2]; 2],
            lazy_b: [false; 2],
            lazy_b_allowed: true,
            lean_edges: true,
            comparator_on: false,
            lean_edge_callbacks: 0,
            lazy_b_reads: 0,
            quiet_b_reads: 0,
            b_reads_evaluated: 0,
            edges_raised: [0; 2],
            last_a_edge: [0; 2],
            next_edge: [NEVER; 2],
            planned: [Vec::new(), Vec::new()],
            input_changed_at: [0; 2],
            input_period: [0; 2],
            next_levels: [None; 2],
            b_quiet_cycles: [0; 2],
            b_quiet_until: [0; 2],
            next_internal: NEVER,
        }
    }

    /// The next planned transition of either wheel.
    pub(super) fn next_edge(&self) -> u64 {
        self.next_edge[0].min(self.next_edge[1])
    }

    /// The plant's next internal change (planning ahead holds up to it).
    pub(super) fn next_internal(&self) -> u64 {
        self.next_internal
    }

    /// Which wheels have a transition due at `when`.
    pub(super) fn due(&self, when: u64) -> [bool; 2] {
        self.next_edge.map(|c| c <= when)
    }

    /// The levels on the wired lines, by recorder line (left A, left B,
    /// right A, right B; a one-channel encoder's B is on no pin).
    pub(super) fn levels_shown(&self) -> Vec<(u8, bool)> {
        let mut v = Vec::with_capacity(4);
        for i in 0..2 {
            for ch in 0..2 {
                if self.irq[i][ch].is_some() {
                    v.push(((2 * i + ch) as u8, self.level[i][ch]));
                }
            }
        }
        v
    }

    /// Bring the plant to every edge (see `Bench::advance_plant_at_every_edge`).
    pub(super) fn keep_plant_at_every_edge(&mut self) {
        self.lean_edges = false;
    }

    /// What the firmware can see change on encoder `i`: A alone while B is
    /// raised lazily or is on no pin (a one-channel encoder), both lines
    /// otherwise.
    fn watch(&self, i: usize) -> Watch {
        if self.lazy_b[i] || self.wiring[i].kind == EncoderKind::OneChannel {
            Watch::A
        } else {
            Watch::Both
        }
    }
}

impl Encoders {
    /// Connect the encoder lines to their pins, at the plant's levels.
    pub(super) fn connect(
        &mut self,
        core: &mut Core,
        irq: [[Option<DrivenPin>; 2]; 2],
        robot: &Robot,
    ) {
        self.irq = irq;
        for side in Side::BOTH {
            let i = side.index();
            let (a, b) = robot.encoder_levels(side);
            let shown = [self.wiring[i].interrupt_line(a, b), b];
            for (irq, level) in self.irq[i].into_iter().zip(shown) {
                if let Some(irq) = irq {
                    core.drive(irq, level);
                }
            }
            self.level[i] = shown;
            self.base[i] = [a, b];
        }
    }

    /// The analog comparator's interrupt or capture was switched (the
    /// caller then updates lazy B).
    pub(super) fn set_comparator(&mut self, on: bool) {
        self.comparator_on = on;
    }

    /// Raise B at its own transitions from now on (see
    /// `Bench::true_waveforms`; the caller then updates lazy B).
    pub(super) fn forbid_lazy_b(&mut self) {
        self.lazy_b_allowed = false;
    }

    /// Edges raised on the pins per side, signed as the wiring's decoder
    /// counts them (A edges; every edge on an xor wiring).
    pub(super) fn edges_raised(&self) -> [i64; 2] {
        self.edges_raised
    }

    /// Cycle at which the last A edge of each encoder was due.
    pub(super) fn last_a_edge(&self) -> [u64; 2] {
        self.last_a_edge
    }

    /// Callbacks that raised planned edges from the plan alone.
    pub(super) fn lean_edge_callbacks(&self) -> u64 {
        self.lean_edge_callbacks
    }

    /// PIN reads that brought a lazy B up to date.
    pub(super) fn lazy_b_reads(&self) -> u64 {
        self.lazy_b_reads
    }

    /// PIN reads of a lazy B answered from the last A edge.
    pub(super) fn quiet_b_reads(&self) -> u64 {
        self.quiet_b_reads
    }

    /// PIN reads of a lazy B that evaluated the plant.
    pub(super) fn b_reads_evaluated(&self) -> u64 {
        self.b_reads_evaluated
    }

    pub(super) fn plan(&mut self, robot: &Robot, clock: Clock, now: u64) {
        // The edges are planned ahead up to the internal change: that first.
        self.plan_internal(robot, clock, now);
        for side in Side::BOTH {
            self.plan_edge(robot, clock, side, now);
        }
    }

    /// When the plant's own dynamics change next (battery sag steps, ...):
    /// both wheels' predictions must be redone then.
    fn plan_internal(&mut self, robot: &Robot, clock: Clock, now: u64) {
        self.next_internal = match robot.next_internal_change() {
            Some(t) => clock.cycle_at_or_after(t).max(now + 1),
            None => NEVER,
        };
    }

    /// The inputs of the `changed` wheels changed at `cycle`: only their
    /// motion changes (the battery follows at its next internal change,
    /// which re-plans both).
    pub(super) fn replan_changed_wheels(
        &mut self,
        robot: &Robot,
        clock: Clock,
        changed: [bool; 2],
        cycle: u64,
    ) {
        self.plan_internal(robot, clock, cycle);
        for side in Side::BOTH {
            let i = side.index();
            if changed[i] {
                if self.input_changed_at[i] != 0 {
                    self.input_period[i] = cycle - self.input_changed_at[i];
                }
                self.input_changed_at[i] = cycle;
                self.plan_edge(robot, clock, side, cycle);
            }
        }
    }

    /// Plan `side`'s next transitions from `now` under the present inputs:
    /// the next one and up to [`EDGES_PLANNED`] after it, with the
    /// plant's levels at each, so that the callbacks of the planned edges
    /// need nothing of the plant (`raise_planned_edges`).
    fn plan_edge(&mut self, robot: &Robot, clock: Clock, side: Side, now: u64) {
        let i = side.index();
        let watch = self.watch(i);
        let grid = clock.grid();
        self.next_edge[i] = match robot.next_encoder_transition_on(side, watch, grid) {
            Some(cycle) => cycle.max(now + 1),
            None => NEVER,
        };
        self.next_levels[i] = self.planned_levels(robot, clock, side, self.next_edge[i]);
        // The motion changed: a quiet window from before no longer holds.
        self.b_quiet_until[i] = 0;
        let quiet = robot.encoder_travel_time_bound(side, 0.5).0 * clock.hz() as f64;
        self.b_quiet_cycles[i] = if quiet.is_finite() {
            quiet.max(0.0) as u64
        } else {
            NEVER
        };
        self.planned[i].clear();
        // Planned to the inputs' expected change (and the first edge after
        // it, in case the change is late): what is planned beyond a change
        // is wasted, and a plan that runs out early costs a refill.
        let period = self.input_period[i];
        let (most, horizon) = if period != 0 && now == self.input_changed_at[i] {
            (EDGES_PLANNED_TO_CHANGE, now.saturating_add(period))
        } else {
            (EDGES_PLANNED, NEVER)
        };
        self.fill_plan(robot, clock, side, watch, self.next_edge[i], most, horizon);
    }

    /// Plan up to `most` transitions of `side` after the one at `after` into
    /// its empty plan, stopping at the first at or after `horizon`.
    #[allow(clippy::too_many_arguments)]
    fn fill_plan(
        &mut self,
        robot: &Robot,
        clock: Clock,
        side: Side,
        watch: Watch,
        mut after: u64,
        most: usize,
        horizon: u64,
    ) {
        let i = side.index();
        let grid = clock.grid();
        let mut planned = std::mem::take(&mut self.planned[i]);
        debug_assert!(planned.is_empty(), "a plan is filled when it ran out");
        // Planning ahead holds up to the plant's next internal change only.
        while planned.len() < most && after < horizon && after < self.next_internal {
            match robot.next_encoder_transition_on_after(side, watch, grid, after) {
                Some(cycle) => {
                    planned.push(PlannedEdge {
                        cycle,
                        levels: self.planned_levels(robot, clock, side, cycle),
                    });
                    after = cycle;
                }
                None => break,
            }
        }
        planned.reverse();
        self.planned[i] = planned;
    }

    /// The plant's levels of `side` at a planned transition, if the plan
    /// knows them: before the plant's next internal change, under the
    /// present inputs (the search just evaluated that instant, so this is
    /// cheap).
    fn planned_levels(
        &self,
        robot: &Robot,
        clock: Clock,
        side: Side,
        cycle: u64,
    ) -> Option<(bool, bool)> {
        (cycle < self.next_internal && !robot.encoder(side).is_flawed())
            .then(|| robot.encoder_levels_at(side, clock.seconds(cycle)))
    }

    /// `side`'s plan ran out at its edge at `now`: planned on from that
    /// edge, without the plant, which need not be there (the plan's edges
    /// are the ones a plan made there would hold: the inputs are the same).
    /// False when it cannot be, or no edge is left to plan: the plant must
    /// come to `now` and plan from there.
    fn refill_plan(&mut self, robot: &Robot, clock: Clock, side: Side, now: u64) -> bool {
        let i = side.index();
        if !self.planned[i].is_empty() {
            return true;
        }
        if self.next_edge[i] != now || self.next_levels[i].is_none() {
            return false;
        }
        let watch = self.watch(i);
        self.fill_plan(robot, clock, side, watch, now, EDGES_PLANNED, NEVER);
        !self.planned[i].is_empty()
    }

    /// `side`'s planned edge came: the next planned one, or a new plan.
    fn next_planned_edge(&mut self, robot: &Robot, clock: Clock, side: Side, now: u64) {
        let i = side.index();
        match self.planned[i].pop() {
            Some(edge) => {
                self.next_edge[i] = edge.cycle;
                self.next_levels[i] = edge.levels;
            }
            None => self.plan_edge(robot, clock, side, now),
        }
    }

    /// After the event at `when` (the plant brought there): each wheel
    /// whose edge came goes on to its next. `edge_due` says which wheels'
    /// edges were due when the event began.
    pub(super) fn advance_plans(
        &mut self,
        robot: &Robot,
        clock: Clock,
        when: u64,
        edge_due: [bool; 2],
    ) {
        // The other wheel's prediction stays valid: its input has not changed
        // (a change re-plans both in `refresh_bridge`).
        for side in Side::BOTH {
            let i = side.index();
            if self.next_edge[i] <= when {
                self.next_planned_edge(robot, clock, side, when);
            }
            // As in `raise_planned_edges`: B is quiet for a while after an A
            // edge, under the motion as it is now (any change since re-planned).
            if edge_due[i] && self.lean_edges && self.lazy_b[i] && !robot.encoder(side).is_flawed()
            {
                self.b_quiet_until[i] = when.saturating_add(self.b_quiet_cycles[i]);
            }
        }
    }

    /// Per side, whether channel B may be raised lazily: only when the
    /// pin it is wired to can start nothing in the MCU by itself (no external
    /// or pin-change interrupt, input capture or counter input; on AIN1 only
    /// while the comparator's interrupt and capture are off), no encoder fault
    /// is active on that side, and the true waveform is not wanted. Then the
    /// firmware can see B only by reading its PIN register, and the bench
    /// brings B up to date right before every such read: what the firmware
    /// reads is exactly what it would read with every B edge raised, at half
    /// the events. None when that is what it is already; then the caller
    /// brings the lines up to date, sets the new choice
    /// ([`Encoders::set_lazy_b`]) and re-plans both wheels.
    pub(super) fn lazy_b_change(&self, inject: &Injection) -> Option<[bool; 2]> {
        let mut lazy = [false; 2];
        for side in Side::BOTH {
            let i = side.index();
            // A one-channel encoder's B is on no pin: never raised at all.
            let Some(b) = self.wiring[i].b else {
                continue;
            };
            // On an xor wiring every B edge changes the interrupt pin.
            lazy[i] = self.lazy_b_allowed
                && self.wiring[i].kind == EncoderKind::Quadrature
                && inject.encoder[i] == EncoderFault::Healthy
                && !b.can_interrupt()
                && !(b.is_comparator_input() && self.comparator_on);
        }
        (lazy != self.lazy_b).then_some(lazy)
    }

    pub(super) fn set_lazy_b(&mut self, lazy: [bool; 2]) {
        self.lazy_b = lazy;
    }

    /// Show the plant's levels on both encoders' pins.
    pub(super) fn raise_all(
        &mut self,
        core: &mut Core,
        robot: &Robot,
        inject: &mut Injection,
        recorder: &mut Recorder,
        when: u64,
    ) {
        for side in Side::BOTH {
            let plant = robot.encoder_levels(side);
            self.raise_side(core, inject, recorder, when, side.index(), plant);
        }
    }

    /// Show the plant's levels `plant` of encoder `i` on its pins, through
    /// the encoder faults and glitches.
    #[inline]
    fn raise_side(
        &mut self,
        core: &mut Core,
        inject: &mut Injection,
        recorder: &mut Recorder,
        when: u64,
        i: usize,
        plant: (bool, bool),
    ) {
        let [base_a, base_b] = self.base[i];
        let (base_a, base_b) = inject.encoder_levels(i, plant, (base_a, base_b));
        self.base[i] = [base_a, base_b];
        // A glitch pulse inverts what the pin shows while it lasts.
        let [ga, gb] = inject.glitch[i];
        let wiring = self.wiring[i];
        let (a, b) = (wiring.interrupt_line(base_a, base_b) ^ ga, base_b ^ gb);
        let [old_a, old_b] = self.level[i];
        let [Some(irq_a), irq_b] = self.irq[i] else {
            return;
        };
        if b != old_b {
            // A one-channel encoder's B is kept (it signs the plant's A
            // edges below) but shown on no pin.
            if let Some(irq_b) = irq_b {
                core.drive(irq_b, b);
                recorder.pin(when, 2 * i as u8 + 1, b);
            }
            self.level[i][1] = b;
        }
        if a != old_a {
            core.drive(irq_a, a);
            recorder.pin(when, 2 * i as u8, a);
            self.level[i][0] = a;
            self.last_a_edge[i] = when;
        }
        self.edges_raised[i] += match wiring.kind {
            // One channel: signed as the plant moves, which the firmware
            // can only take from its own motor command.
            EncoderKind::Quadrature | EncoderKind::OneChannel if a != old_a => decode_a_edge(a, b),
            EncoderKind::Quadrature | EncoderKind::OneChannel => 0,
            // The channels the pins show: A is the xor line's level ^ B.
            EncoderKind::Xor => decode_step((old_a ^ old_b, old_b), (a ^ b, b)),
        };
    }

    /// The callback of planned encoder edges with nothing else due at
    /// `when` (the caller checked that nothing else is): the plan knows the
    /// levels, so the plant is left where it is (it catches up at the next
    /// event that needs it). False, having done nothing, when that is not
    /// the case.
    #[inline]
    #[allow(clippy::too_many_arguments)]
    pub(super) fn raise_planned_edges(
        &mut self,
        core: &mut Core,
        robot: &Robot,
        clock: Clock,
        inject: &mut Injection,
        recorder: &mut Recorder,
        when: u64,
    ) -> bool {
        if !self.lean_edges {
            return false;
        }
        let due = self.due(when);
        if due == [false; 2] {
            return false;
        }
        for (i, due) in due.into_iter().enumerate() {
            let plain = self.next_levels[i].is_some()
                && inject.encoder[i] == EncoderFault::Healthy
                && inject.glitch[i] == [false; 2];
            if due && !(plain && self.refill_plan(robot, clock, Side::BOTH[i], when)) {
                return false;
            }
        }
        for side in Side::BOTH {
            let i = side.index();
            if let (true, Some(levels)) = (due[i], self.next_levels[i]) {
                self.raise_side(core, inject, recorder, when, i, levels);
                if self.lazy_b[i] {
                    // Watching A alone, this was an A edge: B changes half a
                    // state away at the least.
                    self.b_quiet_until[i] = when.saturating_add(self.b_quiet_cycles[i]);
                }
                self.next_planned_edge(robot, clock, side, when);
            }
        }
        self.lean_edge_callbacks += 1;
        true
    }

    /// The firmware is about to read the PIN register at `addr`: a lazily
    /// raised B on it is brought to its level at this cycle (see
    /// `lazy_b_change`). The plant is not advanced: its closed form holds
    /// until its next event, which has not come yet.
    #[inline]
    pub(super) fn before_pin_read(
        &mut self,
        core: &mut Core,
        robot: &Robot,
        clock: Clock,
        inject: &mut Injection,
        recorder: &mut Recorder,
        addr: u16,
    ) {
        let cycle = core.cycle();
        for side in Side::BOTH {
            let i = side.index();
            if !self.lazy_b[i] || self.wiring[i].b.map(|b| b.pin_register()) != Some(addr) {
                continue;
            }
            // Shortly after a planned A edge the plant's B is the one raised
            // with it (when nothing but the plant drives the line).
            if cycle < self.b_quiet_until[i]
                && inject.encoder[i] == EncoderFault::Healthy
                && inject.glitch[i] == [false; 2]
            {
                self.quiet_b_reads += 1;
                continue;
            }
            self.b_reads_evaluated += 1;
            let t = Seconds(clock.seconds(cycle).0.max(robot.now().0));
            // As `raise_all` computes it: the faults on the plant's
            // levels, then a glitch pulse's inversion.
            let (_, base_b) = inject.encoder_levels(
                i,
                robot.encoder_levels_at(side, t),
                (self.base[i][0], self.base[i][1]),
            );
            self.base[i][1] = base_b;
            let b = base_b ^ inject.glitch[i][1];
            let old_b = self.level[i][1];
            if b != old_b {
                if let Some(irq_b) = self.irq[i][1] {
                    core.drive(irq_b, b);
                }
                self.level[i][1] = b;
                self.lazy_b_reads += 1;
                recorder.pin(cycle, 2 * i as u8 + 1, b);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::board::{Mcu, Pin, HENRYTWO};

    /// B is raised lazily only where its pin cannot interrupt: Henrytwo's
    /// D4 and D5; a board with B on INT0 and INT1 (D21, D20) gets B's edges
    /// at their own cycles, and one with a single such B on that side only.
    #[test]
    fn lazy_b_follows_the_boards_pins() {
        let inject = Injection::new(0);
        let henrytwo = Encoders::new(&HENRYTWO);
        assert_eq!(henrytwo.lazy_b_change(&inject), Some([true, true]));
        let mut board = HENRYTWO;
        board.left_encoder.b = Pin::arduino(Mcu::Atmega2560, 21);
        board.right_encoder.b = Pin::arduino(Mcu::Atmega2560, 20);
        let eager = Encoders::new(&board);
        assert_eq!(eager.lazy_b_change(&inject), None, "both stay eager");
        assert_eq!(eager.watch(0), Watch::Both);
        board.left_encoder.b = HENRYTWO.left_encoder.b;
        let one = Encoders::new(&board);
        assert_eq!(one.lazy_b_change(&inject), Some([true, false]));
    }

    /// On an xor wiring every B edge changes the interrupt pin: B is never
    /// raised lazily, and the plant is watched on both channels.
    #[test]
    fn an_xor_wiring_raises_b_at_its_own_edges() {
        let inject = Injection::new(0);
        let mut board = HENRYTWO;
        board.left_encoder.kind = crate::board::EncoderKind::Xor;
        let e = Encoders::new(&board);
        assert_eq!(e.lazy_b_change(&inject), Some([false, true]));
    }

    /// A four-edge decoder over the plant's quadrature cycle: each step up
    /// (A leading B) counts +1, each step down -1, a jump of both lines 0.
    #[test]
    fn decode_step_counts_every_edge_of_the_cycle() {
        let levels = |q: i64| plant_model::encoder::levels(q);
        for q in -8..8 {
            assert_eq!(decode_step(levels(q), levels(q + 1)), 1, "up from {q}");
            assert_eq!(decode_step(levels(q + 1), levels(q)), -1, "down to {q}");
            assert_eq!(decode_step(levels(q), levels(q + 2)), 0, "jump from {q}");
            assert_eq!(decode_step(levels(q), levels(q)), 0);
        }
    }
}
