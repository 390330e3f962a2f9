"""Checks that no test name begins with '-'.

CTest runs each test as `EXECUTABLE "NAME"`, and the test runner reads a
name that begins with '-' as one of its own options: "--reference ..." made
the test fail to start, and "-o that names ..." ran the whole suite into a
file of that name and passed.

Usage: check_test_names.py [ROOT]      check the tests under ROOT (default: this checkout)
       check_test_names.py --self-test prove on a made-up file that such a name is caught

Exit status 0 when every name is fine, 1 with one line per offending name otherwise.
"""
import os
import re
import sys
import tempfile

NAME = re.compile(r'TEST_CASE\(\s*"(-[^"]*)"')


def offending_names(root):
    found = []
    for folder, _, files in os.walk(os.path.join(root, "tests")):
        for name in sorted(files):
            if not name.endswith((".cpp", ".hpp")):
                continue
            path = os.path.join(folder, name)
            with open(path, encoding="utf-8") as f:
                for number, line in enumerate(f, 1):
                    for match in NAME.finditer(line):
                        found.append(f"{os.path.relpath(path, root)}:{number}: test name \"{match.group(1)}\" "
                                     "begins with '-', which the test runner reads as an option")
    return found


def self_test():
    with tempfile.TemporaryDirectory() as root:
        os.makedirs(os.path.join(root, "tests"))
        with open(os.path.join(root, "tests", "t.cpp"), "w", encoding="utf-8") as f:
            f.write('TEST_CASE("fine name", "[x]") {}\nTEST_CASE("--option-like name", "[x]") {}\n')
        found = offending_names(root)
        if len(found) != 1 or "--option-like name" not in found[0]:
            print("self-test failed: expected the one option-like name, got", found)
            return 1
    print("self-test passed")
    return 0


def main():
    if sys.argv[1:] == ["--self-test"]:
        return self_test()
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..")
    found = offending_names(root)
    for line in found:
        print(line)
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
