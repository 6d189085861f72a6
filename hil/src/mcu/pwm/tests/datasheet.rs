//! Every mode of the 8-bit timers 0 and 2 (tables 16-8, 20-8) and of the
//! 16-bit timers 1, 3, 4, 5 (table 17-2), at every prescaler of their
//! tables, against the datasheet's formulas, written here independently of
//! the model:
//!
//! - fast PWM: f = f_clk / (N (1 + TOP)), non-inverting duty (OCR + 1) /
//!   (TOP + 1), a one-step spike at OCR = BOTTOM, constant at OCR = TOP;
//! - phase correct and phase and frequency correct: f = f_clk / (2 N TOP),
//!   duty OCR / TOP, constant at OCR = 0 and OCR = TOP;
//! - normal and CTC, toggling: f = f_clk / (2 N (1 + TOP)), duty 1/2 (CTC:
//!   TOP = OCRnA or ICRn; normal: TOP = MAX);
//! - TOP per mode, the counting sequence (single slope 0..TOP, 0; dual
//!   slope 0..TOP..1, 0), and when an OCR write takes effect (at TOP in
//!   phase correct, at BOTTOM in fast PWM and phase and frequency correct,
//!   at once in normal and CTC).

use super::*;

#[derive(Debug, Clone, Copy, PartialEq)]
enum Shape {
    Normal,
    Ctc,
    Fast,
    PhaseCorrect,
    PhaseFrequency,
}

#[derive(Debug, Clone, Copy)]
enum TopOf {
    Fixed(u32),
    Ocra,
    Icr,
}

/// Table 17-2, without the reserved mode 13.
const SIXTEEN_BIT: [(u8, Shape, TopOf); 15] = [
    (0, Shape::Normal, TopOf::Fixed(0xFFFF)),
    (1, Shape::PhaseCorrect, TopOf::Fixed(0xFF)),
    (2, Shape::PhaseCorrect, TopOf::Fixed(0x1FF)),
    (3, Shape::PhaseCorrect, TopOf::Fixed(0x3FF)),
    (4, Shape::Ctc, TopOf::Ocra),
    (5, Shape::Fast, TopOf::Fixed(0xFF)),
    (6, Shape::Fast, TopOf::Fixed(0x1FF)),
    (7, Shape::Fast, TopOf::Fixed(0x3FF)),
    (8, Shape::PhaseFrequency, TopOf::Icr),
    (9, Shape::PhaseFrequency, TopOf::Ocra),
    (10, Shape::PhaseCorrect, TopOf::Icr),
    (11, Shape::PhaseCorrect, TopOf::Ocra),
    (12, Shape::Ctc, TopOf::Icr),
    (14, Shape::Fast, TopOf::Icr),
    (15, Shape::Fast, TopOf::Ocra),
];

/// Tables 16-8 (timer 0) and 20-8 (timer 2), alike, without the reserved
/// modes 4 and 6.
const EIGHT_BIT: [(u8, Shape, TopOf); 6] = [
    (0, Shape::Normal, TopOf::Fixed(0xFF)),
    (1, Shape::PhaseCorrect, TopOf::Fixed(0xFF)),
    (2, Shape::Ctc, TopOf::Ocra),
    (3, Shape::Fast, TopOf::Fixed(0xFF)),
    (5, Shape::PhaseCorrect, TopOf::Ocra),
    (7, Shape::Fast, TopOf::Ocra),
];

/// Tables 16-9 and 17-6 (timers 0, 1, 3, 4, 5) and 20-9 (timer 2): (clock
/// select, N).
const PRESCALERS_SHARED: [(u8, u32); 5] = [(1, 1), (2, 8), (3, 64), (4, 256), (5, 1024)];
const PRESCALERS_2: [(u8, u32); 7] = [
    (1, 1),
    (2, 8),
    (3, 32),
    (4, 64),
    (5, 128),
    (6, 256),
    (7, 1024),
];

/// A variable TOP (OCRnA or ICRn) for the table.
fn variable_top(n: u8) -> u32 {
    if matches!(n, 0 | 2) {
        199
    } else {
        999
    }
}

/// Write a 16-bit (or timer 2's 8-bit) register as firmware does: high
/// byte to TEMP first.
fn write16(t: &mut PwmTimer, l: &Layout, addr: u16, v: u32, cycle: u64) {
    if l.sixteen_bit {
        t.write(addr + 1, (v >> 8) as u8, cycle).unwrap();
    }
    t.write(addr, v as u8, cycle).unwrap();
}

