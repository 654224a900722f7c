"""Run-loop stops of `driver_stops`: `&run max_energy_growth`,
`max_particle_loss_fraction` and `min_dt_ratio` stop a run that went wrong without a non-finite
value, with state `failed`, exit status 3, the reason in `<name>.status` and the state dumped to
`<name>_failed_<step>.h5`; on a sound run they change nothing.

Cases (each a second or less):
* the linear elastic bar (namelists/mpm_bar_1d.nml, 50 cells) at `&time cfl = 1` is unstable and
  stays finite, its particles dilating until the time step (from each particle's current wave
  speed, which grows as sqrt(det F)) falls below dt_min at step 207; `max_energy_growth = 2` stops
  it at step 24;
* the same bar free at both ends, drifting at 2 m/s out through x+, loses 7 of 80 particles
  and finishes; `max_particle_loss_fraction = 0.05` stops it at the 5th;
* the 1D column under self-weight (namelists/mpm_column_1d.nml) with linear shape functions,
  25 cells and E = 3e4 Pa is unstable: at t = 2.92 s (step 2,983) its stability limit drops by
  3000x and stays below 4 % of the first steps' (particles thrown against the walls are put
  back on them and keep the step small), so the run goes on at small steps (3.6 million steps
  to its end: the test stops it at step 6,000); `min_dt_ratio = 0.01` stops it at the drop;
* the GIMP bar at the namelist's cfl 0.2 with all three stops set tight finishes, bitwise equal
  to the run without them.
"""
from __future__ import annotations

import math
import pathlib
import sys

import h5py
import numpy as np

REPO = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO))
from postproc.dump_compare import assert_dumps_identical
from postproc.mpm_common import series  # noqa: E402

BAR = str(REPO / "namelists" / "mpm_bar_1d.nml")
COLUMN = str(REPO / "namelists" / "mpm_column_1d.nml")


def read_status(path: pathlib.Path) -> dict[str, str]:
    """`key = value` lines of a status file."""
    status = {}
    for line in path.read_text().splitlines():
        key, _, value = line.partition("=")
        status[key.strip()] = value.strip()
    return status


def run_case(run_mpmice, cwd, out, nml, sets):
    args = [nml]
    for text in sets:
        args += ["--set", text]
    args += ["--set", f"&run output_dir = '{out}', output_interval = 0.0 /"]
    result = run_mpmice(args, cwd=cwd, timeout=120)
    return result, read_status(cwd / out / f"{'bar1d' if nml == BAR else 'column1d'}.status")


def assert_failed(result, status, cwd, out, name, reason_start):
    assert result.returncode == 3, result.stdout + result.stderr
    assert status["state"] == "failed"
    assert status["reason"].startswith(reason_start), status["reason"]
    step = int(status["step"])
    dump = cwd / out / f"{name}_failed_{step:06d}.h5"
    assert dump.is_file() and status["reason"].endswith(f"state dumped to {out}/{dump.name}")
    assert status["reason"].split(";")[0] in result.stdout
    return step


UNSTABLE_BAR = ["&numerics shape_function = 'linear' /", "&grid ncells = 50, 1, 1 /",
                "&time cfl = 1.0, dt_max = 0.04 /"]


