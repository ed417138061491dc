#!/usr/bin/env python3
"""Checks the layering rules of docs/architecture.md ("Modules and what they may include").

Run from ctest (test `layering`) as `check_layering.py ROOT`; exits non-zero and lists every
violation. `check_layering.py --self-test` builds small trees that break each rule and checks
that every one is caught.

Rules:
  1. A module includes only its own headers and the public headers (isoforge/<m>/...) of the
     modules it may use (ALLOWED below); the CLI and verify/ may use every module.
  2. A private header (src/<m>/...) is included only from its own module: quoted includes
     that are not "isoforge/..." must name a file of the same module directory.
  3. Public headers include only the standard library, isoforge headers and OpenVDB; OpenVDB
     only in the headers whose API takes or returns a sparse grid (SPARSE_HEADERS); no other
     third-party header, no #define and no *_detail namespace in a public header.
  4. The headers a dense-only user includes never reach OpenVDB, transitively.
  5. The umbrella headers isoforge/isoforge.hpp (dense) and isoforge/isoforge_sparse.hpp
     include every public header of their kind.
  6. CGAL appears only in verify/src/mesh_checks.cpp, mesh_distance.cpp and cgal_decimate.cpp; Ceres and
     Draco only in .cpp files.
"""

import os
import re
import sys
import tempfile

# Lowest first: a module may include the public headers of the modules listed for it.
MODULES = ["core", "spatial", "sparse", "implicit", "contour", "model", "filters", "reduce",
           "fit", "io"]
ALLOWED = {
    "core": set(),
    "spatial": {"core"},
    "sparse": {"core"},
    "implicit": {"core", "spatial", "sparse"},
    "contour": {"core", "spatial", "sparse"},
    "model": {"core", "spatial", "sparse", "implicit", "contour"},
    "filters": {"core", "spatial", "sparse", "implicit", "contour"},
    "reduce": {"core", "spatial", "contour"},
    "fit": {"core", "spatial", "implicit", "reduce"},
    "io": {"core", "sparse"},
}
STD_HEADERS = set("""algorithm any array atomic barrier bit bitset cassert cctype cerrno cfloat
charconv chrono cinttypes climits cmath compare complex concepts condition_variable coroutine
csignal cstdarg cstddef cstdint cstdio cstdlib cstring ctime cwchar deque exception execution
filesystem format forward_list fstream functional future initializer_list iomanip ios iosfwd
iostream istream iterator latch limits list locale map memory memory_resource mutex new numbers
numeric optional ostream queue random ranges ratio regex scoped_allocator semaphore set
shared_mutex source_location span sstream stack stdexcept stop_token streambuf string
string_view syncstream system_error thread tuple type_traits typeindex typeinfo unordered_map
unordered_set utility valarray variant vector version""".split())

INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]', re.M)


def is_sparse_header(rel):
    """Public headers whose API takes or returns OpenVDB grids (rel: path under isoforge/)."""
    return (rel.startswith("sparse/") or rel.endswith("_sparse.hpp") or rel == "io/vdb.hpp"
            or rel == "isoforge_sparse.hpp")


def files_under(root, sub, exts):
    base = os.path.join(root, sub)
    for dirpath, _, names in os.walk(base):
        for n in sorted(names):
            if n.endswith(exts):
                yield os.path.join(dirpath, n)


def includes(path):
    with open(path, encoding="utf-8", errors="replace") as f:
        text = f.read()
    return [(m.group(1), m.group(2)) for m in INCLUDE.finditer(text)], text


