//! The timer model against the datasheet: the register blocks, mode 1 as
//! the firmware uses it, what stays refused; `tests/datasheet.rs` holds
//! every mode and prescaler to the datasheet's formulas.

mod datasheet;

use super::layout::Layout;
use super::*;
use rstest::rstest;

const F_CPU: u32 = 16_000_000;

/// The check at each write and the list the bench claims agree on every
/// data-space address.
#[test]
fn owns_write_is_the_list_of_write_addresses() {
    let emulated = (0..=5).filter_map(PwmTimer::number);
    for timer in emulated.chain(PwmTimer::mirror(0)) {
        let list = timer.write_addresses();
        for addr in 0..0x2200u16 {
            assert_eq!(
                timer.owns_write(addr),
                list.contains(&addr),
                "address {addr:#x}"
            );
        }
    }
}

/// Mode 1 at clock/1, as the firmware runs it: the counter from `start`.
fn mode1(start: u64) -> Counter {
    Counter::periodic(start, 0, 1, 255, true)
}

/// Measure frequency and duty from the edges over one second of waveform.
fn measure(ocr: u32, action: Action) -> (f64, f64) {
    let w = ChannelWave {
        counter: mode1(1234),
        ocr,
        action,
        anchor: (1234, false),
    };
    let from = 1234;
    let to = from + F_CPU as u64;
    let edges = w.edges(from, to);
    let rises: Vec<u64> = edges.iter().filter(|e| e.1).map(|e| e.0).collect();
    let hz = if rises.len() >= 2 {
        (rises.len() - 1) as f64 * F_CPU as f64 / (rises[rises.len() - 1] - rises[0]) as f64
    } else {
        0.0
    };
    // Duty by integrating the level between edges.
    let mut level = w.level(from);
    let mut t = from;
    let mut high = 0u64;
    for &(c, l) in &edges {
        if level {
            high += c - t;
        }
        t = c;
        level = l;
    }
    if level {
        high += to - t;
    }
    (hz, high as f64 / (to - from) as f64)
}

/// Datasheet: f_OCnxPCPWM = f_clk / (2 * N * TOP); duty = OCR / TOP for
/// non-inverting; OCR = 0 continuously low, OCR = TOP continuously high.
#[rstest]
#[case(0)]
#[case(1)]
#[case(64)]
#[case(128)]
#[case(170)]
#[case(254)]
#[case(255)]
fn waveform_matches_the_datasheet(#[case] ocr: u32) {
    let (hz, duty) = measure(ocr, Action::NonInverting);
    let expected_duty = ocr as f64 / 255.0;
    assert!(
        (duty - expected_duty).abs() < 1e-4,
        "OCR {ocr}: duty {duty} vs {expected_duty}"
    );
    if ocr == 0 || ocr == 255 {
        assert_eq!(hz, 0.0, "constant output has no edges");
    } else {
        let f = 16e6 / (2.0 * 1.0 * 255.0);
        assert!((hz - 31_372.55).abs() / 31_372.55 < 1e-4, "{hz}");
        assert!((hz - f).abs() / f < 1e-9, "{hz} vs {f}");
    }
    let (_, inv) = measure(ocr, Action::Inverting);
    assert!((inv - (1.0 - expected_duty)).abs() < 1e-4);
}

#[test]
fn counter_runs_up_to_top_and_back() {
    let w = mode1(0);
    assert_eq!(w.tcnt(0), 0);
    assert_eq!(w.tcnt(255), 255);
    assert_eq!(w.tcnt(256), 254);
    assert_eq!(w.tcnt(509), 1);
    assert_eq!(w.tcnt(510), 0);
    assert_eq!(w.next_entry(255, 1), 255);
    assert_eq!(w.next_entry(255, 256), 765);
}

#[test]
fn prescaler_scales_the_period() {
    let w = Counter::periodic(0, 0, 64, 255, true);
    assert!((w.frequency_hz(F_CPU) - 490.196).abs() < 1e-3); // Arduino's default
}

/// The 16-bit timers' registers (datasheet, register summary): TCCRnA,
/// TCCRnB, OCRnB low and high byte, TIMSKn.
struct Regs16 {
    tccra: u16,
    tccrb: u16,
    ocrb: u16,
    timsk: u16,
}

