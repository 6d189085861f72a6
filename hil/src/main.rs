//! `hil`: the bench's command line (see [`cli`]).

#![deny(unsafe_code)]

use std::process::ExitCode;

mod cli;

fn main() -> ExitCode {
    cli::main()
}
