#!/usr/bin/env bash
# The Python package as pip installs it (docs/PYTHON.md, "Install with pip"). In a scratch
# directory outside the source tree: a fresh venv of PYTHON without the system's site-packages,
# the build backend (setuptools, wheel) from Debian's wheels in /usr/share/python-wheels, then
#   - `pip wheel --no-build-isolation` of the source tree: the wheel holds the module, the runtime
#     library it links (and its x86-64-v3 copy in glibc-hwcaps/ where the build made one), the
#     Python files, the stubs and py.typed, and no symbolic link;
#   - `pip install --no-build-isolation` of the source tree into the venv: the installed module and
#     library find their shared libraries (ldd) with no run path into the source or build tree,
#     the module loads with nothing but the venv (the v3 copy on a CPU that has x86-64-v3), and
#     `import nsf` says numpy is missing;
#   - the pytest suite (python/tests), run from the scratch directory by the venv's python, with
#     numpy, pytest and h5py from Debian's dist-packages on PYTHONPATH (no PyPI offline: they
#     cannot be pip-installed into the venv); `import nsf` must come from the venv.
# setup.py builds in BUILD_DIR (NSF_CMAKE_BUILD_DIR) instead of configuring a tree of its own, so
# nothing is compiled twice. Usage: tests/check_python_venv.sh SOURCE_DIR BUILD_DIR PYTHON NSF_CLI.
# Run by ctest (python_venv).
set -euo pipefail
src=$(cd "$1" && pwd)
build=$(cd "$2" && pwd)
python=$3
cli=$4
tmp=$(mktemp -d "${TMPDIR:-/tmp}/nsf_venv.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
die() {
  echo "check_python_venv: $*" >&2
  exit 1
}
step() { echo "== $* ($SECONDS s)"; }
cd "$tmp"

step "a venv of $python without the system's site-packages"
"$python" -m venv "$tmp/venv" ||
  die "$python -m venv failed: Debian's python3-venv is needed (scripts/install-deps.sh)"
py="$tmp/venv/bin/python"
wheels=/usr/share/python-wheels
ls "$wheels"/wheel-*.whl >/dev/null 2>&1 ||
  die "no wheel in $wheels: Debian's python3-wheel-whl is needed (scripts/install-deps.sh)"
"$py" -m pip install -q --no-index --find-links "$wheels" setuptools wheel
site=$("$py" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
[[ "$site" == "$tmp/venv/"* ]] || die "the venv's site-packages is $site"

export NSF_CMAKE_BUILD_DIR="$build" PIP_NO_INDEX=1 PIP_DISABLE_PIP_VERSION_CHECK=1
# The runtime's x86-64-v3 copy (cmake/hwcaps.cmake), where the build made one, and whether the
# loader takes it on this CPU.
hwcaps=glibc-hwcaps/x86-64-v3
[[ -f "$build/$hwcaps/libnsf_runtime.so.0" ]] && export NSF_HWCAPS_COPY="nsf/$hwcaps/libnsf_runtime.so.0"
if [[ -n "${NSF_HWCAPS_COPY:-}" ]] && /lib64/ld-linux-x86-64.so.2 --help 2>/dev/null |
  grep -q "x86-64-v3 (supported, searched)"; then
  export NSF_WANT_ARCH=x86-64-v3
elif [[ -n "${NSF_HWCAPS_COPY:-}" ]]; then
  export NSF_WANT_ARCH=x86-64-v2
fi
step "pip wheel the source tree"
"$py" -m pip wheel -q --no-build-isolation --no-deps -w "$tmp/wheels" "$src"
whl=$(ls "$tmp"/wheels/nsf-*.whl) || die "pip wheel made no nsf wheel"
"$py" - "$whl" <<'EOF' || die "the wheel $whl is not what it should be"
import os, re, stat, sys, zipfile
names = {i.filename: i for i in zipfile.ZipFile(sys.argv[1]).infolist()}
want = ["nsf/__init__.py", "nsf/__init__.pyi", "nsf/py.typed", "nsf/libnsf_runtime.so.0"]
want += [os.environ["NSF_HWCAPS_COPY"]] if os.environ.get("NSF_HWCAPS_COPY") else []
missing = [n for n in want if n not in names]
modules = [n for n in names if re.fullmatch(r"nsf/_nsf\..*\.so", n)]
links = [n for n, i in names.items() if stat.S_ISLNK(i.external_attr >> 16)]
print("wheel:", ", ".join(sorted(names)))
if missing or len(modules) != 1 or links:
    sys.exit("missing %s, modules %s, links %s" % (missing, modules, links))
EOF

step "pip install the source tree into the venv"
"$py" -m pip install -q --no-build-isolation --no-deps "$src"
pkg="$site/nsf"
module=$(ls "$pkg"/_nsf.*.so) || die "no extension module in $pkg"
[[ -z "$(find "$pkg" -type l)" ]] || die "symbolic links installed: $(find "$pkg" -type l)"

step "its shared libraries"
for so in "$module" $(find "$pkg" -name 'libnsf_runtime.so.*'); do
  ldd "$so" >"$tmp/ldd.txt" || die "ldd $so failed"
  ! grep -q 'not found' "$tmp/ldd.txt" || die "$so: $(grep 'not found' "$tmp/ldd.txt")"
  ! grep -qF -e "$src" -e "$build" "$tmp/ldd.txt" || die "$so loads from the source or build tree: $(cat "$tmp/ldd.txt")"
  runpath=$(readelf -d "$so" | grep -E 'RPATH|RUNPATH' || true)
  ! grep -qF -e "$src" -e "$build" <<<"$runpath" || die "$so has a run path into the source or build tree: $runpath"
done
# Through a file: under pipefail, grep -q leaving early kills ldd with SIGPIPE and fails the check.
ldd "$module" >"$tmp/module_ldd.txt"
loads=$pkg/libnsf_runtime.so.0
[[ "${NSF_WANT_ARCH:-}" != x86-64-v3 ]] || loads=$pkg/$hwcaps/libnsf_runtime.so.0
grep -qF "libnsf_runtime.so.0 => $loads" "$tmp/module_ldd.txt" ||
  die "the module does not load the runtime library next to it: $(cat "$tmp/module_ldd.txt")"

step "the venv alone: the module loads; import nsf asks for numpy"
env -u PYTHONPATH "$py" - "$module" <<'EOF' || die "the extension module does not load in the bare venv"
import importlib.machinery, importlib.util, sys
loader = importlib.machinery.ExtensionFileLoader("nsf._nsf", sys.argv[1])
module = importlib.util.module_from_spec(importlib.util.spec_from_loader("nsf._nsf", loader))
loader.exec_module(module)
print("nsf._nsf", module.__version__, "loads")
EOF
if ! env -u PYTHONPATH "$py" -c 'import numpy' 2>/dev/null; then
  if env -u PYTHONPATH "$py" -c 'import nsf' 2>"$tmp/import.txt"; then
    die "import nsf worked without numpy"
  fi
  grep -q "ImportError: nsf needs numpy" "$tmp/import.txt" || die "$(cat "$tmp/import.txt")"
fi

# Debian's numpy, pytest and h5py, which the venv cannot get offline: their directories, and
# nothing else of the system's site-packages (no .pth file there is read: they are on PYTHONPATH).
deps=$("$python" -c '
import os, h5py, numpy, pytest
print(":".join(sorted({os.path.dirname(os.path.dirname(m.__file__)) for m in (h5py, numpy, pytest)})))')
export PYTHONPATH="$deps" PYTHONDONTWRITEBYTECODE=1 NSF_CLI="$cli" NSF_SOURCE_DIR="$src"
export NSF_INSTALLED_IN="$site"
step "import nsf from the venv (PYTHONPATH=$deps)"
"$py" -c '
import os, sys, nsf
where = os.path.realpath(nsf.__file__)
assert where.startswith(os.path.realpath(os.environ["NSF_INSTALLED_IN"]) + os.sep), where
arch = nsf.build_arch()
want = os.environ.get("NSF_WANT_ARCH", arch)
assert arch == want, "the runtime copy loaded is built for %s, not %s" % (arch, want)
print("nsf", nsf.__version__, "from", os.path.dirname(where), "runtime built for", arch)' ||
  die "import nsf does not work from the venv"

step "the pytest suite with the venv's python, from $tmp"
"$py" -m pytest -q -p no:cacheprovider "$src/python/tests"
