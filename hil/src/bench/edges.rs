//! Where an encoder edge is born: the plant says when each wheel's next
//! transitions happen (solved from the motor's analytic response), the bench
//! plans them several at a time with the plant's levels at each, puts the
//! next one on the event queue, and raises it on the MCU pins at its cycle,
//! through the encoder faults and glitches of `crate::inject`.
//!
//! Two economies, both exact for what the firmware can see:
//! - A planned edge with nothing else due is raised from the plan alone;
//!   the plant is left where it is and catches up at the next event that
//!   needs it ([`BenchCore::raise_planned_edges`]).
//! - Channel B on a pin that can interrupt nothing is raised lazily: only
//!   when the firmware reads its PIN register, or with an A edge
//!   ([`BenchCore::update_lazy_b`]); shortly after a planned A edge such a
//!   read is answered from the plan (B cannot have changed yet).

use plant_model::encoder::Watch;
use plant_model::{Seconds, Side};

use super::core::{BenchCore, NEVER};
use crate::inject::EncoderFault;
use crate::sim::{Core, Irq};
use crate::wiring::{EncoderWiring, Wiring};

/// Transitions planned per wheel beyond the next when nothing tells how
/// long the inputs will last (see `BenchCore::plan_edge`).
const EDGES_PLANNED: usize = 8;

/// At most this many transitions planned beyond the next up to the time
/// the inputs are expected to change (see `BenchCore::plan_edge`).
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

/// Both encoders' pins and their plans, indexed by side (`Side::index`),
/// then channel (A, B).
pub(super) struct Encoders {
    wiring: [EncoderWiring; 2],
    irq: [[Option<Irq>; 2]; 2],
    /// The levels on the pins.
    level: [[bool; 2]; 2],
    /// Encoder levels after the encoder faults, before glitches.
    base: [[bool; 2]; 2],
    /// Per side: channel B is raised only when the firmware reads its PIN
    /// register (or with an A edge), not at its own transitions. Exact while
    /// nothing but a read can see B (see `update_lazy_b`).
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
    /// A edges raised on the pins, signed as the thesis' decoder counts them.
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
    pub(super) fn new(wiring: &Wiring) -> Self {
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

    /// The levels shown on the pins, by side and channel.
    pub(super) fn levels_shown(&self) -> [[bool; 2]; 2] {
        self.level
    }

    /// Bring the plant to every edge (see `Bench::advance_plant_at_every_edge`).
    pub(super) fn keep_plant_at_every_edge(&mut self) {
        self.lean_edges = false;
    }

    /// What the firmware can see change on encoder `i`: A alone while B is
    /// raised lazily, both lines otherwise.
    fn watch(&self, i: usize) -> Watch {
        if self.lazy_b[i] {
            Watch::A
        } else {
            Watch::Both
        }
    }
}

impl BenchCore {
    /// Connect the encoder lines to their pins, at the plant's levels.
    pub(super) fn connect_encoders(&mut self, core: &mut Core, irq: [[Irq; 2]; 2]) {
        self.edges.irq = irq.map(|side| side.map(Some));
        for side in Side::BOTH {
            let i = side.index();
            let (a, b) = self.robot.encoder_levels(side);
            for (irq, level) in self.edges.irq[i].into_iter().zip([a, b]) {
                if let Some(irq) = irq {
                    core.raise(irq, level as u32);
                }
            }
            self.edges.level[i] = [a, b];
            self.edges.base[i] = [a, b];
        }
    }

    /// The analog comparator's interrupt or capture was switched.
    pub(super) fn set_comparator(&mut self, core: &mut Core, on: bool) {
        self.edges.comparator_on = on;
        let cycle = core.cycle();
        self.update_lazy_b(core, cycle);
    }

    /// Raise B at its own transitions from now on (see `Bench::true_waveforms`).
    pub(super) fn true_waveforms(&mut self, core: &mut Core) {
        self.edges.lazy_b_allowed = false;
        let cycle = core.cycle();
        self.update_lazy_b(core, cycle);
    }

    /// A edges raised on the pins per side, signed as the thesis' decoder
    /// counts them.
    pub fn edges_raised(&self) -> [i64; 2] {
        self.edges.edges_raised
    }

    /// Cycle at which the last A edge of each encoder was due.
    pub fn last_a_edge(&self) -> [u64; 2] {
        self.edges.last_a_edge
    }

