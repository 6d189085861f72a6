//! The operator's station: one protocol client for the emulated and the real
//! robot ([`client`]), the emulated robot behind a pseudo-terminal paced to
//! the wall clock ([`emulated`]), and the web page that replaces the
//! thesis' MATLAB GUI ([`session`], [`ui`]).

pub mod client;
pub mod emulated;
pub mod session;
pub mod ui;
