//! The bench's clients: programs that drive a bench from outside a run.
//!
//! | where | what |
//! |---|---|
//! | `harness/` | the bench for a user's own `cargo test` ([`harness::Harness`]) |
//! | `station/` | the operator's station: the protocol client for real and emulated robots, `hil serve`, `hil ui` |
//!
//! The gdb stub is part of the bench itself (`crate::bench::gdb`), as simavr's is of its core.

pub mod harness;
pub mod station;
