"""The hand-written stub names exactly what the module has."""
import ast
import inspect
import os

import stridemap

STUB = os.path.join(os.path.dirname(stridemap.__file__), "__init__.pyi")
TYPING_HELPERS = {"PathLike", "ArrayLike", "PoseLike"}


def stub_tree():
    with open(STUB, encoding="utf-8") as f:
        return ast.parse(f.read())


def public(names):
    return {n for n in names if not n.startswith("_")}


def test_stub_names_the_module_attributes():
    tree = stub_tree()
    names = set()
    for node in tree.body:
        if isinstance(node, (ast.ClassDef, ast.FunctionDef)):
            names.add(node.name)
        elif isinstance(node, ast.AnnAssign):
            names.add(node.target.id)
        elif isinstance(node, ast.Assign):
            names.update(t.id for t in node.targets)
    assert public(names) - TYPING_HELPERS == set(stridemap.__all__)
    assert set(stridemap.__all__) == public(dir(stridemap)) - {"annotations"}


def test_stub_classes_name_the_class_attributes():
    for node in stub_tree().body:
        if not isinstance(node, ast.ClassDef) or issubclass(getattr(stridemap, node.name), Exception):
            continue
        declared = set()
        for item in node.body:
            if isinstance(item, ast.FunctionDef):
                declared.add(item.name)
            elif isinstance(item, ast.AnnAssign):
                declared.add(item.target.id)
        actual = {n for n in dir(getattr(stridemap, node.name)) if not n.startswith("_")}
        assert public(declared) == actual, node.name


def test_every_binding_has_a_docstring():
    for name in stridemap.__all__:
        obj = getattr(stridemap, name)
        assert obj.__doc__ and obj.__doc__.strip(), name
        if inspect.isclass(obj) and not issubclass(obj, Exception):
            for attr, member in vars(obj).items():
                # Data constants are described in the class docstring.
                if attr.startswith("_") or isinstance(member, (tuple, str, int, float)):
                    continue
                doc = getattr(member, "__doc__", None)
                assert doc and doc.strip(), f"{name}.{attr}"
