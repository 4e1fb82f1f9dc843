"""xnavlab.mars.kernel.kernels and the modules it is made of: how they are compiled and how they read
their arguments. Their arithmetic is tested through both backends (the compiled kernel against
the numpy loop) in tests/mars/navigation/test_scenarios.py, and step by step in the test module of each."""

import ast
import importlib
from pathlib import Path

from numba.core.registry import CPUDispatcher

from xnavlab.mars.kernel import kernel_compile, kernels

PACKAGE = Path(kernels.__file__).resolve().parents[2]
#: the modules that compile with kernel_compile.jit (the other sources are read, not compiled)
KERNEL_MODULES = [rel for rel in kernel_compile.SOURCES
                  if "jit(" in (PACKAGE / rel).read_text() and rel != "mars/kernel/kernel_compile.py"]


def _dispatchers():
    found = {}
    for rel in KERNEL_MODULES:
        module = importlib.import_module("xnavlab." + rel[:-3].replace("/", "."))
        found.update({f"{module.__name__}.{name}": f for name, f in vars(module).items()
                      if isinstance(f, CPUDispatcher) and f.__module__ == module.__name__})
    return found


def test_no_fast_math_so_a_fresh_compile_and_the_cache_give_the_same_bits():
    # with fastmath={"contract"}, a process that compiled the kernels and one that loaded them
    # from numba's cache differed in the last digits (see kernel_compile's docstring)
    found = _dispatchers()
    assert len(found) >= 30 and "xnavlab.mars.kernel.kernels.run_epochs" in found
    for name, f in found.items():
        assert not f.targetoptions.get("fastmath"), f"{name} is compiled with fast-math"


def test_every_kernel_is_cached_on_disk_under_the_digest_of_all_their_sources():
    # the first call in a fresh environment compiles once; later processes load the code, as
    # long as no source of the kernel changed (a helper's change recompiles its callers)
    stamp = ("xnavlab kernel sources", kernel_compile.sources_digest())
    for name, f in _dispatchers().items():
        assert isinstance(f._cache, kernel_compile.SourcesCache), name
        assert f._cache._cache_file._source_stamp == stamp, name


def _functions():
    for rel in KERNEL_MODULES:
        tree = ast.parse((PACKAGE / rel).read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.FunctionDef):
                yield rel, node


def test_the_kernel_unpacks_no_tuple_by_position():
    """``a, b = tup`` reads fields by their order: the kernel reads them by name
    (``a, b = tup.a, tup.b`` is fine, and so is a helper's returned pair)."""
    bad = []
    for rel, fn in _functions():
        for node in ast.walk(fn):
            targets = node.targets if isinstance(node, ast.Assign) else []
            if any(isinstance(t, ast.Tuple) for t in targets) and \
                    isinstance(node.value, (ast.Name, ast.Attribute, ast.Subscript)):
                bad.append(f"{rel}:{node.lineno} ({fn.name})")
    assert not bad, "\n".join(bad)


def test_every_helper_takes_few_arguments():
    # the entry point's eight are the containers of kernel_inputs plus the epoch span
    long = [f"{rel}:{fn.lineno} {fn.name} ({len(fn.args.args)})" for rel, fn in _functions()
            if len(fn.args.args) > 8]
    assert not long, "\n".join(long)
