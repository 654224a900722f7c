"""The shape of an input file: empty and comments-only files, files without
`&run`, CR-only line ends, a UTF-8 byte-order mark, groups the chosen scene does not read and an
unterminated quote. Every bad file gives one line on standard error naming the file and the
problem, exit status 1 and nothing written (config_parse, config_scene_groups). All runs are
`--check` or stop before the run starts: about 1 s each."""
import pathlib

import pytest

HEAT = "&run name = 'files', scene = 'heat_conduction', output_dir = 'out' /\n"


@pytest.fixture(autouse=True)
def quiet_launcher(monkeypatch):
    """No multi-line report of Open MPI's mpirun on a non-zero exit (as in test_input_errors)."""
    monkeypatch.setenv("OMPI_MCA_orte_execute_quiet", "1")


def write(directory: pathlib.Path, data: bytes) -> pathlib.Path:
    path = directory / "case.nml"
    path.write_bytes(data)
    return path


def one_error_line(result) -> str:
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert result.returncode == 1, result.stdout + result.stderr
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith("mpmice: input error: "), lines[0]
    return lines[0]


@pytest.mark.parametrize("data, pieces", [
    (b"", ["case.nml", "no namelist group"]),
    (b"! only a comment\n\n   ! and another\n", ["case.nml", "no namelist group"]),
    (b"&grid ncells = 8, 1, 1 /\n", ["case.nml", "no &run group", "&grid"]),
])
def test_file_without_run_group_is_an_error(run_mpmice, tmp_case_dir, data, pieces):
    """An empty file, a comments-only file and a file without &run stop with one line, and
    nothing is written: no ./output of a default scene."""
    case = write(tmp_case_dir, data)
    line = one_error_line(run_mpmice([case.name]))
    for piece in pieces:
        assert piece in line, line
    assert sorted(p.name for p in tmp_case_dir.iterdir()) == ["case.nml"]


def test_cr_only_line_ends(run_mpmice, tmp_case_dir):
    """Old Mac line ends: a comment ends at the CR, so the groups after it are read."""
    text = ("! a case written with CR line ends\r" + HEAT.replace("\n", "\r") +
            "&time cfl = 0.3 ! the step\r/\r")
    case = write(tmp_case_dir, text.encode())
    result = run_mpmice(["--check", case.name])
    assert result.returncode == 0, result.stdout + result.stderr
    assert "name = 'files'" in result.stdout
    assert "cfl = 0.3" in result.stdout


def test_byte_order_mark_is_accepted(run_mpmice, tmp_case_dir):
    case = write(tmp_case_dir, b"\xef\xbb\xbf" + HEAT.encode())
    result = run_mpmice(["--check", case.name])
    assert result.returncode == 0, result.stdout + result.stderr
    assert "name = 'files'" in result.stdout


@pytest.mark.parametrize("text, sets, pieces", [
    (HEAT + "&fluid name = 'water' /\n", [],
     ["case.nml", "&fluid", "not used", "'heat_conduction'", "&heat"]),
    (HEAT + "&physics gravity = 0, -9.81, 0 /\n", [],
     ["case.nml", "&physics", "not used", "'heat_conduction'"]),
    (HEAT, ["&mpm flip_fraction = 0.9 /"], ["--set", "&mpm", "not used", "'heat_conduction'"]),
    ("&run name = 'm', scene = 'mpm' /\n&solid name = 's', lower = 0.2, 0.0, 0.0, "
     "upper = 0.8, 1.0, 1.0 /\n&heat conductivity = 2.0 /\n", [],
     ["case.nml", "&heat", "not used", "'mpm'"]),
])
def test_group_the_scene_does_not_read_is_an_error(run_mpmice, tmp_case_dir, text, sets,
                                                    pieces):
    case = write(tmp_case_dir, text.encode())
    args = ["--check", case.name]
    for s in sets:
        args += ["--set", s]
    line = one_error_line(run_mpmice(args))
    for piece in pieces:
        assert piece in line, line


@pytest.mark.parametrize("scene_text", [
    HEAT,
    "&run name = 'i', scene = 'ice' /\n&fluid name = 'air', volume_fraction = 1.0 /\n",
])
def test_resolved_input_is_accepted_again(run_mpmice, tmp_case_dir, scene_text):
    """`--check` (like `<name>.used.nml`) prints every singleton group, the ones the scene does
    not read included: that text is accepted as a case file."""
    case = write(tmp_case_dir, scene_text.encode())
    first = run_mpmice(["--check", case.name])
    assert first.returncode == 0, first.stdout + first.stderr
    assert "&heat" in first.stdout and "&mpm" in first.stdout
    echo = tmp_case_dir / "echo.nml"
    echo.write_text(first.stdout)
    second = run_mpmice(["--check", echo.name])
    assert second.returncode == 0, second.stdout + second.stderr
    assert second.stdout == first.stdout


def test_unterminated_quote_names_its_line(run_mpmice, tmp_case_dir):
    text = HEAT + "&time cfl = 0.4 /\n&heat\n  conductivity = 1.0\n  modes = 1, 1, 1, name = \"x /\n"
    case = write(tmp_case_dir, text.encode())
    line = one_error_line(run_mpmice(["--check", case.name]))
    assert "unterminated quote" in line and "line 5" in line and "&heat" in line, line
