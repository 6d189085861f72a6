//! The parameters kept across resets (the MCU's EEPROM): the layout, the
//! codec of one parameter, the boot-time load, and the queue that writes
//! the changed bytes one at a time from the main loop.
//!
//! Layout, from EEPROM address [`BASE`]:
//! - byte 0: [`MAGIC`], the layout's version;
//! - then one slot of [`SLOT_LEN`] bytes per parameter id 1..=31, at
//!   `BASE + 1 + 5 * (id - 1)`: the value as `f32` little-endian, then the
//!   CRC-8 (`henrytwo_protocol::crc8`) of the id byte and those four bytes.
//!   The slot of `LegLengthMm` (id 4) is never written: the leg length is the
//!   bench variable `HT_LEG_LENGTH_MM`, which the bench writes in RAM.
//!
//! At boot every slot whose CRC matches and whose value passes
//! `Param::check` is taken; anything else (an erased EEPROM reads 0xFF: a
//! NaN with a wrong CRC) keeps the factory value. With another magic byte
//! nothing is taken, the slots that are not erased are queued to be
//! rewritten with the factory values, and the magic is written after them.
//!
//! Ids 27-31 (stop timing and thresholds) came after ids 1-26 under the
//! same magic: their slots follow, so an EEPROM written before them keeps
//! its values and reads the new slots erased, the factory values.
//!
//! A write never waits: [`Stored::step`] writes one byte when the EEPROM is
//! not busy (3.4 ms per byte on the chip), skipping bytes that already hold
//! their value; a slot set again while being written starts over.

use henrytwo_protocol::{crc8, Param};

use crate::settings::Settings;

/// Bytes in and out of a non-volatile memory.
pub trait ByteStore {
    /// The byte at `addr` (the caller has checked [`ByteStore::busy`]).
    fn read(&mut self, addr: u16) -> u8;
    /// A write is in progress: nothing else may start.
    fn busy(&self) -> bool;
    /// Starts writing `byte` at `addr` (only when not busy).
    fn write(&mut self, addr: u16, byte: u8);
}

/// First address of the layout.
pub const BASE: u16 = 0;
/// Byte 0 of the layout: this layout, version 1.
pub const MAGIC: u8 = 0xA1;
/// Bytes per parameter: the `f32` and its CRC.
pub const SLOT_LEN: u16 = 5;
/// Bytes of the whole layout.
pub const LAYOUT_LEN: u16 = 1 + SLOT_LEN * Param::ALL.len() as u16;

/// Address of `p`'s slot.
pub const fn slot_addr(p: Param) -> u16 {
    BASE + 1 + SLOT_LEN * (p.id() as u16 - 1)
}

/// Whether `p` is kept in the EEPROM (all but the leg length).
pub const fn persisted(p: Param) -> bool {
    !matches!(p, Param::LegLengthMm)
}

/// The slot's bytes for `p` = `v`.
pub fn encode_slot(p: Param, v: f32) -> [u8; SLOT_LEN as usize] {
    let [a, b, c, d] = v.to_le_bytes();
    [a, b, c, d, crc8(&[p.id(), a, b, c, d])]
}

/// The value in a slot of `p`, if its CRC matches and `p` accepts it.
pub fn decode_slot(p: Param, slot: [u8; SLOT_LEN as usize]) -> Option<f32> {
    let [a, b, c, d, crc] = slot;
    if crc8(&[p.id(), a, b, c, d]) != crc {
        return None;
    }
    p.check(f32::from_le_bytes([a, b, c, d])).ok()
}

/// Bit of the magic byte in [`Stored`]'s queue (the slots' bits are their ids).
const MAGIC_BIT: u32 = 1;

// The queue holds a bit per id in a `u32`: ids up to 31.
const _: () = assert!(Param::ALL.len() < 32);

/// The settings with the store they are kept in, and what is still to be
/// written there.
pub struct Stored<S> {
    /// The settings.
    pub settings: Settings,
    store: S,
    /// Queued: bit `id` for a slot, [`MAGIC_BIT`] for the magic byte.
    queued: u32,
    /// Id of the slot being written (0: none), and its next byte.
    current: u8,
    index: u8,
    /// The magic byte in the store is [`MAGIC`].
    magic_ok: bool,
}

