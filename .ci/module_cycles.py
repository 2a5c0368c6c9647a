#!/usr/bin/env python3
"""No import circle between the modules of a crate, at any level (issue #60).

Two reads of who uses whom, merged:
- cargo-modules draws a crate's item graph, resolved by rust-analyzer: every module, type,
  trait and function, with a `uses` edge from an item to each item its signature or a `use`
  names (an impl's methods count where their type lives) and an `owns` edge from each
  module to what it contains. It does not look into function bodies.
- so the source is read too: every path a body writes from `crate::`, `super::` or
  `self::` (`super::terrain::image(…)`), resolved to the deepest module of the graph it
  names; comments, strings and `#[cfg(test)]` modules are left out.
Every item is mapped to the module that owns it, and every use between two modules to an edge
between the two *siblings* under their nearest common ancestor that contain them: a
function in `a::x` naming a type in `b::y` is an edge a -> b at the crate's root, and
x -> y inside `a` only if both sit in `a`. A parent's own items naming a child's (or the
reverse) are not sibling edges. Any strongly connected set of siblings at any level is a
circle and fails the check, with one item-to-item use shown per link.

    module_cycles.py PACKAGE TARGET...      run cargo-modules on PACKAGE (TARGET: --lib or
                                            --bin=NAME) and check it; exit 1 on a circle
    module_cycles.py --dot FILE             check a graph already drawn (tests)
    module_cycles.py --self-test            the check fails on planted circles (one through
                                            types only, one through function bodies only)
                                            and passes once they are broken
"""
import collections
import json
import os
import re
import subprocess
import sys
import tempfile

NODE = re.compile(r'^\s*"([^"]+)" \[label="([^|"]*)\|')
EDGE = re.compile(r'^\s*"([^"]+)" -> "([^"]+)" \[label="(uses|owns)"')


def parse(dot):
    """Node kinds (`mod`, `crate`, `fn`, `struct`…) and the `uses` and `owns` edges."""
    kinds, uses, owns = {}, [], []
    for line in dot.splitlines():
        m = EDGE.match(line)
        if m:
            (uses if m.group(3) == "uses" else owns).append((m.group(1), m.group(2)))
            continue
        m = NODE.match(line)
        if m:
            kinds[m.group(1)] = m.group(2).split()[-1]
    return kinds, uses, owns


def without_tests_comments_strings(text):
    """The source with `#[cfg(test)]` modules, comments and string literals blanked."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            i = n if j < 0 else j + 2
        elif c == '"' or (c == "r" and re.match(r'r#*"', text[i:]) and not re.match(r"\w", text[i - 1:i] or " ")):
            m = re.match(r'r(#*)"', text[i:])
            if m:  # a raw string: up to the quote and as many #
                end = text.find('"' + m.group(1), i + len(m.group(0)))
                i = n if end < 0 else end + 1 + len(m.group(1))
            else:
                j = i + 1
                while j < n and text[j] != '"':
                    j += 2 if text[j] == "\\" else 1
                i = j + 1
            out.append('""')
        elif c == "'" and re.match(r"'(\\.|[^\\'])'", text[i:]):
            i += len(re.match(r"'(\\.|[^\\'])'", text[i:]).group(0))  # a char literal
        else:
            out.append(c)
            i += 1
    text = "".join(out)
    # `#[cfg(test)] mod name { … }`: dropped to its closing brace.
    while True:
        m = re.search(r"#\[cfg\(test\)\]\s*(pub(\([^)]*\))?\s+)?mod\s+\w+\s*\{", text)
        if not m:
            return text
        depth, j = 1, m.end()
        while j < len(text) and depth:
            depth += {"{": 1, "}": -1}.get(text[j], 0)
            j += 1
        text = text[: m.start()] + text[j:]


def expand(tree):
    """`a::{b, c::{d, e}}` -> ['a::b', 'a::c::d', 'a::c::e']."""
    tree = re.sub(r"\s+", "", tree)
    i = tree.find("{")
    if i < 0:
        return [tree.split("as")[0] if "::" in tree else tree]
    head, inner = tree[:i], tree[i + 1 : tree.rfind("}")]
    parts, depth, cur = [], 0, ""
    for ch in inner:
        if ch == "," and depth == 0:
            parts.append(cur)
            cur = ""
            continue
        depth += {"{": 1, "}": -1}.get(ch, 0)
        cur += ch
    parts.append(cur)
    return [head + q for p in parts if p for q in expand(p)]


def body_uses(src, crate, modules):
    """(module, the module a path names, where) for every `crate::`/`super::`/`self::`
    path written in the crate's source under `src`."""
    found = []
    for base, _, files in os.walk(src):
        for f in sorted(files):
            if not f.endswith(".rs"):
                continue
            rel = os.path.relpath(os.path.join(base, f), src)[:-3].split(os.sep)
            if rel[-1] in ("lib", "main", "mod"):
                rel = rel[:-1]
            here = [crate] + rel
            with open(os.path.join(base, f), encoding="utf-8") as fh:
                text = without_tests_comments_strings(fh.read())
            paths = [p for m in re.finditer(r"\buse\s+((?:crate|super|self)\b[^;]*);", text) for p in expand(m.group(1))]
            paths += re.findall(r"\b(?:crate|super|self)(?:::\w+)+", text)
            for path in paths:
                segs = [x for x in path.split("::") if x]
                if segs[0] == "crate":
                    full = [crate] + segs[1:]
                elif segs[0] == "self":
                    full = here + segs[1:]
                else:
                    up = list(here)
                    while segs and segs[0] == "super":
                        up, segs = up[:-1], segs[1:]
                    full = up + segs
                while full and "::".join(full) not in modules:
                    full = full[:-1]
                if full:
                    found.append(("::".join(here), "::".join(full), f"{os.path.relpath(os.path.join(base, f), src)}: {path}"))
    return found


