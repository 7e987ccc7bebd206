#!/usr/bin/env python3
"""Names that two files of one unity batch both define at file scope.

With ROSY_UNITY the test programs and the CLI are compiled in batches: CMake writes
BUILD/**/Unity/unity_<n>_cxx.cxx, each including several .cpp files, so their anonymous
namespaces become one. Two files defining the same name then either fail to compile
(same signature) or, worse, become overloads of each other: a call may silently pick the
other file's function (a `put(s, &x, 4)` once took a template `put(s, T, bool)` from
another file). This script lists every name declared at namespace scope (anonymous or
named namespaces, `static`, or plainly) by two files of one batch; tests/CMakeLists.txt runs
it as the ctest `UnityBatches.NoSharedFileScopeNames`.

    tools/unity_names.py BUILD_DIR     # exit 1 and a list when a name is shared

The parser is deliberately simple (comments, strings and raw strings removed, braces
counted); it errs on the side of reporting.
"""
import re
import sys
from collections import defaultdict
from pathlib import Path

IDENT = r"[A-Za-z_][A-Za-z0-9_]*"
KEYWORDS = {"if", "for", "while", "switch", "return", "sizeof", "decltype", "operator", "alignas",
            "static_assert", "noexcept", "requires", "TEST", "TEST_F", "TEST_P", "TYPED_TEST",
            "INSTANTIATE_TEST_SUITE_P", "GTEST_SKIP", "namespace", "template", "const", "constexpr"}


def strip(text: str) -> str:
    """The source without comments, string and character literals (raw strings included)."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            i = n if j < 0 else j + 2
        elif c == "R" and i + 1 < n and text[i + 1] == '"' and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            m = re.match(r'R"([^(\s]*)\(', text[i:])
            if not m:
                out.append(c)
                i += 1
                continue
            end = text.find(")" + m.group(1) + '"', i + m.end())
            out.append('""')
            i = n if end < 0 else end + len(m.group(1)) + 2
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


def file_scope_names(path: Path) -> set:
    """Names declared at namespace scope: outside any namespace, in anonymous ones and in named
    ones (a batch merges `namespace rosy::cli { namespace { ... } }` of two files just the
    same); not members of classes, not locals of functions."""
    text = strip(path.read_text(encoding="utf-8", errors="replace"))
    text = re.sub(r"^\s*#.*$", "", text, flags=re.M)  # preprocessor lines
    names = set()
    # Stack of brace kinds: 'anon' (anonymous namespace: still file scope), 'named', 'other'.
    stack = []
    head = []

    def at_file_scope():
        return all(k in ("anon", "named") for k in stack)

    def declare(h: str):
        h = " ".join(h.split())
        if not h or h.startswith("using namespace") or h.startswith("namespace"):
            return
        m = re.match(r"(?:template\s*<.*>\s*)?(?:struct|class|enum(?:\s+class)?|union)\s+(" + IDENT + ")", h)
        if m:
            names.add(m.group(1))
            return
        m = re.match(r"using\s+(" + IDENT + r")\s*=", h)
        if m:
            names.add(m.group(1))
            return
        if h.startswith("using ") or h.startswith("extern "):
            return
        # A function: the identifier before the first '(' at paren depth 0.
        m = re.search(r"(" + IDENT + r")\s*\(", h)
        eq = h.find("=")
        if m and (eq < 0 or m.start() < eq):
            if m.group(1) not in KEYWORDS:
                names.add(m.group(1))
            return
        # A variable: the identifier before '=', '[' or '{' or the end.
        m = re.search(r"(" + IDENT + r")\s*(?:\[[^\]]*\]\s*)*(?:=|$|\{)", h if eq < 0 else h[:eq + 1])
        if m and m.group(1) not in KEYWORDS:
            names.add(m.group(1))

    i = 0
    while i < len(text):
        c = text[i]
        if c == "{":
            h = "".join(head).strip()
            if at_file_scope():
                if re.fullmatch(r"(inline\s+)?namespace", h):
                    stack.append("anon")
                elif re.match(r"(inline\s+)?namespace\b", h):
                    stack.append("named")
                elif re.fullmatch(r'extern\s*""', h):
                    stack.append("anon")
                else:
                    declare(h)
                    stack.append("other")
            else:
                stack.append("other")
            head = []
        elif c == "}":
            if stack:
                stack.pop()
            head = []
        elif c == ";":
            if at_file_scope():
                declare("".join(head))
            head = []
        else:
            head.append(c)
        i += 1
    return names


def main() -> int:
    if len(sys.argv) != 2:
        print(__doc__.strip().splitlines()[0], file=sys.stderr)
        print("usage: tools/unity_names.py BUILD_DIR", file=sys.stderr)
        return 2
    build = Path(sys.argv[1])
    # Only the batches the build uses (a target switched to SEPARATE_FILES leaves old ones).
    ninja = (build / "build.ninja").read_text(errors="replace") if (build / "build.ninja").exists() else None
    batches = [b for b in sorted(build.glob("**/Unity/unity_*_cxx.cxx"))
               if ninja is None or str(b.relative_to(build)) in ninja]
    clashes = []
    for batch in batches:
        files = [Path(m) for m in re.findall(r'#include\s+"([^"]+)"', batch.read_text())]
        owners = defaultdict(list)
        for f in files:
            for name in file_scope_names(f):
                owners[name].append(f)
        for name, where in sorted(owners.items()):
            if len(where) > 1 and name != "main":
                clashes.append(f"{batch}: '{name}' at file scope in " + ", ".join(str(w) for w in where))
    for c in clashes:
        print(c)
    if clashes:
        print(f"unity_names: {len(clashes)} name(s) shared inside a unity batch: rename one, move it to a "
              "shared header, or give the target SEPARATE_FILES (tests/CMakeLists.txt)")
        return 1
    print(f"unity_names: {len(batches)} batches, no file-scope name shared")
    return 0


if __name__ == "__main__":
    sys.exit(main())
