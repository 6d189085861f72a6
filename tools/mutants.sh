#!/usr/bin/env bash
# Mutation testing, on demand (not part of tools/test.sh or CI: it builds and
# tests the crate once per mutant). For each crate folder given (default:
# protocol), cargo-mutants changes the crate's code one small edit at a time
# and runs that crate's own tests against each edit; a mutant the tests do
# not notice ("missed") is a behaviour nothing checks. Results go to
# target/mutants/CRATE/mutants.out/ (missed.txt, caught.txt, outcomes.json).
# See docs/mutants.md for the last figures and the mutants left on purpose.
#
#   tools/mutants.sh                 # protocol
#   tools/mutants.sh protocol calib  # several crates, one after the other
#   MUTANTS_JOBS=2 tools/mutants.sh calib
#   tools/mutants.sh calib -- -f calib/src/umbmark.rs   # extra cargo-mutants arguments
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
  manifest="$crate/Cargo.toml"
  if [ ! -f "$manifest" ]; then
    echo "mutants: no crate folder $crate (one of: protocol plant-model calib gap hil)" >&2
    exit 2
  fi
  # The package name as Cargo knows it (the folder protocol/ is henrytwo-protocol).
  package=$(sed -n 's/^name *= *"\(.*\)"/\1/p' "$manifest" | head -n 1)
  out="target/mutants/$crate"
  mkdir -p "$out"
  echo "mutants: $crate (package $package), results in $out/mutants.out" >&2
  # The tests' own profile (release without LTO); only the mutated package's
  # tests run against each mutant. Exit code 2 means some mutants were missed.
  cargo mutants --package "$package" --profile ci --jobs "${MUTANTS_JOBS:-1}" \
    --output "$out" "${extra[@]}" || status=$?
done
exit $status
