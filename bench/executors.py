"""Where a sweep's episodes run: local worker processes (default, one per core) or Ray.

Both run `fn(item)` for every item and yield `(item, result)` as items finish, in completion
order; `result` is the exception when the call raised (`WorkerDied` when its worker process
died, `EpisodeTimeout` when it overran its wall-clock budget). Neither stops at a failed item.

Local workers: long-lived processes (spawned, so no simulator or BLAS state is inherited),
each running one item at a time, sent over its own pipe. The parent knows which item every
worker runs, so

- a worker that dies (killed, or a crash in a simulator's C code) takes only its own item with
  it: that item is run once more in a fresh worker (something outside may have killed it) and
  recorded as `WorkerDied` if its worker dies again; Python's fault handler writes where the
  crash happened, and the message says so;
- an item that overruns its budget (`budget(item)` seconds of wall-clock time) is ended by the
  parent: it reads the stage and simulated time that the episode publishes in shared memory
  (`worker_progress`), asks the worker for its Python stack (SIGUSR1, answered by the fault
  handler's C-level signal handler even inside a C call that holds the GIL), kills it and
  yields `EpisodeTimeout`. Nothing a worker runs can block the sweep: a solver without an
  iteration limit of its own (quadprog) is bounded by this;
- a worker exits when the parent dies, however it dies (SIGKILL included): on Linux the kernel
  sends it SIGKILL (prctl PR_SET_PDEATHSIG), elsewhere a watcher thread polls the parent's
  pid; an idle worker also exits when its pipe closes. Workers ignore SIGINT, so Ctrl-C reaches
  the parent only, which stops every worker before it returns.

Ray: `ray.init(address)` (None: a local instance with `workers` CPUs); each item is a task
with one CPU, retried once if its worker dies, then recorded as `WorkerDied`. At most one task
per CPU is in flight, so that a task's budget is counted from its submission; a task past its
budget is cancelled (`ray.cancel(force=True)`, which kills its worker) and recorded as
`EpisodeTimeout` without a stage (the driver cannot see inside a running task). Ray's own
processes share the fate of the driver that started them.
"""

from __future__ import annotations

import contextlib
import ctypes
import faulthandler
import math
import multiprocessing
import os
import re
import shutil
import signal
import socket
import sys
import tempfile
import threading
import time
from collections import deque
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from multiprocessing.connection import Connection, wait
from pathlib import Path
from typing import Any, Protocol

EXECUTORS = ("local", "ray")
STACK_WAIT_S = 1.0  # how long a timed-out worker gets to write its stack before it is killed
ADDRESS_TIMEOUT_S = 5.0  # how long `check_ray_address` waits for a TCP connection


class WorkerDied(RuntimeError):
    """The process running an episode ended without returning (killed or crashed)."""


class EpisodeTimeout(RuntimeError):
    """An episode overran its wall-clock budget and was ended."""

    def __init__(
        self,
        budget_s: float,
        stage: str | None = None,
        sim_time_s: float | None = None,
        location: str | None = None,
    ) -> None:
        self.budget_s, self.stage, self.sim_time_s, self.location = (
            budget_s,
            stage,
            sim_time_s,
            location,
        )
        where = "in an unknown stage" if stage is None else f"in the {stage} stage"
        if sim_time_s is not None:
            where += f" at t = {sim_time_s:.3f} s"
        if location:
            where += f" ({location})"
        super().__init__(f"no result within the wall-clock budget of {budget_s:.0f} s: {where}")

    def __reduce__(self):
        """Pickle by the constructor's arguments, not the message: a branched episode's timeout
        crosses a process boundary inside its pool worker's result, and the default (the
        class called with the message) put the message where the budget goes and failed to
        unpickle, which ended the whole sweep (found 2026-11-27 with the hierarchy's walking
        pushes: 20 rows lost and "Unknown format code 'f'")."""
        return (type(self), (self.budget_s, self.stage, self.sim_time_s, self.location))


class Executor(Protocol):
    def map_unordered(
        self,
        fn: Callable[[Any], Any],
        items: Iterable[Any],
        budget: Callable[[Any], float] | None = None,
    ) -> Iterator[tuple[Any, Any]]:
        """(item, fn(item) or the exception in its place) for every item, as they end.
        `budget(item)`: its wall-clock budget [s]. `items` given as a `collections.deque` is
        read as work is handed out: items the caller appends to it while it consumes results
        are run too (a search whose next walk depends on the last, `bench.speed_protocol`)."""
        ...

    def close(self) -> None: ...


