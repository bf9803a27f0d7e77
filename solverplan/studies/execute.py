"""Running a study: in this process, on a local process pool, or on a Dask cluster; resumable.

:func:`run_study` computes the rows a study still lacks and assembles its table:

- ``workers=1``: in this process, one row after the other (simplest to debug);
- ``workers=N`` (default: the CPUs this process may use): a :class:`~concurrent.futures.ProcessPoolExecutor`
  of N processes (``forkserver`` start method: workers fork from a server that has imported
  solverplan once, and ignore SIGINT so the parent alone decides how to stop);
- ``scheduler="tcp://host:8786"`` (or a :class:`distributed.Client`): the same tasks on a Dask
  distributed cluster (the optional extra ``solverplan[dask]``; the workers need solverplan installed).

Every engine runs the same pure function (:func:`~solverplan.studies.study.run_task`) on the same
tasks, so the tables are identical apart from the ``seconds`` column. Rows reach the parent as they
finish and are appended to ``DIR/NAME.jsonl`` at once (:mod:`solverplan.studies.store`); the final
tables ``DIR/NAME.csv`` and ``DIR/NAME.json`` are written atomically, in table order, when every row
is there. Interrupted (Ctrl-C, SIGTERM, a failing row), a study keeps its finished rows, and running
it again computes only the missing ones.
"""

from __future__ import annotations

import json
import logging
import os
import re
import signal
import threading
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import field, replace
from pathlib import Path
from typing import Any, Callable, Iterator

from solverplan._io import atomic_write_text, cannot_write
from solverplan.errors import InputError, SolverFailed, SolverplanError
from solverplan.limits import quote
from solverplan.result import answer_dataclass
from solverplan.studies.store import RowStore
from solverplan.studies.study import Study, StudyTable, Task, run_task

__all__ = ["run_study", "StudyResult", "StudyInterrupted", "default_workers", "output_paths"]

logger = logging.getLogger(__name__)

Progress = Callable[[int, int], None]
"""Called with (rows done, rows in the study): once before the first new row, then after each."""


class StudyInterrupted(SolverplanError):
    """The study was stopped (SIGINT / SIGTERM) before it finished; its finished rows are saved."""


def default_workers() -> int:
    """The number of CPUs this process may run on."""
    try:
        return max(len(os.sched_getaffinity(0)), 1)
    except AttributeError:  # pragma: no cover - not on Linux
        return max(os.cpu_count() or 1, 1)


def output_paths(study: Study, out_dir: str | os.PathLike[str]) -> dict[str, Path]:
    """Where a study's files go: ``rows`` (.jsonl), ``csv``, ``json`` and ``figure`` (.png)."""
    folder = Path(out_dir)
    return {kind: folder / f"{study.name}{ext}" for kind, ext in
            (("rows", ".jsonl"), ("csv", ".csv"), ("json", ".json"), ("figure", ".png"))}


