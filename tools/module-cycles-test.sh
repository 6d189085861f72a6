#!/usr/bin/env bash
# Tests tools/module-cycles.py on tiny crates written here: one without a cycle (exit 0),
# one with a cycle at the top level through a re-export, one between siblings of a folder
# module through `super::`, and the things that must not count (comments, strings, a
# `#[cfg(test)]` module, a child naming its parent).
# Usage: tools/module-cycles-test.sh
set -euo pipefail
tool="$(cd "$(dirname "$0")" && pwd)/module-cycles.py"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0

# expect NAME RC PATTERN...: the tool's exit code on crate NAME is RC and its output
# contains every PATTERN (fixed strings).
expect() {
  local name=$1 rc=$2 out got
  shift 2
  set +e
  out=$(cd "$tmp" && python3 "$tool" "$name" 2>&1)
  got=$?
  set -e
  if [ "$got" != "$rc" ]; then
    echo "FAIL $name: exit $got, expected $rc"; echo "$out"; fail=1; return
  fi
  for p in "$@"; do
    if ! grep -qF -- "$p" <<<"$out"; then
      echo "FAIL $name: no \`$p\` in:"; echo "$out"; fail=1; return
    fi
  done
  echo "ok   $name"
}

# write FILE: the rest of stdin is its text.
write() { mkdir -p "$(dirname "$tmp/$1")"; cat > "$tmp/$1"; }

# A layered crate: a -> b -> c, and what must not make an edge back.
write layered/src/lib.rs <<'EOF'
mod a;
mod b;
mod c;
pub use c::Leaf;
EOF
write layered/src/a.rs <<'EOF'
use crate::b::middle;
pub fn top() -> u32 { middle() }
EOF
write layered/src/b.rs <<'EOF'
// crate::a::top would be a cycle, but this is a comment.
pub fn middle() -> u32 { let _s = "crate::a::top"; crate::Leaf::VALUE }
EOF
write layered/src/c.rs <<'EOF'
pub struct Leaf;
impl Leaf { pub const VALUE: u32 = 1; }
#[cfg(test)]
mod tests {
    use crate::a::top;
    #[test]
    fn t() { assert_eq!(top(), super::Leaf::VALUE); }
}
EOF
expect layered 0 "layered/src/lib.rs: no module cycles"

# The same crate with the test counted: c's tests reach a, which reaches c.
cp -r "$tmp/layered" "$tmp/layered_tests"
set +e
out=$(cd "$tmp" && python3 "$tool" --with-tests layered_tests 2>&1); rc=$?
set -e
if [ $rc = 1 ] && grep -qF "cycle in crate: a -> b -> c -> a" <<<"$out"; then
  echo "ok   layered_tests (--with-tests)"
else
  echo "FAIL layered_tests: exit $rc"; echo "$out"; fail=1
fi

# A top-level cycle through a name lib.rs re-exports: b names crate::Thing, defined in a.
write reexport/src/lib.rs <<'EOF'
mod a;
mod b;
pub use a::Thing;
EOF
write reexport/src/a.rs <<'EOF'
pub struct Thing;
pub fn make() -> Thing { crate::b::helper(); Thing }
EOF
write reexport/src/b.rs <<'EOF'
use crate::Thing;
pub fn helper() -> Option<Thing> { None }
EOF
expect reexport 1 "cycle in crate: a -> b -> a" "a -> b  (reexport/src/a.rs:2)" \
  "b -> a  (reexport/src/b.rs:1)"

# Siblings inside a folder module, through super:: and a grouped use; the top level is clean.
write folder/src/lib.rs <<'EOF'
pub mod room;
EOF
write folder/src/room/mod.rs <<'EOF'
mod x;
mod y;
pub use x::run;
EOF
write folder/src/room/x.rs <<'EOF'
use super::{y::{self, Y}};
pub fn run() -> Y { y::make() }
EOF
write folder/src/room/y.rs <<'EOF'
pub struct Y;
pub fn make() -> Y { let _ = super::x::run as fn() -> Y; Y }
EOF
expect folder 1 "cycle in room: x -> y -> x" "x -> y  (folder/src/room/x.rs:1)" \
  "y -> x  (folder/src/room/y.rs:2)"

if [ $fail = 0 ]; then echo "module-cycles: all tests pass"; fi
exit $fail
