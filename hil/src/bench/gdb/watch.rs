//! Watchpoints: which data bytes an instruction reads and writes, decoded
//! from its opcode and the registers before it runs (exact for every load,
//! store, push, pop, call, return and IO instruction of the ATmega2560), and
//! a before/after comparison of the watched bytes for what no instruction
//! decodes (an interrupt's entry pushing the PC, a peripheral or the bench
//! itself changing a byte). Nothing of this runs while no watchpoint is set.

/// What a watchpoint stops on (gdb's `watch`, `rwatch`, `awatch`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum WatchKind {
    Write,
    Read,
    Access,
}

impl WatchKind {
    pub(super) fn of(z_type: u8) -> Option<Self> {
        match z_type {
            2 => Some(Self::Write),
            3 => Some(Self::Read),
            4 => Some(Self::Access),
            _ => None,
        }
    }

    /// The stop reply's name for it.
    fn reply_name(self) -> &'static str {
        match self {
            Self::Write => "watch",
            Self::Read => "rwatch",
            Self::Access => "awatch",
        }
    }

    fn sees(self, write: bool) -> bool {
        match self {
            Self::Write => write,
            Self::Read => !write,
            Self::Access => true,
        }
    }
}

/// One watchpoint on data-space bytes `addr .. addr + len`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Watch {
    pub kind: WatchKind,
    pub addr: u16,
    pub len: u16,
}

/// One data-space access of an instruction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Access {
    pub addr: u16,
    pub write: bool,
}

/// The registers an instruction's addresses come from.
pub(super) struct Regs {
    pub x: u16,
    pub y: u16,
    pub z: u16,
    pub sp: u16,
}

/// IO addresses (`in`, `out`, `sbi`, ...) start at data address 0x20.
const IO_BASE: u16 = 0x20;

/// The data accesses of the instruction `op` (`next`: the word after it,
/// the address of `lds`/`sts`), in the order it makes them. Calls and
/// returns move the 3-byte PC of a 256 KiB part.
pub(super) fn accesses(op: u16, next: u16, r: &Regs) -> Vec<Access> {
    let read = |addr: u16| Access { addr, write: false };
    let write = |addr: u16| Access { addr, write: true };
    let io = IO_BASE + (((op >> 5) & 0x30) | (op & 0x0f));
    let io_bit = IO_BASE + ((op >> 3) & 0x1f);
    match op & 0xfe0f {
        0x9000 => return vec![read(next)],
        0x9200 => return vec![write(next)],
        0x900c | 0x900d => return vec![read(r.x)],
        0x900e => return vec![read(r.x.wrapping_sub(1))],
        0x9009 => return vec![read(r.y)],
        0x900a => return vec![read(r.y.wrapping_sub(1))],
        0x9001 => return vec![read(r.z)],
        0x9002 => return vec![read(r.z.wrapping_sub(1))],
        0x900f => return vec![read(r.sp.wrapping_add(1))],
        0x920c | 0x920d => return vec![write(r.x)],
        0x920e => return vec![write(r.x.wrapping_sub(1))],
        0x9209 => return vec![write(r.y)],
        0x920a => return vec![write(r.y.wrapping_sub(1))],
        0x9201 => return vec![write(r.z)],
        0x9202 => return vec![write(r.z.wrapping_sub(1))],
        0x920f => return vec![write(r.sp)],
        _ => {}
    }
    let push_pc = || (0..3).map(|i| write(r.sp.wrapping_sub(i))).collect();
    let pop_pc = || (1..4).map(|i| read(r.sp.wrapping_add(i))).collect();
    match op {
        0x9509 | 0x9519 => return push_pc(),
        0x9508 | 0x9518 => return pop_pc(),
        _ => {}
    }
    if op & 0xfe0e == 0x940e || op & 0xf000 == 0xd000 {
        return push_pc();
    }
    if op & 0xd200 == 0x8000 || op & 0xd200 == 0x8200 {
        // ldd/std (ld/st through Y or Z without a change of the pointer).
        let q = ((op >> 8) & 0x20) | ((op >> 7) & 0x18) | (op & 0x07);
        let base = if op & 0x08 != 0 { r.y } else { r.z };
        let at = base.wrapping_add(q);
        return vec![if op & 0x0200 != 0 {
            write(at)
        } else {
            read(at)
        }];
    }
    match op & 0xf800 {
        0xb000 => return vec![read(io)],
        0xb800 => return vec![write(io)],
        _ => {}
    }
    match op & 0xff00 {
        // sbic, sbis
        0x9900 | 0x9b00 => vec![read(io_bit)],
        // cbi, sbi: read, modify, write.
        0x9800 | 0x9a00 => vec![read(io_bit), write(io_bit)],
        _ => Vec::new(),
    }
}

