"""Every kind of answer solverplan gives, and what each kind can do: the registry of answer kinds.

An answer's JSON says what it is in its first key, ``kind`` (:data:`solverplan.result.ANSWER_KEY_ORDER`); this
module maps each kind to its class (:func:`solverplan.result.answer_dataclass` registered it) and to its hooks:

- ``read``: read the JSON back into the typed answer (``cls.from_json``); the kinds whose JSON is a summary of what
  they computed (simulations, studies, room simulations, imports: their arrays are not written) read back as an
  :class:`AnswerSummary`, their JSON checked key by key;
- ``certificate``: :func:`solverplan.certify.build.certificate`, which dispatches on the answer's type (it raises
  :class:`TypeError` for an answer it cannot certify, :class:`~solverplan.certify.build.NothingToCertify` for one
  with nothing to claim); ``check``: :func:`solverplan.certify.check.check_certificate`, the one exact checker;
- ``picture``: the matplotlib figure of the answer (``None`` when it has none);
- ``report``: :func:`solverplan.render.report.make_report` (every kind has a report).

The kinds are kinds of *answers*, not of robots: a robot model answers in several kinds (the wall-following robot:
``cut-ordering``, ``learned-ordering``, ``vertex-count``, ``pursuit``).

>>> sorted(KINDS)[:4]
['controller', 'cut-ordering', 'cycle', 'exploration']
>>> from solverplan.environment import Environment
>>> square = Environment.from_coords([[0, 0], [4, 0], [4, 4], [0, 4]], name="square")
>>> from solverplan.plan import find_plan
>>> plan = find_plan(square, "e0", "e2")
>>> read_answer(plan.to_json()).to_json() == plan.to_json()
True
"""

from __future__ import annotations

import copy
import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Mapping

from solverplan.bounce.controller import ConstantController
from solverplan.bounce.cycles import LimitCycle
from solverplan.certify.build import certificate as build_certificate
from solverplan.certify.check import check_certificate
from solverplan.environment import Environment, read_json
from solverplan.errors import InputError, MalformedFile
from solverplan.explore.depth_first import Exploration
from solverplan.explore.range_limited import RangeExploration
from solverplan.floorplan.importer import FloorplanImport
from solverplan.limits import read_text_within_limits
from solverplan.plan.funnels import Funnel
from solverplan.plan.localization import Localization
from solverplan.plan.patrols import Patrol
from solverplan.plan.result import ParetoFront, Plan
from solverplan.rectilinear.decomposition import Decomposition
from solverplan.reflection.navigation import FieldNavigation
from solverplan.render.report import make_report
from solverplan.result import Status, answer_kinds, with_article
from solverplan.rollout import Rollouts
from solverplan.studies.execute import StudyResult
from solverplan.rectilinear.simulation import RoomRuns, RuleComparison
from solverplan.wallfollow.filters import WalkCount
from solverplan.wallfollow.learning import LearnedOrdering
from solverplan.wallfollow.ordering import CutOrdering
from solverplan.wallfollow.pursuit import PursuitPlan

__all__ = ["AnswerKind", "AnswerSummary", "KINDS", "read_answer", "load_answer_file"]


def _picture_rooms(answer: Decomposition) -> Any:
    from solverplan.render.rooms import render_rooms

    return render_rooms(answer)


def _picture_fields(answer: FieldNavigation) -> Any:
    from solverplan.render.fields import render_fields

    return render_fields(answer)


def _picture_answer(answer: Any) -> Any:
    from solverplan.render.answers import render_answer

    return render_answer(answer)


@dataclass(frozen=True)
class AnswerKind:
    """One kind of answer: its class and hooks (module docstring)."""

    kind: str
    cls: type
    needs_env: bool
    read: Callable[..., Any]
    certificate: Callable[..., Any] = build_certificate
    check: Callable[..., Any] = check_certificate
    picture: Callable[[Any], Any] | None = None
    report: Callable[..., Any] = make_report