def circles(dot, src=None, crate=None):
    """Every circle: (the parent module, the sibling modules in it, one use per link)."""
    kinds, uses, owns = parse(dot)
    modules = {p for p, k in kinds.items() if k in ("mod", "crate")}
    uses = [(u, v, f"{u} uses {v}") for u, v in uses]
    if src:
        uses += body_uses(src, crate, modules)
    owner = {child: parent for parent, child in owns if parent in modules}

    def module_of(item):
        # The module that owns the item (a method's owner is its type's module); items
        # the graph does not own are placed by their path.
        seen = set()
        while item not in modules and item not in seen:
            seen.add(item)
            item = owner.get(item) or item.rsplit("::", 1)[0]
        return tuple(item.split("::"))

    links = collections.defaultdict(dict)  # parent -> {(A, B): why}
    for u, v, why in uses:
        a, b = module_of(u), module_of(v)
        n = 0
        while n < min(len(a), len(b)) and a[n] == b[n]:
            n += 1
        if n == len(a) or n == len(b):
            continue  # the same module, or one inside the other
        links[a[:n]].setdefault((a[: n + 1], b[: n + 1]), why)
    found = []
    for parent, edges in sorted(links.items()):
        graph = collections.defaultdict(set)
        for a, b in edges:
            graph[a].add(b)
        for component in strongly_connected(graph):
            if len(component) > 1:
                inside = [(e, w) for e, w in sorted(edges.items()) if e[0] in component and e[1] in component]
                found.append((parent, sorted(component), inside))
    return found


def strongly_connected(graph):
    """Tarjan's strongly connected components of {node: {successors}}."""
    index, low, stack, on, out = {}, {}, [], set(), []
    counter = [0]
    nodes = set(graph) | {w for ws in graph.values() for w in ws}

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on.discard(w)
                component.append(w)
                if w == v:
                    break
            out.append(component)

    sys.setrecursionlimit(100000)
    for v in sorted(nodes):
        if v not in index:
            visit(v)
    return out


def report(name, dot, src=None, crate=None):
    """Prints the check of one crate's graph (and its source under `src`); True when it
    has no circle."""
    kinds, _, _ = parse(dot)
    n = sum(1 for k in kinds.values() if k in ("mod", "crate"))
    if n == 0:
        print(f"module-cycles: {name}: cargo-modules drew no module (did the crate build?)")
        return False
    found = circles(dot, src, crate)
    if not found:
        print(f"module-cycles: {name}: {n} modules, {len(kinds)} items, no circle")
        return True
    for parent, component, inside in found:
        short = lambda m: "::".join(m[len(parent):])
        print(f"module-cycles: {name}: circle in {'::'.join(parent)}: {' <-> '.join(short(m) for m in component)}")
        for (a, b), why in inside:
            print(f"    {short(a)} -> {short(b)}: {why}")
    return False


