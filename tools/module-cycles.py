#!/usr/bin/env python3
"""Print the dependency cycles between a crate's modules; exit 1 if there is any.

Usage: python3 tools/module-cycles.py [--with-tests] CRATE_DIR...

A cycle makes a crate harder to read as a set of rooms: no module of it can be understood
(or moved) on its own. For each crate root (src/lib.rs, src/main.rs, src/bin/*.rs) this
reads the module tree (`mod x;` and inline `mod x { }`) and every path that names another
module: `use` trees, `crate::a::b`, `super::x`, `self::x` and paths through a name
imported with `use`. A name re-exported by a parent (`pub use a::Thing;` in lib.rs) is
followed to the module that defines it, so `crate::Thing` counts as a use of `a`.

Nodes are the children of one module: the crate's top-level modules, and the sibling
modules inside each folder module. A reference from anywhere inside child X (its own
submodules included) to something inside sibling Y is an edge X -> Y; a module naming its
parent or its own children is no edge. Every elementary cycle is printed with, for each
edge, the first place that makes it.

`#[cfg(test)]` modules are left out (a test may reach across the layers it tests) unless
--with-tests is given. Macros' bodies are read as plain code; `$crate` is ignored.
Stdlib only.
"""

import os
import re
import sys

IDENT = r"[A-Za-z_][A-Za-z0-9_]*"
TOKEN = re.compile(r"\s+|(?P<id>r#" + IDENT + "|" + IDENT + r")|(?P<p>::|[{}();,*#\[\]=!<>]|.)", re.S)


