#!/usr/bin/env python3
"""Checks that the file-scope names of one target's .cpp files are unique across its files.

The sanitizer build (make fuzz, make sanitize) is a CMake unity build: batches of the library's
.cpp files (and of the CLI's) are compiled as one translation unit, so two files that each
define `struct Block` in an anonymous namespace, or each have a `static` helper `fail(...)`,
collide there although each compiles alone. Which files share a batch changes whenever a file
is added, so the rule is simply: a name defined at file scope of a .cpp (in an anonymous
namespace, or `static`, or a #define) is defined in no other .cpp of the same target.

Run from ctest (test `unity_names`) as `check_unity_names.py ROOT`; exits non-zero and lists
every clash. `check_unity_names.py --self-test` checks the parser on small sources.

The parser is a tokenizer with a scope stack, not a C++ front end: it finds classes, enums,
aliases, variables and functions declared directly in an anonymous namespace, `static`
functions and variables at namespace scope, the enumerators of unscoped enums (which have no
linkage, so two sources may each define one), and macros. Overloads count as clashes too: in one
translation unit they would silently join one overload set.
"""

import os
import re
import sys

TOKEN = re.compile(r"[A-Za-z_]\w*|::|->|[{}()\[\];=<>,~*&:]|\S")
KEYWORDS = {"const", "constexpr", "static", "inline", "thread_local", "extern", "mutable",
            "volatile", "unsigned", "signed", "typename", "noexcept", "override", "final",
            "auto", "void", "int", "long", "short", "char", "bool", "float", "double",
            "consteval", "constinit", "alignas", "explicit", "virtual", "friend", "return",
            "operator", "decltype", "sizeof", "requires", "static_assert", "struct", "class", "enum", "union"}


