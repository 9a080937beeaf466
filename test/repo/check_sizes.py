#!/usr/bin/env python3
"""The repository's size limits, so that a function or a file cannot silently grow past them:
no function in core/, registration/, io/, radar_ndt/, sim/, ros/, apps/, benchmarks/ and python/ is longer than 60 lines (from the first line of
its signature to its closing brace) unless the comment block right above it says why, with the
words "Kept as one function:"; no C++ source file anywhere is longer than 500 lines.

Usage: check_sizes.py REPO_ROOT
Functions are found by brace matching after comments and string literals are blanked: a block
whose head ends in a parameter list (and qualifiers or a constructor's initialisers) outside any
other function is a function; lambdas and blocks inside one count as its lines.
"""
import bisect
import os
import re
import sys

MAX_FUNCTION = 60
MAX_FILE = 500
FUNCTION_DIRS = ("core", "registration", "io", "radar_ndt", "sim", "ros", "apps", "benchmarks", "python")
SOURCE_DIRS = ("apps", "benchmarks", "core", "io", "python", "radar_ndt", "registration", "ros", "sim", "test")
EXCEPTION = "Kept as one function:"


def blank(src):
    """The source with comments and the contents of string and character literals blanked (lines kept)."""
    out, i, n = [], 0, len(src)
    while i < n:
        if src.startswith("//", i):
            j = src.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif src.startswith("/*", i):
            j = src.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", src[i:j]))
            i = j
        elif src[i] == '"' and i > 0 and src[i - 1] == "R":
            m = re.match(r'R"([^(]*)\(', src[i - 1:])
            end = src.find(")" + m.group(1) + '"', i)
            j = end + len(m.group(1)) + 2
            out.append('"' + re.sub(r"[^\n]", " ", src[i + 1:j - 1]) + '"')
            i = j
        elif src[i] in "\"'":
            q, j = src[i], i + 1
            while j < n and src[j] != q:
                j += 2 if src[j] == "\\" else 1
            j += 1
            out.append(q + re.sub(r"[^\n]", " ", src[i + 1:j - 1]) + q)
            i = j
        else:
            out.append(src[i])
            i += 1
    return "".join(out)


FUNC_HEAD = re.compile(r"\)\s*(const|override|final|noexcept|->\s*[\w:<>,\s*&]+|\s)*$|\)\s*:\s*.*$", re.S)


def functions(src):
    """(first line, last line, name) of each function in the source, 1-based."""
    s = blank(src)
    starts = [0]
    for k, ch in enumerate(s):
        if ch == "\n":
            starts.append(k + 1)
    line = lambda pos: bisect.bisect_right(starts, pos)
    stack, found, last = [], [], 0
    for m in re.finditer(r"[{};]", s):
        p, ch = m.start(), m.group()
        if ch == "{":
            head = s[last:p]
            text = " ".join(head.split())
            in_function = any(kind == "function" for kind, _, _ in stack)
            kind = "block"
            if not in_function:
                if re.search(r"\b(namespace|class|struct|enum|union)\b", text) and not re.search(r"\)\s*(const)?\s*$", text):
                    kind = "scope"
                elif FUNC_HEAD.search(text) and not re.search(r"=\s*$|\breturn\b", text):
                    kind = "function"
            first = p - len(head) + (len(head) - len(head.lstrip()))
            stack.append((kind, first, text))
        elif ch == "}" and stack:
            kind, first, text = stack.pop()
            if kind == "function":
                name = re.search(r"([~\w:<>]+)\s*\(", text)
                found.append((line(first), line(p), name.group(1) if name else text[:60]))
        last = p + 1
    return found


def main(root):
    problems = 0
    checked_files = checked_functions = 0
    for top in SOURCE_DIRS:
        for folder, _, names in os.walk(os.path.join(root, top)):
            for name in sorted(names):
                if not name.endswith((".cpp", ".h", ".hpp")):
                    continue
                path = os.path.join(folder, name)
                rel = os.path.relpath(path, root)
                src = open(path, encoding="utf-8").read()
                lines = src.split("\n")
                checked_files += 1
                if len(lines) - (1 if src.endswith("\n") else 0) > MAX_FILE:
                    print("%s: %d lines, more than %d" % (rel, len(lines) - 1, MAX_FILE))
                    problems += 1
                if not rel.startswith(FUNCTION_DIRS):
                    continue
                for first, end, fname in functions(src):
                    checked_functions += 1
                    if end - first + 1 <= MAX_FUNCTION:
                        continue
                    above = []
                    k = first - 2
                    while k >= 0 and lines[k].strip().startswith(("//", "template")):
                        above.append(lines[k])
                        k -= 1
                    if any(EXCEPTION in l for l in above):
                        continue
                    print("%s:%d: %s is %d lines, more than %d (split it, or say why above it: '%s ...')"
                          % (rel, first, fname, end - first + 1, MAX_FUNCTION, EXCEPTION))
                    problems += 1
    print("sizes: %d files, %d functions checked, %d over the limits" % (checked_files, checked_functions, problems))
    return 1 if problems else 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    sys.exit(main(sys.argv[1]))
