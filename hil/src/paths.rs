//! Default locations of the firmware and the robot configs in this repository.

use std::path::PathBuf;

/// The repository root (the host workspace).
pub fn workspace_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(PathBuf::from)
        .unwrap_or_default()
}

/// The firmware build `name` ("robust" or "thesis"), as `cargo build
/// --release` in firmware/ leaves it. `HIL_FIRMWARE_DIR` overrides the folder.
pub fn firmware_elf(name: &str) -> PathBuf {
    let dir = std::env::var_os("HIL_FIRMWARE_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| workspace_root().join("firmware/target/avr-none/release"));
    dir.join(format!("{name}.elf"))
}

/// The reference robot: the best estimate of the thesis' Henrytwo, the
/// config the bench and the station use unless told otherwise.
pub const REFERENCE_ROBOT: &str = "henrytwo";

/// A robot config in fixtures/robots/.
pub fn robot_config(name: &str) -> PathBuf {
    workspace_root()
        .join("fixtures/robots")
        .join(format!("{name}.toml"))
}
