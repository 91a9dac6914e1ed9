#!/usr/bin/env python3
"""The command files of src/app parse flags and call the library: no function there runs over
60 lines (issue #56), bar the option registrations (add_*_command, add_*_commands), which are one
line per flag. Counts every function body, free or member, from its opening line to its closing
brace; lambdas count toward the function they are in. Fails listing each function over the limit.
Usage: tests/check_function_length.py [SRC_APP_DIR] [LIMIT]. Run by ctest."""
import pathlib
import re
import sys

CONTROL = re.compile(r"^\s*(\}\s*)?(if|for|while|switch|catch|do|else|try|return)\b")
NOT_FUNCTION = re.compile(r"\b(namespace|class|struct|union|enum)\b|=\s*$|\]\s*(\(|mutable|$)|\)\s*->")
REGISTRATION = re.compile(r"\badd_\w+_commands?\s*\(")


def strip(text):
    """The code with comments, strings and character literals blanked (lines kept)."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append("\n" * text.count("\n", i, j))
            i = j
        elif text.startswith('R"', i):
            m = re.match(r'R"([^(]*)\(', text[i:])
            end = text.find(")" + m.group(1) + '"', i)
            out.append('""' + "\n" * text.count("\n", i, end))
            i = end + len(m.group(1)) + 2
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            out.append(c + c)
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


def functions(path):
    """(name line, first line, length) of each outermost function body in the file."""
    code = strip(path.read_text())
    stack = []  # (kind, line) per open brace: kind "f" a function body, "o" anything else
    head = ""  # the code since the last ; { or } at this point: the brace's declaration
    line = 1
    for c in code:
        if c == "\n":
            line += 1
            head += " "
        elif c == "{":
            h = head.strip()
            inside = any(k == "f" for k, _, _ in stack)
            is_fn = (not inside and ")" in h and not CONTROL.match(h) and not NOT_FUNCTION.search(h)
                     and not h.startswith("#"))
            stack.append(("f" if is_fn else "o", line, h))
            head = ""
        elif c == "}":
            if stack:
                kind, start, h = stack.pop()
                if kind == "f":
                    yield h, start, line - start + 1
            head = ""
        elif c == ";":
            head = ""
        else:
            head += c


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).parent.parent / "src/app")
    limit = int(sys.argv[2]) if len(sys.argv) > 2 else 60
    long = []
    for path in sorted(root.glob("*.cpp")) + sorted(root.glob("*.h")):
        for head, start, length in functions(path):
            if length > limit and not REGISTRATION.search(head):
                name = re.sub(r"\s+", " ", head)[:80]
                long.append(f"{path.name}:{start}: {length} lines: {name}")
    if long:
        print("\n".join(long))
        print(f"check_function_length: {len(long)} function(s) of {root} run over {limit} lines; "
              "move the work into the library or split it", file=sys.stderr)
        return 1
    print(f"check_function_length: no function of {root} runs over {limit} lines "
          "(option registrations aside)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
