"""Check before it leaves: every answer is verified by the independent exact checker before it is given.

:func:`checked_answer` runs a query, turns its answer into certificates (:func:`~solverplan.certify.build.certificate`:
a plan, **every point** of a Pareto front, a patrol, a funnel, a localisation strategy; and the other models' answers:
rooms, an exploration, a cut ordering, a pursuit plan, composed fields) and checks each one with
:func:`~solverplan.certify.check.check_certificate`, against the query's environment, start and goal sets. The
checker shares no code with the planner, the graph builder or the graph cache, so an answer computed from a
corrupt or forged cached graph (arcs marked safe that are not, shifted intervals) is caught here, whatever the
cache's own checks said. When a check fails, the cached graphs are discarded (memory, and the disk entries this
process read: :func:`~solverplan.bounce._cache.discard_graphs`), the query runs again with freshly built graphs
(:func:`~solverplan.bounce._cache.fresh_graphs`), and that answer is checked in turn; if it fails again the
answer is refused with :class:`AnswerNotVerified` (the command line: one line, exit 1) — an unsound answer never
leaves.

Answers that say there is **no** plan are checked through their infeasibility certificates (an inductive invariant
of belief states, :mod:`solverplan.certify.negative`) when one can be made; when none can (a plan exists only
without the planner's margins, or the answer is a search that found nothing) it passes unchecked and
:attr:`Checked.unchecked` says why. Either way, an answer that there is no plan made with graphs read from the disk
cache is made again with freshly built graphs before it leaves: a forged entry that drops arcs would look just like
it, and a certificate speaks of its own class of plans (landings on the segments of its table), not exactly of the
planner's. Optimality bounds are
checked where the certificate carries a bound block (fewest and tolerance plans); otherwise for consistency only.

>>> from solverplan.environment import Environment
>>> from solverplan.plan import find_plan
>>> square = Environment.from_coords([[0, 0], [10, 0], [10, 10], [0, 10]], name="square")
>>> checked = checked_answer(lambda: find_plan(square, "e0", "e2"), env=square, start="e0", goal="e2")
>>> checked.answer.bounces, checked.checked, checked.retried, checked.unchecked
(2, 1, False, None)
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass
from typing import Any, Callable, Generic, TypeVar

from solverplan.bounce._cache import discard_graphs, fresh_graphs, read_from_disk
from solverplan.certify import build
from solverplan.certify.build import NothingToCertify
from solverplan.certify.check import CheckReport, CheckStopped, check_certificate
from solverplan.certify.schema import Certificate, ModelCertificate
from solverplan.environment import Environment
from solverplan.errors import InputError, SolverFailed
from solverplan.plan.result import ParetoFront, Plan

__all__ = ["checked_answer", "Checked", "AnswerNotVerified", "check_infeasibility"]

logger = logging.getLogger(__name__)

T = TypeVar("T")


class AnswerNotVerified(SolverFailed):
    """An answer failed the exact check twice, the second time computed with freshly built graphs: an internal
    failure (CLI exit 1), never an answer given. ``failure`` names the claim that does not hold."""

    def __init__(self, what: str, failure: str) -> None:
        self.failure = failure
        super().__init__(f"the {what} failed its exact check, even with freshly built graphs: {failure}")


@dataclass(frozen=True)
class Checked(Generic[T]):
    """A verified answer.

    ``answer``
        The query's answer, as computed.
    ``certificate``
        Its certificate, already checked (a Pareto front: its most tolerant plan's, as
        :func:`~solverplan.certify.build.certificate` makes it); ``None`` when there is nothing to certify.
    ``checked``
        The number of certificates checked (every point of a Pareto front).
    ``retried``
        The first answer failed its check; this one was computed again with freshly built graphs.
    ``unchecked``
        Why the answer could not be checked (an infeasible answer, for now), ``None`` when it was.
    ``seconds``
        Time spent making and checking certificates.
    ``stopped``
        The check reached the caller's ``stop_at`` before deciding: the answer leaves unchecked, its optimality
        marked not proved with the reason among its limits, and no certificate is given.
    """

    answer: T
    certificate: Certificate | ModelCertificate | None
    checked: int
    retried: bool = False
    unchecked: str | None = None
    seconds: float = 0.0
    stopped: bool = False


def checked_answer(compute: Callable[[], T], *, env: Environment | None = None, start: str | None = None,
                   goal: str | None = None, stop_at: float | None = None) -> Checked[T]:
    """``compute()``'s answer, once the independent exact checker has verified it (module docstring).

    Parameters
    ----------
    compute
        Runs the query and returns its answer (a plan, a Pareto front, a patrol, a funnel or a localisation
        strategy); called again, with no graph reused, if the first answer fails its check.
    env
        The query's environment: the certificate must be about exactly these rings. Required for plans and
        Pareto fronts (they do not carry their environment); the other answers carry theirs.
    start, goal
        The query's start and goal sets (boundary-set text, e.g. ``"e0:0.2:0.8"``), when it has them: the
        certificate must answer exactly this query.
    stop_at
        A :func:`time.monotonic` time (the end of a ``--timeout``) past which the check stops: the answer then
        leaves unchecked, not proved, with the reason among its optimality limits (:attr:`Checked.stopped`) — the
        user's time limit wins over the check, and says so. ``None``: the check always completes.

    Raises
    ------
    AnswerNotVerified
        The answer failed its check twice (the second time with freshly built graphs).
    TypeError
        A plan or Pareto front without ``env``.

    Notes
    -----
    If ``compute`` itself raises (anything but :class:`~solverplan.errors.InputError`) after using a graph read from
    the disk cache, the graphs are discarded and ``compute`` runs once more with fresh ones: a forged graph may break
    the planner rather than its answer. Without a graph read from disk, the error propagates unchanged.
    """
    try:
        answer = compute()
    except InputError:
        raise  # bad input is bad input, whatever the cache holds
    except Exception as exc:
        if not read_from_disk():
            raise
        # a graph read from the disk cache may be what broke the query: answer again without it
        logger.warning("the query failed with graphs read from the cache (%s: %s): discarding them and answering again",
                       type(exc).__name__, exc)
        discard_graphs()
        with fresh_graphs():
            answer = compute()
        return _accept(answer, _verify(answer, env, start, goal, stop_at), retried=True)
    verdict = _verify(answer, env, start, goal, stop_at)
    if verdict.stopped:
        logger.warning("the %s leaves unchecked: %s", _what(answer), verdict.unchecked)
        return verdict.result(answer)
    if verdict.failure is None and _says_none(answer) and read_from_disk():
        # an answer that there is no plan, made with graphs from the disk cache: a forged entry that drops arcs would
        # look just like it, and its certificate (when one can be made) speaks of its own class of plans, not exactly
        # of the planner's — so the answer given is the one made with freshly built graphs
        logger.info("the %s says there is no plan and used cached graphs: answering again with fresh ones",
                    _what(answer))
        with fresh_graphs():
            answer = compute()
        return _accept(answer, _verify(answer, env, start, goal, stop_at), retried=True)
    if verdict.failure is None:
        logger.debug("the %s passed its exact check (%d certificates, %.3f s)", _what(answer), verdict.checked,
                     verdict.seconds)
        return verdict.result(answer)
    logger.warning("the %s failed its exact check (%s): discarding the cached graphs and answering again",
                   _what(answer), verdict.failure)
    discard_graphs()
    with fresh_graphs():
        answer = compute()
    return _accept(answer, _verify(answer, env, start, goal, stop_at), retried=True)


def _says_none(answer: Any) -> bool:
    """Does the answer claim, proved, that there is no plan (infeasible, an empty front)? A search stopped by its
    timeout or caps claims nothing (and answering it again would double the time the user allowed)."""
    empty = not answer.points if isinstance(answer, ParetoFront) else not getattr(answer, "found", True)
    optimality = getattr(answer, "optimality", None)
    return empty and optimality is not None and bool(optimality.proved) and not getattr(optimality, "limits", ())


def _not_proved(answer: T, why: str) -> T:
    """``answer`` with its optimality (when it has one) marked not proved and ``why`` among its limits."""
    from dataclasses import is_dataclass, replace

    optimality = getattr(answer, "optimality", None)
    if optimality is None or not is_dataclass(optimality) or not is_dataclass(answer):
        return answer
    limits = tuple(getattr(optimality, "limits", ()) or ()) + (why,)
    return replace(answer, optimality=replace(optimality, proved=False, limits=limits))  # type: ignore[type-var]


def _accept(answer: T, verdict: _Verdict, *, retried: bool) -> Checked[T]:
    if verdict.stopped:
        return verdict.result(answer, retried=retried)
    if verdict.failure is not None:
        raise AnswerNotVerified(_what(answer), verdict.failure)
    logger.info("the %s computed with freshly built graphs passed its exact check", _what(answer))
    return verdict.result(answer, retried=retried)


def check_infeasibility(answer: Any, env: Environment | None) -> CheckReport | None:
    """The exact check of an answer saying there is no plan (an infeasible plan or Pareto front, a patrol, funnel
    or localisation strategy not found): ``None`` while such answers have no certificates.

    This is the hook for infeasibility certificates: when :mod:`solverplan.certify` can certify that no plan
    exists, make the certificate here and return its :func:`~solverplan.certify.check.check_certificate` report;
    :func:`checked_answer` then refuses an infeasible answer whose report is invalid, exactly as it refuses a plan.
    """
    return None


# ---------------------------------------------------------------------- the verdict
STOPPED = "the exact check of the answer was stopped by the time limit (--timeout): the answer is not checked"
"""The reason a stopped check gives, among the answer's optimality limits."""


