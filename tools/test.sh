#!/usr/bin/env bash
# The test suite: set up, then lint and test the host workspace (the tests
# run the real firmware ELF in the emulator).
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
cargo fmt --all --check
# The ci profile: release without link-time optimisation (see Cargo.toml).
cargo clippy --workspace --all-targets --profile ci --quiet -- -D warnings
cargo test --workspace --profile ci