/// Timer `n` in mode `wgm` with clock select `cs` from cycle 0, channel
/// B's COM bits `com` at compare value `ocrb`, TOP registers at `top`.
fn configured(n: u8, wgm: u8, cs: u8, com: u8, ocrb: u32, top: u32) -> PwmTimer {
    let l = Layout::of(n).unwrap();
    let mut t = PwmTimer::number(n).unwrap();
    // In mode 0 OCR writes reach the compare unit at once.
    write16(&mut t, &l, l.ocr[0].1, top, 0);
    write16(&mut t, &l, l.ocr[1].1, ocrb, 0);
    let b = (wgm >> 2) << 3;
    t.write(l.tccra, com << 4 | (wgm & 0b11), 0).unwrap();
    t.write(l.tccrb, b, 0).unwrap();
    if let Some(icr) = l.icr {
        write16(&mut t, &l, icr, top, 0);
    }
    t.write(l.tccrb, b | cs, 0).unwrap();
    t
}

fn top_value(n: u8, top: TopOf) -> u32 {
    match top {
        TopOf::Fixed(t) => t,
        TopOf::Ocra | TopOf::Icr => variable_top(n),
    }
}

/// (frequency, duty) of an output by the datasheet's formulas; frequency
/// 0 for a constant one.
fn datasheet(shape: Shape, top: u32, n: u32, com: u8, ocr: u32) -> (f64, f64) {
    let f_clk = F_CPU as f64;
    let (n, top_f) = (n as f64, top as f64);
    let (f, duty) = match shape {
        Shape::Fast if ocr >= top => (0.0, 1.0),
        Shape::Fast => (
            f_clk / (n * (1.0 + top_f)),
            (ocr as f64 + 1.0) / (top_f + 1.0),
        ),
        Shape::PhaseCorrect | Shape::PhaseFrequency if ocr == 0 => (0.0, 0.0),
        Shape::PhaseCorrect | Shape::PhaseFrequency if ocr >= top => (0.0, 1.0),
        Shape::PhaseCorrect | Shape::PhaseFrequency => {
            (f_clk / (2.0 * n * top_f), ocr as f64 / top_f)
        }
        Shape::Normal | Shape::Ctc => return (f_clk / (2.0 * n * (1.0 + top_f)), 0.5),
    };
    if com == 3 {
        (f, 1.0 - duty)
    } else {
        (f, duty)
    }
}

/// (frequency, duty) of channel B measured from the model's edges over
/// `periods` of the counter, from a cycle inside a period (so that the
/// level there counts as much as the edges).
fn measured(t: &PwmTimer, periods: u64) -> (f64, f64) {
    measured_channel(t, 'B', periods)
}

/// [`measured`], of channel `ch`.
fn measured_channel(t: &PwmTimer, ch: char, periods: u64) -> (f64, f64) {
    let w = t.waveform(ch).expect("running");
    let from = w.counter.period_cycles() * 5 / 7 + 3;
    let to = from + periods * w.counter.period_cycles();
    let edges = w.edges(from, to);
    let rises: Vec<u64> = edges.iter().filter(|e| e.1).map(|e| e.0).collect();
    let f = if rises.len() >= 2 {
        (rises.len() - 1) as f64 * F_CPU as f64 / (rises[rises.len() - 1] - rises[0]) as f64
    } else {
        0.0
    };
    // The edges are where the level changes.
    for &(c, l) in &edges {
        assert_eq!(w.level(c), l, "level after the edge at {c}");
        assert_eq!(w.level(c - 1), !l, "level before the edge at {c}");
    }
    let (mut level, mut at, mut high) = (w.level(from), from, 0);
    for &(c, l) in &edges {
        if level {
            high += c - at;
        }
        (at, level) = (c, l);
    }
    if level {
        high += to - at;
    }
    (f, high as f64 / (to - from) as f64)
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * b.abs().max(1e-9)
}

/// Every (timer, mode, prescaler) of the tables.
fn every_case() -> Vec<(u8, u8, Shape, TopOf, u8, u32)> {
    let mut v = Vec::new();
    for n in 0..=5u8 {
        let (modes, prescalers): (&[_], &[_]) = match n {
            0 => (&EIGHT_BIT, &PRESCALERS_SHARED),
            2 => (&EIGHT_BIT, &PRESCALERS_2),
            _ => (&SIXTEEN_BIT, &PRESCALERS_SHARED),
        };
        for &(wgm, shape, top) in modes {
            for &(cs, div) in prescalers {
                v.push((n, wgm, shape, top, cs, div));
            }
        }
    }
    v
}

