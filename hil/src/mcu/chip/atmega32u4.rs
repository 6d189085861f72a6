//! The ATmega32U4, on the Arduino Leonardo and Pololu's Romi, Zumo and
//! 3pi+ 32U4 boards (ATmega16U4/32U4 datasheet; the Arduino core's
//! `variants/leonardo/pins_arduino.h`): its pins (section 10.3 "Alternate
//! Port Functions"), vectors (table 9-1), ports and timers (register
//! summary). Its 10-bit high-speed timer 4 is not emulated.

use super::{AnalogPins, Chip, ExtInt, Mcu, PcintGroup, Port, PwmSource, Usart, UsbDevice};
use crate::mcu::pwm::layout::Layout;

const fn oc(timer: u8, channel: char) -> PwmSource {
    PwmSource { timer, channel }
}

#[rustfmt::skip]
pub static ATMEGA32U4: Chip = Chip {
    mcu: Mcu::Atmega32u4,
    name: "atmega32u4",
    simavr_core: "atmega32u4",
    arch: object::elf::EF_AVR_ARCH_AVR5,
    arch_name: "avr5",
    flash_bytes: 32 * 1024,
    sram: (0x100, 0xAFF),
    pc_bytes: 2,
    variant: "leonardo",
    ports: &[
        Port { letter: 'B', pin: 0x23, bits: 0xFF },
        Port { letter: 'C', pin: 0x26, bits: 0xC0 },
        Port { letter: 'D', pin: 0x29, bits: 0xFF },
        Port { letter: 'E', pin: 0x2C, bits: 0x44 },
        Port { letter: 'F', pin: 0x2F, bits: 0xF3 },
    ],
    // D24-D29 name D4, D6, D8, D9, D10, D12 again (as A6-A11); PE2 (HWB)
    // has no number.
    arduino: &[
        ('D', 2), // D0  RXD1 INT2
        ('D', 3), // D1  TXD1 INT3
        ('D', 1), // D2  SDA INT1
        ('D', 0), // D3  OC0B SCL INT0
        ('D', 4), // D4  ICP1 ADC8
        ('C', 6), // D5  OC3A
        ('D', 7), // D6  OC4D T0 ADC10
        ('E', 6), // D7  INT6 AIN0
        ('B', 4), // D8  ADC11 PCINT4
        ('B', 5), // D9  OC1A ADC12 PCINT5
        ('B', 6), // D10 OC1B OC4B ADC13 PCINT6
        ('B', 7), // D11 OC0A OC1C PCINT7
        ('D', 6), // D12 T1 ADC9
        ('C', 7), // D13 OC4A ICP3
        ('B', 3), // D14 MISO PCINT3
        ('B', 1), // D15 SCK PCINT1
        ('B', 2), // D16 MOSI PCINT2
        ('B', 0), // D17 SS PCINT0 (RX LED)
        ('F', 7), ('F', 6), ('F', 5), ('F', 4), ('F', 1), ('F', 0), // D18-D23 = A0-A5
        ('D', 4), ('D', 7), ('B', 4), ('B', 5), ('B', 6), ('D', 6), // D24-D29 = A6-A11
        ('D', 5), // D30 XCK1 (TX LED)
    ],
    analog: AnalogPins {
        first: 18,
        channels: &[7, 6, 5, 4, 1, 0, 8, 10, 11, 12, 13, 9],
    },
    // PB6 carries OC1B and OC4B, PB7 OC0A and OC1C; the core's analogWrite
    // uses the first. Timer 4's inverted outputs are left out.
    oc: &[
        (('B', 5), &[oc(1, 'A')]),
        (('B', 6), &[oc(1, 'B'), oc(4, 'B')]),
        (('B', 7), &[oc(0, 'A'), oc(1, 'C')]),
        (('C', 6), &[oc(3, 'A')]),
        (('C', 7), &[oc(4, 'A')]),
        (('D', 0), &[oc(0, 'B')]),
        (('D', 7), &[oc(4, 'D')]),
    ],
    ext_int: &[
        ExtInt { n: 0, pin: ('D', 0), vector: 1 },
        ExtInt { n: 1, pin: ('D', 1), vector: 2 },
        ExtInt { n: 2, pin: ('D', 2), vector: 3 },
        ExtInt { n: 3, pin: ('D', 3), vector: 4 },
        ExtInt { n: 6, pin: ('E', 6), vector: 7 },
    ],
    pcint: &[PcintGroup {
        group: 0,
        vector: 9,
        pins: &[('B', 0), ('B', 1), ('B', 2), ('B', 3), ('B', 4), ('B', 5), ('B', 6), ('B', 7)],
    }],
    // ICP3 PC7; ICP1 PD4, XCK1 PD5, T1 PD6, T0 PD7.
    other_triggers: &[('C', 0x80), ('D', 0xF0)],
    comparator: &[('E', 6)],
    usarts: &[Usart { n: 1, rxd: ('D', 2), txd: ('D', 3) }],
    adc: &[
        (('F', 0), 0), (('F', 1), 1), (('F', 4), 4), (('F', 5), 5), (('F', 6), 6), (('F', 7), 7),
        (('D', 4), 8), (('D', 6), 9), (('D', 7), 10), (('B', 4), 11), (('B', 5), 12), (('B', 6), 13),
    ],
    // Vectors 5, 6, 8 and 13-15 are reserved.
    vectors: &[
        "RESET", "INT0", "INT1", "INT2", "INT3", "reserved", "reserved", "INT6", "reserved",
        "PCINT0", "USB_GEN", "USB_COM", "WDT", "reserved", "reserved", "reserved",
        "TIMER1_CAPT", "TIMER1_COMPA", "TIMER1_COMPB", "TIMER1_COMPC", "TIMER1_OVF",
        "TIMER0_COMPA", "TIMER0_COMPB", "TIMER0_OVF", "SPI_STC", "USART1_RX", "USART1_UDRE",
        "USART1_TX", "ANALOG_COMP", "ADC", "EE_READY", "TIMER3_CAPT", "TIMER3_COMPA",
        "TIMER3_COMPB", "TIMER3_COMPC", "TIMER3_OVF", "TWI", "SPM_READY", "TIMER4_COMPA",
        "TIMER4_COMPB", "TIMER4_COMPD", "TIMER4_OVF", "TIMER4_FPF",
    ],
    timers: &[Layout::TIMER0, Layout::TIMER1, Layout::TIMER3],
    unemulated_timers: &[(
        4,
        "the atmega32u4's timer 4 (10-bit, high speed) is not emulated (simavr lacks it too)",
    )],
    // USBCON at 0xD8 (datasheet 21.13, avr-libc's iom32u4.h); USB_GEN is vector 10.
    usb: Some(UsbDevice { usbcon: 0xD8, general_vector: 10 }),
};
