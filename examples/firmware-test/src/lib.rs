//! An example of a user's own firmware tests on the HIL bench: the tests in
//! `tests/` build a bench from a robot config, a board file and the robust
//! firmware's ELF with `hil::clients::harness`, talk to the firmware over its
//! Bluetooth UART, run until a condition holds, inject a fault and assert.
//! Copy the folder to start a crate of your own (README.md says how to point
//! it at the bench); `cargo test` runs them.