    /// Callbacks that raised planned edges from the plan alone.
    pub fn lean_edge_callbacks(&self) -> u64 {
        self.edges.lean_edge_callbacks
    }

    /// PIN reads that brought a lazy B up to date.
    pub fn lazy_b_reads(&self) -> u64 {
        self.edges.lazy_b_reads
    }

    /// PIN reads of a lazy B answered from the last A edge.
    pub fn quiet_b_reads(&self) -> u64 {
        self.edges.quiet_b_reads
    }

    /// PIN reads of a lazy B that evaluated the plant.
    pub fn b_reads_evaluated(&self) -> u64 {
        self.edges.b_reads_evaluated
    }

    pub(super) fn plan_edges(&mut self, now: u64) {
        // The edges are planned ahead up to the internal change: that first.
        self.plan_internal(now);
        for side in Side::BOTH {
            self.plan_edge(side, now);
        }
    }

    /// When the plant's own dynamics change next (battery sag steps, ...):
    /// both wheels' predictions must be redone then.
    fn plan_internal(&mut self, now: u64) {
        self.edges.next_internal = match self.robot.next_internal_change() {
            Some(t) => self.clock.cycle_at_or_after(t).max(now + 1),
            None => NEVER,
        };
    }

    /// The inputs of the `changed` wheels changed at `cycle`: only their
    /// motion changes (the battery follows at its next internal change,
    /// which re-plans both).
    pub(super) fn replan_changed_wheels(&mut self, changed: [bool; 2], cycle: u64) {
        self.plan_internal(cycle);
        for side in Side::BOTH {
            let i = side.index();
            if changed[i] {
                let e = &mut self.edges;
                if e.input_changed_at[i] != 0 {
                    e.input_period[i] = cycle - e.input_changed_at[i];
                }
                e.input_changed_at[i] = cycle;
                self.plan_edge(side, cycle);
            }
        }
    }

    /// Plan `side`'s next transitions from `now` under the present inputs:
    /// the next one and up to [`EDGES_PLANNED`] after it, with the
    /// plant's levels at each, so that the callbacks of the planned edges
    /// need nothing of the plant (`raise_planned_edges`).
    fn plan_edge(&mut self, side: Side, now: u64) {
        let i = side.index();
        let watch = self.edges.watch(i);
        let grid = self.clock.grid();
        self.edges.next_edge[i] = match self.robot.next_encoder_transition_on(side, watch, grid) {
            Some(cycle) => cycle.max(now + 1),
            None => NEVER,
        };
        self.edges.next_levels[i] = self.planned_levels(side, self.edges.next_edge[i]);
        // The motion changed: a quiet window from before no longer holds.
        self.edges.b_quiet_until[i] = 0;
        let quiet = self.robot.encoder_travel_time_bound(side, 0.5).0 * self.clock.hz() as f64;
        self.edges.b_quiet_cycles[i] = if quiet.is_finite() {
            quiet.max(0.0) as u64
        } else {
            NEVER
        };
        self.edges.planned[i].clear();
        // Planned to the inputs' expected change (and the first edge after
        // it, in case the change is late): what is planned beyond a change
        // is wasted, and a plan that runs out early costs a refill.
        let period = self.edges.input_period[i];
        let (most, horizon) = if period != 0 && now == self.edges.input_changed_at[i] {
            (EDGES_PLANNED_TO_CHANGE, now.saturating_add(period))
        } else {
            (EDGES_PLANNED, NEVER)
        };
        self.fill_plan(side, watch, self.edges.next_edge[i], most, horizon);
    }

    /// Plan up to `most` transitions of `side` after the one at `after` into
    /// its empty plan, stopping at the first at or after `horizon`.
    fn fill_plan(&mut self, side: Side, watch: Watch, mut after: u64, most: usize, horizon: u64) {
        let i = side.index();
        let grid = self.clock.grid();
        let mut planned = std::mem::take(&mut self.edges.planned[i]);
        debug_assert!(planned.is_empty(), "a plan is filled when it ran out");
        // Planning ahead holds up to the plant's next internal change only.
        while planned.len() < most && after < horizon && after < self.edges.next_internal {
            match self
                .robot
                .next_encoder_transition_on_after(side, watch, grid, after)
            {
                Some(cycle) => {
                    planned.push(PlannedEdge {
                        cycle,
                        levels: self.planned_levels(side, cycle),
                    });
                    after = cycle;
                }
                None => break,
            }
        }
        planned.reverse();
        self.edges.planned[i] = planned;
    }

