#!/usr/bin/env bash
# Regenerate the results pages of docs/results/: each block between
# <!-- results:NAME --> and <!-- /results:NAME --> is replaced by the output
# of the hil commands that measure it, in a fenced code block, under a line
# naming the commit it was measured at. The hand-written text around the
# blocks is left as it is. See docs/README.md ("Results").
set -euo pipefail
cd "$(dirname "$0")/.."

usage() {
  cat <<'EOF'
usage: tools/results.sh [--quick] [--only PAGE|BLOCK]... [--list] [--help]

Regenerates the generated blocks of docs/results/*.md from hil commands.

  --only NAME  regenerate one page (speed, faults, calibration, robots, timing,
               blackbox, gap-self-test, sizes, mutation) or one block (--list shows
               them); may be given more than once
  --quick      only the blocks that take a few minutes at most (leaves out
               hil bench --diagnosis, the bench-backed gap runs and the blocks
               printed by cargo tests)
  --list       list the pages, their blocks and commands, and exit
  --help       this text

The hil binary: $HIL if set, else target/release/hil, built first with
`cargo build --release -p hil`. The firmware ELFs must exist (tools/setup.sh
builds them). Each block's stderr (progress) goes to target/results/BLOCK.log.
The mutation scores are not rerun here (cargo-mutants takes hours): see
tools/mutants.sh and docs/results/mutation.md.
EOF
}

quick=0
list=0
only=()
while [ $# -gt 0 ]; do
  case "$1" in
    --quick) quick=1 ;;
    --list) list=1 ;;
    --only)
      [ $# -ge 2 ] || { echo "results: --only needs a page or block name" >&2; exit 2; }
      only+=("$2")
      shift
      ;;
    --only=*) only+=("${1#--only=}") ;;
    -h | --help) usage; exit 0 ;;
    *) echo "results: unknown argument $1" >&2; usage >&2; exit 2 ;;
  esac
  shift
done

# The blocks: page, block name, quick (1) or slow (0), the function that
# prints the block's content. Pages are docs/results/PAGE.md.
blocks=(
  "speed bench 1 block_bench"
  "speed bench-diagnosis 0 block_bench_diagnosis"
  "faults faults 1 block_faults"
  "calibration calibrate-thesis 1 block_calibrate_thesis"
  "calibration identify 1 block_identify"
  "calibration identify-holdout 0 block_identify_holdout"
  "calibration calibrate-rounds 1 block_calibrate_rounds"
  "calibration calibrate-recovery 0 block_calibrate_recovery"
  "calibration calibrate-corners 0 block_calibrate_corners"
  "calibration calibrate-line-search 1 block_calibrate_line_search"
  "robots robots 1 block_robots"
  "timing timing 1 block_timing"
  "blackbox blackbox 1 block_blackbox"
  "gap-self-test gap-self-test 1 block_gap_self_test"
  "gap-self-test gap-thesis 1 block_gap_thesis"
  "gap-self-test gap-robots 1 block_gap_robots"
  "gap-self-test gap-self-test-bench 0 block_gap_self_test_bench"
  "gap-self-test gap-thesis-bench 0 block_gap_thesis_bench"
  "sizes sizes 1 block_sizes"
)
pages=(speed faults calibration robots timing blackbox gap-self-test sizes mutation)

# One command of a block: echoed as `$ hil ...`, its stdout kept, its
# stderr to the block's log, a non-zero exit written after its output
# (a check that fails is a result too, not a reason to stop).
hil_cmd() {
  printf '$ hil %s\n' "$*"
  local rc=0
  "$HIL" "$@" 2>>"$log" || rc=$?
  [ "$rc" -eq 0 ] || printf '(exit %d)\n' "$rc"
  printf '\n'
}

# A test that prints its figures: what `cargo test --profile ci -p PACKAGE
# --test TEST -- --nocapture FILTER` prints, less the harness's own lines.
test_cmd() {
  local package=$1 test=$2 filter=$3
  printf '$ cargo test --profile ci -p %s --test %s -- --nocapture %s\n' "$package" "$test" "$filter"
  local out rc=0
  out=$(cargo test --quiet --profile ci -p "$package" --test "$test" -- --nocapture --test-threads 1 "$filter" 2>>"$log") || rc=$?
  printf '%s\n' "$out" | grep -Ev '^(running [0-9]+ tests?|test .* \.\.\. |test result: |$)' || true
  [ "$rc" -eq 0 ] || printf '(exit %d)\n' "$rc"
  printf '\n'
}

ideal=fixtures/robots/henrytwo-ideal.toml
sketch_tests=firmware/arduino/henrytwo-thesis/tests.toml

block_bench() { hil_cmd bench; }
block_bench_diagnosis() { hil_cmd bench --diagnosis --jobs 2; }
block_faults() { hil_cmd faults --all --deterministic; }
block_calibrate_thesis() {
  hil_cmd calibrate --from-csv fixtures/thesis-data/umbmark_endpoints.csv --experiment 1 --thesis-compat --deterministic
  hil_cmd calibrate --from-csv fixtures/thesis-data/umbmark_endpoints.csv --experiment 1 --deterministic
}
block_identify() {
  hil_cmd identify fixtures/thesis-data/motor_step_right.csv
  hil_cmd identify fixtures/thesis-data/motor_step_left.csv
}
block_identify_holdout() {
  test_cmd plant-model identify_physical held_out
}
block_calibrate_rounds() {
  hil_cmd calibrate --method umbmark --rounds 1 --seed 7 --deterministic
  hil_cmd calibrate --method triangle --rounds 1 --seed 7 --deterministic
}
block_calibrate_recovery() {
  test_cmd hil calibration injected_ed_and_eb
}
block_calibrate_corners() {
  test_cmd hil calibration rounds_converge
}
block_calibrate_line_search() {
  local r m
  for r in coarse65 heavy100 compact48 rover65; do
    local args=(--robot "fixtures/robots/$r.toml")
    [ "$r" = rover65 ] && args+=(--board fixtures/boards/rover65.toml)
    for m in umbmark triangle; do
      hil_cmd calibrate --method "$m" --rounds 3 "${args[@]}" --deterministic
    done
  done
}
block_robots() {
  local r
  for r in compact48 rover65; do
    local args=(--robot "fixtures/robots/$r.toml")
    [ "$r" = rover65 ] && args+=(--board fixtures/boards/rover65.toml)
    hil_cmd line --length-mm 2000 "${args[@]}" --deterministic
    hil_cmd run umbmark-cw "${args[@]}" --deterministic
    hil_cmd calibrate --rounds 2 "${args[@]}" --deterministic
  done
}
block_timing() {
  hil_cmd timing --robot "$ideal" --deterministic
  hil_cmd timing --test umbmark-cw --robot "$ideal" --deterministic
}
block_blackbox() {
  local t
  for t in umbmark-cw umbmark-ccw line triangle; do
    hil_cmd run "$t" --tests "$sketch_tests" --seed 0 --deterministic
    hil_cmd run "$t" --firmware thesis --leg-mm 400 --seed 0 --deterministic
  done
  hil_cmd run umbmark-ccw --tests fixtures/arduino/square-demo/tests.toml --deterministic
}
block_gap_self_test() { hil_cmd gap --self-test; }
# What each ELF takes of the ATmega2560's flash and SRAM, as avr-size counts it.
block_sizes() {
  local elf
  for elf in firmware/target/avr-none/release/*.elf firmware/target/arduino/*.elf; do
    printf '$ avr-size -C --mcu=atmega2560 %s\n' "$elf"
    avr-size -C --mcu=atmega2560 "$elf" | grep -E '^(Program|Data):'
    printf '\n'
  done
}
block_gap_thesis() { hil_cmd gap --real fixtures/real/thesis --model "$ideal"; }
block_gap_robots() {
  hil_cmd gap --real fixtures/real/compact48 --model fixtures/robots/compact48.toml
  hil_cmd gap --real fixtures/real/rover65 --model fixtures/robots/rover65.toml
}
block_gap_self_test_bench() { hil_cmd gap --self-test --bench --cases 14 --jobs 2; }
block_gap_thesis_bench() { hil_cmd gap --real fixtures/real/thesis --model "$ideal" --bench --jobs 2; }

if [ "$list" -eq 1 ]; then
  for b in "${blocks[@]}"; do
    read -r page name fast fn <<<"$b"
    speed=slow
    [ "$fast" -eq 1 ] && speed=quick
    printf '%-14s %-20s %-5s ' "$page" "$name" "$speed"
    declare -f "$fn" | sed -n -e 's/^ *hil_cmd \(.*\)/hil \1/p' -e 's/^ *test_cmd \(.*\)/cargo test: \1/p' |
      sed 's/;$//' | paste -sd '|' | sed 's/|/; /g'
  done
  printf '%-14s %-20s %-5s %s\n' mutation mutation-summary - "not rerun: tools/mutants.sh CRATE, then edit docs/results/mutation.md"
  exit 0
fi

# Which blocks: --only names pages or blocks; every name must exist.
selected=()
for b in "${blocks[@]}"; do
  read -r page name fast _ <<<"$b"
  want=1
  if [ ${#only[@]} -gt 0 ]; then
    want=0
    for o in "${only[@]}"; do
      [ "$o" = "$page" ] || [ "$o" = "$name" ] && want=1
    done
  fi
  [ "$quick" -eq 1 ] && [ "$fast" -eq 0 ] && want=0
  [ "$want" -eq 1 ] && selected+=("$b")
done
for o in "${only[@]}"; do
  known=0
  for p in "${pages[@]}"; do [ "$o" = "$p" ] && known=1; done
  for b in "${blocks[@]}"; do
    read -r _ name _ _ <<<"$b"
    [ "$o" = "$name" ] && known=1
  done
  [ "$known" -eq 1 ] || { echo "results: no page or block named $o (--list shows them)" >&2; exit 2; }
  if [ "$o" = mutation ]; then
    echo "results: the mutation scores are not rerun here (hours per crate): run tools/mutants.sh CRATE," >&2
    echo "         then update docs/results/mutation.md by hand with the commit it ran at" >&2
  fi
done
if [ ${#selected[@]} -eq 0 ]; then
  echo "results: nothing to regenerate" >&2
  exit 0
fi

# The firmware the commands run: built by tools/setup.sh, never committed.
fw_dir=${HIL_FIRMWARE_DIR:-firmware/target/avr-none/release}
missing=()
for elf in "$fw_dir/robust.elf" "$fw_dir/thesis.elf" \
  firmware/target/arduino/henrytwo-thesis.elf firmware/target/arduino/square-demo.elf; do
  [ -f "$elf" ] || missing+=("$elf")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "results: firmware missing: ${missing[*]}" >&2
  echo "results: run tools/setup.sh first (it builds the firmware and the sketches)" >&2
  exit 1
fi

if [ -z "${HIL:-}" ]; then
  cargo build --release --quiet -p hil
  HIL=target/release/hil
fi
[ -x "$HIL" ] || { echo "results: no hil binary at $HIL" >&2; exit 1; }

commit=$(git describe --always --dirty 2>/dev/null || echo unknown)
stamp="Regenerated by \`tools/results.sh\` at \`$commit\` on $(date -u +%Y-%m-%d) ($(nproc) cores)."
mkdir -p target/results

# Replace the block NAME of PAGE with the text in FILE.
replace_block() {
  local page=$1 name=$2 file=$3 tmp
  if ! grep -qx "<!-- results:$name -->" "$page" || ! grep -qx "<!-- /results:$name -->" "$page"; then
    echo "results: $page has no block $name (markers <!-- results:$name --> and <!-- /results:$name -->)" >&2
    return 1
  fi
  tmp=$(mktemp)
  awk -v start="<!-- results:$name -->" -v end="<!-- /results:$name -->" -v file="$file" '
    $0 == start { print; while ((getline line < file) > 0) print line; skip = 1; next }
    $0 == end { skip = 0 }
    !skip { print }
  ' "$page" >"$tmp"
  mv "$tmp" "$page"
}

for b in "${selected[@]}"; do
  read -r page name _ fn <<<"$b"
  file="docs/results/$page.md"
  log="target/results/$name.log"
  : >"$log"
  echo "results: $name ($file)" >&2
  out=$(mktemp)
  {
    printf '%s\n\n```text\n' "$stamp"
    "$fn" | sed -e :a -e '/^\n*$/{$d;N;ba' -e '}'
    printf '```\n'
  } >"$out"
  replace_block "$file" "$name" "$out"
  rm -f "$out"
done
echo "results: done; review with git diff docs/results/" >&2
