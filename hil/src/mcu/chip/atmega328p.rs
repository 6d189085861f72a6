//! The ATmega328P, on the Arduino Uno and Nano (ATmega48A/PA/88A/PA/168A/PA/
//! 328/P datasheet; the Arduino core's `variants/standard/pins_arduino.h`):
//! its pins (section 14.3 "Alternate Port Functions"), vectors (table
//! 12-6), ports and timers (register summary). Every pin is on a pin-change
//! interrupt.

use super::{AnalogPins, Chip, ExtInt, Mcu, PcintGroup, Port, PwmSource, Usart};
use crate::mcu::pwm::layout::Layout;

const fn oc(timer: u8, channel: char) -> PwmSource {
    PwmSource { timer, channel }
}

#[rustfmt::skip]
pub static ATMEGA328P: Chip = Chip {
    mcu: Mcu::Atmega328p,
    name: "atmega328p",
    simavr_core: "atmega328p",
    arch: object::elf::EF_AVR_ARCH_AVR5,
    arch_name: "avr5",
    flash_bytes: 32 * 1024,
    sram: (0x100, 0x8FF),
    pc_bytes: 2,
    variant: "standard",
    // PC6 is RESET on the Uno (fuse); PB6/PB7 the crystal.
    ports: &[
        Port { letter: 'B', pin: 0x23, bits: 0xFF },
        Port { letter: 'C', pin: 0x26, bits: 0x7F },
        Port { letter: 'D', pin: 0x29, bits: 0xFF },
    ],
    // D0-D7 PD0-7, D8-D13 PB0-5, D14-D19 (A0-A5) PC0-5.
    arduino: &[
        ('D', 0), // D0  RXD PCINT16
        ('D', 1), // D1  TXD PCINT17
        ('D', 2), // D2  INT0 PCINT18
        ('D', 3), // D3  OC2B INT1 PCINT19
        ('D', 4), // D4  T0 XCK PCINT20
        ('D', 5), // D5  OC0B T1 PCINT21
        ('D', 6), // D6  OC0A AIN0 PCINT22
        ('D', 7), // D7  AIN1 PCINT23
        ('B', 0), // D8  ICP1 PCINT0
        ('B', 1), // D9  OC1A PCINT1
        ('B', 2), // D10 OC1B SS PCINT2
        ('B', 3), // D11 OC2A MOSI PCINT3
        ('B', 4), // D12 MISO PCINT4
        ('B', 5), // D13 SCK PCINT5
        ('C', 0), ('C', 1), ('C', 2), ('C', 3), ('C', 4), ('C', 5), // A0-A5 ADC0-5 PCINT8-13
    ],
    analog: AnalogPins {
        first: 14,
        channels: &[0, 1, 2, 3, 4, 5],
    },
    oc: &[
        (('D', 6), &[oc(0, 'A')]),
        (('D', 5), &[oc(0, 'B')]),
        (('B', 1), &[oc(1, 'A')]),
        (('B', 2), &[oc(1, 'B')]),
        (('B', 3), &[oc(2, 'A')]),
        (('D', 3), &[oc(2, 'B')]),
    ],
    ext_int: &[
        ExtInt { n: 0, pin: ('D', 2), vector: 1 },
        ExtInt { n: 1, pin: ('D', 3), vector: 2 },
    ],
    pcint: &[
        PcintGroup {
            group: 0,
            vector: 3,
            pins: &[('B', 0), ('B', 1), ('B', 2), ('B', 3), ('B', 4), ('B', 5), ('B', 6), ('B', 7)],
        },
        PcintGroup {
            group: 1,
            vector: 4,
            pins: &[('C', 0), ('C', 1), ('C', 2), ('C', 3), ('C', 4), ('C', 5), ('C', 6)],
        },
        PcintGroup {
            group: 2,
            vector: 5,
            pins: &[('D', 0), ('D', 1), ('D', 2), ('D', 3), ('D', 4), ('D', 5), ('D', 6), ('D', 7)],
        },
    ],
    // Every other trigger (T0, T1, ICP1, XCK, SPI, TWI) is on a PCINT pin.
    other_triggers: &[],
    comparator: &[('D', 6), ('D', 7)],
    usarts: &[Usart { n: 0, rxd: ('D', 0), txd: ('D', 1) }],
    adc: &[
        (('C', 0), 0), (('C', 1), 1), (('C', 2), 2),
        (('C', 3), 3), (('C', 4), 4), (('C', 5), 5),
    ],
    // avr-libc names the one USART's vectors USART_*.
    vectors: &[
        "RESET", "INT0", "INT1", "PCINT0", "PCINT1", "PCINT2", "WDT", "TIMER2_COMPA",
        "TIMER2_COMPB", "TIMER2_OVF", "TIMER1_CAPT", "TIMER1_COMPA", "TIMER1_COMPB",
        "TIMER1_OVF", "TIMER0_COMPA", "TIMER0_COMPB", "TIMER0_OVF", "SPI_STC", "USART_RX",
        "USART_UDRE", "USART_TX", "ADC", "EE_READY", "ANALOG_COMP", "TWI", "SPM_READY",
    ],
    timers: &[Layout::TIMER0, Layout::TIMER1_AB, Layout::TIMER2],
    unemulated_timers: &[],
    usb: None,
};
