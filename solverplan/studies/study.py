"""A study: a grid of generator parameters × N seeds per cell → one tidy row per environment.

A :class:`Study` names a generator (:data:`~solverplan.generators.GENERATORS`), the grid of
its parameters (axes with one value are fixed parameters), the metric's own option axes (the rules
study's ``rule``), ``per_cell`` replicates and a base ``seed``. Its :meth:`~Study.tasks` are the rows
to compute, in table order: cells in grid order (the product of the axes, last axis fastest), then
replicates 0..per_cell−1.

**Row seeds.** Replicate k of a cell draws its environment with the seed
``row_seed(base seed, generator, generator parameters, k)`` (a 32-bit hash, :func:`row_seed`): it
depends on the generator's parameters and k only, so

- any row is regenerated from the row alone: ``generate(row generator, seed=row["seed"], **params)``;
- the cells of a metric option axis (the rules study's ``rule``) see the **same** environments;
- adding values to an axis or replicates to a study keeps the rows already computed valid (a resumed
  study reuses them).

**Rows.** :func:`run_task` generates the environment and calls the metric; the row is a flat dict:
``cell`` (index in the grid), ``replicate``, ``seed``, the generator parameters, the metric options,
``vertices``, ``holes``, the metric's columns, and ``seconds`` (wall time of the row; the only column
that differs between two runs of the same study).
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
import re
import time
from dataclasses import dataclass, field
from typing import Any, Iterable, Mapping, Sequence

import numpy as np

from solverplan.errors import InputError
from solverplan.generators import GENERATORS, generate
from solverplan.studies.metrics import Metric

__all__ = [
    "Study",
    "Task",
    "Heatmap",
    "StudyTable",
    "parse_values",
    "parse_grid",
    "row_seed",
    "run_task",
    "PAPER_GRID",
    "KEY_COLUMNS",
]

KEY_COLUMNS = ("cell", "replicate", "seed")
"""The first columns of every row; a row is identified by its cell's parameters and its replicate."""

PAPER_GRID: tuple[tuple[str, tuple], ...] = (
    ("n", (20,)),
    ("irregularity", (0.1, 0.175, 0.25, 0.325, 0.4)),
    ("spikiness", (0.1, 0.2, 0.3, 0.4, 0.5)),
)
"""The paper's §7.3 grid: star polygons with 20 vertices, irregularity 0.1..0.4 × spikiness 0.1..0.5 (5 × 5)."""

_NUMBER = re.compile(r"^[+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?$")


# ---------------------------------------------------------------------- parameter values
def _value(text: str) -> int | float | str:
    t = text.strip()
    if re.fullmatch(r"[+-]?\d+", t):
        return int(t)
    if _NUMBER.match(t):
        return _tidy(float(t))
    if t.lower() in ("true", "false"):
        raise InputError(f"parameter value {t!r}: booleans are not grid values")
    return t


def _tidy(x: float) -> float:
    """Round away float noise (0.1 + 3 × 0.075 → 0.325) so values print and hash as typed."""
    return float(f"{x:.12g}")