impl<S: ByteStore> Stored<S> {
    /// Reads the settings from `store`: each kept parameter from its slot,
    /// `defaults`' value where the slot is missing or invalid. At boot: no
    /// write of this firmware is in progress then (EEPE resets to 0, and a
    /// slot a reset tore fails its CRC).
    pub fn load(mut store: S, defaults: Settings) -> Self {
        let mut read = |addr: u16| store.read(addr);
        let magic_ok = read(BASE) == MAGIC;
        let mut settings = defaults;
        let mut queued = 0;
        for p in Param::ALL {
            if !persisted(p) {
                continue;
            }
            let a = slot_addr(p);
            let slot = [read(a), read(a + 1), read(a + 2), read(a + 3), read(a + 4)];
            if magic_ok {
                if let Some(v) = decode_slot(p, slot) {
                    settings.set(p, v);
                }
            } else if slot != [0xFF; SLOT_LEN as usize] {
                queued |= 1 << p.id();
            }
        }
        if queued != 0 {
            queued |= MAGIC_BIT;
        }
        Stored { settings, store, queued, current: 0, index: 0, magic_ok }
    }

    /// Sets `p` (checked by the caller) and queues it to be kept.
    pub fn set(&mut self, p: Param, v: f32) {
        self.settings.set(p, v);
        if !persisted(p) {
            return;
        }
        if self.current == p.id() {
            self.index = 0;
        } else {
            self.queued |= 1 << p.id();
        }
        if !self.magic_ok {
            self.queued |= MAGIC_BIT;
        }
    }

    /// Something is still to be written.
    #[inline(always)]
    pub fn pending(&self) -> bool {
        self.queued != 0 || self.current != 0
    }

    /// Writes the next byte that differs from the store's, if the store is
    /// not busy; bytes that already hold their value are passed over.
    #[inline(never)]
    pub fn step(&mut self) {
        if self.store.busy() {
            return;
        }
        loop {
            if self.current == 0 {
                let slots = self.queued & !MAGIC_BIT;
                if slots != 0 {
                    self.current = slots.trailing_zeros() as u8;
                    self.queued &= !(1 << self.current);
                    self.index = 0;
                } else if self.queued != 0 {
                    // The magic last: the slots before it hold this layout.
                    self.queued = 0;
                    self.magic_ok = true;
                    if self.store.read(BASE) != MAGIC {
                        self.store.write(BASE, MAGIC);
                    }
                    return;
                } else {
                    return;
                }
            }
            let Some(p) = Param::from_u8(self.current) else {
                self.current = 0;
                continue;
            };
            let bytes = encode_slot(p, self.settings.get(p));
            while let Some(&b) = bytes.get(self.index as usize) {
                let addr = slot_addr(p) + self.index as u16;
                self.index += 1;
                if self.store.read(addr) != b {
                    self.store.write(addr, b);
                    return;
                }
            }
            self.current = 0;
        }
    }

    /// The store.
    pub fn store(&self) -> &S {
        &self.store
    }
}

/// The MCU's EEPROM as a [`ByteStore`].
#[cfg(target_arch = "avr")]
impl ByteStore for crate::hal::eeprom::Eeprom {
    #[inline(always)]
    fn read(&mut self, addr: u16) -> u8 {
        crate::hal::eeprom::Eeprom::read(self, addr)
    }

    #[inline(always)]
    fn busy(&self) -> bool {
        crate::hal::eeprom::Eeprom::busy(self)
    }

    #[inline(always)]
    fn write(&mut self, addr: u16, byte: u8) {
        crate::hal::eeprom::Eeprom::write(self, addr, byte)
    }
}

// The layout fits the ATmega2560's 4 KiB EEPROM.
const _: () = assert!(BASE as u32 + LAYOUT_LEN as u32 <= 4096);

#[cfg(test)]
mod tests {
    use std::vec::Vec;

    use henrytwo_protocol::Command;

    use super::*;
    use crate::bench;
    use crate::robust::fake::{self, Eeprom};
    use crate::robust::App;

    /// A value `p` accepts that is not its factory value.
    fn other_value(p: Param) -> f32 {
        let r = p.range();
        let v = if r.integer { r.min + 1.0 } else { r.min + (r.max - r.min) * 0.375 };
        assert_ne!(v, p.factory_default(), "{p:?}");
        p.check(v).unwrap()
    }

    /// Writes everything queued, `step` by `step`, the EEPROM busy
    /// `write_time` calls after each write; the number of steps.
    fn drain(s: &mut Stored<Eeprom>) -> usize {
        let mut steps = 0;
        while s.pending() {
            s.step();
            steps += 1;
            assert!(steps < 100_000, "never done");
        }
        steps
    }

    fn persisted_params() -> impl Iterator<Item = Param> {
        Param::ALL.into_iter().filter(|&p| persisted(p))
    }

    #[test]
    fn the_factory_settings_are_the_protocols_factory_defaults() {
        let _bench = fake::lock();
        for p in Param::ALL {
            assert_eq!(Settings::DEFAULT.get(p), p.factory_default(), "{p:?}");
        }
    }

