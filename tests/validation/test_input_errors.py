"""Input handling of the ``mpmice`` executable: every class of bad input stops the run with exit
status 1 and exactly one line on standard error naming the file (or ``--set``), the namelist
group, the variable and the value, before anything is written, on 1 and 2 ranks; ``--check``
prints the resolved input (every group, defaults included) and writes nothing; ``--set`` overrides
the file in order.

Uses the ``run_mpmice(args, nranks=1, cwd=None, timeout=300)`` fixture of ``conftest.py``.
"""
from __future__ import annotations

import pathlib
import sys

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO))
from postproc.namelist import parse_namelist_groups, parse_namelist_text  # noqa: E402

GROUPS = ("run", "grid", "time", "numerics", "solver", "output", "heat", "physics", "ice", "mpm",
          "coupling")

#: A valid case that runs on 1 and 2 ranks; its output would go to ``out/``.
GOOD = """! a small heat-conduction case
&run
  name = 'good'
  output_dir = 'out'      ! relative to the working directory
  end_time = 0.01         ! s
/
&grid
  ncells = 16, 1, 1
  upper = 2.0, 1.0, 1.0   ! m
/
&time
  dt_init = 1.0e-4
  dt_max = 1.0e-3
/
&heat
  amplitude = 0.5
/
"""

#: (id, case file text, --set texts, pieces the error line must contain)
BAD_INPUTS = [
    ("ncells_negative", "&grid ncells = -5, 1, 1 /", [],
     ["case.nml", "&grid", "ncells", "-5, 1, 1", ">= 1"]),
    ("ncells_not_integer", "&grid ncells = 'abc' /", [],
     ["case.nml", "&grid", "ncells", "'abc'"]),
    ("end_time_negative", "&run output_dir = 'out', end_time = -1 /", [],
     ["case.nml", "&run", "end_time", "-1.0", ">= 0 [s]"]),
    ("real_malformed", "&run end_time = 1.0.0 /", [],
     ["case.nml", "&run", "end_time", "1.0.0"]),
    ("integer_given_real", "&run max_steps = 2.5 /", [],
     ["case.nml", "&run", "max_steps", "2.5"]),
    ("logical_malformed", "&output xdmf = yes /", [],
     ["case.nml", "&output", "xdmf", "yes"]),
    ("unknown_variable", "&time cfl = 0.4, dt_inti = 1e-4 /", [],
     ["case.nml", "&time", "dt_inti", "1e-4", "unknown"]),
    ("too_many_values", "&grid lower = 0, 0, 0, 0 /", [],
     ["case.nml", "&grid", "lower", "0, 0, 0, 0"]),
    ("missing_value", "&time cfl = /", [],
     ["case.nml", "&time", "cfl", "missing value"]),
    ("unquoted_string", "&run scene = heat_conduction /", [],
     ["case.nml", "&run", "scene", "heat_conduction", "quoted"]),
    ("cfl_out_of_range", "&time cfl = 1.5 /", [],
     ["case.nml", "&time", "cfl", "1.5", "<= 1"]),
    ("dt_max_below_dt_init", "&time dt_init = 0.01 dt_max = 0.001 /", [],
     ["case.nml", "&time", "dt_max", "0.001", "dt_init"]),
    ("max_energy_growth_below_one", "&run max_energy_growth = 0.5 /", [],
     ["case.nml", "&run", "max_energy_growth", "0.5", "0 (off) or > 1"]),
    ("max_particle_loss_fraction_above_one", "&run max_particle_loss_fraction = 1.5 /", [],
     ["case.nml", "&run", "max_particle_loss_fraction", "1.5", "0 <= f <= 1"]),
    ("min_dt_ratio_one", "&run min_dt_ratio = 1.0 /", [],
     ["case.nml", "&run", "min_dt_ratio", "1.0", "0 <= r < 1"]),
    ("energy_stop_needs_solids", "&run max_energy_growth = 2.0 /", [],
     ["case.nml", "&run", "max_energy_growth", "2.0", "scene 'heat_conduction'", "mpm, mpmice"]),
    ("unknown_scene", "&run scene = 'volcano' /", [],
     ["case.nml", "&run", "scene", "'volcano'", "heat_conduction"]),
    ("overflow", "&run end_time = 1e400 /", [],
     ["case.nml", "&run", "end_time", "Infinity", "finite"]),
    ("nan", "&heat conductivity = NaN /", [],
     ["case.nml", "&heat", "conductivity", "NaN"]),
    ("ghost_width_too_small", "&grid ghost_width = 1 /", [],
     ["case.nml", "&grid", "ghost_width", "= 1", "2..4"]),
    ("ghost_width_smagorinsky", "&grid ghost_width = 1 /\n&numerics advection_order = 1, "
     "shape_function = 'linear' /\n&ice smagorinsky = .true. /", [],
     ["case.nml", "&grid", "ghost_width", "= 1", "2..4", "smagorinsky = .true."]),
    ("smagorinsky_constant_zero", "&ice smagorinsky = .true., smagorinsky_constant = 0.0 /", [],
     ["case.nml", "&ice", "smagorinsky_constant", "= 0", "> 0"]),
    ("modes_zero", "&heat modes = 0, 1, 1 /", [],
     ["case.nml", "&heat", "modes", "0, 1, 1"]),
    ("repeated_group", "&time cfl = 0.4 /\n&time cfl = 0.3 /", [],
     ["case.nml", "&time", "more than once"]),
    ("unknown_group", "&gird ncells = 4 /", [], ["case.nml", "&gird", "unknown"]),
    ("unterminated_group", "&grid ncells = 4, 1, 1", [], ["case.nml", "&grid", "terminated"]),
    ("set_out_of_range", "", ["&grid ncells = 0, 1, 1 /"],
     ["--set", "&grid", "ncells", "0, 1, 1"]),
    ("set_malformed", "", ["&time cfl = 0.3 /", "&time cfl = abc /"],
     ["--set", "&time", "cfl", "abc"]),
    ("set_unknown_variable", "", ["&run bogus = 1 /"], ["--set", "&run", "bogus", "1"]),
    ("coupling_unknown_variable", "&coupling drag_shceme = 'explicit' /", [],
     ["case.nml", "&coupling", "drag_shceme", "'explicit'", "unknown", "drag_scheme"]),
    ("coupling_bad_drag_scheme", "&coupling drag_scheme = 'semi' /", [],
     ["case.nml", "&coupling", "drag_scheme", "'semi'", "implicit, explicit"]),
    ("coupling_max_solid_fraction", "&coupling max_solid_fraction = 0.0 /", [],
     ["case.nml", "&coupling", "max_solid_fraction", "0.0", "0 < max_solid_fraction <= 1"]),
    ("coupling_heat_exchange_negative", "", ["&coupling heat_exchange_coefficient = -1 /"],
     ["--set", "&coupling", "heat_exchange_coefficient", "-1.0", ">= 0 [W/m^3/K]"]),
]


