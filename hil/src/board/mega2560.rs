//! The Arduino Mega 2560's pins: Arduino number -> ATmega2560 port and bit
//! (the Arduino core's `variants/mega/pins_arduino.h`,
//! `digital_pin_to_port_PGM` / `digital_pin_to_bit_mask_PGM`), and what each
//! port bit can do besides GPIO (ATmega640/1280/2560 datasheet, section 13.3
//! "Alternate Port Functions"): its timer output-compare channel, external or
//! pin-change interrupt, USART line and ADC channel.

use super::Pin;

/// Port and bit of each Arduino Mega pin, D0..D69 (A0..A15 are D54..D69).
const PORT_BIT: [(char, u8); 70] = [
    ('E', 0), // D0  RXD0
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
    ('A', 0),
    ('A', 1),
    ('A', 2),
    ('A', 3),
    ('A', 4),
    ('A', 5),
    ('A', 6),
    ('A', 7), // D22..D29
    ('C', 7),
    ('C', 6),
    ('C', 5),
    ('C', 4),
    ('C', 3),
    ('C', 2),
    ('C', 1),
    ('C', 0), // D30..D37
    ('D', 7), // D38 T0
    ('G', 2), // D39
    ('G', 1), // D40
    ('G', 0), // D41
    ('L', 7),
    ('L', 6),
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
    ('F', 0),
    ('F', 1),
    ('F', 2),
    ('F', 3),
    ('F', 4),
    ('F', 5),
    ('F', 6),
    ('F', 7), // D54..D61 = A0..A7, ADC0..7
    ('K', 0),
    ('K', 1),
    ('K', 2),
    ('K', 3),
    ('K', 4),
    ('K', 5),
    ('K', 6),
    ('K', 7), // D62..D69 = A8..A15, ADC8..15, PCINT16..23
];

/// The highest Arduino pin number of the Mega.
pub const LAST_PIN: u8 = PORT_BIT.len() as u8 - 1;

/// The first analog pin, A0 = D54.
pub const A0: u8 = 54;

/// Arduino pin `n` (D0..D69), if the Mega has it.
pub fn pin(n: u8) -> Option<Pin> {
    PORT_BIT.get(n as usize).map(|&(port, bit)| Pin {
        port,
        bit,
        arduino: n,
    })
}

/// A timer's output-compare channel: which timer drives a pin with PWM.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct PwmSource {
    /// Timer 0-5.
    pub timer: u8,
    /// Channel 'A', 'B' or 'C'.
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

impl Pin {
    /// The output-compare channels on this pin (PB7 carries both OC0A and
    /// OC1C). Datasheet table 13-6 (B), 13-15 (E), 13-21 (G), 13-24 (H),
    /// 13-30 (L).
    pub fn pwm_sources(&self) -> &'static [PwmSource] {
        macro_rules! oc {
            ($timer:literal, $channel:literal) => {
                PwmSource {
                    timer: $timer,
                    channel: $channel,
                }
            };
        }
        match (self.port, self.bit) {
            ('B', 4) => &[oc!(2, 'A')],
            ('B', 5) => &[oc!(1, 'A')],
            ('B', 6) => &[oc!(1, 'B')],
            ('B', 7) => &[oc!(0, 'A'), oc!(1, 'C')],
            ('E', 3) => &[oc!(3, 'A')],
            ('E', 4) => &[oc!(3, 'B')],
            ('E', 5) => &[oc!(3, 'C')],
            ('G', 5) => &[oc!(0, 'B')],
            ('H', 3) => &[oc!(4, 'A')],
            ('H', 4) => &[oc!(4, 'B')],
            ('H', 5) => &[oc!(4, 'C')],
            ('H', 6) => &[oc!(2, 'B')],
            ('L', 3) => &[oc!(5, 'A')],
            ('L', 4) => &[oc!(5, 'B')],
            ('L', 5) => &[oc!(5, 'C')],
            _ => &[],
        }
    }

    /// External interrupt INTn on this pin: INT0-3 on PD0-3, INT4-7 on PE4-7.
    pub fn external_interrupt(&self) -> Option<u8> {
        match (self.port, self.bit) {
            ('D', b @ 0..=3) => Some(b),
            ('E', b @ 4..=7) => Some(b),
            _ => None,
        }
    }

    /// The interrupt vector a level change on this pin requests, when the
    /// firmware enables it (datasheet table 14-1): INTn is vector n + 1;
    /// the pin-change groups PCINT0-7, PCINT8-15 and PCINT16-23 are
    /// vectors 9, 10 and 11 (PCINT0, PCINT1, PCINT2).
    pub fn interrupt_vector(&self) -> Option<u8> {
        match (self.external_interrupt(), self.pin_change_interrupt()) {
            (Some(n), _) => Some(n + 1),
            (None, Some(n)) => Some(9 + n / 8),
            (None, None) => None,
        }
    }

    /// Pin-change interrupt PCINTn on this pin: PCINT0-7 on PB0-7, PCINT8
    /// on PE0, PCINT9-15 on PJ0-6, PCINT16-23 on PK0-7.
    pub fn pin_change_interrupt(&self) -> Option<u8> {
        match (self.port, self.bit) {
            ('B', b) => Some(b),
            ('E', 0) => Some(8),
            ('J', b @ 0..=6) => Some(9 + b),
            ('K', b) => Some(16 + b),
            _ => None,
        }
    }

    /// The USART line on this pin: RXD0/TXD0 PE0/PE1, RXD1/TXD1 PD2/PD3,
    /// RXD2/TXD2 PH0/PH1, RXD3/TXD3 PJ0/PJ1.
    pub fn uart_line(&self) -> Option<UartLine> {
        match (self.port, self.bit) {
            ('E', 0) => Some(UartLine::Rxd(0)),
            ('E', 1) => Some(UartLine::Txd(0)),
            ('D', 2) => Some(UartLine::Rxd(1)),
            ('D', 3) => Some(UartLine::Txd(1)),
            ('H', 0) => Some(UartLine::Rxd(2)),
            ('H', 1) => Some(UartLine::Txd(2)),
            ('J', 0) => Some(UartLine::Rxd(3)),
            ('J', 1) => Some(UartLine::Txd(3)),
            _ => None,
        }
    }

    /// The ADC input channel on this pin: ADC0-7 on PF0-7, ADC8-15 on PK0-7.
    pub fn adc_channel(&self) -> Option<u8> {
        match (self.port, self.bit) {
            ('F', b) => Some(b),
            ('K', b) => Some(8 + b),
            _ => None,
        }
    }
}

