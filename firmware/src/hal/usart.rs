//! Interrupt-driven USART: 8N1, double speed (U2Xn = 1), a receive ring
//! filled by the RX-complete handler and a transmit ring drained by the
//! data-register-empty handler.
//!
//! Both rings hold at most [`BUFFER_CAP`] = 63 bytes, like Arduino's
//! `HardwareSerial` (a 64-byte ring that keeps one slot free): a byte that
//! arrives while 63 wait is dropped, and [`Serial::write_blocking`] waits, as
//! Arduino's `Serial.write`, while 63 bytes wait to be sent.
//! [`Serial::write`] and [`Serial::read`] never wait.
//!
//! The handlers are plain functions ([`on_rx`], [`on_udre`]): each binary
//! binds them to its vectors, so a build links only the vectors it uses
//! ([`usart_vectors!`] binds both USARTs' in one line).

use avr_device::interrupt::{self, Mutex};

use super::ring::Ring;
use crate::Error;

/// Receive ring size per USART.
pub const RX_LEN: usize = 64;
/// Transmit ring size per USART.
pub const TX_LEN: usize = 64;
/// Bytes a ring holds at most (Arduino's `SERIAL_RX/TX_BUFFER_SIZE` - 1).
pub const BUFFER_CAP: usize = 63;

/// A USART peripheral this module can drive.
pub trait Instance {
    /// Programs baud, frame and enables receiver, transmitter and the RX
    /// interrupt. UDRIE stays off until there is something to send.
    fn setup(&self, ubrr: u16);
    /// Turns the receiver, transmitter and their interrupts off.
    fn shutdown(&self);
    /// Enables the data-register-empty interrupt (it fires at once if the
    /// transmitter is idle and then drains the transmit ring).
    fn start_tx(&self);
    /// The receive ring of this instance.
    fn rx_ring() -> &'static Mutex<Ring<RX_LEN>>;
    /// The transmit ring of this instance.
    fn tx_ring() -> &'static Mutex<Ring<TX_LEN>>;
}

/// Baud setting, computed at compile time from the CPU clock.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Baud {
    /// UBRRn for double-speed mode.
    pub ubrr: u16,
}

impl Baud {
    /// The divisor for `baud` at `cpu_hz` (double speed).
    pub const fn new(cpu_hz: u32, baud: u32) -> Self {
        Baud { ubrr: super::clock::ubrr_double_speed(cpu_hz, baud) }
    }
}

/// One USART with its two rings.
pub struct Serial<U: Instance> {
    usart: U,
}

impl<U: Instance> Serial<U> {
    /// Configures and enables the USART (receiver, transmitter, RX interrupt).
    pub fn new(usart: U, baud: Baud) -> Self {
        usart.setup(baud.ubrr);
        Serial { usart }
    }

    /// Takes the oldest received byte, if any.
    pub fn read(&mut self) -> Option<u8> {
        interrupt::free(|cs| U::rx_ring().borrow(cs).pop())
    }

    /// True when at least one received byte waits.
    pub fn has_input(&self) -> bool {
        interrupt::free(|cs| !U::rx_ring().borrow(cs).is_empty())
    }

    /// Queues as many of `bytes` as fit and starts sending; returns how many
    /// were queued. Never waits.
    pub fn write(&mut self, bytes: &[u8]) -> usize {
        let queued = interrupt::free(|cs| {
            let tx = U::tx_ring().borrow(cs);
            let mut n = 0;
            for &b in bytes {
                if tx.len() >= BUFFER_CAP || !tx.push(b) {
                    break;
                }
                n += 1;
            }
            n
        });
        if queued > 0 {
            self.usart.start_tx();
        }
        queued
    }

    /// Queues `byte`, first waiting (interrupts enabled, the UDRE handler
    /// draining the ring) while [`BUFFER_CAP`] bytes wait: Arduino's
    /// `HardwareSerial::write`. Unbounded by design; only the thesis build
    /// uses it. Must be called with interrupts enabled.
    pub fn write_blocking(&mut self, byte: u8) {
        while interrupt::free(|cs| U::tx_ring().borrow(cs).len()) >= BUFFER_CAP {}
        interrupt::free(|cs| U::tx_ring().borrow(cs).push(byte));
        self.usart.start_tx();
    }