#: A valid ICE case with repeated groups (two fluids, a region, a boundary); y is periodic.
ICE_CASE = """&run name = 'ice', scene = 'ice', output_dir = 'out' /
&grid ncells = 8, 8, 1, periodic = .false., .true., .false. /
&fluid name = 'air', volume_fraction = 1.0 /
&fluid name = 'water', eos = 'linear_water', viscosity = 1.0e-3 /
&region material = 'water', upper = 0.5, 1.0, 1.0, volume_fraction = 1.0 /
&region material = 'air', upper = 0.5, 1.0, 1.0, volume_fraction = 0.0 /
&boundary face = 'x+', fluid = 'pressure' /
"""

#: Input errors of the repeated groups, checked on one rank only (the unit tests cover the rest):
#: (id, text appended to ICE_CASE, --set texts, pieces the error line must contain)
BAD_PHASE_INPUTS = [
    ("duplicate_name", "&fluid name = 'air' /", [],
     ["case.nml", "&fluid(3) name = 'air'", "unique", "&fluid(1)"]),
    ("unknown_region_material", "&region material = 'oil' /", [],
     ["case.nml", "&region(3) material = 'oil'", "'air', 'water'"]),
    ("fractions_do_not_sum_to_one",
     "&region material = 'air', upper = 0.5, 1, 1, volume_fraction = 0.5 /", [],
     ["case.nml", "&region(3) volume_fraction = 0.5", "summing to 1 in every cell",
      "cell 1, 1, 1", "sum 1.5"]),
    ("region_outside_domain", "&region material = 'water', lower = 2, 0, 0, upper = 3, 1, 1 /",
     [], ["case.nml", "&region(3) upper = 3.0, 1.0, 1.0", "at least one cell centre",
          "&grid lower = 0.0, 0.0, 0.0, upper = 1.0, 1.0, 1.0"]),
    ("bad_enum", "&fluid name = 'oil', eos = 'tait' /", [],
     ["case.nml", "&fluid(3) eos = 'tait'", "ideal_gas, linear_water, stiffened_gas"]),
    ("boundary_on_periodic_face", "&boundary face = 'y-' /", [],
     ["case.nml", "&boundary(2) face = 'y-'", "non-periodic"]),
    ("second_boundary_same_face", "&boundary face = 'x+' /", [],
     ["case.nml", "&boundary(2) face = 'x+'", "at most one", "&boundary(1)"]),
    ("inflow_fluid_unknown", "", ["&boundary face = 'x+', inflow_fluid = 'oil' /"],
     ["--set", "&boundary(1) inflow_fluid = 'oil'", "the name of a &fluid ('air', 'water')"]),
    ("inflow_fluid_on_wall", "&boundary face = 'x-', inflow_fluid = 'air' /", [],
     ["case.nml", "&boundary(2) inflow_fluid = 'air'", "fluid = 'wall'",
      "'pressure', 'inflow' or 'outflow'"]),
    ("compression_three_fluids", "&fluid name = 'oil', eos = 'linear_water' /\n"
     "&ice interface_compression = 1.0 /", [],
     ["case.nml", "&ice interface_compression = 1.0", "0 with 3 &fluid groups"]),
    ("compression_out_of_range", "", ["&ice interface_compression = 5 /"],
     ["--set", "&ice interface_compression = 5.0", "0..4"]),
    ("set_selector_not_present", "", ["&fluid name = 'oil', viscosity = 2e-3 /"],
     ["--set", "&fluid name = 'oil'", "present: 'air', 'water'"]),
]


