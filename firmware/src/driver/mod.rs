//! The motor driver as the robot has it, told at run time: its kind
//! (`henrytwo_protocol::DriverKind`) and its Arduino Mega pins
//! ([`DriverWiring`]), driven through the pin table ([`crate::hal::mega_pins`]).
//!
//! The logic asks for a forward and a reverse input per wheel with
//! `analogWrite` semantics ([`Bridges`]); each kind turns that into its own
//! inputs:
//! - `TwoPwm` (DRV8833): pin 1 is the forward input, pin 2 the reverse one,
//!   both PWM; each request writes one channel, exactly as the compiled
//!   Henrytwo driver did (`crate::motors`), register for register.
//! - `EnableTwoDir` (L298N style): pin 1 the PWM enable, pins 2 and 3 IN1 and
//!   IN2. Forward: IN1 high, IN2 low; reverse: IN1 low, IN2 high; then the
//!   enable gets the duty. A duty of 0 drives the enable low (coast).
//! - `PwmDir`: pin 1 PWM, pin 2 the direction (high = forward), written
//!   before the PWM.
//!
//! For the last two the motor goes the way of the one nonzero input; with
//! both inputs 0, or both nonzero (which the logic never asks), it coasts.
//!
//! PWM is 8-bit phase-correct at clock/1 on any channel of timers 2-5, set up
//! like `crate::hal::pwm` sets up timers 2 and 4 (TCCRnA = WGMn0, then
//! TCCRnB = CSn0), and only for the timers the wiring uses (the bench refuses
//! timers it does not emulate). A duty of 0 or 255 sets the PORT bit, then
//! clears the channel's COMnx1 (the pin a plain output); anything else writes
//! OCRnx (16-bit timers: high byte 0, then the low byte), then sets COMnx1.
//! Timer registers are only written: TCCRnA lives in a shadow copy.
//!
//! Register addresses and masks are worked out once, when a wiring is applied
//! ([`Driver::new`], [`Bridges::rewire`]); the control tick's writes only
//! load them.

pub mod check;

#[cfg(test)]
mod tests;

pub use check::{WiringError, WiringFault};

use core::borrow::BorrowMut;

use henrytwo_protocol::{DriverKind, NO_PIN};

use crate::critical;
use crate::hal::clock::Prescaler;
use crate::hal::mega_pins;
use crate::io::{Bridges, Side};
use crate::settings::{DriverWiring, Settings};

/// Byte access to the chip's data space (the I/O registers).
pub trait Registers {
    /// Reads the register at `addr`.
    fn read(&mut self, addr: u16) -> u8;
    /// Writes `v` to the register at `addr`.
    fn write(&mut self, addr: u16, v: u8);
}

/// The ATmega2560's own registers.
#[cfg(target_arch = "avr")]
pub struct Mmio {
    _private: (),
}

#[cfg(target_arch = "avr")]
impl Mmio {
    /// The chip's registers.
    ///
    /// # Safety
    /// The driver built on this writes the ports and timers its wiring names:
    /// no other code may drive those pins or timers 2-5 (in the robust build
    /// only the driver does; the pins it may use are checked against the
    /// others the firmware uses, [`DriverWiring::check`]).
    pub const unsafe fn new() -> Self {
        Mmio { _private: () }
    }
}

#[cfg(target_arch = "avr")]
impl Registers for Mmio {
    #[inline(always)]
    fn read(&mut self, addr: u16) -> u8 {
        // SAFETY: `addr` comes from the pin table (a PORTx, DDRx, PINx
        // address of this chip); reading those has no side effect.
        unsafe { core::ptr::read_volatile(addr as *const u8) }
    }

    #[inline(always)]
    fn write(&mut self, addr: u16, v: u8) {
        // SAFETY: `addr` is a port or PWM timer register from the pin table,
        // of a pin or timer the checked wiring gives this driver alone.
        unsafe { core::ptr::write_volatile(addr as *mut u8, v) }
    }
}

/// WGMn0 in TCCRnA: mode 1, 8-bit phase-correct PWM, as `hal::pwm`.
const WGM_PHASE_CORRECT_8BIT: u8 = 0b01;
/// Clock select of timers 3, 4, 5 at clock/1.
const CS_DIV1: u8 = Prescaler::Div1.cs_bits();
/// Clock select of timer 2 at clock/1.
const CS2_DIV1: u8 = Prescaler::Div1.cs_bits_timer2();

