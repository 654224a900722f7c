"""Heat-conduction scene against its exact solution.

Usage:  python -m postproc.heat_conduction OUTPUT_DIR [--name NAME] [--png FILE]

Reads the last dump of the run in OUTPUT_DIR, prints the relative L2 error of the temperature
perturbation, ``||T - T_exact||_2 / ||T_exact - T_base||_2``, and writes a comparison PNG.
"""
from __future__ import annotations

import argparse
import os

import numpy as np

from postproc.analytic import heat_mode_solution
from postproc.figures import pyplot, save_figure
from postproc.mpmice_io import cell_centres, list_dumps, read_dump
from postproc.namelist import parse_namelist_text
from postproc.run_files import run_name


def dump_files(output_dir: str, name: str | None = None) -> list[str]:
    """Dump files of a run (not checkpoints or failure dumps), sorted by step
    (``mpmice_io.list_dumps`` of the run ``name``, or of the one run in ``output_dir``)."""
    return list_dumps(output_dir, run_name(output_dir, name))


def read_temperature(path: str) -> dict:
    """Temperature [i, j, k], grid attributes and the resolved input of one dump
    (``mpmice_io.read_dump``)."""
    dump = read_dump(path)
    attrs = dump["attrs"]
    ncells = np.asarray(attrs["ncells"]).astype(int)
    lower = np.asarray(attrs["lower"], dtype=float)
    dx = np.asarray(attrs["dx"], dtype=float)
    return {"time": dump["time"], "step": dump["step"], "T": dump["cell"]["temperature"],
            "centres": list(cell_centres(dump)), "ncells": ncells, "lower": lower,
            "upper": lower + ncells * dx, "nml": parse_namelist_text(str(attrs["namelist"]))}


def exact_temperature(dump: dict) -> np.ndarray:
    """Exact solution at the dump's cell centres and time."""
    grid = dump["nml"]["grid"]
    periodic = grid.get("periodic", [False, False, False])
    active = [n > 1 for n in dump["ncells"]]
    return heat_mode_solution(dump["centres"], dump["lower"], dump["upper"], periodic, active,
                              dump["nml"].get("heat", {}), dump["time"])


def relative_error(dump: dict) -> float:
    """||T - T_exact||_2 / ||T_exact - T_base||_2 over all cells."""
    exact = exact_temperature(dump)
    base = dump["nml"].get("heat", {}).get("base_temperature", 300.0)
    return float(np.linalg.norm(dump["T"] - exact) / np.linalg.norm(exact - base))


def plot_comparison(dump: dict, png: str) -> None:
    """Profile along x through the middle of the other dimensions: computed vs exact."""
    plt = pyplot()

    exact = exact_temperature(dump)
    base = dump["nml"].get("heat", {}).get("base_temperature", 300.0)
    j = dump["ncells"][1] // 2
    k = dump["ncells"][2] // 2
    x = dump["centres"][0]
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    axes[0].plot(x, exact[:, j, k] - base, "k-", label="exact")
    axes[0].plot(x, dump["T"][:, j, k] - base, "o", ms=3, label="MPMICE")
    axes[0].set_xlabel("x [m]")
    axes[0].set_ylabel(f"T - {base:g} K [K]")
    axes[0].set_title(f"t = {dump['time']:.4g} s, cut at j={j + 1}, k={k + 1}")
    axes[0].legend()
    if dump["ncells"][1] > 1:
        err = (dump["T"] - exact)[:, :, k]
        im = axes[1].imshow(err.T, origin="lower", aspect="auto",
                            extent=[dump["lower"][0], dump["upper"][0], dump["lower"][1],
                                    dump["upper"][1]])
        fig.colorbar(im, ax=axes[1], label="T - T_exact [K]")
        axes[1].set_xlabel("x [m]")
        axes[1].set_ylabel("y [m]")
    else:
        axes[1].plot(x, dump["T"][:, j, k] - exact[:, j, k])
        axes[1].set_xlabel("x [m]")
        axes[1].set_ylabel("T - T_exact [K]")
    axes[1].set_title(f"relative L2 error {relative_error(dump):.3e}")
    fig.tight_layout()
    save_figure(fig, png)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("output_dir")
    parser.add_argument("--name", default=None)
    parser.add_argument("--png", default=None)
    args = parser.parse_args(argv)
    files = dump_files(args.output_dir, args.name)
    if not files:
        parser.error(f"no dumps in {args.output_dir}")
    dump = read_temperature(files[-1])
    error = relative_error(dump)
    png = args.png or os.path.join(args.output_dir, "heat_conduction_vs_exact.png")
    plot_comparison(dump, png)
    print(f"{os.path.basename(files[-1])}: t = {dump['time']:.6g} s, "
          f"relative L2 error of the perturbation = {error:.4e}")
    print(f"plot: {png}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