#: A valid MPMICE case: one fluid, one porous solid with a traction on its top layer.
MPMICE_CASE = """&run name = 'mpmice', scene = 'mpmice', output_dir = 'out' /
&grid ncells = 1, 10, 1 /
&fluid name = 'water', eos = 'linear_water', volume_fraction = 1.0 /
&solid name = 'soil', upper = 1.0, 1.0, 1.0, porosity = 0.3, traction = 0, -1.0e4, 0,
  traction_lower = 0.0, 0.9, 0.0, traction_upper = 1.0, 1.0, 1.0 /
"""

_VH = "&boundary face = 'y-', solid = 'velocity',"

#: Input errors of scene 'mpmice' and the new &solid variables, on one rank:
#: (id, text appended to MPMICE_CASE, --set texts, pieces the error line must contain)
BAD_MPMICE_INPUTS = [
    ("mpmice_without_solid", "", ["&run scene = 'ice' /"],
     ["--set", "&run scene = 'ice'", "no &solid group", "1 &fluid, 1 &solid"]),
    ("drag_law_unknown", "", ["&solid name = 'soil', drag_law = 'ergun' /"],
     ["--set", "&solid(1) drag_law = 'ergun'",
      "kozeny_carman, beetstra, constant, impermeable, forchheimer"]),
    ("forchheimer_b_negative", "&solid name = 's2', upper = 1, 1, 1, forchheimer_b = -1 /",
     [], ["case.nml", "&solid(2) forchheimer_b = -1.0", ">= 0 [-] (Ergun: 1.75)"]),
    ("drag_coefficient_negative", "&solid name = 's2', upper = 1, 1, 1, drag_coefficient = -1 /",
     [], ["case.nml", "&solid(2) drag_coefficient = -1.0", ">= 0 [kg/m^3/s]"]),
    ("grain_bulk_modulus_negative",
     "&solid name = 's2', upper = 1, 1, 1, grain_bulk_modulus = -1 /", [],
     ["case.nml", "&solid(2) grain_bulk_modulus = -1.0", ">= 0 [Pa]"]),
    ("traction_box_empty", "&solid name = 's2', upper = 1, 1, 1, traction = 5, 0, 0 /", [],
     ["case.nml", "&solid(2) traction_upper = 0.0, 0.0, 0.0", "traction_lower",
      "(5.0, 0.0, 0.0)"]),
    ("contractant_without_min_porosity", "", ["&solid name = 'soil', model = 'mohr_coulomb', "
                                               "friction_angle = 30, dilation_angle = -5 /"],
     ["case.nml", "&solid(1) min_porosity = 0.0", "0 < value < porosity (0.3)",
      "densest packing"]),
    ("min_porosity_not_contractant", "", ["&solid name = 'soil', min_porosity = 0.2 /"],
     ["--set", "&solid(1) min_porosity = 0.2", "dilation_angle < 0"]),
    ("suspension_bound_without_loosest_packing", "",
     ["&solid name = 'soil', model = 'mohr_coulomb', suspension_cell_bound = .true. /"],
     ["--set", "&solid(1) suspension_cell_bound = .true.", "max_porosity < 1"]),
    ("suspension_settling_without_loosest_packing", "",
     ["&solid name = 'soil', model = 'mohr_coulomb', suspension_settling = .true. /"],
     ["--set", "&solid(1) suspension_settling = .true.", "max_porosity < 1"]),
    ("compaction_for_mohr_coulomb", "",
     ["&solid name = 'soil', model = 'mohr_coulomb', compaction_index = 0.01 /"],
     ["--set", "&solid(1) compaction_index = 0.01", "only a critical_state_sand solid"]),
    ("tension_gap_for_mohr_coulomb", "",
     ["&solid name = 'soil', model = 'mohr_coulomb', tension_gap = .true. /"],
     ["--set", "&solid(1) tension_gap = .true.", "unless model = 'critical_state_sand'"]),
    ("compaction_pressure_zero", "",
     ["&solid name = 'soil', model = 'critical_state_sand', compaction_index = 0.01, "
      "compaction_pressure = 0.0 /"],
     ["--set", "&solid(1) compaction_pressure = 0.0", "> 0 [Pa]"]),
    ("dilation_below_minus_friction", "", ["&solid name = 'soil', model = 'mohr_coulomb', "
                                            "friction_angle = 30, dilation_angle = -40 /"],
     ["--set", "&solid(1) dilation_angle = -40.0", "-friction_angle..friction_angle (30.0)"]),
    ("modulus_exponent_elastic", "", ["&solid name = 'soil', modulus_exponent = 0.5 /"],
     ["--set", "&solid(1) modulus_exponent = 0.5", "only a mohr_coulomb solid"]),
    ("modulus_exponent_above_one", "", ["&solid name = 'soil', model = 'mohr_coulomb', "
                                         "friction_angle = 30, modulus_exponent = 1.5 /"],
     ["--set", "&solid(1) modulus_exponent = 1.5", "0 <= m <= 1"]),
    ("face_plane_with_sliding_rigid",
     "&solid name = 'bed', model = 'rigid', drag_law = 'impermeable', upper = 1, 0.1, 1 /",
     ["&mpm rigid_contact = 'friction' /", "&coupling face_drag = 'face_plane' /"],
     ["--set", "&coupling face_drag = 'face_plane'", "'cell' with &mpm rigid_contact = "
      "'friction' and a rigid &solid"]),
    ("traction_ramp_time_negative", "", ["&solid name = 'soil', traction_ramp_time = -1 /"],
     ["--set", "&solid(1) traction_ramp_time = -1.0", ">= 0 [s]"]),
    ("solid_outside_domain", "&solid name = 's2', lower = 0, 1.5, 0, upper = 1, 2, 1 /", [],
     ["case.nml", "&solid(2) upper = 1.0, 2.0, 1.0", "overlapping the domain",
      "upper = 1.0, 1.0, 1.0"]),
    ("grain_size_zero_rigid",
     "&solid name = 's2', model = 'rigid', upper = 1, 1, 1, grain_size = 0 /", [],
     ["case.nml", "&solid(2) grain_size = 0.0", "> 0 [m]"]),
    # soil models (docs/soil_models.md)
    ("cam_clay_kappa_above_lambda", "", ["&solid name = 'soil', model = 'cam_clay', "
                                          "compression_index = 0.1, swelling_index = 0.2 /"],
     ["--set", "&solid(1) swelling_index = 0.2", "0 < kappa < compression_index (0.1)"]),
    ("cam_clay_ocr_below_one", "", ["&solid name = 'soil', model = 'cam_clay', ocr = 0.5 /"],
     ["--set", "&solid(1) ocr = 0.5", ">= 1"]),
    ("cam_clay_without_porosity", "", ["&solid name = 'soil', model = 'cam_clay', "
                                        "porosity = 0 /"],
     ["--set", "&solid(1) porosity = 0.0", "0 < n < 1 for model cam_clay"]),
    ("sand_phi_m_above_one", "", ["&solid name = 'soil', model = 'critical_state_sand', "
                                   "critical_solid_fraction = 1.2 /"],
     ["--set", "&solid(1) critical_solid_fraction = 1.2", "0 < phi_m < 1"]),
    ("sand_fluid_viscosity_negative", "", ["&solid name = 'soil', fluid_viscosity = -1 /"],
     ["--set", "&solid(1) fluid_viscosity = -1.0", ">= 0 [Pa s]"]),
    ("plastic_start_negative", "", ["&solid name = 'soil', plastic_start = -1 /"],
     ["--set", "&solid(1) plastic_start = -1.0", ">= 0 [s]"]),
    ("local_damping_end_negative", "&mpm local_damping = 0.7, local_damping_end = -1 /", [],
     ["case.nml", "&mpm", "local_damping_end", "-1.0", ">= 0 [s]"]),
    ("local_damping_force_unknown", "&mpm local_damping_force = 'fluid' /", [],
     ["case.nml", "&mpm", "local_damping_force", "'fluid'", "one of solid, total"]),
    ("velocity_transfer_unknown", "&mpm velocity_transfer = 'mls' /", [],
     ["case.nml", "&mpm", "velocity_transfer", "'mls'", "one of flip, apic"]),
    ("apic_with_linear_shapes", "&mpm velocity_transfer = 'apic' /",
     ["&numerics shape_function = 'linear' /"],
     ["case.nml", "&mpm", "velocity_transfer", "'apic'", "shape_function = 'linear'", "gimp"]),
    ("face_drag_unknown", "&coupling face_drag = 'nodal' /", [],
     ["case.nml", "&coupling", "face_drag", "'nodal'", "one of cell, face_plane"]),
] + [
    # &boundary velocity history (solid_velocity_times / solid_velocity_history)
    ("history_times_not_increasing",
     f"{_VH} solid_velocity_times = 0, 0.2, 0.1, solid_velocity_history = 9*0.0 /", [],
     ["case.nml", "&boundary(1) solid_velocity_times = 0.0, 0.2, 0.1",
      "strictly increasing times [s]"]),
    ("history_count_mismatch",
     f"{_VH} solid_velocity_times = 0, 0.1, solid_velocity_history = 0, 0, 0 /", [],
     ["case.nml", "&boundary(1) solid_velocity_history = 0.0, 0.0, 0.0",
      "3 components for each of the 2 solid_velocity_times"]),
    ("history_value_not_finite",
     f"{_VH} solid_velocity_times = 0, 0.1, solid_velocity_history = 0, 0, 0, 0, 1e400, 0 /", [],
     ["case.nml", "&boundary(1) solid_velocity_history", "Infinity", "finite numbers [m/s]"]),
    ("history_time_nan",
     f"{_VH} solid_velocity_times = nan, 0.1, solid_velocity_history = 6*0.0 /", [],
     ["case.nml", "&boundary(1) solid_velocity_times = NaN, 0.1", "finite numbers [s]"]),
    ("history_times_gap", f"{_VH} solid_velocity_times(1) = 0, solid_velocity_times(3) = 1, "
     "solid_velocity_history = 6*0.0 /", [],
     ["case.nml", "&boundary(1) solid_velocity_times = 0.0, 1.0",
      "consecutive entries from solid_velocity_times(1), at most 64"]),
    ("history_too_long", f"{_VH} solid_velocity_times = 65*0.5 /", [],
     ["case.nml", "&boundary(1) solid_velocity_times = 65*0.5", "up to 64 real numbers"]),
    ("history_on_fixed_face", "&boundary face = 'y-', solid = 'fixed', "
     "solid_velocity_times = 0, 1, solid_velocity_history = 6*0.0 /", [],
     ["case.nml", "&boundary(1) solid_velocity_times = 0.0, 1.0", "only with solid = 'velocity'"]),
    ("history_and_constant",
     f"{_VH} solid_velocity_times = 0, 1, solid_velocity_history = 6*0.0 /",
     ["&boundary face = 'y-', solid_velocity = 0, 1, 0 /"],
     ["--set", "&boundary(1) solid_velocity = 0.0, 1.0, 0.0", "history prescribes"]),
]


