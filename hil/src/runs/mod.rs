//! The runs built on the bench: one pipeline per kind of run.
//!
//! | where | what | command |
//! |---|---|---|
//! | `start.rs` | the host's start of a test: the robot told over the protocol, then the test started | |
//! | `experiment/` | one test on the bench: its start, legs and turns measured from the bridge, a described firmware's run | `hil run` |
//! | `odometry/` | UMBmark and Triangular Path as the thesis ran them: plans and seeds, parallel runs, shards, calibration rounds | `hil umbmark`, `hil triangle`, `hil calibrate --rounds`, `hil merge` |
//! | `line.rs` | the straight-line summary | `hil line` |
//! | `faults/` | the fault library, one file a fault, each with the reaction the firmware owes | `hil faults` |
//! | `scenario/` | scenario files: faults and a user's expectations | `hil run --scenario`, `hil test` |
//! | `golden/` | golden runs recorded and checked | `hil golden` |
//! | `tune.rs` | a robot's derived PID gains checked on the bench: step response, no chatter, settling | `hil tune` |
//! | `timing.rs` | timing budgets of the PID loop, cycle-exact | `hil timing` |
//! | `fuzz.rs` | invalid frames into the robust firmware's parser | `hil fuzz` |
//! | `gap_bench/` | the bench itself as the sim-to-real gap model | `hil gap --bench` |
//! | `calibrate.rs` | corrections from measured end points | `hil calibrate --from-csv` |
//! | `perf/` | how fast the bench runs, against raw simavr | `hil bench` |
//! | `report.rs` | the runs' results as text, for people | |

pub mod calibrate;
pub mod experiment;
pub mod faults;
pub mod fuzz;
pub mod gap_bench;
pub mod golden;
pub mod line;
pub mod odometry;
pub mod perf;
pub mod report;
pub mod scenario;
pub mod start;
pub mod timing;
pub mod tune;
