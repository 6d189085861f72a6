//! The Arduino Mega 2560's digital pins on the ATmega2560: for each Arduino
//! number its port, bit and the timer compare output on it, and the registers
//! of the ports and of the PWM timers by name (data-space addresses, from the
//! datasheet's register summary).
//!
//! The pin order and the timer channels are the Arduino AVR core's Mega
//! variant (`variants/mega/pins_arduino.h`): D54-D69 are A0-A15. Where a pin
//! carries two compare outputs (D13: OC0A and OC1C) the table keeps the one
//! `analogWrite` uses, as the variant does. This is a plain table, so the host
//! tests check it (below) and the run-time motor driver
//! ([`crate::driver`]) reads it.

/// An I/O port of the ATmega2560 (there is no port I).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[repr(u8)]
pub enum Port {
    /// Port A.
    A,
    /// Port B.
    B,
    /// Port C.
    C,
    /// Port D.
    D,
    /// Port E.
    E,
    /// Port F.
    F,
    /// Port G.
    G,
    /// Port H.
    H,
    /// Port J.
    J,
    /// Port K.
    K,
    /// Port L.
    L,
}

impl Port {
    /// Data-space address of PINx; DDRx and PORTx follow it.
    pub const fn pin_reg(self) -> u16 {
        match self {
            Port::A => PINA,
            Port::B => PINB,
            Port::C => PINC,
            Port::D => PIND,
            Port::E => PINE,
            Port::F => PINF,
            Port::G => PING,
            Port::H => PINH,
            Port::J => PINJ,
            Port::K => PINK,
            Port::L => PINL,
        }
    }

    /// Data-space address of DDRx.
    pub const fn ddr_reg(self) -> u16 {
        self.pin_reg() + 1
    }

    /// Data-space address of PORTx.
    pub const fn port_reg(self) -> u16 {
        self.pin_reg() + 2
    }
}

/// PINA. Ports A-G are in the I/O space (data space 0x20 + I/O address) ...
pub const PINA: u16 = 0x20;
/// PINB.
pub const PINB: u16 = 0x23;
/// PINC.
pub const PINC: u16 = 0x26;
/// PIND.
pub const PIND: u16 = 0x29;
/// PINE.
pub const PINE: u16 = 0x2C;
/// PINF.
pub const PINF: u16 = 0x2F;
/// PING.
pub const PING: u16 = 0x32;
/// PINH. ... ports H-L in the extended I/O space.
pub const PINH: u16 = 0x100;
/// PINJ.
pub const PINJ: u16 = 0x103;
/// PINK.
pub const PINK: u16 = 0x106;
/// PINL.
pub const PINL: u16 = 0x109;

/// A timer's compare output channel.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Channel {
    /// OCnA.
    A,
    /// OCnB.
    B,
    /// OCnC (16-bit timers 1, 3, 4, 5 only).
    C,
}

impl Channel {
    /// The channel's COMnx1 bit in TCCRnA (A: 7, B: 5, C: 3, on every timer).
    pub const fn com1(self) -> u8 {
        match self {
            Channel::A => 1 << 7,
            Channel::B => 1 << 5,
            Channel::C => 1 << 3,
        }
    }

    /// Index 0, 1, 2 for A, B, C.
    pub const fn index(self) -> usize {
        match self {
            Channel::A => 0,
            Channel::B => 1,
            Channel::C => 2,
        }
    }
}

/// A timer compare output: timer 0-5 and its channel.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Oc {
    /// Timer number, 0-5.
    pub timer: u8,
    /// The channel.
    pub channel: Channel,
}

/// One Arduino Mega pin.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct MegaPin {
    /// Its port.
    pub port: Port,
    /// Its bit in the port, 0-7.
    pub bit: u8,
    /// The compare output `analogWrite` drives it with, if any.
    pub oc: Option<Oc>,
}

impl MegaPin {
    /// The pin's bit mask in PINx, DDRx and PORTx.
    pub const fn mask(&self) -> u8 {
        1 << self.bit
    }
}

/// Pins D0-D69 (`NUM_DIGITAL_PINS`).
pub const COUNT: u8 = 70;