/// One bridge input, its registers worked out.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
struct Output {
    /// PORTx address (0: no pin).
    port: u16,
    /// The pin's bit in PORTx and DDRx.
    mask: u8,
    /// TCCRnA address (0: a plain output).
    tccra: u16,
    /// OCRnx (low byte) address.
    ocr: u16,
    /// COMnx1 in TCCRnA.
    com1: u8,
    /// Index of the timer's TCCRnA shadow (timer - 2).
    timer: u8,
    /// OCRnx is 16 bits wide (timers 3, 4, 5).
    wide: bool,
}

impl Output {
    /// The registers of Arduino pin `n` (none for [`NO_PIN`] or a pin the
    /// Mega lacks; PWM only if `pwm` and it is on timer 2-5).
    fn of(n: u8, pwm: bool) -> Output {
        let Some(p) = mega_pins::pin(n) else { return Output::default() };
        let mut o = Output { port: p.port.port_reg(), mask: p.mask(), ..Output::default() };
        if let Some((oc, t)) = p.oc.filter(|_| pwm).and_then(|oc| mega_pins::pwm_timer(oc.timer).map(|t| (oc, t))) {
            o.tccra = t.tccra;
            o.ocr = t.ocr[oc.channel.index()];
            o.com1 = oc.channel.com1();
            o.timer = oc.timer - 2;
            o.wide = t.wide;
        }
        o
    }
}

/// Which way a bridge of the direction kinds is set.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Dir {
    /// Not written since the wiring was applied.
    Unknown,
    Forward,
    Reverse,
}

/// One motor's driver inputs and what the logic last asked of them.
#[derive(Clone, Copy, Debug)]
struct Bridge {
    /// Pins 1-3.
    out: [Output; 3],
    /// The forward and reverse requests (direction kinds only).
    forward: u8,
    reverse: u8,
    /// The direction pins' state.
    dir: Dir,
}

impl Bridge {
    fn new(kind: DriverKind, pins: [u8; 3]) -> Bridge {
        // Pin 1 is PWM in every kind; TwoPwm's pin 2 too.
        let pwm2 = kind == DriverKind::TwoPwm;
        Bridge {
            out: [Output::of(pins[0], true), Output::of(pins[1], pwm2), Output::of(pins[2], false)],
            forward: 0,
            reverse: 0,
            dir: Dir::Unknown,
        }
    }
}

/// The driver's state: its kind, both bridges, the PWM timers' shadows.
pub struct State {
    kind: DriverKind,
    /// Left, right.
    bridges: [Bridge; 2],
    /// TCCRnA of timers 2, 3, 4, 5 as last written.
    shadow: [u8; 4],
    /// Bit `t - 2` set: timer `t` runs.
    running: u8,
    /// The wiring applied.
    wiring: DriverWiring,
}

impl State {
    /// No wiring applied yet.
    pub const fn new() -> Self {
        const NONE: Output = Output { port: 0, mask: 0, tccra: 0, ocr: 0, com1: 0, timer: 0, wide: false };
        const B: Bridge = Bridge { out: [NONE; 3], forward: 0, reverse: 0, dir: Dir::Unknown };
        State {
            kind: DriverKind::TwoPwm,
            bridges: [B; 2],
            shadow: [0; 4],
            running: 0,
            wiring: DriverWiring { kind: 0, left: [NO_PIN; 3], right: [NO_PIN; 3] },
        }
    }
}

impl Default for State {
    fn default() -> Self {
        Self::new()
    }
}

/// The robust build's driver state, in a static: the driver itself is then
/// zero-sized, so the drive's other fields keep their offsets, and the
/// control tick reaches the state at fixed addresses.
#[cfg(target_arch = "avr")]
pub struct StaticState {
    _private: (),
}

#[cfg(target_arch = "avr")]
static mut STATE: State = State::new();

#[cfg(target_arch = "avr")]
impl StaticState {
    /// The one static state.
    ///
    /// # Safety
    /// At most one `StaticState` may exist (the robust build makes one, in
    /// `main`), and no interrupt handler may use it.
    pub const unsafe fn take() -> Self {
        StaticState { _private: () }
    }
}

#[cfg(target_arch = "avr")]
impl core::borrow::Borrow<State> for StaticState {
    #[inline(always)]
    fn borrow(&self) -> &State {
        // SAFETY: `take`'s contract makes this the only handle on `STATE`,
        // and `&self` excludes a `&mut` borrow through it meanwhile.
        unsafe { &*core::ptr::addr_of!(STATE) }
    }
}

