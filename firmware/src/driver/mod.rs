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

use henrytwo_protocol::{DriverKind, NO_PIN};

use crate::critical;
use crate::hal::clock::Prescaler;
use crate::hal::mega_pins;
use crate::io::{Bridges, Side};
use crate::settings::DriverWiring;

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

/// The motor driver: its kind, both bridges, the PWM timers' state.
pub struct Driver<R: Registers> {
    regs: R,
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

#[inline(always)]
fn index(side: Side) -> usize {
    match side {
        Side::Left => 0,
        Side::Right => 1,
    }
}

impl<R: Registers> Driver<R> {
    /// Takes the registers and applies `wiring`, which must have passed
    /// [`DriverWiring::check`]: its pins become outputs driving low, the
    /// timers it uses start, every input at 0 (the motors coast).
    pub fn new(regs: R, wiring: &DriverWiring) -> Self {
        let mut d = Driver {
            regs,
            kind: DriverKind::TwoPwm,
            bridges: [Bridge::new(DriverKind::TwoPwm, [NO_PIN; 3]); 2],
            shadow: [0; 4],
            running: 0,
            wiring: *wiring,
        };
        d.apply(wiring);
        d
    }

    /// The registers (the host tests read the fake's log).
    pub fn registers(&mut self) -> &mut R {
        &mut self.regs
    }

    /// The wiring applied.
    pub fn wiring(&self) -> &DriverWiring {
        &self.wiring
    }

    fn apply(&mut self, w: &DriverWiring) {
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
                self.modify(p.port.port_reg(), mask, false);
                self.modify(p.port.ddr_reg(), mask, true);
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
                if let (Some(s), Some(regs)) = (self.shadow.get_mut(t), mega_pins::pwm_timer(o.timer + 2)) {
                    *s |= WGM_PHASE_CORRECT_8BIT;
                    let v = *s;
                    let cs = if o.timer == 0 { CS2_DIV1 } else { CS_DIV1 };
                    critical::free(|_| {
                        self.regs.write(regs.tccra, v);
                        self.regs.write(regs.tccrb, cs);
                    });
                }
            }
        }
        // Every input at 0: forward then reverse, right then left, like
        // the compiled driver's construction.
        for side in [Side::Right, Side::Left] {
            self.set_forward(side, 0);
            self.set_reverse(side, 0);
        }
    }

    /// Drives every input of the applied wiring low and releases its compare
    /// output (timers keep running; pins stay outputs).
    fn release(&mut self) {
        for b in 0..2 {
            for i in 0..3 {
                let o = self.bridges[b].out[i];
                if o.port != 0 {
                    self.write_duty(o, 0);
                }
            }
        }
    }

    /// Sets or clears `mask` at `reg` with interrupts off.
    #[inline(always)]
    fn modify(&mut self, reg: u16, mask: u8, set: bool) {
        critical::free(|_| {
            let v = self.regs.read(reg);
            self.regs.write(reg, if set { v | mask } else { v & !mask });
        });
    }

    /// `analogWrite(o, duty)`, in the order of the module docs.
    #[inline(always)]
    fn write_duty(&mut self, o: Output, duty: u8) {
        if o.tccra == 0 {
            // A plain output (only reached by `release`).
            self.modify(o.port, o.mask, duty != 0);
        } else {
            write_pwm(&mut self.regs, &mut self.shadow, &o, duty);
        }
    }

    /// A direction kind's bridge after its requests changed.
    fn update(&mut self, side: Side) {
        let b = self.bridges[index(side)];
        let (dir, duty) = match (b.forward, b.reverse) {
            (f, 0) if f != 0 => (Dir::Forward, f),
            (0, r) if r != 0 => (Dir::Reverse, r),
            _ => (b.dir, 0),
        };
        if duty != 0 && dir != b.dir {
            let fwd = dir == Dir::Forward;
            let [_, p2, p3] = b.out;
            self.modify(p2.port, p2.mask, fwd);
            if self.kind == DriverKind::EnableTwoDir {
                self.modify(p3.port, p3.mask, !fwd);
            }
            self.bridges[index(side)].dir = dir;
        }
        self.write_duty(b.out[0], duty);
    }
}

/// `analogWrite` on a PWM output, in the order of the module docs. Out of
/// line: one copy serves every call (the control tick's included), its
/// addresses loaded from `o`.
#[inline(never)]
fn write_pwm<R: Registers>(regs: &mut R, shadow: &mut [u8; 4], o: &Output, duty: u8) {
    let Some(shadow) = shadow.get_mut(o.timer as usize) else { return };
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

impl<R: Registers> Bridges for Driver<R> {
    #[inline(always)]
    fn set_forward(&mut self, side: Side, duty: u8) {
        let i = index(side);
        if self.kind == DriverKind::TwoPwm {
            let o = self.bridges[i].out[0];
            self.write_duty(o, duty);
        } else {
            self.bridges[i].forward = duty;
            self.update(side);
        }
    }

    #[inline(always)]
    fn set_reverse(&mut self, side: Side, duty: u8) {
        let i = index(side);
        if self.kind == DriverKind::TwoPwm {
            let o = self.bridges[i].out[1];
            self.write_duty(o, duty);
        } else {
            self.bridges[i].reverse = duty;
            self.update(side);
        }
    }

    fn all_off(&mut self) {
        self.set_forward(Side::Right, 0);
        self.set_forward(Side::Left, 0);
        self.set_reverse(Side::Right, 0);
        self.set_reverse(Side::Left, 0);
    }

    fn drives(&self, w: &DriverWiring) -> bool {
        self.wiring == *w
    }

    fn rewire(&mut self, w: &DriverWiring) {
        if self.wiring != *w {
            self.release();
            self.apply(w);
        }
    }
}
