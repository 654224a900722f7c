"""The folder layering of modules/ (docs/architecture.md, "Layering"), from the `use`
statements as scripts/module_deps.py reads them: no folder cycle, and MPI only where allowed."""
import importlib.util
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

#: Folders whose files may `use mpi_f08`: parallel/ wraps MPI for every layer above it (base/,
#: below it, gets its abort and finalize from parallel_comm%mpi_start).
MPI_FOLDERS = {"parallel"}


def _module_deps():
    spec = importlib.util.spec_from_file_location("module_deps", ROOT / "scripts" / "module_deps.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_no_folder_cycles():
    """The folder graph of modules/, src/, tools/ and bench/ has no cycle."""
    deps = _module_deps()
    owner, uses = deps.scan(ROOT)
    graph = deps.folder_graph(owner, uses)
    assert {"base", "parallel", "grid", "scene", "particles", "driver"} <= set(graph)
    assert deps.cycles(graph) == []
    assert "parallel" not in graph["grid"] and "driver" not in graph["mpmice"]
    # ICE knows nothing of solids: the exchange layer (the solid phase and the fluid-solid
    # exchange) sits above it and hands ICE's stages the solid's view (`ice_solid_view_t`)
    assert "exchange" not in graph["ice"] and "ice" in graph["exchange"]


def test_cycle_detection_finds_a_cycle():
    """The check can fail: a graph with a cycle is reported."""
    deps = _module_deps()
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}
    assert deps.cycles(graph) == [["a", "b", "c"]]


def test_mpi_only_in_allowed_folders():
    """No file of modules/ outside MPI_FOLDERS uses mpi_f08 (src/ none either)."""
    deps = _module_deps()
    _, uses = deps.scan(ROOT)
    users = {path.relative_to(ROOT) for _, path, mod in uses if mod in ("mpi_f08", "mpi")}
    outside = sorted(str(p) for p in users if p.parts[0] in ("modules", "src")
                     and (p.parts[0] == "src" or p.parts[1] not in MPI_FOLDERS))
    assert outside == []
    assert Path("modules/parallel/parallel_comm.f90") in users


def test_mpi_c_bindings_only_in_allowed_folders():
    """No file of modules/ or src/ outside MPI_FOLDERS binds an MPI C function (`bind(c,
    name='MPI_...')`): the C handle of a communicator for hypre comes from parallel_comm."""
    bound = []
    sources = [path for ext in ("*.f90", "*.fypp") for path in sorted((ROOT / "modules").rglob(ext))]
    for path in sources + sorted((ROOT / "src").rglob("*.f90")):
        rel = path.relative_to(ROOT)
        text = path.read_text(encoding="utf-8").lower()
        if "name='mpi_" in text.replace('"', "'").replace(" ", ""):
            bound.append(rel)
    outside = sorted(str(p) for p in bound if p.parts[0] == "src" or p.parts[1] not in MPI_FOLDERS)
    assert outside == []
    assert Path("modules/parallel/parallel_comm.f90") in bound