def strip(text):
    """Blank out comments, strings and char literals, keeping line numbers."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text.startswith("/*", i):
            depth, j = 1, i + 2
            while j < n and depth:
                if text.startswith("/*", j):
                    depth, j = depth + 1, j + 2
                elif text.startswith("*/", j):
                    depth, j = depth - 1, j + 2
                else:
                    j += 1
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif re.match(r'(b?r#*")', text[i:i + 40]) and (i == 0 or not re.match(r"\w", text[i - 1])):
            m = re.match(r'b?r(#*)"', text[i:])
            end = text.find('"' + m.group(1), i + m.end())
            j = n if end < 0 else end + 1 + len(m.group(1))
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == '"':
            j = i + 1
            while j < n and text[j] != '"':
                j += 2 if text[j] == "\\" else 1
            j += 1
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == "'":
            # A char literal ('a', '\n', '\u{1F600}'), else a lifetime or label.
            m = re.match(r"'(\\u\{[0-9a-fA-F]+\}|\\.|[^\\'])'", text[i:], re.S)
            j = i + (m.end() if m else 1)
            out.append(" " * (j - i) if m else "'")
            i = j
        else:
            out.append(c)
            i += 1
    return "".join(out)


def tokens(text):
    line = 1
    for m in TOKEN.finditer(text):
        s = m.group(0)
        if m.group("id") or m.group("p"):
            yield s, line
        line += s.count("\n")


class Module:
    def __init__(self, path, file, dir_for_children, parent):
        self.path = path  # tuple of names from the crate root
        self.file = file
        self.dir = dir_for_children  # where `mod x;` inside it looks for x.rs / x/mod.rs
        self.parent = parent
        self.children = {}
        self.imports = {}  # name -> absolute path (a list of names) named by a `use`
        self.globs = []  # absolute paths of `use path::*`
        self.refs = []  # (path as written, line, file, scope module)


def expand_use(toks, i):
    """Parse a use tree from toks[i:]; return (list of (segments, alias), next index)."""
    results = []

    def tree(i, prefix):
        segs = list(prefix)
        while i < len(toks):
            t = toks[i][0]
            if t == "::":
                i += 1
            elif t == "{":
                i += 1
                while toks[i][0] != "}":
                    i = tree(i, segs)
                    if toks[i][0] == ",":
                        i += 1
                return i + 1
            elif t == "*":
                results.append((segs, "*"))
                return i + 1
            elif t in (",", "}", ";"):
                if segs and segs[-1] == "self":
                    segs = segs[:-1]
                if segs:
                    results.append((segs, segs[-1]))
                return i
            elif t == "as":
                alias = toks[i + 1][0]
                if segs and segs[-1] == "self":
                    segs = segs[:-1]
                results.append((segs, alias))
                return i + 2
            else:
                segs = segs + [t]
                i += 1
        return i

    i = tree(i, [])
    while i < len(toks) and toks[i][0] != ";":
        i += 1
    return results, i + 1


class Crate:
    def __init__(self, root_file, with_tests):
        self.with_tests = with_tests
        self.modules = {}
        d = os.path.dirname(root_file)
        self.root = self.load((), root_file, d, None)

    def load(self, path, file, child_dir, parent):
        m = Module(path, file, child_dir, parent)
        self.modules[path] = m
        with open(file, encoding="utf-8") as f:
            toks = list(tokens(strip(f.read())))
        self.parse(m, toks, 0, file, top=True)
        return m

    def parse(self, m, toks, i, file, top):
        """Read the items of module m from toks[i:] until its closing brace (or the end)."""
        depth = 0
        cfg_test = False
        while i < len(toks):
            t, line = toks[i]
            if t == "#" and i + 1 < len(toks) and toks[i + 1][0] in ("[", "!"):
                j = i + (2 if toks[i + 1][0] == "[" else 3)
                k, d = j, 1
                while k < len(toks) and d:
                    d += {"[": 1, "]": -1}.get(toks[k][0], 0)
                    k += 1
                attr = " ".join(x for x, _ in toks[j:k - 1])
                if re.fullmatch(r"cfg \( test \)", attr):
                    cfg_test = True
                i = k
                continue
            if t == "{":
                depth += 1
            elif t == "}":
                if depth == 0 and not top:
                    return i + 1
                depth -= 1
            if t == "mod" and i + 2 < len(toks) and re.fullmatch(IDENT, toks[i + 1][0]):
                name, nxt = toks[i + 1][0], toks[i + 2][0]
                skip = cfg_test and not self.with_tests
                if nxt == ";":
                    if not skip:
                        self.load_file_module(m, name)
                    i += 3
                    cfg_test = False
                    continue
                if nxt == "{":
                    child = Module(m.path + (name,), file, os.path.join(m.dir, name), m)
                    end = self.parse(child, toks, i + 3, file, top=False)
                    if not skip:
                        self.modules[child.path] = child
                        m.children[name] = child
                    i = end
                    cfg_test = False
                    continue
            if t == "use":
                uses, j = expand_use(toks, i + 1)
                for segs, alias in uses:
                    m.refs.append((segs, line, file, m))
                    absolute = self.absolute(m, segs)
                    if absolute is None:
                        continue
                    if alias == "*":
                        m.globs.append(absolute)
                    else:
                        m.imports[alias] = absolute
                i = j
                cfg_test = False
                continue
            if t in ("crate", "super", "self") and i + 1 < len(toks) and toks[i + 1][0] == "::" \
                    and not (i > 0 and toks[i - 1][0] in ("$", "::")):
                segs, j = [t], i + 1
                while j + 1 < len(toks) and toks[j][0] == "::" and re.fullmatch(IDENT, toks[j + 1][0]):
                    segs.append(toks[j + 1][0])
                    j += 2
                m.refs.append((segs, line, file, m))
                i = j
                continue
            if re.fullmatch(IDENT, t) and i + 1 < len(toks) and toks[i + 1][0] == "::" \
                    and not (i > 0 and toks[i - 1][0] == "::"):
                # A path through a name in scope: a child module or an imported name.
                segs, j = [t], i + 1
                while j + 1 < len(toks) and toks[j][0] == "::" and re.fullmatch(IDENT, toks[j + 1][0]):
                    segs.append(toks[j + 1][0])
                    j += 2
                m.refs.append((["self"] + segs, line, file, m))
                i = j
                continue
            if t in (";", "}"):
                cfg_test = False
            i += 1
        return i

    def load_file_module(self, parent, name):
        for cand, child_dir in ((os.path.join(parent.dir, name + ".rs"), os.path.join(parent.dir, name)),
                                (os.path.join(parent.dir, name, "mod.rs"), os.path.join(parent.dir, name))):
            if os.path.isfile(cand):
                parent.children[name] = self.load(parent.path + (name,), cand, child_dir, parent)
                return
        print(f"warning: module {'::'.join(parent.path + (name,))} not found under {parent.dir}",
              file=sys.stderr)

    def absolute(self, m, segs):
        """The path segs written in module m as a list of names from the root, if internal."""
        if not segs:
            return None
        if segs[0] == "crate":
            return list(segs[1:])
        if segs[0] in ("super", "self"):
            base = list(m.path)
            k = 0
            while k < len(segs) and segs[k] in ("super", "self"):
                if segs[k] == "super":
                    if not base:
                        return None
                    base.pop()
                k += 1
            return base + list(segs[k:])
        # 2018 edition: a use path may start with a child module or an imported name.
        return list(m.path) + list(segs)

    def resolve(self, absolute, seen=0):
        """The deepest module that the absolute path reaches, following re-exports."""
        m = self.modules[()]
        for k, seg in enumerate(absolute):
            if seg in m.children:
                m = m.children[seg]
            elif seg in m.imports and seen < 20:
                return self.resolve(m.imports[seg] + absolute[k + 1:], seen + 1)
            else:
                for g in m.globs:
                    if seen < 20:
                        target = self.resolve(g + absolute[k:], seen + 1)
                        if target is not None and target.path != tuple(g) and target is not m:
                            return target
                return m
        return m

    def scope_path(self, m, segs):
        """Absolute path of a reference, looking names up in m's scope like rustc does."""
        if segs[0] == "self" and len(segs) > 1 and segs[1] not in m.children:
            name = segs[1]
            if name in m.imports:
                return m.imports[name] + segs[2:]
            if name in ("crate", "super", "self"):
                return self.absolute(m, segs[1:])
            return None  # an extern crate, std, or a local type's associated item
        return self.absolute(m, segs)

    def edges(self):
        """{parent path: {(a, b): (file, line)}} between the children of each module."""
        out = {}
        for m in self.modules.values():
            for segs, line, file, scope in m.refs:
                absolute = self.scope_path(scope, segs)
                if absolute is None:
                    continue
                target = self.resolve(absolute)
                if target is None:
                    continue
                src, dst = m.path, target.path
                k = 0
                while k < len(src) and k < len(dst) and src[k] == dst[k]:
                    k += 1
                if k == len(src) or k == len(dst):
                    continue  # an ancestor or a descendant
                key = (src[k], dst[k])
                level = out.setdefault(src[:k], {})
                if key not in level:
                    level[key] = (file, line)
        return out


