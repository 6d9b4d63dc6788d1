"""Evaluating a study's points: in this process, on local processes or on a Dask cluster.

Every worker builds the numerical vehicle **once** (:func:`express.numeric.statespace.load_vehicle`:
the symbolic generation, about a second) and evaluates each point from its parameter
vector with :meth:`~express.numeric.statespace.VehicleModel.with_values` (milliseconds), which
re-evaluates the derived parameters. The task sent to a worker carries the model's (and
the track's) text, so that workers on other machines need no shared files.

Engines (:class:`Engine`):

- one worker: the points run in this process;
- ``workers = N``: a pool of N local processes (forked after the vehicle is built, so
  that they inherit it); a process that dies has its unfinished points run again in a
  new pool (a chunk that keeps killing its process is split, and a single point that
  kills its process three times is recorded as failed);
- ``scheduler = "tcp://HOST:PORT"``: a Dask distributed cluster (``dask scheduler``,
  ``dask worker ADDRESS``); the scheduler re-runs the tasks of a worker that dies.

Points go out in chunks of consecutive points, and at most a few chunks per worker are
in flight at a time, so that memory does not grow with the number of points. Results
come back as they are computed (:meth:`Engine.run`) and are written to the checkpoint
(:mod:`express.analysis.study.results`) before the next chunk is sent.
"""

from __future__ import annotations

import contextlib
import hashlib
import math
import os
import tempfile
import threading
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from express.analysis.study.outputs import OUTPUTS, OutputSettings, PointOutputs
from express.analysis.study.spec import StudySpec
from express.base.diagnostics import ExpressError, UsageError
from express.base.interrupts import release, temporary_file

__all__ = ["BLOCK", "Engine", "StudyTask", "blocked", "chunk_size", "evaluate_points", "make_task"]

#: Chunks in flight per worker.
IN_FLIGHT = 4
#: Seconds a worker process gets to end after SIGTERM (then SIGKILL), and a Dask client to close.
STOP_SECONDS = 2.0
#: Times a point may kill its worker process before it is recorded as failed.
MAX_ATTEMPTS = 3
#: With ``check = "local"`` the points go out in aligned blocks of this many indices;
#: each block starts a fresh critical-speed search, and so does every point that is not a
#: neighbour of the one before (more than one parameter changed): a point's result then
#: depends only on the points of its block, whatever worker, chunk or resumed run
#: evaluates it.
BLOCK = 64


@dataclass(frozen=True)
class StudyTask:
    """What a worker needs to evaluate points (picklable, no shared files needed).

    Attributes
    ----------
    key : str
        SHA-256 of everything below: identifies the study's vehicle and outputs.
    model_path : str
        The model file where the study was started (used when present with the same text).
    model_text : bytes
    names : tuple of str
        The varied parameters, in the order of a point's vector.
    fixed : tuple of (str, float)
        ``[study.set]`` (SI).
    outputs : tuple of str
    settings : OutputSettings
        With ``track`` None when ``track_text`` carries the track file.
    track_name : str or None
    track_text : bytes or None
    """

    key: str
    model_path: str
    model_text: bytes
    names: tuple[str, ...]
    fixed: tuple[tuple[str, float], ...]
    outputs: tuple[str, ...]
    settings: OutputSettings
    track_name: str | None = None
    track_text: bytes | None = None


def make_task(spec: StudySpec) -> StudyTask:
    """The worker task of a checked study."""
    model_text = spec.model.read_bytes()
    track = spec.settings.track
    named = isinstance(track, str)  # a bundled track travels by its name
    track_text = track.read_bytes() if isinstance(track, Path) else None
    settings = spec.settings if named else replace(spec.settings, track=None)
    digest = hashlib.sha256()
    for part in (model_text, spec.model.suffix.encode(), repr(spec.names).encode(),
                 repr(sorted(spec.fixed.items())).encode(), repr(spec.outputs).encode(), repr(settings).encode(),
                 track_text or b""):
        digest.update(hashlib.sha256(part).digest())
    return StudyTask(
        key=digest.hexdigest(), model_path=str(spec.model.resolve()), model_text=model_text, names=spec.names,
        fixed=tuple(sorted(spec.fixed.items())), outputs=spec.outputs, settings=settings,
        track_name=track.name if isinstance(track, Path) else None, track_text=track_text,
    )


