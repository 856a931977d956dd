#!/usr/bin/env python3
"""The include graph by folder: prints `from -> to  count` for every #include "folder/file.h" whose
folder differs from the including file's, then the folders in layer order; exits 1 when the folders
include each other in a cycle, or when a folder includes one the layering below does not allow it
(docs/ARCHITECTURE.md: the window, ui/, sees the editor and the files it opens, never a producer or
the pyramid). Run by ctest (include_layering). Usage: scripts/include_graph.py [SOURCE_ROOT]"""
import collections
import pathlib
import re
import sys

# The folders each folder may include (besides itself); a folder not listed may include any.
ALLOWED = {
    "model": set(),
    "raster": {"model"},
    "synth": {"model", "raster"},
    "io": {"model", "raster"},
    "pyramid": {"model", "raster", "io"},
    "editor": {"model", "raster", "io", "pyramid"},
    "ui": {"model", "io", "editor"},
    "bench": {"model", "raster", "synth", "io", "pyramid", "editor"},
    "fuzz": {"model", "io", "pyramid"},
}

root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parent.parent)
include = re.compile(r'^\s*#\s*include\s+"([^"/]+)/[^"]+"', re.M)
skip = {"build", "third_party", ".git"}
edges = collections.Counter()
folders = set()
for path in sorted(root.rglob("*")):
    rel = path.relative_to(root)
    if path.suffix not in (".h", ".cpp") or rel.parts[0] in skip or rel.parts[0].startswith("build") or len(rel.parts) < 2:
        continue
    source = rel.parts[0]
    folders.add(source)
    for target in include.findall(path.read_text(errors="replace")):
        if (root / target).is_dir() and target != source:
            edges[(source, target)] += 1
            folders.add(target)

for (source, target), count in sorted(edges.items()):
    print(f"{source:8} -> {target:8} {count:4}")

forbidden = [(s, t) for (s, t) in sorted(edges) if s in ALLOWED and t not in ALLOWED[s]]
for source, target in forbidden:
    print(f"not allowed: {source} includes {target} (scripts/include_graph.py: ALLOWED)")

graph = collections.defaultdict(set)
for source, target in edges:
    graph[source].add(target)
order, state, cycle = [], {}, []


def visit(node, stack):
    state[node] = "open"
    for nxt in sorted(graph[node]):
        if state.get(nxt) == "open":
            cycle.extend(stack[stack.index(nxt):] + [nxt] if nxt in stack else [node, nxt])
            return
        if nxt not in state:
            visit(nxt, stack + [nxt])
            if cycle:
                return
    state[node] = "done"
    order.append(node)


for folder in sorted(folders):
    if folder not in state and not cycle:
        visit(folder, [folder])
if cycle:
    print("cycle: " + " -> ".join(cycle))
    sys.exit(1)
print("layers (each includes only folders before it): " + " <- ".join(order))
if forbidden:
    sys.exit(1)
