//! The interrupt response against the datasheets ("Interrupt Response
//! Time"): on the ATmega2560 (§7.8.1, a device with a 22-bit PC) five
//! cycles from the request to the vector, which holds a `jmp` of three;
//! five more when the interrupt wakes the CPU from idle sleep (whose
//! start-up time is none); five for `reti`. On the ATmega328P (§6.7.1), a
//! 2-byte PC: four, four and four. simavr alone enters the vector at once,
//! and wakes one cycle late (`hil/src/mcu/sim/response.rs` adds what is
//! missing).
//!
//! Each case runs a hand-assembled program on a bare simavr of each MCU:
//! INT0 enabled on any change of its pin (PD0 on the 2560, PD2 on the
//! 328P), which the test toggles from a cycle timer at known cycles; the
//! INT0 vector jumps to an ISR whose first
//! instruction writes GPIOR0 and whose second is `reti`; the code it
//! returns to writes GPIOR1 with its first instruction. The handler
//! timestamps every write (an IO callback sees the cycle its instruction
//! starts at) and every toggle.

#[path = "support/avr_asm.rs"]
mod avr_asm;

use avr_asm::{jmp, ldi, sts};
use hil::mcu::chip::{Chip, Mcu};
use hil::mcu::sim::{Avr, Core, Handler, IoClaim, Irq};

const F_CPU: u32 = 16_000_000;
/// Data-space addresses, the same on both MCUs.
const GPIOR0: u16 = 0x3E;
const GPIOR1: u16 = 0x4A;
const EIMSK: u16 = 0x3D;
const EICRA: u16 = 0x69;
const SMCR: u16 = 0x53;

/// The `jmp` at the vector: three cycles (AVR instruction set).
const JMP_CYCLES: u64 = 3;
/// The MCUs, with the datasheet's response, wake-up and `reti` cycles
/// (`reti` simavr counts itself).
const MCUS: [(Mcu, u64, u64, u64); 2] = [(Mcu::Atmega2560, 5, 5, 5), (Mcu::Atmega328p, 4, 4, 4)];

/// What the program did, cycle by cycle.
#[derive(Default)]
struct Log {
    pin: Option<Irq>,
    /// The cycles to toggle PD0 at, in order; the next is `edges[raised.len()]`.
    edges: Vec<u64>,
    /// The cycles the toggles happened at.
    raised: Vec<u64>,
    /// (data address, cycle) of each write to GPIOR0 and GPIOR1.
    writes: Vec<(u16, u64)>,
}

impl Handler for Log {
    fn io_write(&mut self, core: &mut Core, addr: u16, _value: u8) {
        self.writes.push((addr, core.cycle()));
    }
    fn io_read(&mut self, _core: &mut Core, _addr: u16) -> u8 {
        0
    }
    fn timer(&mut self, core: &mut Core, _when: u64) -> u64 {
        let level = self.raised.len() as u32 % 2 == 0;
        self.raised.push(core.cycle());
        core.raise(self.pin.expect("the pin"), u32::from(level));
        self.edges.get(self.raised.len()).copied().unwrap_or(0)
    }
    fn irq(&mut self, _core: &mut Core, _tag: u32, _value: u32) {}
}

/// `rjmp` at word `from` to word `to`.
fn rjmp(from: usize, to: usize) -> u16 {
    0xC000 | ((to as i32 - from as i32 - 1) as u16 & 0x0FFF)
}

const SEI: u16 = 0x9478;
const SLEEP: u16 = 0x9588;
const RETI: u16 = 0x9518;
/// `out GPIOR0, r17` and `out GPIOR1, r17`: one cycle each.
const OUT_GPIOR0_R17: u16 = 0xBB1E;
const OUT_GPIOR1_R17: u16 = 0xBD1A;

const MAIN: usize = 0x80;
const ISR: usize = 0x400;
/// The awake program's loop: this many one-cycle `out GPIOR1`, then an
/// `rjmp` back.
const LOOP_WRITES: usize = 500;

/// The program: INT0 on any change of PD0, then with interrupts on either
/// idle sleep in a loop (`sleep; out GPIOR1; rjmp` back), or (awake) the
/// loop of `out GPIOR1` (every cycle an instruction boundary, and every
/// instruction one the ISR's return is seen at).
fn program(chip: &Chip, asleep: bool) -> Vec<u8> {
    let mut words = vec![0u16; ISR + 2];
    words[0..2].copy_from_slice(&jmp(MAIN as u16));
    for v in 1..chip.vectors.len() {
        words[2 * v..2 * v + 2].copy_from_slice(&jmp(ISR as u16));
    }
    let mut main = Vec::new();
    for (addr, value) in [(EICRA, 0b01), (EIMSK, 1), (SMCR, 1)] {
        main.push(ldi(16, value));
        main.extend(sts(addr, 16));
    }
    main.extend([ldi(17, 1), SEI]);
    let top = MAIN + main.len();
    if asleep {
        main.extend([SLEEP, OUT_GPIOR1_R17, rjmp(top + 2, top)]);
    } else {
        main.extend([OUT_GPIOR1_R17; LOOP_WRITES]);
        main.push(rjmp(top + LOOP_WRITES, top));
    }
    assert!(MAIN + main.len() < ISR);
    words[MAIN..MAIN + main.len()].copy_from_slice(&main);
    words[ISR] = OUT_GPIOR0_R17;
    words[ISR + 1] = RETI;
    words.iter().flat_map(|w| w.to_le_bytes()).collect()
}

