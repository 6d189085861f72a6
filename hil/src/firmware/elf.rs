//! Firmware images: flash segments and symbols read from an AVR ELF file.
//!
//! The bench loads flash itself instead of through simavr's loader: a Rust
//! ELF carries no `.mmcu` section, and the bench needs the symbol table anyway
//! (to read the firmware's variables and to name the function a PC is in).
//!
//! The bench emulates one MCU, the ATmega2560, so an ELF built for another is
//! refused before it runs (its registers, pins and vectors are elsewhere: it
//! would run as nonsense): by its architecture in `e_flags` (the 2560's
//! family is avr6), by the device the toolchain wrote in the
//! `.note.gnu.avr.deviceinfo` note, and by simavr's `.mmcu` section. An ELF
//! that names no device is accepted.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use object::elf::{EF_AVR_ARCH, EF_AVR_ARCH_AVR6, EM_AVR, PT_LOAD};
use object::read::elf::{ElfFile32, FileHeader, ProgramHeader};
use object::{Endianness, Object, ObjectSection, ObjectSymbol, SymbolKind};
use thiserror::Error;

use crate::mcu::clock::Clock;

/// AVR ELF files put data space at this offset in the address space.
pub const DATA_OFFSET: u32 = 0x80_0000;

/// The MCU the bench emulates, as avr-gcc's `-mmcu` names it.
pub const DEVICE: &str = "atmega2560";

#[derive(Debug, Error)]
pub enum ElfError {
    #[error("cannot read firmware {path}: {source} (build it with `cargo build --release` in firmware/, or pass --elf)")]
    Read {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{path} is not an ELF file: {reason}")]
    NotElf { path: PathBuf, reason: String },
    #[error("{path} is an ELF for machine {machine}, not for the AVR (machine 83); pass the firmware's ELF")]
    NotAvr { path: PathBuf, machine: u16 },
    #[error("{path} is built for {device}; the bench emulates the {DEVICE}: rebuild it with -mmcu={DEVICE}")]
    OtherDevice { path: PathBuf, device: String },
    #[error("{path} is built for the AVR architecture {arch} (e_flags 0x{flags:x}); the bench emulates the {DEVICE}, an avr6: rebuild it with -mmcu={DEVICE}")]
    OtherArch {
        path: PathBuf,
        arch: String,
        flags: u32,
    },
    #[error("{path} has no loadable flash segment")]
    Empty { path: PathBuf },
    #[error("the firmware has no symbol {name:?}")]
    MissingSymbol { name: String },
    #[error("symbol {name:?} has {actual} bytes, the bench expects {expected}")]
    SymbolSize {
        name: String,
        expected: u64,
        actual: u64,
    },
}

/// A symbol: its address (flash byte address, or data-space address for
/// variables) and size in bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Symbol {
    pub addr: u32,
    pub size: u64,
    pub is_data: bool,
}

/// Where in the firmware something happened (see [`Firmware::location`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Location {
    pub cycle: u64,
    pub robot_time_s: f64,
    pub pc: u32,
    pub function: Option<String>,
}

impl std::fmt::Display for Location {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "at robot time {:.6} s (cycle {}), PC 0x{:05x}",
            self.robot_time_s, self.cycle, self.pc
        )?;
        if let Some(func) = &self.function {
            write!(f, " in {func}")?;
        }
        Ok(())
    }
}

/// A loaded firmware image.
#[derive(Debug, Clone)]
pub struct Firmware {
    pub path: PathBuf,
    /// (flash byte address, bytes), in address order.
    pub segments: Vec<(u32, Vec<u8>)>,
    symbols: BTreeMap<String, Symbol>,
    /// Function symbols by start address, to name a PC.
    functions: BTreeMap<u32, (String, u64)>,
}

impl Firmware {
    pub fn load(path: &Path) -> Result<Self, ElfError> {
        let bytes = input_file::read_bytes(path).map_err(|source| ElfError::Read {
            path: path.to_owned(),
            source,
        })?;
        Self::parse(path, &bytes)
    }