@pytest.fixture(autouse=True)
def quiet_launcher(monkeypatch):
    """Open MPI's mpirun adds a multi-line report on standard error whenever a rank exits with a
    non-zero status; ``orte_execute_quiet`` (what ``mpirun -q`` sets) turns it off, so standard
    error holds only what mpmice itself prints. Other MPI launchers ignore the variable."""
    monkeypatch.setenv("OMPI_MCA_orte_execute_quiet", "1")


def text_of(stream) -> str:
    """Standard output or error of a CompletedProcess as text."""
    if stream is None:
        return ""
    return stream if isinstance(stream, str) else stream.decode("utf-8", "replace")


def write_case(directory: pathlib.Path, body: str) -> pathlib.Path:
    """A case file whose output directory is ``out/`` followed by ``body``."""
    path = directory / "case.nml"
    if body.lstrip().lower().startswith("&run"):
        path.write_text(body + "\n")
    else:
        path.write_text("&run output_dir = 'out' /\n" + body + "\n")
    return path


def assert_input_error(result, pieces, directory: pathlib.Path) -> None:
    """Exit status 1, one stderr line holding every piece, nothing written."""
    stderr = text_of(result.stderr)
    lines = [line for line in stderr.splitlines() if line.strip()]
    assert result.returncode == 1, stderr
    assert len(lines) == 1, f"expected one error line, got:\n{stderr}"
    assert lines[0].startswith("mpmice: input error: "), lines[0]
    for piece in pieces:
        assert piece in lines[0], f"{piece!r} missing from: {lines[0]}"
    assert text_of(result.stdout).strip() == "", text_of(result.stdout)
    assert sorted(p.name for p in directory.iterdir()) == ["case.nml"]


