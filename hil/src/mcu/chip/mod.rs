//! The MCUs the bench emulates, each described once as data: what avr-gcc
//! and simavr call it, its memory, its ports and their registers, every pin
//! with its Arduino number and what it can do besides GPIO (timer
//! output-compare channel, external or pin-change interrupt, USART line, ADC
//! channel), its interrupt vectors and its timers' register blocks.
//!
//! One file per MCU; adding an MCU is adding a file and a [`Mcu`] variant.
//! Everything that differs between MCUs is read from here: the board's pin
//! names (`crate::board`), the ELF's MCU (`crate::firmware::elf`), the
//! simavr core and the timers, pins and USARTs the bench wires
//! (`crate::bench`).
//!
//! | file | what |
//! |---|---|
//! | `mod.rs` | [`Mcu`], [`Chip`] and the lookups every MCU shares |
//! | `atmega2560.rs` | the Arduino Mega's MCU (`variants/mega`) |
//! | `atmega328p.rs` | the Arduino Uno's and Nano's MCU (`variants/standard`) |
//! | `atmega32u4.rs` | the Leonardo's and Pololu's 32U4 boards' MCU (`variants/leonardo`) |

mod atmega2560;
mod atmega328p;
mod atmega32u4;
#[cfg(test)]
mod tests;

use super::pwm::layout::Layout;

pub use self::atmega2560::ATMEGA2560;
pub use self::atmega328p::ATMEGA328P;
pub use self::atmega32u4::ATMEGA32U4;

/// An MCU the bench has a description of.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub enum Mcu {
    /// The Arduino Mega 2560's, and the bench's own firmware's.
    #[default]
    Atmega2560,
    /// The Arduino Uno's and Nano's.
    Atmega328p,
    /// The Arduino Leonardo's and Pololu's Romi/Zumo/3pi+ 32U4 boards'.
    Atmega32u4,
}

impl Mcu {
    /// Every described MCU.
    pub const ALL: [Mcu; 3] = [Mcu::Atmega2560, Mcu::Atmega328p, Mcu::Atmega32u4];

    /// Its description.
    pub fn chip(self) -> &'static Chip {
        match self {
            Mcu::Atmega2560 => &ATMEGA2560,
            Mcu::Atmega328p => &ATMEGA328P,
            Mcu::Atmega32u4 => &ATMEGA32U4,
        }
    }

    /// avr-gcc's name for it (`-mmcu`), as ELF files and board files give it.
    pub fn name(self) -> &'static str {
        self.chip().name
    }

    /// The MCU avr-gcc calls `name` (any case), if described.
    pub fn named(name: &str) -> Option<Mcu> {
        Mcu::ALL
            .into_iter()
            .find(|m| m.name().eq_ignore_ascii_case(name))
    }

    /// "atmega2560, atmega328p, atmega32u4": what an error offers.
    pub fn names() -> String {
        Mcu::ALL.map(Mcu::name).join(", ")
    }
}

impl std::fmt::Display for Mcu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl serde::Serialize for Mcu {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

/// A pin by port letter and bit.
pub type PortBit = (char, u8);

/// A timer's output-compare channel: which timer drives a pin with PWM.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct PwmSource {
    /// The timer's number.
    pub timer: u8,
    /// Channel 'A', 'B', 'C' (or 'D' on the 32U4's timer 4).
    pub channel: char,
}

impl std::fmt::Display for PwmSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "OC{}{}", self.timer, self.channel)
    }
}

/// Which USART line a pin is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UartLine {
    Rxd(u8),
    Txd(u8),
}

/// An IO port: its letter, its PINx address (data space; DDRx and PORTx
/// follow at +1 and +2 on every AVR described here) and which of its 8 bits
/// are pins (a mask).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Port {
    pub letter: char,
    pub pin: u16,
    pub bits: u8,
}

/// External interrupt INTn: its pin and vector.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ExtInt {
    pub n: u8,
    pub pin: PortBit,
    pub vector: u8,
}

