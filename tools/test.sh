#!/usr/bin/env bash
# The test suite: set up, then lint and test the host workspace (the tests
# run the real firmware ELF in the emulator) and the firmware's logic on the
# host.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
cargo fmt --all --check
# No module may depend on itself through others (the checker, then its own test).
python3 tools/module-cycles.py hil plant-model calib gap protocol firmware input-file
bash tools/module-cycles-test.sh
# The ci profile: release without link-time optimisation (see Cargo.toml).
cargo clippy --workspace --all-targets --profile ci --quiet -- -D warnings
cargo test --workspace --profile ci
# The example crate copied out of the repository, as a user has it.
tools/example-outside.sh
# The firmware's logic, linted and unit-tested on the host: run from here, cargo
# ignores firmware/.cargo/config.toml (target avr-none) and builds for the host.
cargo fmt --manifest-path firmware/Cargo.toml --check
cargo clippy --manifest-path firmware/Cargo.toml --lib --tests --quiet -- -D warnings
cargo test --manifest-path firmware/Cargo.toml --lib