@dataclass(frozen=True)
class _Verdict:
    failure: str | None
    certificate: Certificate | ModelCertificate | None = None
    checked: int = 0
    unchecked: str | None = None
    seconds: float = 0.0
    stopped: bool = False

    @classmethod
    def stopped_after(cls, checked: int, seconds: float) -> _Verdict:
        """The verdict of a check stopped by the caller's ``stop_at`` after ``checked`` certificates: no failure, no
        certificate, the answer unchecked (:data:`STOPPED`)."""
        return cls(None, None, checked, STOPPED, seconds, stopped=True)

    def result(self, answer: T, *, retried: bool = False) -> Checked[T]:
        """The :class:`Checked` of ``answer`` (marked not proved when its check was stopped: :func:`_not_proved`)."""
        if self.stopped:
            answer = _not_proved(answer, STOPPED)
        return Checked(answer, self.certificate, self.checked, retried, self.unchecked, self.seconds, self.stopped)


def _what(answer: Any) -> str:
    names = {"Plan": "plan", "ParetoFront": "Pareto front", "Patrol": "patrol", "Funnel": "funnel",
             "Localization": "localisation strategy", "Decomposition": "rooms decomposition",
             "Exploration": "exploration", "RangeExploration": "exploration", "CutOrdering": "cut ordering",
             "PursuitPlan": "pursuit plan", "FieldNavigation": "field plan", "FieldPlan": "field plan"}
    return names.get(type(answer).__name__, type(answer).__name__)


