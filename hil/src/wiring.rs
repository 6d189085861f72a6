//! The wiring table's former path: the board description now lives in
//! [`crate::board`] (one definition, loadable from a board TOML); these
//! names stay for the code that uses them.

pub use crate::board::{
    Board as Wiring, BridgeInput, EncoderWiring, LedWiring, MotorWiring, Pin, PwmSource, HENRYTWO,
};
