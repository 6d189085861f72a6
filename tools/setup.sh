#!/usr/bin/env bash
# Idempotent set-up on a Debian machine with Rust stable and nightly:
# system packages, the nightly's rust-src, and the firmware ELFs built from
# source. Quiet when everything is already there.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(gcc-avr avr-libc binutils-avr libelf-dev libclang-dev clang pkg-config zlib1g-dev libzstd-dev)
# The station's browser test drives Debian's Chromium through chromedriver.
packages+=(chromium chromium-driver)
# The VCD trace is checked with a real client: sigrok-cli's VCD input and UART decoder.
packages+=(sigrok-cli)
# The pty is checked with a serial library's client: Debian's pyserial (the system's python3).
packages+=(python3-serial)
# The gdb stub is checked with the real avr-gdb in batch mode.
packages+=(gdb-avr)
# Every JUnit report is validated against Jenkins' junit-10.xsd with xmllint.
packages+=(libxml2-utils)
# A moved VCD and its save file are opened by GTKWave itself, on a virtual display.
packages+=(gtkwave xvfb xauth)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}" >&2
  sudo=""
  [ "$(id -u)" -ne 0 ] && sudo=sudo
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}" >/dev/null
fi

if ! rustup +nightly component list --installed 2>/dev/null | grep -q '^rust-src'; then
  echo "setup: adding rust-src to the nightly toolchain" >&2
  rustup component add rust-src --toolchain nightly
fi

# The firmware: built from source, never committed. cargo is incremental, so
# this is about a second when nothing changed.
(cd firmware && cargo build --release --quiet 2>&1 | grep -v -e 'Linker does not support -no-pie' -e '^$' >&2 || true)
for elf in firmware/target/avr-none/release/*.elf; do
  [ -f "$elf" ] || { echo "setup: the firmware build produced no ELF" >&2; exit 1; }
done

# The Arduino sketches (the thesis' listing as printed, and sketches of our
# own written as users write them), built with Debian's Arduino core:
# firmware/target/arduino/*.elf.
tools/build-sketches.sh