@dataclass(frozen=True)
class AnswerSummary:
    """A summary answer read back (a simulation, a rooms simulation or comparison, a study, an import): its JSON,
    checked key by key, under its ``kind``; ``source`` is the class that wrote it, whose arrays (trajectories, tables,
    rings) the JSON does not hold. ``to_json()`` is the JSON read.

    >>> import solverplan as sp
    >>> from solverplan.simulate import simulate_rule
    >>> from solverplan.bounce.rules import Fixed
    >>> runs = simulate_rule(sp.load_environment("square"), Fixed(0.5), "e0", bounces=5, trials=10, seed=1)
    >>> back = read_answer(runs.to_json())
    >>> back.kind, back.source.__name__, back.to_json() == runs.to_json()
    ('simulation', 'Rollouts', True)
    """

    kind: str
    source: type
    data: Mapping[str, Any]

    @property
    def status(self) -> Status | None:
        """The answer's status, for the kinds that write one (imports)."""
        value = self.data.get("status")
        return Status(value) if isinstance(value, str) else None

    def to_json(self) -> dict:
        """The JSON read (a copy)."""
        return copy.deepcopy(dict(self.data))

    def to_text(self, *, width: int = 100) -> str:
        """Its plain values, one a line (the lists and objects counted)."""
        lines = [f"{self.kind} (a summary of a {self.source.__name__}, read back)"]
        for key, value in self.data.items():
            if key == "kind":
                continue
            shown = (f"{len(value)} entries" if isinstance(value, (dict, list)) else str(value))
            lines.append(f"{key}: {shown}"[:width])
        return "\n".join(lines) + "\n"


_SUMMARY_KEYS: dict[str, dict[str, type | tuple[type, ...]]] = {
    "simulation": {"environment": str, "policy": str, "bounces": (dict, type(None)), "seed": (int, type(None)),
                   "ties": str, "trials": int, "outcomes": dict, "success_rate": (int, float),
                   "flagged_rate": (int, float)},
    "rooms-simulation": {"rule": str, "from": int, "to": int, "rooms": list, "trials": int, "max_bounces": int,
                         "doors": str, "success": (int, float), "trapped": int, "outcomes": dict},
    "rooms-rules": {"rules": dict, "rooms": list, "recommended": str},
    "study": {"study": dict, "files": dict, "rows": int, "computed": int, "reused": int, "means": dict,
              "cells": list},
    "import": {"status": str, "written": (str, type(None)), "outer_vertices": int, "holes": int, "area": (int, float),
               "format": str, "source": str, "name": str, "vertices": int},
}
"""The keys every summary of a kind holds and their JSON types: what :func:`read_answer` checks."""


def _summary_reader(cls: type) -> Callable[..., AnswerSummary]:
    kind = cls.kind  # type: ignore[attr-defined]

    def read(data: Mapping[str, Any], *, env: Environment | None = None) -> AnswerSummary:
        for key, types in _SUMMARY_KEYS[kind].items():
            if key not in data:
                raise MalformedFile(f"{kind}: no {key!r} (a {kind} summary holds {', '.join(_SUMMARY_KEYS[kind])})")
            value = data[key]
            if isinstance(value, bool) or not isinstance(value, types):
                raise MalformedFile(f"{kind}.{key}: unexpected value {json.dumps(value)[:60]}")
        if "status" in data:
            try:
                Status(data["status"])
            except ValueError:
                raise MalformedFile(f"{kind}.status: unknown status {data['status']!r}") from None
        return AnswerSummary(kind, cls, copy.deepcopy(dict(data)))

    return read


def _kind(cls: type, *, needs_env: bool, read: bool = True, picture: Callable[[Any], Any] | None = None) -> AnswerKind:
    reader = cls.from_json if read else _summary_reader(cls)  # type: ignore[attr-defined]
    return AnswerKind(cls.kind, cls, needs_env, reader, picture=picture)  # type: ignore[attr-defined]


