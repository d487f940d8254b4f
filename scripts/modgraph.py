#!/usr/bin/env python3
"""Import circles between the modules of each workspace crate.

For every crate, each source file is a module (`src/a/b.rs` and
`src/a/b/mod.rs` are `a::b`). A path a module names (`use crate::…`,
`super::…`, `self::…`, or inline `crate::…` in code) is resolved to the
deepest module it reaches; an edge joins the two modules at the level where
their paths part (so `sim::closed_loop` naming `sim::record` is an edge
closed_loop → record among the children of `sim`, and `scene` naming
`sim::SimError` is scene → sim among the crate's top-level modules).
References between a module and its own ancestors or descendants are not
edges (a parent declares its children; `super::` items are the parent's),
and test code (`#[cfg(test)]` items, `tests.rs`, `tests/`) is left out.

Prints every circle (strongly connected component of two or more
siblings) with one edge that closes it, and every import from a declared
layer to one above it (LAYERS), and exits 1 if there is any;
`--graph` also prints every edge, `--dot FILE` writes the graph for
Graphviz (the crates and their normal dependencies, then each crate's
modules), and `--check-dot FILE` fails when FILE is not what `--dot` would
write now (CI keeps docs/modules.dot current; docs/modules.svg is
`dot -Tsvg docs/modules.dot`).

    python3 scripts/modgraph.py [--graph] [--dot FILE | --check-dot FILE] [crate …]
"""
import os
import re
import sys
from collections import defaultdict

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CRATES = ["lie", "dynamics", "controllers", "integrators", "sensors", "missions", "scenarios", "logs", "scenes", "studies",
          "geopid", "cli", "xtask", "python", "testkit", "capi"]
# Layers of a crate's top-level modules, bottom first: a module may name
# modules of its own layer or below, never above. Every top-level module
# of such a crate must be placed (a new one fails until it is). Between
# crates the layers are cargo's: the engine (`scenarios`) below the logs
# and the scenes, the studies on top.
LAYERS = {
    "scenes": [
        ("format", ["error", "scene", "reference"]),
        ("scenes", ["builtin", "estimators", "overrides", "registry", "scene_simulation", "run_report", "sources"]),
    ],
    "studies": [
        ("metrics", ["metrics"]),
        ("studies", ["gains", "montecarlo", "regress", "stress", "sensitivity", "sensing", "missions", "estimation", "held_out"]),
        ("figures", ["figures"]),
    ],
}


def layer_violations(crate, edges):
    """Imports from a layer to one above it, and top-level modules in no
    layer; empty when the crate has no layers declared."""
    if crate not in LAYERS:
        return []
    rank = {m: i for i, (_, mods) in enumerate(LAYERS[crate]) for m in mods}
    names = [name for name, _ in LAYERS[crate]]
    found = []
    top = edges.get((), set())
    src = os.path.join(ROOT, crate, "src")
    # Every top-level module, imported or not: `x.rs` or a folder `x/`.
    modules = {n[:-3] if n.endswith(".rs") else n for n in os.listdir(src)
               if n.endswith(".rs") or os.path.isdir(os.path.join(src, n))}
    modules -= {"lib", "main", "tests"}
    for m in sorted(modules - set(rank)):
        found.append(f"{crate}::{m} is in no layer (scripts/modgraph.py LAYERS)")
    for a, b in sorted(top):
        if a in rank and b in rank and rank[a] < rank[b]:
            found.append(f"{crate}: {a} ({names[rank[a]]}) imports {b} ({names[rank[b]]}), a layer above it")
    return found


def module_of(src, path):
    rel = os.path.relpath(path, src)[:-3].split(os.sep)
    if rel[-1] == "mod":
        rel = rel[:-1]
    if rel in (["lib"], ["main"]):
        return ()
    return tuple(rel)


def strip_tests(text):
    """Drops `#[cfg(test)]` items (a `mod tests { … }` or a `use` line) and
    comments, so that test-only imports do not count."""
    text = re.sub(r"//[^\n]*", "", text)
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    out, i = [], 0
    for m in re.finditer(r"#\[cfg\(test\)\]", text):
        if m.start() < i:
            continue
        out.append(text[i:m.start()])
        j = m.end()
        # The item: up to its `;` or through its balanced braces.
        k = j
        while k < len(text) and text[k] not in "{;":
            k += 1
        if k < len(text) and text[k] == "{":
            depth = 0
            while k < len(text):
                depth += {"{": 1, "}": -1}.get(text[k], 0)
                k += 1
                if depth == 0:
                    break
        else:
            k += 1
        i = k
    out.append(text[i:])
    return "".join(out)


def expand_use(tree):
    """`a::{b, c::{d, e}}` → [a::b, a::c::d, a::c::e]."""
    tree = re.sub(r"\s+", "", tree)
    m = re.match(r"^(.*?)\{(.*)\}$", tree)
    if not m:
        return [re.sub(r"as\w+$", "", tree)]
    prefix, inner = m.group(1), m.group(2)
    parts, depth, cur = [], 0, ""
    for ch in inner:
        if ch == "," and depth == 0:
            parts.append(cur)
            cur = ""
            continue
        depth += {"{": 1, "}": -1}.get(ch, 0)
        cur += ch
    parts.append(cur)
    out = []
    for p in parts:
        if p:
            out += [prefix + q for q in expand_use(p)]
    return out


