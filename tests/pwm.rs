//! The PWM the firmware really produces, as the bench's waveform model sees
//! it: timers 2 and 4 at 31 372.55 Hz, duties in steps of 1/255.

#[path = "support/mod.rs"]
mod support;

use hil::bench::{Bench, BenchOptions};
use hil::runs::line::CMD_LINE;
use hil::runs::start::wait_ready;

/// Drive for a second and check every bridge input the firmware used.
#[test]
fn firmware_pwm_is_31372_hz_with_8_bit_duty() {
    let mut bench = Bench::new(
        support::firmware("robust"),
        &support::robot("henrytwo-ideal"),
        BenchOptions::default(),
    )
    .unwrap();
    wait_ready(&mut bench, None).unwrap();
    bench.send(1, &[CMD_LINE]);
    bench.run_for(1.5).unwrap();
    let core = bench.core();
    let pins = core.pin_stats();
    // Forward inputs: D7 (right) and D9 (left) are driven with PWM.
    for pin in [7u8, 9] {
        let p = pins.iter().find(|p| p.pin == pin).unwrap();
        assert!(
            (p.hz - 31_372.55).abs() / 31_372.55 < 1e-4,
            "D{pin}: {} Hz",
            p.hz
        );
        assert!(p.active_s > 1.0, "D{pin} active only {} s", p.active_s);
    }
    let log: Vec<_> = core
        .drive_log()
        .iter()
        .filter(|e| e.pin == 7 || e.pin == 9)
        .collect();
    assert!(
        log.len() > 20,
        "the PID changed the duty only {} times",
        log.len()
    );
    for e in log {
        let steps = e.duty * 255.0;
        assert!(
            (steps - steps.round()).abs() < 1e-9,
            "duty {} on D{} is not k/255",
            e.duty,
            e.pin
        );
    }
}

#[path = "support/avr_asm.rs"]
mod avr_asm;

/// A hand-assembled program driving an L298N's enables as the Arduino core
/// does on timer 0 (`fixtures/boards/l298n-timer0.toml`): both motors
/// forward (IN1 D22/D24 high, IN2 D23/D25 low), timer 0 in fast PWM at
/// clock/64 with its overflow interrupt on (the core's `millis()`), then
/// OCR0A = OCR0B = 191 and `tccr0a` (0xA3 connects OC0A and OC0B, as
/// `analogWrite(13, 191)` and `analogWrite(4, 191)` do); then it sleeps.
fn timer0_program(tccr0a: u8) -> Vec<u8> {
    use avr_asm::{jmp, ldi, sts};
    const MAIN: usize = 0x80;
    const ISR: usize = 0x100;
    let mut words = vec![0u16; ISR + 1];
    words[0..2].copy_from_slice(&jmp(MAIN as u16));
    for v in 1..57 {
        words[2 * v..2 * v + 2].copy_from_slice(&jmp(ISR as u16));
    }
    let writes: [(u16, u8); 11] = [
        (0x21, 0x0F), // DDRA: D22-D25 outputs
        (0x22, 0x05), // PORTA: IN1 high, IN2 low on both motors
        (0x33, 0x20), // DDRG: D4 (PG5) output
        (0x24, 0x80), // DDRB: D13 (PB7) output
        (0x44, 0x03), // TCCR0A: WGM01 | WGM00, fast PWM
        (0x45, 0x03), // TCCR0B: clock/64
        (0x6E, 0x01), // TIMSK0: TOIE0, the core's millis()
        (0x47, 191),  // OCR0A
        (0x48, 191),  // OCR0B
        (0x44, tccr0a),
        (0x53, 0x01), // SMCR: idle sleep
    ];
    let mut main = Vec::new();
    for (addr, value) in writes {
        main.push(ldi(16, value));
        main.extend(sts(addr, 16));
    }
    // sei; sleep; rjmp .-4
    main.extend([0x9478, 0x9588, 0xCFFE]);
    words[MAIN..MAIN + main.len()].copy_from_slice(&main);
    words[ISR] = 0x9518; // reti
    words.iter().flat_map(|w| w.to_le_bytes()).collect()
}

