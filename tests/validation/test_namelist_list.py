"""The namelist list (modules/config/namelist/*.toml) is the one declaration of every namelist
variable: scripts/generate_namelists.py generates the Fortran type components, reads, table, echo
and range checks from it (at build time) and the variable tables of docs/namelists.md.

These tests check that docs/namelists.md is what the list gives (and that the check notices a
difference), that the generator refuses a malformed list with one line naming the file and the
variable, that the executable's echo holds exactly the list's variables in the list's order, and
that a value outside a list range is refused with the list's wording. About 5 s in all (8 runs of
`mpmice --check`; 20 s on a loaded 2-core machine)."""
import importlib.util
import pathlib
import re
import shutil
import subprocess
import sys
import tomllib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
GENERATOR = ROOT / "scripts" / "generate_namelists.py"
LIST = ROOT / "modules" / "config" / "namelist"
DOCS = ROOT / "docs" / "namelists.md"
CASE = ROOT / "namelists" / "mpmice_submerged_block_2d.nml"
HEAT_CASE = ROOT / "namelists" / "heat_conduction_2d.nml"
#: --set selector of an existing occurrence of each repeated group in CASE
SELECTORS = {"fluid": "name = 'water', ", "solid": "name = 'sand', ", "boundary": "face = 'x+', ",
             "region": "material = 'water', "}


@pytest.fixture(autouse=True)
def quiet_launcher(monkeypatch):
    """No multi-line report of Open MPI's mpirun on a non-zero exit (as in test_input_errors)."""
    monkeypatch.setenv("OMPI_MCA_orte_execute_quiet", "1")


def generator():
    spec = importlib.util.spec_from_file_location("generate_namelists", GENERATOR)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def run_generator(*args):
    return subprocess.run([sys.executable, str(GENERATOR), *map(str, args)],
                          capture_output=True, text=True, check=False)


def groups():
    index = tomllib.loads((LIST / "groups.toml").read_text())
    return [(name, tomllib.loads((LIST / f"{name}.toml").read_text())["variable"])
            for name in index["groups"]]


def test_docs_tables_are_generated_from_the_list():
    """docs/namelists.md holds the tables the list gives; after editing the list run
    `scripts/generate_namelists.py --docs docs/namelists.md --write`."""
    result = run_generator("--docs", DOCS, "--check")
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr


def test_docs_check_notices_a_changed_table(tmp_path):
    """A docs table that differs from the list (here a default) fails the check with a diff."""
    text = DOCS.read_text()
    changed = text.replace("| `cfl` | real | 0.5 |", "| `cfl` | real | 0.7 |")
    assert changed != text
    copy = tmp_path / "namelists.md"
    copy.write_text(changed)
    result = run_generator("--docs", copy, "--check")
    assert result.returncode == 1
    assert "-| `cfl` | real | 0.7 |" in result.stdout
    assert "the namelist tables differ from the list" in result.stderr


@pytest.mark.parametrize("edit, message", [
    (('name = "cfl"', 'name = "cfl"\nunits = "s"'), "time.toml: cfl: unknown field(s) ['units']"),
    (('range = "(0, 1]"', 'range = "(0, 1]]"'), "time.toml: cfl: range '(0, 1]]' is not an"),
    (('error = "0 < cfl <= 1"\n', ''), "time.toml: cfl: give 'error'"),
    (('range = "[dt_init, inf)"', 'range = "[dt_growth, inf)"'),
     "time.toml: dt_max: range bound 'dt_growth' is not an earlier scalar"),
])
def test_malformed_list_is_refused(tmp_path, edit, message):
    """The generator names the file and the variable of a mistake and writes nothing."""
    copy = tmp_path / "namelist"
    shutil.copytree(LIST, copy)
    time = copy / "time.toml"
    text = time.read_text()
    assert edit[0] in text
    time.write_text(text.replace(edit[0], edit[1], 1))
    out = tmp_path / "generated"
    result = run_generator("--list", copy, "--fortran", out)
    assert result.returncode == 1
    assert message in result.stderr, result.stderr
    assert not out.exists()


def echo_groups(text):
    """[(group, [variable names])] of an echo, in order (a table left unset is a comment)."""
    found = []
    for line in text.splitlines():
        if line.startswith("&"):
            found.append((line[1:].strip(), []))
        elif m := re.match(r"^  (?:! )?(\w+) = ", line):
            found[-1][1].append(m.group(1))
    return found


def test_echo_lists_the_variables_of_the_list(run_mpmice):
    """Every group of the echo (`--check`) holds the list's variables in the list's order."""
    result = run_mpmice(["--check", str(CASE)])
    assert result.returncode == 0, result.stderr
    listed = {name: [v["name"] for v in variables] for name, variables in groups()}
    echoed = echo_groups(result.stdout)
    assert {g for g, _ in echoed} == set(listed)
    for group, names in echoed:
        assert names == listed[group], group


def out_of_range(variable):
    """A value outside the variable's range (literal bounds only), or None."""
    m = re.match(r"^([\[(])\s*([^,\s]+)\s*,\s*([^,\s]+)\s*([\])])$", variable.get("range", ""))
    if not m or "off" in variable:
        return None
    lo_b, lo, hi, hi_b = m.groups()
    if re.match(r"^-?[\d.]+$", lo):
        value = float(lo) if lo_b == "(" else float(lo) - 1
    elif re.match(r"^-?[\d.]+$", hi):
        value = float(hi) if hi_b == ")" else float(hi) + 1
    else:
        return None
    return str(int(value)) if variable["type"] == "integer" else repr(value)


def first_ranged(variables):
    return next(((v, out_of_range(v)) for v in variables if out_of_range(v) is not None),
                (None, None))


#: a singleton group, the heat scene's group, and every repeated group (with its selector); the
#: range checks of all groups are generated by the same code
RANGE_GROUPS = ["run", "heat", "ice", "fluid", "solid", "region", "boundary"]


@pytest.mark.parametrize("group", RANGE_GROUPS)
def test_list_range_is_enforced(run_mpmice, group):
    """The first variable of the group with a numeric range: a value outside it gives the one
    error line with the list's wording of the range."""
    variables = dict(groups())[group]
    variable, value = first_ranged(variables)
    case = HEAT_CASE if group == "heat" else CASE
    setting = f"&{group} {SELECTORS.get(group, '')}{variable['name']} = {value} /"
    result = run_mpmice(["--check", str(case), "--set", setting])
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert result.returncode == 1, result.stdout[-2000:] + result.stderr
    assert len(lines) == 1, result.stderr
    allowed = generator().error_text(variable)
    assert re.match(rf"^mpmice: input error: --set: &{group}(\(\d+\))? {variable['name']} = ",
                    lines[0]), lines[0]
    assert lines[0].endswith(": " + allowed), (lines[0], allowed)