#[cfg(target_arch = "avr")]
impl core::borrow::BorrowMut<State> for StaticState {
    #[inline(always)]
    fn borrow_mut(&mut self) -> &mut State {
        // SAFETY: as `borrow`; `&mut self` makes this borrow exclusive.
        unsafe { &mut *core::ptr::addr_of_mut!(STATE) }
    }
}

/// The motor driver: the registers, and where its [`State`] is (its own
/// field on the host, [`StaticState`] in the robust build).
pub struct Driver<R: Registers, S: BorrowMut<State> = State> {
    regs: R,
    st: S,
}

impl<R: Registers> Driver<R, State> {
    /// Takes the registers and applies `wiring` (the factory wiring if it
    /// fails [`DriverWiring::check`]): its pins become outputs driving low,
    /// the timers it uses start, every input at 0 (the motors coast).
    pub fn new(regs: R, wiring: &DriverWiring) -> Self {
        Driver::with_state(regs, State::new(), wiring)
    }
}

impl<R: Registers, S: BorrowMut<State>> Driver<R, S> {
    /// [`Driver::new`] with the state kept in `st`, which must hold
    /// [`State::new`].
    pub fn with_state(regs: R, st: S, wiring: &DriverWiring) -> Self {
        let factory = Settings::DEFAULT.driver;
        let wiring = if wiring.check().is_ok() { wiring } else { &factory };
        let mut d = Driver { regs, st };
        d.st.borrow_mut().apply(&mut d.regs, wiring);
        d
    }

    /// The registers (the host tests read the fake's log).
    pub fn registers(&mut self) -> &mut R {
        &mut self.regs
    }

    /// The wiring applied.
    pub fn wiring(&self) -> &DriverWiring {
        &self.st.borrow().wiring
    }
}

impl State {
    /// Applies `w`, which has passed the check.
    fn apply<R: Registers>(&mut self, regs: &mut R, w: &DriverWiring) {
        let kind = DriverKind::from_u8(w.kind).unwrap_or(DriverKind::TwoPwm);
        self.kind = kind;
        self.wiring = *w;
        self.bridges = [Bridge::new(kind, w.left), Bridge::new(kind, w.right)];
        // Pins in Arduino order, each an output driving low (PORT bit first,
        // then DDR, so it never drives high) ...
        let mut pins = [w.left[0], w.left[1], w.left[2], w.right[0], w.right[1], w.right[2]];
        pins.sort_unstable();
        for n in pins {
            if let Some(p) = mega_pins::pin(n) {
                let mask = p.mask();
                modify(regs, p.port.port_reg(), mask, false);
                modify(regs, p.port.ddr_reg(), mask, true);
            }
        }
        // ... then the timers of the PWM inputs, in the order their first
        // pin comes.
        for n in pins {
            let o = Output::of(n, true);
            let pwm =
                self.bridges.iter().any(|b| b.out.iter().any(|x| x.tccra != 0 && x.port == o.port && x.mask == o.mask));
            let bit = 1 << o.timer;
            if pwm && self.running & bit == 0 {
                self.running |= bit;
                let t = o.timer as usize;
                if let (Some(s), Some(timer)) = (self.shadow.get_mut(t), mega_pins::pwm_timer(o.timer + 2)) {
                    *s |= WGM_PHASE_CORRECT_8BIT;
                    let v = *s;
                    let cs = if o.timer == 0 { CS2_DIV1 } else { CS_DIV1 };
                    critical::free(|_| {
                        regs.write(timer.tccra, v);
                        regs.write(timer.tccrb, cs);
                    });
                }
            }
        }
        // Every input at 0: forward then reverse, right then left, like
        // the compiled driver's construction.
        for side in [Side::Right, Side::Left] {
            self.set_input(regs, side, 0, 0);
            self.set_input(regs, side, 1, 0);
        }
    }

    /// Drives every input of the applied wiring low and releases its compare
    /// output (timers keep running; pins stay outputs).
    fn release<R: Registers>(&mut self, regs: &mut R) {
        for b in 0..2 {
            for i in 0..3 {
                let o = self.bridges[b].out[i];
                if o.tccra != 0 {
                    write_pwm(regs, &mut self.shadow, &o, 0);
                } else if o.port != 0 {
                    modify(regs, o.port, o.mask, false);
                }
            }
        }
    }

