#!/usr/bin/env bash
# The example crate as a user has it: examples/firmware-test copied to a
# folder outside this repository, its one `hil` line pointing here by path,
# its tests run with `cargo test` there. The firmware ELFs are found through
# HIL_FIRMWARE_DIR, as a user's own build would be. It shares this
# repository's target folder and lock file, so the dependencies are not built
# again; the bench's own crates are (a fingerprint names the workspace it was
# built in), and the next build here rebuilds them once more.
set -euo pipefail
repo="$(cd "$(dirname "$0")/.." && pwd)"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
cp -r "$repo/examples/firmware-test" "$out/"
crate="$out/firmware-test"
# The one line a user writes: hil by path (or by git, see the crate's README).
sed -i "s|^hil = { path = \"../../hil\" }$|hil = { path = \"$repo/hil\" }|" "$crate/Cargo.toml"
grep -q "^hil = { path = \"$repo/hil\" }$" "$crate/Cargo.toml" || {
  echo "example-outside: examples/firmware-test/Cargo.toml has no 'hil = { path = \"../../hil\" }' line to point here" >&2
  exit 1
}
# The same versions of every dependency as here, and the same test profile
# (a profile of a workspace is not seen from outside it: a config file is).
cp "$repo/Cargo.lock" "$crate/"
mkdir -p "$crate/.cargo"
# (The repository's ci profile, as written there; the release profile's
# link-time settings do not apply to it.)
cat > "$crate/.cargo/config.toml" <<'TOML'
[profile.release]
debug = 1
[profile.ci]
inherits = "release"
lto = false
codegen-units = 16
debug = "line-tables-only"
[profile.ci.package."*"]
debug = 0
TOML
# The bench's own crates are compiled again here whatever the profile: a path
# dependency's fingerprint names the workspace it was built in. Unoptimised,
# as a user's default `cargo test` builds them, that second build is about a
# third of its optimised CPU time; the dependencies stay the shared ones.
for own in hil gap calib plant-model henrytwo-protocol input-file simavr-ffi; do
  printf '[profile.ci.package.%s]\nopt-level = 0\ndebug = 0\n' "$own" >> "$crate/.cargo/config.toml"
done
cd "$crate"
HIL_FIRMWARE_DIR="$repo/firmware/target/avr-none/release" CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$repo/target}" \
  cargo test --profile ci --quiet
