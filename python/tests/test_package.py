"""The package as shipped: the type stubs describe exactly what the
extension exports, and the PEP 561 marker is there."""

import ast
import pathlib

import rove


def stub_names():
    stub = pathlib.Path(rove.__file__).with_name("__init__.pyi")
    tree = ast.parse(stub.read_text())
    names = set()
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            names.add(node.name)
    return names, tree


def test_stubs_match_the_extension():
    names, tree = stub_names()
    public = {n for n in dir(rove._rove) if not n.startswith("__")}
    assert public - names == set(), "exported but not in __init__.pyi"
    assert {n for n in names if not n.startswith("_")} - public == set(), "stubbed but not exported"
    # Every stubbed class lists the public attributes the real class has.
    for node in tree.body:
        if isinstance(node, ast.ClassDef) and not node.name.startswith("_") and \
                not issubclass(getattr(rove, node.name), BaseException):
            stubbed = {n.name for n in node.body if isinstance(n, ast.FunctionDef)}
            stubbed |= {t.target.id for t in node.body if isinstance(t, ast.AnnAssign)}
            for base in node.bases:  # attributes stubbed on a private base
                for b in tree.body:
                    if isinstance(b, ast.ClassDef) and isinstance(base, ast.Name) and b.name == base.id:
                        stubbed |= {n.name for n in b.body if isinstance(n, ast.FunctionDef)}
                        stubbed |= {t.target.id for t in b.body if isinstance(t, ast.AnnAssign)}
            real = {n for n in vars(getattr(rove, node.name)) if not n.startswith("_")}
            assert real - stubbed == set(), node.name


def test_marker_and_exceptions():
    assert pathlib.Path(rove.__file__).with_name("py.typed").is_file()
    assert issubclass(rove.ParseError, ValueError) and issubclass(rove.ParseError, rove.Error)
    assert issubclass(rove.IoError, OSError) and issubclass(rove.ResourceError, OSError)
    assert issubclass(rove.InvalidArgument, ValueError)
    assert issubclass(rove.ConfigError, ValueError)


def test_batch_stubs_match_the_module():
    """rove.batch (pure Python) and batch.pyi: the same public names, and
    each function's parameters with the same names, kinds and defaults
    given or not."""
    import inspect
    from rove import batch
    stub = pathlib.Path(batch.__file__).with_name("batch.pyi")
    tree = ast.parse(stub.read_text())
    stubbed = {n.name: n for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
    assert set(stubbed) == set(batch.__all__)

    def params(fn_node):
        a = fn_node.args
        positional = a.posonlyargs + a.args
        defaults = [None] * (len(positional) - len(a.defaults)) + a.defaults
        out = [(p.arg, "POSITIONAL_OR_KEYWORD", d is not None) for p, d in zip(positional, defaults)]
        out += [(p.arg, "KEYWORD_ONLY", d is not None) for p, d in zip(a.kwonlyargs, a.kw_defaults)]
        return out

    def real(fn):
        return [(p.name, p.kind.name, p.default is not inspect.Parameter.empty)
                for p in inspect.signature(fn).parameters.values()]

    for name, node in stubbed.items():
        obj = getattr(batch, name)
        if isinstance(node, ast.FunctionDef):
            assert params(node) == real(obj), name
            continue
        methods = {n.name: n for n in node.body if isinstance(n, ast.FunctionDef)}
        public = {k for k, v in vars(obj).items() if not k.startswith("_") and
                  (callable(v) or isinstance(v, (property, classmethod, staticmethod)))}
        assert public <= set(methods), (name, public - set(methods))
        for m, fn_node in methods.items():
            member = vars(obj)[m]
            if isinstance(member, property):
                continue
            fn = member.__func__ if isinstance(member, (classmethod, staticmethod)) else member
            assert params(fn_node) == real(fn), (name, m)