def parse_values(text: str, *, name: str = "value") -> tuple:
    """Grid values from their spelling: ``20``, ``0.1,0.2,0.4`` (a list), ``0.1:0.4:5`` (5 values
    evenly spaced from 0.1 to 0.4, both included), or words (``convex,star``).

    >>> parse_values("0.1:0.4:5")
    (0.1, 0.175, 0.25, 0.325, 0.4)
    >>> parse_values("20"), parse_values("4,8"), parse_values("convex")
    ((20,), (4, 8), ('convex',))
    >>> parse_values("0.1:0.4", name="irregularity")
    Traceback (most recent call last):
    ...
    solverplan.errors.InputError: irregularity: expected VALUE, V1,V2,... or START:STOP:COUNT, got '0.1:0.4'
    """
    if not isinstance(text, str) or not text.strip():
        raise InputError(f"{name}: expected VALUE, V1,V2,... or START:STOP:COUNT, got {text!r}")
    if ":" in text:
        parts = text.split(":")
        if len(parts) != 3 or not all(_NUMBER.match(p.strip()) for p in parts[:2]) or not parts[2].strip().isdigit():
            raise InputError(f"{name}: expected VALUE, V1,V2,... or START:STOP:COUNT, got {text!r}")
        start, stop, count = float(parts[0]), float(parts[1]), int(parts[2])
        if count < 1:
            raise InputError(f"{name}: START:STOP:COUNT needs COUNT >= 1, got {text!r}")
        if count == 1:
            return (_tidy(start),)
        values: tuple[int | float | str, ...] = tuple(_tidy(v) for v in np.linspace(start, stop, count))
        if all(float(v).is_integer() for v in values) and all(_NUMBER.match(p) and "." not in p for p in parts[:2]):
            values = tuple(int(v) for v in values)
        return values
    values = tuple(_value(part) for part in text.split(","))
    if any(v == "" for v in values):
        raise InputError(f"{name}: empty value in {text!r}")
    if len(set(values)) != len(values):
        raise InputError(f"{name}: repeated value in {text!r}")
    return values


def parse_grid(specs: Iterable[str], *, base: Sequence[tuple[str, tuple]] = ()) -> tuple[tuple[str, tuple], ...]:
    """Axes from ``NAME=VALUES`` strings (:func:`parse_values`), replacing or extending ``base``.

    >>> parse_grid(["spikiness=0.2", "n=12"], base=PAPER_GRID)
    (('n', (12,)), ('irregularity', (0.1, 0.175, 0.25, 0.325, 0.4)), ('spikiness', (0.2,)))
    """
    axes = dict(base)
    for spec in specs:
        name, sep, values = spec.partition("=")
        name = name.strip()
        if not sep or not re.fullmatch(r"[a-z_][a-z0-9_]*", name):
            raise InputError(f"grid axis {spec!r}: expected NAME=VALUES, e.g. spikiness=0.1:0.5:5")
        axes[name] = parse_values(values, name=name)
    return tuple(axes.items())


def row_seed(base_seed: int, generator: str, params: Mapping[str, Any], replicate: int) -> int:
    """The seed of replicate ``replicate`` of the cell with generator ``params`` (32 bits, stable).

    >>> row_seed(0, "star", {"n": 20, "irregularity": 0.1, "spikiness": 0.1}, 0)
    3359378886
    """
    text = json.dumps([int(base_seed), generator, sorted(params.items()), int(replicate)], separators=(",", ":"))
    return int.from_bytes(hashlib.blake2b(text.encode(), digest_size=4).digest(), "big")


# ---------------------------------------------------------------------- the study
@dataclass(frozen=True)
class Task:
    """One row to compute: everything a worker needs (small and picklable)."""

    cell: int
    replicate: int
    seed: int
    generator: str
    params: tuple[tuple[str, Any], ...]
    options: tuple[tuple[str, Any], ...]
    metric: Metric

    @property
    def key(self) -> str:
        return row_key(dict(self.params), dict(self.options), self.replicate)


def row_key(params: Mapping[str, Any], options: Mapping[str, Any], replicate: int) -> str:
    """The identity of a row: its cell's parameter values and its replicate (canonical JSON)."""
    return json.dumps([sorted(params.items()), sorted(options.items()), int(replicate)], separators=(",", ":"))


