#!/usr/bin/env bash
# Checks that vendor/simavr-ffi is the published simavr-ffi crate (the files
# kept of it, listed with their hashes in pristine.sha256) with the patches
# in vendor/simavr-ffi/patches applied, and nothing else: the patches are
# taken back off a copy, and what remains must hash as published.
# Offline; needs `patch` and `sha256sum`. See vendor/simavr-ffi/VENDORED.md.
set -euo pipefail
repo="$(cd "$(dirname "$0")/.." && pwd)"
crate="$repo/vendor/simavr-ffi"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
# The crate's files, without the vendoring's own (the patches, the list, the note).
(cd "$crate" && find . -type f ! -path './patches/*' ! -name pristine.sha256 ! -name VENDORED.md \
  | sed 's|^\./||' | LC_ALL=C sort) > "$work/files"
tar -C "$crate" -cf - -T "$work/files" | tar -C "$work" --one-top-level=tree -xf -
# Taken back off in the reverse order they were applied: simavr's last first.
for p in $(ls "$crate"/patches/simavr/*.patch | LC_ALL=C sort -r); do
  patch -s -R -p1 -d "$work/tree/vendor/simavr" --no-backup-if-mismatch < "$p" || {
    echo "vendor-check: $(basename "$p") does not come off vendor/simavr-ffi/vendor/simavr cleanly: the vendored simavr was changed outside the patch files" >&2
    exit 1
  }
done
for p in $(ls "$crate"/patches/crate/*.patch | LC_ALL=C sort -r); do
  patch -s -R -p1 -d "$work/tree" --no-backup-if-mismatch < "$p" || {
    echo "vendor-check: $(basename "$p") does not come off vendor/simavr-ffi cleanly: the vendored crate was changed outside the patch files" >&2
    exit 1
  }
done
(cd "$work/tree" && LC_ALL=C sort -k2 "$crate/pristine.sha256" | sha256sum --quiet -c -) || {
  echo "vendor-check: vendor/simavr-ffi is not the published crate plus its patches (the files above differ)" >&2
  exit 1
}
listed="$(awk '{print $2}' "$crate/pristine.sha256" | LC_ALL=C sort)"
if [ "$listed" != "$(cat "$work/files")" ]; then
  echo "vendor-check: vendor/simavr-ffi holds files pristine.sha256 does not list, or lacks some it lists:" >&2
  diff <(echo "$listed") "$work/files" >&2 || true
  exit 1
fi
echo "vendor-check: vendor/simavr-ffi is simavr-ffi $(grep -m1 "^version = " "$crate/Cargo.toml" | cut -d\" -f2) as published, trimmed, plus $(ls "$crate"/patches/*/*.patch | wc -l) patches"
