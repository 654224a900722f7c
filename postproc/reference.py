"""Where the digitised laboratory data live: ``../shared/reference/experiments/<name>`` beside the
repository (never copied into it).

``$MPMICE_REFERENCE`` names another shared reference folder (the one holding ``experiments/``);
from a git worktree whose own ``../shared`` is absent, the folder beside the main checkout is
used. The postproc scripts take ``--reference DIR`` on top of this default.
"""
from __future__ import annotations

import os

from postproc.run_case import ROOT


def _main_checkout(root: str) -> str | None:
    """The main checkout of the git worktree ``root`` (its ``.git`` a file naming
    ``gitdir: <main>/.git/worktrees/<name>``), or None."""
    marker = os.path.join(root, ".git")
    if not os.path.isfile(marker):
        return None
    with open(marker, encoding="utf-8") as handle:
        line = handle.readline().strip()
    if not line.startswith("gitdir:"):
        return None
    gitdir = line.split(":", 1)[1].strip()
    sep = os.sep + ".git" + os.sep
    return gitdir.split(sep)[0] if sep in gitdir else None


def experiment_folder(name: str, root: str = ROOT) -> str:
    """The folder of the experiment ``name`` (e.g. ``rondon2011``, ``grilli2017``)."""
    override = os.environ.get("MPMICE_REFERENCE")
    if override:
        return os.path.normpath(os.path.join(override, "experiments", name))
    here = os.path.normpath(os.path.join(root, "..", "shared", "reference", "experiments", name))
    main = None if os.path.isdir(here) else _main_checkout(root)
    if main:
        return os.path.normpath(os.path.join(main, "..", "shared", "reference", "experiments",
                                             name))
    return here