def test_energy_growth_stops_the_unstable_bar(run_mpmice, tmp_case_dir):
    """Linear bar at cfl 1: without the stop the energy grows > 2x and the run fails late, when
    its step falls below dt_min (step 207 measured); with max_energy_growth = 2 it fails at the
    first step whose energy exceeds twice E(0) (step 24; the bar has no gravity or load: the
    reference is E(0))."""
    result, status = run_case(run_mpmice, tmp_case_dir, "free", BAR, UNSTABLE_BAR)
    # the late failure (step below dt_min) also dumps its last accepted state
    assert_failed(result, status, tmp_case_dir, "free", "bar1d", "time step")
    s = series(str(tmp_case_dir / "free"), "bar1d")
    energy = s["kinetic_energy"] + s["strain_energy"]
    e0 = 0.5 * 1000.0 * 0.01**2 * 0.5       # (1/2) rho A L v0^2 / 2: the sine mode's energy
    assert abs(energy[0] / e0 - 1.0) < 0.02
    assert np.max(energy) > 2.0 * e0
    full_steps = int(status["step"])
    first_over = int(np.argmax(energy > 2.0 * energy[0])) + 1

    result, status = run_case(run_mpmice, tmp_case_dir, "stopped", BAR,
                              UNSTABLE_BAR + ["&run max_energy_growth = 2.0 /"])
    step = assert_failed(result, status, tmp_case_dir, "stopped", "bar1d", "energy growth")
    assert abs(step - first_over) <= 1, (step, first_over)
    assert step < 0.2 * full_steps
    assert "run stops: largest solid energy / reference" in result.stdout


COLUMN_SETS = ["&grid ncells = 1, 31, 1 /", "&numerics shape_function = 'linear' /"]


def column_sets(youngs: float) -> list[str]:
    """The column of bench/stability_maps.run_column: ramp gravity over 10 periods of the first
    mode, run for 20."""
    period = 4.0 / math.sqrt(youngs * 0.7 / (1.3 * 0.4) / 2000.0)
    return COLUMN_SETS + [f"&solid name = 'soil', youngs_modulus = {youngs!r} /",
                          f"&mpm gravity_ramp_time = {10 * period!r} /",
                          f"&time dt_max = {period!r} /",
                          f"&run end_time = {20 * period!r} /"]


DRIFTING_BAR = ["&boundary face = 'x-', solid = 'free' /",
                "&solid name = 'bar', velocity = 2.0, 0.0, 0.0, "
                "velocity_wavenumber = 0.0, 0.0, 0.0 /"]


def test_particle_loss_stops_the_drifting_bar(run_mpmice, tmp_case_dir):
    """The bar, free at both ends, drifts at 2 m/s toward the free face x = 1.25 m: its last
    particle (x = 0.99375 m) leaves at t = 0.128 s; by the end (t = 0.4 s, the edge decelerates
    it) 7 of the 80 particles are gone. Fraction 0.1 lets it finish; 0.05 stops it at the 5th."""
    result, status = run_case(run_mpmice, tmp_case_dir, "lenient", BAR,
                              DRIFTING_BAR + ["&run max_particle_loss_fraction = 0.1 /"])
    assert result.returncode == 0 and status["state"] == "finished"
    assert "particles removed (left the domain): 7" in result.stdout
    first = float(result.stderr.split("left the domain at t = ")[1].split()[0])
    assert abs(first - 0.25625 / 2.0) < 0.005, first
    result, status = run_case(run_mpmice, tmp_case_dir, "strict", BAR,
                              DRIFTING_BAR + ["&run max_particle_loss_fraction = 0.05 /"])
    assert_failed(result, status, tmp_case_dir, "strict", "bar1d", "particle loss")
    assert "5 of 80 particles left the domain (fraction 6.250000E-02" in status["reason"]


#: Steps of the column run without the stop: past its collapse (step 2,983 measured), far short of
#: its end (3.6 million steps at the collapsed step, minutes of wall time).
FREE_COLUMN_STEPS = 6000