    /// The layout is the magic byte and one slot per parameter, no more: the
    /// check that it fits the EEPROM counts exactly the bytes it uses.
    #[test]
    fn the_layout_length_ends_with_the_last_slot() {
        let end = Param::ALL.iter().map(|&p| slot_addr(p) + SLOT_LEN).max().unwrap();
        assert_eq!(BASE + LAYOUT_LEN, end);
        assert_eq!(LAYOUT_LEN, 1 + 5 * Param::ALL.len() as u16);
    }

    #[test]
    fn an_erased_eeprom_gives_the_factory_settings_and_writes_nothing() {
        let mut s = Stored::load(Eeprom::default(), Settings::DEFAULT);
        assert_eq!(s.settings, Settings::DEFAULT);
        assert!(!s.pending());
        drain(&mut s);
        assert!(s.store().writes.is_empty());
    }

    #[test]
    fn every_kept_parameter_survives_a_reset() {
        let _bench = fake::lock();
        let mut s = Stored::load(Eeprom::default(), Settings::DEFAULT);
        for p in persisted_params() {
            s.set(p, other_value(p));
        }
        drain(&mut s);
        let again = Stored::load(Eeprom::holding(s.store()), Settings::DEFAULT);
        for p in persisted_params() {
            assert_eq!(again.settings.get(p), other_value(p), "{p:?}");
        }
        assert_eq!(again.settings, s.settings);
        assert!(!again.pending());
    }

    #[test]
    fn the_layout_is_the_magic_then_a_value_and_its_crc_per_id() {
        let mut s = Stored::load(Eeprom::default(), Settings::DEFAULT);
        s.set(Param::CountsPerWheelRev, 360.0);
        drain(&mut s);
        let e = s.store();
        assert_eq!(e.bytes[0], MAGIC);
        let a = 1 + 5 * (19 - 1);
        let v = 360.0f32.to_le_bytes();
        assert_eq!(&e.bytes[a..a + 5], &[v[0], v[1], v[2], v[3], crc8(&[19, v[0], v[1], v[2], v[3]])]);
        // Only that slot and the magic, the magic last.
        let addrs: Vec<u16> = e.writes.iter().map(|w| w.0).collect();
        assert_eq!(addrs, [a as u16, a as u16 + 1, a as u16 + 2, a as u16 + 3, a as u16 + 4, 0]);
        assert!(e.bytes.iter().enumerate().all(|(i, &b)| b == 0xFF || i == 0 || (a..a + 5).contains(&i)));
    }

    #[test]
    fn the_leg_length_is_never_kept() {
        let _bench = fake::lock();
        let mut s = Stored::load(Eeprom::default(), Settings::DEFAULT);
        s.set(Param::LegLengthMm, 1234.0);
        assert!(!s.pending());
        // Even a valid slot for it is not loaded: the bench's variable stays.
        let mut e = Eeprom::default();
        e.bytes[0] = MAGIC;
        let a = slot_addr(Param::LegLengthMm) as usize;
        e.bytes[a..a + 5].copy_from_slice(&encode_slot(Param::LegLengthMm, 500.0));
        bench::set_leg_length_mm(777.0);
        Stored::load(e, Settings::DEFAULT);
        assert_eq!(bench::leg_length_mm(), 777.0);
    }

    /// An EEPROM written before ids 27-31 existed (their slots erased)
    /// keeps its values and runs the new ones at their factory values,
    /// without rewriting anything.
    #[test]
    fn an_eeprom_of_the_26_parameter_layout_keeps_its_values() {
        let mut e = Eeprom::default();
        e.bytes[0] = MAGIC;
        let a = slot_addr(Param::WheelbaseMm) as usize;
        e.bytes[a..a + 5].copy_from_slice(&encode_slot(Param::WheelbaseMm, 180.0));
        assert_eq!(slot_addr(Param::BrakeCoastMs), 1 + 5 * 26);
        let mut s = Stored::load(e, Settings::DEFAULT);
        assert_eq!(s.settings.wheelbase_mm, 180.0);
        assert_eq!(s.settings.stop, Settings::DEFAULT.stop);
        assert!(!s.pending());
        s.set(Param::StopLeadMs, 250.0);
        drain(&mut s);
        let again = Stored::load(Eeprom::holding(s.store()), Settings::DEFAULT);
        assert_eq!((again.settings.wheelbase_mm, again.settings.stop.lead_ms), (180.0, 250));
    }