/// A pin-change interrupt group (PCINTn for n in 8 group .. 8 group + 7):
/// its vector and its pins in PCINT order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PcintGroup {
    pub group: u8,
    pub vector: u8,
    pub pins: &'static [PortBit],
}

/// A USART: its number and its RXD and TXD pins.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Usart {
    pub n: u8,
    pub rxd: PortBit,
    pub txd: PortBit,
}

/// The Arduino core's analog pins: A`n` is digital pin `first` + n, and
/// reads ADC channel `channels[n]` (`analogPinToChannel`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AnalogPins {
    pub first: u8,
    pub channels: &'static [u8],
}

/// One MCU, as data.
#[derive(Debug)]
pub struct Chip {
    pub mcu: Mcu,
    /// avr-gcc's `-mmcu` name, the one ELF notes carry.
    pub name: &'static str,
    /// simavr's core name (`avr_make_mcu_by_name`).
    pub simavr_core: &'static str,
    /// The AVR architecture in the ELF header's `e_flags` (`EF_AVR_ARCH_*`).
    pub arch: u32,
    /// Its name, as binutils says it ("avr6").
    pub arch_name: &'static str,
    pub flash_bytes: u32,
    /// Internal SRAM, first and last data-space address.
    pub sram: (u16, u16),
    /// Bytes of a return address on the stack: 3 with a 22-bit PC (over
    /// 128 KB of flash), else 2.
    pub pc_bytes: u8,
    /// The Arduino core's variant whose `pins_arduino.h` numbers its pins.
    pub variant: &'static str,
    pub ports: &'static [Port],
    /// Port and bit of each Arduino digital pin, by number.
    pub arduino: &'static [PortBit],
    pub analog: AnalogPins,
    /// Output-compare channels by pin; a pin's first is the one the Arduino
    /// core's `analogWrite` uses.
    pub oc: &'static [(PortBit, &'static [PwmSource])],
    pub ext_int: &'static [ExtInt],
    pub pcint: &'static [PcintGroup],
    /// Pins whose level change can start something by itself besides INTn
    /// and PCINTn (input capture, counter and clock inputs, USART clock,
    /// SPI, TWI), by port: a mask of bits.
    pub other_triggers: &'static [(char, u8)],
    /// The analog comparator's inputs.
    pub comparator: &'static [PortBit],
    pub usarts: &'static [Usart],
    /// ADC channels by pin.
    pub adc: &'static [(PortBit, u8)],
    /// Interrupt vector names by number (datasheet's reset and interrupt
    /// vectors table; avr-libc's `*_vect` without the suffix).
    pub vectors: &'static [&'static str],
    /// The timers the bench models, in timer order.
    pub timers: &'static [Layout],
    /// Timers the MCU has and the bench does not emulate, with why.
    pub unemulated_timers: &'static [(u8, &'static str)],
    /// Its USB device controller, if it has one.
    pub usb: Option<UsbDevice>,
}

/// A USB device controller (the 32U4's): where its registers start and
/// its general interrupt (the start of frame's).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct UsbDevice {
    /// USBCON's data-space address; the others follow at fixed offsets.
    pub usbcon: u16,
    /// USB_GEN's vector.
    pub general_vector: u8,
}

impl Chip {
    /// Arduino digital pin `n`.
    pub fn arduino_pin(&self, n: u8) -> Option<PortBit> {
        self.arduino.get(usize::from(n)).copied()
    }

    /// The Arduino number of the pin at `port`/`bit` (the lowest, where the
    /// core names a pin twice, as the Leonardo's A6-A11).
    pub fn arduino_number(&self, pin: PortBit) -> Option<u8> {
        self.arduino.iter().position(|&p| p == pin).map(|n| n as u8)
    }

    /// A pin as reports and errors name it: "D7" by its Arduino number,
    /// "PE2" by port and bit where it has none.
    pub fn pin_name(&self, pin: PortBit) -> String {
        match self.arduino_number(pin) {
            Some(n) => format!("D{n}"),
            None => format!("P{}{}", pin.0, pin.1),
        }
    }

    /// The highest Arduino digital pin number.
    pub fn last_arduino_pin(&self) -> u8 {
        self.arduino.len() as u8 - 1
    }

