//! CRC-8/SMBUS: polynomial x^8 + x^2 + x + 1 (0x07), initial value 0x00,
//! no reflection, no final XOR. Check value: `crc8(b"123456789") == 0xF4`.
//!
//! Computed bit by bit (no table): on the AVR a 256-byte table would live in
//! RAM, and at 9600 baud a byte arrives only every ~1 ms anyway.

/// The generator polynomial without its x^8 term.
pub const POLY: u8 = 0x07;
/// Value the register starts from.
pub const INIT: u8 = 0x00;

/// Feeds one byte into a running CRC.
pub const fn crc8_update(crc: u8, byte: u8) -> u8 {
    let mut c = crc ^ byte;
    let mut bit = 0;
    while bit < 8 {
        c = if c & 0x80 != 0 {
            (c << 1) ^ POLY
        } else {
            c << 1
        };
        bit += 1;
    }
    c
}

/// CRC-8/SMBUS of `bytes`.
pub const fn crc8(bytes: &[u8]) -> u8 {
    let mut c = INIT;
    let mut i = 0;
    while i < bytes.len() {
        c = crc8_update(c, bytes[i]);
        i += 1;
    }
    c
}

// The catalogue check value of CRC-8/SMBUS.
const _: () = assert!(crc8(b"123456789") == 0xF4);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn check_value() {
        assert_eq!(crc8(b"123456789"), 0xF4);
        assert_eq!(crc8(&[]), 0x00);
    }

    /// A table built from the polynomial agrees with the bitwise update.
    #[test]
    fn matches_a_table_implementation() {
        let mut table = [0u8; 256];
        for (i, t) in table.iter_mut().enumerate() {
            let mut c = i as u8;
            for _ in 0..8 {
                c = if c & 0x80 != 0 {
                    (c << 1) ^ POLY
                } else {
                    c << 1
                };
            }
            *t = c;
        }
        let data: [u8; 7] = [0x05, 0x30, 0x04, 0x00, 0x00, 0xFA, 0x44];
        let mut c = INIT;
        for &b in &data {
            c = table[(c ^ b) as usize];
        }
        assert_eq!(c, crc8(&data));
    }

    /// Every single-bit error in a short frame changes the CRC.
    #[test]
    fn detects_every_single_bit_error() {
        let data = [0x06, 0x30, 0x04, 0x00, 0x00, 0xFA, 0x44];
        let good = crc8(&data);
        for byte in 0..data.len() {
            for bit in 0..8 {
                let mut d = data;
                d[byte] ^= 1 << bit;
                assert_ne!(crc8(&d), good, "byte {byte} bit {bit}");
            }
        }
    }
}
