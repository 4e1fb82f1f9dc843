"""xnavlab.mars.kernels: how the kernels are compiled. Their arithmetic is tested through both
backends (the compiled kernel against the numpy loop) in tests/mars/test_scenarios.py."""

from numba.core.registry import CPUDispatcher

from xnavlab.mars import kernels


def _dispatchers():
    return {name: f for name, f in vars(kernels).items() if isinstance(f, CPUDispatcher)}


def test_no_fast_math_so_a_fresh_compile_and_the_cache_give_the_same_bits():
    # with fastmath={"contract"}, a process that compiled the kernels and one that loaded them
    # from numba's cache differed in the last digits (see the module docstring)
    found = _dispatchers()
    assert len(found) >= 30 and "run_epochs" in found
    for name, f in found.items():
        assert not f.targetoptions.get("fastmath"), f"{name} is compiled with fast-math"


def test_every_kernel_is_cached_on_disk():
    # the first call in a fresh environment compiles once; later processes load the code
    for name, f in _dispatchers().items():
        assert type(f._cache).__name__ == "FunctionCache", name