    pub fn parse(path: &Path, bytes: &[u8]) -> Result<Self, ElfError> {
        let not_elf = |reason: String| ElfError::NotElf {
            path: path.to_owned(),
            reason,
        };
        if bytes.len() < 20 || &bytes[..4] != b"\x7fELF" {
            return Err(not_elf("no ELF magic number".into()));
        }
        if bytes[4] != 1 {
            // AVR ELFs are 32-bit; say which machine a 64-bit file is for.
            let machine = u16::from_le_bytes([bytes[18], bytes[19]]);
            return Err(ElfError::NotAvr {
                path: path.to_owned(),
                machine,
            });
        }
        let file = ElfFile32::<Endianness>::parse(bytes).map_err(|e| not_elf(e.to_string()))?;
        let endian = file.endian();
        let header = file.elf_header();
        let machine = header.e_machine(endian);
        if machine != EM_AVR {
            return Err(ElfError::NotAvr {
                path: path.to_owned(),
                machine,
            });
        }
        // The device first: its name says more than its family.
        if let Some(device) = declared_device(&file).filter(|d| !d.eq_ignore_ascii_case(DEVICE)) {
            return Err(ElfError::OtherDevice {
                path: path.to_owned(),
                device,
            });
        }
        let flags = header.e_flags(endian);
        if flags & EF_AVR_ARCH != EF_AVR_ARCH_AVR6 {
            return Err(ElfError::OtherArch {
                path: path.to_owned(),
                arch: arch_name(flags & EF_AVR_ARCH),
                flags,
            });
        }
        let mut segments = Vec::new();
        for ph in file.elf_program_headers() {
            if ph.p_type(endian) != PT_LOAD || ph.p_filesz(endian) == 0 {
                continue;
            }
            let paddr = ph.p_paddr(endian);
            if paddr >= DATA_OFFSET {
                // Data-space images (EEPROM, fuses): not flash.
                continue;
            }
            let data = ph
                .data(endian, bytes)
                .map_err(|_| not_elf("truncated program segment".into()))?;
            segments.push((paddr, data.to_vec()));
        }
        if segments.is_empty() {
            return Err(ElfError::Empty {
                path: path.to_owned(),
            });
        }
        segments.sort_by_key(|(a, _)| *a);

        let mut symbols = BTreeMap::new();
        let mut functions = BTreeMap::new();
        for sym in file.symbols() {
            let Ok(name) = sym.name() else { continue };
            if name.is_empty() {
                continue;
            }
            let addr = sym.address() as u32;
            let is_data = addr >= DATA_OFFSET;
            let s = Symbol {
                addr: if is_data { addr - DATA_OFFSET } else { addr },
                size: sym.size(),
                is_data,
            };
            if sym.kind() == SymbolKind::Text && !is_data {
                // Rust's mangled names are unreadable in a report; `{:#}`
                // leaves out the hash suffix.
                let readable = format!("{:#}", rustc_demangle::demangle(name));
                functions.insert(addr, (readable, sym.size()));
            }
            symbols.entry(name.to_owned()).or_insert(s);
        }
        Ok(Self {
            path: path.to_owned(),
            segments,
            symbols,
            functions,
        })
    }

    /// A firmware of flash alone, without symbols: the hand-assembled
    /// programs tests run on the bench (named by `path`'s file stem).
    pub fn from_flash(path: &Path, segments: Vec<(u32, Vec<u8>)>) -> Self {
        Self {
            path: path.to_owned(),
            segments,
            symbols: BTreeMap::new(),
            functions: BTreeMap::new(),
        }
    }

    /// The build's name: the ELF's file stem ("robust", "thesis").
    pub fn name(&self) -> String {
        self.path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default()
    }

