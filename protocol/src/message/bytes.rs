//! Little-endian values at an offset of a payload, as every multi-byte value travels;
//! `None` where the bytes run short, so a short payload is an error, not a panic.

pub(super) fn f32_at(b: &[u8], at: usize) -> Option<f32> {
    let bytes: [u8; 4] = b.get(at..at + 4)?.try_into().ok()?;
    Some(f32::from_le_bytes(bytes))
}

pub(super) fn u32_at(b: &[u8], at: usize) -> Option<u32> {
    let bytes: [u8; 4] = b.get(at..at + 4)?.try_into().ok()?;
    Some(u32::from_le_bytes(bytes))
}

pub(super) fn u16_at(b: &[u8], at: usize) -> Option<u16> {
    let bytes: [u8; 2] = b.get(at..at + 2)?.try_into().ok()?;
    Some(u16::from_le_bytes(bytes))
}

/// Copies `src` to the start of `out`; `None` if it does not fit.
pub(super) fn put(out: &mut [u8], at: usize, src: &[u8]) -> Option<()> {
    out.get_mut(at..at + src.len())?.copy_from_slice(src);
    Some(())
}