    #[test]
    fn a_damaged_or_out_of_range_slot_keeps_the_factory_value() {
        let mut s = Stored::load(Eeprom::default(), Settings::DEFAULT);
        s.set(Param::WheelbaseMm, 180.0);
        s.set(Param::KpLeft, 3.0);
        s.set(Param::StallDuty, 150.0);
        drain(&mut s);
        let mut e = Eeprom::holding(s.store());
        // A flipped bit in the wheelbase's value.
        e.bytes[slot_addr(Param::WheelbaseMm) as usize + 2] ^= 0x04;
        // A stall duty of 300 with a matching CRC.
        let a = slot_addr(Param::StallDuty) as usize;
        e.bytes[a..a + 5].copy_from_slice(&encode_slot(Param::StallDuty, 300.0));
        let loaded = Stored::load(e, Settings::DEFAULT).settings;
        assert_eq!(loaded.wheelbase_mm, Settings::DEFAULT.wheelbase_mm);
        assert_eq!(loaded.stall_duty, Settings::DEFAULT.stall_duty);
        assert_eq!(loaded.gains.left.kp, 3.0);
    }

    #[test]
    fn a_slot_moved_to_another_id_does_not_load() {
        // The CRC covers the id: the wheelbase's bytes in the turn's slot fail.
        let slot = encode_slot(Param::WheelbaseMm, 90.0);
        assert_eq!(decode_slot(Param::WheelbaseMm, slot), Some(90.0));
        assert_eq!(decode_slot(Param::TurnUmbmarkDeg, slot), None);
    }

    #[test]
    fn another_layout_loads_nothing_and_is_rewritten_before_the_magic() {
        let mut e = Eeprom::default();
        e.bytes[0] = MAGIC.wrapping_add(1);
        let a = slot_addr(Param::WheelbaseMm) as usize;
        e.bytes[a..a + 5].copy_from_slice(&encode_slot(Param::WheelbaseMm, 90.0));
        let mut s = Stored::load(e, Settings::DEFAULT);
        assert_eq!(s.settings, Settings::DEFAULT);
        assert!(s.pending());
        drain(&mut s);
        let e = s.store();
        assert_eq!(e.writes.last(), Some(&(0, MAGIC)));
        let again = Stored::load(Eeprom::holding(e), Settings::DEFAULT);
        assert_eq!(again.settings, Settings::DEFAULT);
        assert_eq!(&e.bytes[a..a + 5], &encode_slot(Param::WheelbaseMm, 130.0));
    }

    #[test]
    fn one_byte_per_step_and_none_while_busy() {
        let mut e = Eeprom::default();
        e.write_time = 3;
        let mut s = Stored::load(e, Settings::DEFAULT);
        s.set(Param::CorrLeft, 1.25);
        s.step();
        assert_eq!(s.store().writes.len(), 1);
        for _ in 0..3 {
            s.step();
        }
        assert_eq!(s.store().writes.len(), 1, "busy: no write");
        s.step();
        assert_eq!(s.store().writes.len(), 2);
        drain(&mut s);
        assert_eq!(s.store().writes.len(), 6);
        assert_eq!(s.store().reads_while_busy, 0);
    }

    #[test]
    fn bytes_that_hold_their_value_are_not_written_again() {
        let mut s = Stored::load(Eeprom::default(), Settings::DEFAULT);
        s.set(Param::CorrLeft, 1.25);
        drain(&mut s);
        let n = s.store().writes.len();
        s.set(Param::CorrLeft, 1.25);
        drain(&mut s);
        assert_eq!(s.store().writes.len(), n);
    }

    #[test]
    fn a_value_set_while_its_slot_is_written_ends_up_kept() {
        let mut s = Stored::load(Eeprom::default(), Settings::DEFAULT);
        s.set(Param::CorrLeft, 1.25);
        s.step();
        s.step();
        s.set(Param::CorrLeft, 0.75);
        drain(&mut s);
        let again = Stored::load(Eeprom::holding(s.store()), Settings::DEFAULT);
        assert_eq!(again.settings.correction.left, 0.75);
    }

    #[test]
    fn set_param_is_kept_across_a_reset_of_the_application() {
        let _bench = fake::lock();
        let mut app = App::fake();
        app.receive(Command::SetParam(Param::MmPerCountLeft, 0.567));
        app.receive(Command::SetParam(Param::CountsPerWheelRev, 360.0));
        for _ in 0..40 {
            app.tick_plant(0);
        }
        assert!(!app.stored.pending());
        let app = App::fake_with(Eeprom::holding(app.stored.store()));
        assert_eq!(app.stored.settings.mm_per_count.left, 0.567);
        assert_eq!(app.stored.settings.counts_per_wheel_rev, 360.0);
        // And the speed conversion is the kept geometry's from the start.
        let mut expected = crate::robust::drive::Speeds::new();
        expected.set(360.0);
        assert_eq!(app.drive.speeds.per_count, expected.per_count);
    }
}
