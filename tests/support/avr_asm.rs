//! AVR instruction words for the hand-assembled programs of the tests that
//! check simavr against the datasheet (instruction set manual encodings).

/// `ldi r, k` (r16..r31).
pub fn ldi(r: u16, k: u8) -> u16 {
    let k = k as u16;
    0xE000 | (k & 0xF0) << 4 | (r - 16) << 4 | (k & 0x0F)
}

/// `sts addr, r`.
pub fn sts(addr: u16, r: u16) -> [u16; 2] {
    [0x9200 | r << 4, addr]
}

/// `jmp word` (a word address).
pub fn jmp(word: u16) -> [u16; 2] {
    [0x940C, word]
}
