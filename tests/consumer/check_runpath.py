#!/usr/bin/env python3
"""Checks the library search paths (DT_RUNPATH, DT_RPATH) of every program and shared library
under the given directories: each entry must be an absolute directory or one relative to the
file's own ($ORIGIN), and exist. An empty entry (the trailing ':' of CMake's padded build RPATH)
or a relative one makes the loader search the current directory, where a stranger's libfmt.so.9
would be loaded.

  check_runpath.py [--expect NAME]... DIR...   check the files; each NAME must be among them
                                              with a search path
  check_runpath.py --self-test                 the checker's own test
"""
import os
import re
import subprocess
import sys


def entry_problem(entry, origin):
    """Why `entry` of a search path of a file in directory `origin` is unsafe, or None."""
    if entry == "":
        return "an empty entry (the current directory)"
    if entry.startswith("$ORIGIN") or entry.startswith("${ORIGIN}"):
        resolved = re.sub(r"^\$\{?ORIGIN\}?", lambda _: origin, entry)
    elif entry.startswith("/"):
        resolved = entry
    else:
        return "a relative entry (relative to the current directory)"
    if not os.path.isdir(resolved):
        return f"no directory {resolved}"
    return None


def search_paths(path):
    """The DT_RUNPATH and DT_RPATH strings of an ELF file."""
    out = subprocess.run(["readelf", "-d", "-W", path], capture_output=True, text=True).stdout
    return re.findall(r"Library (?:runpath|rpath): \[(.*)\]", out)


def is_elf_binary(path):
    if os.path.islink(path) or not os.path.isfile(path):
        return False
    name = os.path.basename(path)
    if not (os.access(path, os.X_OK) or re.search(r"\.so(\.|$)", name)):
        return False
    with open(path, "rb") as f:
        return f.read(4) == b"\x7fELF"


def check(dirs, expected):
    problems = []
    found = set()
    checked = 0
    for top in dirs:
        for root, subdirs, files in os.walk(top):
            subdirs[:] = [d for d in subdirs if d != "CMakeFiles"]
            for name in files:
                path = os.path.join(root, name)
                if not is_elf_binary(path):
                    continue
                checked += 1
                for value in search_paths(path):
                    found.add(name)
                    for entry in value.split(":"):
                        why = entry_problem(entry, os.path.dirname(os.path.abspath(path)))
                        if why:
                            problems.append(f"{path}: search path [{value}] has {why}")
    for name in expected:
        if name not in found:
            problems.append(f"no file {name} with a search path under {' '.join(dirs)}")
    for p in problems:
        print(p)
    print(f"{checked} programs and libraries checked, {len(problems)} problems")
    return 1 if problems else 0


def self_test():
    here = os.path.dirname(os.path.abspath(__file__))
    cases = [("", "empty"), ("lib", "relative"), (".", "relative"), ("$ORIGIN", None),
             ("${ORIGIN}/..", None), ("$ORIGIN/no-such-dir", "no directory"), ("/", None),
             ("/no/such/dir", "no directory")]
    failures = 0
    for entry, want in cases:
        got = entry_problem(entry, here)
        if (want is None) != (got is None) or (want and want not in got):
            print(f"entry '{entry}': got {got!r}, want {want!r}")
            failures += 1
    print(f"{len(cases)} cases, {failures} failures")
    return 1 if failures else 0


def main(argv):
    if argv == ["--self-test"]:
        return self_test()
    expected, dirs = [], []
    i = 0
    while i < len(argv):
        if argv[i] == "--expect" and i + 1 < len(argv):
            expected.append(argv[i + 1])
            i += 2
        else:
            dirs.append(argv[i])
            i += 1
    if not dirs:
        print(__doc__)
        return 2
    return check(dirs, expected)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
