"""Bitwise comparison of MPMICE dumps and checkpoints: the restart, rank-count and refactoring
checks (two runs that must write the very same numbers).

    from postproc.dump_compare import assert_dumps_identical
    assert_dumps_identical(run_a / "out/case_000040.h5", run_b / "out/case_000040.h5")

    python -m postproc.dump_compare DIR_A DIR_B     # every *.h5 the two folders share

Two files are identical when they hold the same datasets with the same shapes and the same bits
(NaN equal to NaN) and the same root attributes ``time`` and ``step``. Particle datasets are
compared in the order of their ``id`` when the set has one (a rank-count comparison writes the
particles in another order) with ``by_id=True``; otherwise as stored.
"""
from __future__ import annotations

import argparse
import os
import sys

import h5py
import numpy as np

from postproc.mpm_common import particles

#: Root attributes that a bitwise-identical continuation must reproduce.
STATE_ATTRIBUTES = ("time", "step")


def _datasets(f: h5py.File, select=None) -> dict[str, h5py.Dataset]:
    found = {}

    def visit(name, obj):
        if isinstance(obj, h5py.Dataset) and (select is None or select(name)):
            found[name] = obj

    f.visititems(visit)
    return found


def _particle_order(f: h5py.File, name: str):
    """Sort index of the particle set holding dataset ``name`` (by its ``id``), else None."""
    parts = name.split("/")
    if parts[0] != "particles" or len(parts) < 3 or parts[-1] in ("id", "rank_counts"):
        return None
    ids = f.get("/".join(parts[:-1]) + "/id")
    return None if ids is None else np.argsort(ids[...], kind="stable")


def dump_differences(path_a, path_b, select=None, by_id: bool = False) -> list[str]:
    """What differs between two dump or checkpoint files (empty: bitwise identical). ``select``
    (a function of the dataset path) limits the datasets compared; ``by_id`` compares particle
    datasets in the order of their ids."""
    diffs = []
    with h5py.File(path_a, "r") as fa, h5py.File(path_b, "r") as fb:
        for key in STATE_ATTRIBUTES:
            va, vb = fa.attrs.get(key), fb.attrs.get(key)
            if not np.array_equal(np.asarray(va), np.asarray(vb)):
                diffs.append(f"attribute {key}: {va!r} != {vb!r}")
        da, db = _datasets(fa, select), _datasets(fb, select)
        for name in sorted(set(da) ^ set(db)):
            diffs.append(f"{name}: only in {path_a if name in da else path_b}")
        for name in sorted(set(da) & set(db)):
            a, b = da[name][...], db[name][...]
            if by_id and name.split("/")[-1] != "rank_counts":
                oa, ob = _particle_order(fa, name), _particle_order(fb, name)
                if oa is not None and ob is not None and len(oa) == len(a) and len(ob) == len(b):
                    a, b = a[oa], b[ob]
                elif name.split("/")[-1] == "id":
                    a, b = np.sort(a), np.sort(b)
            if a.shape != b.shape:
                diffs.append(f"{name}: shape {a.shape} != {b.shape}")
            elif not np.array_equal(a, b, equal_nan=a.dtype.kind in "fc"):
                if a.dtype.kind in "fc":
                    diffs.append(f"{name}: max |difference| {np.nanmax(np.abs(a - b)):.3e}")
                else:
                    diffs.append(f"{name}: differs")
    return diffs


def assert_dumps_identical(path_a, path_b, select=None, by_id: bool = False) -> None:
    """Fail (AssertionError naming each difference) unless the two files are bitwise identical
    (`dump_differences`)."""
    diffs = dump_differences(path_a, path_b, select=select, by_id=by_id)
    assert not diffs, f"{path_a} and {path_b} differ:\n  " + "\n  ".join(diffs)


def assert_field_close(path_a, path_b, key: str, relative: float) -> None:
    """Dataset ``key`` (e.g. ``cell/pressure``) of two dumps agrees to ``relative`` times its
    largest |value| in ``path_a`` - the rank-count and rebalancing comparisons."""
    with h5py.File(path_a) as fa, h5py.File(path_b) as fb:
        a, b = fa[key][...], fb[key][...]
    assert np.max(np.abs(a - b)) < relative * np.max(np.abs(a)), key


def assert_particles_close(path_a, path_b, solid: str, position: float, velocity: float,
                           stress: float, stresses=("xx", "yy", "xy")) -> None:
    """The particles of ``solid`` in two dumps agree to round-off: the same ids, positions
    within ``position`` [m], velocities within ``velocity`` [m/s] (x and y) and the stress
    components ``stresses`` within ``stress`` times the largest |stress| of ``path_a``
    (xx, yy, xy) - the rank-count and rebalancing comparisons."""
    _, ref = particles(path_a, solid)
    _, other = particles(path_b, solid)
    assert np.array_equal(ref["id"], other["id"])
    scale = max(np.max(np.abs(ref[f"stress_{c}"])) for c in ("xx", "yy", "xy"))
    for c in ("x", "y"):
        assert np.max(np.abs(other[c] - ref[c])) < position, c
        assert np.max(np.abs(other[f"velocity_{c}"] - ref[f"velocity_{c}"])) < velocity, c
    for c in stresses:
        assert np.max(np.abs(other[f"stress_{c}"] - ref[f"stress_{c}"])) < stress * scale, c


def compare_folders(dir_a, dir_b, by_id: bool = False) -> tuple[int, list[str]]:
    """Compare every ``*.h5`` file the two folders (searched recursively) share by relative
    path: (files compared, differences)."""
    def files(root):
        out = {}
        for base, _, names in os.walk(root):
            for n in names:
                if n.endswith(".h5"):
                    full = os.path.join(base, n)
                    out[os.path.relpath(full, root)] = full
        return out

    fa, fb = files(dir_a), files(dir_b)
    diffs = [f"{rel}: only in {dir_a if rel in fa else dir_b}" for rel in sorted(set(fa) ^ set(fb))]
    shared = sorted(set(fa) & set(fb))
    for rel in shared:
        diffs += [f"{rel}: {d}" for d in dump_differences(fa[rel], fb[rel], by_id=by_id)]
    return len(shared), diffs


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description="Bitwise comparison of the dumps of two runs")
    ap.add_argument("a", help="first output folder (or file)")
    ap.add_argument("b", help="second output folder (or file)")
    ap.add_argument("--by-id", action="store_true", help="compare particles in the order of id")
    args = ap.parse_args(argv)
    if os.path.isfile(args.a):
        count, diffs = 1, dump_differences(args.a, args.b, by_id=args.by_id)
    else:
        count, diffs = compare_folders(args.a, args.b, by_id=args.by_id)
    for d in diffs:
        print(d)
    print(f"{count} files compared, {len(diffs)} differences")
    return 1 if diffs or count == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
