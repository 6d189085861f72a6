//! The encoder latency's budget row: a latency with no sample is no pass.

use super::*;

fn isr(vector: u8, latencies: &[u64]) -> IsrTiming {
    let mut t = IsrTiming {
        vector,
        name: vector_name(&crate::mcu::chip::ATMEGA2560, vector),
        ..Default::default()
    };
    t.duration.add(40);
    for &l in latencies {
        t.latency.add(l);
    }
    t
}

fn encoder(side: &'static str, pin: &str, vector: Option<u8>) -> EncoderVector {
    EncoderVector {
        side,
        pin: pin.into(),
        vector,
        name: vector.map(|v| vector_name(&crate::mcu::chip::ATMEGA2560, v)),
    }
}

/// A report of encoders on INT2 (D19) and PCINT0 (D11), with these ISRs.
fn report(isrs: Vec<IsrTiming>, right: Option<u8>) -> TimingReport {
    TimingReport {
        clock_hz: 16_000_000,
        mcu: crate::mcu::chip::Mcu::Atmega2560,
        control_function: Some("control".into()),
        control_cycles: Stats::default(),
        tick_period_cycles: Stats::default(),
        tick_jitter_max_cycles: 0,
        tick_restarts: 0,
        isrs,
        encoder_vectors: vec![
            encoder("left", "D19", Some(3)),
            encoder("right", "D11", right),
        ],
        interrupts_off_max_cycles: 0,
        interrupts_off_max_at: None,
        stack_min_sp: 0x2000,
        static_data_end: 0x300,
        stack_margin_bytes: 0x1d00,
        cpu_load: 0.1,
    }
}

fn latency_row(r: &TimingReport) -> BudgetRow {
    let budgets = Budgets {
        control_max_us: Some(2000.0),
        tick_jitter_max_us: Some(100.0),
        tick_period_us: Some(15000.0),
        isr_max_us: 50.0,
        isr_latency_max_us: 50.0,
        interrupts_off_max_us: 100.0,
        stack_margin_min_bytes: 256,
        cpu_load_max: 0.5,
    };
    r.check(&budgets)
        .into_iter()
        .find(|row| row.what.starts_with("encoder edge to handler"))
        .unwrap()
}

/// Both encoders' vectors measured: the longest of their latencies, a pass.
#[test]
fn latencies_of_both_encoders_pass() {
    let r = report(vec![isr(3, &[5, 10]), isr(9, &[5, 16])], Some(9));
    let row = latency_row(&r);
    assert_eq!(row.what, "encoder edge to handler (INT2, PCINT0), longest");
    assert_eq!(row.measured, Some(1.0)); // 16 cycles at 16 MHz
    assert!(row.pass);
}

/// A vector that ran but never after an edge, one that never ran, and an
/// encoder pin that cannot interrupt: not measured, never a pass, and the
/// text says which.
#[test]
fn a_latency_not_measured_is_no_pass() {
    for (isrs, right, says) in [
        (
            vec![isr(3, &[5]), isr(9, &[])],
            Some(9),
            "right encoder A D11: PCINT0 never ran after an edge",
        ),
        (
            vec![isr(3, &[5])],
            Some(9),
            "right encoder A D11: PCINT0 never ran after an edge",
        ),
        (
            vec![isr(3, &[5])],
            None,
            "right encoder A D11: cannot interrupt",
        ),
        (
            Vec::new(),
            Some(9),
            "left encoder A D19: INT2 never ran after an edge",
        ),
    ] {
        let r = report(isrs, right);
        let row = latency_row(&r);
        assert_eq!(row.measured, None, "{says}");
        assert!(!row.pass, "{says}");
        let text = r.render(&[row]);
        assert!(text.contains(says), "{text}");
        assert!(text.contains("NOT MEASURED"), "{text}");
    }
}