@pytest.mark.parametrize("nranks", [1, 2])
@pytest.mark.parametrize("case_id, body, sets, pieces", BAD_INPUTS, ids=[b[0] for b in BAD_INPUTS])
def test_bad_input_stops_with_one_line(run_mpmice, tmp_case_dir, nranks, case_id, body, sets,
                                       pieces):
    write_case(tmp_case_dir, body)
    args = ["case.nml"]
    for text in sets:
        args += ["--set", text]
    result = run_mpmice(args, nranks=nranks, cwd=tmp_case_dir)
    assert_input_error(result, pieces, tmp_case_dir)


@pytest.mark.parametrize("nranks", [1, 2])
def test_missing_file(run_mpmice, tmp_case_dir, nranks):
    (tmp_case_dir / "case.nml").write_text(GOOD)
    result = run_mpmice(["nothere.nml"], nranks=nranks, cwd=tmp_case_dir)
    assert_input_error(result, ["nothere.nml", "cannot read"], tmp_case_dir)


@pytest.mark.parametrize("nranks", [1, 2])
def test_missing_restart_file(run_mpmice, tmp_case_dir, nranks):
    (tmp_case_dir / "case.nml").write_text(GOOD)
    result = run_mpmice(["--restart", "nothere.h5"], nranks=nranks, cwd=tmp_case_dir)
    assert_input_error(result, ["nothere.h5"], tmp_case_dir)