def check(root):
    errors = []
    rel = lambda p: os.path.relpath(p, root)

    # Rules 1 and 2: module sources and public headers.
    for m in MODULES:
        sources = list(files_under(root, os.path.join("src", m), (".cpp", ".hpp")))
        headers = list(files_under(root, os.path.join("include", "isoforge", m), (".hpp",)))
        for path in sources + headers:
            for kind, inc in includes(path)[0]:
                if kind != '"':
                    continue
                if inc.startswith("isoforge/"):
                    parts = inc.split("/")
                    if len(parts) < 3:
                        continue  # isoforge/version.hpp, isoforge/isoforge.hpp
                    other = parts[1]
                    if other != m and other not in ALLOWED[m]:
                        errors.append(f"{rel(path)}: module '{m}' may not include '{inc}' "
                                      f"(allowed: {', '.join(sorted(ALLOWED[m] | {m}))})")
                    if not os.path.exists(os.path.join(root, "include", inc)):
                        errors.append(f"{rel(path)}: '{inc}' is not a public header")
                elif path in headers:
                    errors.append(f"{rel(path)}: a public header includes the private '{inc}'")
                else:
                    # Relative to the including file, or to src/ (the library's private
                    # include directory): either way a file of this module.
                    home = os.path.join(root, "src", m)
                    candidates = [os.path.normpath(os.path.join(os.path.dirname(path), inc)),
                                  os.path.normpath(os.path.join(root, "src", inc))]
                    if not any(t.startswith(home + os.sep) and os.path.exists(t)
                               for t in candidates):
                        errors.append(f"{rel(path)}: '{inc}' is not a header of module '{m}' "
                                      "(use the public header of another module)")

    # Rule 3: what public headers include and contain.
    public = {}
    for path in files_under(root, os.path.join("include", "isoforge"), (".hpp",)):
        r = os.path.relpath(path, os.path.join(root, "include", "isoforge"))
        incs, text = includes(path)
        public[r] = [inc for kind, inc in incs if kind == '"' and inc.startswith("isoforge/")]
        for kind, inc in incs:
            if kind == '"':
                continue
            if inc.startswith("openvdb/"):
                if not is_sparse_header(r):
                    errors.append(f"{rel(path)}: includes <{inc}>, but only the sparse headers "
                                  "(sparse/*, *_sparse.hpp, io/vdb.hpp) may include OpenVDB")
            elif inc not in STD_HEADERS:
                errors.append(f"{rel(path)}: a public header includes the third-party <{inc}>")
        if re.search(r"^\s*#\s*define\b", text, re.M):
            errors.append(f"{rel(path)}: a public header defines a macro")
        if re.search(r"\bnamespace\s+\w*_detail\b", text):
            errors.append(f"{rel(path)}: a public header declares a *_detail namespace")

    # Rule 4: dense headers never reach OpenVDB.
    def reaches_openvdb(r, seen):
        if r in seen or r not in public:
            return None
        seen.add(r)
        path = os.path.join(root, "include", "isoforge", r)
        if any(inc.startswith("openvdb/") for kind, inc in includes(path)[0] if kind == "<"):
            return [r]
        for inc in public[r]:
            chain = reaches_openvdb(inc[len("isoforge/"):], seen)
            if chain:
                return [r] + chain
        return None

    for r in sorted(public):
        if not is_sparse_header(r):
            chain = reaches_openvdb(r, set())
            if chain:
                errors.append(f"include/isoforge/{r}: a dense header reaches OpenVDB through "
                              + " -> ".join(chain))

    # Rule 5: the umbrella headers are complete.
    for umbrella, sparse in (("isoforge.hpp", False), ("isoforge_sparse.hpp", True)):
        if umbrella not in public:
            errors.append(f"include/isoforge/{umbrella}: the umbrella header is missing")
            continue
        listed = {inc[len("isoforge/"):] for inc in public[umbrella]}
        for r in sorted(public):
            if "/" in r and is_sparse_header(r) == sparse and r not in listed:
                if not sparse or r != "isoforge.hpp":
                    errors.append(f"include/isoforge/{umbrella}: does not include "
                                  f"isoforge/{r}")

    # Rule 6: CGAL, Ceres and Draco stay where they belong.
    cgal_ok = {os.path.join("verify", "src", "mesh_checks.cpp"),
               os.path.join("verify", "src", "mesh_distance.cpp"),
               os.path.join("verify", "src", "cgal_decimate.cpp")}
    for sub in ("src", "include", "verify", "tests"):
        for path in files_under(root, sub, (".cpp", ".hpp", ".h")):
            for kind, inc in includes(path)[0]:
                if kind != "<":
                    continue
                if inc.startswith("CGAL/") and rel(path) not in cgal_ok:
                    errors.append(f"{rel(path)}: includes CGAL (only {', '.join(sorted(cgal_ok))} "
                                  "may)")
                if inc.startswith(("ceres/", "draco/")) and not path.endswith(".cpp"):
                    errors.append(f"{rel(path)}: includes <{inc}> outside a .cpp file")
    return errors


