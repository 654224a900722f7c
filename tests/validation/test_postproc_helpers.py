"""The shared helpers of the postproc scripts (postproc/figures.py, postproc/mpmice_io.list_dumps),
without runs of mpmice (~1 s)."""
import os

import h5py

from postproc import figures, mpm_common
from postproc.mpmice_io import list_dumps
from postproc.run_case import ROOT


def test_study_parser_defaults_and_out_folder(tmp_path):
    parser = figures.study_parser("first line\nrest", nranks=True)
    assert parser.description == "first line"
    args = parser.parse_args([])
    assert args.out == os.path.join(ROOT, "docs", "validation") and args.nranks == 1
    assert "nranks" not in vars(figures.study_parser("d").parse_args([]))
    out = tmp_path / "a" / "b"
    args = figures.parse_study_args(parser, ["--out", str(out), "--nranks", "2"])
    assert out.is_dir() and args.nranks == 2


def test_save_figure_writes_and_closes(tmp_path):
    plt = figures.pyplot()
    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1])
    path = figures.save_figure(fig, str(tmp_path / "f.png"), dpi=50)
    assert path == str(tmp_path / "f.png") and os.path.getsize(path) > 0
    assert not plt.fignum_exists(fig.number)


def test_list_dumps_order_and_exclusions(tmp_path):
    """Dumps in step order (7-digit steps after 6-digit ones); checkpoints, failure dumps, other
    cases and other files left out; mpm_common.dump_paths is the same function."""
    names = ["case_000010.h5", "case_000002.h5", "case_1000000.h5", "case_checkpoint_000010.h5",
             "case_failed_000011.h5", "case_000010.xmf", "case2_000001.h5", "other_000001.h5"]
    for name in names:
        # a minimal dump: list_dumps skips files without the root attributes time and step
        with h5py.File(tmp_path / name, "w") as f:
            f.attrs["time"] = 0.0
            f.attrs["step"] = 0
    expected = [str(tmp_path / n) for n in ("case_000002.h5", "case_000010.h5", "case_1000000.h5")]
    assert list_dumps(str(tmp_path), "case") == expected
    assert mpm_common.dump_paths is list_dumps


def test_launcher_noise_is_dropped_from_stderr():
    """The event library's shutdown warning that Open MPI's launcher sometimes prints (seen once
    in a 2-rank input-error test: a second stderr line) is dropped; the program's lines, and any
    other line, are kept."""
    from postproc.run_case import without_launcher_noise
    program = "mpmice: input error: case.nml: &heat conductivity = NaN: a finite number, > 0\n"
    noise = ("[warn] Epoll MOD(1) on fd 24 failed. Old events were 6; read change was 0 (none); "
             "write change was 2 (del); close change was 0 (none): Bad file descriptor\n")
    assert without_launcher_noise(program + noise) == program
    assert without_launcher_noise(noise + program) == program
    other = "[warn] something else\n"
    assert without_launcher_noise(program + other) == program + other
    assert without_launcher_noise(None) == ""
