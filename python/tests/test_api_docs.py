"""The public API is documented and typed: every class, function, method and property that `nsf`
exports has a docstring, and the stubs shipped with the package (nsf/__init__.pyi, py.typed) name
the same things with the same parameters."""

import ast
import inspect
import os
import re

import nsf

PACKAGE_DIR = os.path.dirname(nsf.__file__)
# pybind11 puts the signature on a docstring's first line: "name(self: nsf._nsf.Scene) -> str".
SIGNATURE = re.compile(r"^\s*\w+\(.*\)( -> .*)?$")


def text_of(doc):
    """A docstring without pybind11's signature lines: what a person wrote."""
    lines = (doc or "").splitlines()
    return "\n".join(line for line in lines if not SIGNATURE.match(line)).strip()


def public_api():
    """(qualified name, object) of each exported function and class and of each public method and
    property a class defines."""
    for name in nsf.__all__:
        obj = getattr(nsf, name)
        if name.startswith("__"):
            continue
        yield "nsf." + name, obj
        if inspect.isclass(obj):
            for member, value in vars(obj).items():
                if not member.startswith("_"):
                    yield "nsf.%s.%s" % (name, member), value


def test_every_public_item_has_a_docstring():
    assert text_of(nsf.__doc__)
    items = dict(public_api())
    assert {"nsf.Rom.latent", "nsf.Rom.stress", "nsf.Rom.affine", "nsf.Rom.health",
            "nsf.Scene.rest_positions", "nsf.Run.frame_count"} <= set(items)
    missing = [name for name, obj in items.items() if not text_of(inspect.getdoc(obj) or obj.__doc__)]
    assert missing == []


def stub():
    path = os.path.join(PACKAGE_DIR, "__init__.pyi")
    assert os.path.isfile(path), "no type stubs shipped with the package"
    with open(path, encoding="utf-8") as f:
        return ast.parse(f.read(), path)


def parameters(node):
    a = node.args
    return [p.arg for p in a.posonlyargs + a.args + a.kwonlyargs]


def test_the_package_is_marked_typed():
    assert os.path.isfile(os.path.join(PACKAGE_DIR, "py.typed"))


def test_the_stubs_name_what_the_package_defines():
    tree = stub()
    functions = {n.name: n for n in tree.body if isinstance(n, ast.FunctionDef)}
    classes = {n.name: n for n in tree.body if isinstance(n, ast.ClassDef)}
    exported = {n for n in nsf.__all__ if not n.startswith("__")}
    assert set(functions) | set(classes) == exported
    for name, node in functions.items():
        assert parameters(node) == list(inspect.signature(getattr(nsf, name)).parameters), name
    for name, node in classes.items():
        cls = getattr(nsf, name)
        defined = {n.name: n for n in node.body if isinstance(n, ast.FunctionDef)}
        public = {m for m in vars(cls) if not m.startswith("_")}
        assert {m for m in defined if not m.startswith("_")} == public, name
        for member, fn in defined.items():
            value = vars(cls).get(member)
            if isinstance(value, property) or not inspect.isfunction(value):
                continue  # a property, or pybind11's (its signature is in its docstring)
            assert parameters(fn) == list(inspect.signature(value).parameters), \
                "%s.%s" % (name, member)