/// The pin of Arduino number `n`, if the Mega has one.
pub fn pin(n: u8) -> Option<MegaPin> {
    let i = n as usize;
    if i >= PINS.len() {
        return None;
    }
    let b = read_packed(i);
    let t = read_packed(PINS.len() + i);
    let port = PORTS[(b >> 3) as usize & 15];
    let oc = if b & 0x80 != 0 { Some(Oc { timer: t >> 2, channel: CHANNELS[(t & 3) as usize] }) } else { None };
    Some(MegaPin { port, bit: b & 7, oc })
}

/// Port by its index in [`Port`] (the unused indices never occur).
const PORTS: [Port; 16] = [
    Port::A,
    Port::B,
    Port::C,
    Port::D,
    Port::E,
    Port::F,
    Port::G,
    Port::H,
    Port::J,
    Port::K,
    Port::L,
    Port::A,
    Port::A,
    Port::A,
    Port::A,
    Port::A,
];
/// Channel by its [`Channel::index`].
const CHANNELS: [Channel; 4] = [Channel::A, Channel::B, Channel::C, Channel::A];

/// [`PINS`] packed two bytes a pin, so that the table can stay in flash
/// (a `const` array indexed at run time would be copied to the 8 KiB of
/// RAM): bytes 0..70 `has_oc << 7 | port << 3 | bit`, bytes 70..140
/// `timer << 2 | channel`.
#[cfg_attr(target_arch = "avr", link_section = ".progmem.data")]
static PACKED: [u8; 2 * COUNT as usize] = pack();

const fn pack() -> [u8; 2 * COUNT as usize] {
    let mut out = [0u8; 2 * COUNT as usize];
    let mut i = 0;
    while i < PINS.len() {
        let p = PINS[i];
        let port = p.port as u8;
        out[i] = port << 3 | p.bit;
        if let Some(oc) = p.oc {
            out[i] |= 0x80;
            out[PINS.len() + i] = oc.timer << 2 | oc.channel.index() as u8;
        }
        i += 1;
    }
    out
}

/// Byte `i` of [`PACKED`].
#[cfg(target_arch = "avr")]
fn read_packed(i: usize) -> u8 {
    let addr = PACKED.as_ptr().wrapping_add(i);
    let v: u8;
    // SAFETY: `PACKED` is in `.progmem.data`, which the linker puts at the
    // start of `.text`, below 64 KiB, so `lpm` through Z reads it; `i` is
    // within the array (the callers check it against `PINS.len()`).
    unsafe {
        core::arch::asm!("lpm {v}, Z", v = out(reg) v, in("Z") addr, options(pure, readonly, nostack, preserves_flags));
    }
    v
}

/// Byte `i` of [`PACKED`] (host: plain memory).
#[cfg(not(target_arch = "avr"))]
fn read_packed(i: usize) -> u8 {
    PACKED[i]
}

const fn p(port: Port, bit: u8) -> MegaPin {
    MegaPin { port, bit, oc: None }
}

const fn pwm(port: Port, bit: u8, timer: u8, channel: Channel) -> MegaPin {
    MegaPin { port, bit, oc: Some(Oc { timer, channel }) }
}

use Channel::{A as CA, B as CB, C as CC};
use Port::*;

