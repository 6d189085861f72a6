#!/usr/bin/env bash
# The main job: set up, then run the bench's main test on the emulated robot.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
exec cargo run --release --quiet -p hil -- line --length-mm 2000 "$@"
