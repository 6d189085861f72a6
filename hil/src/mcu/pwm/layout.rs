//! Where each timer's registers are (ATmega640/1280/2560 datasheet,
//! register summary): the 8-bit timers 0 (0x44-0x48) and 2 (0xB0-0xB6),
//! the 16-bit timers 1, 3, 4 and 5 laid out alike (section 17.11) at 0x80,
//! 0x90, 0xA0 and 0x120. The ATmega2560's timers are the table
//! [`ATMEGA2560`]: another MCU's come as another such table.

use super::mode::Prescalers;
use super::TimerId;

/// Register addresses and layout of one timer.
#[derive(Debug, Clone, Copy)]
pub struct Layout {
    pub id: TimerId,
    pub tccra: u16,
    pub tccrb: u16,
    pub tccrc: Option<u16>,
    pub tcnt: u16,
    /// Low-byte address of each OCR (channel letter, address); 16-bit
    /// timers have the high byte at address + 1.
    pub ocr: &'static [(char, u16)],
    pub icr: Option<u16>,
    pub timsk: u16,
    pub tifr: u16,
    pub assr: Option<u16>,
    pub sixteen_bit: bool,
    /// Its clock select table.
    pub prescalers: Prescalers,
}

/// The ATmega2560's timers, in timer order.
pub const ATMEGA2560: [Layout; 6] = [
    Layout::TIMER0,
    Layout::TIMER1,
    Layout::TIMER2,
    Layout::TIMER3,
    Layout::TIMER4,
    Layout::TIMER5,
];

impl Layout {
    /// Timer 0 (register summary: TCCR0A 0x44 .. OCR0B 0x48, TIMSK0 0x6E,
    /// TIFR0 0x35), the Arduino core's `millis()` timer.
    pub const TIMER0: Layout = Layout {
        id: TimerId(0),
        tccra: 0x44,
        tccrb: 0x45,
        tccrc: None,
        tcnt: 0x46,
        ocr: &[('A', 0x47), ('B', 0x48)],
        icr: None,
        timsk: 0x6E,
        tifr: 0x35,
        assr: None,
        sixteen_bit: false,
        prescalers: Prescalers::Shared,
    };

    /// Timer 1 (register summary: 0x80-0x8D, TIMSK1 0x6F, TIFR1 0x36).
    pub const TIMER1: Layout = Layout {
        id: TimerId(1),
        tccra: 0x80,
        tccrb: 0x81,
        tccrc: Some(0x82),
        tcnt: 0x84,
        ocr: &[('A', 0x88), ('B', 0x8A), ('C', 0x8C)],
        icr: Some(0x86),
        timsk: 0x6F,
        tifr: 0x36,
        assr: None,
        sixteen_bit: true,
        prescalers: Prescalers::Shared,
    };

    pub const TIMER2: Layout = Layout {
        id: TimerId(2),
        tccra: 0xB0,
        tccrb: 0xB1,
        tccrc: None,
        tcnt: 0xB2,
        ocr: &[('A', 0xB3), ('B', 0xB4)],
        icr: None,
        timsk: 0x70,
        tifr: 0x37,
        assr: Some(0xB6),
        sixteen_bit: false,
        prescalers: Prescalers::Asynchronous,
    };

    /// Timer 3 (register summary: 0x90-0x9D, TIMSK3 0x71, TIFR3 0x38).
    pub const TIMER3: Layout = Layout {
        id: TimerId(3),
        tccra: 0x90,
        tccrb: 0x91,
        tccrc: Some(0x92),
        tcnt: 0x94,
        ocr: &[('A', 0x98), ('B', 0x9A), ('C', 0x9C)],
        icr: Some(0x96),
        timsk: 0x71,
        tifr: 0x38,
        assr: None,
        sixteen_bit: true,
        prescalers: Prescalers::Shared,
    };

    pub const TIMER4: Layout = Layout {
        id: TimerId(4),
        tccra: 0xA0,
        tccrb: 0xA1,
        tccrc: Some(0xA2),
        tcnt: 0xA4,
        ocr: &[('A', 0xA8), ('B', 0xAA), ('C', 0xAC)],
        icr: Some(0xA6),
        timsk: 0x72,
        tifr: 0x39,
        assr: None,
        sixteen_bit: true,
        prescalers: Prescalers::Shared,
    };

    /// Timer 5 (register summary: 0x120-0x12D, TIMSK5 0x73, TIFR5 0x3A).
    pub const TIMER5: Layout = Layout {
        id: TimerId(5),
        tccra: 0x120,
        tccrb: 0x121,
        tccrc: Some(0x122),
        tcnt: 0x124,
        ocr: &[('A', 0x128), ('B', 0x12A), ('C', 0x12C)],
        icr: Some(0x126),
        timsk: 0x73,
        tifr: 0x3A,
        assr: None,
        sixteen_bit: true,
        prescalers: Prescalers::Shared,
    };

    /// The ATmega2560's timer `n`.
    pub fn of(n: u8) -> Option<Layout> {
        ATMEGA2560.into_iter().find(|l| l.id.number() == n)
    }

    /// The 16-bit registers' low-byte addresses.
    fn wide(&self) -> impl Iterator<Item = u16> + '_ {
        let ocr = self.ocr.iter().map(|&(_, a)| a);
        std::iter::once(self.tcnt).chain(self.icr).chain(ocr)
    }

    /// The high byte of a 16-bit register (written to TEMP).
    pub fn is_high_byte(&self, addr: u16) -> bool {
        self.sixteen_bit && self.wide().any(|a| a + 1 == addr)
    }

    pub fn write_addresses(&self) -> Vec<u16> {
        let mut v = vec![self.tccra, self.tccrb, self.timsk];
        v.extend(self.tccrc);
        v.extend(self.assr);
        for a in self.wide() {
            v.push(a);
            if self.sixteen_bit {
                v.push(a + 1);
            }
        }
        v
    }

    pub fn owns_write(&self, addr: u16) -> bool {
        let width = if self.sixteen_bit { 2 } else { 1 };
        addr == self.tccra
            || addr == self.tccrb
            || addr == self.timsk
            || self.tccrc == Some(addr)
            || self.assr == Some(addr)
            || self.wide().any(|a| addr >= a && addr < a + width)
    }

    /// The counter's bytes and the interrupt flags.
    pub fn read_addresses(&self) -> Vec<u16> {
        let mut v = vec![self.tcnt];
        if self.sixteen_bit {
            v.push(self.tcnt + 1);
        }
        v.push(self.tifr);
        v
    }
}