/// The first watchpoint an access or a change hits: the stop reply's
/// `watch:ADDR;` part (ADDR in avr-gdb's map, data from `data_offset`).
pub(super) fn hit(
    watches: &[Watch],
    accesses: &[Access],
    changed: &[u16],
    data_offset: u32,
) -> Option<String> {
    let within = |w: &Watch, a: u16| a >= w.addr && (a - w.addr) < w.len;
    let found = watches.iter().find_map(|w| {
        accesses
            .iter()
            .find(|a| within(w, a.addr) && w.kind.sees(a.write))
            .map(|a| a.addr)
            .or_else(|| {
                changed
                    .iter()
                    .copied()
                    .find(|a| within(w, *a) && w.kind.sees(true))
            })
            .map(|a| (w.kind, a))
    })?;
    let (kind, addr) = found;
    Some(format!(
        "{}:{:x};",
        kind.reply_name(),
        data_offset + u32::from(addr)
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    const R: Regs = Regs {
        x: 0x200,
        y: 0x300,
        z: 0x400,
        sp: 0x21ff,
    };

    fn one(op: u16, next: u16) -> (u16, bool) {
        let a = accesses(op, next, &R);
        assert_eq!(a.len(), 1, "{op:04x}: {a:?}");
        (a[0].addr, a[0].write)
    }

    #[test]
    fn loads_and_stores_decode_to_their_address() {
        // lds r24, 0x0123 / sts 0x0123, r24
        assert_eq!(one(0x9180, 0x0123), (0x0123, false));
        assert_eq!(one(0x9380, 0x0123), (0x0123, true));
        // ld r24, X+ / st -X, r24 / ld r24, -Z / st Y+, r24
        assert_eq!(one(0x918d, 0), (0x200, false));
        assert_eq!(one(0x938e, 0), (0x1ff, true));
        assert_eq!(one(0x9182, 0), (0x3ff, false));
        assert_eq!(one(0x9389, 0), (0x300, true));
        // ldd r24, Y+5 / std Z+63, r24 / ld r24, Z (ldd q = 0)
        assert_eq!(one(0x818d, 0), (0x305, false));
        assert_eq!(one(0xaf87, 0), (0x43f, true));
        assert_eq!(one(0x8180, 0), (0x400, false));
        // push r24 / pop r24
        assert_eq!(one(0x938f, 0), (0x21ff, true));
        assert_eq!(one(0x918f, 0), (0x2200, false));
        // in r24, 0x3f (SREG at 0x5f) / out 0x05, r24 (PORTB at 0x25)
        assert_eq!(one(0xb78f, 0), (0x5f, false));
        assert_eq!(one(0xb985, 0), (0x25, true));
        // sbis 0x03, 2 (PINB at 0x23)
        assert_eq!(one(0x9b1a, 0), (0x23, false));
        // sbi 0x05, 1: read then write PORTB
        let rmw = accesses(0x9a29, 0, &R);
        assert_eq!(
            rmw.iter().map(|a| (a.addr, a.write)).collect::<Vec<_>>(),
            [(0x25, false), (0x25, true)]
        );
        // call, rcall, ret move three bytes; add r24, r25 none; lpm none.
        assert_eq!(accesses(0x940e, 0x1234, &R).len(), 3);
        assert!(accesses(0xd001, 0, &R).iter().all(|a| a.write));
        assert!(accesses(0x9508, 0, &R).iter().all(|a| !a.write));
        assert!(accesses(0x0f89, 0, &R).is_empty());
        assert!(accesses(0x9004, 0, &R).is_empty());
    }

    #[test]
    fn a_hit_names_the_kind_and_the_byte() {
        let w = [Watch {
            kind: WatchKind::Write,
            addr: 0x200,
            len: 2,
        }];
        let store = [Access {
            addr: 0x201,
            write: true,
        }];
        let load = [Access {
            addr: 0x201,
            write: false,
        }];
        assert_eq!(
            hit(&w, &store, &[], 0x80_0000).as_deref(),
            Some("watch:800201;")
        );
        assert_eq!(hit(&w, &load, &[], 0x80_0000), None);
        assert_eq!(
            hit(&w, &[], &[0x200], 0x80_0000).as_deref(),
            Some("watch:800200;")
        );
        assert_eq!(hit(&w, &[], &[0x202], 0x80_0000), None);
        let r = [Watch {
            kind: WatchKind::Read,
            ..w[0]
        }];
        assert_eq!(
            hit(&r, &load, &[], 0x80_0000).as_deref(),
            Some("rwatch:800201;")
        );
        let a = [Watch {
            kind: WatchKind::Access,
            ..w[0]
        }];
        assert_eq!(
            hit(&a, &store, &[], 0x80_0000).as_deref(),
            Some("awatch:800201;")
        );
    }
}