    pub fn symbol(&self, name: &str) -> Result<Symbol, ElfError> {
        self.symbols
            .get(name)
            .copied()
            .ok_or_else(|| ElfError::MissingSymbol { name: name.into() })
    }

    /// A data variable of exactly `size` bytes; returns its data-space address.
    pub fn variable(&self, name: &str, size: u64) -> Result<u16, ElfError> {
        let s = self.symbol(name)?;
        if !s.is_data {
            return Err(ElfError::MissingSymbol { name: name.into() });
        }
        if s.size != size {
            return Err(ElfError::SymbolSize {
                name: name.into(),
                expected: size,
                actual: s.size,
            });
        }
        Ok(s.addr as u16)
    }

    /// The ELF name of the function called `name`: that symbol, or a C++
    /// function of that plain name without arguments (`PID` is `_Z3PIDv`),
    /// or, failing that, the only C++ overload of that name.
    pub fn function_named(&self, name: &str) -> Option<&str> {
        let is_function = |n: &str| self.functions.values().any(|(f, _)| f == n);
        if is_function(name) {
            return self.symbols.get_key_value(name).map(|(k, _)| k.as_str());
        }
        let prefix = format!("_Z{}{name}", name.len());
        let mut overloads = self
            .functions
            .values()
            .map(|(f, _)| f.as_str())
            .filter(|f| f.starts_with(&prefix));
        let all: Vec<&str> = overloads.by_ref().collect();
        all.iter()
            .find(|f| f.len() == prefix.len() + 1 && f.ends_with('v'))
            .copied()
            .or_else(|| (all.len() == 1).then(|| all[0]))
    }

    /// The function containing flash byte address `pc`, with the offset into it.
    pub fn function_at(&self, pc: u32) -> Option<(&str, u32)> {
        let (start, (name, size)) = self.functions.range(..=pc).next_back()?;
        if *size == 0 || pc < start + *size as u32 {
            Some((name.as_str(), pc - start))
        } else {
            None
        }
    }

    /// Where the firmware is when it executes `pc` at `cycle`.
    pub fn location(&self, clock: Clock, cycle: u64, pc: u32) -> Location {
        Location {
            cycle,
            robot_time_s: clock.seconds(cycle).0,
            pc,
            function: self
                .function_at(pc)
                .map(|(name, off)| format!("{name}+0x{off:x}")),
        }
    }

    /// A content hash of the flash image (FNV-1a, 64 bits, hex): two ELFs
    /// with the same hash load the same program.
    pub fn content_hash(&self) -> String {
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        for (addr, bytes) in &self.segments {
            for b in addr.to_le_bytes().iter().chain(bytes) {
                h ^= *b as u64;
                h = h.wrapping_mul(0x0000_0100_0000_01b3);
            }
        }
        format!("{h:016x}")
    }

    /// Flash bytes used.
    pub fn flash_size(&self) -> usize {
        self.segments.iter().map(|(_, b)| b.len()).sum()
    }
}

/// The device an ELF says it is built for: the name in avr-gcc's
/// `.note.gnu.avr.deviceinfo` note, else in simavr's `.mmcu` section.
fn declared_device(file: &ElfFile32<Endianness>) -> Option<String> {
    let section = |name: &str| file.section_by_name(name).and_then(|s| s.data().ok());
    section(".note.gnu.avr.deviceinfo")
        .and_then(note_device)
        .or_else(|| section(".mmcu").and_then(mmcu_device))
}

/// The device name of an AVR device-info note (binutils' layout, little
/// endian): namesz, descsz, type, the name "AVR" padded to 4 bytes, then the
/// description: flash start and size, RAM start and size, EEPROM start and
/// size (six words), the offset table's length in bytes (counting itself)
/// and its offsets, the first of which points into the string table that
/// follows at the device's name.
fn note_device(note: &[u8]) -> Option<String> {
    let word = |b: &[u8], at: usize| -> Option<usize> {
        Some(u32::from_le_bytes(b.get(at..at + 4)?.try_into().ok()?) as usize)
    };
    let namesz = word(note, 0)?;
    let descsz = word(note, 4)?;
    let desc_at = 12 + namesz.div_ceil(4) * 4;
    let desc = note.get(desc_at..desc_at.checked_add(descsz)?)?;
    let table_len = word(desc, 24)?;
    let strings = desc.get(24usize.checked_add(table_len)?..)?;
    let name_at = word(desc, 28)?;
    c_string(strings.get(name_at..)?)
}

