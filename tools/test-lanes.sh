#!/usr/bin/env bash
# Runs the workspace's test binaries (built by `cargo test --no-run` before)
# in LANES at a time, longest first, each from its package's folder as cargo
# runs it; the doc tests run with them. `cargo test` runs one binary after
# another, and the cores idle in each binary's tail (its last test alone)
# and in the end-to-end tests that wait on a browser, a pty or a virtual
# display. Each binary's output is printed whole when it ends, with its wall
# time; the exit status is 1 if any binary failed, and the failed ones are
# named last.
#
# Usage: tools/test-lanes.sh PROFILE [LANES]
set -euo pipefail
cd "$(dirname "$0")/.."
profile="$1"
lanes="${2:-2}"

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# Every test executable with its package's folder, from cargo's own record
# of what it built (nothing is compiled here: the build came before);
# longest first, from the CI logs: the bench diagnosis' self-test, the
# end-to-end tests, the other bench diagnosis binaries; then the rest (a few
# seconds each) in cargo's order, and the doc tests.
cargo test --workspace --profile "$profile" --no-run --message-format=json 2>/dev/null |
  python3 -c '
import json, os, sys
first = ["gap_bench_selftest", "e2e", "gap_bench_joint", "gap_bench_shard", "gap_bench_thesis"]
found = []
for line in sys.stdin:
    m = json.loads(line)
    if m.get("reason") == "compiler-artifact" and m.get("executable") and m["profile"]["test"]:
        found.append((os.path.dirname(m["manifest_path"]), m["executable"], m["target"]["name"]))
rank = lambda t: first.index(t[2]) if t[2] in first else len(first)
for t in sorted(found, key=rank):
    print(*t)
print("doc")
' >"$work/queue"

# One binary (or the doc tests): its output kept, then printed with its time.
run_one() {
  local dir="$1" exe="${2:-}" name="${3:-doc tests}" out start status=0
  out="$(mktemp -p "$work")"
  start=$SECONDS
  if [ "$dir" = "doc" ]; then
    cargo test --workspace --profile "$profile" --doc >"$out" 2>&1 || status=$?
  else
    (cd "$dir" && "$exe") >"$out" 2>&1 || status=$?
  fi
  {
    echo "==== $name ($((SECONDS - start)) s, exit $status)"
    cat "$out"
  } >&2
  if [ "$status" -ne 0 ]; then
    echo "$name" >>"$work/failed"
  fi
  rm -f "$out"
}
export -f run_one
export work profile

# Each queue line is one job; xargs keeps LANES of them running.
tr '\n' '\0' <"$work/queue" | xargs -0 -P "$lanes" -I{} bash -c 'run_one {}'

if [ -s "$work/failed" ]; then
  echo "error: test binaries failed: $(tr '\n' ' ' <"$work/failed")" >&2
  exit 1
fi