    /// The plant's levels of `side` at a planned transition, if the plan
    /// knows them: before the plant's next internal change, under the
    /// present inputs (the search just evaluated that instant, so this is
    /// cheap).
    fn planned_levels(&self, side: Side, cycle: u64) -> Option<(bool, bool)> {
        (cycle < self.edges.next_internal && !self.robot.encoder(side).is_flawed()).then(|| {
            self.robot
                .encoder_levels_at(side, self.clock.seconds(cycle))
        })
    }

    /// `side`'s plan ran out at its edge at `now`: planned on from that
    /// edge, without the plant, which need not be there (the plan's edges
    /// are the ones a plan made there would hold: the inputs are the same).
    /// False when it cannot be, or no edge is left to plan: the plant must
    /// come to `now` and plan from there.
    fn refill_plan(&mut self, side: Side, now: u64) -> bool {
        let i = side.index();
        if !self.edges.planned[i].is_empty() {
            return true;
        }
        if self.edges.next_edge[i] != now || self.edges.next_levels[i].is_none() {
            return false;
        }
        let watch = self.edges.watch(i);
        self.fill_plan(side, watch, now, EDGES_PLANNED, NEVER);
        !self.edges.planned[i].is_empty()
    }

    /// `side`'s planned edge came: the next planned one, or a new plan.
    fn next_planned_edge(&mut self, side: Side, now: u64) {
        let i = side.index();
        match self.edges.planned[i].pop() {
            Some(edge) => {
                self.edges.next_edge[i] = edge.cycle;
                self.edges.next_levels[i] = edge.levels;
            }
            None => self.plan_edge(side, now),
        }
    }

    /// After the event at `when` (the plant brought there): each wheel
    /// whose edge came goes on to its next. `edge_due` says which wheels'
    /// edges were due when the event began.
    pub(super) fn advance_plans(&mut self, when: u64, edge_due: [bool; 2]) {
        // The other wheel's prediction stays valid: its input has not changed
        // (a change re-plans both in `refresh_bridge`).
        for side in Side::BOTH {
            let i = side.index();
            if self.edges.next_edge[i] <= when {
                self.next_planned_edge(side, when);
            }
            // As in `raise_planned_edges`: B is quiet for a while after an A
            // edge, under the motion as it is now (any change since re-planned).
            if edge_due[i]
                && self.edges.lean_edges
                && self.edges.lazy_b[i]
                && !self.robot.encoder(side).is_flawed()
            {
                self.edges.b_quiet_until[i] = when.saturating_add(self.edges.b_quiet_cycles[i]);
            }
        }
    }

    /// Decide per side whether channel B may be raised lazily: only when the
    /// pin it is wired to can start nothing in the MCU by itself (no external
    /// or pin-change interrupt, input capture or counter input; on AIN1 only
    /// while the comparator's interrupt and capture are off), no encoder fault
    /// is active on that side, and the true waveform is not wanted. Then the
    /// firmware can see B only by reading its PIN register, and the bench
    /// brings B up to date right before every such read: what the firmware
    /// reads is exactly what it would read with every B edge raised, at half
    /// the events. On a change the lines are brought up to date and both
    /// wheels re-planned.
    pub(super) fn update_lazy_b(&mut self, core: &mut Core, cycle: u64) {
        let mut lazy = [false; 2];
        for side in Side::BOTH {
            let i = side.index();
            let b = self.edges.wiring[i].b;
            lazy[i] = self.edges.lazy_b_allowed
                && self.inject.encoder[i] == EncoderFault::Healthy
                && !b.can_interrupt()
                && !(b.is_comparator_input() && self.edges.comparator_on);
        }
        if lazy != self.edges.lazy_b {
            self.advance_plant(cycle);
            self.raise_encoders(core, cycle);
            self.edges.lazy_b = lazy;
            self.plan_edges(cycle);
        }
    }

    /// Show the plant's levels on both encoders' pins.
    pub(super) fn raise_encoders(&mut self, core: &mut Core, when: u64) {
        for side in Side::BOTH {
            let plant = self.robot.encoder_levels(side);
            self.raise_side(core, when, side.index(), plant);
        }
    }