/// The pins by Arduino number (read at run time through [`pin`]) (`digital_pin_to_port_PGM`,
/// `digital_pin_to_bit_mask_PGM`, `digital_pin_to_timer_PGM`).
pub const PINS: [MegaPin; COUNT as usize] = [
    p(E, 0),          // D0 RXD0
    p(E, 1),          // D1 TXD0
    pwm(E, 4, 3, CB), // D2
    pwm(E, 5, 3, CC), // D3
    pwm(G, 5, 0, CB), // D4
    pwm(E, 3, 3, CA), // D5
    pwm(H, 3, 4, CA), // D6
    pwm(H, 4, 4, CB), // D7
    pwm(H, 5, 4, CC), // D8
    pwm(H, 6, 2, CB), // D9
    pwm(B, 4, 2, CA), // D10
    pwm(B, 5, 1, CA), // D11
    pwm(B, 6, 1, CB), // D12
    pwm(B, 7, 0, CA), // D13 (also OC1C)
    p(J, 1),          // D14 TXD3
    p(J, 0),          // D15 RXD3
    p(H, 1),          // D16 TXD2
    p(H, 0),          // D17 RXD2
    p(D, 3),          // D18 TXD1
    p(D, 2),          // D19 RXD1
    p(D, 1),          // D20 SDA
    p(D, 0),          // D21 SCL
    p(A, 0),          // D22
    p(A, 1),          // D23
    p(A, 2),          // D24
    p(A, 3),          // D25
    p(A, 4),          // D26
    p(A, 5),          // D27
    p(A, 6),          // D28
    p(A, 7),          // D29
    p(C, 7),          // D30
    p(C, 6),          // D31
    p(C, 5),          // D32
    p(C, 4),          // D33
    p(C, 3),          // D34
    p(C, 2),          // D35
    p(C, 1),          // D36
    p(C, 0),          // D37
    p(D, 7),          // D38
    p(G, 2),          // D39
    p(G, 1),          // D40
    p(G, 0),          // D41
    p(L, 7),          // D42
    p(L, 6),          // D43
    pwm(L, 5, 5, CC), // D44
    pwm(L, 4, 5, CB), // D45
    pwm(L, 3, 5, CA), // D46
    p(L, 2),          // D47
    p(L, 1),          // D48
    p(L, 0),          // D49
    p(B, 3),          // D50 MISO
    p(B, 2),          // D51 MOSI
    p(B, 1),          // D52 SCK
    p(B, 0),          // D53 SS
    p(F, 0),          // D54 A0
    p(F, 1),          // D55 A1
    p(F, 2),          // D56 A2
    p(F, 3),          // D57 A3
    p(F, 4),          // D58 A4
    p(F, 5),          // D59 A5
    p(F, 6),          // D60 A6
    p(F, 7),          // D61 A7
    p(K, 0),          // D62 A8
    p(K, 1),          // D63 A9
    p(K, 2),          // D64 A10
    p(K, 3),          // D65 A11
    p(K, 4),          // D66 A12
    p(K, 5),          // D67 A13
    p(K, 6),          // D68 A14
    p(K, 7),          // D69 A15
];

/// The registers of one PWM timer (data-space addresses). The 16-bit
/// timers' OCRnx are the address of the low byte; the high byte follows.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct TimerRegs {
    /// TCCRnA: waveform mode low bits and the COM bits.
    pub tccra: u16,
    /// TCCRnB: clock select.
    pub tccrb: u16,
    /// OCRnA, OCRnB, OCRnC (0 where the timer has no such channel).
    pub ocr: [u16; 3],
    /// A 16-bit timer (OCR written high byte first through TEMP).
    pub wide: bool,
}

/// TCCR2A.
pub const TCCR2A: u16 = 0xB0;
/// TCCR2B.
pub const TCCR2B: u16 = 0xB1;
/// OCR2A.
pub const OCR2A: u16 = 0xB3;
/// OCR2B.
pub const OCR2B: u16 = 0xB4;
/// TCCR3A.
pub const TCCR3A: u16 = 0x90;
/// TCCR3B.
pub const TCCR3B: u16 = 0x91;
/// OCR3A (low byte).
pub const OCR3A: u16 = 0x98;
/// OCR3B (low byte).
pub const OCR3B: u16 = 0x9A;
/// OCR3C (low byte).
pub const OCR3C: u16 = 0x9C;
/// TCCR4A.
pub const TCCR4A: u16 = 0xA0;
/// TCCR4B.
pub const TCCR4B: u16 = 0xA1;
/// OCR4A (low byte).
pub const OCR4A: u16 = 0xA8;
/// OCR4B (low byte).
pub const OCR4B: u16 = 0xAA;
/// OCR4C (low byte).
pub const OCR4C: u16 = 0xAC;
/// TCCR5A.
pub const TCCR5A: u16 = 0x120;
/// TCCR5B.
pub const TCCR5B: u16 = 0x121;
/// OCR5A (low byte).
pub const OCR5A: u16 = 0x128;
/// OCR5B (low byte).
pub const OCR5B: u16 = 0x12A;
/// OCR5C (low byte).
pub const OCR5C: u16 = 0x12C;

