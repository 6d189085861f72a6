//! Each MCU's description against the Arduino core's `pins_arduino.h` for
//! its board, avr-libc's device header (vector numbers, register addresses)
//! and spot tables from the datasheets.

use super::*;

/// Where Debian's `arduino-core-avr` installs the variants.
const VARIANTS: &str = "/usr/share/arduino/hardware/arduino/avr/variants";
/// Where Debian's `avr-libc` installs the device headers.
const AVR_INCLUDE: &str = "/usr/lib/avr/include/avr";

/// A header's text, or None (with a line saying so) where it is not
/// installed: the spot tables below still check the description.
fn header(path: String) -> Option<String> {
    let text = std::fs::read_to_string(&path).ok();
    if text.is_none() {
        eprintln!("{path} not installed: checked by the spot tables only");
    }
    text
}

/// The entries of one PROGMEM table of a `pins_arduino.h`, in order
/// (preprocessor lines and comments left out: the ATmega8 alternatives of
/// the standard variant are `#if`ed out for these MCUs, and read as the
/// `#else` branch).
fn header_table(text: &str, name: &str) -> Vec<String> {
    let start = text.find(name).expect("table in the header");
    let body = &text[start..];
    let body = &body[body.find('{').unwrap() + 1..body.find("};").unwrap()];
    let mut out = Vec::new();
    let mut skipping = false;
    for line in body.lines().map(str::trim) {
        if line.starts_with("#if") {
            skipping = true;
            continue;
        }
        if line.starts_with("#else") || line.starts_with("#endif") {
            skipping = false;
            continue;
        }
        if skipping || line.is_empty() || line.starts_with("//") {
            continue;
        }
        let entry = line.split(',').next().unwrap();
        let entry = entry
            .split("//")
            .next()
            .unwrap()
            .split("/*")
            .next()
            .unwrap();
        out.push(entry.trim().to_string());
    }
    out
}

/// Every pin's port, bit and timer channel, and A0's number and the analog
/// channels, agree with the Arduino core's variant of the MCU's board.
#[test]
fn every_chip_is_its_arduino_variant() {
    for mcu in Mcu::ALL {
        let chip = mcu.chip();
        let Some(text) = header(format!("{VARIANTS}/{}/pins_arduino.h", chip.variant)) else {
            continue;
        };
        let ports = header_table(&text, "digital_pin_to_port_PGM[]");
        let bits = header_table(&text, "digital_pin_to_bit_mask_PGM[]");
        let timers = header_table(&text, "digital_pin_to_timer_PGM[]");
        assert_eq!(ports.len(), chip.arduino.len(), "{mcu}: pin count");
        for (n, &(port, bit)) in chip.arduino.iter().enumerate() {
            assert_eq!(ports[n], format!("P{port}"), "{mcu} D{n} port");
            assert_eq!(
                bits[n].replace(' ', ""),
                format!("_BV({bit})"),
                "{mcu} D{n} bit"
            );
            // A second number for a pin (the Leonardo's A6-A11) is on no
            // timer in the core: analogWrite goes by the first.
            if chip.arduino_number((port, bit)) != Some(n as u8) {
                continue;
            }
            let timer = chip
                .pwm_sources((port, bit))
                .first()
                .map_or("NOT_ON_TIMER".to_string(), |s| {
                    format!("TIMER{}{}", s.timer, s.channel)
                });
            assert_eq!(timers[n], timer, "{mcu} D{n} timer");
        }
        let a0 = format!("#define PIN_A0   ({})", chip.analog.first);
        assert!(text.contains(&a0), "{mcu}: {a0}");
        if text.contains("analog_pin_to_channel_PGM[] = {") {
            let channels = header_table(&text, "analog_pin_to_channel_PGM[] = {");
            let ours: Vec<String> = chip.analog.channels.iter().map(u8::to_string).collect();
            assert_eq!(channels, ours, "{mcu}: analog channels");
        }
        for (n, &c) in chip.analog.channels.iter().enumerate() {
            let pin = chip.arduino_pin(chip.analog.first + n as u8).unwrap();
            assert_eq!(chip.adc_channel(pin), Some(c), "{mcu} A{n}");
        }
    }
}