def _materialise(path_hint: str | None, name: str, text: bytes, key: str) -> Path:
    """The file holding ``text``: ``path_hint`` if it holds it, else a private copy."""
    if path_hint is not None:
        try:
            if Path(path_hint).read_bytes() == text:
                return Path(path_hint)
        except OSError:
            pass
    folder = Path(tempfile.gettempdir()) / f"express-study-{key[:16]}"
    folder.mkdir(parents=True, exist_ok=True)
    target = folder / name
    if not (target.exists() and target.read_bytes() == text):
        handle, temporary = temporary_file(folder, prefix=f".{name}.", suffix=".tmp")
        try:
            with os.fdopen(handle, "wb") as stream:
                stream.write(text)
            os.replace(temporary, target)
        except BaseException:
            temporary.unlink(missing_ok=True)
            raise
        finally:
            release(temporary)
    return target


class _Worker:
    """A worker's vehicle (built once) and output calculator."""

    def __init__(self, task: StudyTask):
        import multiprocessing

        from express.numeric.statespace import load_vehicle

        if multiprocessing.parent_process() is not None:  # a pool or Dask worker process
            from threadpoolctl import threadpool_limits

            threadpool_limits(limits=1, user_api="blas")  # small matrices: threads only contend
        model = _materialise(task.model_path, Path(task.model_path).name, task.model_text, task.key)
        settings = task.settings
        if task.track_text is not None and task.track_name is not None:
            settings = replace(settings, track=_materialise(None, task.track_name, task.track_text, task.key))
        self.base = load_vehicle(model)
        if settings.linearisation != "tangent":  # with_values re-linearises each point
            from express.forces.linearisation import linearised

            self.base = linearised(self.base, settings.linearisation_spec)
        self.names = task.names
        self.fixed = dict(task.fixed)
        self.output_names = task.outputs
        self.outputs = PointOutputs(task.outputs, settings)
        self.previous: list[float] | None = None

    def restart(self) -> None:
        """Start a chunk: the next point starts a fresh critical-speed search."""
        self.previous = None

    def evaluate(self, index: int, vector: Sequence[float]) -> dict[str, Any]:
        """One point: ``{"point", "values", "outputs", "error"}`` (outputs SI, None for nan).

        The critical-speed search follows on from the previous point only when the two
        differ in one parameter (neighbours along a grid line); otherwise it starts again.
        """
        vector = [float(x) for x in vector]
        if self.previous is None or sum(a != b for a, b in zip(vector, self.previous, strict=True)) > 1:
            self.outputs.restart()
        self.previous = vector
        changes = dict(self.fixed)
        changes.update(zip(self.names, (float(x) for x in vector), strict=True))
        try:
            vehicle = self.base.with_values(changes)
            values, notes = self.outputs(vehicle)
            error = "; ".join(notes)
        except (ExpressError, ValueError, ArithmeticError, np.linalg.LinAlgError) as exception:
            values, error = {}, _message(exception)
        except Exception as exception:  # a point never stops the study; the message says what broke
            values, error = {}, f"internal error: {type(exception).__name__}: {_message(exception)}"
        outputs = [values.get(name, math.nan) for name in self.output_names]
        missing = [name for name, x in zip(self.output_names, outputs, strict=True) if not math.isfinite(x)]
        if missing and not error:  # nan is the documented marker of a failed output: never without its reason
            error = f"no finite value of {', '.join(missing)}"
        return {
            "point": int(index),
            "values": [float(x) for x in vector],
            "outputs": [float(x) if math.isfinite(x) else None for x in outputs],
            "error": error,
        }


def _message(exception: BaseException) -> str:
    text = " ".join(str(exception).split()) or type(exception).__name__
    return text[:500]


_WORKERS: dict[str, _Worker] = {}
_LOCK = threading.Lock()


def _worker(task: StudyTask) -> _Worker:
    with _LOCK:
        worker = _WORKERS.get(task.key)
        if worker is None:
            if len(_WORKERS) >= 2:
                _WORKERS.pop(next(iter(_WORKERS)))
            worker = _WORKERS[task.key] = _Worker(task)
        return worker