def _pieces(env: Environment | None, text: str | None) -> list | None:
    if env is None or text is None:
        return None
    return [(p.edge, p.t0, p.t1) for p in env.boundary_set(text).pieces]


def _verify(answer: Any, env: Environment | None, start: str | None, goal: str | None,
            stop_at: float | None = None) -> _Verdict:
    t0 = time.perf_counter()
    query: dict[str, Any] = {}
    if env is not None:
        query["expected_rings"] = env.rings
    expected_start, expected_goal = _pieces(env, start), _pieces(env, goal)
    if expected_start is not None:
        query["expected_start"] = expected_start
    if expected_goal is not None:
        query["expected_goal"] = expected_goal
    if env is None and isinstance(answer, (Plan, ParetoFront)):
        raise TypeError("a plan does not carry its environment: call checked_answer(..., env=...)")
    plans: list[Any] = [p.plan for p in answer.points] if isinstance(answer, ParetoFront) else [answer]
    last: Certificate | ModelCertificate | None = None
    checked = 0
    for k, item in enumerate(plans):
        where = f"point {k} ({item.bounces} bounces) of the front: " if isinstance(answer, ParetoFront) else ""
        if stop_at is not None and time.monotonic() > stop_at and getattr(item, "found", True):
            # (an answer that found nothing claims nothing: it goes on to its cheap no-plan path)
            return _Verdict.stopped_after(checked, time.perf_counter() - t0)
        try:
            cert = build.certificate(item, env=env)
        except NothingToCertify as exc:
            unchecked = _nothing_to_certify(item, env, start, goal, exc)
            if unchecked.failure is not None:
                return _Verdict(where + unchecked.failure, seconds=time.perf_counter() - t0)
            if isinstance(answer, ParetoFront) and answer.points:
                continue  # a point of no stages that records no start or goal: checked by _nothing_to_certify
            return _Verdict(None, None, checked, unchecked.unchecked, time.perf_counter() - t0)
        except Exception as exc:  # noqa: BLE001 - an answer that cannot even be certified is not given
            return _Verdict(f"{where}no certificate can be made of it ({type(exc).__name__}: {exc})",
                            seconds=time.perf_counter() - t0)
        try:
            report = check_certificate(cert, **query, stop=None if stop_at is None else lambda: time.monotonic() > stop_at)
        except CheckStopped:
            return _Verdict.stopped_after(checked, time.perf_counter() - t0)
        checked += 1
        if not report.valid:
            return _Verdict(f"{where}{report.failures[0]}", seconds=time.perf_counter() - t0)
        last = cert  # a front's certificate is its most tolerant (last) point's
    if isinstance(answer, ParetoFront) and not answer.points:
        return _nothing_to_certify(answer, env, start, goal, None)
    return _Verdict(None, last, checked, None, time.perf_counter() - t0)


