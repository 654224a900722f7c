#!/usr/bin/env python3
"""Folder dependency graph of the Fortran modules, from their `use` statements.

    scripts/module_deps.py              the graph (folder -> folders it uses) and its cycles
    scripts/module_deps.py --modules    the module-level edges that cross folders too
    scripts/module_deps.py --mpi        the files that use MPI directly (`use mpi_f08`)
    scripts/module_deps.py --check      exit 1 when the folder graph has a cycle

Every module is mapped to the folder under modules/ (or src/) of the file that defines it; an
edge A -> B means a file in folder A uses a module defined in folder B. Intrinsic and external
modules (iso_fortran_env, mpi_f08, hdf5, ...) are not folders and are left out. A cycle is a
strongly connected component of more than one folder (docs/architecture.md states the allowed
edges).
"""
import argparse
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
MODULE_RE = re.compile(r"^\s*module\s+(?!procedure\b)(\w+)\s*(?:!.*)?$", re.I)
USE_RE = re.compile(r"^\s*use\s*(?:,\s*(?:non_)?intrinsic\s*::\s*|::\s*|\s)\s*(\w+)", re.I)


def sources(root):
    """The Fortran sources of the library and the executables (templates included)."""
    files = []
    for top in ("modules", "src", "tools", "bench"):
        for ext in ("*.f90", "*.F90", "*.f90.in", "*.fypp"):
            files.extend(sorted((root / top).rglob(ext)))
    return files


def folder_of(path, root):
    rel = path.relative_to(root).parts
    return rel[1] if rel[0] == "modules" and len(rel) > 2 else rel[0]


def scan(root):
    """(module -> folder, [(folder, file, used module)])."""
    owner = {}
    uses = []
    for path in sources(root):
        folder = folder_of(path, root)
        for line in path.read_text(errors="replace").splitlines():
            m = MODULE_RE.match(line)
            if m:
                owner[m.group(1).lower()] = folder
                continue
            u = USE_RE.match(line)
            if u:
                uses.append((folder, path, u.group(1).lower()))
    return owner, uses


def folder_graph(owner, uses):
    graph = {f: set() for f in set(owner.values()) | {f for f, _, _ in uses}}
    for folder, _, mod in uses:
        target = owner.get(mod)
        if target is not None and target != folder:
            graph[folder].add(target)
    return graph


def cycles(graph):
    """Strongly connected components with more than one folder (Tarjan)."""
    index, low, stack, on, out = {}, {}, [], set(), []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def layers(graph):
    """Folders by level: a folder's level is one more than the highest it uses (cycles: None)."""
    level = {}

    def depth(v, seen):
        if v in level:
            return level[v]
        if v in seen:
            return None
        seen.add(v)
        below = [depth(w, seen) for w in graph[v]]
        seen.discard(v)
        if any(b is None for b in below):
            return None
        level[v] = 1 + max(below, default=-1)
        return level[v]

    for v in graph:
        depth(v, set())
    return level


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--root", type=Path, default=ROOT, help="repository root")
    ap.add_argument("--modules", action="store_true", help="list cross-folder module edges")
    ap.add_argument("--mpi", action="store_true", help="list files that use mpi_f08")
    ap.add_argument("--check", action="store_true", help="exit 1 on a folder cycle")
    args = ap.parse_args()
    root = args.root.resolve()
    owner, uses = scan(root)
    if args.mpi:
        files = sorted({str(p.relative_to(root)) for _, p, m in uses if m in ("mpi_f08", "mpi")})
        print(f"{len(files)} files use MPI directly:")
        for f in files:
            print(f"  {f}")
        return 0
    graph = folder_graph(owner, uses)
    level = layers(graph)
    print("folder dependencies (folder -> folders it uses), lowest layer first:")
    for v in sorted(graph, key=lambda f: (level.get(f, 99), f)):
        lv = level.get(v)
        print(f"  [{'-' if lv is None else lv}] {v:10s} -> {', '.join(sorted(graph[v])) or '(none)'}")
    if args.modules:
        print("cross-folder module edges:")
        edges = sorted({(folder_of(p, root), str(p.relative_to(root)), m, owner[m])
                        for _, p, m in uses if m in owner and owner[m] != folder_of(p, root)})
        for src, path, mod, dst in edges:
            print(f"  {src} -> {dst}: {path} uses {mod}")
    cyc = cycles(graph)
    if cyc:
        print(f"{len(cyc)} folder cycle(s):")
        for comp in cyc:
            print("  " + " <-> ".join(comp))
            for a in comp:
                for b in sorted(graph[a] & set(comp)):
                    via = sorted({f"{p.relative_to(root)}: {m}" for f, p, m in uses
                                  if f == a and owner.get(m) == b})
                    print(f"    {a} -> {b}: {'; '.join(via[:4])}{' ...' if len(via) > 4 else ''}")
    else:
        print("no folder cycles")
    return 1 if (args.check and cyc) else 0


if __name__ == "__main__":
    sys.exit(main())