    /// Sets `side`'s forward (`input` 0) or reverse (1) request. Fields are
    /// borrowed apart and nothing is copied: this is the control tick's path.
    #[inline(always)]
    fn set_input<R: Registers>(&mut self, regs: &mut R, side: Side, input: usize, duty: u8) {
        let State { kind, bridges, shadow, .. } = self;
        let b = match side {
            Side::Left => &mut bridges[0],
            Side::Right => &mut bridges[1],
        };
        if *kind == DriverKind::TwoPwm {
            // Pins 1 and 2 of a checked TwoPwm wiring are PWM outputs.
            if let Some(o) = b.out.get(input) {
                write_pwm(regs, shadow, o, duty);
            }
        } else {
            if input == 0 {
                b.forward = duty;
            } else {
                b.reverse = duty;
            }
            update(regs, shadow, *kind, b);
        }
    }
}

/// Sets or clears `mask` at `reg` with interrupts off.
#[inline(always)]
fn modify<R: Registers>(regs: &mut R, reg: u16, mask: u8, set: bool) {
    critical::free(|_| {
        let v = regs.read(reg);
        regs.write(reg, if set { v | mask } else { v & !mask });
    });
}

/// A direction kind's bridge `b` after its requests changed: the direction
/// pins if the direction changes, then pin 1's duty.
#[inline(never)]
fn update<R: Registers>(regs: &mut R, shadow: &mut [u8; 4], kind: DriverKind, b: &mut Bridge) {
    let (dir, duty) = match (b.forward, b.reverse) {
        (f, 0) if f != 0 => (Dir::Forward, f),
        (0, r) if r != 0 => (Dir::Reverse, r),
        _ => (b.dir, 0),
    };
    let [p1, p2, p3] = &b.out;
    if duty != 0 && dir != b.dir {
        let fwd = dir == Dir::Forward;
        modify(regs, p2.port, p2.mask, fwd);
        if kind == DriverKind::EnableTwoDir {
            modify(regs, p3.port, p3.mask, !fwd);
        }
        b.dir = dir;
    }
    write_pwm(regs, shadow, p1, duty);
}

/// `analogWrite` on a PWM output, in the order of the module docs. Inlined:
/// in the robust build `o` and the shadows are in a static, so each field
/// is one load from a fixed address (an out-of-line copy through pointers
/// cost the control tick about 45 cycles a write more).
#[inline(always)]
fn write_pwm<R: Registers>(regs: &mut R, shadow: &mut [u8; 4], o: &Output, duty: u8) {
    let shadow = &mut shadow[o.timer as usize & 3];
    critical::free(|_| match duty {
        0 | 255 => {
            let v = regs.read(o.port);
            regs.write(o.port, if duty == 0 { v & !o.mask } else { v | o.mask });
            *shadow &= !o.com1;
            regs.write(o.tccra, *shadow);
        }
        d => {
            if o.wide {
                regs.write(o.ocr + 1, 0);
            }
            regs.write(o.ocr, d);
            *shadow |= o.com1;
            regs.write(o.tccra, *shadow);
        }
    });
}

impl<R: Registers, S: BorrowMut<State>> Bridges for Driver<R, S> {
    #[inline(always)]
    fn set_forward(&mut self, side: Side, duty: u8) {
        self.st.borrow_mut().set_input(&mut self.regs, side, 0, duty);
    }

    #[inline(always)]
    fn set_reverse(&mut self, side: Side, duty: u8) {
        self.st.borrow_mut().set_input(&mut self.regs, side, 1, duty);
    }

    fn all_off(&mut self) {
        self.set_forward(Side::Right, 0);
        self.set_forward(Side::Left, 0);
        self.set_reverse(Side::Right, 0);
        self.set_reverse(Side::Left, 0);
    }

    fn drives(&self, w: &DriverWiring) -> bool {
        self.st.borrow().wiring == *w
    }

    fn rewire(&mut self, w: &DriverWiring) {
        // Only a wiring that passes the check is ever applied: the PWM
        // writes rely on it (pin 1, and TwoPwm's pin 2, on a timer).
        let st = self.st.borrow_mut();
        if st.wiring != *w && w.check().is_ok() {
            st.release(&mut self.regs);
            st.apply(&mut self.regs, w);
        }
    }
}