/// Frequency and duty of every mode and prescaler, at the extreme and
/// some middle compare values, non-inverting and inverting (toggling in
/// normal and CTC).
#[test]
fn frequency_and_duty_follow_the_datasheet() {
    let mut failures = Vec::new();
    let mut checked = 0;
    for (n, wgm, shape, top, cs, div) in every_case() {
        let top = top_value(n, top);
        let pwm = !matches!(shape, Shape::Normal | Shape::Ctc);
        let coms: &[u8] = if pwm { &[2, 3] } else { &[1] };
        for &com in coms {
            for ocr in [0, 1, top / 3, top - 1, top] {
                let t = configured(n, wgm, cs, com, ocr, top);
                let got = measured(&t, 4);
                if div == 1 && top <= 0x3FF {
                    // The level step by step, over two periods.
                    let w = t.waveform('B').unwrap();
                    let steps = 2 * w.counter.period_steps();
                    let high = (0..steps).filter(|&k| w.level(k)).count();
                    let duty = high as f64 / steps as f64;
                    if !close(duty, datasheet(shape, top, div, com, ocr).1) {
                        failures.push(format!(
                            "timer {n} mode {wgm} COM {com} OCR {ocr}: level high {duty} of the steps"
                        ));
                    }
                }
                let want = datasheet(shape, top, div, com, ocr);
                checked += 1;
                if !close(got.0, want.0) || !close(got.1, want.1) {
                    failures.push(format!(
                        "timer {n} mode {wgm} N {div} COM {com} OCR {ocr}: got {got:?}, datasheet {want:?}"
                    ));
                }
                // What the bridge gives the plant agrees.
                if let PinDrive::Pwm { duty, .. } = t.drive('B', F_CPU, 0) {
                    if !close(duty, want.1) {
                        failures.push(format!(
                            "timer {n} mode {wgm} N {div} COM {com} OCR {ocr}: drive duty {duty}, datasheet {}",
                            want.1
                        ));
                    }
                }
            }
        }
    }
    assert!(checked > 1000, "{checked}");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// TOP per mode and the counting sequence: single slope 0, 1, ..., TOP,
/// 0; dual slope 0, ..., TOP, TOP - 1, ..., 1, 0; read as firmware reads
/// it (the low byte latches the high into TEMP).
#[test]
fn counter_sequence_and_top_per_mode() {
    for (n, wgm, shape, top, cs, div) in every_case() {
        let top = top_value(n, top);
        let mut t = configured(n, wgm, cs, 0, 0, top);
        let l = Layout::of(n).unwrap();
        let step = div as u64;
        let mut read = |steps: u64| {
            let cycle = steps * step;
            let low = t.read(l.tcnt, cycle).unwrap() as u32;
            let high = if l.sixteen_bit {
                t.read(l.tcnt + 1, cycle + 1).unwrap() as u32
            } else {
                0
            };
            high << 8 | low
        };
        let ctx = format!("timer {n} mode {wgm} N {div}");
        assert_eq!(read(0), 0, "{ctx}");
        assert_eq!(read(1), 1, "{ctx}");
        assert_eq!(read(top as u64), top, "{ctx}");
        if matches!(shape, Shape::PhaseCorrect | Shape::PhaseFrequency) {
            assert_eq!(read(top as u64 + 1), top - 1, "{ctx}");
            assert_eq!(read(2 * top as u64 - 1), 1, "{ctx}");
            assert_eq!(read(2 * top as u64), 0, "{ctx}");
        } else {
            assert_eq!(read(top as u64 + 1), 0, "{ctx}");
            assert_eq!(read(top as u64 + 2), 1, "{ctx}");
        }
    }
}

/// An OCR write takes effect at TOP (phase correct), at BOTTOM (fast PWM,
/// phase and frequency correct), at once (normal, CTC).
#[test]
fn ocr_buffering_point_per_mode() {
    for (n, wgm, shape, top, cs, div) in every_case() {
        let top = top_value(n, top);
        let l = Layout::of(n).unwrap();
        let mut t = configured(n, wgm, cs, 2, top / 3, top);
        let step = div as u64;
        // Half way up the first slope.
        let at = (top as u64 / 2) * step + 1;
        write16(&mut t, &l, l.ocr[1].1, top / 2, at);
        let ctx = format!("timer {n} mode {wgm} N {div}");
        let expected = match shape {
            Shape::Normal | Shape::Ctc => None,
            Shape::PhaseCorrect => Some(top as u64 * step),
            Shape::Fast => Some((top as u64 + 1) * step),
            Shape::PhaseFrequency => Some(2 * top as u64 * step),
        };
        assert_eq!(t.pending_update_at(at), expected, "{ctx}");
        let ocr_now = t.waveform('B').unwrap().ocr;
        match expected {
            None => assert_eq!(ocr_now, top / 2, "{ctx}: at once"),
            Some(update) => {
                assert_eq!(ocr_now, top / 3, "{ctx}: buffered");
                t.apply_update(update).unwrap();
                assert_eq!(t.waveform('B').unwrap().ocr, top / 2, "{ctx}");
            }
        }
    }
}

/// COM = 1 in the PWM modes: OCnA toggles where the datasheet says
/// (16-bit: modes 8-11, 14, 15; timers 0 and 2: WGMn2 set), every other
/// channel is disconnected.
#[test]
fn com_1_in_pwm_modes() {
    for (n, wgm, shape, _, _, _) in every_case() {
        if matches!(shape, Shape::Normal | Shape::Ctc) {
            continue;
        }
        let eight_bit = matches!(n, 0 | 2);
        let mode = Mode::decode(wgm, !eight_bit).unwrap();
        let toggles = if eight_bit {
            wgm & 0b100 != 0
        } else {
            matches!(wgm, 8..=11 | 14 | 15)
        };
        let a = if toggles {
            Action::Toggle
        } else {
            Action::Disconnected
        };
        assert_eq!(mode.action(0, 1), a, "timer {n} mode {wgm}");
        assert_eq!(mode.action(1, 1), Action::Disconnected);
        assert_eq!(mode.action(1, 2), Action::NonInverting);
        assert_eq!(mode.action(1, 3), Action::Inverting);
    }
}

/// Non-PWM set and clear: the output changes at the first match and
/// stays; the bench schedules that match.
#[test]
fn set_and_clear_latch_at_the_first_match() {
    let l = Layout::TIMER3;
    for (com, level) in [(3u8, true), (2, false)] {
        // CTC, TOP 999, OCR3B 100, clock/8; the output starts opposite.
        let mut t = configured(3, 4, 2, 0, 100, 999);
        if !level {
            t.write(l.tccra, 3 << 4, 0).unwrap(); // set first
            t.apply_update(t.pending_update_at(0).unwrap()).unwrap();
        }
        t.write(l.tccra, com << 4, 5000 * 8).unwrap();
        let first = t.pending_update_at(5000 * 8).unwrap();
        // Step 5000 is BOTTOM; the match acts at the step after TCNT = 100.
        assert_eq!(first, (5000 + 101) * 8, "COM {com}");
        assert_eq!(t.waveform('B').unwrap().level(first - 1), !level);
        assert_eq!(t.waveform('B').unwrap().level(first), level);
        t.apply_update(first).unwrap();
        assert_eq!(t.pending_update_at(first), None);
    }
}

/// A TOP written below the counter: it counts on to MAX and wraps (the
/// sketch pattern TCCRnB = mode 14 before ICRn); written above it again,
/// the counting goes on.
#[test]
fn top_below_the_counter_runs_to_max() {
    let l = Layout::TIMER4;
    let mut t = PwmTimer::timer4();
    t.write(l.tccra, 0b1000_0010, 0).unwrap(); // COM4A1, WGM41
    t.write(l.tccrb, 0b0000_0001, 0).unwrap(); // mode 2, clock/1
    t.write(l.tccrb, 0b0001_1001, 300).unwrap(); // mode 14, ICR4 = 0
    assert_eq!(t.unverified(300), None, "OCR4A in use (0) is not met");
    assert_eq!(t.tcnt(310), 310);
    assert_eq!(t.tcnt(300 + 65535 - 299), 0, "wrapped at MAX");
    write16(&mut t, &l, 0xA6, 639, 320);
    assert_eq!(t.tcnt(320 + 319), 639);
    assert_eq!(t.tcnt(320 + 320), 0, "TOP 639 from now on");
}

/// Pololu's motor PWM (its Romi/Zumo 32U4 motor libraries, as written):
/// TCCR1A = 0xA0 (COM1A1, COM1B1), TCCR1B = 0x11 (WGM13, CS10): mode 8,
/// phase and frequency correct with TOP = ICR1, no prescaler; then ICR1 =
/// 400 with the timer running. f = 16 MHz / (2 * 1 * 400) = 20 kHz; duty
/// OCR1A / 400, a new OCR1A taking effect at BOTTOM.
#[test]
fn pololu_20_khz_on_timer_1() {
    let l = Layout::TIMER1;
    let mut t = PwmTimer::number(1).unwrap();
    t.write(l.tccra, 0xA0, 100).unwrap();
    t.write(l.tccrb, 0x11, 101).unwrap();
    let config = t.config();
    assert_eq!((config.wgm, config.cs), (8, 1));
    assert_eq!(
        config.mode.map(|m| m.name()).as_deref(),
        Some("phase- and frequency-correct PWM, TOP ICRn")
    );
    write16(&mut t, &l, 0x86, 400, 102); // ICR1
    write16(&mut t, &l, 0x88, 0, 104); // OCR1A
    write16(&mut t, &l, 0x8A, 0, 106); // OCR1B
    let set_at = 5_000;
    for (ocr, at) in [(300u32, set_at), (57, set_at + 100_000)] {
        write16(&mut t, &l, 0x88, ocr, at);
        let bottom = t.pending_update_at(at + 1).expect("buffered to BOTTOM");
        // BOTTOM: the counter (from 0 at cycle 102, when ICR1's low byte
        // set TOP; TOP 0 held it at 0 before) at a multiple of 800 steps.
        assert_eq!((bottom - 102) % 800, 0, "OCR1A {ocr}: update at {bottom}");
        assert!(bottom > at && bottom <= at + 800);
        assert_eq!(t.tcnt(bottom), 0);
        t.apply_update(bottom).unwrap();
        match t.drive('A', F_CPU, bottom) {
            PinDrive::Pwm { duty, hz } => {
                assert_eq!(hz, 20_000.0, "OCR1A {ocr}");
                assert_eq!(duty, ocr as f64 / 400.0, "OCR1A {ocr}");
            }
            other => panic!("{other:?}"),
        }
        let (hz, duty) = measured_channel(&t, 'A', 10);
        assert!(close(hz, 20_000.0), "edges: {hz} Hz");
        assert!(close(duty, ocr as f64 / 400.0), "edges: duty {duty}");
    }
    assert_eq!(
        t.drive('B', F_CPU, set_at),
        PinDrive::Pwm {
            duty: 0.0,
            hz: 20_000.0
        }
    );
}

/// The Arduino core on timer 0, the `millis()` timer: `init()` sets WGM01,
/// WGM00 in TCCR0A (mode 3, fast PWM, 8-bit) and CS01, CS00 in TCCR0B
/// (clock/64), one bit at a time; `analogWrite(pin, v)` sets COM0x1 and
/// OCR0x = v. f = 16 MHz / (64 * 256) = 976.5625 Hz, duty (v + 1) / 256, on
/// the mirrored timer as the bench runs it.
#[test]
fn arduino_analog_write_on_timer_0() {
    let l = Layout::TIMER0;
    for (ch, com1, ocr) in [('A', 0x80u8, 0x47u16), ('B', 0x20, 0x48)] {
        for v in [1u8, 64, 128, 191, 254] {
            let mut t = PwmTimer::mirror(0).unwrap();
            let mut tccra = 0;
            for bit in [0x02, 0x01] {
                tccra |= bit;
                t.write(l.tccra, tccra, 10).unwrap();
            }
            t.write(l.tccrb, 0x02, 12).unwrap();
            t.write(l.tccrb, 0x03, 14).unwrap();
            assert_eq!(t.config().wgm, 3);
            t.write(l.tccra, tccra | com1, 5_000).unwrap();
            t.write(ocr, v, 5_002).unwrap();
            let bottom = t.pending_update_at(5_002).unwrap();
            assert_eq!((bottom - 14) % (64 * 256), 0, "at BOTTOM");
            t.apply_update(bottom).unwrap();
            let ctx = format!("OC0{ch} = {v}");
            let want = (v as f64 + 1.0) / 256.0;
            match t.drive(ch, F_CPU, bottom) {
                PinDrive::Pwm { duty, hz } => {
                    assert_eq!(hz, 976.5625, "{ctx}");
                    assert_eq!(duty, want, "{ctx}");
                }
                other => panic!("{ctx}: {other:?}"),
            }
            let (hz, duty) = measured_channel(&t, ch, 6);
            assert!(close(hz, 976.5625), "{ctx}: edges {hz} Hz");
            assert!(close(duty, want), "{ctx}: edges duty {duty}");
        }
    }
}
