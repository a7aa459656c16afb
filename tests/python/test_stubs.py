"""python/pellucid/_core.pyi agrees with the compiled module: it is what pybind11-stubgen writes
(tools/gen_stubs.py), and, checked independently of that tool, it has the same public names, the
same classes, methods and properties, and the parameter names of the pybind11 signatures in __doc__."""
from __future__ import annotations

import ast
import difflib
import importlib.util
import inspect
from typing import Dict, List

import pytest

import pellucid
from pellucid import _core

from conftest import ROOT

STUB = ROOT / "python" / "pellucid" / "_core.pyi"


def _stub(text: str = "") -> ast.Module:
    return ast.parse(text or STUB.read_text(), filename=str(STUB))


def _gen():
    """tools/gen_stubs.py as a module."""
    spec = importlib.util.spec_from_file_location("gen_stubs", ROOT / "tools" / "gen_stubs.py")
    gen = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(gen)
    return gen


def _split_top(s: str) -> List[str]:
    """Split a parameter list at commas outside brackets (pybind11 reprs of defaults use <...>)
    and quotes; the parts are stripped."""
    out, depth, cur, quote = [], 0, "", ""
    for ch in s:
        if quote:
            quote = "" if ch == quote else quote
        elif ch in "'\"":
            quote = ch
        elif ch in "([{<":
            depth += 1
        elif ch in ")]}>":
            depth -= 1
        elif ch == "," and depth == 0:
            out.append(cur.strip())
            cur = ""
            continue
        cur += ch
    if cur.strip():
        out.append(cur.strip())
    return out


def _doc_params(obj, name: str) -> List[str]:
    """Parameter names from pybind11's signature line ``name(a: int, b: str = 'x') -> T``."""
    doc = obj.__doc__ or ""
    first = doc.strip().splitlines()[0]
    assert first.startswith(name + "("), f"{name}: no pybind11 signature in __doc__: {first!r}"
    inner = first[len(name) + 1:first.rindex(") ->")]
    names = [p.split(":")[0].strip() for p in _split_top(inner)]
    return [n for n in names if n not in ("self", "*", "/") and n]


def _stub_params(fn: ast.FunctionDef) -> List[str]:
    a = fn.args
    names = [x.arg for x in a.posonlyargs + a.args + a.kwonlyargs]
    return [n for n in names if n not in ("self", "cls")]


def _public(names) -> set:
    return {n for n in names if not n.startswith("_")}


def test_stub_and_module_have_the_same_public_names() -> None:
    stub = _stub()
    stub_names = set()
    for node in stub.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            stub_names.add(node.name)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            stub_names.add(node.target.id)
        elif isinstance(node, ast.Assign):
            stub_names |= {t.id for t in node.targets if isinstance(t, ast.Name)}
    module_names = _public(dir(_core)) | {"__version__", "__all__"}
    assert stub_names - {"__version__", "__all__"} == _public(stub_names), "stub defines private names"
    assert module_names - stub_names == set(), "in _core, missing from the stub"
    assert stub_names - module_names == set(), "in the stub, not in _core"
    declared_all = next(ast.literal_eval(n.value) for n in stub.body
                        if isinstance(n, ast.AnnAssign) and getattr(n.target, "id", "") == "__all__")
    assert sorted(declared_all) == sorted(_public(dir(_core)))


def _functions(body) -> Dict[str, ast.FunctionDef]:
    return {n.name: n for n in body if isinstance(n, ast.FunctionDef)}


def _check_function_parameters(text: str = "") -> None:
    for name, fn in _functions(_stub(text).body).items():
        assert _stub_params(fn) == _doc_params(getattr(_core, name), name), name


def test_function_parameters_match_the_pybind11_signatures() -> None:
    _check_function_parameters()


def test_classes_methods_and_properties_match() -> None:
    for cls_node in (n for n in _stub().body if isinstance(n, ast.ClassDef)):
        cls = getattr(_core, cls_node.name)
        if issubclass(cls, BaseException):
            assert any(isinstance(b, ast.Name) and b.id == cls.__mro__[1].__name__ for b in cls_node.bases)
            continue
        methods = _functions(cls_node.body)
        props = {n for n, f in methods.items()
                 if any(isinstance(d, ast.Name) and d.id == "property" for d in f.decorator_list)}
        real_props = {n for n, v in vars(cls).items() if isinstance(v, property)}
        real_methods = {n for n, v in vars(cls).items()
                        if not isinstance(v, property) and callable(v)
                        and (not n.startswith("_") or (n == "__init__" and (v.__doc__ or "").startswith("__init__(")))}
        stub_methods = {n for n in methods if n not in props and (not n.startswith("_") or n == "__init__")}
        assert props == _public(real_props), cls_node.name
        assert stub_methods == real_methods, cls_node.name
        for n in stub_methods:
            doc_name = n
            assert _stub_params(methods[n]) == _doc_params(getattr(cls, n), doc_name), f"{cls_node.name}.{n}"


def test_the_check_is_not_vacuous() -> None:
    """A renamed parameter in the stub is caught."""
    text = STUB.read_text()
    assert "def load_file(path: str, lenient: bool = False, params" in text
    with pytest.raises(AssertionError, match="load_file"):
        _check_function_parameters(text.replace("def load_file(path: str, lenient", "def load_file(p: str, lenient"))


def test_committed_stub_is_what_the_generator_writes() -> None:
    """tools/gen_stubs.py regenerates the stub from the module with pybind11-stubgen; a difference
    means a binding changed without `python tools/gen_stubs.py`."""
    pytest.importorskip("pybind11_stubgen", reason="pybind11-stubgen is not installed (make installs it)")
    generated = _gen().generate()
    diff = "".join(difflib.unified_diff(STUB.read_text().splitlines(True), generated.splitlines(True),
                                        "committed", "generated"))
    assert not diff, "run `python tools/gen_stubs.py`:\n" + diff


def test_py_typed_marker_ships() -> None:
    assert (ROOT / "python" / "pellucid" / "py.typed").exists()
    assert inspect.ismodule(pellucid._core)
