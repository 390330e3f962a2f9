"""Values out of the summary.json files of pd-solve and pd-post, for the bench scripts.

find(d, key) returns the first value named `key` in the objects of the parsed JSON `d`
(depth first, not inside arrays; None if there is none), so that a script need not know in which
section a tool reports it. From the shell:  python3 bench/summary_json.py FILE KEY
"""
import json
import sys


def find(d, key):
    if isinstance(d, dict):
        for k, v in d.items():
            if k == key:
                return v
            r = find(v, key)
            if r is not None:
                return r
    return None


def load(path):
    with open(path) as f:
        return json.load(f)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: summary_json.py FILE KEY")
    value = find(load(sys.argv[1]), sys.argv[2])
    if value is None:
        sys.exit(f"summary_json.py: no key '{sys.argv[2]}' in {sys.argv[1]}")
    print(value)
