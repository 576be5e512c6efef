#!/usr/bin/env python3
"""The include graph of the project's sources: no header cycle, and no layer that includes one
above it (docs/architecture.md): the physics core includes nothing of the shape pipeline, the MPI
folder, the run drivers or the protocol; parallel/ nothing of app/. Exit 1 naming each offence.
  include_graph.py ROOT        check the tree at ROOT
  include_graph.py --self-test plant a cycle and an upward include in a scratch tree and expect both"""
import os
import re
import sys
import tempfile

SOURCES = ("common", "dynamics_server", "protocol", "viz_client", "haptic_client")
# folder -> include prefixes it must not use (its layers above, and MPI outside parallel/)
FORBIDDEN = {
    "dynamics_server/core/": ("app/", "parallel/", "shape/", "server/", "codec/", "client/", "recording/", "mpi.h"),
    "dynamics_server/shape/": ("app/", "parallel/", "mpi.h"),
    "dynamics_server/parallel/": ("app/",),
}
INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]([^>"]+)[>"]', re.M)


def scan(root):
    files = []
    for top in SOURCES:
        for d, _, names in os.walk(os.path.join(root, top)):
            files += [os.path.relpath(os.path.join(d, n), root) for n in names if n.endswith((".hpp", ".h", ".cpp"))]
    headers = {f for f in files if f.endswith((".hpp", ".h"))}
    by_tail = {}
    for h in headers:
        parts = h.split("/")
        for k in range(len(parts)):
            by_tail.setdefault("/".join(parts[k:]), []).append(h)
    graph, offences = {}, []
    for f in files:
        with open(os.path.join(root, f), encoding="utf-8", errors="replace") as src:
            includes = INCLUDE.findall(src.read())
        for prefix, banned in FORBIDDEN.items():
            if f.startswith(prefix):
                offences += [f"{f} includes {i}, a layer above {prefix}" for i in includes if i.startswith(banned)]
        if f in headers:
            deps = []
            for i in includes:
                here = os.path.normpath(os.path.join(os.path.dirname(f), i))
                deps += [here] if here in headers else by_tail.get(i, [])[:1]
            graph[f] = deps
    state, stack = {}, []

    def visit(u):
        state[u] = 1
        stack.append(u)
        for v in graph.get(u, []):
            if state.get(v) == 1:
                offences.append("include cycle: " + " -> ".join(stack[stack.index(v):] + [v]))
            elif v not in state:
                visit(v)
        stack.pop()
        state[u] = 2

    for u in sorted(graph):
        if u not in state:
            visit(u)
    return len(files), offences


def self_test():
    with tempfile.TemporaryDirectory() as root:
        core = os.path.join(root, "dynamics_server", "core")
        os.makedirs(core)
        with open(os.path.join(core, "A.hpp"), "w") as f:
            f.write('#include "B.hpp"\n')
        with open(os.path.join(core, "B.hpp"), "w") as f:
            f.write('#include "A.hpp"\n#include "app/runs/Batch.hpp"\n')
        _, offences = scan(root)
    cycle = any(o.startswith("include cycle") for o in offences)
    upward = any("app/runs/Batch.hpp" in o for o in offences)
    print(f"self-test: cycle found {cycle}, upward include found {upward}")
    return 0 if cycle and upward else 1


def main():
    if len(sys.argv) != 2 or sys.argv[1] in ("-h", "--help"):
        print(__doc__)
        return 0 if len(sys.argv) == 2 else 2
    if sys.argv[1] == "--self-test":
        return self_test()
    count, offences = scan(sys.argv[1])
    for o in offences:
        print(o)
    print(f"{count} files, {len(offences)} offences")
    return 1 if offences else 0


if __name__ == "__main__":
    sys.exit(main())
