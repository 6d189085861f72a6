#!/usr/bin/env bash
# The main job: set up, then the reduced UMBmark on the emulated robot with
# the default robot config. Extra arguments go to `hil umbmark`; the report,
# its Markdown and the plots land in out/umbmark/.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
cargo build --release --quiet -p hil
exec target/release/hil umbmark --out out/umbmark "$@"
