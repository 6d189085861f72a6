//! The host's side of the MCU's USB device controller (`sim/avr_usb.c`):
//! what a USB host does on the bus, as simavr's ioctls let it (a SETUP, an
//! IN, an OUT, a bus reset), plus what simavr leaves to the host and the
//! bench does here:
//! - the start of frame: simavr's own generator is switched off in its
//!   source (`if (0)` in the reset ioctl), and the Arduino core sends its
//!   serial output on the SOF interrupt (`USB_Flush` in `USB_GEN_vect`), so
//!   the host raises it once per frame through simavr's vector table;
//! - VBUS: simavr defines `AVR_IOCTL_USB_VBUS` but handles no such ioctl, so
//!   the host sets USBSTA's VBUS bit itself;
//! - a look at an endpoint's state (UECONX, UEINTX) without side effects:
//!   simavr takes an OUT over a SETUP the firmware has not read yet (the two
//!   share the endpoint's FIFO), and prints a warning on stdout for an IN or
//!   OUT on an endpoint the firmware has not enabled; a host that looks
//!   first does neither.
//!
//! No usbip, no VHCI: the host is the bench, in-process, at cycles it
//! chooses.

use std::ffi::c_void;
use std::ptr::NonNull;

use simavr_ffi as ffi;

use super::irq::Irq;
use super::mcu::{data_read, data_write, io_slot, ioctl_def};
use super::view::Core;
use super::{Avr, Handler, SimError};

/// USBCON's offset to the registers the host touches (the 32U4's layout,
/// which simavr's `enum usb_regs` follows).
const USBSTA: u16 = 1;
const UDINT: u16 = 9;
const UDIEN: u16 = 10;
const UENUM: u16 = 17;
const UECONX: u16 = 19;
const UEINTX: u16 = 16;
/// UDINT's and UDIEN's start-of-frame bit.
const SOFI: u8 = 1 << 2;
/// USBSTA's VBUS bit.
const VBUS: u8 = 1 << 0;

/// A transaction's answer, as the device gave it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UsbAnswer {
    /// Done: for an IN, that many bytes came.
    Ack(usize),
    /// Not ready: try again later.
    Nak,
    /// The endpoint refuses the request.
    Stall,
}

/// An endpoint's state as the firmware would read it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EndpointState {
    /// UECONX.EPEN: the firmware has enabled it.
    pub enabled: bool,
    /// UEINTX.RXSTPI: a SETUP waits for the firmware.
    pub setup_pending: bool,
}

/// The MCU's USB device controller, for use with the [`Avr`] (and inside
/// its callbacks, the [`Core`]) it came from only.
#[derive(Debug, Clone, Copy)]
pub struct UsbPort {
    /// USBCON's data-space address.
    usbcon: u16,
    /// simavr's USB general interrupt vector (the SOF's).
    general: NonNull<ffi::avr_int_vector_t>,
    /// The IRQ simavr raises when the firmware attaches (clears UDCON.DETACH).
    attach: Irq,
}

impl<H: Handler> Avr<H> {
    /// The USB device controller whose registers start at `usbcon`, with
    /// its general interrupt at `general_vector`; an error when simavr's
    /// core for this MCU has none.
    pub fn usb(&mut self, usbcon: u16, general_vector: u8) -> Result<UsbPort, SimError> {
        let a = self.raw();
        // SAFETY: an IRQ lookup on the live MCU, null when it has no USB.
        let attach = unsafe {
            ffi::avr_io_getirq(
                a,
                ioctl_def(b'u', b's', b'b', b' '),
                ffi::USB_IRQ_ATTACH as i32,
            )
        };
        let attach = self.own(attach).ok_or(SimError::NoUsb)?;
        // SAFETY: plain reads of the live MCU's vector table: `vector_count`
        // entries, each a vector registered by a peripheral at init.
        let general = unsafe {
            let table = &(*a).interrupts;
            table.vector[..table.vector_count as usize]
                .iter()
                .copied()
                .filter_map(NonNull::new)
                .find(|v| v.as_ref().vector == general_vector)
        };
        let general = general.ok_or(SimError::NoUsb)?;
        io_slot(usbcon + UEINTX)?;
        Ok(UsbPort {
            usbcon,
            general,
            attach,
        })
    }
}

impl UsbPort {
    /// The IRQ raised (with 1) when the firmware attaches to the bus.
    pub fn attach_irq(&self) -> Irq {
        self.attach
    }
}

/// simavr's ioctl `code` on the USB controller with `pipe` and `buf`.
///
/// # Safety
/// `avr` is a live MCU with a USB controller; `buf` is valid for `len`
/// bytes (written by an IN, read otherwise) and at least 64 long for an IN.
unsafe fn usb_ioctl(
    avr: *mut ffi::avr_t,
    code: u8,
    pipe: u8,
    buf: *mut u8,
    len: usize,
) -> (i32, u32) {
    let mut io = ffi::avr_io_usb {
        pipe,
        sz: len as u32,
        buf,
    };
    // SAFETY: as the caller guarantees; simavr reads `io` and copies at
    // most the endpoint's size (64 at most) into or out of `buf`.
    let rc = unsafe {
        ffi::avr_ioctl(
            avr,
            ioctl_def(b'u', b's', b'b', code),
            &mut io as *mut ffi::avr_io_usb as *mut c_void,
        )
    };
    (rc, io.sz)
}