    /// Show the plant's levels `plant` of encoder `i` on its pins, through
    /// the encoder faults and glitches.
    fn raise_side(&mut self, core: &mut Core, when: u64, i: usize, plant: (bool, bool)) {
        let e = &mut self.edges;
        let [base_a, base_b] = e.base[i];
        let (base_a, base_b) = self.inject.encoder_levels(i, plant, (base_a, base_b));
        e.base[i] = [base_a, base_b];
        // A glitch pulse inverts what the pin shows while it lasts.
        let [ga, gb] = self.inject.glitch[i];
        let (a, b) = (base_a ^ ga, base_b ^ gb);
        let [old_a, old_b] = e.level[i];
        let [Some(irq_a), Some(irq_b)] = e.irq[i] else {
            return;
        };
        if b != old_b {
            core.raise(irq_b, b as u32);
            e.level[i][1] = b;
            self.recorder.pin(when, 2 * i as u8 + 1, b);
        }
        if a != old_a {
            core.raise(irq_a, a as u32);
            self.recorder.pin(when, 2 * i as u8, a);
            e.level[i][0] = a;
            e.edges_raised[i] += decode_a_edge(a, b);
            e.last_a_edge[i] = when;
        }
    }

    /// The callback of planned encoder edges with nothing else due at
    /// `when`: the plan knows the levels, so the plant is left where it is
    /// (it catches up at the next event that needs it). False, having done
    /// nothing, when that is not the case.
    pub(super) fn raise_planned_edges(&mut self, core: &mut Core, when: u64) -> bool {
        let others = self.next_other_event();
        if !self.edges.lean_edges || others <= when || self.power.releasing() {
            return false;
        }
        let due = self.edges.due(when);
        if due == [false; 2] {
            return false;
        }
        for (i, due) in due.into_iter().enumerate() {
            let plain = self.edges.next_levels[i].is_some()
                && self.inject.encoder[i] == EncoderFault::Healthy
                && self.inject.glitch[i] == [false; 2];
            if due && !(plain && self.refill_plan(Side::BOTH[i], when)) {
                return false;
            }
        }
        for side in Side::BOTH {
            let i = side.index();
            if let (true, Some(levels)) = (due[i], self.edges.next_levels[i]) {
                self.raise_side(core, when, i, levels);
                if self.edges.lazy_b[i] {
                    // Watching A alone, this was an A edge: B changes half a
                    // state away at the least.
                    self.edges.b_quiet_until[i] = when.saturating_add(self.edges.b_quiet_cycles[i]);
                }
                self.next_planned_edge(side, when);
            }
        }
        self.edges.lean_edge_callbacks += 1;
        true
    }

    /// The firmware is about to read the PIN register at `addr`: a lazily
    /// raised B on it is brought to its level at this cycle (see
    /// `update_lazy_b`). The plant is not advanced: its closed form holds
    /// until its next event, which has not come yet.
    pub(super) fn before_pin_read(&mut self, core: &mut Core, addr: u16) {
        let cycle = core.cycle();
        for side in Side::BOTH {
            let i = side.index();
            let e = &mut self.edges;
            if !e.lazy_b[i] || e.wiring[i].b.pin_register() != addr {
                continue;
            }
            // Shortly after a planned A edge the plant's B is the one raised
            // with it (when nothing but the plant drives the line).
            if cycle < e.b_quiet_until[i]
                && self.inject.encoder[i] == EncoderFault::Healthy
                && self.inject.glitch[i] == [false; 2]
            {
                e.quiet_b_reads += 1;
                continue;
            }
            e.b_reads_evaluated += 1;
            let t = Seconds(self.clock.seconds(cycle).0.max(self.robot.now().0));
            // As `raise_encoders` computes it: the faults on the plant's
            // levels, then a glitch pulse's inversion.
            let (_, base_b) = self.inject.encoder_levels(
                i,
                self.robot.encoder_levels_at(side, t),
                (e.base[i][0], e.base[i][1]),
            );
            e.base[i][1] = base_b;
            let b = base_b ^ self.inject.glitch[i][1];
            let old_b = e.level[i][1];
            if b != old_b {
                if let Some(irq_b) = e.irq[i][1] {
                    core.raise(irq_b, b as u32);
                }
                e.level[i][1] = b;
                e.lazy_b_reads += 1;
                self.recorder.pin(cycle, 2 * i as u8 + 1, b);
            }
        }
    }
}