@dataclass(frozen=True)
class Study:
    """A grid of generator parameters × ``per_cell`` seeds, measured by ``metric`` (module docstring).

    >>> from solverplan.studies.metrics import ReachabilityMetric
    >>> study = Study(ReachabilityMetric(), per_cell=2, grid=(("n", (8,)), ("irregularity", (0.1, 0.3)), ("spikiness", (0.2,))))
    >>> study.n_cells, len(study.tasks()), study.axes
    (2, 4, ('irregularity',))
    >>> study.columns[:6]
    ('cell', 'replicate', 'seed', 'n', 'irregularity', 'spikiness')
    """

    metric: Metric
    generator: str = "star"
    grid: tuple[tuple[str, tuple], ...] = PAPER_GRID
    per_cell: int = 10
    seed: int = 0
    name: str = ""

    def __post_init__(self) -> None:
        if self.generator not in GENERATORS:
            raise InputError(f"unknown generator {self.generator!r}: use {', '.join(GENERATORS)}")
        if isinstance(self.per_cell, bool) or not isinstance(self.per_cell, int) or self.per_cell < 1:
            raise InputError(f"expected per_cell >= 1, got per_cell={self.per_cell!r}")
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise InputError(f"expected a seed >= 0, got seed={self.seed!r}")
        grid = tuple((str(k), tuple(v)) for k, v in self.grid)
        names = [k for k, _ in grid] + [k for k, _ in self.metric.options]
        for k, values in (*grid, *self.metric.options):
            if not values:
                raise InputError(f"grid axis {k!r} has no values")
        if len(set(names)) != len(names):
            raise InputError(f"grid axes repeat a name: {', '.join(names)}")
        reserved = set(KEY_COLUMNS) | {"vertices", "holes", "seconds"} | set(self.metric.columns)
        clash = sorted(reserved & set(names))
        if clash:
            raise InputError(f"grid axis {clash[0]!r} clashes with a column of the table")
        import inspect

        accepted = inspect.signature(GENERATORS[self.generator]).parameters
        for k, _ in grid:
            if k not in accepted or k == "seed":
                usable = ", ".join(p for p in accepted if p != "seed")
                raise InputError(f"generator {self.generator!r} has no parameter {k!r}: use {usable}")
        missing = [p.name for p in accepted.values() if p.default is inspect.Parameter.empty
                   and p.kind is not inspect.Parameter.VAR_KEYWORD and p.name not in dict(grid) and p.name != "seed"]
        if missing:
            raise InputError(f"generator {self.generator!r} needs a value for {missing[0]!r} (--grid {missing[0]}=VALUES)")
        object.__setattr__(self, "grid", grid)
        object.__setattr__(self, "name", self.name or self.metric.name)

    # ------------------------------------------------------------------ shape
    @property
    def option_axes(self) -> tuple[tuple[str, tuple], ...]:
        return tuple(self.metric.options)

    @property
    def all_axes(self) -> tuple[tuple[str, tuple], ...]:
        return (*self.grid, *self.option_axes)

    @property
    def axes(self) -> tuple[str, ...]:
        """The generator axes with more than one value (the heatmap's axes: the last two)."""
        return tuple(k for k, v in self.grid if len(v) > 1)

    @property
    def n_cells(self) -> int:
        return math.prod(len(v) for _, v in self.all_axes)

    @property
    def columns(self) -> tuple[str, ...]:
        return (*KEY_COLUMNS, *(k for k, _ in self.all_axes), "vertices", "holes", *self.metric.columns, "seconds")

    def cells(self) -> list[tuple[dict, dict]]:
        """(generator parameters, metric options) of every cell, in grid order."""
        gen_names = [k for k, _ in self.grid]
        opt_names = [k for k, _ in self.option_axes]
        out = []
        for values in itertools.product(*(v for _, v in self.all_axes)):
            out.append((dict(zip(gen_names, values[: len(gen_names)])), dict(zip(opt_names, values[len(gen_names):]))))
        return out

    def tasks(self) -> list[Task]:
        """Every row of the study, in table order."""
        out = []
        for cell, (params, options) in enumerate(self.cells()):
            for k in range(self.per_cell):
                out.append(Task(cell, k, row_seed(self.seed, self.generator, params, k), self.generator,
                                tuple(params.items()), tuple(options.items()), self.metric))
        return out

    def check_parameters(self) -> None:
        """Raise the generator's own :class:`InputError` for a bad parameter value in any cell, before any work.

        Each distinct cell draws one candidate (``max_attempts=1``); failing to find a valid polygon in
        one try is not an error here, only a rejected parameter is.
        """
        from solverplan.errors import InvalidEnvironment

        for params in {json.dumps(sorted(p.items())): p for p, _ in self.cells()}.values():
            try:
                generate(self.generator, seed=0, **{"max_attempts": 1, **params})
            except InvalidEnvironment:
                pass
            except InputError as exc:
                cell = ", ".join(f"{k}={v}" for k, v in params.items())
                raise InputError(f"cell ({cell}): {exc}") from None

    def key_of(self, row: Mapping[str, Any]) -> str:
        """The key of a row of this study (its cell's parameters and replicate): :attr:`Task.key`."""
        return row_key({k: row[k] for k, _ in self.grid}, {k: row[k] for k, _ in self.option_axes}, row["replicate"])

    def identity(self) -> dict:
        """What rows depend on besides their own cell and replicate (a resumed output must match it)."""
        return {"study": self.name, "generator": self.generator, "seed": self.seed, "metric": self.metric.spec(),
                "axes": [k for k, _ in self.all_axes]}

    def to_json(self) -> dict:
        return {**self.identity(), "grid": {k: list(v) for k, v in self.all_axes}, "per_cell": self.per_cell,
                "cells": self.n_cells, "rows": self.n_cells * self.per_cell}