# ------------------------------------------------------------------------------- workers

_THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")
_progress: Any = None  # this worker's shared [stage code, simulated time], if it is one


@contextlib.contextmanager
def single_threaded_workers() -> Iterator[None]:
    """One BLAS / OpenMP thread per worker process started inside this context (they inherit
    this process's environment, which is restored on leaving; a value the user set is kept):
    a pool already uses every core, and the episodes' small matrix products lose more to
    oversubscribed threads than they gain (measured: 5-10 % faster per episode with 2 workers
    on 2 cores; the linear MPC's p99 update on Murooka's (B) 114 ms with two threads per
    worker against 5 ms with one)."""
    before = {variable: os.environ.get(variable) for variable in _THREAD_VARIABLES}
    for variable in _THREAD_VARIABLES:
        os.environ.setdefault(variable, "1")
    try:
        yield
    finally:
        for variable, value in before.items():
            if value is None:
                os.environ.pop(variable, None)
            else:
                os.environ[variable] = value


def worker_progress() -> Any:
    """The shared-memory progress slot of this worker process (None outside a worker): what
    `bench.runner.run_episode` writes its stage and simulated time into."""
    return _progress


SPLIT_SLOT = 2
"""The progress slot's index that a branched group sets to 1 when it has split
(`bench.branching.Brancher.split`): from then on its worker is held to the group's budget."""


def progress_stage(code: float) -> str:
    """The name of a stage code written by `bench.runner.run_episode`."""
    from bench.runner import PROGRESS_STAGES

    index = int(code)
    return PROGRESS_STAGES[index] if 0 <= index < len(PROGRESS_STAGES) else "unknown"


PR_SET_PDEATHSIG, PR_GET_PDEATHSIG = 1, 2  # linux/prctl.h


def parent_death_signal() -> int:
    """The signal this process gets when its parent dies (Linux prctl PR_GET_PDEATHSIG; 0:
    none, or not Linux)."""
    if not sys.platform.startswith("linux"):
        return 0
    value = ctypes.c_int(0)
    ctypes.CDLL(None, use_errno=True).prctl(PR_GET_PDEATHSIG, ctypes.byref(value), 0, 0, 0)
    return value.value


def _die_with_parent(parent_pid: int) -> None:
    """Make this process end when its parent does (see the module docstring): SIGKILL from
    the kernel on Linux (it works while the worker hangs in C code holding the GIL), and a
    watcher thread everywhere (which needs the GIL)."""
    if sys.platform.startswith("linux"):
        libc = ctypes.CDLL(None, use_errno=True)
        if libc.prctl(PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0) != 0:
            error = ctypes.get_errno()
            print(
                f"centrobench worker: prctl(PR_SET_PDEATHSIG) failed: {os.strerror(error)}",
                file=sys.stderr,
            )

    def watch() -> None:
        # the parent's SIGUSR1 asks the main thread for its stack: never this thread
        signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGUSR1})
        while os.getppid() == parent_pid:
            time.sleep(1.0)
        os._exit(1)

    if os.getppid() != parent_pid:  # the parent died before prctl took effect
        os._exit(1)
    threading.Thread(target=watch, name="parent-watch", daemon=True).start()


