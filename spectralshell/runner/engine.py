"""Dispatch of tasks through any ``concurrent.futures.Executor``, a bounded number at a time."""

from __future__ import annotations

from collections.abc import Callable, Iterable
from concurrent.futures import FIRST_COMPLETED, Executor, Future, wait
from typing import Any


class PartialFailure(Exception):
    """Raised by a task that failed after finishing part of its work: ``done`` is delivered to
    ``on_result`` like a result, and ``error`` is then the task's error (:func:`run_tasks`)."""

    def __init__(self, done: Any, error: BaseException):
        super().__init__(done, error)  # the args rebuild it when it is pickled back from a worker
        self.done, self.error = done, error


def run_tasks(executor: Executor, fn: Callable[..., Any], tasks: Iterable[tuple], *,
              in_flight: int, on_result: Callable[[tuple, Any], None]) -> None:
    """Call ``fn(*task)`` for every task on ``executor``, keeping at most ``in_flight`` submitted,
    and ``on_result(task, result)`` in this process as each one finishes (in completion order).

    On the first task error nothing more is submitted, queued tasks are cancelled, the running
    ones finish and are still delivered to ``on_result``, and then the error is raised; a task
    that raises :class:`PartialFailure` has its finished part delivered first. On
    KeyboardInterrupt (or an error in ``on_result``) everything pending is cancelled at once.
    """
    todo = iter(tasks)
    pending: dict[Future, tuple] = {}
    first_error: BaseException | None = None

    def submit_next() -> None:
        for task in todo:
            pending[executor.submit(fn, *task)] = task
            return

    try:
        while len(pending) < in_flight and first_error is None:
            before = len(pending)
            submit_next()
            if len(pending) == before:
                break
        while pending:
            done, _ = wait(pending, return_when=FIRST_COMPLETED)
            for future in done:
                task = pending.pop(future)
                if future.cancelled():
                    continue
                error = future.exception()
                if isinstance(error, PartialFailure):
                    on_result(task, error.done)
                    error = error.error
                if error is not None:
                    if first_error is None:
                        first_error = error
                        for other in pending:
                            other.cancel()
                    continue
                on_result(task, future.result())
                if first_error is None:
                    submit_next()
    except BaseException:
        for future in pending:
            future.cancel()
        raise
    if first_error is not None:
        raise first_error