def draw(package, target, cwd="."):
    """The item graph cargo-modules draws of one target of `package`."""
    return subprocess.run(
        ["cargo", "modules", "dependencies", "--package", package, target,
         "--no-externs", "--no-sysroot"],
        cwd=cwd, check=True, capture_output=True, text=True).stdout


def target(package, kind, cwd="."):
    """The source directory and crate name of `package`'s `--lib` or `--bin=NAME`."""
    meta = json.loads(subprocess.run(
        ["cargo", "metadata", "--no-deps", "--format-version", "1"],
        cwd=cwd, check=True, capture_output=True, text=True).stdout)
    for p in meta["packages"]:
        if p["name"] != package:
            continue
        for t in p["targets"]:
            if (kind == "--lib" and "lib" in t["kind"]) or kind == f"--bin={t['name']}":
                return os.path.dirname(t["src_path"]), t["name"].replace("-", "_")
    raise SystemExit(f"module-cycles: no target {kind} in package {package}")


def check(package, kind, cwd="."):
    """Checks one target of `package`; True when it has no circle."""
    src, crate = target(package, kind, cwd)
    return report(package, draw(package, kind, cwd), src, crate)


# Planted circles for the self-test: `a` and `b` name each other only through a field's
# type and a function's return type (no module-level `use` either way); `c` and `d` only
# inside function bodies (which cargo-modules' graph does not see). `clean` is the same
# crate with both circles broken.
PLANTED = {
    "src/lib.rs": "pub mod a;\npub mod b;\npub mod c;\npub mod d;\n",
    "src/a.rs": "pub struct A {\n    pub b: crate::b::B,\n}\n",
    "src/b.rs": "pub struct B;\n\npub fn make() -> crate::a::A {\n    crate::a::A { b: B }\n}\n",
    "src/c.rs": "pub fn f() -> u32 {\n    super::d::g() + 1\n}\n\npub fn h() -> u32 {\n    2\n}\n",
    "src/d.rs": "pub fn g() -> u32 {\n    crate::c::h() * 3\n}\n",
}
CLEAN = dict(PLANTED)
CLEAN["src/b.rs"] = "pub struct B;\n"
CLEAN["src/d.rs"] = "pub fn g() -> u32 {\n    // crate::c::h() in a comment is no use\n    3\n}\n"


def self_test():
    """The check fails on each planted circle, and cargo-modules' graph alone misses the
    one in function bodies; it passes once both are broken."""
    ok = True
    with tempfile.TemporaryDirectory() as tmp:
        results = {}
        for name, files in [("planted", PLANTED), ("clean", CLEAN)]:
            root = os.path.join(tmp, name)
            files = dict(files)
            files["Cargo.toml"] = f'[package]\nname = "{name}"\nversion = "0.1.0"\nedition = "2024"\n\n[workspace]\n'
            for path, text in files.items():
                os.makedirs(os.path.dirname(os.path.join(root, path)), exist_ok=True)
                with open(os.path.join(root, path), "w") as f:
                    f.write(text)
            dot = draw(name, "--lib", cwd=root)
            results[name] = (circles(dot), circles(dot, os.path.join(root, "src"), name))
        graph_only, both = results["planted"]
        pairs = lambda found: sorted(tuple(m[-1] for m in comp) for _, comp, _ in found)
        expect = [
            ("planted: the type-level circle a <-> b and the body-level c <-> d fail",
             pairs(both) == [("a", "b"), ("c", "d")]),
            ("planted: cargo-modules' graph alone sees a <-> b but not c <-> d",
             pairs(graph_only) == [("a", "b")]),
            ("clean: no circle", results["clean"][1] == []),
        ]
        for what, good in expect:
            print(f"module-cycles: self-test: {what}: {'ok' if good else 'FAILED'}")
            ok &= good
        if not ok:
            for name, (_, found) in results.items():
                print(f"    {name}: {found}")
    return ok


def main(argv):
    if argv[:1] == ["--self-test"]:
        return 0 if self_test() else 1
    if argv[:1] == ["--dot"]:
        with open(argv[1]) as f:
            return 0 if report(argv[1], f.read()) else 1
    if len(argv) != 2:
        print(__doc__)
        return 2
    return 0 if check(argv[0], argv[1]) else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