def paths_in(text):
    for m in re.finditer(r"\buse\s+([^;]+);", text):
        for p in expand_use(m.group(1)):
            yield p
    for m in re.finditer(r"\b((?:crate|super|self)(?:::\w+)+)", text):
        yield m.group(1)


def resolve(path, here, modules):
    segs = path.split("::")
    if segs[0] == "crate":
        base, rest = (), segs[1:]
    elif segs[0] in ("super", "self"):
        base = here
        while segs and segs[0] in ("super", "self"):
            if segs[0] == "super":
                base = base[:-1]
            segs = segs[1:]
        rest = segs
    else:
        return None
    target = base
    for s in rest:
        if target + (s,) in modules:
            target = target + (s,)
        else:
            break
    return target


def crate_graph(crate):
    src = os.path.join(ROOT, crate, "src")
    if not os.path.isdir(src):
        return None
    files = {}
    for d, _, names in os.walk(src):
        for n in names:
            if n.endswith(".rs"):
                p = os.path.join(d, n)
                mod = module_of(src, p)
                if mod and mod[-1] == "tests":
                    continue
                files[mod] = p
    modules = set(files)
    edges = defaultdict(set)
    for mod, p in files.items():
        text = strip_tests(open(p, encoding="utf-8").read())
        for path in paths_in(text):
            t = resolve(path, mod, modules)
            if t is None:
                continue
            k = 0
            while k < min(len(mod), len(t)) and mod[k] == t[k]:
                k += 1
            if k == len(mod) or k == len(t):
                continue  # the same module, an ancestor or a descendant
            edges[mod[:k]].add((mod[k], t[k]))
    return edges


def circles(pairs):
    """Strongly connected components with two or more nodes (Tarjan)."""
    graph = defaultdict(set)
    for a, b in pairs:
        graph[a].add(b)
        graph.setdefault(b, set())
    index, low, stack, on, out, n = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = n[0]
        n[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def crate_deps(crate):
    """The workspace crates `crate` names under [dependencies] (normal
    dependencies only: dev and build dependencies are not layers)."""
    deps, section = [], None
    with open(os.path.join(ROOT, crate, "Cargo.toml"), encoding="utf-8") as f:
        for line in f:
            line = line.strip()
            if line.startswith("["):
                section = line
                continue
            name = line.split("=", 1)[0].strip()
            # A dependency is keyed by its folder's name or by its package's.
            name = name[len("geopid-"):] if name.startswith("geopid-") else name
            if section == "[dependencies]" and name in CRATES and name != crate:
                deps.append(name)
    return deps


def main(argv):
    show = "--graph" in argv
    dot, check = None, None
    for flag in ("--dot", "--check-dot"):
        if flag in argv:
            value = argv[argv.index(flag) + 1]
            argv = [a for a in argv if a not in (flag, value)]
            dot, check = (value, check) if flag == "--dot" else (dot, value)
    crates = [a for a in argv if not a.startswith("--")] or CRATES
    found, lines = 0, ["digraph modules {", "  rankdir=LR; node [shape=box, fontsize=10];"]
    lines.append('  subgraph "cluster_crates" { label="crates (normal dependencies)";')
    for crate in crates:
        lines.append(f'    "{crate}" [style=bold];')
        for dep in crate_deps(crate):
            lines.append(f'    "{crate}" -> "{dep}";')
    lines.append("  }")
    for crate in crates:
        edges = crate_graph(crate)
        if edges is None:
            continue
        lines.append(f'  subgraph "cluster_{crate}" {{ label="{crate}";')
        for parent, pairs in sorted(edges.items()):
            where = "::".join((crate,) + parent)
            for a, b in sorted(pairs):
                if show:
                    print(f"{where}: {a} -> {b}")
                lines.append(f'    "{where}::{a}" -> "{where}::{b}";')
            for comp in circles(pairs):
                found += 1
                inner = sorted((a, b) for a, b in pairs if a in comp and b in comp)
                print(f"circle in {where}: {' , '.join(comp)} (edges: "
                      + ", ".join(f"{a} -> {b}" for a, b in inner) + ")")
        lines.append("  }")
        for v in layer_violations(crate, edges):
            found += 1
            print(v)
        if crate in LAYERS and not layer_violations(crate, edges):
            print(f"{crate}: layers {' < '.join(n for n, _ in LAYERS[crate])}, every import goes down or sideways")
    lines.append("}")
    text = "\n".join(lines) + "\n"
    if dot:
        with open(dot, "w", encoding="utf-8") as f:
            f.write(text)
    if check:
        with open(check, encoding="utf-8") as f:
            if f.read() != text:
                print(f"{check} is not the current module graph: "
                      f"python3 scripts/modgraph.py --dot {check} && dot -Tsvg {check} -o {check[:-4]}.svg")
                return 1
        print(f"{check} is the current module graph")
    if found:
        print(f"{found} import circle(s) or layer violation(s)")
        return 1
    print(f"no import circles among the modules of {', '.join(crates)}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