    /// Digital pin number of analog pin A`n`.
    pub fn analog_pin(&self, n: u8) -> Option<u8> {
        (usize::from(n) < self.analog.channels.len()).then(|| self.analog.first + n)
    }

    pub fn port(&self, letter: char) -> Option<&Port> {
        self.ports.iter().find(|p| p.letter == letter)
    }

    /// Whether the MCU has pin `bit` of port `letter`.
    pub fn has_pin(&self, (letter, bit): PortBit) -> bool {
        bit < 8 && self.port(letter).is_some_and(|p| p.bits & (1 << bit) != 0)
    }

    pub fn pwm_sources(&self, pin: PortBit) -> &'static [PwmSource] {
        self.oc
            .iter()
            .find(|(p, _)| *p == pin)
            .map_or(&[], |(_, s)| s)
    }

    pub fn external_interrupt(&self, pin: PortBit) -> Option<&ExtInt> {
        self.ext_int.iter().find(|e| e.pin == pin)
    }

    /// PCINTn on the pin, with its group.
    pub fn pin_change_interrupt(&self, pin: PortBit) -> Option<(u8, &PcintGroup)> {
        self.pcint.iter().find_map(|g| {
            let i = g.pins.iter().position(|&p| p == pin)?;
            Some((g.group * 8 + i as u8, g))
        })
    }

    /// The vector a level change on the pin requests when the firmware
    /// enables it: its INTn's, else its pin-change group's.
    pub fn interrupt_vector(&self, pin: PortBit) -> Option<u8> {
        self.external_interrupt(pin)
            .map(|e| e.vector)
            .or_else(|| self.pin_change_interrupt(pin).map(|(_, g)| g.vector))
    }

    /// Whether a level change on the pin can start something by itself,
    /// however the firmware configures it (INTn, PCINTn, or one of
    /// [`Chip::other_triggers`]); the comparator's inputs are apart.
    pub fn can_interrupt(&self, pin: PortBit) -> bool {
        self.interrupt_vector(pin).is_some()
            || self
                .other_triggers
                .iter()
                .any(|&(l, mask)| l == pin.0 && mask & (1 << pin.1) != 0)
    }

    pub fn is_comparator_input(&self, pin: PortBit) -> bool {
        self.comparator.contains(&pin)
    }

    pub fn usart(&self, n: u8) -> Option<&Usart> {
        self.usarts.iter().find(|u| u.n == n)
    }

    /// "0-3", "0", "1": the USART numbers, as errors offer them.
    pub fn usart_range(&self) -> String {
        let first = self.usarts.first().map_or(0, |u| u.n);
        let last = self.usarts.last().map_or(0, |u| u.n);
        if first == last {
            format!("{first}")
        } else {
            format!("{first}-{last}")
        }
    }

    pub fn uart_line(&self, pin: PortBit) -> Option<UartLine> {
        self.usarts.iter().find_map(|u| {
            if u.rxd == pin {
                Some(UartLine::Rxd(u.n))
            } else if u.txd == pin {
                Some(UartLine::Txd(u.n))
            } else {
                None
            }
        })
    }

    pub fn adc_channel(&self, pin: PortBit) -> Option<u8> {
        self.adc.iter().find(|(p, _)| *p == pin).map(|&(_, c)| c)
    }

    /// The pin of ADC channel `n`.
    pub fn adc_pin(&self, n: u8) -> Option<PortBit> {
        self.adc.iter().find(|(_, c)| *c == n).map(|&(p, _)| p)
    }

    /// The ADC channels, as errors offer them ("0-15").
    pub fn adc_channels(&self) -> String {
        let mut c: Vec<u8> = self.adc.iter().map(|&(_, c)| c).collect();
        c.sort_unstable();
        ranges(&c)
    }

    /// Timer `n`'s register block, if the bench models it.
    pub fn timer(&self, n: u8) -> Option<Layout> {
        self.timers.iter().copied().find(|l| l.id.number() == n)
    }

    /// Why timer `n` is not emulated, if the MCU has it and the bench not.
    pub fn unemulated_timer(&self, n: u8) -> Option<&'static str> {
        self.unemulated_timers
            .iter()
            .find(|(t, _)| *t == n)
            .map(|&(_, why)| why)
    }

    /// Vector `n`'s name.
    pub fn vector_name(&self, n: u8) -> Option<&'static str> {
        self.vectors.get(usize::from(n)).copied()
    }

    /// Bytes of flash per interrupt vector slot: a two-word `jmp` on a
    /// device with more than 8 KB of flash, else a one-word `rjmp`.
    pub fn vector_slot_bytes(&self) -> u32 {
        if self.flash_bytes > 8 * 1024 {
            4
        } else {
            2
        }
    }

    /// The flash byte address of vector `n`'s slot.
    pub fn vector_address(&self, n: u8) -> u32 {
        u32::from(n) * self.vector_slot_bytes()
    }

    /// Cycles from an interrupt request to the vector's first instruction,
    /// the CPU awake: the response pushes the PC, a cycle per byte, and
    /// fetches the vector. Five with a 3-byte PC (ATmega2560 datasheet
    /// §7.8.1), four with a 2-byte one (ATmega328P §6.7.1, ATmega32U4
    /// §4.8.1).
    pub fn response_cycles(&self) -> u64 {
        u64::from(self.pc_bytes) + 2
    }

    /// Cycles the response takes longer when it wakes the CPU from sleep
    /// (idle, whose start-up time is none): as many again, five on the
    /// ATmega2560, four on the ATmega328P and ATmega32U4 (the same
    /// sections).
    pub fn wake_up_cycles(&self) -> u64 {
        self.response_cycles()
    }

    /// SRAM's data-space addresses, as a range.
    pub fn sram_range(&self) -> std::ops::Range<u16> {
        self.sram.0..self.sram.1 + 1
    }

    /// The PWM pins by Arduino number with their timers, as errors offer
    /// them: "D5 D6 (timer 0), D9 D10 (timer 1), ...".
    pub fn pwm_pins(&self) -> String {
        let mut timers: Vec<u8> = self.timers.iter().map(|l| l.id.number()).collect();
        timers.sort_unstable();
        let per_timer = timers.iter().filter_map(|&t| {
            let mut pins: Vec<u8> = self
                .oc
                .iter()
                .filter(|(_, s)| s.first().is_some_and(|s| s.timer == t))
                .filter_map(|(p, _)| self.arduino_number(*p))
                .collect();
            pins.sort_unstable();
            (!pins.is_empty()).then(|| {
                let names: Vec<String> = pins.iter().map(|n| format!("D{n}")).collect();
                format!("{} (timer {t})", names.join(" "))
            })
        });
        per_timer.collect::<Vec<_>>().join(", ")
    }

    /// The interrupt-capable pins by Arduino number: "D2 D3 (INT), D8-D13
    /// ... (PCINT)".
    pub fn interrupt_pins(&self) -> String {
        let named = |pins: &mut dyn Iterator<Item = PortBit>| {
            let mut n: Vec<u8> = pins.filter_map(|p| self.arduino_number(p)).collect();
            n.sort_unstable();
            n.dedup();
            n.iter()
                .map(|n| format!("D{n}"))
                .collect::<Vec<_>>()
                .join(" ")
        };
        let ints = named(&mut self.ext_int.iter().map(|e| e.pin));
        let pcints = named(&mut self.pcint.iter().flat_map(|g| g.pins.iter().copied()));
        format!("{ints} (INT), {pcints} (PCINT)")
    }
}

/// "0-5 8-13": sorted numbers as ranges.
fn ranges(v: &[u8]) -> String {
    let mut out: Vec<String> = Vec::new();
    let mut i = 0;
    while i < v.len() {
        let mut j = i;
        while j + 1 < v.len() && v[j + 1] == v[j] + 1 {
            j += 1;
        }
        out.push(if i == j {
            v[i].to_string()
        } else {
            format!("{}-{}", v[i], v[j])
        });
        i = j + 1;
    }
    out.join(" ")
}
