#!/usr/bin/env python3
"""Checks the test binary: every function that both the tests' objects and the library's
archives compile out of line (an inline or template function, kept once by the linker) is
the library's copy in the binary, so that the library runs the code ffdtool runs: -O3
where the tests' own code is -O1, instrumented in the sanitizers' build where the tests'
own code is not (tests/CMakeLists.txt).

Usage: check_library_copies.py BINARY TEST_OBJECT_DIR ARCHIVE...
A copy is told by its size: the library's and the tests' copies of a function, compiled
with other options, mostly differ in size; one whose sizes agree is not counted. Exit 1
naming the functions that are the tests' copies, 2 on bad usage.
"""
import pathlib
import subprocess
import sys


def sizes(paths, kinds=("W",)):
    """Name -> size of the functions of nm's kinds the files define (W: weak, inline or
    template functions)."""
    out = subprocess.run(["nm", "-S", "--defined-only", *map(str, paths)], capture_output=True,
                         text=True, check=True).stdout
    found = {}
    for line in out.splitlines():
        parts = line.split()
        if len(parts) == 4 and parts[2] in kinds:
            found.setdefault(parts[3], parts[1])
    return found


def main(argv):
    if len(argv) < 4:
        print("usage: check_library_copies.py BINARY TEST_OBJECT_DIR ARCHIVE...", file=sys.stderr)
        return 2
    binary, test_dir, archives = argv[1], pathlib.Path(argv[2]), argv[3:]
    tests = sizes(sorted(test_dir.rglob("*.o")))
    library = sizes(archives)
    linked = sizes([binary], ("W", "T"))
    differing = [name for name in tests.keys() & library.keys() if tests[name] != library[name]]
    wrong = sorted(name for name in differing if linked.get(name) != library[name])
    print(f"{len(differing)} functions compiled by both the tests and the library, "
          f"{len(differing) - len(wrong)} of them the library's copy in {binary}")
    for name in wrong:
        print(f"not the library's copy: {name}")
    return 1 if wrong or not differing else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