def evaluate_points(task: StudyTask, indices: Sequence[int], vectors: Sequence[Sequence[float]]) -> list[dict]:
    """Evaluate a chunk of points on this process's worker (built on first use); one
    record each. Each chunk starts a fresh critical-speed search."""
    worker = _worker(task)
    worker.restart()
    return [worker.evaluate(i, v) for i, v in zip(indices, vectors, strict=True)]


def blocked(task: StudyTask) -> bool:
    """Whether the points go out in aligned blocks (``check = "local"``)."""
    return task.settings.check == "local" and "critical" in {OUTPUTS[name][1] for name in task.outputs}


def chunk_size(points: int, workers: int) -> int:
    """Points per chunk: about 16 chunks per worker, from 1 to 64 points."""
    return max(1, min(64, math.ceil(points / max(1, workers * 16))))


def _chunks(indices: Sequence[int], vectors: np.ndarray, size: int, aligned: bool = False):
    """Chunks of consecutive entries of ``indices`` (``aligned``: one per block of
    :data:`BLOCK` point indices)."""
    start = 0
    while start < len(indices):
        if aligned:
            block = indices[start] // BLOCK
            end = start
            while end < len(indices) and indices[end] // BLOCK == block:
                end += 1
        else:
            end = min(start + size, len(indices))
        yield list(indices[start:end]), [list(map(float, vectors[k])) for k in range(start, end)]
        start = end


def _stop_pool(pool: Any) -> None:
    """Stop a process pool now: queued chunks cancelled, workers terminated and joined
    (killed if they do not end within :data:`STOP_SECONDS`)."""
    processes = list((getattr(pool, "_processes", None) or {}).values())
    for process in processes:
        with contextlib.suppress(OSError, ValueError, AttributeError):
            process.terminate()
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        with contextlib.suppress(OSError, ValueError, AttributeError, AssertionError):
            process.join(STOP_SECONDS)
            if process.is_alive():
                process.kill()
                process.join(STOP_SECONDS)


def _end_with_parent() -> None:
    """In a worker process: be killed when the study's process dies, even by ``kill -9``
    (Linux's ``PR_SET_PDEATHSIG``; elsewhere the pool's own shutdown is all there is)."""
    import ctypes
    import signal
    import sys

    if sys.platform.startswith("linux"):
        with contextlib.suppress(OSError):
            ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, int(signal.SIGKILL), 0, 0, 0)  # 1: PR_SET_PDEATHSIG


#: How long a scheduler may take to answer before ``--scheduler`` is an error [s].
CONNECT_SECONDS = 30.0


def _bounded_client(client_class: Any, address: str) -> Any:
    """A Dask client of ``address``, or a clear error within :data:`CONNECT_SECONDS`.

    ``Client(timeout=...)`` bounds the TCP connection, not the handshake: a port that
    accepts and never answers held it forever (issue 36).  So the client is made in a
    daemon thread and waited for; one that never answers is left behind (its thread ends
    with the process), never closed (its ``__del__`` would wait 40 s more)."""
    import threading

    from distributed.comm.addressing import parse_address, parse_host_port

    try:  # checked before a Client exists: a half-made one waits 60 s in __del__ and prints a traceback
        scheme, location = parse_address(address, strict=True)
        if scheme in ("tcp", "tls"):
            parse_host_port(location)
    except ValueError as error:
        raise UsageError(f"--scheduler {address}: not a Dask scheduler address such as tcp://HOST:8786 ({error})") from None
    made: dict[str, Any] = {}

    def connect() -> None:
        try:
            made["client"] = client_class(address, timeout=f"{CONNECT_SECONDS:g}s", set_as_default=False)
        except BaseException as error:  # reported below, in the calling thread
            made["error"] = error

    thread = threading.Thread(target=connect, name="express-dask-connect", daemon=True)
    thread.start()
    thread.join(CONNECT_SECONDS + 5.0)
    if "client" in made:
        return made["client"]
    failure = made.get("error")
    if failure is None:
        raise UsageError(f"--scheduler {address}: no answer from a Dask scheduler within {CONNECT_SECONDS:g} s "
                         "(is it a Dask scheduler's address?)")
    if isinstance(failure, (OSError, TimeoutError, ValueError)):
        raise UsageError(f"--scheduler {address}: cannot connect to the Dask scheduler ({failure})") from None
    raise failure