/// The two pins of USART `n` (RXD, TXD).
pub fn uart_pins(n: u8) -> Option<[Pin; 2]> {
    let (rx, tx) = match n {
        0 => (0, 1),
        1 => (19, 18),
        2 => (17, 16),
        3 => (15, 14),
        _ => return None,
    };
    Some([pin(rx)?, pin(tx)?])
}

/// The pin of ADC channel `n` (A`n`).
pub fn adc_pin(n: u8) -> Option<Pin> {
    if n < 16 {
        pin(A0 + n)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Where the Arduino core's header is installed (Debian's `arduino-core`).
    const HEADER: &str = "/usr/share/arduino/hardware/arduino/avr/variants/mega/pins_arduino.h";

    /// The rows of one PROGMEM table of the header: its entries in order,
    /// with the comment that names the pin.
    fn header_table<'a>(text: &'a str, name: &str) -> Vec<&'a str> {
        let start = text.find(name).expect("table in the header");
        let body = &text[start..];
        let body = &body[body.find('{').unwrap() + 1..body.find("};").unwrap()];
        body.lines()
            .map(str::trim)
            .filter(|l| !l.is_empty() && !l.starts_with("//"))
            .map(|l| l.split(',').next().unwrap().trim())
            .collect()
    }

    /// The table agrees with the Arduino core's: every pin's port, bit and
    /// timer channel (the header gives one timer for PB7: TIMER0A).
    #[test]
    fn the_table_is_the_arduino_cores() {
        // ARDUINO_MEGA_PINS_H: the header elsewhere (an unpacked arduino-core).
        let path = std::env::var("ARDUINO_MEGA_PINS_H").unwrap_or_else(|_| HEADER.to_string());
        let Ok(text) = std::fs::read_to_string(&path) else {
            eprintln!("{path} not installed: the table is checked by the spot checks only");
            return;
        };
        let ports = header_table(&text, "digital_pin_to_port_PGM");
        let bits = header_table(&text, "digital_pin_to_bit_mask_PGM");
        let timers = header_table(&text, "digital_pin_to_timer_PGM");
        assert_eq!(ports.len(), PORT_BIT.len());
        for n in 0..=LAST_PIN {
            let p = pin(n).unwrap();
            assert_eq!(ports[n as usize], format!("P{}", p.port), "D{n} port");
            assert_eq!(bits[n as usize], format!("_BV( {} )", p.bit), "D{n} bit");
            let timer = p
                .pwm_sources()
                .first()
                .map_or("NOT_ON_TIMER".to_string(), |s| {
                    format!("TIMER{}{}", s.timer, s.channel)
                });
            assert_eq!(timers[n as usize], timer, "D{n} timer");
        }
    }

    /// Spot checks from the datasheet's pin-out (the header's own comments).
    #[test]
    fn known_pins() {
        let d = |n| pin(n).unwrap();
        assert_eq!((d(2).port, d(2).bit), ('E', 4));
        assert_eq!(d(2).external_interrupt(), Some(4));
        assert_eq!(d(21).external_interrupt(), Some(0));
        assert_eq!(
            d(9).pwm_sources(),
            &[PwmSource {
                timer: 2,
                channel: 'B'
            }]
        );
        assert_eq!(
            d(46).pwm_sources(),
            &[PwmSource {
                timer: 5,
                channel: 'A'
            }]
        );
        assert_eq!(d(13).pwm_sources().len(), 2);
        assert_eq!(d(10).pin_change_interrupt(), Some(4));
        assert_eq!(d(15).pin_change_interrupt(), Some(9));
        assert_eq!(d(69).pin_change_interrupt(), Some(23));
        // INT4, INT5, INT2, INT3, INT0; PCINT4, PCINT9, PCINT23; none.
        for (n, vector) in [(2, 5), (3, 6), (19, 3), (18, 4), (21, 1), (10, 9), (15, 10)] {
            assert_eq!(d(n).interrupt_vector(), Some(vector), "D{n}");
        }
        assert_eq!(d(69).interrupt_vector(), Some(11));
        assert_eq!(d(22).interrupt_vector(), None);
        assert_eq!(d(19).uart_line(), Some(UartLine::Rxd(1)));
        assert_eq!(d(54).adc_channel(), Some(0));
        assert_eq!(d(69).adc_channel(), Some(15));
        assert_eq!(adc_pin(15).unwrap().arduino, 69);
        assert!(pin(70).is_none());
        for n in 0..4 {
            let [rx, tx] = uart_pins(n).unwrap();
            assert_eq!(rx.uart_line(), Some(UartLine::Rxd(n)));
            assert_eq!(tx.uart_line(), Some(UartLine::Txd(n)));
        }
    }
}