KINDS: dict[str, AnswerKind] = {k.kind: k for k in (
    _kind(Plan, needs_env=False),
    _kind(ParetoFront, needs_env=False),
    _kind(Patrol, needs_env=True, picture=_picture_answer),
    _kind(Funnel, needs_env=True, picture=_picture_answer),
    _kind(Localization, needs_env=True, picture=_picture_answer),
    _kind(LimitCycle, needs_env=True),
    _kind(ConstantController, needs_env=True),
    _kind(Decomposition, needs_env=True, picture=_picture_rooms),
    _kind(Exploration, needs_env=True),
    _kind(RangeExploration, needs_env=True),
    _kind(CutOrdering, needs_env=False),
    _kind(LearnedOrdering, needs_env=False),
    _kind(WalkCount, needs_env=False),
    _kind(PursuitPlan, needs_env=True),
    _kind(FieldNavigation, needs_env=True, picture=_picture_fields),
    _kind(Rollouts, needs_env=False, read=False),
    _kind(RoomRuns, needs_env=False, read=False),
    _kind(RuleComparison, needs_env=False, read=False),
    _kind(StudyResult, needs_env=False, read=False),
    _kind(FloorplanImport, needs_env=False, read=False),
)}
"""Every answer kind and its hooks, by kind."""

assert set(KINDS) == set(answer_kinds()), "an answer class is registered without hooks (or hooks without a class)"


def read_answer(data: object, *, env: Environment | None = None) -> Any:
    """The typed answer of an answer's JSON, by its ``kind``.

    Parameters
    ----------
    data
        An answer's JSON (``answer.to_json()``, or a file a command wrote with ``-o``, parsed).
    env
        The environment the answer was made in: required for the kinds that name its edges (``needs_env``).

    Returns
    -------
    Answer
        The answer of the class :data:`KINDS` names (an :class:`AnswerSummary` for the kinds whose JSON is a
        summary); its ``to_json()`` is ``data`` again.

    Examples
    --------
    >>> from solverplan.wallfollow.cut import cut_ordering
    >>> from solverplan.models import load
    >>> answer = read_answer(cut_ordering(load("l_shape")).to_json())
    >>> answer.kind, answer.labels[:3]
    ('cut-ordering', ('v0', 'l3', 'v1'))

    Raises
    ------
    MalformedFile
        No ``kind``, an unknown kind, or a malformed answer.
    InputError
        ``env`` is needed (the answer names its edges) and missing or not the answer's environment.
    """
    if not isinstance(data, dict) or not isinstance(data.get("kind"), str):
        raise MalformedFile("not an answer: expected a JSON object whose 'kind' says what it is")
    entry = KINDS.get(data["kind"])
    if entry is None:
        raise MalformedFile(f"unknown answer kind {data['kind']!r}: known kinds are {', '.join(sorted(KINDS))}")
    if entry.needs_env and env is None:
        raise InputError(f"{with_article(entry.kind)} answer is read back in its environment: give it")
    return entry.read(data, env=env)


def load_answer_file(path: str | Path, *, env: Environment | None = None) -> Any:
    """:func:`read_answer` of a file (within the input limits; bad JSON is :class:`MalformedFile` naming the file).

    Parameters
    ----------
    path
        The answer file, as a command wrote it with ``-o``.
    env
        The environment, for the kinds that need it.

    Returns
    -------
    Answer
        The typed answer.

    Examples
    --------
    >>> import json, tempfile, os
    >>> from solverplan.wallfollow.cut import cut_ordering
    >>> from solverplan.models import load
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = os.path.join(folder, "a.json")
    ...     _ = open(path, "w").write(json.dumps(cut_ordering(load("l_shape")).to_json()))
    ...     load_answer_file(path).kind
    'cut-ordering'
    """
    text = read_text_within_limits(Path(path))
    try:
        data = read_json(text, exact=False)
    except json.JSONDecodeError as exc:
        raise MalformedFile(f"{path}: not valid JSON ({exc.msg} at line {exc.lineno})") from None
    try:
        return read_answer(data, env=env)
    except MalformedFile as exc:
        raise MalformedFile(f"{path}: {exc}") from None
