"""Where a sweep's episodes run: a local process pool (default, workers = cores) or Ray.

Both run `fn(item)` for every item and yield `(item, result)` as items finish, in completion
order; `result` is the exception when the call raised or its worker died. Neither stops at a
failed item.

Local pool: at most `workers` episodes are in flight, each in a fresh simulator inside a
long-lived worker process (spawned, so no simulator or BLAS state is inherited). When a worker
dies (killed, or a crash in a simulator's C code) the pool breaks and every in-flight episode
with it; those are run again one at a time, so that the one that kills its worker is found
and recorded as an error, and the others complete.

Ray: `ray.init(address)` (None: a local instance with `workers` CPUs); each episode is a task
with one CPU, retried once if its worker dies, then recorded as an error.
"""

from __future__ import annotations

import multiprocessing
import os
from collections import deque
from collections.abc import Callable, Iterable, Iterator
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from typing import Any, Protocol

EXECUTORS = ("local", "ray")


class WorkerDied(RuntimeError):
    """The process running an episode ended without returning (killed or crashed)."""


class Executor(Protocol):
    def map_unordered(
        self, fn: Callable[[Any], Any], items: Iterable[Any]
    ) -> Iterator[tuple[Any, Any]]: ...

    def close(self) -> None: ...


_THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")


class LocalExecutor:
    def __init__(self, workers: int | None = None) -> None:
        if workers is not None and workers < 1:
            raise ValueError(f"workers must be >= 1, got {workers}")
        self.workers = workers or os.cpu_count() or 1
        self._pool: ProcessPoolExecutor | None = None

    def _new_pool(self) -> ProcessPoolExecutor:
        # One BLAS / OpenMP thread per worker: the pool already uses every core, and the
        # episodes' small matrix products lose more to oversubscribed threads than they gain
        # (measured: 5-10 % faster per episode with 2 workers on 2 cores). The workers inherit
        # this process's environment; a value the user set is kept.
        for variable in _THREAD_VARIABLES:
            os.environ.setdefault(variable, "1")
        return ProcessPoolExecutor(self.workers, mp_context=multiprocessing.get_context("spawn"))

    def map_unordered(
        self, fn: Callable[[Any], Any], items: Iterable[Any]
    ) -> Iterator[tuple[Any, Any]]:
        pending = deque(items)
        suspects: deque = deque()  # in flight when a worker died: rerun one at a time
        retried: set[int] = set()  # ids of suspects that already died once on their own
        self._pool = self._new_pool()
        try:
            in_flight: dict[Future, Any] = {}
            while pending or suspects or in_flight:
                limit = 1 if suspects else self.workers
                source = suspects if suspects else pending
                while source and len(in_flight) < limit:
                    item = source.popleft()
                    in_flight[self._pool.submit(fn, item)] = item
                done, _ = wait(in_flight, return_when=FIRST_COMPLETED)
                broken = []
                for future in done:
                    item = in_flight.pop(future)
                    try:
                        yield item, future.result()
                    except BrokenProcessPool:
                        broken.append(item)
                    except Exception as exc:
                        yield item, exc
                if broken:
                    broken.extend(in_flight.values())  # the rest of that pool's work died too
                    in_flight.clear()
                    self._pool.shutdown(wait=False, cancel_futures=True)
                    self._pool = self._new_pool()
                    if limit == 1 and id(broken[0]) in retried:  # died twice, alone
                        yield broken[0], WorkerDied("the worker process died during this episode")
                    elif limit == 1:
                        retried.add(id(broken[0]))
                        suspects.appendleft(broken[0])
                    else:
                        suspects.extend(broken)
        finally:
            self.close()

    def close(self) -> None:
        if self._pool is not None:
            _terminate(self._pool)
            self._pool = None


def _terminate(pool: ProcessPoolExecutor) -> None:
    """Stop a pool now, killing running workers (for Ctrl-C and for broken pools)."""
    processes = list((getattr(pool, "_processes", None) or {}).values())
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        if process.is_alive():
            process.terminate()
    for process in processes:
        process.join(timeout=5)


class RayExecutor:
    def __init__(self, address: str | None = None, workers: int | None = None) -> None:
        try:
            import ray
        except ImportError:
            raise ImportError(
                "the Ray executor needs Ray: pip install -c constraints.txt -e '.[ray]'"
            ) from None
        self.ray = ray
        self._started = False
        if not ray.is_initialized():
            options: dict[str, Any] = {"include_dashboard": False, "log_to_driver": False}
            if address is None:
                options["num_cpus"] = workers or os.cpu_count() or 1
            ray.init(address=address, **options)
            self._started = True
        self.window = 4 * int(ray.cluster_resources().get("CPU", 1))

    def map_unordered(
        self, fn: Callable[[Any], Any], items: Iterable[Any]
    ) -> Iterator[tuple[Any, Any]]:
        ray = self.ray
        remote = ray.remote(num_cpus=1, max_retries=1)(fn)
        pending = deque(items)
        in_flight: dict[Any, Any] = {}
        while pending or in_flight:
            while pending and len(in_flight) < self.window:
                item = pending.popleft()
                in_flight[remote.remote(item)] = item
            ready, _ = ray.wait(list(in_flight), num_returns=1)
            for reference in ready:
                item = in_flight.pop(reference)
                try:
                    yield item, ray.get(reference)
                except ray.exceptions.WorkerCrashedError as exc:
                    yield item, WorkerDied(f"the Ray worker died during this episode: {exc}")
                except Exception as exc:
                    yield item, exc

    def close(self) -> None:
        if self._started:
            self.ray.shutdown()
            self._started = False


def make_executor(name: str, workers: int | None = None, address: str | None = None) -> Executor:
    if name == "local":
        if address is not None:
            raise ValueError("--address is for the ray executor")
        return LocalExecutor(workers)
    if name == "ray":
        return RayExecutor(address, workers)
    raise ValueError(f"unknown executor {name!r}; choose one of: {', '.join(EXECUTORS)}")
