//! The ADC, single conversions on ADC0 (Arduino A0) against AVCC.
//!
//! Register values (the bench may check them):
//! - ADCSRA = 0x87 at start-up: ADEN, prescaler 128 (ADPS2:0 = 111), i.e.
//!   125 kHz ADC clock at 16 MHz, as Arduino's `init()` leaves it;
//! - ADCSRB: MUX5 = 0; ADMUX = 0x40: REFS1:0 = 01 (AVCC), ADLAR = 0
//!   (right-adjusted 10-bit result), MUX4:0 = 0 (ADC0);
//! - a conversion starts by writing ADCSRA = 0xC7 (ADSC) and takes 13 ADC
//!   clocks (1 664 CPU cycles, 104 us; the first after ADEN 25 clocks); the
//!   result is read ADCL first, then ADCH.
//!
//! No ADC interrupt is used: ADIE stays 0.

use avr_device::atmega2560::ADC;

use super::reg::read_u16;

/// ADCSRA: ADEN | ADPS2 | ADPS1 | ADPS0.
pub const ADCSRA_ENABLED: u8 = 0x87;
/// ADCSRA bit ADSC (start conversion; reads 1 while converting).
pub const ADSC: u8 = 1 << 6;
/// ADMUX: AVCC reference, right-adjusted, channel ADC0.
pub const ADMUX_AVCC_ADC0: u8 = 0x40;
/// ADCSRB bit MUX5.
const MUX5: u8 = 1 << 3;

/// The ADC, enabled and set to A0.
pub struct Adc {
    adc: ADC,
}

impl Adc {
    /// Enables the ADC with prescaler 128 (ADCSRA = 0x87), then selects A0
    /// (ADCSRB MUX5 cleared, ADMUX = 0x40). Nothing is converted yet.
    pub fn new(adc: ADC) -> Self {
        // SAFETY: documented valid settings; no conversion is running.
        unsafe { adc.adcsra().write(|w| w.bits(ADCSRA_ENABLED)) };
        let mut a = Adc { adc };
        a.select_a0();
        a
    }

    /// ADCSRB = ADCSRB & !MUX5, ADMUX = 0x40 (what Arduino's
    /// `analogRead(A0)` writes before each conversion).
    #[inline]
    pub fn select_a0(&mut self) {
        // SAFETY: clearing MUX5 and selecting ADC0 with AVCC are valid.
        unsafe {
            self.adc.adcsrb().modify(|r, w| w.bits(r.bits() & !MUX5));
            self.adc.admux().write(|w| w.bits(ADMUX_AVCC_ADC0));
        }
    }

    /// Starts one conversion (ADCSRA = 0xC7).
    #[inline]
    pub fn start(&mut self) {
        // SAFETY: ADEN, ADSC and the prescaler bits: a valid value.
        unsafe { self.adc.adcsra().write(|w| w.bits(ADCSRA_ENABLED | ADSC)) };
    }

    /// True while a conversion runs.
    #[inline]
    pub fn busy(&self) -> bool {
        self.adc.adcsra().read().bits() & ADSC != 0
    }

    /// The last result, 0..=1023 (ADCL, then ADCH).
    #[inline]
    pub fn result(&self) -> u16 {
        // SAFETY: reading the data register has no side effect besides the
        // ADCL/ADCH lock, which the high-byte read releases; only this
        // driver reads it.
        unsafe { read_u16(self.adc.adc().as_ptr()) }
    }

    /// Arduino's `analogRead(A0)`: select A0, start, busy-wait for the end
    /// of the conversion, read. Not bounded by a timeout (the conversion
    /// always ends); only the thesis build uses it.
    pub fn read_blocking(&mut self) -> u16 {
        self.select_a0();
        // SAFETY: sets ADSC on top of the current value, as `sbi` does.
        unsafe { self.adc.adcsra().modify(|r, w| w.bits(r.bits() | ADSC)) };
        while self.busy() {}
        self.result()
    }
}

impl crate::io::BatteryInput for Adc {
    #[inline(always)]
    fn start(&mut self) {
        Adc::start(self)
    }

    #[inline(always)]
    fn busy(&self) -> bool {
        Adc::busy(self)
    }

    #[inline(always)]
    fn result(&self) -> u16 {
        Adc::result(self)
    }
}