/// avr-libc's header for the MCU (the one `<avr/io.h>` picks).
fn libc_header(mcu: Mcu) -> Option<String> {
    let files: &[&str] = match mcu {
        // The family's header, and the device's own (RAMEND).
        Mcu::Atmega2560 => &["iomxx0_1.h", "iom2560.h"],
        Mcu::Atmega328p => &["iom328p.h"],
        Mcu::Atmega32u4 => &["iom32u4.h"],
    };
    let texts: Option<Vec<String>> = files
        .iter()
        .map(|f| header(format!("{AVR_INCLUDE}/{f}")))
        .collect();
    texts.map(|t| t.concat())
}

/// `#define NAME _SFR_IO8(0x03)` as (NAME, data-space address 0x23).
fn registers(text: &str) -> BTreeMap<String, u16> {
    let mut out = BTreeMap::new();
    for line in text.lines() {
        let words: Vec<&str> = line
            .trim_start_matches(['#', ' '])
            .split_whitespace()
            .collect();
        let [define, name, value, ..] = words[..] else {
            continue;
        };
        if define != "define" {
            continue;
        }
        let (offset, rest) = if let Some(r) = value.strip_prefix("_SFR_IO8(") {
            (0x20, r)
        } else if let Some(r) = value.strip_prefix("_SFR_IO16(") {
            (0x20, r)
        } else if let Some(r) = value.strip_prefix("_SFR_MEM8(") {
            (0, r)
        } else if let Some(r) = value.strip_prefix("_SFR_MEM16(") {
            (0, r)
        } else {
            continue;
        };
        let hex = rest.trim_end_matches(')').to_ascii_lowercase();
        if let Ok(a) = u16::from_str_radix(hex.trim_start_matches("0x"), 16) {
            out.insert(name.to_string(), a + offset);
        }
    }
    out
}

use std::collections::BTreeMap;

/// Vector numbers and register addresses agree with avr-libc's.
#[test]
fn vectors_and_registers_are_avr_libcs() {
    for mcu in Mcu::ALL {
        let chip = mcu.chip();
        let Some(text) = libc_header(mcu) else {
            continue;
        };
        let mut seen = 0;
        for line in text.lines() {
            let words: Vec<&str> = line
                .trim_start_matches(['#', ' '])
                .split_whitespace()
                .collect();
            if let ["define", name, v, ..] = words[..] {
                if let (Some(name), Some(n)) = (
                    name.strip_suffix("_vect"),
                    v.strip_prefix("_VECTOR(").and_then(|v| v.strip_suffix(')')),
                ) {
                    let n: u8 = n.parse().unwrap();
                    assert_eq!(chip.vector_name(n), Some(name), "{mcu} vector {n}");
                    seen = seen.max(n);
                }
            }
        }
        assert_eq!(
            usize::from(seen) + 1,
            chip.vectors.len(),
            "{mcu}: vector count"
        );
        let regs = registers(&text);
        let reg = |name: String| *regs.get(&name).unwrap_or_else(|| panic!("{mcu}: {name}"));
        for p in chip.ports {
            assert_eq!(
                p.pin,
                reg(format!("PIN{}", p.letter)),
                "{mcu} PIN{}",
                p.letter
            );
            assert_eq!(
                p.pin + 1,
                reg(format!("DDR{}", p.letter)),
                "{mcu} DDR{}",
                p.letter
            );
            assert_eq!(
                p.pin + 2,
                reg(format!("PORT{}", p.letter)),
                "{mcu} PORT{}",
                p.letter
            );
        }
        for l in chip.timers {
            let n = l.id.number();
            assert_eq!(l.tccra, reg(format!("TCCR{n}A")), "{mcu} TCCR{n}A");
            assert_eq!(l.tccrb, reg(format!("TCCR{n}B")), "{mcu} TCCR{n}B");
            assert_eq!(l.timsk, reg(format!("TIMSK{n}")), "{mcu} TIMSK{n}");
            assert_eq!(l.tifr, reg(format!("TIFR{n}")), "{mcu} TIFR{n}");
            let low = if l.sixteen_bit { "L" } else { "" };
            assert_eq!(l.tcnt, reg(format!("TCNT{n}{low}")), "{mcu} TCNT{n}");
            for &(c, a) in l.ocr {
                assert_eq!(a, reg(format!("OCR{n}{c}{low}")), "{mcu} OCR{n}{c}");
            }
            // No channel the MCU has is missing from the block.
            let next = (b'A' + l.ocr.len() as u8) as char;
            assert!(
                !regs.contains_key(&format!("OCR{n}{next}")),
                "{mcu} OCR{n}{next}"
            );
            if let Some(icr) = l.icr {
                assert_eq!(icr, reg(format!("ICR{n}L")), "{mcu} ICR{n}");
            }
            if let Some(c) = l.tccrc {
                assert_eq!(c, reg(format!("TCCR{n}C")), "{mcu} TCCR{n}C");
            }
        }
        assert_eq!(chip.sram.1, reg_end(&text), "{mcu} RAMEND");
        assert_eq!(
            chip.vectors.len() as u32 * chip.vector_slot_bytes(),
            vectors_size(&text),
            "{mcu} _VECTORS_SIZE"
        );
    }
}

