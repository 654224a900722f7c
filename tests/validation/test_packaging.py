"""Packaging checks that need no Fortran compiler (docs/install.md): the Spack recipe
packaging/spack/package.py and the installed Python package.

* The recipe compiles, and loaded against a stub of Spack's recipe API (``spack.package``) it
  declares class ``Mpmice(CMakePackage)``, the dependencies the build needs (mpi, hdf5+mpi+fortran,
  hypre+mpi, lapack; pfunit for tests; python, numpy, h5py, matplotlib at run time under
  +postproc), the variants ``build_type`` and ``postproc``, the project's version, CMake
  options that exist in the CMake sources, and a run environment that fits the install layout.
* ``cmake --install`` of the build tree gives a ``postproc`` package that runs with
  ``PYTHONPATH=<prefix>/share/mpmice`` from any directory, finds ``<prefix>/bin/mpmice`` and
  compares a run of the installed program and example with the exact solution.

The install, the run and the comparison take a few seconds; the CMake side (find_package,
the consumer, the version in the program and the dumps) is ctest ``packaging.install_consumer``.
"""

import contextlib
import os
import py_compile
import re
import subprocess
import sys
import types
from pathlib import Path

import h5py

from postproc.run_case import mpi_environment, mpirun_command

REPO_ROOT = Path(__file__).resolve().parents[2]

RECIPE = REPO_ROOT / 'packaging' / 'spack' / 'package.py'


def project_version():
    """The x.y.z of ``project(mpmice VERSION x.y.z ...)`` in CMakeLists.txt."""
    text = (REPO_ROOT / 'CMakeLists.txt').read_text()
    match = re.search(r'project\(\s*mpmice\s+VERSION\s+([0-9.]+)', text)
    assert match, 'CMakeLists.txt has no project(mpmice VERSION x.y.z)'
    return match.group(1)


class _Recorder:
    """What the recipe's directives declared."""

    def __init__(self):
        self.versions, self.variants, self.depends = [], {}, []
        self.when_stack = []


def load_recipe():
    """Execute the recipe with a stub ``spack.package``; return (class, recorder)."""
    rec = _Recorder()

    class CMakePackage:  # the parts of Spack's CMakePackage the recipe uses
        run_tests = False

        def define(self, name, value):
            kind = 'BOOL' if isinstance(value, bool) else 'STRING'
            value = ('ON' if value else 'OFF') if isinstance(value, bool) else value
            return f'-D{name}:{kind}={value}'

        def define_from_variant(self, name, variant):
            return self.define(name, self.spec.variants[variant])

    def version(name, **kwargs):
        rec.versions.append(name)

    def variant(name, default=None, values=None, description='', **kwargs):
        rec.variants[name] = {'default': default, 'values': values, 'description': description}

    def depends_on(spec, type=('build', 'link'), when=None):
        whens = list(rec.when_stack) + ([when] if when else [])
        kinds = (type,) if isinstance(type, str) else tuple(type)
        rec.depends.append({'spec': spec, 'type': kinds, 'when': ' '.join(whens)})

    @contextlib.contextmanager
    def when(condition):
        rec.when_stack.append(condition)
        yield
        rec.when_stack.pop()

    api = types.ModuleType('spack.package')
    api.CMakePackage = CMakePackage
    api.version, api.variant, api.depends_on, api.when = version, variant, depends_on, when
    api.maintainers = lambda *names: None
    api.join_path = os.path.join
    api.__all__ = ['CMakePackage', 'version', 'variant', 'depends_on', 'when', 'maintainers',
                   'join_path']
    saved = {k: sys.modules.get(k) for k in ('spack', 'spack.package')}
    sys.modules['spack'] = types.ModuleType('spack')
    sys.modules['spack.package'] = api
    try:
        namespace = {'__name__': 'mpmice_recipe'}
        exec(compile(RECIPE.read_text(), str(RECIPE), 'exec'), namespace)
    finally:
        for key, module in saved.items():
            if module is None:
                sys.modules.pop(key, None)
            else:
                sys.modules[key] = module
    return namespace['Mpmice'], CMakePackage, rec


def dependency(rec, name):
    """The depends_on entries whose spec names package ``name``."""
    return [d for d in rec.depends if re.match(rf'{re.escape(name)}(?![\w-])', d['spec'])]


def test_recipe_compiles(tmp_path):
    py_compile.compile(str(RECIPE), doraise=True, cfile=str(tmp_path / 'package.pyc'))


def test_recipe_dependencies_and_variants():
    cls, base, rec = load_recipe()
    assert issubclass(cls, base)
    # link dependencies of the library (what mpmiceConfig.cmake finds again)
    for name, variants in [('mpi', ()), ('hdf5', ('+mpi', '+fortran')), ('hypre', ('+mpi',)),
                           ('lapack', ())]:
        found = dependency(rec, name)
        assert found, f'no depends_on("{name}...")'
        spec = found[0]['spec']
        for v in variants:
            assert v in spec, f'{name} must be {v}: {spec}'
        assert 'link' in found[0]['type'] and not found[0]['when'], found[0]
    assert dependency(rec, 'cmake')[0]['type'] == ('build',)
    pfunit = dependency(rec, 'pfunit')
    assert pfunit and pfunit[0]['type'] == ('test',) and '+mpi' in pfunit[0]['spec']
    for name in ('python', 'py-numpy', 'py-h5py', 'py-matplotlib'):
        found = dependency(rec, name)
        assert found, f'no depends_on("{name}")'
        assert 'run' in found[0]['type'] and '+postproc' in found[0]['when'], found[0]
    # the build runs scripts/generate_namelists.py (tomllib: Python >= 3.11)
    assert any(d['type'] == ('build',) and d['spec'].startswith('python@3.11')
               for d in dependency(rec, 'python'))
    assert set(rec.variants) == {'build_type', 'postproc'}
    assert rec.variants['build_type']['default'] == 'Release'
    assert rec.variants['postproc']['default'] is True