def _worker_main(
    fn: Callable[[Any], Any], conn: Connection, progress: Any, stack_path: str, parent_pid: int
) -> None:
    """A worker's loop: receive (task id, item), send (task id, ok, result or exception)."""
    global _progress
    _die_with_parent(parent_pid)
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's to handle
    with contextlib.suppress(Exception):
        import resource

        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))  # a crash leaves no core file
    # the worker's stderr (Python's and C libraries') goes to a file beside its stack: a
    # sweep's command line shows its own lines only; a worker that dies has its last line
    # quoted in the episode's error row (`_Worker.last_words`)
    log = os.open(stack_path + ".stderr", os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
    os.dup2(log, 2)
    os.close(log)
    stack_file = open(stack_path, "w")  # noqa: SIM115 - open for the worker's lifetime
    faulthandler.enable(stack_file)  # crashes (SIGSEGV, SIGABRT, ...) write their stack
    faulthandler.register(signal.SIGUSR1, stack_file, all_threads=False)  # the parent asks
    _progress = progress
    try:
        conn.send(None)  # ready: imports done, so that they do not count against a budget
    except OSError:  # the parent stopped listening (it is closing): leave quietly
        return
    while True:
        try:
            message = conn.recv()
        except (EOFError, OSError):
            return
        if message is None:
            return
        task_id, item = message
        try:
            reply = (task_id, True, fn(item))
        except BaseException as exc:
            reply = (task_id, False, exc)
        try:
            conn.send(reply)
        except OSError:  # the parent stopped listening (it is closing): leave quietly
            return
        except Exception as exc:  # a result or exception that does not pickle
            try:
                conn.send((task_id, False, RuntimeError(f"{type(exc).__name__}: {exc}")))
            except OSError:
                return


@dataclass
class _Task:
    item: Any
    budget_s: float
    attempts: int = 0
    before_split_s: float = math.inf
    """[s] the budget until the worker's progress slot says its group has split (`SPLIT_SLOT`):
    an item that runs a shared part first (`split_budget_s`, a branched group) is held to one
    episode's budget for it, not to the sum of its episodes'."""

    def budget_now(self, progress: Any) -> float:
        """The budget [s] that holds now: `before_split_s` until the split, then `budget_s`."""
        return self.budget_s if progress[SPLIT_SLOT] else min(self.before_split_s, self.budget_s)


class _Worker:
    """One worker process, its pipe, its progress slot and its stack file."""

    def __init__(self, context, fn: Callable[[Any], Any], folder: Path, number: int) -> None:
        self.conn, child = context.Pipe()
        self.progress = context.RawArray("d", 3)  # stage, simulated time, split done
        self.stack_path = folder / f"worker-{number}.stack"
        self.process = context.Process(
            target=_worker_main,
            args=(fn, child, self.progress, str(self.stack_path), os.getpid()),
            name=f"centrobench-worker-{number}",
            daemon=True,
        )
        # Ctrl-C reaches the whole process group: the worker ignores SIGINT from its first
        # instruction (an ignored signal stays ignored across exec), so that none prints a
        # KeyboardInterrupt while it imports; the parent alone handles it
        try:
            previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
        except ValueError:  # not the main thread: signals are the main thread's
            previous = None
        try:
            self.process.start()
        finally:
            if previous is not None:
                signal.signal(signal.SIGINT, previous)
        child.close()
        self.ready = False  # the worker has said it is ready (its imports are done)
        self.started_up = False  # it has said so once: a death after that is not a start-up's
        self.task: _Task | None = None
        self.task_id = -1
        self.started = 0.0
        self.stack_offset = 0  # [bytes] where the current task's part of the stack file starts

    def send(self, task: _Task, task_id: int) -> bool:
        """Give the worker `task`; False if its pipe is broken (it died while idle). The
        progress slot is cleared before the task goes out: the worker may write it at once."""
        self.progress[0] = self.progress[1] = self.progress[SPLIT_SLOT] = 0.0
        self.stack_offset = self.stack_size()  # what earlier tasks wrote is not this one's
        try:
            self.conn.send((task_id, task.item))
        except OSError:  # BrokenPipeError, ConnectionResetError
            return False
        self.task, self.task_id, self.started = task, task_id, time.monotonic()
        task.attempts += 1
        return True

    def stack_size(self) -> int:
        """[bytes] of the stack file so far (0 before the worker made it)."""
        with contextlib.suppress(OSError):
            return self.stack_path.stat().st_size
        return 0

    def stack(self, since: int | None = None) -> str:
        """The stack file from byte `since` (default: the current task's start) on: the fault
        handler's dumps of this task (a crash, or the parent's SIGUSR1), and those of branch
        processes forked in it, which inherit the file."""
        offset = self.stack_offset if since is None else since
        with contextlib.suppress(OSError), self.stack_path.open("rb") as file:
            file.seek(offset)
            return file.read().decode(errors="replace")
        return ""

    def last_words(self) -> str | None:
        """The last line the worker wrote to its stderr, if any."""
        with contextlib.suppress(OSError):
            lines = Path(f"{self.stack_path}.stderr").read_text(errors="replace").split("\n")
            lines = [line.strip() for line in lines if line.strip()]
            return lines[-1][:300] if lines else None
        return None

    def kill(self) -> None:
        """Kill the worker, then close its pipe (in that order: a worker that finished just
        now must not find its pipe closed while it still runs)."""
        if self.process.is_alive():
            self.process.kill()
        self.process.join(timeout=5)
        with contextlib.suppress(OSError):
            self.conn.close()

    def exit_description(self) -> str:
        code = self.process.exitcode
        if code is None:
            return "did not exit"
        if code < 0:
            with contextlib.suppress(ValueError):
                return f"was killed by {signal.Signals(-code).name}"
            return f"was killed by signal {-code}"
        return f"exited with status {code}"


_FRAME = re.compile(r'File "(?P<file>[^"]+)", line (?P<line>\d+) in (?P<function>\S+)')


def stack_location(text: str) -> str | None:
    """Where a fault-handler stack was: its innermost frame in the project's own files (as
    "folder/file.py:line in function"), else its innermost frame; None without frames. Of
    several dumps in `text` (a branch's crash, then the worker's own), the last."""
    root = Path(__file__).resolve().parents[1]
    innermost = None
    # each dump opens with its own thread's stack ("Current thread ..." for a crash, "Stack
    # (...)" for SIGUSR1), the other threads' after it
    header = max(text.rfind("Current thread "), text.rfind("Stack (most recent call first)"))
    if header >= 0:
        text = text[header:]
    for match in _FRAME.finditer(text):  # most recent call first
        path = Path(match["file"]).resolve()
        where = f"{path}:{match['line']} in {match['function']}"
        innermost = innermost or where
        if path.is_relative_to(root) and ".venv" not in path.relative_to(root).parts:
            return f"{path.relative_to(root)}:{match['line']} in {match['function']}"
    return innermost


class LocalExecutor:
    def __init__(self, workers: int | None = None) -> None:
        if workers is not None and workers < 1:
            raise ValueError(f"workers must be >= 1, got {workers}")
        self.workers = workers or os.cpu_count() or 1
        self._pool: list[_Worker] = []
        self._folder: Path | None = None
        self._fn: Callable[[Any], Any] | None = None
        self._started = 0  # workers started so far (numbers their stack files)
        self._start_failures = 0  # workers in a row that died before they said they were ready

    def _start_worker(self, fn: Callable[[Any], Any] | None, number: int) -> _Worker:
        assert self._folder is not None
        with single_threaded_workers():  # the worker starts (spawns) in its constructor
            return _Worker(multiprocessing.get_context("spawn"), fn, self._folder, number)

    def map_unordered(
        self,
        fn: Callable[[Any], Any],
        items: Iterable[Any],
        budget: Callable[[Any], float] | None = None,
    ) -> Iterator[tuple[Any, Any]]:
        self._fn = fn
        self._started = self._start_failures = 0
        self._folder = Path(tempfile.mkdtemp(prefix="centrobench-workers-"))
        # a caller's deque is read as work is handed out (it may append while consuming)
        pending = items if isinstance(items, deque) else deque(items)
        retry: deque[_Task] = deque()  # items whose worker died once: run again first
        next_id = 0

        def take() -> _Task:
            item = pending.popleft()
            task = _Task(item, math.inf if budget is None else budget(item))
            task.before_split_s = getattr(item, "split_budget_s", math.inf)
            return task

        try:
            while pending or retry or any(w.task is not None for w in self._pool):
                # a worker for every slot; work for every ready, idle worker
                for index in range(self.workers):
                    if not (pending or retry):
                        break
                    if index >= len(self._pool):
                        self._pool.append(self._new_worker())
                    worker = self._pool[index]
                    if worker.ready and worker.task is None:
                        task = retry.popleft() if retry else take()
                        if not worker.send(task, next_id):  # died idle: a fresh one next turn
                            retry.appendleft(task)
                            worker.ready = False
                        next_id += 1
                ready = self._wait()
                for index, worker in enumerate(self._pool):
                    task = worker.task
                    result = self._receive(worker) if worker.conn in ready else _NOTHING
                    if worker.ready and not worker.started_up:  # a worker can start
                        worker.started_up = True
                        self._start_failures = 0
                    if task is not None and result is not _NOTHING:
                        worker.task = None
                        yield task.item, result
                    elif worker.process.sentinel in ready or not worker.process.is_alive():
                        died = self._replace_dead(index)
                        if task is not None and task.attempts < 2:
                            retry.append(task)  # something outside may have killed it
                        elif task is not None:
                            yield task.item, WorkerDied(f"{died}, twice")
                    elif task is not None and (
                        time.monotonic() - worker.started > task.budget_now(worker.progress)
                    ):
                        yield task.item, self._end_overrun(index)
        finally:
            self.close()

    def _new_worker(self) -> _Worker:
        self._started += 1
        return self._start_worker(self._fn, self._started)

    def _wait(self) -> list[Any]:
        """Wait (at most 1 s, or until the nearest budget runs out) for a result, a worker
        that is ready or a worker that died; the ready pipes and sentinels."""
        busy = [w for w in self._pool if w.task is not None]
        watched = busy + [w for w in self._pool if not w.ready]
        now = time.monotonic()
        deadline = min(
            (w.started + w.task.budget_now(w.progress) for w in busy),  # type: ignore[union-attr]
            default=now + 1.0,
        )
        timeout = min(max(deadline - now, 0.0), 1.0)
        return wait([w.conn for w in watched] + [w.process.sentinel for w in watched], timeout)

    @staticmethod
    def _receive(worker: _Worker) -> Any:
        """The result of the worker's current task, or _NOTHING (a ready message, a stale
        result, or a pipe closed by a worker that died)."""
        try:
            message = worker.conn.recv()
        except (EOFError, OSError):
            return _NOTHING
        except Exception as exc:  # a reply that does not unpickle here: the task's error row,
            if worker.task is None:  # never the sweep's end (a worker has one task at a time)
                return _NOTHING
            what = f"{type(exc).__name__}: {exc}"
            return RuntimeError(f"the worker's result could not be read: {what}")
        if message is None:
            worker.ready = True
            return _NOTHING
        return message[2] if message[0] == worker.task_id else _NOTHING

    def _replace_dead(self, index: int) -> str:
        """Replace the dead worker at `index`; what happened to it, as a sentence. Raises
        RuntimeError when four workers in a row die before they say they are ready (they cannot
        start); a worker that had started and died idle (killed from outside: the OOM killer)
        is replaced without counting."""
        worker = self._pool[index]
        worker.kill()  # closes its pipe and reaps it
        location = stack_location(worker.stack())
        where = f" (at {location})" if location else ""
        said = worker.last_words()
        where += f"; its last words: {said}" if said else ""
        if worker.task is None and not worker.started_up:
            self._start_failures += 1
            if self._start_failures > 3:
                raise RuntimeError(
                    f"worker processes die at start-up: the last {worker.exit_description()}"
                    + where
                )
        self._pool[index] = self._new_worker()
        return f"the worker process {worker.exit_description()} during this episode{where}"

    def _end_overrun(self, index: int) -> EpisodeTimeout:
        """End the worker at `index`, whose task overran its budget, and replace it: the
        stage and simulated time from its progress slot, the location from its stack."""
        worker = self._pool[index]
        stage = progress_stage(worker.progress[0])
        sim_time = float(worker.progress[1])
        before = worker.stack_size()  # the dump asked for comes after what is there now
        with contextlib.suppress(ProcessLookupError):
            os.kill(worker.process.pid, signal.SIGUSR1)  # type: ignore[arg-type]
        location = self._await_stack(worker, before)
        worker.kill()
        self._pool[index] = self._new_worker()
        assert worker.task is not None
        budget_s = worker.task.budget_now(worker.progress)
        return EpisodeTimeout(budget_s, stage, sim_time, location)

    @staticmethod
    def _await_stack(worker: _Worker, since: int) -> str | None:
        """The location in the stack that a worker writes on SIGUSR1 after byte `since` of its
        stack file (waits STACK_WAIT_S)."""
        end = time.monotonic() + STACK_WAIT_S
        while time.monotonic() < end:
            location = stack_location(worker.stack(since))
            if location is not None:
                return location
            time.sleep(0.02)
        return None

    def close(self) -> None:
        """Stop every worker now (idle ones are told to exit, busy ones killed)."""
        pool, self._pool = self._pool, []
        for worker in pool:
            if worker.task is None and worker.ready:
                with contextlib.suppress(OSError, BrokenPipeError):
                    worker.conn.send(None)
        for worker in pool:
            if worker.task is not None or not worker.ready:
                worker.kill()
        for worker in pool:
            worker.process.join(timeout=2)
            worker.kill()
        if self._folder is not None:
            shutil.rmtree(self._folder, ignore_errors=True)
            self._folder = None


_NOTHING = object()


# ----------------------------------------------------------------------------------- Ray


def check_ray_address(address: str | None, timeout_s: float = ADDRESS_TIMEOUT_S) -> None:
    """ValueError unless `address` (HOST:PORT, ray://HOST:PORT, or "auto"/None) names a Ray
    cluster that accepts a TCP connection within `timeout_s`: so that a wrong address fails
    at once with one line, before anything is run or written (ray.init would retry for
    minutes)."""
    if address is None or address == "auto":
        return  # None: a local instance is started; "auto": Ray itself finds a running one
    text = address.removeprefix("ray://")
    host, _, port = text.rpartition(":")
    if not host or not port.isdigit() or not 0 < int(port) < 65536:
        raise ValueError(f"--address must be HOST:PORT (or auto), got {address!r}")
    try:
        with socket.create_connection((host.strip("[]"), int(port)), timeout=timeout_s):
            pass
    except OSError as exc:
        reason = "no answer" if isinstance(exc, TimeoutError) else exc.strerror or str(exc)
        raise ValueError(
            f"no Ray cluster at {address}: {reason} (waited at most {timeout_s:g} s)"
        ) from None


class RayExecutor:
    def __init__(self, address: str | None = None, workers: int | None = None) -> None:
        try:
            import ray
        except ImportError:
            raise ImportError(
                "the Ray executor needs Ray: pip install -c constraints.txt -e '.[ray]'"
            ) from None
        check_ray_address(address)
        self.ray = ray
        self._started = False
        if not ray.is_initialized():
            options: dict[str, Any] = {"include_dashboard": False, "log_to_driver": False}
            if address is None:
                options["num_cpus"] = workers or os.cpu_count() or 1
            ray.init(address=address, **options)
            self._started = True
        self.window = max(1, int(ray.cluster_resources().get("CPU", 1)))

    def map_unordered(
        self,
        fn: Callable[[Any], Any],
        items: Iterable[Any],
        budget: Callable[[Any], float] | None = None,
    ) -> Iterator[tuple[Any, Any]]:
        ray = self.ray
        remote = ray.remote(num_cpus=1, max_retries=1)(fn)
        # a caller's deque is read as work is handed out (it may append while consuming)
        pending = items if isinstance(items, deque) else deque(items)
        in_flight: dict[Any, tuple[Any, float, float]] = {}  # ref: item, start, budget
        try:
            while pending or in_flight:
                while pending and len(in_flight) < self.window:
                    item = pending.popleft()
                    allowed = math.inf if budget is None else budget(item)
                    in_flight[remote.remote(item)] = (item, time.monotonic(), allowed)
                now = time.monotonic()
                deadline = min(start + allowed for _, start, allowed in in_flight.values())
                ready, _ = ray.wait(
                    list(in_flight), num_returns=1, timeout=min(max(deadline - now, 0.0), 1.0)
                )
                for reference in ready:
                    item, _, _ = in_flight.pop(reference)
                    try:
                        yield item, ray.get(reference)
                    except ray.exceptions.WorkerCrashedError as exc:
                        yield item, WorkerDied(f"the Ray worker died during this episode: {exc}")
                    except Exception as exc:
                        yield item, exc
                now = time.monotonic()
                for reference, (item, start, allowed) in list(in_flight.items()):
                    if now - start > allowed:
                        ray.cancel(reference, force=True)
                        del in_flight[reference]
                        yield item, EpisodeTimeout(allowed)
        finally:
            for reference in in_flight:
                with contextlib.suppress(Exception):
                    ray.cancel(reference, force=True)

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