# ---------------------------------------------------------------------- results
@answer_dataclass("study")
class StudyResult:
    """A finished study: its table, the files written, and how the rows were obtained."""

    table: StudyTable
    files: dict[str, str] = field(default_factory=dict)
    computed: int = 0
    reused: int = 0
    seconds: float = 0.0
    engine: dict = field(default_factory=dict)

    def figure_title(self) -> str:
        """Title of the study's heatmap figure: what was measured over what."""
        study = self.table.study
        fixed = ", ".join(f"{k}={v[0]}" for k, v in study.grid if len(v) == 1)
        return (f"{study.name}: {study.generator} environments{f' ({fixed})' if fixed else ''}, "
                f"mean of {study.per_cell} per cell")

    def with_file(self, kind: str, path: str | os.PathLike[str]) -> StudyResult:
        """The same result listing one more file written (the CLI's heatmap figure)."""
        return replace(self, files={**self.files, kind: str(path)})

    def _cells(self) -> list[dict]:
        out = []
        for cell in self.table.cell_summaries():
            entry = {k: v for k, v in cell.items() if not isinstance(v, dict) and v is not None}
            for c in self.table.metric_columns():
                entry[c] = cell[c]["mean"] if cell[c] else None
            out.append(entry)
        return out

    def means_by_option(self) -> dict:
        """Means of the metric columns per value of each metric option axis (the rules study: per family)."""
        return {name: {str(v): self.table.means(where={name: v}) for v in values}
                for name, values in self.table.study.option_axes}

    def to_json(self) -> dict:
        """Summary for stdout: study, files, row counts, timings, engine, overall and per-cell means."""
        data = {
            "kind": "study",
            "study": self.table.study.to_json(),
            "files": dict(self.files),
            "rows": len(self.table.rows),
            "computed": self.computed,
            "reused": self.reused,
            "seconds": round(self.seconds, 3),
            "engine": self.engine,
            "means": self.table.means(),
        }
        if self.table.study.option_axes:
            data["means_by"] = self.means_by_option()
        data["cells"] = self._cells()
        return data

    def to_text(self, *, width: int = 100) -> str:
        study = self.table.study
        lines = [
            f"study {study.name}: {study.generator} polygons, {study.n_cells} cells x {study.per_cell} seeds = "
            f"{len(self.table.rows)} rows ({self.computed} computed, {self.reused} reused) in {self.seconds:.1f} s",
        ]
        shown = [c for c in dict.fromkeys(v for v, _ in study.metric.panels)]
        axes = [k for k, v in study.all_axes if len(v) > 1]
        header = [*axes, *shown]
        rows = [[f"{c[k]:g}" if isinstance(c[k], float) else str(c[k]) for k in axes]
                + [("-" if c[v] is None else f"{c[v]:.4g}") for v in shown] for c in self._cells()]
        widths = [max(len(h), *(len(r[k]) for r in rows)) if rows else len(h) for k, h in enumerate(header)]
        lines.append("  ".join(h.rjust(w) for h, w in zip(header, widths)))
        lines += ["  ".join(x.rjust(w) for x, w in zip(r, widths)) for r in rows]
        means = self.table.means()
        lines.append("mean: " + ", ".join(f"{k} {means[k]:.4g}" for k in shown if means.get(k) is not None))
        for kind, path in self.files.items():
            lines.append(f"{kind}: {path}")
        return "\n".join(lines) + "\n"


# ---------------------------------------------------------------------- engines
def _describe(task: Task) -> str:
    values = ", ".join(f"{k}={v}" for k, v in (*task.params, *task.options))
    return f"cell {task.cell} ({values}), replicate {task.replicate}, seed {task.seed}"


def _failed(task: Task, exc: BaseException) -> SolverplanError:
    if isinstance(exc, InputError):
        return InputError(f"row {_describe(task)}: {exc}")
    return SolverFailed(f"row {_describe(task)} failed: {type(exc).__name__}: {exc}")


def _serial(tasks: list[Task]) -> Iterator[dict]:
    for task in tasks:
        try:
            row = run_task(task)
        except (KeyboardInterrupt, SystemExit):
            raise
        except Exception as exc:
            raise _failed(task, exc) from exc
        yield row


def _ignore_sigint() -> None:  # pragma: no cover - runs in the workers
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)


def _run_chunk(tasks: list[Task]) -> list[tuple[int, dict | BaseException]]:  # pragma: no cover - in the workers
    """Run a few tasks in a worker: (index in the chunk, row or the exception it raised)."""
    out: list[tuple[int, dict | BaseException]] = []
    for k, task in enumerate(tasks):
        try:
            out.append((k, run_task(task)))
        except Exception as exc:
            out.append((k, exc))
            break
    return out


