import os
import re
import subprocess
import sys

import pytest

import nsf


def test_import_gives_the_api_and_the_version():
    for name in ("load_scene", "simulate", "read_run", "Rom", "Run", "Scene"):
        assert hasattr(nsf, name), name
    assert nsf.__version__.count(".") == 2


def test_without_numpy_the_import_says_what_to_install():
    # numpy made unimportable in a child: the message names the Debian package to install.
    code = "import sys; sys.modules['numpy'] = None; import nsf"
    child = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                           env=dict(os.environ))
    assert child.returncode != 0
    assert "ImportError: nsf needs numpy" in child.stderr
    assert "apt-get install python3-numpy" in child.stderr


def test_the_module_exports_none_of_the_engines_symbols():
    # Like libnsf_runtime.so (tests/check_install.sh), the module keeps the engine's Eigen, JSON
    # and nsf code to itself; nsf::Runtime's typeinfo is the public facade's.
    nm = subprocess.run(["nm", "-DC", "--defined-only", nsf._nsf.__file__], capture_output=True,
                        text=True, check=True)
    exported = [line.split(" ", 2)[-1] for line in nm.stdout.splitlines()]
    assert "PyInit__nsf" in exported
    leaked = [s for s in exported if re.search(r"\b(Eigen|nlohmann|torch|c10|at|nsf)::", s)
              and not s.endswith(" for nsf::Runtime")]
    assert leaked == []


def test_imported_from_the_installed_package():
    # Set by tests/check_python_venv.sh (the ctest python_venv): the package pip installed into a
    # venv, not the source or build tree, is the one imported, module and all.
    where = os.environ.get("NSF_INSTALLED_IN")
    if not where:
        pytest.skip("not run from an installed package")
    where = os.path.realpath(where) + os.sep
    for f in (nsf.__file__, nsf._nsf.__file__):
        assert os.path.realpath(f).startswith(where), f