def cycles(nodes, edges):
    """Every elementary cycle (Johnson's algorithm, small graphs), each starting at its least node."""
    adj = {n: sorted(b for (a, b) in edges if a == n) for n in nodes}
    order = sorted(nodes)
    found = []
    for s_idx, s in enumerate(order):
        allowed = set(order[s_idx:])
        stack, blocked, bmap = [s], set([s]), {}

        def unblock(u):
            blocked.discard(u)
            for w in bmap.pop(u, set()):
                if w in blocked:
                    unblock(w)

        def circuit(v):
            closed = False
            for w in adj[v]:
                if w not in allowed:
                    continue
                if w == s:
                    found.append(list(stack))
                    closed = True
                elif w not in blocked:
                    stack.append(w)
                    blocked.add(w)
                    if circuit(w):
                        closed = True
                    stack.pop()
            if closed:
                unblock(v)
            else:
                for w in adj[v]:
                    if w in allowed:
                        bmap.setdefault(w, set()).add(v)
            return closed

        circuit(s)
    return found


def roots(crate_dir):
    src = os.path.join(crate_dir, "src")
    out = [os.path.join(src, f) for f in ("lib.rs", "main.rs") if os.path.isfile(os.path.join(src, f))]
    bins = os.path.join(src, "bin")
    if os.path.isdir(bins):
        out += sorted(os.path.join(bins, f) for f in os.listdir(bins) if f.endswith(".rs"))
    return out


def main(argv):
    with_tests = "--with-tests" in argv
    dirs = [a for a in argv if a != "--with-tests"]
    if not dirs or any(a.startswith("-") for a in dirs):
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        return 2
    total = 0
    for d in dirs:
        files = roots(d)
        if not files:
            print(f"{d}: no src/lib.rs, src/main.rs or src/bin/*.rs", file=sys.stderr)
            return 2
        for root_file in files:
            crate = Crate(root_file, with_tests)
            name = os.path.relpath(root_file)
            n_crate = 0
            for parent, level in sorted(crate.edges().items()):
                nodes = set(crate.modules[parent].children)
                for cyc in cycles(nodes, level):
                    n_crate += 1
                    where = "crate" if not parent else "::".join(parent)
                    print(f"{name}: cycle in {where}: {' -> '.join(cyc + [cyc[0]])}")
                    for a, b in zip(cyc, cyc[1:] + cyc[:1]):
                        f, line = level[(a, b)]
                        print(f"    {a} -> {b}  ({os.path.relpath(f)}:{line})")
            if n_crate == 0:
                print(f"{name}: no module cycles ({len(crate.modules)} modules)")
            total += n_crate
    return 1 if total else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