def _chunks(tasks: list[Task], workers: int) -> list[list[Task]]:
    """Small batches (about 8 per worker, at most 8 tasks each): fewer round trips, rows still saved often."""
    size = max(1, min(8, len(tasks) // (8 * workers)))
    return [tasks[k:k + size] for k in range(0, len(tasks), size)]


def _pool(tasks: list[Task], workers: int) -> Iterator[dict]:
    import multiprocessing

    context = multiprocessing.get_context("forkserver")
    context.set_forkserver_preload(["solverplan.studies.rule_systems", "solverplan.studies.study"])
    executor = ProcessPoolExecutor(max_workers=min(workers, len(tasks)), mp_context=context, initializer=_ignore_sigint)
    try:
        futures = {executor.submit(_run_chunk, chunk): chunk for chunk in _chunks(tasks, workers)}
        for future in as_completed(futures):
            chunk = futures[future]
            try:
                results = future.result()
            except Exception as exc:
                raise _failed(chunk[0], exc) from exc
            for k, result in results:
                if isinstance(result, BaseException):
                    raise _failed(chunk[k], result) from result
                yield result
    finally:
        executor.shutdown(wait=True, cancel_futures=True)


_SCHEDULER_ADDRESS = re.compile(r"^(?:(?P<scheme>[a-z]+)://)?(?P<host>\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9._-]+)(?::(?P<port>\d{1,5}))?(?P<path>/\S*)?$")

SCHEDULER_PROBE_SECONDS = 5.0
"""How long a ``tcp://`` scheduler may take to accept a plain connection before the study gives up (seconds)."""


def _probe_scheduler(address: str) -> None:
    """Refuse a malformed or unreachable scheduler address in one line, before Dask starts its threads.

    A ``tcp://HOST:PORT`` (or bare ``HOST:PORT``) address must accept a TCP connection within
    :data:`SCHEDULER_PROBE_SECONDS`: a refused or silent port fails at once, where Dask's own client would
    retry for its whole timeout and leave its event loop behind. Other schemes (``tls``, ``ws``, ``inproc``,
    ...) are left to Dask.
    """
    import socket

    if not isinstance(address, str):
        raise InputError(f"--scheduler: expected an address such as tcp://host:8786, got {quote(address)}")
    match = _SCHEDULER_ADDRESS.match(address.strip())
    if match is None:
        raise InputError(f"--scheduler {quote(address)}: expected an address such as tcp://host:8786")
    scheme, host, port = match.group("scheme") or "tcp", match.group("host"), match.group("port")
    if scheme not in ("tcp", "tls", "ws", "wss", "ucx", "inproc"):
        raise InputError(f"--scheduler {quote(address)}: unknown scheme {quote(scheme)} (use tcp, tls, ws, wss, ucx or inproc)")
    if port is not None and not 0 < int(port) < 65536:
        raise InputError(f"--scheduler {quote(address)}: port {port} is not between 1 and 65535")
    if scheme != "tcp":
        return
    try:
        with socket.create_connection((host.strip("[]"), int(port or 8786)), timeout=SCHEDULER_PROBE_SECONDS):
            pass
    except OSError as exc:
        reason = "no answer" if isinstance(exc, TimeoutError) else (exc.strerror or type(exc).__name__).lower()
        raise InputError(f"cannot reach the Dask scheduler at {quote(address)}: {reason}") from None


def _connect(scheduler: Any) -> tuple[Any, bool]:
    """A Dask client for ``scheduler`` (an address, or a Client used as is) and whether we own it."""
    try:
        import distributed
    except ImportError:
        raise InputError("--scheduler needs Dask: pip install 'solverplan[dask]'") from None
    if isinstance(scheduler, distributed.Client):
        return scheduler, False
    _probe_scheduler(scheduler)
    try:
        return distributed.Client(scheduler, timeout="20s", set_as_default=False), True
    except (OSError, TimeoutError, ValueError) as exc:
        raise InputError(f"cannot reach the Dask scheduler at {scheduler}: {exc}") from None


def _dask(tasks: list[Task], client: Any, own: bool) -> Iterator[dict]:
    import distributed

    try:
        futures = client.map(run_task, tasks, pure=False)
        by_key = {f.key: t for f, t in zip(futures, tasks)}
        try:
            for future in distributed.as_completed(futures, loop=client.loop):
                try:
                    row = future.result()
                except Exception as exc:
                    raise _failed(by_key[future.key], exc) from exc
                yield row
        finally:
            client.cancel([f for f in futures if not f.done()])
    finally:
        if own:
            client.close()


# ---------------------------------------------------------------------- running
class _Terminate:
    """Turn SIGTERM into KeyboardInterrupt while a study runs (main thread only), so it stops cleanly."""

    def __enter__(self) -> None:
        self.old = None
        if threading.current_thread() is threading.main_thread():
            def handler(signum: int, frame: Any) -> None:
                raise KeyboardInterrupt

            self.old = signal.signal(signal.SIGTERM, handler)

    def __exit__(self, *exc: object) -> None:
        if self.old is not None:
            signal.signal(signal.SIGTERM, self.old)


def run_study(
    study: Study,
    out_dir: str | os.PathLike[str] | None = None,
    *,
    workers: int | None = None,
    scheduler: Any = None,
    resume: bool = True,
    progress: Progress | None = None,
) -> StudyResult:
    """Compute every row of ``study`` not already in ``out_dir`` and write its tables there.

    A script that runs a study on the local pool must guard its entry point with
    ``if __name__ == "__main__":`` (the workers start by the ``forkserver`` method, which re-imports
    the main module).

    Parameters
    ----------
    study
        The study (:class:`~solverplan.studies.study.Study`).
    out_dir
        Folder of the rows file and tables (module docstring); ``None`` keeps everything in memory
        (no resume).
    workers
        Local processes (default :func:`default_workers`); 1 runs in this process.
    scheduler
        A Dask scheduler address or :class:`distributed.Client`; when given, ``workers`` is ignored.
    resume
        Reuse the finished rows in ``out_dir`` (default); ``False`` starts over.
    progress
        :data:`Progress` callback (the CLI's progress bar).

    Raises
    ------
    StudyInterrupted
        On SIGINT / SIGTERM; the finished rows are saved, and the same call resumes.
    InputError
        A bad parameter (also from a row: its cell, replicate and seed are named), an output folder
        holding another study, an unreachable scheduler.
    SolverFailed
        A row failed (named as above); the other finished rows are saved.
    """
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise InputError(f"expected workers >= 1, got workers={workers!r}")
    n_workers = workers or default_workers()
    start = time.perf_counter()
    tasks = study.tasks()
    study.check_parameters()  # a bad value is reported before anything is written
    client, own = _connect(scheduler) if scheduler is not None else (None, False)  # before anything is written
    paths = output_paths(study, out_dir) if out_dir is not None else None
    store = RowStore(paths["rows"], study) if paths else None
    try:
        done_rows = store.open(resume=resume) if store else {}
    except BaseException:
        if own and client is not None:  # own implies a client
            client.close()
        raise
    todo = [t for t in tasks if t.key not in done_rows]
    reused = len(tasks) - len(todo)
    if client is not None:
        engine: dict = {"engine": "dask", "scheduler": str(client.scheduler.address)}
        if todo:
            rows_iter = _dask(todo, client, own)  # closes a client it owns when done
        else:
            if own:
                client.close()
            rows_iter = iter(())
    elif n_workers == 1 or len(todo) <= 1:
        engine = {"engine": "local", "workers": 1}
        rows_iter = _serial(todo)
    else:
        engine = {"engine": "local", "workers": min(n_workers, len(todo))}
        rows_iter = _pool(todo, n_workers)
    logger.info("study %s: %d rows, %d to compute (%s)", study.name, len(tasks), len(todo), engine)
    new: list[dict] = []
    try:
        with _Terminate():
            if progress:
                progress(reused, len(tasks))
            try:
                for row in rows_iter:
                    if store:
                        store.append(row)
                    new.append(row)
                    logger.debug("row %d of %d done: cell %d, replicate %d", reused + len(new), len(tasks), row["cell"],
                                 row["replicate"])
                    if progress:
                        progress(reused + len(new), len(tasks))
            except KeyboardInterrupt:
                saved = store.saved_count() if store else reused + len(new)
                raise StudyInterrupted(
                    f"study {study.name} interrupted after {saved} of {len(tasks)} rows"
                    + (f"; its rows are in {paths['rows']}: run it again to finish" if paths else "")
                ) from None
            finally:
                close = getattr(rows_iter, "close", None)
                if close:
                    close()
    finally:
        if store:
            store.close()
        if own and client is not None and client.status not in ("closed", "closing"):  # a client the engine never got to use
            client.close()
    by_key = dict(done_rows)
    by_key.update({study.key_of(r): r for r in new})
    rows = []
    for task in tasks:
        row = dict(by_key[task.key])
        row["cell"] = task.cell  # the cell's index in *this* grid
        rows.append({c: row.get(c) for c in study.columns})
    seconds = time.perf_counter() - start
    table = StudyTable(study, tuple(rows), stats={"seconds": round(seconds, 3), "computed": len(todo), "reused": reused,
                                                  **engine})
    files: dict[str, str] = {}
    if paths:
        files["rows"] = str(paths["rows"])
        _write(paths["csv"], table.to_csv())
        files["csv"] = str(paths["csv"])
        _write(paths["json"], json.dumps(table.to_json(), indent=1) + "\n")
        files["json"] = str(paths["json"])
    return StudyResult(table, files, computed=len(todo), reused=reused, seconds=seconds, engine=engine)


def _write(path: Path, text: str) -> None:
    try:
        atomic_write_text(path, text)
    except OSError as exc:
        raise InputError(cannot_write(path, exc)) from None
