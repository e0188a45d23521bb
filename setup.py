"""pip install . : builds the Python module seqtopo._core with CMake and packages it with python/seqtopo.

CMake configures the project with SEQTOPO_BUILD_PYTHON=ON (tests and benchmarks off) for the interpreter running
this script and builds only what the module needs: the target seqtopo_python (the library's modules it links) and
the codecs plugin, 113 compiled files; the command-line tool's own 24 are left out. While it builds, the
stages and the compile percentage are shown whether or not there is a terminal (python/build_progress.py), since
pip shows a build's output only with -v. Environment:
  SEQTOPO_PIP_COMMAND=1    also build the seqtopo command and its bundled demo data into the package (the
                           `seqtopo` console entry point then runs it; without it that entry point says how to
                           get the command);
  SEQTOPO_CMAKE_BUILD_DIR  CMake build folder (default: build/pip-<python version> in the source tree),
                           kept between installs so that a rebuild only recompiles what changed;
  SEQTOPO_BUILD_JOBS       parallel compile jobs (default: every core);
  CMAKE_ARGS               extra arguments for the CMake configure step.
"""

import os
import shlex
import shutil
import subprocess
import sys
import sysconfig

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext
from setuptools.command.egg_info import egg_info

ROOT = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(ROOT, "python"))
from build_progress import BuildProgress  # noqa: E402


def project_version() -> str:
    with open(os.path.join(ROOT, "CMakeLists.txt"), encoding="utf-8") as cmake:
        for line in cmake:
            if line.startswith("project(seqtopo VERSION "):
                return line.split()[2]
    raise RuntimeError("no project version in CMakeLists.txt")


def build_folder() -> str:
    tag = f"pip-py{sys.version_info.major}{sys.version_info.minor}"
    return os.environ.get("SEQTOPO_CMAKE_BUILD_DIR") or os.path.join(ROOT, "build", tag)


class CMakeExtension(Extension):
    def __init__(self, name: str):
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    def build_extension(self, ext: Extension) -> None:
        build_dir = build_folder()
        os.makedirs(build_dir, exist_ok=True)
        configure = [
            "cmake", "-S", ROOT, "-B", build_dir,
            "-DCMAKE_BUILD_TYPE=Release",
            "-DSEQTOPO_BUILD_PYTHON=ON", "-DSEQTOPO_BUILD_TESTS=OFF", "-DSEQTOPO_BUILD_BENCH=OFF",
            # Unity translation units (the library's files a module at a time; the run preset builds so too).
            "-DCMAKE_UNITY_BUILD=ON",
            f"-DSEQTOPO_PYTHON={sys.executable}",
        ]
        if shutil.which("ninja") and not os.path.exists(os.path.join(build_dir, "CMakeCache.txt")):
            configure += ["-G", "Ninja"]
        configure += shlex.split(os.environ.get("CMAKE_ARGS", ""))
        progress = BuildProgress()
        progress.run(configure, "configuring with CMake in " + os.path.relpath(build_dir, ROOT))
        jobs = os.environ.get("SEQTOPO_BUILD_JOBS") or str(os.cpu_count() or 1)
        command = os.environ.get("SEQTOPO_PIP_COMMAND") == "1"
        targets = ["seqtopo_python", "seqtopo_codecs"] + (["seqtopo"] if command else [])
        what = "the module and the command" if command else "the module"
        progress.run(["cmake", "--build", build_dir, "--target", *targets, "-j", jobs],
                     "building %s with %s jobs (a first build takes minutes)" % (what, jobs))

        suffix = sysconfig.get_config_var("EXT_SUFFIX")
        built = os.path.join(build_dir, "python", "seqtopo", "_core" + suffix)
        target = self.get_ext_fullpath(ext.name)
        os.makedirs(os.path.dirname(target), exist_ok=True)
        shutil.copyfile(built, target)
        # OpenCV's codecs, which the module and the command open on first use, beside each (image/codecs.hpp).
        codecs = os.path.join(build_dir, "src", "libseqtopo_codecs.so")
        shutil.copy2(codecs, os.path.dirname(target))
        package = os.path.dirname(target)
        for stale in ("bin", "data"):  # a command from an earlier SEQTOPO_PIP_COMMAND=1 build in the same tree
            shutil.rmtree(os.path.join(package, stale), ignore_errors=True)
        if command:
            # The command-line tool, run by the `seqtopo` console entry point (seqtopo/_cli.py): the launcher and
            # the program it starts, side by side, and the demo data `seqtopo map` maps when given no input
            # (found from the program's place: seqtopo/bin/ -> seqtopo/data/).
            tools = os.path.join(package, "bin")
            os.makedirs(tools, exist_ok=True)
            for name in ("seqtopo", "seqtopo-main"):
                shutil.copy2(os.path.join(build_dir, "src", name), os.path.join(tools, name))
            shutil.copy2(codecs, tools)
            shutil.copytree(os.path.join(ROOT, "data", "rtabmap-corridor"),
                            os.path.join(package, "data", "rtabmap-corridor"))
        progress.done("seqtopo._core" + (" and the seqtopo command" if command else ""))


class OutOfTreeEggInfo(egg_info):
    """Writes the .egg-info metadata under build/ instead of beside the package sources."""

    def initialize_options(self) -> None:
        super().initialize_options()
        self.egg_base = os.path.relpath(os.path.join(ROOT, "build"), os.getcwd())
        os.makedirs(os.path.join(ROOT, "build"), exist_ok=True)


setup(
    name="seqtopo",
    version=project_version(),
    description="Topological mapping and localization with the algorithms of DNA sequence alignment",
    long_description="Python bindings of the seqtopo C++ library; see docs/python.md.",
    license="BSD-3-Clause",
    license_files=["LICENSE"],
    python_requires=">=3.9",
    install_requires=["numpy"],
    packages=["seqtopo"],
    package_dir={"": "python"},
    ext_modules=[CMakeExtension("seqtopo._core")],
    entry_points={"console_scripts": ["seqtopo = seqtopo._cli:main"]},
    cmdclass={"build_ext": CMakeBuild, "egg_info": OutOfTreeEggInfo},
    zip_safe=False,
)
