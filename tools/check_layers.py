#!/usr/bin/env python3
"""Checks the libraries' layers in CMake's target graph (cmake --graphviz): no cycle, and each
project library links only libraries of layers below its own (docs/architecture.md):

    core/quantum < core/game, core/audio, core/tracking, core/reference < bindings < runtime
    < runtime/desk, tools/synthetic < tools

Usage: check_layers.py BUILD_DIR SOURCE_DIR. Writes BUILD_DIR/layers/graph.dot and prints every
link that breaks the order, exiting 1 if there is one."""
import os
import re
import subprocess
import sys

LAYERS = {
    "quantum_core": 0,
    "quantum_game": 1, "quantum_audio": 1, "quantum_tracking": 1, "quantum_reference": 1,
    "quantum_lua": 2,
    "quantum_runtime": 3,
    # Beside the runtime's sessions, drawing them (the desk) or making the tests' recordings.
    "quantum_desk": 4, "quantum_synthetic": 4,
    "quantum_tools": 5,
}
# Links no layer order forbids but the design does: the runtime knows no Lua (its sport comes
# through runtime/sport_source.h), and so neither directly nor through another library.
NEVER = [("quantum_runtime", "quantum_lua")]


def links(dot):
    """(from, to) target names for each edge of the graphviz file."""
    names = dict(re.findall(r'"(node\d+)"\s*\[\s*label\s*=\s*"([^"]+)"', dot))
    return [(names[a], names[b]) for a, b in re.findall(r'"(node\d+)"\s*->\s*"(node\d+)"', dot) if a in names and b in names]


def cycle(edges):
    """A cycle among the edges as a list of names, or None."""
    graph = {}
    for a, b in edges:
        graph.setdefault(a, []).append(b)
    state, path = {}, []

    def visit(node):
        state[node] = "open"
        path.append(node)
        for nxt in graph.get(node, []):
            if state.get(nxt) == "open":
                return path[path.index(nxt):] + [nxt]
            if nxt not in state:
                found = visit(nxt)
                if found:
                    return found
        state[node] = "done"
        path.pop()
        return None

    for node in list(graph):
        if node not in state:
            found = visit(node)
            if found:
                return found
    return None


def reachable(edges, start):
    """Every target `start` links, directly or through others."""
    seen, todo = set(), [start]
    while todo:
        node = todo.pop()
        for a, b in edges:
            if a == node and b not in seen:
                seen.add(b)
                todo.append(b)
    return seen


def main():
    build, source = sys.argv[1], sys.argv[2]
    out = os.path.join(build, "layers")
    os.makedirs(out, exist_ok=True)
    dot_file = os.path.join(out, "graph.dot")
    # Its own folder: configuring there leaves the build's own cache alone.
    subprocess.run(["cmake", "-S", source, "-B", os.path.join(out, "build"), "--graphviz=" + dot_file,
                    "-DQUANTUM_BUILD_TESTS=OFF"], check=True, stdout=subprocess.DEVNULL)
    with open(dot_file) as f:
        edges = links(f.read())
    ours = [(a, b) for a, b in edges if a in LAYERS and b in LAYERS]
    problems = []
    loop = cycle(ours)
    if loop:
        problems.append("cycle: " + " -> ".join(loop))
    for a, b in ours:
        if LAYERS[b] >= LAYERS[a]:
            problems.append(f"{a} links {b}: a library links only layers below its own")
    for a, b in NEVER:
        if b in reachable(ours, a):
            problems.append(f"{a} reaches {b}, which it must not")
    # A new library must be given its layer here before it may link anything.
    unplaced = sorted({n for e in edges for n in e if n.startswith("quantum_") and n not in LAYERS})
    if unplaced:
        problems.append("libraries with no layer (add them to LAYERS): " + ", ".join(unplaced))
    missing = sorted(set(LAYERS) - {n for e in edges for n in e})
    if missing:
        problems.append("not in the graph (renamed? update tools/check_layers.py): " + ", ".join(missing))
    for p in problems:
        print("check_layers:", p)
    if not problems:
        print(f"check_layers: {len(ours)} links between {len(LAYERS)} libraries, each to a layer below")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