def test_step_collapse_stops_the_column(run_mpmice, tmp_case_dir):
    """E = 3e4 Pa: without the stop the stability limit drops below 1 % of the first step's
    (to 1.2e-6 s of 3.6e-3 s, at t = 2.92 s, step 2,983) and the run goes on at small steps
    (to FREE_COLUMN_STEPS here); min_dt_ratio = 0.01 fails the run at that drop."""
    result, status = run_case(run_mpmice, tmp_case_dir, "free", COLUMN, column_sets(3.0e4)
                              + [f"&run max_steps = {FREE_COLUMN_STEPS} /"])
    assert result.returncode == 0 and status["state"] == "stopped", status
    assert int(status["step"]) == FREE_COLUMN_STEPS
    dt = np.diff(series(str(tmp_case_dir / "free"), "column1d")["time"])
    # steps grow from dt_init to the stability limit within the first 100
    assert np.min(dt[200:-1]) < 0.01 * np.max(dt[:200])
    # after the drop no step regains a tenth of the early ones (at most 3.6 % measured)
    drop = 200 + int(np.argmax(dt[200:] < 0.01 * np.max(dt[:200])))
    assert np.max(dt[drop:]) < 0.1 * np.max(dt[:200]), np.max(dt[drop:])
    full_steps = int(status["step"])
    result, status = run_case(run_mpmice, tmp_case_dir, "collapsed", COLUMN,
                              column_sets(3.0e4) + ["&run min_dt_ratio = 0.01 /"])
    step = assert_failed(result, status, tmp_case_dir, "collapsed", "column1d",
                         "time step collapsed")
    assert step < full_steps
    assert abs(float(status["time"]) - 2.92) < 0.05, status["time"]


def test_stops_leave_a_sound_run_unchanged(run_mpmice, tmp_case_dir):
    """GIMP bar at cfl 0.2 (stable: energy within 0.4 % of E(0)): all stops set tight, the run
    finishes and its final particles are bitwise those of the run without stops."""
    paths = []
    for out, extra in (("plain", []), ("watched", ["&run max_energy_growth = 1.05, "
                                                  "max_particle_loss_fraction = 0.0, "
                                                  "min_dt_ratio = 0.5 /"])):
        result, status = run_case(run_mpmice, tmp_case_dir, out, BAR, extra)
        assert result.returncode == 0 and status["state"] == "finished", status
        paths.append(sorted((tmp_case_dir / out).glob("bar1d_0*.h5"))[-1])
    assert_dumps_identical(paths[0], paths[1])


def test_stop_references_travel_in_checkpoints(run_mpmice, tmp_case_dir):
    """A checkpoint of a watched run holds the stops' references (E(0) of the bar's first mode,
    no load work without gravity, the first step's stability limit cfl dx / (c + |v|max) = 0.2 x
    0.025 / 100.01 s); a restart from it finishes bitwise like the uninterrupted run."""
    watch = "&run max_energy_growth = 1.05, min_dt_ratio = 0.5 /"
    result, status = run_case(run_mpmice, tmp_case_dir, "whole", BAR,
                              [watch, "&run checkpoint_interval = 0.2 /"])
    assert result.returncode == 0 and status["state"] == "finished"
    checkpoint = sorted((tmp_case_dir / "whole").glob("bar1d_checkpoint_*.h5"))[0]
    with h5py.File(checkpoint) as f:
        assert abs(f.attrs["stop_energy_reference"] / (0.5 * 1000.0 * 0.01**2 * 0.5) - 1) < 0.02
        assert f.attrs["stop_load_work"] == 0.0
        v_max = 0.01 * math.sin(0.5 * math.pi * 0.99375)       # the outermost particle
        assert abs(f.attrs["stop_dt_reference"] / (0.2 * 0.025 / (100.0 + v_max)) - 1) < 1e-12
    final = sorted((tmp_case_dir / "whole").glob("bar1d_0*.h5"))[-1]
    with h5py.File(final) as f:
        expected = f["particles/bar/x"][...], f["particles/bar/stress_xx"][...]
    final.unlink()          # the restart must write it again, at the same step
    restart = run_mpmice(["--restart", str(checkpoint)], cwd=tmp_case_dir, timeout=120)
    assert restart.returncode == 0, restart.stdout + restart.stderr
    with h5py.File(final) as f:
        assert np.array_equal(f["particles/bar/x"][...], expected[0])
        assert np.array_equal(f["particles/bar/stress_xx"][...], expected[1])
    assert "largest solid energy / reference" in restart.stdout