def run_task(task: Task) -> dict:
    """Compute one row (module docstring): generate the environment, measure it, time it."""
    start = time.perf_counter()
    params, options = dict(task.params), dict(task.options)
    env = generate(task.generator, seed=task.seed, **params)
    values = task.metric(env, seed=task.seed, **options)
    missing = [c for c in task.metric.columns if c not in values]
    if missing:
        raise InputError(f"metric {task.metric.name!r} returned no {missing[0]!r}")
    row = {"cell": task.cell, "replicate": task.replicate, "seed": task.seed, **params, **options,
           "vertices": env.n_vertices, "holes": len(env.holes)}
    row.update({c: _plain(values[c]) for c in task.metric.columns})
    row["seconds"] = round(time.perf_counter() - start, 6)
    return row


def _plain(value: Any) -> Any:
    if isinstance(value, (np.integer,)):
        return int(value)
    if isinstance(value, (np.floating,)):
        return float(value)
    return value


# ---------------------------------------------------------------------- tables
@dataclass(frozen=True)
class Heatmap:
    """Mean of one column over the rows of each (x, y) cell: what render.draw_heatmap draws.

    ``mean[i, j]`` is the mean at y = ``y_values[i]``, x = ``x_values[j]`` (NaN without rows),
    averaged over every other axis; ``count`` the number of rows behind it.
    """

    title: str
    value: str
    x_name: str
    x_values: tuple
    y_name: str
    y_values: tuple
    mean: np.ndarray
    count: np.ndarray

    @property
    def overall(self) -> float:
        """The mean over all rows behind the heatmap."""
        total = float(np.nansum(self.mean * self.count))
        n = int(self.count.sum())
        return total / n if n else float("nan")