fn answer(rc: i32, n: u32) -> UsbAnswer {
    match rc {
        0 => UsbAnswer::Ack(n as usize),
        -3 => UsbAnswer::Stall,
        // -2 is a NAK; -1 an endpoint not enabled, which the host looks
        // for first and treats alike.
        _ => UsbAnswer::Nak,
    }
}

impl Core {
    /// # Panics
    /// When `usb` belongs to another `Avr`.
    fn own_usb(&self, usb: &UsbPort) {
        usb.attach.raw_for(self.owner());
    }

    /// Drive VBUS (USBSTA.VBUS): the cable's 5 V.
    pub fn usb_vbus(&mut self, usb: &UsbPort, on: bool) {
        self.own_usb(usb);
        let addr = usb.usbcon + USBSTA;
        let v = self.data(addr);
        self.set_data(addr, if on { v | VBUS } else { v & !VBUS });
    }

    /// End a bus reset: simavr resets endpoints 1-4 and raises EORSTI.
    pub fn usb_bus_reset(&mut self, usb: &UsbPort) {
        self.own_usb(usb);
        // SAFETY: the live MCU (this callback's); the reset takes no buffer.
        unsafe { usb_ioctl(self.avr_ptr().as_ptr(), b'R', 0, std::ptr::null_mut(), 0) };
    }

    /// A start of frame: UDINT.SOFI, and the general interrupt if the
    /// firmware enabled it (UDIEN.SOFE), as the device controller would.
    pub fn usb_start_of_frame(&mut self, usb: &UsbPort) {
        self.own_usb(usb);
        let udint = usb.usbcon + UDINT;
        self.set_data(udint, self.data(udint) | SOFI);
        if self.data(usb.usbcon + UDIEN) & SOFI != 0 {
            // SAFETY: the vector is one of this live MCU's own (found in its
            // table by `Avr::usb`); simavr checks its enable bit (USBE).
            unsafe { ffi::avr_raise_interrupt(self.avr_ptr().as_ptr(), usb.general.as_ptr()) };
        }
    }

    /// The state of endpoint `ep` (0-4) as the firmware reads it, without
    /// side effects: UENUM is pointed at it for the look and put back.
    pub fn usb_endpoint(&mut self, usb: &UsbPort, ep: u8) -> EndpointState {
        self.own_usb(usb);
        assert!(ep < 5, "the 32U4 has endpoints 0-4");
        let avr = self.avr_ptr();
        let uenum = usb.usbcon + UENUM;
        // SAFETY: the live MCU; the two registers' slots were checked by
        // `Avr::usb`, and simavr's read handlers for them only read the
        // endpoint's state (UEINTX's refreshes its RWAL bit from the FIFO,
        // as any read by the firmware does).
        unsafe {
            let saved = data_read(avr, uenum);
            data_write(avr, uenum, ep);
            let read = |off: u16| {
                let addr = usb.usbcon + off;
                let io = &(*avr.as_ptr()).io[addr as usize - 32];
                match io.r.c {
                    Some(f) => f(avr.as_ptr(), addr, io.r.param),
                    None => data_read(avr, addr),
                }
            };
            let (ueconx, ueintx) = (read(UECONX), read(UEINTX));
            data_write(avr, uenum, saved);
            EndpointState {
                enabled: ueconx & 1 != 0,
                setup_pending: ueintx & (1 << 3) != 0,
            }
        }
    }

    /// A SETUP transaction on endpoint 0.
    pub fn usb_setup(&mut self, usb: &UsbPort, packet: &[u8; 8]) -> UsbAnswer {
        self.own_usb(usb);
        let mut p = *packet;
        // SAFETY: the live MCU; simavr copies the 8 bytes out of `p`.
        let (rc, n) = unsafe { usb_ioctl(self.avr_ptr().as_ptr(), b's', 0, p.as_mut_ptr(), 8) };
        answer(rc, n)
    }

    /// An IN transaction on endpoint `ep`: up to 64 bytes into `buf`.
    pub fn usb_in(&mut self, usb: &UsbPort, ep: u8, buf: &mut [u8; 64]) -> UsbAnswer {
        self.own_usb(usb);
        // SAFETY: the live MCU; simavr copies at most the endpoint's size
        // (64 at most on the 32U4) into the 64-byte buffer.
        let (rc, n) = unsafe { usb_ioctl(self.avr_ptr().as_ptr(), b'r', ep, buf.as_mut_ptr(), 0) };
        answer(rc, n.min(64))
    }

    /// An OUT transaction of `data` (64 bytes at most) on endpoint `ep`.
    pub fn usb_out(&mut self, usb: &UsbPort, ep: u8, data: &[u8]) -> UsbAnswer {
        self.own_usb(usb);
        assert!(data.len() <= 64, "a full-speed packet is 64 bytes at most");
        let mut buf = [0u8; 64];
        buf[..data.len()].copy_from_slice(data);
        // SAFETY: the live MCU; simavr copies `len` bytes out of `buf`.
        let (rc, _) = unsafe {
            usb_ioctl(
                self.avr_ptr().as_ptr(),
                b'w',
                ep,
                buf.as_mut_ptr(),
                data.len(),
            )
        };
        answer(rc, data.len() as u32)
    }
}