    /// Number of received bytes waiting (Arduino's `available()`).
    pub fn available(&self) -> usize {
        interrupt::free(|cs| U::rx_ring().borrow(cs).len())
    }

    /// Queues all of `bytes` or nothing.
    pub fn write_all(&mut self, bytes: &[u8]) -> Result<(), Error> {
        let fits = interrupt::free(|cs| BUFFER_CAP - U::tx_ring().borrow(cs).len() >= bytes.len());
        if !fits {
            return Err(Error::TxFull);
        }
        self.write(bytes);
        Ok(())
    }

    /// Stops the USART and gives the peripheral back.
    pub fn release(self) -> U {
        self.usart.shutdown();
        self.usart
    }
}

impl<U: Instance> crate::io::Line for Serial<U> {
    const RX_LEN: usize = RX_LEN;

    #[inline(always)]
    fn read(&mut self) -> Option<u8> {
        Serial::read(self)
    }

    #[inline(always)]
    fn write_all(&mut self, bytes: &[u8]) -> Result<(), Error> {
        Serial::write_all(self, bytes)
    }
}

impl<U: Instance> ufmt::uWrite for Serial<U> {
    type Error = Error;

    /// Queues the string; a string that does not fit entirely is cut and
    /// reported as [`Error::TxFull`] (the line is then incomplete, but the
    /// caller never waits for the UART).
    fn write_str(&mut self, s: &str) -> Result<(), Error> {
        if self.write(s.as_bytes()) == s.len() {
            Ok(())
        } else {
            Err(Error::TxFull)
        }
    }
}

/// The interrupt handler bodies of one USART (see [`on_rx`], [`on_udre`]).
pub trait Handlers {
    /// Receive complete.
    ///
    /// # Safety
    /// Call only from this USART's RX-complete vector.
    unsafe fn rx();
    /// Data register empty.
    ///
    /// # Safety
    /// Call only from this USART's data-register-empty vector.
    unsafe fn udre();
}

/// Body of the `USARTn_RX` vector: stores the received byte in the receive
/// ring (dropped when [`BUFFER_CAP`] bytes wait) and wakes the main loop.
///
/// # Safety
/// Call only from the RX-complete vector of `U`, e.g.
/// `#[avr_device::interrupt(atmega2560)] fn USART1_RX() { unsafe { on_rx::<USART1>() } }`.
#[inline(always)]
pub unsafe fn on_rx<U: Handlers>() {
    // SAFETY: forwarded from the caller.
    unsafe { U::rx() }
}

/// Body of the `USARTn_UDRE` vector: sends the next queued byte, or turns
/// this interrupt off when the transmit ring is empty.
///
/// # Safety
/// Call only from the data-register-empty vector of `U`.
#[inline(always)]
pub unsafe fn on_udre<U: Handlers>() {
    // SAFETY: forwarded from the caller.
    unsafe { U::udre() }
}

// UCSRnA / UCSRnB / UCSRnC bits (same positions on every USART).
const U2X: u8 = 1 << 1;
const RXCIE: u8 = 1 << 7;
const UDRIE: u8 = 1 << 5;
const RXEN: u8 = 1 << 4;
const TXEN: u8 = 1 << 3;
/// UCSZn1:0 = 11: 8 data bits; no parity, 1 stop bit, asynchronous.
const FRAME_8N1: u8 = 0b0000_0110;