@dataclass(frozen=True)
class StudyTable:
    """The rows of a study in table order (one per cell × replicate), with per-cell summaries."""

    study: Study
    rows: tuple[dict, ...]
    stats: dict = field(default_factory=dict)

    @property
    def columns(self) -> tuple[str, ...]:
        return self.study.columns

    def column(self, name: str) -> np.ndarray:
        return np.asarray([r[name] for r in self.rows])

    def metric_columns(self) -> tuple[str, ...]:
        return tuple(self.study.metric.columns)

    def cell_summaries(self) -> list[dict]:
        """Per cell: its parameters, the number of rows, and mean / std / min / max of each metric column."""
        by_cell: dict[int, list[dict]] = {}
        for row in self.rows:
            by_cell.setdefault(row["cell"], []).append(row)
        out = []
        for cell, (params, options) in enumerate(self.study.cells()):
            rows = by_cell.get(cell, [])
            entry: dict[str, Any] = {"cell": cell, **params, **options, "rows": len(rows)}
            for c in (*self.metric_columns(), "seconds"):
                values = np.asarray([r[c] for r in rows], dtype=float)
                entry[c] = ({"mean": float(values.mean()), "std": float(values.std()), "min": float(values.min()),
                             "max": float(values.max())} if len(values) else None)
            out.append(entry)
        return out

    def means(self, *, where: Mapping[str, Any] | None = None) -> dict:
        """Mean of each metric column over all rows (or those matching ``where``)."""
        rows = [r for r in self.rows if all(r.get(k) == v for k, v in (where or {}).items())]
        return {c: (float(np.mean([r[c] for r in rows])) if rows else None) for c in (*self.metric_columns(), "seconds")}

    def heatmap(self, value: str, *, where: Mapping[str, Any] | None = None, x: str | None = None,
                y: str | None = None) -> Heatmap:
        """The mean of ``value`` per (x, y), x and y default to the last two varying generator axes."""
        if value not in self.columns:
            raise InputError(f"unknown column {value!r}: columns are {', '.join(self.columns)}")
        axes = self.study.axes
        grid = dict(self.study.all_axes)
        y = y or (axes[-2] if len(axes) >= 2 else None)
        x = x or (axes[-1] if axes else None)
        x_values = tuple(grid[x]) if x else ("",)
        y_values = tuple(grid[y]) if y else ("",)
        total = np.zeros((len(y_values), len(x_values)))
        count = np.zeros((len(y_values), len(x_values)), dtype=np.int64)
        for row in self.rows:
            if where and any(row.get(k) != v for k, v in where.items()):
                continue
            i = y_values.index(row[y]) if y else 0
            j = x_values.index(row[x]) if x else 0
            total[i, j] += float(row[value])
            count[i, j] += 1
        with np.errstate(invalid="ignore", divide="ignore"):
            mean = np.where(count > 0, total / np.maximum(count, 1), np.nan)
        label = ", ".join(f"{k}={v}" for k, v in (where or {}).items())
        title = getattr(self.study.metric, "labels", {}).get(value, value)
        title = f"{label}: {title}" if label else title
        return Heatmap(title, value, x or "", x_values, y or "", y_values, mean, count)

    def heatmaps(self) -> list[Heatmap]:
        """The study's panels (its metric's ``panels``), in order."""
        return [self.heatmap(value, where=where or None) for value, where in self.study.metric.panels]

    def panel_columns(self) -> int:
        """Panels per row of the figure: one row per distinct value when several panels share it."""
        values = [v for v, _ in self.study.metric.panels]
        per_value = values.count(values[0]) if values else 1
        return per_value if per_value > 1 else max(len(values), 1)

    # ------------------------------------------------------------------ output formats
    def to_csv(self) -> str:
        """The rows as CSV (header = :attr:`columns`); floats at full precision (``repr``)."""
        import csv
        import io

        buffer = io.StringIO()
        writer = csv.writer(buffer, lineterminator="\n")
        writer.writerow(self.columns)
        for row in self.rows:
            writer.writerow([repr(v) if isinstance(v, float) else v for v in (row.get(c) for c in self.columns)])
        return buffer.getvalue()

    def to_json(self) -> dict:
        """``{"study", "columns", "rows", "cells", "means", "stats"}``: rows as objects, cells summarised."""
        return {
            "study": self.study.to_json(),
            "columns": list(self.columns),
            "rows": [{c: r.get(c) for c in self.columns} for r in self.rows],
            "cells": self.cell_summaries(),
            "means": self.means(),
            "stats": self.stats,
        }