/// `#define _VECTORS_SIZE 228` or `(26 * 4)`: the vector table's bytes
/// (the last definition: the device's own header comes after its family's).
fn vectors_size(text: &str) -> u32 {
    let line = text
        .lines()
        .rev()
        .find(|l| {
            l.trim_start_matches(['#', ' '])
                .starts_with("define _VECTORS_SIZE")
        })
        .expect("_VECTORS_SIZE");
    let v = line.split_once("_VECTORS_SIZE").unwrap().1;
    v.split(|c: char| !c.is_ascii_digit())
        .filter(|w| !w.is_empty())
        .map(|w| w.parse::<u32>().unwrap())
        .product()
}

/// The interrupt response, from each datasheet ("Interrupt Response
/// Time"): five cycles to the vector on the ATmega2560, whose response
/// pushes a 3-byte PC (§7.8.1), four on the ATmega328P (§6.7.1) and the
/// ATmega32U4 (§4.8.1), which push two bytes; as many more to wake from
/// sleep.
#[test]
fn the_interrupt_response_is_each_datasheets() {
    for (mcu, response) in [
        (Mcu::Atmega2560, 5),
        (Mcu::Atmega328p, 4),
        (Mcu::Atmega32u4, 4),
    ] {
        let c = mcu.chip();
        assert_eq!(c.response_cycles(), response, "{mcu}");
        assert_eq!(c.wake_up_cycles(), response, "{mcu}");
    }
}

/// `#define RAMEND 0x8FF`, or `(RAMSTART + RAMSIZE - 1)` with those.
fn reg_end(text: &str) -> u16 {
    let value = |name: &str| -> Option<String> {
        text.lines().find_map(|l| {
            let w: Vec<&str> = l.split_whitespace().collect();
            (w.len() >= 3 && w[0] == "#define" && w[1] == name).then(|| w[2].to_ascii_lowercase())
        })
    };
    let hex = |v: String| {
        let v = v.trim_matches(|c| c == '(' || c == ')');
        u16::from_str_radix(v.trim_start_matches("0x"), 16).unwrap()
    };
    match value("RAMEND").unwrap() {
        v if !v.contains("ramstart") => hex(v),
        _ => hex(value("RAMSTART").unwrap()) + hex(value("RAMSIZE").unwrap()) - 1,
    }
}

