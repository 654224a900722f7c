"""Shared command line and figure helpers of the validation scripts in postproc/.

matplotlib is imported only when a script asks for it (:func:`pyplot`), so the modules that use
these helpers stay importable without it::

    from postproc.figures import parse_study_args, pyplot, save_figure, study_parser

    parser = study_parser(__doc__, nranks=True)       # --out DIR (default docs/validation)
    args = parse_study_args(parser, argv)             # parsed, args.out created
    plt = pyplot()
    fig, ax = plt.subplots()
    ...
    save_figure(fig, os.path.join(args.out, "case.png"))
"""
from __future__ import annotations

import argparse
import csv
import os
import tempfile

from postproc.run_case import ROOT

#: Default folder of the validation reports and plots (the scripts' ``--out``).
VALIDATION_DIR = os.path.join(ROOT, "docs", "validation")


def study_parser(doc: str, nranks: bool = False) -> argparse.ArgumentParser:
    """Command line of a validation study: described by the first line of ``doc`` (the script's
    docstring), with ``--out DIR`` (where the CSV and PNG go; default docs/validation) and, when
    ``nranks`` is true, ``--nranks N`` (MPI ranks of the runs; default 1)."""
    parser = argparse.ArgumentParser(description=doc.splitlines()[0])
    parser.add_argument("--out", default=VALIDATION_DIR)
    if nranks:
        parser.add_argument("--nranks", type=int, default=1)
    return parser


def parse_study_args(parser: argparse.ArgumentParser, argv=None) -> argparse.Namespace:
    """``parser.parse_args(argv)``, with the folder ``args.out`` created when missing."""
    args = parser.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    return args


def run_study(doc: str, run, report, plot, write_csv, stem: str, argv=None) -> int:
    """The ``main`` of a study with ``--out`` and ``--nranks`` (:func:`study_parser`): ``results =
    run(workdir, nranks=N)`` in a temporary folder, then ``report(results)``, ``plot(results,
    OUT/stem.png)`` and ``write_csv(results, OUT/stem.csv)``; returns 0."""
    args = parse_study_args(study_parser(doc, nranks=True), argv)
    with tempfile.TemporaryDirectory() as work:
        results = run(work, nranks=args.nranks)
    report(results)
    plot(results, os.path.join(args.out, stem + ".png"))
    write_csv(results, os.path.join(args.out, stem + ".csv"))
    return 0


def pyplot():
    """``matplotlib.pyplot`` on the non-interactive Agg backend (no display needed)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def save_figure(fig, path: str, dpi: int = 110) -> str:
    """Write ``fig`` to ``path`` (format from the file ending) at ``dpi``, close it (frees its
    memory) and return ``path``."""
    fig.savefig(path, dpi=dpi)
    pyplot().close(fig)
    return path


def write_table(path: str, rows: list[dict], fields: list[str] | None = None) -> str:
    """A study's result table as CSV: one row per dict, the columns `fields` (default: every key
    in the order of first appearance; a row without a column leaves it empty), floats as %.6g."""
    if fields is None:
        fields = []
        for row in rows:
            fields += [k for k in row if k not in fields]
    with open(path, "w", newline="", encoding="utf-8") as f:
        writer = csv.DictWriter(f, fieldnames=fields)
        writer.writeheader()
        for row in rows:
            writer.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v)
                             for k, v in row.items()})
    return path