@pytest.mark.parametrize("nranks", [1, 2])
def test_restart_file_not_hdf5(run_mpmice, tmp_case_dir, nranks):
    (tmp_case_dir / "case.nml").write_text(GOOD)
    result = run_mpmice(["--restart", "case.nml"], nranks=nranks, cwd=tmp_case_dir)
    assert_input_error(result, ["case.nml", "not an HDF5"], tmp_case_dir)


def test_restart_configuration_comes_from_the_checkpoint(run_mpmice, tmp_case_dir):
    """--check --restart prints the input stored in the checkpoint, with --set applied."""
    (tmp_case_dir / "case.nml").write_text(
        GOOD.replace("end_time = 0.01", "end_time = 0.002, checkpoint_interval = 0.001"))
    run = run_mpmice(["case.nml"], nranks=1, cwd=tmp_case_dir)
    assert run.returncode == 0, text_of(run.stderr)
    checkpoints = sorted((tmp_case_dir / "out").glob("good_checkpoint_*.h5"))
    assert checkpoints, sorted(p.name for p in (tmp_case_dir / "out").iterdir())
    (tmp_case_dir / "case.nml").unlink()  # the restart must not need the case file
    result = run_mpmice(["--check", "--restart", str(checkpoints[-1]),
                         "--set", "&run end_time = 0.004 /"], nranks=2, cwd=tmp_case_dir)
    assert result.returncode == 0, text_of(result.stderr)
    groups = parse_namelist_text(text_of(result.stdout))
    assert groups["run"]["name"] == "good"
    assert groups["run"]["end_time"] == 0.004
    assert groups["run"]["checkpoint_interval"] == 0.001
    assert groups["grid"]["upper"] == [2.0, 1.0, 1.0]
    bad = run_mpmice(["--check", "--restart", str(checkpoints[-1]),
                      "--set", "&time cfl = -1 /"], nranks=1, cwd=tmp_case_dir)
    assert bad.returncode == 1
    expected = "mpmice: input error: --set: &time cfl = -1.0: 0 < cfl <= 1"
    assert text_of(bad.stderr).strip() == expected


def test_too_many_ranks_for_the_grid(run_mpmice, tmp_case_dir):
    """3 cells make one valid block but not two blocks of 2 ghost layers."""
    write_case(tmp_case_dir, "&grid ncells = 3, 1, 1 /")
    assert run_mpmice(["--check", "case.nml"], nranks=1, cwd=tmp_case_dir).returncode == 0
    result = run_mpmice(["case.nml"], nranks=2, cwd=tmp_case_dir)
    assert_input_error(result, ["case.nml", "&grid", "ncells", "3, 1, 1", "2 ranks"], tmp_case_dir)


@pytest.mark.mpi
def test_more_ranks_than_cells(run_mpmice, tmp_case_dir):
    """4 ranks for 3 cells: not even one cell per rank."""
    write_case(tmp_case_dir, "&grid ncells = 3, 1, 1 /")
    result = run_mpmice(["case.nml"], nranks=4, cwd=tmp_case_dir)
    assert_input_error(result, ["case.nml", "&grid", "ncells", "3, 1, 1", "one cell per rank",
                                "4 ranks"], tmp_case_dir)


def test_block_cells_must_match_ranks(run_mpmice, tmp_case_dir):
    """Three given blocks along x do not fit 2 ranks: the error names the list."""
    write_case(tmp_case_dir, "&grid ncells = 16, 16, 1, block_cells_x = 4, 6, 6 /")
    result = run_mpmice(["case.nml"], nranks=2, cwd=tmp_case_dir)
    assert_input_error(result, ["case.nml", "&grid", "block_cells_x", "4, 6, 6"], tmp_case_dir)


@pytest.mark.parametrize("blocks", ["4, 6", "1, 15"])
def test_block_cells_must_tile_x(run_mpmice, tmp_case_dir, blocks):
    """Given blocks that do not sum to ncells, or one thinner than ghost_width: one error line
    naming the list and its value."""
    write_case(tmp_case_dir, f"&grid ncells = 16, 16, 1, block_cells_x = {blocks} /")
    result = run_mpmice(["case.nml"], nranks=2, cwd=tmp_case_dir)
    assert_input_error(result, ["case.nml", "&grid", "block_cells_x", blocks], tmp_case_dir)