/// The registers of PWM timer 2, 3, 4 or 5; `None` for timers 0 and 1,
/// which the firmware keeps for itself (timer 1 is the robust build's clock).
pub const fn pwm_timer(timer: u8) -> Option<TimerRegs> {
    match timer {
        2 => Some(TimerRegs { tccra: TCCR2A, tccrb: TCCR2B, ocr: [OCR2A, OCR2B, 0], wide: false }),
        3 => Some(TimerRegs { tccra: TCCR3A, tccrb: TCCR3B, ocr: [OCR3A, OCR3B, OCR3C], wide: true }),
        4 => Some(TimerRegs { tccra: TCCR4A, tccrb: TCCR4B, ocr: [OCR4A, OCR4B, OCR4C], wide: true }),
        5 => Some(TimerRegs { tccra: TCCR5A, tccrb: TCCR5B, ocr: [OCR5A, OCR5B, OCR5C], wide: true }),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    extern crate std;

    use super::*;
    use std::string::String;
    use std::vec::Vec;

    /// The Mega variant's three tables, written out from
    /// `variants/mega/pins_arduino.h` (Arduino AVR core 1.8.x): port letter,
    /// bit, and the `TIMERnx` name or `-` for `NOT_ON_TIMER`, by Arduino
    /// number.
    const VARIANT: &str = "\
        E0- E1- E4 3B E5 3C G5 0B E3 3A H3 4A H4 4B H5 4C H6 2B B4 2A B5 1A B6 1B B7 0A \
        J1- J0- H1- H0- D3- D2- D1- D0- \
        A0- A1- A2- A3- A4- A5- A6- A7- \
        C7- C6- C5- C4- C3- C2- C1- C0- D7- G2- G1- G0- \
        L7- L6- L5 5C L4 5B L3 5A L2- L1- L0- B3- B2- B1- B0- \
        F0- F1- F2- F3- F4- F5- F6- F7- K0- K1- K2- K3- K4- K5- K6- K7-";

    /// A pin as the variant file and the table give it: port, bit, timer and channel.
    type Row = (char, u8, Option<(u8, char)>);

    fn variant_rows() -> Vec<Row> {
        let mut rows = Vec::new();
        let words: Vec<&str> = VARIANT.split_whitespace().collect();
        let mut i = 0;
        while i < words.len() {
            let w: Vec<char> = words[i].chars().collect();
            let port = w[0];
            let bit = w[1].to_digit(10).unwrap() as u8;
            if w.len() == 3 {
                rows.push((port, bit, None));
                i += 1;
            } else {
                let t: Vec<char> = words[i + 1].chars().collect();
                rows.push((port, bit, Some((t[0].to_digit(10).unwrap() as u8, t[1]))));
                i += 2;
            }
        }
        rows
    }

    fn port_letter(p: Port) -> char {
        std::format!("{p:?}").chars().next().unwrap()
    }

    fn channel_letter(c: Channel) -> char {
        std::format!("{c:?}").chars().next().unwrap()
    }

    fn table_rows() -> Vec<Row> {
        PINS.iter().map(|m| (port_letter(m.port), m.bit, m.oc.map(|o| (o.timer, channel_letter(o.channel))))).collect()
    }

    #[test]
    fn the_packed_table_reads_back_every_pin() {
        for (n, want) in PINS.iter().enumerate() {
            assert_eq!(pin(n as u8).as_ref(), Some(want), "D{n}");
        }
        assert_eq!(pin(COUNT), None);
        assert_eq!(pin(255), None);
    }

    #[test]
    fn every_pin_matches_the_mega_variant() {
        let v = variant_rows();
        assert_eq!(v.len(), COUNT as usize);
        for (n, (t, v)) in table_rows().iter().zip(v.iter()).enumerate() {
            assert_eq!(t, v, "D{n}");
        }
    }

    /// Where the Arduino core is installed (Debian's `arduino-core-avr`),
    /// the table also matches the header itself, line by line.
    #[test]
    fn every_pin_matches_the_installed_header() {
        let path = "/usr/share/arduino/hardware/arduino/avr/variants/mega/pins_arduino.h";
        let Ok(text) = std::fs::read_to_string(path) else { return };
        let table = |name: &str| -> Vec<String> {
            let start = text.find(&std::format!("{name}[] = {{")).expect(name);
            let body = &text[start..];
            let body = &body[..body.find("};").unwrap()];
            body.lines()
                .filter_map(|l| l.split_once(','))
                .filter(|(v, c)| c.contains("**") && !v.contains('='))
                .map(|(v, _)| v.trim().replace(' ', ""))
                .collect()
        };
        let ports = table("digital_pin_to_port_PGM");
        let bits = table("digital_pin_to_bit_mask_PGM");
        let timers = table("digital_pin_to_timer_PGM");
        assert_eq!(ports.len(), COUNT as usize);
        for (n, m) in PINS.iter().enumerate() {
            assert_eq!(ports[n], std::format!("P{}", port_letter(m.port)), "D{n} port");
            assert_eq!(bits[n], std::format!("_BV({})", m.bit), "D{n} bit");
            let t = m.oc.map_or(String::from("NOT_ON_TIMER"), |o| {
                std::format!("TIMER{}{}", o.timer, channel_letter(o.channel))
            });
            assert_eq!(timers[n], t, "D{n} timer");
        }
    }

    /// The addresses, written out from the datasheet's register summary
    /// (ATmega640/1280/2560, "Register Summary": I/O addresses + 0x20 for
    /// ports A-G, extended I/O for H-L and the timers).
    #[test]
    fn registers_match_the_datasheet() {
        let ports = [
            (Port::A, 0x20, 0x21, 0x22),
            (Port::B, 0x23, 0x24, 0x25),
            (Port::C, 0x26, 0x27, 0x28),
            (Port::D, 0x29, 0x2A, 0x2B),
            (Port::E, 0x2C, 0x2D, 0x2E),
            (Port::F, 0x2F, 0x30, 0x31),
            (Port::G, 0x32, 0x33, 0x34),
            (Port::H, 0x100, 0x101, 0x102),
            (Port::J, 0x103, 0x104, 0x105),
            (Port::K, 0x106, 0x107, 0x108),
            (Port::L, 0x109, 0x10A, 0x10B),
        ];
        for (p, pin, ddr, port) in ports {
            assert_eq!((p.pin_reg(), p.ddr_reg(), p.port_reg()), (pin, ddr, port), "{p:?}");
        }
        let timers = [
            (2, 0xB0, 0xB1, [0xB3, 0xB4, 0], false),
            (3, 0x90, 0x91, [0x98, 0x9A, 0x9C], true),
            (4, 0xA0, 0xA1, [0xA8, 0xAA, 0xAC], true),
            (5, 0x120, 0x121, [0x128, 0x12A, 0x12C], true),
        ];
        for (t, tccra, tccrb, ocr, wide) in timers {
            assert_eq!(pwm_timer(t), Some(TimerRegs { tccra, tccrb, ocr, wide }), "timer {t}");
        }
        assert_eq!(pwm_timer(0), None);
        assert_eq!(pwm_timer(1), None);
        assert_eq!([Channel::A.com1(), Channel::B.com1(), Channel::C.com1()], [0x80, 0x20, 0x08]);
    }

    /// avr-libc's header for the chip (installed with the AVR toolchain) names
    /// the same addresses.
    #[test]
    fn registers_match_avr_libc() {
        let Ok(text) = std::fs::read_to_string("/usr/lib/avr/include/avr/iom2560.h") else { return };
        let addr = |name: &str| -> u16 {
            let line = text
                .lines()
                .find(|l| l.starts_with(&std::format!("#define {name} ")))
                .unwrap_or_else(|| panic!("{name} in iom2560.h"));
            let (kind, rest) = line.split_once('(').unwrap();
            let hex = rest.trim_end_matches(')').trim();
            let v = u16::from_str_radix(hex.trim_start_matches("0X").trim_start_matches("0x"), 16).unwrap();
            if kind.contains("_SFR_IO") {
                v + 0x20
            } else {
                v
            }
        };
        for p in [Port::A, Port::B, Port::C, Port::D, Port::E, Port::F, Port::G, Port::H, Port::J, Port::K, Port::L] {
            let l = port_letter(p);
            assert_eq!(p.pin_reg(), addr(&std::format!("PIN{l}")), "PIN{l}");
            assert_eq!(p.ddr_reg(), addr(&std::format!("DDR{l}")), "DDR{l}");
            assert_eq!(p.port_reg(), addr(&std::format!("PORT{l}")), "PORT{l}");
        }
        for t in 2..=5u8 {
            let r = pwm_timer(t).unwrap();
            assert_eq!(r.tccra, addr(&std::format!("TCCR{t}A")));
            assert_eq!(r.tccrb, addr(&std::format!("TCCR{t}B")));
            for (i, c) in ['A', 'B', 'C'].iter().enumerate() {
                if t == 2 && *c == 'C' {
                    continue;
                }
                let name = if t == 2 { std::format!("OCR{t}{c}") } else { std::format!("OCR{t}{c}L") };
                assert_eq!(r.ocr[i], addr(&name), "{name}");
            }
        }
    }
}