const REGS1: Regs16 = Regs16 {
    tccra: 0x80,
    tccrb: 0x81,
    ocrb: 0x8A,
    timsk: 0x6F,
};
const REGS3: Regs16 = Regs16 {
    tccra: 0x90,
    tccrb: 0x91,
    ocrb: 0x9A,
    timsk: 0x71,
};
const REGS4: Regs16 = Regs16 {
    tccra: 0xA0,
    tccrb: 0xA1,
    ocrb: 0xAA,
    timsk: 0x72,
};
const REGS5: Regs16 = Regs16 {
    tccra: 0x120,
    tccrb: 0x121,
    ocrb: 0x12A,
    timsk: 0x73,
};

fn started(n: u8, r: &Regs16, cycle: u64) -> PwmTimer {
    let mut t = PwmTimer::number(n).unwrap();
    t.write(r.tccra, 0b0000_0001, cycle).unwrap(); // WGMn0
    t.write(r.tccrb, 0b0000_0001, cycle).unwrap(); // CSn0
    t
}

/// Each 16-bit timer's register block, as the register summary lays it
/// out: TCCRnA/B/C, TCNTn, ICRn, OCRnA/B/C (low, high), TIMSKn; the
/// counter and TIFRn (0x38-0x3A) read.
#[rstest]
#[case::timer1(1, 0x80, 0x6F, 0x36)]
#[case::timer3(3, 0x90, 0x71, 0x38)]
#[case::timer4(4, 0xA0, 0x72, 0x39)]
#[case::timer5(5, 0x120, 0x73, 0x3A)]
fn sixteen_bit_register_blocks(
    #[case] n: u8,
    #[case] base: u16,
    #[case] timsk: u16,
    #[case] tifr: u16,
) {
    let t = PwmTimer::number(n).unwrap();
    let mut list = t.write_addresses();
    list.sort_unstable();
    let mut expected: Vec<u16> = [0, 1, 2, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13]
        .iter()
        .map(|o| base + o)
        .collect();
    expected.insert(0, timsk);
    assert_eq!(list, expected, "timer {n}");
    assert_eq!(t.read_addresses(), vec![base + 4, base + 5, tifr]);
    assert_eq!(t.id().number(), n);
}

/// Timer 0's register block (register summary: TCCR0A 0x44, TCCR0B 0x45,
/// TCNT0 0x46, OCR0A 0x47, OCR0B 0x48, TIMSK0 0x6E, TIFR0 0x35); mirrored,
/// TIMSK0 and the reads are simavr's.
#[test]
fn timer_0_register_block() {
    let t = PwmTimer::number(0).unwrap();
    let mut list = t.write_addresses();
    list.sort_unstable();
    assert_eq!(list, [0x44, 0x45, 0x46, 0x47, 0x48, 0x6E]);
    assert_eq!(t.read_addresses(), [0x46, 0x35]);
    let m = PwmTimer::mirror(0).unwrap();
    let mut list = m.write_addresses();
    list.sort_unstable();
    assert_eq!(list, [0x44, 0x45, 0x46, 0x47, 0x48]);
    assert!(m.read_addresses().is_empty());
    assert!(m.is_mirrored() && !t.is_mirrored());
}

/// An emulated timer's interrupts: the firmware's clock, refused naming
/// it; a mirrored timer's are simavr's, not the model's.
#[test]
fn interrupts_on_an_emulated_timer_are_the_firmwares_clock() {
    let l = Layout::TIMER1;
    let mut t = PwmTimer::number(1).unwrap();
    t.write(l.timsk, 0, 0).unwrap();
    let err = t.write(l.timsk, 0x02, 0).unwrap_err();
    assert_eq!(
        err,
        PwmError::FirmwareClock {
            config: t.config(),
            timsk: 0x02
        }
    );
    let text = err.to_string();
    assert!(text.contains("TIMSK1 = 0x02"), "{text}");
    assert!(text.contains("the firmware's clock"), "{text}");
    let mut m = PwmTimer::mirror(0).unwrap();
    assert!(!m.owns_write(Layout::TIMER0.timsk));
    assert_eq!(
        m.write(Layout::TIMER0.timsk, 1, 0),
        Ok(WriteEffect::default())
    );
}