def strip(text):
    """Removes comments, string and character literals; keeps line structure."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append("\n" * text.count("\n", i, j))
            i = j
        elif c == 'R' and text.startswith('R"', i):
            m = re.match(r'R"([^(\s]*)\(', text[i:])
            end = text.find(")" + m.group(1) + '"', i) if m else -1
            j = n if end < 0 else end + len(m.group(1)) + 2
            out.append('""' + "\n" * text.count("\n", i, j))
            i = j
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            out.append(c + c)
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


def file_scope_names(text):
    """Returns {name: kind} for the names a .cpp defines at file scope (see module doc)."""
    names = {}
    body_lines = []
    for line in strip(text).split("\n"):
        s = line.strip()
        if s.startswith("#"):
            m = re.match(r"#\s*define\s+(\w+)", s)
            if m and not m.group(1).startswith("ISOFORGE_"):
                names[m.group(1)] = "macro"
            body_lines.append("")
        else:
            body_lines.append(line)
    tokens = TOKEN.findall("\n".join(body_lines))

    # Scope stack of (kind, namespace path): kind is "anon", "ns" (named namespace or global)
    # or "other". Names are keyed by their enclosing named namespace: anonymous namespaces in
    # different named namespaces are different namespaces and do not clash.
    stack = [("ns", "")]
    stmt = []
    i = 0
    while i < len(tokens):
        t = tokens[i]
        if t == "{":
            kind, path = "other", stack[-1][1]
            if stmt and stmt[0] == "namespace" and "=" not in stmt:
                kind = "anon" if len(stmt) == 1 else "ns"
                if kind == "ns":
                    path = path + "::" + "".join(x for x in stmt[1:] if x != "inline")
            elif stmt[:2] == ["extern", '"'] or stmt == ["extern"]:
                kind = "ns"
            if kind == "other":
                declare(stmt, stack[-1], names, body=True)
                # An unscoped enum's enumerators are names of the enclosing scope (they have no
                # linkage, so two sources may each define one; a unity batch may not).
                head = skip_template(stmt)
                unscoped_enum = (bool(head) and head[0] == "enum" and
                                 (len(head) < 2 or head[1] not in ("class", "struct")))
                # Skip the whole braced body.
                depth = 1
                i += 1
                while i < len(tokens) and depth:
                    if (unscoped_enum and depth == 1 and tokens[i - 1] in ("{", ",") and
                            re.match(r"[A-Za-z_]\w*$", tokens[i]) and stack[-1][0] in ("anon", "ns")):
                        names[(stack[-1][1] + "::" + tokens[i]).lstrip(":")] = "enumerator"
                    depth += {"{": 1, "}": -1}.get(tokens[i], 0)
                    i += 1
                # A class or enum definition (or a braced initializer) ends with ';'.
                stmt = ["<defined>"] if is_aggregate(stmt) else []
                continue
            stack.append((kind, path))
            stmt = []
        elif t == "}":
            if len(stack) > 1:
                stack.pop()
            stmt = []
        elif t == ";":
            if stmt != ["<defined>"]:
                declare(stmt, stack[-1], names, body=False)
            stmt = []
        else:
            if stmt == ["<defined>"]:
                stmt = []  # e.g. `struct S {...} s;` names no new file-scope entity we track
            stmt.append(t)
        i += 1
    return names


def is_aggregate(stmt):
    """Whether a braced body just skipped may be followed by ';' (a class or a braced
    initializer) rather than end its declaration (a function body)."""
    stmt = skip_template(stmt)
    for t in stmt:
        if t in ("struct", "class", "enum", "union", "="):
            return True
        if t == "(":
            return False
    return False


def skip_template(stmt):
    """Drops a leading template<...> header."""
    while stmt and stmt[0] == "template":
        depth = 0
        for j, t in enumerate(stmt[1:], 1):
            depth += {"<": 1, ">": -1}.get(t, 0)
            if depth == 0:
                stmt = stmt[j + 1:]
                break
        else:
            return []
    return stmt


def declare(stmt, where, names, body):
    scope, path = where
    stmt = skip_template(stmt)
    def key(n):
        return (path + "::" + n).lstrip(":")
    if not stmt or stmt[0] == "namespace" or stmt[0] == "using" and "=" not in stmt:
        return  # namespace aliases may be repeated; using-declarations declare nothing new
    if scope == "ns" and "static" not in stmt[:3]:
        return
    if scope not in ("anon", "ns"):
        return
    if stmt[0] == "using" and len(stmt) > 2 and stmt[2] == "=":
        names[key(stmt[1])] = "alias"
        return
    if stmt[0] in ("typedef",):
        idents = [t for t in stmt if re.match(r"[A-Za-z_]\w*$", t)]
        if idents:
            names[key(idents[-1])] = "alias"
        return
    for k, t in enumerate(stmt):
        if t in ("struct", "class", "union", "enum"):
            rest = [x for x in stmt[k + 1:] if x not in ("class", "struct", "alignas")]
            if rest and re.match(r"[A-Za-z_]\w*$", rest[0]) and (body or len(rest) > 1):
                names[key(rest[0])] = "type"
            return
        if t in ("=", "(", "[", "{"):
            break
    # A function: the identifier before the first '(' (outside template arguments).
    angle = 0
    for k, t in enumerate(stmt):
        if t == "<":
            angle += 1
        elif t == ">":
            angle -= 1
        elif angle == 0 and t in ("=", "[", "{"):
            break
        elif angle == 0 and t == "(":
            if k and stmt[k - 1] not in KEYWORDS and re.match(r"[A-Za-z_]\w*$", stmt[k - 1]):
                if k < 2 or stmt[k - 2] not in ("operator", "::", "~"):  # not X::f, ~X
                    names[key(stmt[k - 1])] = "function"
            return
    # A variable: the last identifier before '=', '[', '{' or the end.
    ident = None
    angle = 0
    for t in stmt:
        if t == "<":
            angle += 1
        elif t == ">":
            angle -= 1
        elif angle == 0 and t in ("=", "[", "{"):
            break
        elif angle == 0 and re.match(r"[A-Za-z_]\w*$", t) and t not in KEYWORDS:
            ident = t
    if ident:
        names[key(ident)] = "variable"


def targets(root):
    """The .cpp files of each unity-built target: the library and the CLI."""
    lib, cli = [], []
    src = os.path.join(root, "src")
    for dirpath, _, files in os.walk(src):
        for f in sorted(files):
            if f.endswith(".cpp"):
                path = os.path.join(dirpath, f)
                rel = os.path.relpath(path, src)
                (cli if rel.startswith("cli" + os.sep) else lib).append(path)
    return {"library (src/)": sorted(lib), "CLI (src/cli/)": sorted(cli)}


def clashes(files, read=lambda p: open(p, encoding="utf-8").read()):
    seen = {}
    for path in files:
        for name, kind in file_scope_names(read(path)).items():
            seen.setdefault(name, []).append((path, kind))
    return {n: v for n, v in seen.items() if len(v) > 1}


def check(root):
    bad = 0
    for target, files in targets(root).items():
        for name, where in sorted(clashes(files).items()):
            bad += 1
            places = ", ".join(f"{os.path.relpath(p, root)} ({k})" for p, k in where)
            print(f"{target}: '{name}' is defined at file scope in {places}")
    if bad:
        print(f"{bad} name(s) would clash in the unity build; rename them (e.g. with the "
              f"file's subject as a prefix)")
        return 1
    print("unity names: no clashes")
    return 0


def self_test():
    a = """
