#!/usr/bin/env bash
# Builds the Arduino sketches from source with Debian's Arduino AVR core and
# arduino-builder, as the Arduino IDE would for each sketch's board (a Mega
# 2560, an Uno or a Leonardo): the builder's prototypes, the core's flags
# (-Os, LTO), its core library. Each ELF (with its symbols) lands in
# firmware/target/arduino/NAME.elf, built from
# source and never committed.
#
# Quiet when nothing changed (an ELF newer than every file of its sketch and
# than this script is kept); on a failed build the builder's and the
# compiler's messages go to stderr and the script exits non-zero.
set -euo pipefail
cd "$(dirname "$0")/.."

# Each sketch with the board it is built for (its fqbn, as arduino-cli names it).
mega=arduino:avr:mega:cpu=atmega2560
uno=arduino:avr:uno
leonardo=arduino:avr:leonardo
sketches=(
  "firmware/arduino/henrytwo-thesis $mega"
  "fixtures/arduino/square-demo $mega"
  "fixtures/arduino/pullup-encoders $mega"
  "fixtures/arduino/int-encoders $mega"
  "fixtures/arduino/uno-l298n $uno"
  "fixtures/arduino/romi-32u4 $leonardo"
  "fixtures/arduino/uno-pcint $uno"
  "fixtures/arduino/usb-serial $leonardo"
  "fixtures/arduino/uno-one-channel $uno"
)
out=firmware/target/arduino

packages=(arduino-core-avr arduino-builder)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "build-sketches: installing ${missing[*]}" >&2
  sudo=""
  [ "$(id -u)" -ne 0 ] && sudo=sudo
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}" >/dev/null
fi

# Debian's core (1.8.7) with Debian's gcc-avr 5.4: WString.cpp uses
# DECIMAL_DIG, which that compiler's <float.h> only offers as
# __DECIMAL_DIG__. compiler.cpp.extra_flags is the core's platform.txt hook
# for C++ flags (empty there), so nothing else of the core's command changes.
prefs=(-prefs=compiler.cpp.extra_flags=-DDECIMAL_DIG=__DECIMAL_DIG__)
# The core lives in /usr/share/arduino/hardware; arduino-builder's own
# platform.txt (/usr/share/arduino-builder) names arduino-ctags, which the
# prototype generation runs.
builder=(arduino-builder -compile -quiet
  -hardware /usr/share/arduino/hardware -hardware /usr/share/arduino-builder
  -tools /usr/share/arduino-builder -warnings default)

mkdir -p "$out"
failed=0
for entry in "${sketches[@]}"; do
  read -r dir fqbn <<<"$entry"
  name=$(basename "$dir")
  elf="$out/$name.elf"
  if [ -f "$elf" ] && [ -z "$(find "$dir" tools/build-sketches.sh -newer "$elf" -print -quit)" ]; then
    continue
  fi
  build="$out/build/$name"
  mkdir -p "$build"
  log="$build/build.log"
  # arduino-builder wants the sketch's absolute path (it derives the build's
  # file names from it); its build path keeps the objects for the next run.
  if "${builder[@]}" -fqbn "$fqbn" "${prefs[@]}" -build-path "$PWD/$build" "$PWD/$dir/$name.ino" >"$log" 2>&1 \
    && [ -f "$build/$name.ino.elf" ]; then
    cp "$build/$name.ino.elf" "$elf"
  else
    echo "build-sketches: $dir failed to build:" >&2
    cat "$log" >&2
    rm -f "$elf"
    failed=1
  fi
done
exit "$failed"
