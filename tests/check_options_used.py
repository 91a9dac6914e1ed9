#!/usr/bin/env python3
"""Every option that `nsf rom --help` and `nsf train --help` list is used somewhere: by a test, a
scene, a script, a benchmark or a stored row's command (issue #56). An option nothing uses is an
experiment that never won or a switch only a test needs; retire it (src/app/retired_options.cpp)
or move it behind the test interface. Fails listing each unused option.
Usage: tests/check_options_used.py NSF_BINARY [REPO_ROOT]. Run by ctest."""
import pathlib
import re
import subprocess
import sys

COMMANDS = ("rom", "train")
# Where a use counts: the suites, the scenes and what makes the stored figures.
PLACES = ("tests", "python/tests", "scenes", "scripts", "bench", "docs/results", ".ci")
SUFFIXES = {".cpp", ".h", ".py", ".sh", ".json", ".c", ""}


def options(nsf, command):
    help_text = subprocess.run([nsf, command, "--help"], capture_output=True, text=True,
                               check=True).stdout
    return sorted(set(re.findall(r"^\s+(?:-\w, )?(--[a-z0-9][a-z0-9-]*)", help_text, re.M)) -
                  {"--help"})


def main():
    nsf = sys.argv[1]
    root = pathlib.Path(sys.argv[2] if len(sys.argv) > 2 else pathlib.Path(__file__).parent.parent)
    text = []
    for place in PLACES:
        for path in (root / place).rglob("*"):
            if path.is_file() and path.suffix in SUFFIXES and path.name != pathlib.Path(__file__).name:
                text.append(path.read_text(errors="replace"))
    corpus = "\n".join(text)
    unused = [f"nsf {c} {o}" for c in COMMANDS for o in options(nsf, c)
              if not re.search(re.escape(o) + r"(?![a-z0-9-])", corpus)]
    if unused:
        print("\n".join(unused))
        print(f"check_options_used: {len(unused)} option(s) that no test, scene, script, benchmark "
              "or row uses", file=sys.stderr)
        return 1
    print(f"check_options_used: every option of nsf {' and nsf '.join(COMMANDS)} is used")
    return 0


if __name__ == "__main__":
    sys.exit(main())
