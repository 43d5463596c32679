"""Builds the Python module through CMake (cmake/Python.cmake): the
extension mbrt._mbrt, for the interpreter running pip.

Environment: CMAKE_ARGS (more -D options, e.g. a compiler launcher),
MBRT_CMAKE_BUILD_DIR (the CMake build folder; default: setuptools' own),
MBRT_JOBS (parallel build jobs; default: all cores)."""
import os
import pathlib
import shlex
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent


class CMakeExtension(Extension):
    def __init__(self, name):
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        target = pathlib.Path(self.get_ext_fullpath(ext.name)).resolve()
        build = pathlib.Path(os.environ.get("MBRT_CMAKE_BUILD_DIR") or pathlib.Path(self.build_temp) / "cmake").resolve()
        configure = ["cmake", "-S", str(ROOT), "-B", str(build), "-DMBRT_PYTHON=ON",
                     f"-DMBRT_PYTHON_EXECUTABLE={os.path.realpath(sys.executable)}"]  # a venv: its base
        if not (build / "CMakeCache.txt").exists():
            # A new folder builds the library and the module only; an existing
            # one (MBRT_CMAKE_BUILD_DIR) keeps its other settings.
            configure += ["-DCMAKE_BUILD_TYPE=Release", "-DMBRT_BUILD_TESTS=OFF", "-DMBRT_BUILD_TOOLS=OFF"]
            if shutil.which("ninja"):
                configure += ["-G", "Ninja"]
        configure += shlex.split(os.environ.get("CMAKE_ARGS", ""))
        subprocess.run(configure, check=True)
        jobs = os.environ.get("MBRT_JOBS", str(os.cpu_count() or 1))
        subprocess.run(["cmake", "--build", str(build), "--target", "mbrt_python", "-j", jobs], check=True)
        built = next((build / "python" / "mbrt").glob("_mbrt*.so"))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built, target)


setup(
    packages=["mbrt"],
    package_dir={"": "python"},
    package_data={"mbrt": ["*.pyi", "py.typed"]},
    ext_modules=[CMakeExtension("mbrt._mbrt")],
    cmdclass={"build_ext": CMakeBuild},
    zip_safe=False,
)
