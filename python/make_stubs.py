#!/usr/bin/env python3
"""Writes the type stubs of the compiled module (radar_ndt/_radar_ndt.pyi) beside it, with mypy's
stubgen (Debian's mypy; offline), and makes what it read from pybind11 valid for type checkers:
numpy.ndarray[numpy.float64[3,3]] becomes numpy.ndarray, a return annotation that is not a type
(stubgen reads a property's docstring as one) becomes Any, an attribute whose docstring stubgen
read as its type (the options' fields, documented from their field tables) gets the type its
getter's signature gives, and a path takes str as well.

Usage: make_stubs.py PACKAGE_PARENT [STUBGEN]   (the folder holding radar_ndt/, e.g. build/python;
the stubgen program, default the one on PATH)
"""

import ast
import os
import pathlib
import re
import subprocess
import sys
import tempfile


def plain_arrays(text):
    """numpy.ndarray[...] (brackets nested) as numpy.ndarray."""
    out, i, key = [], 0, "numpy.ndarray["
    while True:
        j = text.find(key, i)
        if j < 0:
            return "".join(out) + text[i:]
        out.append(text[i:j] + "numpy.ndarray")
        depth, k = 1, j + len(key)
        while depth:
            depth += {"[": 1, "]": -1}.get(text[k], 0)
            k += 1
        i = k


TYPE_NAMES = {"int", "float", "str", "bool", "bytes", "dict", "list", "tuple", "object", "None", "Any", "List",
              "Dict", "Tuple", "Optional", "Union", "Callable", "Iterator", "numpy"}


def valid_returns(text):
    """Each `-> X: ...` whose X is not a type (a name the stub defines or imports) becomes `-> Any: ...`."""
    known = TYPE_NAMES | set(re.findall(r"^class (\w+)", text, re.M))

    def fix(m):
        names = re.findall(r"(?<![\w.])[A-Za-z_]\w*", m.group(1))
        try:
            ast.parse(m.group(1), mode="eval")
        except SyntaxError:
            names = ["?"]
        return m.group(0) if names and set(names) <= known else "-> Any: ..."

    text = re.sub(r"-> (.+): \.\.\.$", fix, text, flags=re.M)
    # pybind11's path caster takes str and os.PathLike; stubgen writes only the latter.
    text = text.replace(": os.PathLike", ": Union[str, os.PathLike]")
    return "from typing import Any, Union\n" + text


def attribute_types(text, module):
    """`name: X` in `class C:` with X not a type: the type C.name's getter returns (pybind11 writes
    it in the getter's signature, "(self: C) -> float")."""
    known = TYPE_NAMES | set(re.findall(r"^class (\w+)", text, re.M))
    out, cls = [], None
    for line in text.split("\n"):
        m = re.match(r"^class (\w+)", line)
        if m:
            cls = m.group(1)
        a = re.match(r"^(    )(\w+): (.+)$", line)
        if a and cls and not a.group(3).endswith("..."):
            names = re.findall(r"(?<![\w.])[A-Za-z_]\w*", a.group(3))
            try:
                ast.parse(a.group(3), mode="eval")
                valid = bool(names) and set(names) <= known
            except SyntaxError:
                valid = False
            if not valid:
                kind = "Any"
                attr = getattr(getattr(module, cls, None), a.group(2), None)
                sig = re.search(r"-> ([\w.\[\], ]+)", getattr(getattr(attr, "fget", None), "__doc__", "") or "")
                if sig:
                    kind = re.sub(r"radar_ndt\._radar_ndt\.", "", sig.group(1).strip())
                    kind = re.sub(r"\blist\b", "list", kind)
                    kind = plain_arrays(kind)
                line = a.group(1) + a.group(2) + ": " + kind
        out.append(line)
    return "\n".join(out)


def main():
    parent = pathlib.Path(sys.argv[1]).resolve()
    env = dict(os.environ, PYTHONPATH=str(parent))
    with tempfile.TemporaryDirectory() as tmp:
        stubgen = sys.argv[2] if len(sys.argv) > 2 else "stubgen"
        subprocess.run([stubgen, "-p", "radar_ndt._radar_ndt", "-o", tmp], check=True, env=env,
                       stdout=subprocess.DEVNULL)
        stub = (pathlib.Path(tmp) / "radar_ndt" / "_radar_ndt.pyi").read_text()
    sys.path.insert(0, str(parent))
    import radar_ndt._radar_ndt as module  # the module stubgen read, for its getters' signatures
    stub = attribute_types(plain_arrays(stub), module)
    (parent / "radar_ndt" / "_radar_ndt.pyi").write_text(valid_returns(stub))


if __name__ == "__main__":
    main()