#[rstest]
#[case::timer1(1, REGS1)]
#[case::timer3(3, REGS3)]
#[case::timer4(4, REGS4)]
#[case::timer5(5, REGS5)]
fn ocr_write_takes_effect_at_top_through_temp(#[case] n: u8, #[case] r: Regs16) {
    let mut t = started(n, &r, 100);
    t.write(r.tccra, 0b0010_0001, 100).unwrap(); // COMnB1 + WGMn0
    t.write(r.ocrb + 1, 0x00, 200).unwrap(); // OCRnBH -> TEMP
    let e = t.write(r.ocrb, 170, 201).unwrap(); // OCRnBL commits
    assert!(e.pending_update);
    assert_eq!(
        t.drive('B', F_CPU, 201),
        PinDrive::Pwm {
            duty: 0.0,
            hz: 16e6 / 510.0
        }
    );
    assert_eq!(t.pending_update_at(201), Some(100 + 255));
    t.apply_update(100 + 255).unwrap();
    match t.drive('B', F_CPU, 400) {
        PinDrive::Pwm { duty, .. } => assert!((duty - 170.0 / 255.0).abs() < 1e-12),
        other => panic!("{other:?}"),
    }
    assert_eq!(t.drive('A', F_CPU, 400), PinDrive::Gpio);
    assert!(t.write(r.timsk, 1, 300).is_err(), "interrupts refused");
}

/// Tables 16-9 and 17-6 (timers 0, 1, 3, 4, 5): clock selects 1-5 divide
/// by 1, 8, 64, 256, 1024 (the frequency f_clk / (2 N TOP) in mode 1);
/// 6 and 7 are the external clock on Tn,
/// unverified (judged when it can matter, `bench/timers.rs`).
#[rstest]
fn sixteen_bit_prescalers(
    #[values(0, 1, 3, 4, 5)] n: u8,
    #[values((1, 1), (2, 8), (3, 64), (4, 256), (5, 1024))] cs: (u8, u32),
) {
    let r = Layout::of(n).unwrap();
    let mut t = PwmTimer::number(n).unwrap();
    t.write(r.tccra, 0b1000_0001, 0).unwrap(); // COMnA1 + WGMn0
    t.write(r.tccrb, cs.0, 0).unwrap();
    assert_eq!(t.unverified(0), None);
    match t.drive('A', F_CPU, 0) {
        PinDrive::Pwm { hz, .. } => {
            let f = 16e6 / (2.0 * cs.1 as f64 * 255.0);
            assert!((hz - f).abs() / f < 1e-12, "timer {n} CS {}: {hz}", cs.0)
        }
        other => panic!("{other:?}"),
    }
    t.write(r.tccrb, 6, 0).unwrap();
    let err = t.unverified(0).unwrap();
    assert!(err.to_string().contains("external clock"), "{err}");
    assert!(err.to_string().contains("clock select 6"), "{err}");
}

/// Mode 13 of the 16-bit timers and timer 2's 4 and 6 are reserved:
/// unverified once clocked, not while stopped.
#[rstest]
#[case::timer0(0, 0b00, 0b1000)]
#[case::timer1(1, 0b01, 0b1_1000)]
#[case::timer2(2, 0b00, 0b1000)]
#[case::timer3(3, 0b01, 0b1_1000)]
#[case::timer5(5, 0b01, 0b1_1000)]
fn reserved_modes_are_unverified(#[case] n: u8, #[case] a: u8, #[case] b: u8) {
    let l = Layout::of(n).unwrap();
    let mut t = PwmTimer::number(n).unwrap();
    t.write(l.tccra, a, 0).unwrap();
    t.write(l.tccrb, b, 0).unwrap();
    assert_eq!(t.unverified(0), None, "stopped");
    t.write(l.tccrb, b | 1, 0).unwrap();
    let err = t.unverified(0).unwrap().to_string();
    assert!(err.contains("reserved"), "{err}");
    assert!(err.contains(&format!("timer {n}")), "{err}");
}

#[test]
fn interrupts_flags_and_running_counter_writes_are_refused() {
    let l = Layout::TIMER2;
    let mut t = PwmTimer::timer2();
    assert!(t.write(l.timsk, 1, 0).is_err());
    t.write(l.tcnt, 7, 0).unwrap(); // stopped: the counter holds it
    assert_eq!(t.read(l.tcnt, 0), Ok(7));
    t.write(l.tccrb, 1, 10).unwrap(); // normal mode, clock/1
    assert_eq!(t.read(l.tcnt, 15), Ok(12));
    assert!(t.write(l.tcnt, 0, 20).is_err(), "written while running");
    let err = t.read(l.tifr, 20).unwrap_err().to_string();
    assert!(err.contains("interrupt flags"), "{err}");
}