/// The device name of simavr's `.mmcu` section: records of a tag byte, a
/// length byte and that many bytes; tag 1 (`AVR_MMCU_TAG_NAME`) is the name.
fn mmcu_device(mut records: &[u8]) -> Option<String> {
    const AVR_MMCU_TAG_NAME: u8 = 1;
    while let [tag, len, rest @ ..] = records {
        let data = rest.get(..*len as usize)?;
        if *tag == AVR_MMCU_TAG_NAME {
            return c_string(data);
        }
        records = &rest[*len as usize..];
    }
    None
}

/// The NUL-terminated text at the start of `bytes`, when it is not empty.
fn c_string(bytes: &[u8]) -> Option<String> {
    let end = bytes.iter().position(|&b| b == 0).unwrap_or(bytes.len());
    let name = std::str::from_utf8(&bytes[..end]).ok()?.trim();
    (!name.is_empty()).then(|| name.to_owned())
}

/// binutils' name of an `EF_AVR_ARCH_*` number ("avr5", "avrxmega2").
fn arch_name(arch: u32) -> String {
    match arch {
        0 => "none (e_flags names no AVR architecture)".into(),
        100 => "avrtiny".into(),
        101..=107 => format!("avrxmega{}", arch - 100),
        n => format!("avr{n}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// binutils' note for the atmega2560, as in our Rust builds.
    const NOTE_2560: &[u8] = b"\x04\0\0\0\x2d\0\0\0\x01\0\0\0AVR\0\
        \0\0\0\0\0\0\x04\0\0\x02\0\0\0\x20\0\0\0\0\0\0\0\x10\0\0\
        \x08\0\0\0\x01\0\0\0\0atmega2560\0\0\0\0\0";

    #[test]
    fn the_device_note_names_the_device() {
        assert_eq!(note_device(NOTE_2560).as_deref(), Some("atmega2560"));
        assert_eq!(note_device(&NOTE_2560[..20]), None, "truncated: no name");
    }

    #[test]
    fn the_mmcu_section_names_the_device() {
        let mut s = vec![2, 4, 0, 0x24, 0xf4, 0]; // frequency first
        s.extend([1, 11]);
        s.extend(b"atmega328p\0");
        s.extend([0, 0]);
        assert_eq!(mmcu_device(&s).as_deref(), Some("atmega328p"));
        assert_eq!(mmcu_device(&[0, 0]), None);
        assert_eq!(mmcu_device(&[1, 40, b'a']), None, "truncated");
    }

    #[test]
    fn rejects_non_elf_with_a_reason() {
        let err = Firmware::parse(Path::new("x.bin"), b"hello world, not an elf").unwrap_err();
        assert!(matches!(err, ElfError::NotElf { .. }), "{err}");
        assert!(err.to_string().contains("not an ELF"));
    }

    #[test]
    fn rejects_host_elf_naming_the_machine() {
        // The test binary itself is an ELF for the host (x86-64: machine 62).
        let exe = std::env::current_exe().unwrap();
        let err = Firmware::load(&exe).unwrap_err();
        match err {
            ElfError::NotAvr { machine, .. } => assert_ne!(machine, EM_AVR),
            other => panic!("expected NotAvr, got {other}"),
        }
    }

    #[test]
    fn missing_file_says_how_to_build() {
        let err = Firmware::load(Path::new("does/not/exist.elf")).unwrap_err();
        assert!(err.to_string().contains("cargo build --release"), "{err}");
    }
}
