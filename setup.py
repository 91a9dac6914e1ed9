"""The build helper behind pyproject.toml: setuptools' build_ext builds the extension module nsf._nsf
with CMake (the target nsf_python of python/CMakeLists.txt) and copies it, with the runtime
library it links (libnsf_runtime.so.N, found through the module's run path $ORIGIN), next to the
pure-Python files of python/nsf/ in the wheel. docs/PYTHON.md, "Install with pip".

Environment:
  NSF_CMAKE_BUILD_DIR  an existing CMake build tree of this source (configured for this Python)
                       to build the target in and take the files from, instead of configuring a
                       tree of its own under build-pip/ (the first build compiles nsf and its
                       LibTorch layer, minutes); setuptools' files go to its pip/ then
  NSF_CMAKE_ARGS       more arguments for that configure step, e.g.
                       "-DCMAKE_PREFIX_PATH=/opt/libtorch"
"""

import os
import re
import shlex
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

SOURCE_DIR = os.path.dirname(os.path.abspath(__file__))
# setuptools' own build directory: in the CMake tree given, else next to CMake's build/ (.gitignore).
BUILD_BASE = (os.path.join(os.path.abspath(os.environ["NSF_CMAKE_BUILD_DIR"]), "pip")
              if os.environ.get("NSF_CMAKE_BUILD_DIR") else os.path.join(SOURCE_DIR, "build-pip"))


def cmake_version():
    with open(os.path.join(SOURCE_DIR, "CMakeLists.txt"), encoding="utf-8") as f:
        m = re.search(r"project\(\s*nsf\s+VERSION\s+([0-9.]+)", f.read())
    if not m:
        raise RuntimeError("no project(nsf VERSION x.y.z) in CMakeLists.txt")
    return m.group(1)


def run(cmd, **kw):
    print("nsf setup.py: " + " ".join(shlex.quote(c) for c in cmd), flush=True)
    subprocess.run(cmd, check=True, **kw)


class CMakeExtension(Extension):
    """The extension module, built by CMake rather than by setuptools' compiler."""

    def __init__(self, name, target):
        super().__init__(name, sources=[])
        self.target = target


class CMakeBuild(build_ext):
    """Builds the CMake target of each CMakeExtension and copies what its install component (of
    the same name) puts into nsf/: the module and the shared libraries it needs."""

    def build_extension(self, ext):
        if not isinstance(ext, CMakeExtension):
            return super().build_extension(ext)
        tree = os.environ.get("NSF_CMAKE_BUILD_DIR")
        if tree:
            tree = os.path.abspath(tree)
            if not os.path.isfile(os.path.join(tree, "CMakeCache.txt")):
                raise RuntimeError("NSF_CMAKE_BUILD_DIR=%s is not a configured CMake build tree" % tree)
        else:
            tree = os.path.abspath(os.path.join(self.build_temp, "cmake"))
            self.configure(tree)
        run(["cmake", "--build", tree, "--target", ext.target])

        stage = os.path.abspath(os.path.join(self.build_temp, "stage"))
        shutil.rmtree(stage, ignore_errors=True)
        run(["cmake", "--install", tree, "--component", ext.target, "--prefix", stage])
        staged = os.path.join(stage, "nsf")
        module = os.path.basename(self.get_ext_filename(ext.name))  # _nsf.cpython-311-...so
        if not os.path.isfile(os.path.join(staged, module)):
            found = sorted(os.listdir(staged)) if os.path.isdir(staged) else []
            raise RuntimeError(
                "the build tree %s holds no %s for this Python (%s, %s); it has %s. Configure it "
                "with -DPython3_EXECUTABLE=%s, or leave NSF_CMAKE_BUILD_DIR unset"
                % (tree, module, sys.executable, sys.version.split()[0], found or "nothing",
                   sys.executable))

        # A wheel holds no symbolic links: each link (libnsf_runtime.so.0, the name the module
        # asks for) is shipped as a copy of the file it names, and that file itself is left out.
        # The runtime's x86-64-v3 copy keeps its folder, glibc-hwcaps/x86-64-v3/, where the
        # loader looks for it first on a CPU that has AVX2 and FMA (docs/PYTHON.md).
        dest = os.path.dirname(os.path.abspath(self.get_ext_fullpath(ext.name)))
        os.makedirs(dest, exist_ok=True)
        for name in os.listdir(dest):  # what an earlier build left: the component's files only
            if re.fullmatch(r"(_nsf\..*\.so|lib.*\.so(\.[0-9]+)*)", name):
                os.remove(os.path.join(dest, name))
        shutil.rmtree(os.path.join(dest, "glibc-hwcaps"), ignore_errors=True)
        for folder, _, names in os.walk(staged):
            linked = {os.path.realpath(os.path.join(folder, n)) for n in names
                      if os.path.islink(os.path.join(folder, n))}
            for name in sorted(names):
                path = os.path.join(folder, name)
                if not os.path.islink(path) and os.path.realpath(path) in linked:
                    continue
                target = os.path.join(dest, os.path.relpath(path, staged))
                os.makedirs(os.path.dirname(target), exist_ok=True)
                if os.path.lexists(target):
                    os.remove(target)
                shutil.copyfile(path, target)  # follows a link
                shutil.copymode(path, target)

    def configure(self, tree):
        args = ["-DCMAKE_BUILD_TYPE=Release", "-DNSF_BUILD_TESTS=OFF", "-DNSF_BUILD_BENCH=OFF",
                "-DNSF_BUILD_PYTHON=ON", "-DPython3_EXECUTABLE=" + sys.executable]
        if shutil.which("ninja") and not os.path.isfile(os.path.join(tree, "CMakeCache.txt")):
            args += ["-G", "Ninja"]
        args += shlex.split(os.environ.get("NSF_CMAKE_ARGS", ""))
        run(["cmake", "-S", SOURCE_DIR, "-B", tree] + args)


os.makedirs(BUILD_BASE, exist_ok=True)
setup(
    version=cmake_version(),
    ext_modules=[CMakeExtension("nsf._nsf", target="nsf_python")],
    cmdclass={"build_ext": CMakeBuild},
    options={"build": {"build_base": BUILD_BASE}, "egg_info": {"egg_base": BUILD_BASE}},
)
