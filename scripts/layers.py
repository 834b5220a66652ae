#!/usr/bin/env python3
"""Checks that the core's dependencies point one way.

Layers (src/ folders) may use only the layers listed below them, and no
two modules (files) anywhere in src/ import each other through a cycle.
A module's edges are its `crate::…` paths and `super::…` paths to
siblings, in code (not in comments: a doc link is no dependency). A parent
module using its children (parent-owned dispatch) is not a cycle. Exit 1 on a violation, listing it.
"""
import os
import re
import sys

ROOT = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "src")
if "--src" in sys.argv:
    ROOT = sys.argv[sys.argv.index("--src") + 1]
# Each layer and the layers it may use.
ALLOWED = {
    "math": set(),
    "grid": {"math"},
    "search": {"math", "grid"},
    "verify": {"math", "grid"},
    "coverage": {"math", "grid", "search", "verify"},
    "robot": {"math", "grid"},
    "localize": {"math", "grid", "robot"},
    "nav": {"math", "grid", "search", "robot"},
    "mission": {"math", "grid", "search", "verify", "coverage", "robot", "nav", "localize"},
    # The sim link's messages carry the mission's types.
    "link": {"math", "grid", "robot", "nav", "localize", "mission"},
    # The top: the firmware's sizes of everything, the mission's buffers too.
    "capacity": {"math", "grid", "search", "coverage", "localize", "robot", "mission"},
}
PATH = re.compile(r"\b(crate|super)::([a-z_0-9]+(?:::[a-z_0-9]+)*)")
GROUP = re.compile(r"\b(crate|super)::\{([^{}]*)\}")


def module_of(path):
    rel = os.path.relpath(path, ROOT)[:-3].split(os.sep)
    if rel[-1] == "mod":
        rel = rel[:-1]
    return rel


def main():
    mods, edges, bad = {}, {}, []
    for d, _, files in os.walk(ROOT):
        for f in files:
            if f.endswith(".rs") and f not in ("lib.rs", "main.rs"):
                p = os.path.join(d, f)
                mods[tuple(module_of(p))] = p
    for m, p in mods.items():
        # Code only: doc links name modules without depending on them.
        text = "\n".join(l.split("//")[0] for l in open(p).read().splitlines())
        out = set()
        found = PATH.findall(text)
        for kind, inner in GROUP.findall(text):
            found += [(kind, item.strip()) for item in inner.split(",") if item.strip()]
        for kind, path in found:
            path = re.sub(r"[^a-zA-Z_0-9:].*$", "", path)
            parts = path.split("::")
            base = list(m[:-1]) if kind == "super" else []
            if kind == "super" and os.path.basename(p) == "mod.rs":
                base = list(m[:-1])
            full = base + parts
            # the longest module prefix that exists
            for k in range(len(full), 0, -1):
                if tuple(full[:k]) in mods and tuple(full[:k]) != m:
                    out.add(tuple(full[:k]))
                    break
        edges[m] = out
        for t in out:
            a, b = m[0], t[0]
            if "--cycles-only" not in sys.argv and a != b and b not in ALLOWED.get(a, set()):
                bad.append(f"layer {a} uses {b}: {'::'.join(m)} -> {'::'.join(t)}")
    # cycles between modules, ignoring a parent using its own children
    # (the parent-owned dispatch) but not children using each other in a ring
    def child(a, b):
        return len(b) > len(a) and b[: len(a)] == a

    graph = {m: {t for t in out if not child(m, t)} for m, out in edges.items()}
    state, stack = {}, []

    def visit(m):
        state[m] = 1
        stack.append(m)
        for t in graph.get(m, ()):
            if state.get(t) == 1:
                cyc = stack[stack.index(t):] + [t]
                bad.append("cycle: " + " -> ".join("::".join(x) for x in cyc))
            elif t not in state:
                visit(t)
        stack.pop()
        state[m] = 2

    for m in sorted(graph):
        if m not in state:
            visit(m)
    print(f"{len(mods)} modules, {sum(len(v) for v in edges.values())} dependencies, "
          f"{len(bad)} problems")
    for b in bad:
        print("   ", b)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
