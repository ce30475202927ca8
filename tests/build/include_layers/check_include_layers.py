#!/usr/bin/env python3
"""The include graph of romp's libraries, folder by folder, against the design card's layers.

    check_include_layers.py ROOT          checks the tree at ROOT
    check_include_layers.py --self-test   checks the checker on small made-up trees

A folder is the directory of a source file (kernels/mpm, nn/io, host/run, host for host/'s root files).
The rules (DESIGN.md, Layers; issue #34):
  1. a layer includes only itself and the layers above it: kernels/ < nn/ < host/;
  2. no two folders include each other, directly or through others (the folder graph has no cycle), so
     every folder can be read and built knowing only the folders it includes;
  3. kernels/ and nn/io (the file formats) include no LibTorch, and kernels/ no HDF5.
Prints every violation with one include that causes it, and exits 1 if there is any.
"""
import os
import re
import sys

LAYERS = ["kernels", "nn", "host"]  # each may include those before it
SOURCE_SUFFIXES = (".h", ".cpp", ".cu", ".cuh")
QUOTED = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
ANGLED = re.compile(r'^\s*#\s*include\s+<([^>]+)>', re.M)
NO_TORCH = ("kernels", "nn/io")


def folder_of(path):
    return os.path.dirname(path)


def layer_of(folder):
    return folder.split("/")[0]


def inside(folder, prefix):
    return folder == prefix or folder.startswith(prefix + "/")


def violations(sources):
    """sources: {relative path: file text} of the library layers. Returns the violations, one line each."""
    found = []
    edges = {}  # (from folder, to folder) -> the first "file includes header" that makes it
    for path in sorted(sources):
        text = sources[path]
        folder = folder_of(path)
        for header in QUOTED.findall(text):
            target = folder_of(header)
            if layer_of(target) not in LAYERS:
                continue
            if LAYERS.index(layer_of(target)) > LAYERS.index(layer_of(folder)):
                found.append(f"layer: {path} includes {header} ({layer_of(folder)}/ may not use {layer_of(target)}/)")
            if target != folder:
                edges.setdefault((folder, target), f"{path} includes {header}")
        for header in ANGLED.findall(text):
            if header.startswith(("torch/", "ATen/", "c10/")) and any(inside(folder, p) for p in NO_TORCH):
                found.append(f"torch: {path} includes <{header}> ({folder}/ must build without LibTorch)")
            if header.startswith("hdf5") and inside(folder, "kernels"):
                found.append(f"hdf5: {path} includes <{header}> (kernels/ does no file I/O)")
    found += cycles(edges)
    return found


def cycles(edges):
    """One line per folder cycle, as the chain of includes around it."""
    graph = {}
    for a, b in edges:
        graph.setdefault(a, set()).add(b)
    state, stack, found, reported = {}, [], [], set()

    def visit(node):
        state[node] = "open"
        stack.append(node)
        for succ in sorted(graph.get(node, ())):
            if state.get(succ) == "open":
                loop = stack[stack.index(succ):] + [succ]
                key = frozenset(loop)
                if key not in reported:
                    reported.add(key)
                    chain = "; ".join(edges[(loop[i], loop[i + 1])] for i in range(len(loop) - 1))
                    found.append(f"cycle: {' -> '.join(loop)} ({chain})")
            elif succ not in state:
                visit(succ)
        stack.pop()
        state[node] = "done"

    for node in sorted(graph):
        if node not in state:
            visit(node)
    return found


def read_tree(root):
    sources = {}
    for layer in LAYERS:
        for folder, _, names in os.walk(os.path.join(root, layer)):
            for name in names:
                if name.endswith(SOURCE_SUFFIXES):
                    path = os.path.join(folder, name)
                    with open(path, encoding="utf-8") as f:
                        sources[os.path.relpath(path, root)] = f.read()
    return sources


def self_test():
    clean = {
        "kernels/mpm/a.h": '#include "kernels/math/b.h"\n',
        "kernels/math/b.h": "#include <cmath>\n",
        "nn/io/c.h": '#include "kernels/math/b.h"\n#include <hdf5.h>\n',
        "nn/rom/d.cpp": '#include "nn/io/c.h"\n#include <torch/torch.h>\n',
        "host/run/e.cpp": '#include "nn/rom/d.h"\n#include "host/f.h"\n',
        "host/f.h": "",
    }
    assert violations(clean) == [], violations(clean)
    upward = dict(clean, **{"nn/io/g.cpp": '#include "host/f.h"\n'})
    assert violations(upward) == ["layer: nn/io/g.cpp includes host/f.h (nn/ may not use host/)"], violations(upward)
    loop = dict(clean, **{"host/f.h": '#include "host/run/e.h"\n'})
    assert violations(loop) == ["cycle: host -> host/run -> host (host/f.h includes host/run/e.h; "
                                "host/run/e.cpp includes host/f.h)"], violations(loop)
    torch_in_io = dict(clean, **{"nn/io/h.cpp": "#include <torch/torch.h>\n"})
    assert violations(torch_in_io) == ["torch: nn/io/h.cpp includes <torch/torch.h> (nn/io/ must build without "
                                       "LibTorch)"], violations(torch_in_io)
    hdf5_in_kernels = dict(clean, **{"kernels/mpm/i.cu": "#include <hdf5.h>\n"})
    assert len(violations(hdf5_in_kernels)) == 1, violations(hdf5_in_kernels)
    print("check_include_layers self-test: ok")


def main(argv):
    if argv[1:] == ["--self-test"]:
        self_test()
        return 0
    sources = read_tree(argv[1])
    found = violations(sources)
    for line in found:
        print(line)
    folders = {folder_of(p) for p in sources}
    print(f"{len(sources)} files in {len(folders)} folders: {len(found)} violation(s)")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