#include <x>
#define HELPER_MAX 3
namespace fs = std::filesystem;
namespace isoforge::filters {
namespace {
// struct Commented {};
struct Block { int entries[4]; };
constexpr std::size_t kBlockCells = 4096;
template <class T> T twice(T x) { return x + x; }
using Index = std::uint32_t;
enum class Mode { kA, kB };
enum Code : std::uint8_t { kIn = 0, kOut = kIn + 1 };
const char* kText = "namespace { struct Fake {}; }";
}  // namespace
Result cut(const Data& d) { struct Local {}; return {}; }
int Block::size() const { return 4; }
static void helper(int) {}
}  // namespace isoforge::filters
"""
    b = """
namespace isoforge::filters {
namespace {
struct Block;
class Block final : public Base { };
std::vector<int> kBlockCells(3);
int twice(int x) { return 2 * x; }
constexpr double kOut = 1;
}  // namespace
int Index = 0;
static int helper = 1;
struct Public { };
Result cut(const Data& d) { return {}; }
}
#define HELPER_MAX 4
namespace fs = std::filesystem;
namespace isoforge::io {
namespace {
struct Block { };
}
}
"""
    names_a = file_scope_names(a)
    f = "isoforge::filters::"
    expect_a = {"HELPER_MAX": "macro", f + "Block": "type", f + "kBlockCells": "variable",
                f + "twice": "function", f + "Index": "alias", f + "Mode": "type",
                f + "Code": "type", f + "kIn": "enumerator", f + "kOut": "enumerator",
                f + "kText": "variable", f + "helper": "function"}
    ok = names_a == expect_a
    if not ok:
        print("file_scope_names(a) =", names_a)
    found = clashes(["a", "b"], read=lambda p: a if p == "a" else b)
    expect = {f + "Block", f + "kBlockCells", f + "twice", f + "helper", f + "kOut", "HELPER_MAX"}
    if set(found) != expect:
        print("clashes =", sorted(found), "expected", sorted(expect))
        ok = False
    print("self-test", "passed" if ok else "FAILED")
    return 0 if ok else 1


if __name__ == "__main__":
    if sys.argv[1:] == ["--self-test"]:
        sys.exit(self_test())
    if len(sys.argv) != 2:
        print("usage: check_unity_names.py ROOT | --self-test")
        sys.exit(2)
    sys.exit(check(sys.argv[1]))
