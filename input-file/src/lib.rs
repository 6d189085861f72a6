//! One way to read an input file (a robot config, a scenario, a CSV table, a
//! manifest, an ELF, a golden file, ...), shared by every crate that reads
//! one: at most [`MAX_BYTES`], so that `/dev/zero` or a stray multi-gigabyte
//! file is refused at once instead of eating memory until the machine's limit;
//! and text without a leading UTF-8 byte order mark, so that TOML, CSV and
//! JSON written by an editor that adds one read alike. [`json_unique_keys`]
//! finds what JSON readers let pass: a key given twice.
//!
//! The errors are [`std::io::Error`]s: each caller already names the file in
//! its own error type, and an oversized file is one more reason a read fails.

use std::io::Read;
use std::path::Path;

/// The most an input file may hold: 64 MiB. The largest real input (a day of
/// telemetry at 100 Hz, an ELF with debug information) is a few MiB.
pub const MAX_BYTES: u64 = 64 * 1024 * 1024;

/// The UTF-8 byte order mark, which some editors write at a text file's start.
const BOM: &str = "\u{feff}";

/// The bytes of `path`, refused past [`MAX_BYTES`]. A regular file's size is
/// known before reading and named in the error; anything else (a device, a
/// pipe) is read up to the bound and refused when more follows, so that an
/// endless source is refused after 64 MiB, not read forever.
pub fn read_bytes(path: impl AsRef<Path>) -> std::io::Result<Vec<u8>> {
    read_bounded(path.as_ref(), MAX_BYTES)
}

/// The text of `path` (UTF-8), bounded as [`read_bytes`], without a leading
/// byte order mark.
pub fn read_text(path: impl AsRef<Path>) -> std::io::Result<String> {
    let bytes = read_bytes(path)?;
    let mut text = String::from_utf8(bytes).map_err(|e| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!(
                "not UTF-8 text (invalid byte at offset {})",
                e.utf8_error().valid_up_to()
            ),
        )
    })?;
    if text.starts_with(BOM) {
        text.drain(..BOM.len());
    }
    Ok(text)
}

/// `text` without a leading byte order mark (for text that did not come
/// from a file, e.g. an argument or a test's string).
pub fn strip_bom(text: &str) -> &str {
    text.strip_prefix(BOM).unwrap_or(text)
}

fn read_bounded(path: &Path, max: u64) -> std::io::Result<Vec<u8>> {
    let file = std::fs::File::open(path)?;
    let meta = file.metadata()?;
    if meta.is_dir() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "it is a folder, not a file",
        ));
    }
    if meta.is_file() && meta.len() > max {
        return Err(too_large(&format!("{} bytes", meta.len()), max));
    }
    let mut bytes = Vec::with_capacity(if meta.is_file() {
        meta.len() as usize
    } else {
        0
    });
    // One byte past the bound tells a file of exactly `max` bytes from a longer one.
    file.take(max + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > max {
        return Err(too_large(&format!("more than {} bytes", max), max));
    }
    Ok(bytes)
}

fn too_large(size: &str, max: u64) -> std::io::Error {
    std::io::Error::new(
        std::io::ErrorKind::InvalidData,
        format!(
            "it holds {size}; an input file may hold at most {max} bytes ({} MiB)",
            max / (1024 * 1024)
        ),
    )
}

/// Whether the JSON `text` gives no key twice in one object. A JSON reader
/// keeps the last of two (serde_json's `Value` does): a hand-edited file
/// with `"test": "line"` and later `"test": "triangle"` would be read as the
/// second without a word. The error says which key, and where.
pub fn json_unique_keys(text: &str) -> Result<(), serde_json::Error> {
    use serde::de::DeserializeSeed;
    let mut de = serde_json::Deserializer::from_str(strip_bom(text));
    Unique.deserialize(&mut de)?;
    de.end()
}

/// A JSON value walked for keys given twice, nothing kept.
struct Unique;

impl<'de> serde::de::DeserializeSeed<'de> for Unique {
    type Value = ();
    fn deserialize<D: serde::Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        d.deserialize_any(self)
    }
}

impl<'de> serde::de::Visitor<'de> for Unique {
    type Value = ();

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a JSON value")
    }

    fn visit_map<A: serde::de::MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        let mut seen = std::collections::BTreeSet::new();
        while let Some(key) = map.next_key::<String>()? {
            map.next_value_seed(Unique)?;
            if !seen.insert(key.clone()) {
                return Err(serde::de::Error::custom(format!(
                    "the key {key:?} is given twice in one object"
                )));
            }
        }
        Ok(())
    }

    fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut seq: A) -> Result<(), A::Error> {
        while seq.next_element_seed(Unique)?.is_some() {}
        Ok(())
    }

    fn visit_bool<E>(self, _: bool) -> Result<(), E> {
        Ok(())
    }
    fn visit_i64<E>(self, _: i64) -> Result<(), E> {
        Ok(())
    }
    fn visit_u64<E>(self, _: u64) -> Result<(), E> {
        Ok(())
    }
    fn visit_f64<E>(self, _: f64) -> Result<(), E> {
        Ok(())
    }
    fn visit_str<E>(self, _: &str) -> Result<(), E> {
        Ok(())
    }
    fn visit_unit<E>(self) -> Result<(), E> {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp(name: &str, bytes: &[u8]) -> std::path::PathBuf {
        let p = std::env::temp_dir().join(format!("input-file-{}-{name}", std::process::id()));
        std::fs::write(&p, bytes).unwrap();
        p
    }

    #[test]
    fn a_bom_is_dropped_and_text_kept() {
        let p = temp("bom", "\u{feff}a = 1\n".as_bytes());
        assert_eq!(read_text(&p).unwrap(), "a = 1\n");
        let p = temp("plain", b"a = 1\n");
        assert_eq!(read_text(&p).unwrap(), "a = 1\n");
    }

    #[test]
    fn an_endless_device_is_refused_after_the_bound() {
        let err = read_bounded(Path::new("/dev/zero"), 1000).unwrap_err();
        assert!(
            err.to_string().contains("holds more than 1000 bytes"),
            "{err}"
        );
    }

    #[test]
    fn a_file_past_the_bound_is_refused_by_its_size() {
        let p = temp("big", &[b'x'; 1001]);
        let err = read_bounded(&p, 1000).unwrap_err();
        assert!(err.to_string().contains("holds 1001 bytes"), "{err}");
        assert_eq!(read_bounded(&p, 1001).unwrap().len(), 1001);
    }

    #[test]
    fn a_key_given_twice_is_found_at_any_depth() {
        assert!(json_unique_keys(r#"{"a": 1, "b": [{"c": 1}, {"c": 2}]}"#).is_ok());
        let e = json_unique_keys(r#"{"a": 1, "b": {"c": 1, "c": 2}}"#).unwrap_err();
        assert!(e.to_string().contains("\"c\" is given twice"), "{e}");
        let e = json_unique_keys(r#"{"a": 1, "a": 1}"#).unwrap_err();
        assert!(e.to_string().contains("\"a\" is given twice"), "{e}");
    }

    #[test]
    fn a_folder_is_refused() {
        let err = read_bytes(std::env::temp_dir()).unwrap_err();
        assert!(err.to_string().contains("folder"), "{err}");
    }
}