/// Timer 0's fast PWM reaches the plant: on the timer-0 board both enables
/// run at 16 MHz / (64 * 256) = 976.5625 Hz with duty (191 + 1) / 256 from
/// the first BOTTOM after the write, and
/// both wheels turn forward; with the outputs disconnected (the same
/// program, COM0A/COM0B = 0) the enables stay low and nothing moves.
#[test]
fn timer_0_fast_pwm_drives_the_plant() {
    use hil::board::Board;
    use hil::firmware::elf::Firmware;
    use plant_model::Side;
    let path = hil::paths::workspace_root().join("fixtures/boards/l298n-timer0.toml");
    let board = Board::load(path).unwrap();
    let run = |tccr0a: u8| {
        let firmware = Firmware::from_flash(
            std::path::Path::new("timer0-l298n"),
            vec![(0, timer0_program(tccr0a))],
        );
        let options = BenchOptions {
            board,
            ..BenchOptions::default()
        };
        let mut bench = Bench::new(firmware, &support::robot("rover65"), options).unwrap();
        bench.run_for(1.0).unwrap();
        bench
    };
    let bench = run(0xA3);
    let core = bench.core();
    for pin in [4u8, 13] {
        let p = core.pin_stats().into_iter().find(|p| p.pin == pin).unwrap();
        assert_eq!(p.hz, 976.5625, "D{pin}");
        // OCR0x is double buffered in fast PWM: the 191 written waits for
        // BOTTOM, and the output connected before it compares with 0 (a
        // one-step spike a period) until then.
        let drives: Vec<f64> = core
            .drive_log()
            .iter()
            .filter(|e| e.pin == pin)
            .map(|e| e.duty)
            .collect();
        assert_eq!(drives, [1.0 / 256.0, 0.75], "D{pin}");
    }
    for side in Side::BOTH {
        let mm = core.robot().distance_travelled(side).0;
        assert!(mm > 100.0, "{side:?} wheel: {mm} mm in 1 s at 3/4 duty");
    }
    let idle = run(0x03);
    for side in Side::BOTH {
        assert_eq!(idle.core().robot().distance_travelled(side).0, 0.0);
    }
    let enables = idle
        .core()
        .drive_log()
        .iter()
        .filter(|e| e.pin == 4 || e.pin == 13);
    assert_eq!(enables.count(), 0, "the enables stay low");
}

/// A timer is refused as the firmware's clock only for the firmware that
/// uses it so: on a board with a motor input on D11 (OC1A), the robust
/// firmware, whose clock is timer 1 (TIMSK1 = OCIE1A at boot), is refused
/// naming it; the square-demo sketch, which leaves timer 1 to the Arduino
/// core (mode 1, clock/64, no interrupt), runs.
#[test]
fn timer_1_is_refused_as_the_clock_of_the_firmware_that_uses_it_so() {
    use hil::board::{BridgeInput, Mcu, Pin, PwmSource, HENRYTWO};
    use hil::firmware::elf::Firmware;
    let mut board = HENRYTWO;
    board.right_motor.pin2 = BridgeInput {
        pin: Pin::arduino(Mcu::Atmega2560, 11).unwrap(),
        pwm: Some(PwmSource {
            timer: 1,
            channel: 'A',
        }),
    };
    board.battery_leds.as_mut().unwrap().blue = Pin::arduino(Mcu::Atmega2560, 30).unwrap();
    let run = |firmware: Firmware| {
        let options = BenchOptions {
            board,
            ..BenchOptions::default()
        };
        let mut bench = Bench::new(firmware, &support::robot("henrytwo-ideal"), options).unwrap();
        bench.run_for(0.5).map(|()| bench.cycle())
    };
    let err = run(support::firmware("robust")).unwrap_err().to_string();
    assert!(err.contains("timer 1"), "{err}");
    assert!(err.contains("TIMSK1 = 0x02"), "{err}");
    assert!(err.contains("the firmware's clock"), "{err}");
    let demo = hil::paths::workspace_root().join("firmware/target/arduino/square-demo.elf");
    let cycle = run(Firmware::load(&demo).unwrap()).unwrap();
    assert_eq!(cycle, 8_000_000);
}
