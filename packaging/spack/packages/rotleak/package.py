# Spack recipe for rotleak. Untested: this machine has no network and no Spack, so it has never been
# concretised or built; it states the build as CMakeLists.txt does (every dependency, the MPI and
# Python variants, the test suite). Use it from a local repository:
#   spack repo add packaging/spack && spack install rotleak+mpi+python
from spack.package import *


class Rotleak(CMakePackage):
    """Escape from the Bunimovich stadium with a rotating leak: survival probability, its exponential
    rate and algebraic tail from many particles on all cores, which digits are true (MPFR,
    double-double, __float128, intervals), and the leak's speed analysed exactly."""

    homepage = "https://arxiv.org/abs/1606.00364"
    git = "https://example.invalid/rotleak.git"  # no public repository yet: point this at yours

    maintainers("rotleak-developers")
    license("MIT")

    version("main", branch="main")

    variant("mpi", default=True, description="Split runs over MPI ranks (mpirun -np K rotleak simulate ...)")
    variant("python", default=True, description="The Python package with the in-process module (pybind11)")
    variant("native", default=False, description="Compile for the build machine's CPU (-march=native)")

    depends_on("cmake@3.22:", type="build")
    depends_on("pkgconfig", type="build")
    depends_on("gmp")
    depends_on("mpfr")
    depends_on("mpfi")
    depends_on("qd")
    depends_on("boost@1.74:")
    depends_on("cgal")
    depends_on("sleef")
    depends_on("random123")
    depends_on("tomlplusplus")
    depends_on("nlohmann-json")
    depends_on("cli11")
    depends_on("xsimd")
    depends_on("googletest", type="test")
    depends_on("benchmark", type="build")
    depends_on("mpi", when="+mpi")
    extends("python", when="+python")  # python_platlib below: where the package installs
    depends_on("python@3.11:", when="+python", type=("build", "run"))
    depends_on("py-pybind11", when="+python", type="build")
    depends_on("py-numpy", when="+python", type="run")
    depends_on("py-pandas", when="+python", type="run")
    depends_on("py-matplotlib", type="run")  # rotleak plot

    def cmake_args(self):
        return [
            self.define("ROTLEAK_MPI", "ON" if self.spec.satisfies("+mpi") else "OFF"),
            self.define("ROTLEAK_PYTHON_MODULE", "ON" if self.spec.satisfies("+python") else "OFF"),
            self.define_from_variant("ROTLEAK_NATIVE", "native"),
            self.define("ROTLEAK_TESTS", self.run_tests),
            self.define("ROTLEAK_BENCH", False),
            self.define("ROTLEAK_PYTHON_INSTALL_DIR", python_platlib) if self.spec.satisfies("+python") else
            self.define("ROTLEAK_PYTHON_INSTALL_DIR", "lib/python3/site-packages"),
        ]

    def check(self):
        with working_dir(self.build_directory):
            ctest("--output-on-failure", "-L", "unit|numeric")
