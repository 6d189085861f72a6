#!/usr/bin/env bash
# Mutation testing, on demand (not part of tools/test.sh or CI: it builds and
# tests the crate once per mutant). For each crate folder given (default:
# protocol), cargo-mutants changes the crate's code one small edit at a time
# and runs that crate's own tests against each edit; a mutant the tests do
# not notice ("missed") is a behaviour nothing checks. Results go to
# target/mutants/CRATE/mutants.out/ (missed.txt, caught.txt, outcomes.json).
# See docs/results/mutation.md for the last figures and the mutants left on purpose.
#
#   tools/mutants.sh                 # protocol
#   tools/mutants.sh protocol calib  # several crates, one after the other
#   MUTANTS_JOBS=2 tools/mutants.sh calib
#   tools/mutants.sh calib -- -f calib/src/umbmark.rs   # extra cargo-mutants arguments
#   MUTANTS_OPT_LEVEL=0 tools/mutants.sh calib          # build the mutated crate unoptimised
#   tools/mutants.sh firmware                           # the firmware's host-tested logic
#
# MUTANTS_OPT_LEVEL builds only the mutated package at that optimisation level
# (its dependencies stay as the ci profile builds them), incrementally: the
# same code and the same tests (no option of a profile's opt-level changes
# what the code computes; overflow checks stay off as in ci), several times
# faster to rebuild per mutant, the tests slower. Worth it for a crate whose
# tests are quick (protocol, calib), not for gap or hil.
#
# firmware: its own workspace, built for the AVR by firmware/.cargo/config.toml
# and for the host, where its unit tests run, from the repository root (as
# tools/test.sh does). The mutants run in a scratch copy of firmware/ and
# protocol/ without that config, against `cargo test --lib`, on the files the
# host tests cover (src/robust/, src/driver/, src/odometry.rs) minus the items
# compiled for the AVR only (a mutant there is never built on the host).
set -euo pipefail
cd "$(dirname "$0")/.."

crates=()
extra=()
while [ $# -gt 0 ]; do
  if [ "$1" = "--" ]; then
    shift
    extra=("$@")
    break
  fi
  crates+=("$1")
  shift
done
[ ${#crates[@]} -eq 0 ] && crates=(protocol)

if ! cargo mutants --version >/dev/null 2>&1; then
  echo "mutants: installing cargo-mutants" >&2
  cargo install cargo-mutants --locked
fi

status=0
for crate in "${crates[@]}"; do
  if [ "$crate" = firmware ]; then
    out="$PWD/target/mutants/firmware"
    scratch=$(mktemp -d)
    mkdir -p "$out"
    tar --exclude=target -c firmware protocol | tar -x -C "$scratch"
    rm -rf "$scratch/firmware/.cargo" "$scratch/firmware/rust-toolchain.toml"
    echo "mutants: firmware (host logic, scratch copy $scratch), results in $out/mutants.out" >&2
    # The host tests' profile is `test` (firmware/Cargo.toml: unoptimised already).
    (cd "$scratch/firmware" && cargo mutants --in-place --output "$out" -C --lib \
      -f 'src/robust/**' -f 'src/driver/**' -f src/odometry.rs \
      -E 'Mmio|StaticState|crate::hal::eeprom::Eeprom' "${extra[@]}") || status=$?
    rm -rf "$scratch"
    continue
  fi
  manifest="$crate/Cargo.toml"
  if [ ! -f "$manifest" ]; then
    echo "mutants: no crate folder $crate (one of: protocol plant-model calib gap hil firmware)" >&2
    exit 2
  fi
  # The package name as Cargo knows it (the folder protocol/ is henrytwo-protocol).
  package=$(sed -n 's/^name *= *"\(.*\)"/\1/p' "$manifest" | head -n 1)
  out="target/mutants/$crate"
  mkdir -p "$out"
  echo "mutants: $crate (package $package), results in $out/mutants.out" >&2
  # The tests' own profile (release without LTO); only the mutated package's
  # tests run against each mutant. Exit code 2 means some mutants were missed.
  opt=()
  if [ -n "${MUTANTS_OPT_LEVEL:-}" ]; then
    opt=(-C "--config=profile.ci.package.$package.opt-level=${MUTANTS_OPT_LEVEL}"
      -C "--config=profile.ci.incremental=true")
  fi
  # --jobs only when asked: cargo-mutants refuses it with --in-place.
  jobs=()
  [ -n "${MUTANTS_JOBS:-}" ] && jobs=(--jobs "$MUTANTS_JOBS")
  cargo mutants --package "$package" --profile ci "${jobs[@]}" \
    --output "$out" "${opt[@]}" "${extra[@]}" || status=$?
done
exit $status
