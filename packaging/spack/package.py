# Spack recipe of MPMICE (docs/install.md "Spack"). Copy it into a Spack package repository as
# packages/mpmice/package.py; build a checkout with `spack develop` (no download URL yet).
# Checked by tests/validation/test_packaging.py (syntax, dependencies, variants).
from spack.package import *  # noqa: F401,F403 (Spack's recipe API: version, variant, ...)

try:  # Spack >= 1.0: the build systems live in the builtin package repository
    from spack_repo.builtin.build_systems.cmake import CMakePackage  # noqa: F811
except ImportError:  # Spack 0.x: CMakePackage comes with spack.package
    pass


class Mpmice(CMakePackage):
    """MPMICE: material point method (MPM) solids coupled to multi-material ICE fluids
    (Fortran 2008, MPI, hypre, parallel HDF5), for submarine landslides, debris flows and
    fluid-structure problems, with a Python postprocessing package."""

    # homepage, git and checksummed releases: to be added once the repository is published

    # The number comes from project(mpmice VERSION ...) in CMakeLists.txt; the test checks that
    # the newest numbered version here is that one.
    version("develop")
    version("0.1.0")

    variant(
        "build_type",
        default="Release",
        values=("Release", "Debug", "RelWithDebInfo"),
        description="CMake build type (Debug: -fcheck=all and floating-point traps)",
    )
    variant(
        "postproc",
        default=True,
        description="Install the Python postprocessing package (share/mpmice/postproc)",
    )

    depends_on("cmake@3.20:", type="build")
    depends_on("c", type="build")
    depends_on("fortran", type="build")

    # MPI with the mpi_f08 module (MPI 3); parallel HDF5 with its Fortran interface; hypre with
    # MPI and the default 32-bit integers the Fortran bindings use; LAPACK.
    depends_on("mpi@3:")
    depends_on("hdf5+mpi+fortran")
    depends_on("hypre+mpi~int64~mixedint")
    depends_on("lapack")

    # The unit tests build and run under `spack install --test=root` (Spack's way, instead of a
    # variant): BUILD_TESTING follows it, and they need a real pFUnit 4 with MPI. The MPI tests
    # use mpi_f08 communicators, i.e. a pFUnit configured with ENABLE_MPI_F08=YES, which Spack's
    # pfunit recipe has no variant for (docs/testing.md "Real pFUnit or pfunit-lite").
    depends_on("pfunit@4:+mpi", type="test")

    with when("+postproc"):
        depends_on("python@3.9:", type="run")
        depends_on("py-numpy", type="run")
        depends_on("py-h5py", type="run")
        depends_on("py-matplotlib", type="run")

    # The build generates the namelist code from modules/config/namelist/*.toml with
    # scripts/generate_namelists.py (standard library only, tomllib: Python 3.11), and expands the
    # Fortran templates (modules/**/*.fypp) with fypp (cmake/mpmice_fypp.cmake).
    depends_on("python@3.11:", type="build")
    depends_on("py-fypp", type="build")

    def cmake_args(self):
        return [
            self.define("BUILD_TESTING", self.run_tests),
            self.define_from_variant("MPMICE_INSTALL_POSTPROC", "postproc"),
        ]

    def setup_run_environment(self, env):
        # postproc finds the program through MPMICE_EXE (postproc/run_case.py)
        env.set("MPMICE_EXE", join_path(self.prefix.bin, "mpmice"))
        if self.spec.satisfies("+postproc"):
            env.prepend_path("PYTHONPATH", join_path(self.prefix.share, "mpmice"))