def test_dims_must_match_ranks(run_mpmice, tmp_case_dir):
    write_case(tmp_case_dir, "&grid ncells = 16, 16, 1, dims = 1, 1, 0 /")
    result = run_mpmice(["case.nml"], nranks=2, cwd=tmp_case_dir)
    assert_input_error(result, ["case.nml", "&grid", "dims", "1, 1, 0"], tmp_case_dir)


@pytest.mark.parametrize("args", [[], ["a.nml", "b.nml"], ["case.nml", "--frobnicate"],
                                  ["case.nml", "--set"]])
def test_usage_errors(run_mpmice, tmp_case_dir, args):
    (tmp_case_dir / "case.nml").write_text(GOOD)
    result = run_mpmice(args, nranks=1, cwd=tmp_case_dir)
    lines = text_of(result.stderr).strip().splitlines()
    assert result.returncode == 1
    assert len(lines) == 1 and lines[0].startswith("mpmice: usage error: "), lines


@pytest.mark.parametrize("nranks", [1, 2])
def test_check_prints_every_group_and_writes_nothing(run_mpmice, tmp_case_dir, nranks):
    (tmp_case_dir / "case.nml").write_text(GOOD)
    result = run_mpmice(["--check", "case.nml"], nranks=nranks, cwd=tmp_case_dir)
    stdout = text_of(result.stdout)
    assert result.returncode == 0, text_of(result.stderr)
    assert text_of(result.stderr).strip() == ""
    assert stdout.count("&run") == 1  # printed by one rank only
    groups = parse_namelist_text(stdout)
    assert set(groups) == set(GROUPS)
    assert groups["run"]["name"] == "good"
    assert groups["grid"]["ncells"] == [16, 1, 1]
    assert groups["grid"]["upper"] == [2.0, 1.0, 1.0]
    assert groups["time"]["dt_init"] == 1.0e-4
    assert groups["heat"]["amplitude"] == 0.5
    # defaults of variables the file does not set are printed too
    assert groups["time"]["cfl"] == 0.5
    assert groups["solver"]["max_iterations"] == 200
    assert groups["output"]["xdmf"] is True
    assert groups["numerics"]["shape_function"] == "gimp"
    assert sorted(p.name for p in tmp_case_dir.iterdir()) == ["case.nml"]


def test_check_output_is_a_fixed_point(run_mpmice, tmp_case_dir):
    """The printed input, read back, resolves to the same text."""
    (tmp_case_dir / "case.nml").write_text(GOOD)
    first = text_of(run_mpmice(["--check", "case.nml"], cwd=tmp_case_dir).stdout)
    (tmp_case_dir / "resolved.nml").write_text(first)
    second = run_mpmice(["--check", "resolved.nml"], cwd=tmp_case_dir)
    assert second.returncode == 0, text_of(second.stderr)
    assert text_of(second.stdout) == first


def test_set_overrides_in_order(run_mpmice, tmp_case_dir):
    (tmp_case_dir / "case.nml").write_text(GOOD)
    result = run_mpmice(["--check", "case.nml", "--set", "&grid ncells = 200, 1, 1 /",
                         "--set=&time cfl = 0.3 / &run end_time = 2.0 /",
                         "--set", "&time cfl = 0.25 /"], cwd=tmp_case_dir)
    assert result.returncode == 0, text_of(result.stderr)
    groups = parse_namelist_text(text_of(result.stdout))
    assert groups["grid"]["ncells"] == [200, 1, 1]
    assert groups["run"]["end_time"] == 2.0
    assert groups["time"]["cfl"] == 0.25
    assert groups["grid"]["upper"] == [2.0, 1.0, 1.0]  # from the file, untouched


@pytest.mark.parametrize("path", sorted((REPO / "namelists").glob("**/*.nml")),
                         ids=lambda p: str(p.relative_to(REPO / "namelists")))
def test_shipped_namelists_are_valid(run_mpmice, tmp_case_dir, path):
    """Every shipped namelist, the documentation examples in namelists/examples/ included."""
    result = run_mpmice(["--check", str(path)], nranks=1, cwd=tmp_case_dir)
    assert result.returncode == 0, text_of(result.stderr)
    assert set(GROUPS) <= set(parse_namelist_text(text_of(result.stdout)))


def test_help_and_version(run_mpmice, tmp_case_dir):
    help_result = run_mpmice(["--help"], cwd=tmp_case_dir)
    assert help_result.returncode == 0
    assert "--check" in text_of(help_result.stdout) and "--set" in text_of(help_result.stdout)
    version = run_mpmice(["--version"], cwd=tmp_case_dir)
    assert version.returncode == 0
    assert text_of(version.stdout).startswith("mpmice ")


@pytest.mark.parametrize("case_id, extra, sets, pieces", BAD_PHASE_INPUTS,
                         ids=[b[0] for b in BAD_PHASE_INPUTS])
