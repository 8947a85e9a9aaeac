"""The type stubs (python/gyrosid/_gyrosid.pyi) against the extension itself: the same names, and for every function
and method the same parameters in the same order as the signature pybind11 writes into its docstring; every public
name documented. A binding added or changed without its stub fails here."""
import ast
import os
import re
import unittest

import gyrosid
from gyrosid import _gyrosid

STUB = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "gyrosid", "_gyrosid.pyi")
DUNDERS_BOUND = {"__init__", "__len__", "__getitem__"}


def split_top_level(text):
    """Split at commas outside brackets and quotes."""
    parts, depth, quote, start = [], 0, None, 0
    for i, c in enumerate(text):
        if quote:
            quote = None if c == quote else quote
        elif c in "'\"":
            quote = c
        elif c in "([{":
            depth += 1
        elif c in ")]}":
            depth -= 1
        elif c == "," and depth == 0:
            parts.append(text[start:i])
            start = i + 1
    parts.append(text[start:])
    return [p.strip() for p in parts if p.strip()]


def pybind_parameters(obj):
    """Parameter names from the signature line pybind11 puts first in a docstring (self left out)."""
    first = obj.__doc__.strip().splitlines()[0]
    match = re.match(r"^\w+\((.*)\) -> ", first)
    if not match:
        raise AssertionError("no signature in the docstring of %r: %s" % (obj, first))
    names = [p.split(":")[0].split("=")[0].strip() for p in split_top_level(match.group(1))]
    return [n for n in names if n != "self"]


def stub_parameters(node):
    return [a.arg for a in node.args.args if a.arg != "self"] + [a.arg for a in node.args.kwonlyargs]


def stub_tree():
    with open(STUB) as f:
        return ast.parse(f.read())


class Stubs(unittest.TestCase):
    def test_every_function_has_the_modules_parameters(self):
        functions = [n for n in stub_tree().body if isinstance(n, ast.FunctionDef)]
        self.assertGreater(len(functions), 5)
        for node in functions:
            with self.subTest(function=node.name):
                self.assertEqual(stub_parameters(node), pybind_parameters(getattr(_gyrosid, node.name)))

    def test_every_class_has_the_modules_members(self):
        classes = [n for n in stub_tree().body if isinstance(n, ast.ClassDef)]
        for node in classes:
            cls = getattr(_gyrosid, node.name)
            members = [m for m in node.body if isinstance(m, ast.FunctionDef)]
            stubbed = {m.name for m in members}
            public = {n for n in vars(cls) if not n.startswith("_") or n in DUNDERS_BOUND}
            if not (getattr(cls.__init__, "__doc__", "") or "").startswith("__init__("):
                public.discard("__init__")  # no constructor bound: pybind11's placeholder refuses construction
            if node.name != "Error":
                self.assertEqual(stubbed, public, node.name)
            for m in members:
                attribute = getattr(cls, m.name)
                if isinstance(attribute, property) or m.name == "__init__" and node.name == "Error":
                    continue
                with self.subTest(member="%s.%s" % (node.name, m.name)):
                    self.assertEqual(stub_parameters(m), pybind_parameters(attribute))

    def test_the_stub_names_everything_the_module_exports(self):
        stubbed = {n.name for n in stub_tree().body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
        exported = {n for n in dir(_gyrosid) if not n.startswith("_")}
        self.assertEqual(exported, stubbed)
        self.assertLessEqual(set(gyrosid.__all__), stubbed)

    def test_every_public_name_has_a_docstring(self):
        for name in gyrosid.__all__:
            obj = getattr(gyrosid, name)
            lines = (obj.__doc__ or "").strip().splitlines()
            # pybind11 writes the signature first; the description follows it.
            described = [line for line in lines if line.strip() and not re.match(r"^\w+\(.*\) -> ", line)]
            with self.subTest(name=name):
                self.assertTrue(described, "%s has no docstring beyond its signature" % name)
            if isinstance(obj, type) and name != "Error":
                for member, attribute in vars(obj).items():
                    if member.startswith("_"):
                        continue
                    doc = attribute.__doc__ if not isinstance(attribute, property) else attribute.fget.__doc__
                    text = [line for line in (doc or "").strip().splitlines() if line.strip() and not re.match(r"^\w+\(.*\) -> ", line)]
                    with self.subTest(member="%s.%s" % (name, member)):
                        self.assertTrue(text, "%s.%s has no docstring" % (name, member))


if __name__ == "__main__":
    unittest.main()
