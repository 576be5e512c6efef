#!/usr/bin/env python3
"""Checks that BoP's folders include each other in one direction only.

Each source file belongs to a part: common/, or a component's folder (dynamics_server/core,
protocol/server, viz_client/render, ...). A quoted #include from one part into another is an
edge; the check fails (exit 1) when the edges form a circle, naming it, so that no file includes
back up into a part that includes it. Tests are left out (they include what they test).

  scripts/include-graph.py            check; prints the graph's edges
  scripts/include-graph.py --quiet    check; prints only a circle if there is one
"""
import collections
import os
import re
import subprocess
import sys

INCLUDE = re.compile(r'\s*#\s*include\s+"([^"]+)"')


def part_of(path):
    parts = path.split("/")
    if parts[0] == "common":
        return "common"
    return "/".join(parts[:2]) if len(parts) > 2 else parts[0]


def sources():
    out = subprocess.check_output(["git", "ls-files", "*.cpp", "*.hpp", "*.h"], text=True)
    return [f for f in out.split() if not f.startswith("tests/")]


def resolve(name, including, files, by_tail):
    """The file a quoted include names: beside the includer first, then anywhere by its tail."""
    beside = os.path.normpath(os.path.join(os.path.dirname(including), name))
    if beside in files:
        return beside
    matches = by_tail.get(name, [])
    return min(matches, key=len) if matches else None  # generated headers (flatc) are not sources


def graph(files):
    fileset = set(files)
    by_tail = collections.defaultdict(list)
    for f in files:
        parts = f.split("/")
        for i in range(len(parts)):
            by_tail["/".join(parts[i:])].append(f)
    edges = collections.defaultdict(set)
    for f in files:
        with open(f, errors="replace") as text:
            for line in text:
                m = INCLUDE.match(line)
                target = m and resolve(m.group(1), f, fileset, by_tail)
                if target and part_of(target) != part_of(f):
                    edges[part_of(f)].add(part_of(target))
    return edges


def find_circle(edges):
    """A list of parts forming a circle, or None (depth-first search, three colours)."""
    state, stack = {}, []

    def visit(node):
        state[node] = "open"
        stack.append(node)
        for nxt in sorted(edges.get(node, ())):
            if state.get(nxt) == "open":
                return stack[stack.index(nxt):] + [nxt]
            if nxt not in state:
                found = visit(nxt)
                if found:
                    return found
        stack.pop()
        state[node] = "done"
        return None

    for node in sorted(edges):
        if node not in state:
            found = visit(node)
            if found:
                return found
    return None


def main():
    os.chdir(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    quiet = "--quiet" in sys.argv[1:]
    if any(a not in ("--quiet",) for a in sys.argv[1:]):
        print(__doc__)
        return 0 if {"-h", "--help"} & set(sys.argv[1:]) else 2
    edges = graph(sources())
    if not quiet:
        for part in sorted(edges):
            print(f"{part} -> {', '.join(sorted(edges[part]))}")
    circle = find_circle(edges)
    if circle:
        print("include-graph: a circle: " + " -> ".join(circle), file=sys.stderr)
        return 1
    print(f"include-graph: {len(edges)} parts include one way only (no circle)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
