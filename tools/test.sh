#!/usr/bin/env bash
# The test suite: set up, then lint and test the host workspace (the tests
# run the real firmware ELF in the emulator) and the firmware's logic on the
# host. Each stage's wall time goes to stderr ("test.sh: ... s"), so that a
# CI log says where its minutes went.
set -euo pipefail
cd "$(dirname "$0")/.."

# Runs a stage, then prints its name and wall time.
stage() {
  local name="$1" start=$SECONDS
  shift
  "$@"
  echo "test.sh: $name: $((SECONDS - start)) s" >&2
}

# The firmware's logic, linted and unit-tested on the host: run from there,
# cargo ignores firmware/.cargo/config.toml (target avr-none) and builds for
# the host. It shares nothing with the workspace's build but the cores, so it
# runs beside the workspace's tests (many of which leave one of 2 cores idle
# for stretches), its output kept until they are done.
firmware_host() {
  cargo fmt --manifest-path firmware/Cargo.toml --check
  cargo clippy --manifest-path firmware/Cargo.toml --lib --tests --quiet -- -D warnings
  cargo test --manifest-path firmware/Cargo.toml --lib
}

stage "set-up" tools/setup.sh
cargo fmt --all --check
# The vendored simavr-ffi is the published crate plus its patch files.
tools/vendor-check.sh
# No module may depend on itself through others (the checker, then its own test).
python3 tools/module-cycles.py hil plant-model calib gap protocol firmware input-file
bash tools/module-cycles-test.sh

fw_log="$(mktemp)"
fw_start=$SECONDS
firmware_host >"$fw_log" 2>&1 &
fw_pid=$!
# A failed stage below ends the script: the firmware's checks end with it.
trap 'kill "$fw_pid" 2>/dev/null || true; rm -f "$fw_log"' EXIT

# Clippy lints the workspace as it builds: clippy-driver (what `cargo clippy`
# runs) is the compiler of the workspace's own crates in the build below, so
# each crate's front end runs once for the lints and the code, not once in
# `cargo clippy` and again in the build (about 80 s on 2 cores). The build is
# every target `cargo clippy --all-targets` lints (the workspace has no
# benches), and a lint fails it: `-D warnings`. Set for the workspace's
# commands only (the lanes list the executables with it, or cargo would
# rebuild the crates without it); the tests' own firmware build drops it.
export RUSTC_WORKSPACE_WRAPPER=clippy-driver
export CLIPPY_ARGS="-D__CLIPPY_HACKERY__warnings__CLIPPY_HACKERY__"

# The ci profile: release without link-time optimisation (see Cargo.toml).
stage "workspace build and clippy" cargo test --workspace --profile ci --no-run --quiet
# The test binaries two at a time, longest first (tools/test-lanes.sh).
stage "workspace tests" tools/test-lanes.sh ci 2
# The example crate copied out of the repository, as a user has it.
# (A user's build: the compiler itself, no lints.)
stage "example crate outside" env -u RUSTC_WORKSPACE_WRAPPER -u CLIPPY_ARGS tools/example-outside.sh

fw_status=0
wait "$fw_pid" || fw_status=$?
echo "test.sh: the firmware's host checks (run beside the above):" >&2
cat "$fw_log" >&2
if [ "$fw_status" -ne 0 ]; then
  echo "error: the firmware's host checks failed (exit $fw_status)" >&2
  exit 1
fi
echo "test.sh: firmware host checks: $((SECONDS - fw_start)) s (beside the workspace's)" >&2