def _nothing_to_certify(answer: Any, env: Environment | None, start: str | None, goal: str | None,
                        exc: NothingToCertify | None) -> _Verdict:
    """An answer without a certificate: a found plan with no stages that records no start or goal set (the caller's
    start set must lie in its goal set, checked here exactly; a plan that records them gets a certificate of no
    stages), or an answer that there is none (:func:`check_infeasibility`)."""
    if isinstance(answer, Plan) and answer.found:
        if env is None:
            return _Verdict(None, unchecked="a plan without stages and without its environment")
        s, g = start or answer.start, goal or answer.goal
        if not s or not g:
            return _Verdict(None, unchecked="a plan without stages and without its start or goal set")
        goal_runs = env.boundary_set(g).by_edge()
        for piece in env.boundary_set(s).merged().pieces:
            if not any(lo <= piece.t0 and piece.t1 <= hi for lo, hi in goal_runs.get(piece.edge, ())):
                return _Verdict(f"the plan has no stages, but its start set is not inside its goal set: {piece} is not")
        return _Verdict(None)
    report = check_infeasibility(answer, env)
    if report is None:
        why = exc.why if exc is not None else "the answer is that there is none"
        logger.debug("the %s is not checked: %s", _what(answer), why)
        return _Verdict(None, unchecked=f"{why}: infeasibility is not certified yet")
    if not report.valid:
        return _Verdict(f"infeasibility: {report.failures[0]}")
    return _Verdict(None, checked=1)