def test_bad_phase_input_stops_with_one_line(run_mpmice, tmp_case_dir, case_id, extra, sets,
                                             pieces):
    (tmp_case_dir / "case.nml").write_text(ICE_CASE + extra + "\n")
    args = ["case.nml"]
    for text in sets:
        args += ["--set", text]
    result = run_mpmice(args, nranks=1, cwd=tmp_case_dir)
    assert_input_error(result, pieces, tmp_case_dir)


def test_repeated_groups_echo_and_set_selector(run_mpmice, tmp_case_dir):
    """--check prints every occurrence in order; --set modifies the occurrence it names; the
    printed text, read back, resolves to the same text."""
    (tmp_case_dir / "case.nml").write_text(ICE_CASE)
    result = run_mpmice(["--check", "case.nml", "--set",
                         "&fluid name = 'water', viscosity = 2.5e-3 /"], cwd=tmp_case_dir)
    assert result.returncode == 0, text_of(result.stderr)
    first = text_of(result.stdout)
    groups = parse_namelist_groups(first)
    fluids = [values for name, values in groups if name == "fluid"]
    assert [f["name"] for f in fluids] == ["air", "water"]
    assert fluids[0]["viscosity"] == 0.0 and fluids[1]["viscosity"] == 2.5e-3
    assert fluids[1]["eos"] == "linear_water" and fluids[0]["eos"] == "ideal_gas"
    assert [v["material"] for name, v in groups if name == "region"] == ["water", "air"]
    assert [v["face"] for name, v in groups if name == "boundary"] == ["x+"]
    (tmp_case_dir / "resolved.nml").write_text(first)
    second = run_mpmice(["--check", "resolved.nml"], cwd=tmp_case_dir)
    assert second.returncode == 0, text_of(second.stderr)
    assert text_of(second.stdout) == first


def test_mpmice_scene_needs_fluid_and_solid(run_mpmice, tmp_case_dir):
    """Scene 'mpmice' needs at least one &fluid and at least one &solid group."""
    (tmp_case_dir / "case.nml").write_text(
        "&run scene = 'mpmice', output_dir = 'out' /\n&grid ncells = 1, 10, 1 /\n"
        "&fluid name = 'water' /\n")
    result = run_mpmice(["case.nml"], nranks=1, cwd=tmp_case_dir)
    assert_input_error(result, ["case.nml", "&run scene = 'mpmice'", "at least one &solid",
                                "(the input has 1 &fluid, 0 &solid)"], tmp_case_dir)


@pytest.mark.parametrize("case_id, extra, sets, pieces", BAD_MPMICE_INPUTS,
                         ids=[b[0] for b in BAD_MPMICE_INPUTS])
def test_bad_mpmice_input_stops_with_one_line(run_mpmice, tmp_case_dir, case_id, extra, sets,
                                              pieces):
    (tmp_case_dir / "case.nml").write_text(MPMICE_CASE + extra + "\n")
    args = ["case.nml"]
    for text in sets:
        args += ["--set", text]
    result = run_mpmice(args, nranks=1, cwd=tmp_case_dir)
    assert_input_error(result, pieces, tmp_case_dir)


def test_mpmice_check_echo_and_coupling_set(run_mpmice, tmp_case_dir):
    """--check of an 'mpmice' case prints &coupling and the new &solid variables (defaults
    included); --set on &coupling works; the printed text is a fixed point."""
    (tmp_case_dir / "case.nml").write_text(MPMICE_CASE)
    result = run_mpmice(["--check", "case.nml", "--set", '&coupling drag_scheme = "explicit" /'],
                        cwd=tmp_case_dir)
    assert result.returncode == 0, text_of(result.stderr)
    first = text_of(result.stdout)
    single = parse_namelist_text(first)
    assert single["run"]["scene"] == "mpmice"
    assert single["coupling"] == {"drag_scheme": "explicit", "face_drag": "cell",
                                  "heat_exchange_coefficient": 0.0,
                                  "max_solid_fraction": 0.999, "solid_fraction_relaxation": 0.1}
    solids = [values for name, values in parse_namelist_groups(first) if name == "solid"]
    assert len(solids) == 1
    soil = solids[0]
    assert soil["drag_law"] == "kozeny_carman"
    assert soil["drag_coefficient"] == 0.0 and soil["grain_bulk_modulus"] == 0.0
    assert soil["forchheimer_a"] == 150.0 and soil["forchheimer_b"] == 1.75
    assert soil["traction"] == [0.0, -1.0e4, 0.0]
    assert soil["traction_lower"] == [0.0, 0.9, 0.0]
    assert soil["traction_upper"] == [1.0, 1.0, 1.0]
    assert soil["traction_ramp_time"] == 0.0
    assert sorted(p.name for p in tmp_case_dir.iterdir()) == ["case.nml"]
    (tmp_case_dir / "resolved.nml").write_text(first)
    second = run_mpmice(["--check", "resolved.nml"], cwd=tmp_case_dir)
    assert second.returncode == 0, text_of(second.stderr)
    assert text_of(second.stdout) == first
