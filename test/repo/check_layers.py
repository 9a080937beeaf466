#!/usr/bin/env python3
"""The layers, read from the folders: no folder includes a header of a higher one.

    core  <  io, registration  <  radar_ndt  <  sim  <  apps, benchmarks, python, test;  core  <  io  <  ros  <  apps, benchmarks

and inside radar_ndt/: frontend < odometry < pipeline < evaluation. io and registration are
beside each other and include neither the other. Every header is found by where it lives
(`<folder>/include/radar_ndt/...`), so a file that moves changes its layer with it.

Usage: check_layers.py REPO_ROOT       checks the repository (exit 1 naming each include that
                                       reaches up or sideways)
       check_layers.py --self-test     checks that a tree with one such include fails and the
                                       same tree without it passes
"""
import os
import re
import shutil
import sys
import tempfile

# Each top-level folder and the folders its files may include from (its own always).
ALLOWED = {
    "core": {"core"},
    "io": {"core"},
    "registration": {"core"},
    "radar_ndt": {"core", "io", "registration"},
    "sim": {"core", "io", "registration", "radar_ndt"},
    "ros": {"core", "io"},
    "python": {"core", "io", "registration", "radar_ndt", "ros"},
    "apps": {"core", "io", "registration", "radar_ndt", "sim", "ros"},
    "benchmarks": {"core", "io", "registration", "radar_ndt", "sim", "ros"},
}
# The stages inside radar_ndt/, lowest first: a stage includes only its own and lower ones.
STAGES = ["frontend", "odometry", "pipeline", "evaluation"]
INCLUDE = re.compile(r'^\s*#\s*include\s*[<"](radar_ndt/[^>"]+)[>"]', re.M)


def owners(root):
    """Each public header's include path ("radar_ndt/io/nuscenes.h") -> the top folder it lives in."""
    found = {}
    for top in ALLOWED:
        for folder, _, names in os.walk(os.path.join(root, top)):
            rel = os.path.relpath(folder, root).split(os.sep)
            if "include" not in rel:
                continue
            inc = rel[rel.index("include") + 1:]
            for name in names:
                found["/".join(inc + [name])] = top
    return found


def stage_of(rel):
    """The radar_ndt/ stage a library file or header include path belongs to, or None."""
    parts = rel.split("/")
    for s in STAGES:
        if s in parts:
            return s
    return None


def check(root):
    where = owners(root)
    problems = []
    for top in ALLOWED:
        for folder, _, names in os.walk(os.path.join(root, top)):
            for name in sorted(names):
                if not name.endswith((".h", ".hpp", ".cpp")):
                    continue
                path = os.path.join(folder, name)
                rel = os.path.relpath(path, root).replace(os.sep, "/")
                for inc in INCLUDE.findall(open(path, encoding="utf-8").read()):
                    owner = where.get(inc)
                    if owner is None:
                        problems.append("%s: includes %s, which no layer's include folder holds" % (rel, inc))
                    elif owner != top and owner not in ALLOWED[top]:
                        problems.append("%s (%s) includes %s of %s, a higher or sideways layer" % (rel, top, inc, owner))
                    elif top == "radar_ndt" and owner == "radar_ndt":
                        mine, theirs = stage_of(rel), stage_of(inc)
                        if mine and theirs and STAGES.index(theirs) > STAGES.index(mine):
                            problems.append("%s (%s) includes %s of the later stage %s" % (rel, mine, inc, theirs))
    return problems


def self_test():
    """A tree with io/ including a radar_ndt/ header fails; without that include it passes."""
    tmp = tempfile.mkdtemp()
    try:
        def write(rel, text):
            os.makedirs(os.path.dirname(os.path.join(tmp, rel)), exist_ok=True)
            open(os.path.join(tmp, rel), "w").write(text)
        write("core/include/radar_ndt/se2.h", "#pragma once\n")
        write("io/include/radar_ndt/io/reader.h", '#include "radar_ndt/se2.h"\n')
        write("radar_ndt/include/radar_ndt/frontend/f.h", '#include "radar_ndt/io/reader.h"\n')
        write("radar_ndt/include/radar_ndt/odometry/o.h", '#include "radar_ndt/frontend/f.h"\n')
        clean = check(tmp)
        write("io/src/reader.cpp", '#include "radar_ndt/frontend/f.h"\n')
        up = check(tmp)
        os.remove(os.path.join(tmp, "io/src/reader.cpp"))
        write("radar_ndt/src/frontend/f.cpp", '#include "radar_ndt/odometry/o.h"\n')
        stage = check(tmp)
    finally:
        shutil.rmtree(tmp)
    ok = not clean and len(up) == 1 and "io/src/reader.cpp" in up[0] and len(stage) == 1
    print("self-test: clean tree %d problems, io including the front-end %d, a front-end file including "
          "odometry %d: %s" % (len(clean), len(up), len(stage), "ok" if ok else "FAILED"))
    return 0 if ok else 1


def main(argv):
    if len(argv) != 2:
        sys.exit(__doc__)
    if argv[1] == "--self-test":
        return self_test()
    problems = check(argv[1])
    for p in problems:
        print(p)
    print("layers: %d includes reach up or sideways" % len(problems))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
