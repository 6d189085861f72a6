//! The firmware under test, as the bench sees it.
//!
//! | where | what |
//! |---|---|
//! | `elf.rs` | firmware images: flash segments and symbols read from an AVR ELF |
//! | `vars.rs` | the bench builds' bench interface: `HT_` variables read from SRAM by symbol |
//! | `params.rs` | what the firmware is told about the robot before a run, and what it then believes |
//! | `settings.rs` | the robot config's `[firmware]` table: gains, set-points, thresholds, checked |
//! | `stop.rs` | stop timing (coast, counter-pulse, lead) and watchdog thresholds derived for a robot |
//! | `tune.rs` | PID gains derived for a robot from its motor model and encoders; chatter predicted on a loop model |
//! | `link.rs` | the host's side of the framed protocol (`henrytwo-protocol`) |
//! | `description/` | firmware that knows nothing of the bench, run from a test description |
//!
//! Below the bench: nothing here runs an MCU.

pub mod description;
pub mod elf;
pub mod link;
pub mod params;
pub mod settings;
pub mod stop;
pub mod tune;
pub mod vars;