def self_test():
    """Each broken tree must produce exactly the expected kind of violation."""
    def tree(files):
        d = tempfile.mkdtemp(prefix="layering-")
        for name, text in files.items():
            p = os.path.join(d, name)
            os.makedirs(os.path.dirname(p), exist_ok=True)
            with open(p, "w") as f:
                f.write(text)
        return d

    good = {
        "include/isoforge/core/a.hpp": "#pragma once\n#include <vector>\n",
        "include/isoforge/sparse/grid.hpp": "#pragma once\n#include <openvdb/openvdb.h>\n",
        "include/isoforge/contour/c.hpp": '#pragma once\n#include "isoforge/core/a.hpp"\n',
        "include/isoforge/isoforge.hpp":
            '#include "isoforge/core/a.hpp"\n#include "isoforge/contour/c.hpp"\n',
        "include/isoforge/isoforge_sparse.hpp": '#include "isoforge/sparse/grid.hpp"\n',
        "src/contour/c.cpp": '#include "isoforge/contour/c.hpp"\n#include "tables.hpp"\n',
        "src/contour/tables.hpp": "#pragma once\n",
        "src/core/a.cpp": '#include "isoforge/core/a.hpp"\n',
    }
    assert check(tree(good)) == [], check(tree(good))
    cases = {
        "may not include": {"src/core/a.cpp": '#include "isoforge/contour/c.hpp"\n'},
        "io/vdb": {"src/model/m.cpp": '#include "isoforge/io/vdb.hpp"\n'},
        "is not a header of module": {"src/model/m.cpp": '#include "contour/tables.hpp"\n'},
        "includes the private": {"include/isoforge/core/b.hpp": '#include "detail/x.hpp"\n'},
        "only the sparse headers": {"include/isoforge/core/b.hpp": "#include <openvdb/x.h>\n"},
        "third-party": {"include/isoforge/core/b.hpp": "#include <tbb/parallel_for.h>\n"},
        "defines a macro": {"include/isoforge/core/b.hpp": "#define KERNEL inline\n"},
        "_detail namespace": {"include/isoforge/core/b.hpp": "namespace model_detail {}\n"},
        "reaches OpenVDB": {"include/isoforge/contour/c.hpp":
                            '#include "isoforge/sparse/grid.hpp"\n'},
        "does not include": {"include/isoforge/core/b.hpp": "#pragma once\n"},
        "includes CGAL": {"verify/src/main.cpp": "#include <CGAL/Exact.h>\n"},
        "outside a .cpp": {"include/isoforge/fit/f.hpp": "#include <ceres/ceres.h>\n"},
    }
    for expect, files in cases.items():
        errors = check(tree({**good, **files}))
        if not any(expect in e for e in errors):
            print(f"self-test: a tree with {files} gave {errors}, expected '{expect}'")
            return 1
    print(f"self-test: {len(cases)} broken trees caught")
    return 0


def main():
    if len(sys.argv) == 2 and sys.argv[1] == "--self-test":
        return self_test()
    if len(sys.argv) != 2:
        print("usage: check_layering.py ROOT | --self-test", file=sys.stderr)
        return 2
    errors = check(os.path.abspath(sys.argv[1]))
    for e in errors:
        print(e)
    if errors:
        print(f"{len(errors)} layering violation(s); the rules are in docs/architecture.md")
        return 1
    print("layering: every include follows docs/architecture.md")
    return 0


if __name__ == "__main__":
    sys.exit(main())
