#!/usr/bin/env python3
"""Checks the include rule of docs/architecture.md: a file includes only
files of its own layer or of lower layers, siblings on one layer do not
include each other, and the tools do not include each other.

Usage: check_layers.py [ROOT]      check the source tree at ROOT (default: this checkout)
       check_layers.py --self-test prove on a small made-up tree that a violation is caught

Exit status 0 when the rule holds, 1 with one line per violation otherwise.
"""
import os
import re
import sys
import tempfile

# (folder, rank, group): lower rank = lower layer. A file may include files of
# a lower rank, or of its own rank within its own group. Folders are relative
# to the root; the first folder that contains a file decides its layer.
LAYERS = [
    ("common/discretisation", 1, "discretisation"),
    ("common", 0, "common"),
    ("solver/model", 10, "model"),
    ("solver/input", 11, "input"),
    ("solver/setup", 12, "setup"),
    ("solver/state", 13, "state"),
    ("solver/kernels", 14, "kernels"),
    ("solver/dynamics", 15, "dynamics"),
    ("solver/statics", 15, "statics"),
    ("solver/outputs", 16, "outputs"),
    ("solver/runs", 17, "runs"),
    ("solver", 18, "solver-main"),
    ("mesher", 10, "mesher"),
    ("post", 10, "post"),
    ("validation", 30, "validation"),
]
SOURCE = re.compile(r"\.(h|hpp|c|cc|cpp)$")
INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]+)"')


def layer_of(path):
    for folder, rank, group in LAYERS:
        if path == folder or path.startswith(folder + "/"):
            return rank, group, folder
    return None


def check(root):
    files = {}
    for top in sorted({f.split("/")[0] for f, _, _ in LAYERS}):
        for base, _, names in os.walk(os.path.join(root, top)):
            for name in names:
                if SOURCE.search(name):
                    rel = os.path.relpath(os.path.join(base, name), root).replace(os.sep, "/")
                    files[rel] = layer_of(rel)
    # Includes are by file name (each layer's folder is on the include path).
    by_name = {}
    for rel in files:
        by_name.setdefault(os.path.basename(rel), []).append(rel)
    problems = []
    for name, places in sorted(by_name.items()):
        if len(places) > 1 and name.endswith((".h", ".hpp")):
            problems.append("header name used twice (includes by name are ambiguous): " + ", ".join(places))
    for rel, layer in sorted(files.items()):
        if layer is None:
            continue
        rank, group, _ = layer
        with open(os.path.join(root, rel), encoding="utf-8", errors="replace") as f:
            for number, line in enumerate(f, 1):
                m = INCLUDE.match(line)
                if not m:
                    continue
                target = os.path.basename(m.group(1))
                if target not in by_name:
                    continue  # a generated or system header
                if os.path.dirname(rel) == os.path.dirname(by_name[target][0]):
                    continue  # same folder
                other = files[by_name[target][0]]
                if other is None:
                    continue
                other_rank, other_group, other_folder = other
                lower = other_rank < rank
                same = other_rank == rank and other_group == group
                # Tools (rank 10 outside the solver) see only common/; the solver's layers see the solver below them.
                tool_to_tool = group in ("mesher", "post") and other_group not in ("common", "discretisation")
                if tool_to_tool or not (lower or same) or (
                        other_rank >= 10 and group in ("mesher", "post", "model") and other_group != group):
                    problems.append("%s:%d includes %s (%s, layer %d) from layer %d (%s)" %
                                    (rel, number, m.group(1), other_folder, other_rank, rank, group))
    return problems


def self_test():
    cases = {
        "solver/kernels/a.hpp": '#include "b.hpp"\n',        # kernels -> setup: allowed
        "solver/setup/b.hpp": '#include "c.hpp"\n',          # setup -> runs: a violation
        "solver/runs/c.hpp": "\n",
        "solver/dynamics/d.hpp": '#include "e.hpp"\n',       # dynamics -> statics: siblings, a violation
        "solver/statics/e.hpp": "\n",
        "mesher/m.cpp": '#include "a.hpp"\n',                # mesher -> solver: a violation
        "common/x.hpp": '#include "pd/version.hpp"\n',      # generated header: ignored
    }
    with tempfile.TemporaryDirectory() as root:
        for rel, text in cases.items():
            os.makedirs(os.path.dirname(os.path.join(root, rel)), exist_ok=True)
            with open(os.path.join(root, rel), "w") as f:
                f.write(text)
        found = check(root)
    expected = ["solver/setup/b.hpp", "solver/dynamics/d.hpp", "mesher/m.cpp"]
    caught = [e for e in expected if any(p.startswith(e + ":") for p in found)]
    if caught != expected or len(found) != len(expected):
        print("self-test failed: expected violations in %s, found:\n  %s" % (expected, "\n  ".join(found)))
        return 1
    print("self-test: %d planted violations caught, nothing else reported" % len(expected))
    return 0


def main(argv):
    if len(argv) > 1 and argv[1] == "--self-test":
        return self_test()
    root = argv[1] if len(argv) > 1 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    problems = check(root)
    for p in problems:
        print("layer rule broken: " + p)
    if not problems:
        print("layers: every include goes to the same or a lower layer")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