/// Every pin a function table names is a pin of the MCU, every PWM
/// channel's timer is modelled or said not to be, and INTn/PCINT vectors
/// name themselves.
#[test]
fn the_tables_agree_with_each_other() {
    for mcu in Mcu::ALL {
        let c = mcu.chip();
        let pins = c
            .arduino
            .iter()
            .copied()
            .chain(c.oc.iter().map(|(p, _)| *p))
            .chain(c.ext_int.iter().map(|e| e.pin))
            .chain(c.pcint.iter().flat_map(|g| g.pins.iter().copied()))
            .chain(c.usarts.iter().flat_map(|u| [u.rxd, u.txd]))
            .chain(c.adc.iter().map(|(p, _)| *p))
            .chain(c.comparator.iter().copied());
        for p in pins {
            assert!(c.has_pin(p), "{mcu}: P{}{}", p.0, p.1);
        }
        for (_, sources) in c.oc {
            for s in *sources {
                assert!(
                    c.timer(s.timer).is_some() != c.unemulated_timer(s.timer).is_some(),
                    "{mcu}: {s}"
                );
            }
        }
        for e in c.ext_int {
            assert_eq!(c.vectors[usize::from(e.vector)], format!("INT{}", e.n));
        }
        for g in c.pcint {
            assert_eq!(
                c.vectors[usize::from(g.vector)],
                format!("PCINT{}", g.group)
            );
        }
        for u in c.usarts {
            let rx = c.vectors.iter().any(|v| *v == format!("USART{}_RX", u.n));
            assert!(
                rx || c.usarts.len() == 1 && c.vectors.contains(&"USART_RX"),
                "{mcu}"
            );
        }
        assert_eq!(Mcu::named(&c.name.to_uppercase()), Some(mcu));
    }
}

/// The ATmega2560's pins, from its datasheet's pin-out (table 13-6 ff.)
/// and vectors (table 14-1).
#[test]
fn atmega2560_spot_table() {
    let c = &ATMEGA2560;
    let d = |n| c.arduino_pin(n).unwrap();
    assert_eq!(d(2), ('E', 4));
    assert_eq!(c.external_interrupt(d(2)).unwrap().n, 4);
    assert_eq!(c.external_interrupt(d(21)).unwrap().n, 0);
    assert_eq!(
        c.pwm_sources(d(9)),
        &[PwmSource {
            timer: 2,
            channel: 'B'
        }]
    );
    assert_eq!(
        c.pwm_sources(d(46)),
        &[PwmSource {
            timer: 5,
            channel: 'A'
        }]
    );
    assert_eq!(c.pwm_sources(d(13)).len(), 2);
    assert_eq!(c.pin_change_interrupt(d(10)).unwrap().0, 4);
    assert_eq!(c.pin_change_interrupt(d(15)).unwrap().0, 9);
    assert_eq!(c.pin_change_interrupt(d(69)).unwrap().0, 23);
    for (n, vector) in [
        (2, 5),
        (3, 6),
        (19, 3),
        (18, 4),
        (21, 1),
        (10, 9),
        (15, 10),
        (69, 11),
    ] {
        assert_eq!(c.interrupt_vector(d(n)), Some(vector), "D{n}");
    }
    assert_eq!(c.interrupt_vector(d(22)), None);
    assert!(c.can_interrupt(d(38)), "T0");
    assert!(!c.can_interrupt(d(4)), "OC0B only");
    assert!(c.is_comparator_input(d(5)), "AIN1");
    assert_eq!(c.uart_line(d(19)), Some(UartLine::Rxd(1)));
    assert_eq!(c.adc_channel(d(54)), Some(0));
    assert_eq!(c.adc_channel(d(69)), Some(15));
    assert_eq!(c.analog_pin(15), Some(69));
    assert!(c.arduino_pin(70).is_none());
    assert_eq!(c.port('G').unwrap().pin, 0x32);
    assert_eq!(c.port('L').unwrap().pin, 0x109);
    assert!(!c.has_pin(('G', 6)) && !c.has_pin(('I', 0)));
    assert_eq!(c.usart_range(), "0-3");
    assert_eq!(c.adc_channels(), "0-15");
    assert_eq!((c.pc_bytes, c.arch), (3, object::elf::EF_AVR_ARCH_AVR6));
}