macro_rules! usart_instance {
    ($module:ident, $periph:ident, $ucsra:ident, $ucsrb:ident, $ucsrc:ident, $ubrr:ident, $udr:ident) => {
        mod $module {
            use super::*;
            use avr_device::atmega2560::$periph;

            static RX: Mutex<Ring<RX_LEN>> = Mutex::new(Ring::new());
            static TX: Mutex<Ring<TX_LEN>> = Mutex::new(Ring::new());

            impl Instance for $periph {
                fn setup(&self, ubrr: u16) {
                    // SAFETY: the values are valid settings of these
                    // registers and the USART is off while they change.
                    // UBRRn goes high byte first: writing UBRRnL applies
                    // the divisor at once, so the high byte must be there.
                    unsafe {
                        self.$ucsrb().write(|w| w.bits(0));
                        self.$ucsra().write(|w| w.bits(U2X));
                        crate::hal::reg::write_u16(self.$ubrr().as_ptr(), ubrr);
                        self.$ucsrc().write(|w| w.bits(FRAME_8N1));
                        self.$ucsrb().write(|w| w.bits(RXCIE | RXEN | TXEN));
                    }
                }

                fn shutdown(&self) {
                    // SAFETY: 0 disables the USART; always valid.
                    unsafe { self.$ucsrb().write(|w| w.bits(0)) };
                }

                fn start_tx(&self) {
                    interrupt::free(|_| {
                        // SAFETY: sets one enable bit; the handler clears it
                        // under the same rule (interrupts off).
                        unsafe { self.$ucsrb().modify(|r, w| w.bits(r.bits() | UDRIE)) };
                    });
                }

                fn rx_ring() -> &'static Mutex<Ring<RX_LEN>> {
                    &RX
                }

                fn tx_ring() -> &'static Mutex<Ring<TX_LEN>> {
                    &TX
                }
            }

            impl Handlers for $periph {
                unsafe fn rx() {
                    // SAFETY: the handler reads only UDRn, which clears RXCn;
                    // the main code never reads UDRn.
                    let usart = unsafe { $periph::steal() };
                    let byte = usart.$udr().read().bits();
                    interrupt::free(|cs| {
                        let rx = RX.borrow(cs);
                        if rx.len() < BUFFER_CAP {
                            rx.push(byte);
                        }
                    });
                    crate::hal::sleep::wake();
                }

                unsafe fn udre() {
                    // SAFETY: the handler writes UDRn and clears UDRIE; the
                    // main code only sets UDRIE, with interrupts off.
                    let usart = unsafe { $periph::steal() };
                    interrupt::free(|cs| match TX.borrow(cs).pop() {
                        Some(b) => {
                            // SAFETY: any byte is a valid UDRn value.
                            usart.$udr().write(|w| unsafe { w.bits(b) });
                        }
                        None => {
                            // SAFETY: clears one enable bit.
                            usart.$ucsrb().modify(|r, w| unsafe { w.bits(r.bits() & !UDRIE) });
                        }
                    });
                }
            }
        }
    };
}

usart_instance!(usart0_impl, USART0, ucsr0a, ucsr0b, ucsr0c, ubrr0, udr0);
usart_instance!(usart1_impl, USART1, ucsr1a, ucsr1b, ucsr1c, ubrr1, udr1);

/// Binds the RX-complete and data-register-empty vectors of USART0 and
/// USART1 to [`on_rx`] and [`on_udre`]. Expanded in a binary (the vectors
/// must be defined where they are linked); needs `avr_device`, `USART0` and
/// `USART1` and this module as `usart` in scope.
#[macro_export]
macro_rules! usart_vectors {
    () => {
        #[avr_device::interrupt(atmega2560)]
        fn USART0_RX() {
            // SAFETY: this is USART0's RX-complete vector.
            unsafe { usart::on_rx::<USART0>() }
        }

        #[avr_device::interrupt(atmega2560)]
        fn USART0_UDRE() {
            // SAFETY: this is USART0's data-register-empty vector.
            unsafe { usart::on_udre::<USART0>() }
        }

        #[avr_device::interrupt(atmega2560)]
        fn USART1_RX() {
            // SAFETY: this is USART1's RX-complete vector.
            unsafe { usart::on_rx::<USART1>() }
        }

        #[avr_device::interrupt(atmega2560)]
        fn USART1_UDRE() {
            // SAFETY: this is USART1's data-register-empty vector.
            unsafe { usart::on_udre::<USART1>() }
        }
    };
}