/// One serviced edge: when PD0 changed, when the ISR's first instruction
/// and the first instruction after its `reti` began.
#[derive(Debug)]
struct Serviced {
    edge: u64,
    isr: u64,
    back: u64,
}

/// Run the program, toggling PD0 at `edges`; what the log shows of each.
fn run(mcu: Mcu, asleep: bool, edges: &[u64]) -> (Vec<u64>, Vec<Serviced>) {
    let chip = mcu.chip();
    let mut avr = Avr::new(chip.simavr_core, F_CPU, Log::default()).unwrap();
    avr.load_flash(0, &program(chip, asleep)).unwrap();
    avr.claim_io_write(GPIOR0, IoClaim::Observe).unwrap();
    avr.claim_io_write(GPIOR1, IoClaim::Observe).unwrap();
    let (port, bit) = chip.ext_int.iter().find(|e| e.n == 0).unwrap().pin;
    let pin = avr.port_pin(port, bit).unwrap();
    let log = avr.handler_mut();
    log.pin = Some(pin);
    log.edges = edges.to_vec();
    avr.schedule(edges[0]);
    avr.run_to(edges.last().unwrap() + 2_000);
    let log = avr.handler();
    assert_eq!(log.raised.len(), edges.len(), "every edge raised");
    let serviced = log
        .raised
        .iter()
        .map(|&edge| {
            let after = |addr: u16, from: u64| {
                log.writes
                    .iter()
                    .find(|&&(a, c)| a == addr && c >= from)
                    .map(|&(_, c)| c)
                    .expect("a write after the edge")
            };
            let isr = after(GPIOR0, edge);
            Serviced {
                edge,
                isr,
                back: after(GPIOR1, isr),
            }
        })
        .collect();
    (log.raised.clone(), serviced)
}

/// Edges well apart (each ISR done long before the next), at assorted
/// places of the awake loop; none falls during its `rjmp` (the tests
/// check that each toggle came at its own cycle).
const EDGES: [u64; 6] = [1_000, 1_200, 2_345, 4_000, 4_001 + 137, 9_999];

/// Awake, at an instruction boundary: the ISR's first instruction begins
/// the response + 3 cycles after the edge (5 + 3 on the 2560, 4 + 3 on the
/// 328P), and `reti` takes as many as the response.
#[test]
fn awake_the_vector_is_the_response_after_the_edge_and_reti_as_long() {
    for (mcu, response, _, reti) in MCUS {
        let (raised, serviced) = run(mcu, false, &EDGES);
        // Every cycle of the loop is an instruction boundary: the toggles
        // came at their own cycles, not after an instruction in progress.
        assert_eq!(raised, EDGES, "{mcu}");
        for s in &serviced {
            assert_eq!(s.isr - s.edge, response + JMP_CYCLES, "{mcu} {s:?}");
            // `out GPIOR0` (1 cycle), then `reti`.
            assert_eq!(s.back - (s.isr + 1), reti, "{mcu} {s:?}");
        }
        assert_eq!(mcu.chip().response_cycles(), response, "{mcu}");
    }
}

/// Asleep in idle: the edge comes at its cycle (simavr alone sleeps one
/// past the timer), the ISR's first instruction begins the response, the
/// wake-up and 3 cycles after it (5 + 5 + 3 on the 2560, 4 + 4 + 3 on the
/// 328P), and `reti` returns to the instruction after `sleep`.
#[test]
fn asleep_the_vector_is_the_response_and_the_wake_up_after_the_edge() {
    for (mcu, response, wake_up, reti) in MCUS {
        let (raised, serviced) = run(mcu, true, &EDGES);
        assert_eq!(raised, EDGES, "{mcu}: the toggles at their cycles");
        for s in &serviced {
            assert_eq!(
                s.isr - s.edge,
                response + wake_up + JMP_CYCLES,
                "{mcu} {s:?}"
            );
            assert_eq!(s.back - (s.isr + 1), reti, "{mcu} {s:?}");
        }
        assert_eq!(mcu.chip().wake_up_cycles(), wake_up, "{mcu}");
    }
}

/// An edge during a multi-cycle instruction waits for it to complete
/// (§7.8.1, §6.7.1), then the response: the toggle that falls on the
/// loop's two-cycle `rjmp` is raised after it, and the ISR follows it by
/// the response + 3.
#[test]
fn an_edge_during_an_instruction_waits_for_its_end() {
    for (mcu, response, _, _) in MCUS {
        // The loop's `rjmp` takes the two cycles after its 500 `out`s.
        let rjmp_second_cycle = first_loop_cycle(mcu) + LOOP_WRITES as u64 + 1;
        let (raised, serviced) = run(mcu, false, &[rjmp_second_cycle]);
        assert_eq!(
            raised,
            vec![rjmp_second_cycle + 1],
            "{mcu}: raised after the rjmp"
        );
        let s = &serviced[0];
        assert_eq!(s.isr - s.edge, response + JMP_CYCLES, "{mcu} {s:?}");
    }
}

/// The cycle the awake loop's first `out GPIOR1` begins at.
fn first_loop_cycle(mcu: Mcu) -> u64 {
    let chip = mcu.chip();
    let mut avr = Avr::new(chip.simavr_core, F_CPU, Log::default()).unwrap();
    avr.load_flash(0, &program(chip, false)).unwrap();
    avr.claim_io_write(GPIOR1, IoClaim::Observe).unwrap();
    avr.run_to(100);
    avr.handler().writes[0].1
}