def test_recipe_version_is_the_project_version():
    _, _, rec = load_recipe()
    numbered = [v for v in rec.versions if re.fullmatch(r'[0-9.]+', v)]
    newest = max(numbered, key=lambda v: tuple(int(p) for p in v.split('.')))
    assert newest == project_version()


def test_recipe_cmake_options_exist():
    """Every -D<name> the recipe passes is an option the CMake sources define or read."""
    cls, _, _ = load_recipe()
    package = cls()
    package.spec = types.SimpleNamespace(variants={'postproc': False})
    package.run_tests = True
    args = package.cmake_args()
    assert '-DBUILD_TESTING:BOOL=ON' in args
    assert '-DMPMICE_INSTALL_POSTPROC:BOOL=OFF' in args
    sources = ''.join(p.read_text() for p in [REPO_ROOT / 'CMakeLists.txt',
                                              *(REPO_ROOT / 'cmake').glob('*.cmake')])
    for arg in args:
        name = re.match(r'-D(\w+)', arg).group(1)
        if name != 'BUILD_TESTING':  # CTest's own option
            assert re.search(rf'option\(\s*{name}\b', sources), f'{name}: no such CMake option'


def recipe_run_environment(prefix, postproc):
    """Variables the recipe's ``setup_run_environment`` sets for an install at ``prefix``."""
    cls, _, _ = load_recipe()
    package = cls()
    answers = {'+postproc': postproc, '~postproc': not postproc}
    package.spec = types.SimpleNamespace(satisfies=lambda condition: answers[condition])
    package.prefix = types.SimpleNamespace(bin=str(prefix / 'bin'), share=str(prefix / 'share'))
    variables = {}

    class Env:  # the parts of Spack's EnvironmentModifications the recipe uses
        def set(self, name, value):
            variables[name] = value

        def prepend_path(self, name, path):
            variables[name] = path + (os.pathsep + variables[name] if name in variables else '')

    package.setup_run_environment(Env())
    return variables


def test_installed_postproc_runs(mpmice_exe, unavailable, tmp_path):
    """Install the build tree of ``mpmice_exe`` into a temporary prefix; from outside the
    repository, with only ``PYTHONPATH=<prefix>/share/mpmice``, the installed postproc package
    imports from the prefix and finds ``<prefix>/bin/mpmice``; a short run of the installed
    program on the installed heat_conduction_1d.nml writes dumps with ``mpmice_version`` equal to
    project(VERSION), and ``python -m postproc.heat_conduction`` compares it with the exact
    solution."""
    build = mpmice_exe.parent.parent
    if not (build / 'cmake_install.cmake').is_file():
        unavailable(f'{mpmice_exe} is not in a CMake build tree (<build>/bin/mpmice): '
                    'nothing to install')
    prefix = tmp_path / 'prefix'
    subprocess.run(['cmake', '--install', str(build), '--prefix', str(prefix)], check=True,
                   capture_output=True, text=True, timeout=120)
    # the environment the Spack recipe gives (setup_run_environment) must fit the CMake layout
    recipe_env = recipe_run_environment(prefix, postproc=True)
    assert recipe_env['MPMICE_EXE'] == str(prefix / 'bin' / 'mpmice')
    assert recipe_env['PYTHONPATH'] == str(prefix / 'share' / 'mpmice')
    assert 'PYTHONPATH' not in recipe_run_environment(prefix, postproc=False)
    env = {k: v for k, v in os.environ.items() if k not in ('MPMICE_EXE', 'PYTHONPATH')}
    env['PYTHONPATH'] = recipe_env['PYTHONPATH']
    probe = ('import postproc, postproc.run_case as r; '
             'print(postproc.__file__); print(r.mpmice_executable())')
    out = subprocess.run([sys.executable, '-c', probe], cwd=tmp_path, env=env, check=True,
                         capture_output=True, text=True, timeout=60).stdout.split('\n')
    assert Path(out[0]).resolve().is_relative_to(prefix.resolve()), out[0]
    installed_exe = prefix / 'bin' / 'mpmice'
    assert Path(out[1]) == installed_exe, out[1]

    run_dir = tmp_path / 'run'
    command = mpirun_command(installed_exe, [
        prefix / 'share' / 'mpmice' / 'namelists' / 'heat_conduction_1d.nml',
        '--set', f"&run output_dir = '{run_dir}', end_time = 0.02, output_interval = 0.01 /"], 1)
    ran = subprocess.run(command, cwd=tmp_path, env=mpi_environment(), capture_output=True,
                         text=True, timeout=120)
    assert ran.returncode == 0, ran.stdout + ran.stderr
    dumps = sorted(run_dir.glob('heat1d_*.h5'))
    assert dumps, f'no dump in {run_dir}'
    with h5py.File(dumps[-1], 'r') as f:
        version = f.attrs['mpmice_version']
    version = version.decode() if isinstance(version, bytes) else str(version)
    assert version == project_version()

    png = tmp_path / 'heat.png'
    compared = subprocess.run([sys.executable, '-m', 'postproc.heat_conduction', str(run_dir),
                               '--png', str(png)], cwd=tmp_path, env=env, capture_output=True,
                              text=True, timeout=120)
    assert compared.returncode == 0, compared.stdout + compared.stderr
    assert png.is_file() and png.stat().st_size > 0
