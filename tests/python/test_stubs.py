"""python/pbd.pyi against the module: the same names, and for every public function and method (and __init__) a
signature that inspect can read, with the same parameters (names, kinds, defaults) as the stub, every one typed.
The stubs are the copy beside the module (python/CMakeLists.txt puts it there, as the packages install it)."""
import ast
import inspect
import pathlib
import types

import pytest

import pbd

STUB = pathlib.Path(pbd.__file__).resolve().parent / "pbd.pyi"
TREE = ast.parse(STUB.read_text())
ENUMS = {"StiffnessMode", "Solver", "SweepOrder"}


def public(name):
    return not name.startswith("_")


def stub_names(body):
    """{name: node} of a module's or class's body: defs, classes and annotated attributes."""
    out = {}
    for node in body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            out[node.name] = node
        elif isinstance(node, ast.AnnAssign):
            out[node.target.id] = node
    return out


MODULE_STUBS = stub_names(TREE.body)


def class_members(name):
    """{name: node} of a stub class with those of its bases defined in the stubs (World and WorldDouble share _World)."""
    node = MODULE_STUBS[name]
    out = {}
    for base in node.bases:
        if isinstance(base, ast.Name) and base.id in MODULE_STUBS:
            out.update(class_members(base.id))
    out.update(stub_names(node.body))
    return out


def runtime_functions():
    """(qualified name, runtime callable, stub def) of every public function and method, and each class's __init__."""
    out = []
    for name, obj in vars(pbd).items():
        if not public(name):
            continue
        if inspect.isclass(obj):
            if name in ENUMS or issubclass(obj, BaseException):
                continue
            members = class_members(name)
            for attr, member in vars(obj).items():
                if isinstance(member, (property, types.WrapperDescriptorType)) or not (public(attr) or attr == "__init__"):
                    continue  # properties; a class without a constructor (its __init__ is CPython's slot)
                if callable(getattr(obj, attr)):
                    out.append((f"{name}.{attr}", getattr(obj, attr), members.get(attr)))
        elif callable(obj):
            out.append((name, obj, MODULE_STUBS.get(name)))
    return out


FUNCTIONS = runtime_functions()


def test_the_stubs_name_what_the_module_has():
    assert sorted(n for n in vars(pbd) if public(n)) == sorted(n for n in MODULE_STUBS if public(n))
    for name, obj in vars(pbd).items():
        if public(name) and inspect.isclass(obj) and not issubclass(obj, BaseException):
            runtime = sorted(n for n in vars(obj) if public(n))
            assert runtime == sorted(n for n in class_members(name) if public(n)), name


@pytest.mark.parametrize("name, runtime, stub", FUNCTIONS, ids=[f[0] for f in FUNCTIONS])
def test_signature_matches_the_stub(name, runtime, stub):
    signature = inspect.signature(runtime)  # raises when the docstring has no text signature
    assert stub is not None, f"{name} has no stub"
    args = stub.args
    stub_params = [(a.arg, "POSITIONAL_ONLY") for a in args.posonlyargs]
    stub_params += [(a.arg, "POSITIONAL_OR_KEYWORD") for a in args.args]
    stub_params += [(a.arg, "KEYWORD_ONLY") for a in args.kwonlyargs]
    defaults = [None] * (len(args.posonlyargs) + len(args.args) - len(args.defaults)) + list(args.defaults)
    defaults += list(args.kw_defaults)
    is_method = "." in name and not any(isinstance(d, ast.Name) and d.id == "staticmethod" for d in stub.decorator_list)
    runtime_params = [(p.name, p.kind.name, p.default) for p in signature.parameters.values()]
    if is_method:  # self: positional-only on both sides
        assert stub_params[0] == ("self", "POSITIONAL_ONLY") and runtime_params[0][:2] == stub_params[0], name
        stub_params, defaults, runtime_params = stub_params[1:], defaults[1:], runtime_params[1:]
    assert [(n, k) for n, k, _ in runtime_params] == stub_params, name
    stub_args = (args.posonlyargs + args.args)[1 if is_method else 0:] + args.kwonlyargs
    for (param, _, value), default, arg in zip(runtime_params, defaults, stub_args):
        assert arg.annotation is not None, f"{name}: {param} has no type"
        if default is None:
            assert value is inspect.Parameter.empty, f"{name}: {param} has a default at runtime only"
        elif not (isinstance(default, ast.Constant) and default.value is Ellipsis):
            assert value == ast.literal_eval(default), f"{name}: {param} defaults differ"
    assert stub.returns is not None, f"{name} has no return type"


def test_bound_methods_have_the_signature_without_self():
    w = pbd.World()
    assert str(inspect.signature(w.add_particle)) == "(position, mass, velocity=None)"
    assert str(inspect.signature(w.step)) == "(forces=None)"
    assert str(inspect.signature(pbd.Stiffness.pbd_k)) == "(k)"  # static


def test_an_overload_for_both_precisions_has_one_signature_and_docstring():
    assert str(inspect.signature(pbd.energy)) == "(world)"
    assert pbd.energy.__doc__.startswith("Kinetic") and "energy(world)" not in pbd.energy.__doc__


def test_signatures_carry_the_docstring():
    assert inspect.signature(pbd.World.step).parameters["forces"].default is None
    assert pbd.World.step.__doc__.startswith("Advances the world")
    assert str(inspect.signature(pbd.Material.__init__)) == (
        "(self, /, stiffness, toe_strain=0.0, yield_strain=inf, hardening=0.0, rupture_strain=inf)")
