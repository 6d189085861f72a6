//! Digital pins, named by their port register and bit (`PE4`, `PH3`, ...).
//!
//! A pin is a zero-sized [`Pin<P, MODE>`]: the mode is part of the type and
//! changes by consuming the pin, so a driver that receives a
//! `Pin<PE4, Input>` knows the pin was configured as an input. Pins are created
//! once, by `board::Pins::new`, from the port peripherals it takes by value.
//!
//! Interrupt handlers may read an input without owning it through
//! [`PinId::is_high`]: reading PINx has no side effects.

use core::marker::PhantomData;
use core::ptr::{read_volatile, write_volatile};

use avr_device::interrupt;

/// Mode marker: input, driven from outside; the pull-up is off.
pub struct Input;
/// Mode marker: push-pull output.
pub struct Output;

/// Identity of one pin: the three registers of its port and its bit.
pub trait PinId {
    /// Bit mask of the pin in PINx, DDRx and PORTx.
    const MASK: u8;
    /// Address of PINx.
    fn pin_reg() -> *mut u8;
    /// Address of DDRx.
    fn ddr_reg() -> *mut u8;
    /// Address of PORTx.
    fn port_reg() -> *mut u8;

    /// Level on the pin right now, whatever its mode.
    #[inline(always)]
    fn is_high() -> bool {
        // SAFETY: PINx is a read-only input register; reading it has no side
        // effect, so any context may read it.
        unsafe { read_volatile(Self::pin_reg()) & Self::MASK != 0 }
    }
}

/// Sets or clears `mask` in the register at `reg`, atomically with respect to
/// interrupt handlers (ports above 0x3F have no single-instruction bit set).
#[inline(always)]
fn modify_bit(reg: *mut u8, mask: u8, set: bool) {
    interrupt::free(|_| {
        // SAFETY: `reg` is one of this chip's port registers (from `PinId`);
        // interrupts are off, so the read-modify-write cannot interleave with
        // a handler writing the same register.
        unsafe {
            let v = read_volatile(reg);
            write_volatile(reg, if set { v | mask } else { v & !mask });
        }
    });
}

/// One pin in one mode.
pub struct Pin<P: PinId, MODE> {
    _pin: PhantomData<(P, MODE)>,
}

impl<P: PinId> Pin<P, Input> {
    /// The pin in its reset state (input, no pull-up).
    ///
    /// # Safety
    /// At most one `Pin` per `PinId` may exist; only `board::Pins::new`, which
    /// holds the port peripherals, calls this.
    pub const unsafe fn new() -> Self {
        Pin { _pin: PhantomData }
    }
}

impl<P: PinId, MODE> Pin<P, MODE> {
    /// Makes the pin an input without pull-up (PORTx bit low, DDRx bit low).
    pub fn into_floating_input(self) -> Pin<P, Input> {
        modify_bit(P::ddr_reg(), P::MASK, false);
        modify_bit(P::port_reg(), P::MASK, false);
        Pin { _pin: PhantomData }
    }

    /// Makes the pin an output driving low. PORTx is cleared before DDRx is
    /// set, so the pin never drives high on the way.
    pub fn into_output_low(self) -> Pin<P, Output> {
        modify_bit(P::port_reg(), P::MASK, false);
        modify_bit(P::ddr_reg(), P::MASK, true);
        Pin { _pin: PhantomData }
    }

    /// Level on the pin.
    #[inline(always)]
    pub fn is_high(&self) -> bool {
        P::is_high()
    }
}

impl<P: PinId> Pin<P, Output> {
    /// Drives the pin high.
    #[inline(always)]
    pub fn set_high(&mut self) {
        modify_bit(P::port_reg(), P::MASK, true);
    }

    /// Drives the pin low.
    #[inline(always)]
    pub fn set_low(&mut self) {
        modify_bit(P::port_reg(), P::MASK, false);
    }

    /// Drives the pin to `high`.
    #[inline(always)]
    pub fn set(&mut self, high: bool) {
        modify_bit(P::port_reg(), P::MASK, high);
    }
}

macro_rules! pin_ids {
    ($($name:ident: $periph:ident, $pin:ident, $ddr:ident, $port:ident, $bit:literal;)*) => {$(
        #[doc = concat!("Pin ", stringify!($name), ".")]
        pub struct $name;

        impl PinId for $name {
            const MASK: u8 = 1 << $bit;
            #[inline(always)]
            fn pin_reg() -> *mut u8 {
                // SAFETY: the PAC pointer is the fixed address of this port's
                // register block; only the address is taken, nothing is read.
                unsafe { (*avr_device::atmega2560::$periph::ptr()).$pin().as_ptr() }
            }
            #[inline(always)]
            fn ddr_reg() -> *mut u8 {
                // SAFETY: as above, address only.
                unsafe { (*avr_device::atmega2560::$periph::ptr()).$ddr().as_ptr() }
            }
            #[inline(always)]
            fn port_reg() -> *mut u8 {
                // SAFETY: as above, address only.
                unsafe { (*avr_device::atmega2560::$periph::ptr()).$port().as_ptr() }
            }
        }
    )*};
}

// The pins the robot uses (see `board.rs` for their roles).
pin_ids! {
    PB4: PORTB, pinb, ddrb, portb, 4;
    PB5: PORTB, pinb, ddrb, portb, 5;
    PB6: PORTB, pinb, ddrb, portb, 6;
    PD2: PORTD, pind, ddrd, portd, 2;
    PD3: PORTD, pind, ddrd, portd, 3;
    PE0: PORTE, pine, ddre, porte, 0;
    PE1: PORTE, pine, ddre, porte, 1;
    PE3: PORTE, pine, ddre, porte, 3;
    PE4: PORTE, pine, ddre, porte, 4;
    PE5: PORTE, pine, ddre, porte, 5;
    PF0: PORTF, pinf, ddrf, portf, 0;
    PG5: PORTG, ping, ddrg, portg, 5;
    PH3: PORTH, pinh, ddrh, porth, 3;
    PH4: PORTH, pinh, ddrh, porth, 4;
    PH5: PORTH, pinh, ddrh, porth, 5;
    PH6: PORTH, pinh, ddrh, porth, 6;
}
