"""The compiled kernels' disk cache stays correct: numba checks only the file a cached kernel is
defined in, so a cached kernel that called a kernel defined in another file would keep that
file's old code after it changed (seen: stale kernels failing with "NRT_adapt_ndarray_to_python:
descr is NULL"). Every cached kernel of the project may call only kernels of its own file."""

import importlib
import pkgutil
from pathlib import Path

from numba.core.registry import CPUDispatcher

PACKAGES = ("centroidal", "robots", "estimators", "planners", "stabilizers", "wholebody", "sims")


def project_kernels():
    root = Path(__file__).resolve().parents[2]
    for package in PACKAGES:
        for info in pkgutil.iter_modules([str(root / package)]):
            module = importlib.import_module(f"{package}.{info.name}")
            for value in vars(module).values():
                if isinstance(value, CPUDispatcher) and value.py_func.__module__ == module.__name__:
                    yield module, value


def called_kernels(kernel: CPUDispatcher):
    names = kernel.py_func.__code__.co_names
    for name in names:
        value = kernel.py_func.__globals__.get(name)
        if isinstance(value, CPUDispatcher):
            yield value


def test_cached_kernels_call_only_kernels_of_their_own_file():
    kernels = list(project_kernels())
    assert len(kernels) >= 10  # the check sees the project's kernels
    calls_seen = 0
    for module, kernel in kernels:
        assert kernel._cache.__class__.__name__ != "NullCache", kernel  # all cached on disk
        for callee in called_kernels(kernel):
            calls_seen += 1
            assert callee.py_func.__module__ == module.__name__, (
                f"{module.__name__}.{kernel.__name__} calls {callee.py_func.__module__}."
                f"{callee.__name__}: move one next to the other"
            )
    assert calls_seen >= 5  # kernels do call kernels (of their own file)
