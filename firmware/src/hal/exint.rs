//! External interrupts INT0..INT7 (EICRA/EICRB sense control, EIMSK, EIFR).
//!
//! Only configuration lives here; the handlers (`INTn` vectors) belong to the
//! driver that uses the line, because what they do is the driver's business.

use avr_device::atmega2560::EXINT;

/// What on the pin raises the interrupt (ISCn1:0).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Sense {
    /// Low level (ISC = 00).
    LowLevel = 0b00,
    /// Any logical change (ISC = 01), Arduino's `CHANGE`.
    AnyEdge = 0b01,
    /// Falling edge (ISC = 10).
    Falling = 0b10,
    /// Rising edge (ISC = 11).
    Rising = 0b11,
}

/// One of the eight external interrupt lines.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Line {
    /// INT0 (PD0, Arduino D21)
    Int0 = 0,
    /// INT1 (PD1, Arduino D20)
    Int1 = 1,
    /// INT2 (PD2, Arduino D19)
    Int2 = 2,
    /// INT3 (PD3, Arduino D18)
    Int3 = 3,
    /// INT4 (PE4, Arduino D2)
    Int4 = 4,
    /// INT5 (PE5, Arduino D3)
    Int5 = 5,
    /// INT6 (PE6, not on an Arduino header)
    Int6 = 6,
    /// INT7 (PE7, not on an Arduino header)
    Int7 = 7,
}

/// Owner of the external interrupt registers.
pub struct ExtInts {
    exint: EXINT,
}

impl ExtInts {
    /// Takes the registers; all lines stay masked until [`ExtInts::enable`].
    pub fn new(exint: EXINT) -> Self {
        ExtInts { exint }
    }

    /// Sets the sense of `line` and unmasks it. Follows the datasheet's order:
    /// mask the line, change ISCn, clear INTFn (a change of ISCn can raise a
    /// spurious flag), then unmask.
    pub fn enable(&mut self, line: Line, sense: Sense) {
        let n = line as u8;
        let bit = 1u8 << n;
        let shift = 2 * (n % 4);
        let isc = (sense as u8) << shift;
        let isc_mask = 0b11u8 << shift;
        avr_device::interrupt::free(|_| {
            // SAFETY: every bit pattern is valid for these registers; the
            // values keep the other lines' bits as they were.
            unsafe {
                self.exint.eimsk().modify(|r, w| w.bits(r.bits() & !bit));
                if n < 4 {
                    self.exint.eicra().modify(|r, w| w.bits((r.bits() & !isc_mask) | isc));
                } else {
                    self.exint.eicrb().modify(|r, w| w.bits((r.bits() & !isc_mask) | isc));
                }
                // A flag is cleared by writing a one to it.
                self.exint.eifr().write(|w| w.bits(bit));
                self.exint.eimsk().modify(|r, w| w.bits(r.bits() | bit));
            }
        });
    }

    /// Masks `line` again.
    pub fn disable(&mut self, line: Line) {
        let bit = 1u8 << (line as u8);
        avr_device::interrupt::free(|_| {
            // SAFETY: clears one mask bit, any value is valid.
            unsafe { self.exint.eimsk().modify(|r, w| w.bits(r.bits() & !bit)) };
        });
    }

    /// Gives the registers back.
    pub fn release(self) -> EXINT {
        self.exint
    }
}
