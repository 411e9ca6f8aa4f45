"""A process pool for batches that survives a dying worker and stops at once on Ctrl-C.

`concurrent.futures.ProcessPoolExecutor` fails every pending task when one worker dies (the
out-of-memory killer, a segfault in a native library) and, on Ctrl-C, waits for the running tasks to
finish (and write their files). Here each worker is a fresh interpreter (``spawn``) with its own pipe and
runs one task at a time, so the parent always knows which task a dead worker held: that task alone
fails (`WorkerDied`), a new worker takes its place, and the others go on. On an interrupt (or any error in
the parent) every worker is terminated before the exception propagates; a worker terminated while
writing removes its temporary file (`vectortighten.io.atomic_path`), so no output appears afterwards.
Workers ignore SIGINT: Ctrl-C at a terminal reaches the whole process group, and only the parent acts
on it.
"""

from __future__ import annotations

import multiprocessing
import os
import signal
from collections.abc import Callable, Iterable, Iterator
from multiprocessing.connection import wait

__all__ = ["WorkerDied", "run_tasks"]


class WorkerDied(RuntimeError):
    """The worker process running a task ended without a result (killed, out of memory, crashed)."""


def _on_term(signum, frame):  # pragma: no cover - runs in a worker being terminated
    from .io._common import discard_pending

    discard_pending()
    os._exit(128 + signum)


def _worker(conn, fn: Callable) -> None:  # pragma: no cover - runs in the worker process
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, _on_term)
    while True:
        try:
            item = conn.recv()
        except (EOFError, OSError):
            return
        if item is None:
            return
        key, args = item
        try:
            result = (True, fn(*args))
        except BaseException as exc:   # sent back; the parent decides
            result = (False, exc)
        try:
            conn.send((key, result))
        except Exception as exc:       # an unpicklable result or error
            conn.send((key, (False, RuntimeError(f"{type(exc).__name__}: {exc}"))))


class _Slot:
    def __init__(self, ctx, fn):
        self.conn, child = ctx.Pipe(duplex=True)
        self.proc = ctx.Process(target=_worker, args=(child, fn), daemon=True)
        self.proc.start()
        child.close()
        self.key = None

    def stop(self, terminate: bool) -> None:
        if terminate and self.proc.is_alive():
            self.proc.terminate()
        else:
            try:
                self.conn.send(None)
            except (OSError, BrokenPipeError):
                pass
        self.proc.join(timeout=5)
        if self.proc.is_alive():
            self.proc.kill()
            self.proc.join(timeout=5)
        self.conn.close()


def run_tasks(fn: Callable, tasks: Iterable[tuple], processes: int) -> Iterator[tuple[int, bool, object]]:
    """Run ``fn(*args)`` for every ``args`` of ``tasks`` in up to ``processes`` worker processes.

    Yields ``(index, ok, value)`` as tasks finish (in any order): ``ok`` True with the return value, or
    False with the exception (a `WorkerDied` if the worker ended without a result). ``fn`` must be a
    module-level function and its arguments and results picklable. If the consumer stops (an exception,
    KeyboardInterrupt, or closing the generator), every worker is terminated at once.

    Examples
    --------
    >>> sorted(run_tasks(abs, [(-1,), (-2,)], 2))
    [(0, True, 1), (1, True, 2)]
    """
    ctx = multiprocessing.get_context("spawn")
    todo = list(enumerate(tasks))
    todo.reverse()
    slots: list[_Slot] = []
    clean = False
    try:
        for _ in range(max(1, min(processes, len(todo)))):
            slots.append(_Slot(ctx, fn))
        for s in slots:
            if todo:
                s.key, args = todo.pop()
                s.conn.send((s.key, args))
        while any(s.key is not None for s in slots):
            busy = [s for s in slots if s.key is not None]
            ready = wait([s.conn for s in busy] + [s.proc.sentinel for s in busy])
            for s in busy:
                if s.conn not in ready and s.proc.sentinel not in ready:
                    continue
                key = s.key
                got = None
                try:
                    if s.conn.poll():
                        got = s.conn.recv()
                except (EOFError, OSError):
                    got = None
                if got is None:
                    if s.proc.is_alive():
                        continue
                    code = s.proc.exitcode
                    s.key = None
                    s.stop(terminate=True)
                    slots.remove(s)
                    why = (f"killed by signal {-code}" if code is not None and code < 0
                           else f"exit code {code}")
                    yield key, False, WorkerDied(f"the worker process died ({why}; out of memory?)")
                    if todo:
                        fresh = _Slot(ctx, fn)
                        slots.append(fresh)
                        fresh.key, args = todo.pop()
                        fresh.conn.send((fresh.key, args))
                    continue
                s.key = None
                _, (ok, value) = got
                yield key, ok, value
                if todo:
                    s.key, args = todo.pop()
                    s.conn.send((s.key, args))
        clean = True
    finally:
        for s in slots:
            s.stop(terminate=not clean)
