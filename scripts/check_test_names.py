"""Checks that every test name reaches CTest whole.

CTest runs each test as `EXECUTABLE "NAME"`, and the test runner reads a
name that begins with '-' as one of its own options: "--reference ..." made
the test fail to start, and "-o that names ..." ran the whole suite into a
file of that name and passed.

The entries are discovered as a CMake list of the names, so a name with ';'
is cut in two there, and one with '[' or ']' can join the names after it
into one entry: each such entry named no test case, ran nothing and passed,
and those test cases never ran (tests/CMakeLists.txt now also makes an entry
that runs nothing fail). A name is the TEST_CASE's string literals joined,
as the compiler joins them across lines.

Usage: check_test_names.py [ROOT]      check the tests under ROOT (default: this checkout)
       check_test_names.py --self-test prove on a made-up file that such names are caught

Exit status 0 when every name is fine, 1 with one line per offending name otherwise.
"""
import os
import re
import sys
import tempfile

# The string literals that open a TEST_CASE, across lines.
TEST_CASE = re.compile(r'TEST_CASE\(\s*((?:"(?:[^"\\\n]|\\.)*"\s*)+)')
LITERAL = re.compile(r'"((?:[^"\\\n]|\\.)*)"')
# Characters the discovery's CMake list reads as its own.
LIST_CHARACTERS = ";[]"


def test_names(text):
    """(line number, name) of every TEST_CASE in a source text."""
    for match in TEST_CASE.finditer(text):
        name = "".join(LITERAL.findall(match.group(1)))
        yield text.count("\n", 0, match.start()) + 1, name


def problems(name):
    found = []
    if name.startswith("-"):
        found.append("begins with '-', which the test runner reads as an option")
    chars = sorted(set(c for c in name if c in LIST_CHARACTERS))
    if chars:
        found.append("holds " + ", ".join(f"'{c}'" for c in chars) +
                     ", which the discovery of the CTest entries reads as a list's own: the test case would never run")
    return found


def offending_names(root):
    found = []
    for folder, _, files in os.walk(os.path.join(root, "tests")):
        for name in sorted(files):
            if not name.endswith((".cpp", ".hpp")):
                continue
            path = os.path.join(folder, name)
            with open(path, encoding="utf-8") as f:
                text = f.read()
            for number, test in test_names(text):
                for problem in problems(test):
                    found.append(f"{os.path.relpath(path, root)}:{number}: test name \"{test}\" {problem}")
    return found


def self_test():
    with tempfile.TemporaryDirectory() as root:
        os.makedirs(os.path.join(root, "tests"))
        with open(os.path.join(root, "tests", "t.cpp"), "w", encoding="utf-8") as f:
            f.write('TEST_CASE("fine name, with a comma", "[x]") {}\n'
                    'TEST_CASE("--option-like name", "[x]") {}\n'
                    'TEST_CASE("a name; cut in two", "[x]") {}\n'
                    'TEST_CASE("a range (0, 1] "\n          "over two lines", "[x]") {}\n')
        found = offending_names(root)
        expected = ["t.cpp:2: test name \"--option-like name\" begins with '-'",
                    "t.cpp:3: test name \"a name; cut in two\" holds ';'",
                    "t.cpp:4: test name \"a range (0, 1] over two lines\" holds ']'"]
        if len(found) != len(expected) or any(e not in line for e, line in zip(expected, found)):
            print("self-test failed: expected", expected, "got", found)
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