/// The ATmega328P's, from its datasheet (tables 14-3 ff., vectors table
/// 12-6): the Uno's L298N enables on D5/D6 are timer 0's.
#[test]
fn atmega328p_spot_table() {
    let c = &ATMEGA328P;
    let d = |n| c.arduino_pin(n).unwrap();
    let oc = |timer, channel| PwmSource { timer, channel };
    assert_eq!(c.pwm_sources(d(5)), &[oc(0, 'B')]);
    assert_eq!(c.pwm_sources(d(6)), &[oc(0, 'A')]);
    assert_eq!(c.pwm_sources(d(9)), &[oc(1, 'A')]);
    assert_eq!(c.pwm_sources(d(10)), &[oc(1, 'B')]);
    assert_eq!(c.pwm_sources(d(11)), &[oc(2, 'A')]);
    assert_eq!(c.pwm_sources(d(3)), &[oc(2, 'B')]);
    // INT0 D2, INT1 D3; PCINT0 (B), PCINT1 (C), PCINT2 (D) vectors 3-5.
    for (n, vector) in [
        (2, 1),
        (3, 2),
        (8, 3),
        (13, 3),
        (14, 4),
        (19, 4),
        (4, 5),
        (12, 3),
    ] {
        assert_eq!(c.interrupt_vector(d(n)), Some(vector), "D{n}");
    }
    assert_eq!(c.pin_change_interrupt(d(4)).unwrap().0, 20);
    assert_eq!(c.pin_change_interrupt(d(14)).unwrap().0, 8);
    assert!(
        (0..20).all(|n| c.can_interrupt(d(n))),
        "every pin is on a PCINT"
    );
    assert_eq!(c.uart_line(d(0)), Some(UartLine::Rxd(0)));
    assert_eq!(c.uart_line(d(1)), Some(UartLine::Txd(0)));
    assert_eq!(c.usart_range(), "0");
    assert_eq!(c.analog_pin(0), Some(14));
    assert_eq!(c.analog_pin(6), None);
    assert!(c.arduino_pin(20).is_none());
    assert_eq!(c.timer(1).unwrap().ocr.len(), 2);
    assert!(c.timer(3).is_none());
    assert!(
        c.has_pin(('C', 6)) && !c.has_pin(('C', 7)),
        "PC6 (RESET) is a pin, PC7 none"
    );
    assert_eq!((c.pc_bytes, c.arch), (2, object::elf::EF_AVR_ARCH_AVR5));
    assert_eq!(c.vector_name(18), Some("USART_RX"));
    assert_eq!(
        c.pwm_pins(),
        "D5 D6 (timer 0), D9 D10 (timer 1), D3 D11 (timer 2)"
    );
}

/// The ATmega32U4's, from its datasheet (tables 10-3 ff., vectors table
/// 9-1): the Romi's encoder pins INT6 (PE6) and PCINT4 (PB4), PE2 without
/// an Arduino number, timer 4 not emulated.
#[test]
fn atmega32u4_spot_table() {
    let c = &ATMEGA32U4;
    let d = |n| c.arduino_pin(n).unwrap();
    assert_eq!(d(7), ('E', 6));
    assert_eq!(c.interrupt_vector(d(7)), Some(7), "INT6");
    assert_eq!(c.interrupt_vector(d(8)), Some(9), "PCINT4");
    assert_eq!(c.pin_change_interrupt(d(8)).unwrap().0, 4);
    for (n, vector) in [(3, 1), (2, 2), (0, 3), (1, 4)] {
        assert_eq!(c.interrupt_vector(d(n)), Some(vector), "D{n}");
    }
    assert!(
        c.has_pin(('E', 2)) && c.arduino_number(('E', 2)).is_none(),
        "HWB"
    );
    assert!(!c.can_interrupt(('E', 2)));
    assert!(!c.can_interrupt(('F', 0)), "A5: the Romi's right B");
    assert_eq!(c.arduino_number(('B', 4)), Some(8), "the first of D8/D26");
    assert_eq!(
        c.pwm_sources(d(9)),
        &[PwmSource {
            timer: 1,
            channel: 'A'
        }]
    );
    assert_eq!(
        c.pwm_sources(d(10))[0],
        PwmSource {
            timer: 1,
            channel: 'B'
        }
    );
    assert!(c.unemulated_timer(4).is_some() && c.timer(4).is_none());
    assert!(c.timer(3).is_some() && c.timer(2).is_none());
    assert_eq!(c.usart_range(), "1");
    assert_eq!(c.uart_line(d(0)), Some(UartLine::Rxd(1)));
    assert_eq!(c.adc_channel(d(18)), Some(7), "A0 is ADC7");
    assert_eq!(c.adc_channels(), "0-1 4-13");
    assert_eq!(c.vector_name(10), Some("USB_GEN"));
}
