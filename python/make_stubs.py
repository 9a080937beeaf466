#!/usr/bin/env python3
"""Writes the type stubs of the compiled module (radar_ndt/_radar_ndt.pyi) beside it, with mypy's
stubgen (Debian's mypy; offline), and makes what it read from pybind11 valid for type checkers:
numpy.ndarray[numpy.float64[3,3]] becomes numpy.ndarray, a return annotation that is not a type
(stubgen reads a property's docstring as one) becomes Any, and a path takes str as well.

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


def main():
    parent = pathlib.Path(sys.argv[1]).resolve()
    env = dict(os.environ, PYTHONPATH=str(parent))
    with tempfile.TemporaryDirectory() as tmp:
        stubgen = sys.argv[2] if len(sys.argv) > 2 else "stubgen"
        subprocess.run([stubgen, "-p", "radar_ndt._radar_ndt", "-o", tmp], check=True, env=env,
                       stdout=subprocess.DEVNULL)
        stub = (pathlib.Path(tmp) / "radar_ndt" / "_radar_ndt.pyi").read_text()
    (parent / "radar_ndt" / "_radar_ndt.pyi").write_text(valid_returns(plain_arrays(stub)))


if __name__ == "__main__":
    main()
