#!/usr/bin/env python3
"""Checks extended XYZ files against the format's specification (github.com/libAtoms/extxyz,
"Extended XYZ specification"): per frame a count line, a comment line of key=value pairs and one
line per particle whose columns match the Properties triplets (name:T:m, T in S I R L, m > 0) in
number and type; Lattice 9 reals, pbc 3 logicals. Prints one line per file; exits 1 on the first
violation, naming file, line and rule.

  extxyz_spec.py FILE...
"""
import re
import sys

BARE_INT = r"(?:0|[1-9][0-9]*)"
INT = re.compile(r"[+-]?" + BARE_INT + r"$")
FLOAT = re.compile(r"[+-]?(?:(?:" + BARE_INT + r"\.|\.)[0-9]*(?:[dDeE][+-]?[0-9]+)?|" + BARE_INT +
                   r"(?:[dDeE][+-]?[0-9]+)?)$")
LOGICAL = re.compile(r"(?:[tT]rue|TRUE|T|[fF]alse|FALSE|F)$")
SIMPLE_STRING = re.compile(r"\S+$")
TYPES = {"I": INT, "R": FLOAT, "L": LOGICAL, "S": SIMPLE_STRING}
# key=value: the key a bare or quoted string, the value quoted ("..." with \" escapes), or bare.
PAIR = re.compile(r'\s*([^\s=",{}\[\]\\]+|"(?:\\.|[^"\\])*")\s*=\s*("(?:\\.|[^"\\])*"|\{[^}]*\}|\[[^\]]*\]|[^\s"]+)')


def fail(path, line, why):
    print(f"{path}: line {line}: {why}")
    sys.exit(1)


def pairs(path, line, text):
    out, pos = {}, 0
    while text[pos:].strip():
        m = PAIR.match(text, pos)
        if not m:
            fail(path, line, f"not a key=value pair at '{text[pos:pos + 30]}'")
        key, value = m.group(1).strip('"'), m.group(2)
        if value.startswith('"'):
            value = value[1:-1]
        out[key] = value
        pos = m.end()
    return out


def check(path):
    lines = open(path).read().split("\n")
    while lines and not lines[-1].strip():  # blank lines only at the end
        lines.pop()
    i, frames = 0, 0
    while i < len(lines):
        count = lines[i].strip()
        if not INT.match(count) or int(count) < 0:
            fail(path, i + 1, f"count line '{count[:30]}' is not a non-negative integer")
        n = int(count)
        kv = pairs(path, i + 2, lines[i + 1])
        props = kv.get("Properties")
        if props is None:
            fail(path, i + 2, "no Properties key")
        parts = props.split(":")
        if len(parts) % 3:
            fail(path, i + 2, "Properties is not a series of name:T:m triplets")
        columns = []
        for name, t, m in zip(parts[0::3], parts[1::3], parts[2::3]):
            if t not in TYPES or not INT.match(m) or int(m) < 1 or not name:
                fail(path, i + 2, f"Properties triplet {name}:{t}:{m} is not name:[SIRL]:m with m > 0")
            columns += [(name, TYPES[t])] * int(m)
        if "Lattice" in kv and not (len(kv["Lattice"].split()) == 9 and all(FLOAT.match(x) or INT.match(x)
                                                                            for x in kv["Lattice"].split())):
            fail(path, i + 2, "Lattice is not 9 numbers")
        if "pbc" in kv and not (len(kv["pbc"].split()) == 3 and all(LOGICAL.match(x) for x in kv["pbc"].split())):
            fail(path, i + 2, "pbc is not 3 logicals")
        for k in range(n):
            ln = i + 3 + k
            if ln > len(lines):
                fail(path, ln, "the file ends inside a frame")
            words = lines[ln - 1].split()
            if len(words) != len(columns):
                fail(path, ln, f"{len(words)} columns, Properties gives {len(columns)}")
            for w, (name, rule) in zip(words, columns):
                if not rule.match(w):
                    fail(path, ln, f"'{w}' does not fit column {name}")
        i += n + 2
        frames += 1
    print(f"{path}: {frames} frame(s) within the extended XYZ specification")


if __name__ == "__main__":
    for p in sys.argv[1:]:
        check(p)
