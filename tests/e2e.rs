//! The bench's end-to-end tests in one binary. Each binary of tests links the whole
//! bench (simavr, the plant, the station), so a binary per file cost a link and a copy of
//! the bench's generic code per file; here each file of tests/ is a module, left where it
//! is (its `mod support;` still finds tests/support/), and libtest runs the tests of all
//! files on the cores side by side. A new test file is two lines below, in order; the
//! `coverage` test fails if a file of tests/ is in no test binary.

// Each file declares its own `mod support;`, as it did as a binary of its own: the
// support code is compiled once per file, the files stay as they are written.
#![allow(clippy::duplicate_mod)]

#[path = "bad_inputs.rs"]
mod bad_inputs;
#[path = "blackbox.rs"]
mod blackbox;
#[path = "board.rs"]
mod board;
#[path = "calibration.rs"]
mod calibration;
#[path = "cli.rs"]
mod cli;
#[path = "experiments.rs"]
mod experiments;
#[path = "faults.rs"]
mod faults;
#[path = "firmware_geometry.rs"]
mod firmware_geometry;
#[path = "fragments.rs"]
mod fragments;
#[path = "free_run.rs"]
mod free_run;
#[path = "gdb.rs"]
mod gdb;
#[path = "golden.rs"]
mod golden;
#[path = "harness.rs"]
mod harness;
#[path = "hil_test.rs"]
mod hil_test;
#[path = "inputs.rs"]
mod inputs;
#[path = "interrupt_response.rs"]
mod interrupt_response;
#[path = "line.rs"]
mod line;
#[path = "log.rs"]
mod log;
#[path = "memory.rs"]
mod memory;
#[path = "outputs.rs"]
mod outputs;
#[path = "perf.rs"]
mod perf;
#[path = "protocol.rs"]
mod protocol;
#[path = "pty.rs"]
mod pty;
#[path = "pwm.rs"]
mod pwm;
#[path = "readme.rs"]
mod readme;
#[path = "robots.rs"]
mod robots;
#[path = "run_loop.rs"]
mod run_loop;
#[path = "sharding.rs"]
mod sharding;
#[path = "skip.rs"]
mod skip;
#[path = "station.rs"]
mod station;
#[path = "station_described.rs"]
mod station_described;
#[path = "station_ui.rs"]
mod station_ui;
#[path = "stop_timing.rs"]
mod stop_timing;
#[path = "timer_modes.rs"]
mod timer_modes;
#[path = "timing.rs"]
mod timing;
#[path = "tune.rs"]
mod tune;
#[path = "vcd.rs"]
mod vcd;

// This binary's own check that no file of tests/ is left out.
#[path = "e2e/coverage.rs"]
mod coverage;
