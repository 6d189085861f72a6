//! The ATmega2560, on the Arduino Mega 2560 (ATmega640/1280/2560 datasheet;
//! the Arduino core's `variants/mega/pins_arduino.h`): its pins (section
//! 13.3 "Alternate Port Functions"), vectors (table 14-1), ports and
//! timers (register summary).

use super::{AnalogPins, Chip, ExtInt, Mcu, PcintGroup, Port, PwmSource, Usart};
use crate::mcu::pwm::layout::Layout;

const fn oc(timer: u8, channel: char) -> PwmSource {
    PwmSource { timer, channel }
}

#[rustfmt::skip]
pub static ATMEGA2560: Chip = Chip {
    mcu: Mcu::Atmega2560,
    name: "atmega2560",
    simavr_core: "atmega2560",
    arch: object::elf::EF_AVR_ARCH_AVR6,
    arch_name: "avr6",
    flash_bytes: 256 * 1024,
    sram: (0x200, 0x21FF),
    pc_bytes: 3,
    variant: "mega",
    // Ports A-G in the low IO space, H-L in the extended IO space.
    ports: &[
        Port { letter: 'A', pin: 0x20, bits: 0xFF },
        Port { letter: 'B', pin: 0x23, bits: 0xFF },
        Port { letter: 'C', pin: 0x26, bits: 0xFF },
        Port { letter: 'D', pin: 0x29, bits: 0xFF },
        Port { letter: 'E', pin: 0x2C, bits: 0xFF },
        Port { letter: 'F', pin: 0x2F, bits: 0xFF },
        Port { letter: 'G', pin: 0x32, bits: 0x3F },
        Port { letter: 'H', pin: 0x100, bits: 0xFF },
        Port { letter: 'J', pin: 0x103, bits: 0xFF },
        Port { letter: 'K', pin: 0x106, bits: 0xFF },
        Port { letter: 'L', pin: 0x109, bits: 0xFF },
    ],
    // D0..D69 (A0..A15 are D54..D69).
    arduino: &[
        ('E', 0), // D0  RXD0 PCINT8
        ('E', 1), // D1  TXD0
        ('E', 4), // D2  OC3B INT4
        ('E', 5), // D3  OC3C INT5
        ('G', 5), // D4  OC0B
        ('E', 3), // D5  OC3A AIN1
        ('H', 3), // D6  OC4A
        ('H', 4), // D7  OC4B
        ('H', 5), // D8  OC4C
        ('H', 6), // D9  OC2B
        ('B', 4), // D10 OC2A PCINT4
        ('B', 5), // D11 OC1A PCINT5
        ('B', 6), // D12 OC1B PCINT6
        ('B', 7), // D13 OC0A/OC1C PCINT7
        ('J', 1), // D14 TXD3 PCINT10
        ('J', 0), // D15 RXD3 PCINT9
        ('H', 1), // D16 TXD2
        ('H', 0), // D17 RXD2
        ('D', 3), // D18 TXD1 INT3
        ('D', 2), // D19 RXD1 INT2
        ('D', 1), // D20 SDA INT1
        ('D', 0), // D21 SCL INT0
        ('A', 0), ('A', 1), ('A', 2), ('A', 3), ('A', 4), ('A', 5), ('A', 6), ('A', 7), // D22..D29
        ('C', 7), ('C', 6), ('C', 5), ('C', 4), ('C', 3), ('C', 2), ('C', 1), ('C', 0), // D30..D37
        ('D', 7), // D38 T0
        ('G', 2), // D39
        ('G', 1), // D40
        ('G', 0), // D41
        ('L', 7), // D42
        ('L', 6), // D43
        ('L', 5), // D44 OC5C
        ('L', 4), // D45 OC5B
        ('L', 3), // D46 OC5A
        ('L', 2), // D47 T5
        ('L', 1), // D48 ICP5
        ('L', 0), // D49 ICP4
        ('B', 3), // D50 MISO PCINT3
        ('B', 2), // D51 MOSI PCINT2
        ('B', 1), // D52 SCK PCINT1
        ('B', 0), // D53 SS PCINT0
        ('F', 0), ('F', 1), ('F', 2), ('F', 3), ('F', 4), ('F', 5), ('F', 6), ('F', 7), // A0..A7 ADC0..7
        ('K', 0), ('K', 1), ('K', 2), ('K', 3), ('K', 4), ('K', 5), ('K', 6), ('K', 7), // A8..A15 ADC8..15
    ],
    analog: AnalogPins {
        first: 54,
        channels: &[0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15],
    },
    // Tables 13-6 (B), 13-15 (E), 13-21 (G), 13-24 (H), 13-30 (L). PB7
    // carries OC0A and OC1C; the core's analogWrite uses OC0A.
    oc: &[
        (('B', 4), &[oc(2, 'A')]),
        (('B', 5), &[oc(1, 'A')]),
        (('B', 6), &[oc(1, 'B')]),
        (('B', 7), &[oc(0, 'A'), oc(1, 'C')]),
        (('E', 3), &[oc(3, 'A')]),
        (('E', 4), &[oc(3, 'B')]),
        (('E', 5), &[oc(3, 'C')]),
        (('G', 5), &[oc(0, 'B')]),
        (('H', 3), &[oc(4, 'A')]),
        (('H', 4), &[oc(4, 'B')]),
        (('H', 5), &[oc(4, 'C')]),
        (('H', 6), &[oc(2, 'B')]),
        (('L', 3), &[oc(5, 'A')]),
        (('L', 4), &[oc(5, 'B')]),
        (('L', 5), &[oc(5, 'C')]),
    ],
    // INTn is vector n + 1.
    ext_int: &[
        ExtInt { n: 0, pin: ('D', 0), vector: 1 },
        ExtInt { n: 1, pin: ('D', 1), vector: 2 },
        ExtInt { n: 2, pin: ('D', 2), vector: 3 },
        ExtInt { n: 3, pin: ('D', 3), vector: 4 },
        ExtInt { n: 4, pin: ('E', 4), vector: 5 },
        ExtInt { n: 5, pin: ('E', 5), vector: 6 },
        ExtInt { n: 6, pin: ('E', 6), vector: 7 },
        ExtInt { n: 7, pin: ('E', 7), vector: 8 },
    ],
    // PCINT0-7 on PB0-7, PCINT8 on PE0, PCINT9-15 on PJ0-6, PCINT16-23 on PK0-7.
    pcint: &[
        PcintGroup {
            group: 0,
            vector: 9,
            pins: &[('B', 0), ('B', 1), ('B', 2), ('B', 3), ('B', 4), ('B', 5), ('B', 6), ('B', 7)],
        },
        PcintGroup {
            group: 1,
            vector: 10,
            pins: &[('E', 0), ('J', 0), ('J', 1), ('J', 2), ('J', 3), ('J', 4), ('J', 5), ('J', 6)],
        },
        PcintGroup {
            group: 2,
            vector: 11,
            pins: &[('K', 0), ('K', 1), ('K', 2), ('K', 3), ('K', 4), ('K', 5), ('K', 6), ('K', 7)],
        },
    ],
    // ICP1 PD4, XCK1 PD5, T1 PD6, T0 PD7; XCK0 PE2, T3 PE6, ICP3 PE7;
    // TOSC2/1 PG3/PG4; XCK2 PH2, T4 PH7; ICP4 PL0, ICP5 PL1, T5 PL2.
    other_triggers: &[('D', 0xF0), ('E', 0xC4), ('G', 0x18), ('H', 0x84), ('L', 0x07)],
    comparator: &[('E', 2), ('E', 3)],
    usarts: &[
        Usart { n: 0, rxd: ('E', 0), txd: ('E', 1) },
        Usart { n: 1, rxd: ('D', 2), txd: ('D', 3) },
        Usart { n: 2, rxd: ('H', 0), txd: ('H', 1) },
        Usart { n: 3, rxd: ('J', 0), txd: ('J', 1) },
    ],
    adc: &[
        (('F', 0), 0), (('F', 1), 1), (('F', 2), 2), (('F', 3), 3),
        (('F', 4), 4), (('F', 5), 5), (('F', 6), 6), (('F', 7), 7),
        (('K', 0), 8), (('K', 1), 9), (('K', 2), 10), (('K', 3), 11),
        (('K', 4), 12), (('K', 5), 13), (('K', 6), 14), (('K', 7), 15),
    ],
    vectors: &[
        "RESET", "INT0", "INT1", "INT2", "INT3", "INT4", "INT5", "INT6", "INT7", "PCINT0",
        "PCINT1", "PCINT2", "WDT", "TIMER2_COMPA", "TIMER2_COMPB", "TIMER2_OVF", "TIMER1_CAPT",
        "TIMER1_COMPA", "TIMER1_COMPB", "TIMER1_COMPC", "TIMER1_OVF", "TIMER0_COMPA",
        "TIMER0_COMPB", "TIMER0_OVF", "SPI_STC", "USART0_RX", "USART0_UDRE", "USART0_TX",
        "ANALOG_COMP", "ADC", "EE_READY", "TIMER3_CAPT", "TIMER3_COMPA", "TIMER3_COMPB",
        "TIMER3_COMPC", "TIMER3_OVF", "USART1_RX", "USART1_UDRE", "USART1_TX", "TWI",
        "SPM_READY", "TIMER4_CAPT", "TIMER4_COMPA", "TIMER4_COMPB", "TIMER4_COMPC",
        "TIMER4_OVF", "TIMER5_CAPT", "TIMER5_COMPA", "TIMER5_COMPB", "TIMER5_COMPC",
        "TIMER5_OVF", "USART2_RX", "USART2_UDRE", "USART2_TX", "USART3_RX", "USART3_UDRE",
        "USART3_TX",
    ],
    timers: &[
        Layout::TIMER0,
        Layout::TIMER1,
        Layout::TIMER2,
        Layout::TIMER3,
        Layout::TIMER4,
        Layout::TIMER5,
    ],
    unemulated_timers: &[],
    usb: None,
};
