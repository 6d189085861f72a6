//! Building a bench: the MCU with the firmware's flash, the registers the
//! bench claims or watches, and the IRQs that connect the robot's parts to
//! the MCU pins a [`Board`] names (the parts never name a pin themselves).

use plant_model::{RobotConfig, Side};

use super::core::{
    BenchCore, TAG_LED_PORT, TAG_PORT_DDR, TAG_PORT_REG, TAG_UART_OUT, TAG_USB_ATTACH,
};
use super::registers::ACSR;
use super::usb::UsbHost;
use super::{BenchError, BenchOptions};
use crate::board::Board;
use crate::firmware::elf::Firmware;
use crate::mcu::sim::{Avr, DrivenPin, Handler, IoClaim, SimError};

/// The MCU running `firmware`, its pins wired to `robot`'s parts as
/// `options.board` says, the bench's first event scheduled.
pub(super) fn build(
    firmware: &Firmware,
    robot: &RobotConfig,
    options: &BenchOptions,
    counts: Option<[u16; 2]>,
) -> Result<Avr<BenchCore>, BenchError> {
    let wiring: &Board = &options.board;
    let core = BenchCore::new(robot, options, wiring, counts)?;
    // The board's MCU: the ELF's, checked where both are read (the CLI).
    let mut avr = Avr::new(wiring.mcu.chip().simavr_core, options.clock.hz(), core)?;
    avr.set_free_run(options.free_run);
    avr.set_skip(options.skip);
    for (addr, bytes) in &firmware.segments {
        avr.load_flash(*addr, bytes)?;
    }
    // The timers of the board's PWM pins: emulated by the bench (see
    // pwm.rs), never clocked by simavr, or mirrored (simavr runs them, the
    // bench sees the writes); the others' configurations are judged when
    // something observes them (see timers.rs).
    let timers = avr.handler().bridge.timers().to_vec();
    for timer in &timers {
        let claim = if timer.is_mirrored() {
            IoClaim::Observe
        } else {
            IoClaim::Replace
        };
        for addr in timer.write_addresses() {
            avr.claim_io_write(addr, claim)?;
        }
        for addr in timer.read_addresses() {
            avr.claim_io_read(addr)?;
        }
    }
    let simavr_timers = avr.handler().simavr_timers.clone();
    for addr in simavr_timers.write_addresses() {
        avr.claim_io_write(addr, IoClaim::Observe)?;
    }
    for addr in simavr_timers.read_addresses() {
        avr.observe_io_read(addr)?;
    }
    // The driver inputs' ports, watched like the PWM registers.
    let ports = avr.handler().bridge.ports();
    for (k, port) in ports.into_iter().enumerate() {
        let reg = avr.port_register(port)?;
        let ddr = avr.port_direction(port)?;
        avr.watch_irq(reg, TAG_PORT_REG + k as u32);
        avr.watch_irq(ddr, TAG_PORT_DDR + k as u32);
    }
    if let Some(leds) = wiring.battery_leds {
        let leds = avr.port_register(leds.green.port)?;
        avr.watch_irq(leds, TAG_LED_PORT);
    }
    // A board with no divider leaves the ADC's inputs unconnected.
    if let Some(battery) = wiring.battery {
        let adc = avr.adc_input(battery.adc)?;
        avr.handler_mut().power.connect(adc);
    }
    // B lines may be raised lazily, before reads of their PIN registers;
    // the comparator's control register says when AIN1 is watched.
    for b in Side::BOTH.iter().filter_map(|&side| wiring.encoder(side).b) {
        avr.observe_io_read(b.pin_register())?;
    }
    avr.claim_io_write(ACSR, IoClaim::Observe)?;
    // Low until `connect_encoders` raises the plant's levels.
    let encoders = encoder_pins(&mut avr, wiring)?;
    for n in wiring.link_usarts() {
        let (input, output) = avr.uart(n)?;
        avr.watch_irq(output, TAG_UART_OUT + n as u32);
        avr.handler_mut().uart.connect(n, input);
    }
    // An MCU with USB has the bench's USB host on its port, the cable in
    // unless the options take it out.
    if let Some(usb) = wiring.mcu.chip().usb.filter(|_| options.usb_cable) {
        let port = avr.usb(usb.usbcon, usb.general_vector)?;
        avr.watch_irq(port.attach_irq(), TAG_USB_ATTACH);
        avr.handler_mut().usb = Some(UsbHost::new(port, options.clock));
    }
    avr.with_core(|core, c| {
        if let Some(usb) = &mut core.usb {
            usb.plug(c);
        }
        core.update_supply(c, 0);
        core.update_adc(c, 0);
        // Encoder lines start at the plant's levels.
        core.connect_encoders(c, encoders);
        core.update_lazy_b(c, 0);
        core.plan_edges(0);
    });
    let first = avr.handler().next_event();
    avr.schedule(first);
    Ok(avr)
}

/// The encoder lines of `board` as pins driven from outside (the
/// firmware's port writes, a pull-up switched on, leave their levels
/// alone), low: per side (left, right) the interrupt pin's and B's (None
/// on a one-channel encoder, whose B is on no pin).
pub fn encoder_pins<H: Handler>(
    avr: &mut Avr<H>,
    board: &Board,
) -> Result<[[Option<DrivenPin>; 2]; 2], SimError> {
    let mut pins = [[None; 2]; 2];
    for side in Side::BOTH {
        let e = board.encoder(side);
        pins[side.index()] = [
            Some(avr.driven_pin(e.a.port, e.a.bit, false)?),
            match e.b {
                Some(b) => Some(avr.driven_pin(b.port, b.bit, false)?),
                None => None,
            },
        ];
    }
    Ok(pins)
}