def _failed(indices: Sequence[int], vectors: Sequence[Sequence[float]], outputs: int, message: str) -> list[dict]:
    """Records of points *lost* to the machinery (a worker that died each time, a task the
    cluster dropped): marked ``lost``, they are no results — the study keeps them out of its
    checkpoint, ends with exit status 1 and ``--resume`` computes them again."""
    return [{"point": int(i), "values": [float(x) for x in v], "outputs": [None] * outputs, "error": message,
             "lost": True} for i, v in zip(indices, vectors, strict=True)]


class Engine:
    """Where the points run (module docstring). Use as a context manager.

    Parameters
    ----------
    task : StudyTask
    workers : int
        Local processes (1: this process). Ignored with ``scheduler``.
    scheduler : str, optional
        Address of a Dask scheduler (``tcp://HOST:PORT``).
    in_process : bool, optional
        Evaluate in this process; default: when ``workers`` is 1.
    """

    def __init__(self, task: StudyTask, workers: int = 1, scheduler: str | None = None, in_process: bool | None = None):
        self.task = task
        self.workers = max(1, int(workers))
        self.scheduler = scheduler
        self.in_process = self.workers == 1 if in_process is None else in_process
        self._pool: Any = None
        self._client: Any = None
        self._task_future: Any = None
        self._futures: set[Any] = set()

    def __enter__(self) -> Engine:
        _worker(self.task)  # build the vehicle here: a bad model stops the study before any work
        if self.scheduler is not None:
            self._connect()
        return self

    def __exit__(self, kind, error, trace) -> None:
        """Normally: wait for the workers. After an error or an interrupt: cancel what is
        queued, stop the worker processes at once (SIGTERM, then SIGKILL after
        :data:`STOP_SECONDS`) and join them; cancel the Dask tasks. The points lost in flight
        were not in the checkpoint yet: ``--resume`` computes them again."""
        pool, self._pool = self._pool, None
        client, self._client = self._client, None
        if pool is not None:
            if kind is None:
                pool.shutdown(wait=True, cancel_futures=True)
            else:
                _stop_pool(pool)
        if client is not None:
            if kind is not None and self._futures:
                with contextlib.suppress(Exception):
                    client.cancel(list(self._futures), force=True)
            with contextlib.suppress(Exception):
                client.close(timeout=STOP_SECONDS if kind is not None else "20s")
        self._futures.clear()

    @property
    def parallel(self) -> int:
        """Workers available (Dask: the cluster's worker threads)."""
        if self._client is not None:
            self._threads = max(1, sum(self._client.nthreads().values()))
        return getattr(self, "_threads", self.workers)

    def _connect(self) -> None:
        try:
            from distributed import Client
        except ImportError:  # pragma: no cover - distributed is a dependency
            raise UsageError("--scheduler needs the dask[distributed] package") from None
        assert self.scheduler is not None
        self._client = _bounded_client(Client, self.scheduler)
        self._task_future = self._client.scatter(self.task, broadcast=True, hash=False)

    def run(self, indices: Sequence[int], vectors: np.ndarray) -> Iterator[list[dict]]:
        """Evaluate the points; yields lists of records as chunks finish (any order)."""
        if len(indices) == 0:
            return
        size = chunk_size(len(indices), self.parallel)
        chunks = _chunks(list(indices), np.asarray(vectors, dtype=float), size, blocked(self.task))
        if self._client is not None:
            yield from self._run_dask(chunks)
        elif self.in_process:
            for part, part_vectors in chunks:
                yield evaluate_points(self.task, part, part_vectors)
        else:
            yield from self._run_local(chunks)

    # ---------------------------------------------------------------- local processes

    def _new_pool(self):
        import concurrent.futures
        import multiprocessing

        methods = multiprocessing.get_all_start_methods()
        context = multiprocessing.get_context("fork" if "fork" in methods else "spawn")
        return concurrent.futures.ProcessPoolExecutor(max_workers=self.workers, mp_context=context,
                                                      initializer=_end_with_parent)

    def _run_local(self, chunks: Iterable[tuple[list[int], list[list[float]]]]) -> Iterator[list[dict]]:
        import concurrent.futures
        from concurrent.futures.process import BrokenProcessPool

        pending = list(chunks)[::-1]  # a stack: pop() gives the next chunk in order
        attempts: dict[int, int] = {}
        running: dict[Any, tuple[list[int], list[list[float]]]] = {}
        if self._pool is None:
            self._pool = self._new_pool()
        while pending or running:
            while pending and len(running) < IN_FLIGHT * self.workers:
                part, part_vectors = pending.pop()
                running[self._pool.submit(evaluate_points, self.task, part, part_vectors)] = (part, part_vectors)
            done, _ = concurrent.futures.wait(running, return_when=concurrent.futures.FIRST_COMPLETED)
            broken = False
            for future in done:
                part, part_vectors = running.pop(future)
                try:
                    yield future.result()
                except BrokenProcessPool:
                    broken = True
                    pending.extend(self._retry(part, part_vectors, attempts))
            if broken:
                for future, (part, part_vectors) in running.items():
                    try:
                        yield future.result()
                    except BrokenProcessPool:
                        pending.extend(self._retry(part, part_vectors, attempts))
                running.clear()
                self._pool.shutdown(wait=False, cancel_futures=True)
                self._pool = self._new_pool()
            yield from self._give_up(pending, attempts)

    def _retry(self, part: list[int], vectors: list[list[float]], attempts: dict[int, int]):
        """Chunks to run again after their process died: split after the second death."""
        for i in part:
            attempts[i] = attempts.get(i, 0) + 1
        if len(part) > 1 and attempts[part[0]] >= 2:
            return [([i], [v]) for i, v in zip(part, vectors, strict=True)][::-1]
        return [(part, vectors)]

    def _give_up(self, pending: list, attempts: dict[int, int]) -> Iterator[list[dict]]:
        for chunk in [c for c in pending if len(c[0]) == 1 and attempts.get(c[0][0], 0) >= MAX_ATTEMPTS]:
            pending.remove(chunk)
            yield _failed(chunk[0], chunk[1], len(self.task.outputs),
                          f"the worker process evaluating this point died {MAX_ATTEMPTS} times")

    # ---------------------------------------------------------------- Dask

    def _run_dask(self, chunks: Iterable[tuple[list[int], list[list[float]]]]) -> Iterator[list[dict]]:
        from distributed import as_completed

        client = self._client
        assert client is not None
        window = IN_FLIGHT * self.parallel
        pending = iter(chunks)
        parts = {}

        def submit():
            chunk = next(pending, None)
            if chunk is None:
                return None
            future = client.submit(evaluate_points, self._task_future, chunk[0], chunk[1], pure=False)
            parts[future.key] = chunk
            self._futures.add(future)
            return future

        first = [f for f in (submit() for _ in range(window)) if f is not None]
        futures = as_completed(first, loop=client.loop)  # our client is not the default one
        attempts: dict[int, int] = {}
        for future in futures:
            part, part_vectors = parts.pop(future.key)
            self._futures.discard(future)
            try:
                records = future.result()
            except Exception as error:  # a worker lost (KilledWorker, a dropped task), a lost connection
                attempts[part[0]] = attempts.get(part[0], 0) + 1
                if attempts[part[0]] < MAX_ATTEMPTS:
                    futures.add(self._resubmit(part, part_vectors, parts))
                    continue
                records = _failed(part, part_vectors, len(self.task.outputs),
                                  f"Dask task failed {MAX_ATTEMPTS} times: {_message(error)}")
            yield records
            future.release()
            following = submit()
            if following is not None:
                futures.add(following)

    def _resubmit(self, part: list[int], vectors: list[list[float]], parts: dict) -> Any:
        """Submit a lost chunk again; the study's task scattered anew when the cluster lost
        it with the worker that held it (an only worker killed: its dependents were
        cancelled, "already forgotten")."""
        client = self._client
        assert client is not None
        if self._task_future.status != "finished":
            self._task_future = client.scatter(self.task, broadcast=True, hash=False)
        future = client.submit(evaluate_points, self._task_future, part, vectors, pure=False)
        parts[future.key] = (part, vectors)
        self._futures.add(future)
        return future
