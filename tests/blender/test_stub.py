"""The type stub (``python/pelt/_pelt.pyi``) against the compiled module: every public name, every
method and every parameter list agree, so an editor's completion and a type checker see the
module as it is. (TypedDicts exist only in the stub.)"""

import ast
import inspect
from pathlib import Path

import pelt._pelt as module

STUB = Path(__file__).resolve().parents[2] / "python" / "pelt" / "_pelt.pyi"


def parsed():
    return ast.parse(STUB.read_text())


def is_typed_dict(node) -> bool:
    return isinstance(node, ast.ClassDef) and any(ast.unparse(b) == "TypedDict" for b in node.bases)


def parameter_names(node: ast.FunctionDef) -> list[str]:
    a = node.args
    names = [x.arg for x in a.posonlyargs + a.args]
    names += [a.vararg.arg] if a.vararg else []
    names += [x.arg for x in a.kwonlyargs]
    names += [a.kwarg.arg] if a.kwarg else []
    return names


def runtime_names(obj) -> list[str]:
    return [p.name for p in inspect.signature(obj).parameters.values()]


def test_every_public_name_is_in_the_stub_and_every_stubbed_name_exists():
    stubbed = set()
    for node in parsed().body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)) and not is_typed_dict(node):
            stubbed.add(node.name)
        elif isinstance(node, ast.AnnAssign):
            stubbed.add(node.target.id)
    public = {name for name in dir(module) if not name.startswith("_") or name == "__version__"}
    assert public - stubbed == set(), "in the module, not in the stub"
    assert stubbed - public == set(), "in the stub, not in the module"


def test_functions_take_the_parameters_the_stub_gives():
    for node in parsed().body:
        if isinstance(node, ast.FunctionDef):
            assert runtime_names(getattr(module, node.name)) == parameter_names(node), node.name


def test_classes_have_the_methods_and_parameters_the_stub_gives():
    inherited = set(dir(BaseException)) | set(dir(object))
    for node in parsed().body:
        if not isinstance(node, ast.ClassDef) or is_typed_dict(node):
            continue
        cls = getattr(module, node.name)
        stubbed = {f.name for f in node.body if isinstance(f, ast.FunctionDef)}
        public = {name for name in dir(cls) if not name.startswith("_") and name not in inherited}
        assert public - stubbed == set(), f"{node.name}: in the class, not in the stub"
        for f in node.body:
            if not isinstance(f, ast.FunctionDef):
                continue
            assert hasattr(cls, f.name), f"{node.name}.{f.name} is stubbed but missing"
            if any(ast.unparse(d) in ("property", "staticmethod") or ast.unparse(d).endswith(".setter")
                   for d in f.decorator_list):  # fmt: skip
                continue
            stub_names = parameter_names(f)[1:]  # without self (or cls)
            if f.name == "__init__":
                assert runtime_names(cls) == stub_names, f"{node.name}()"
            elif not f.name.startswith("__"):
                runtime = runtime_names(getattr(cls, f.name))
                if runtime and runtime[0] in ("self", "cls", "$self", "$cls"):
                    runtime = runtime[1:]
                assert runtime == stub_names, f"{node.name}.{f.name}"
