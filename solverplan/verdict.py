"""One verdict for every check: what was checked, what failed, what was proved, and about what.

Every checker of solverplan answers with a :class:`Verdict`: the exact checker of certificates
(:class:`~solverplan.certify.check.CheckReport`, every kind: plans, funnels, cycles, infeasibility, rooms,
exploration, cut orderings, pursuit plans, fields), the geometric ground-truth replay of a pursuit plan
(:class:`~solverplan.wallfollow.pursuit_check.PursuitCheck`) and the flow-through test of a cell's field
(:class:`~solverplan.reflection.fields.FlowCheck`). A verdict has

- ``kind``: what was checked (a certificate's kind, ``pursuit-replay``, ``flow-through``);
- ``valid``: true iff there are no ``failures``;
- ``failures``: :class:`Failure` records, each naming the claim that does not hold and saying what was found;
- ``checked``: what was decided exactly, as ``(name, count)`` pairs;
- ``not_checked``: what was taken on trust or only sampled, in words (a valid verdict may still list some);
- ``proved``: what the check establishes, in words (empty when not valid);
- ``scope``: what those statements speak about, in words;

and reads the same way everywhere: :meth:`Verdict.to_json` puts these keys in one order (``valid``, ``kind``, the
check's own keys, ``failures``, ``checked``, ``not_checked``, ``proved``, ``scope``) and :meth:`Verdict.to_text`
prints ``TITLE: VALID`` (or ``INVALID``), what was checked, ``scope:``, what it claims, ``checked exactly:``, the
``proved:`` lines, one ``FAIL claim: message`` line per failure and the ``not checked:`` lines.

This module imports only the standard library: the exact checker (which shares no code with the planners) and the
models (which may not import the checker) both build on it.

>>> import solverplan as sp
>>> room = sp.Environment.from_coords([[0, 0], [10, 1], [9, 4], [3, 5], [9, 6], [10, 9], [0, 10]])
>>> replay = sp.check_pursuit(room, ["RFOLLOW"])       # the pocket above the wall stays hidden
>>> isinstance(replay, sp.Verdict), replay.valid, replay.failures[0].claim
(True, False, 'cleared_after')
>>> print(replay.to_text().splitlines()[0])
pursuit replay from v0, 1 action: INVALID
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

__all__ = ["Failure", "Verdict", "VERDICT_KEYS"]

VERDICT_KEYS = ("valid", "kind", "failures", "checked", "not_checked", "proved", "scope")
"""The keys of :meth:`Verdict.verdict_json`, in their order (a check's own keys go between ``kind`` and
``failures`` in :meth:`Verdict.to_json`)."""


@dataclass(frozen=True, slots=True)
class Failure:
    """One claim that does not hold.

    Attributes
    ----------
    claim
        Its path in what was checked (``stages[2].moves[0].d_hi`` in a certificate, ``cleared_after`` of a pursuit
        replay, ``sides[3]`` of a cell's flow-through).
    message
        What was found, in words.

    Examples
    --------
    >>> import solverplan as sp
    >>> failure = sp.Failure("claims.min_width", "claims 0.2, the widest common interval is 0.1 rad")
    >>> str(failure)
    'claims.min_width: claims 0.2, the widest common interval is 0.1 rad'
    """

    claim: str
    message: str

    def __str__(self) -> str:
        return f"{self.claim}: {self.message}"

    def to_json(self) -> dict[str, str]:
        """``{"claim", "message"}``."""
        return {"claim": self.claim, "message": self.message}


class Verdict:
    """The verdict every check of solverplan gives (module docstring): one protocol, one JSON shape, one text.

    A base class: each check is a subclass that provides the attributes below (as fields or as properties computed
    from its own record, e.g. a pursuit replay's ``cleared_after``) and may add its own keys and lines through
    :meth:`subject_json`, :meth:`subject_lines` and :meth:`claim_lines`.

    Attributes
    ----------
    kind
        What was checked: a certificate's kind, ``pursuit-replay``, ``flow-through``.
    valid
        True iff ``failures`` is empty.
    failures
        The claims that do not hold (:class:`Failure`), in the order found.
    checked
        What was decided exactly: ``(name, count)`` pairs, e.g. ``("corner_rays", 16)``.
    not_checked
        What was taken on trust or only sampled, in words.
    proved
        What the check establishes, in words; empty when not valid.
    scope
        What the statements speak about, in words.

    Examples
    --------
    Every check answers alike: a certificate's exact check, a pursuit plan's replay, a cell's flow-through.

    >>> import solverplan as sp
    >>> env = sp.load_environment("l_shape")
    >>> report = sp.check_certificate(sp.certificate(sp.find_plan(env, "e5", "e0:0:0.3"), env=env))
    >>> room = sp.Environment.from_coords([[0, 0], [10, 1], [9, 4], [3, 5], [9, 6], [10, 9], [0, 10]])
    >>> replay = sp.check_pursuit(room, ["LFOLLOW"])
    >>> [(v.kind, v.valid, len(v.failures), bool(v.checked)) for v in (report, replay)]
    [('plan', True, 0, True), ('pursuit-replay', True, 0, True)]
    >>> list(replay.to_json())[:2], list(replay.to_json())[-5:]
    (['valid', 'kind'], ['failures', 'checked', 'not_checked', 'proved', 'scope'])
    >>> print(replay.to_text())                                      # doctest: +ELLIPSIS
    pursuit replay from v0, 1 action: VALID
    actions: LFOLLOW
    scope: an evader moving arbitrarily fast in this simple polygon, seen once in the pursuer's line of sight; ...
    cleared: during action 1
    checked exactly: 1 actions, 8 shadows
    proved: during action 1 no shadow component can hold the evader: an evader anywhere in the polygon has been seen
    not checked: labels across an event: carried by the exact overlap of the components a millionth of a piece ...
    <BLANKLINE>
    """

    __slots__ = ()

    if TYPE_CHECKING:  # what each check provides (a field or a property); read-only for every reader
        @property
        def kind(self) -> str: ...

        @property
        def valid(self) -> bool: ...

        @property
        def failures(self) -> tuple[Failure, ...]: ...

        @property
        def checked(self) -> tuple[tuple[str, int], ...]: ...

        @property
        def not_checked(self) -> tuple[str, ...]: ...

        @property
        def proved(self) -> tuple[str, ...]: ...

        @property
        def scope(self) -> str: ...
    else:  # names only (no class attribute: a dataclass subclass must not see a default)
        kind: str
        valid: bool
        failures: tuple
        checked: tuple
        not_checked: tuple
        proved: tuple
        scope: str

    @property
    def verified(self) -> bool:
        """Deprecated: ``valid`` (the name :class:`~solverplan.wallfollow.pursuit_check.PursuitCheck` and
        :class:`~solverplan.reflection.fields.FlowCheck` gave it before every check answered with a verdict)."""
        warnings.warn(f"{type(self).__name__}.verified is deprecated: use .valid (the verdict every check gives)",
                      DeprecationWarning, stacklevel=2)
        return self.valid

    @property
    def title(self) -> str:
        """What the first line of :meth:`to_text` names (it ends ``: VALID`` or ``: INVALID``)."""
        return self.kind

    def subject_json(self) -> dict[str, Any]:
        """The check's own keys of :meth:`to_json` (between ``kind`` and ``failures``); none by default."""
        return {}

    def subject_lines(self) -> list[str]:
        """The lines of :meth:`to_text` saying what was checked (after the first, before ``scope:``); none by
        default."""
        return []

    def claim_lines(self) -> list[str]:
        """The lines of :meth:`to_text` saying what it claims (after ``scope:``); none by default."""
        return []

    def verdict_json(self) -> dict[str, Any]:
        """The verdict alone, :data:`VERDICT_KEYS` in order (an answer embeds it to carry its check's verdict)."""
        core = self._core()
        return {key: core[key] for key in VERDICT_KEYS}

    def to_json(self) -> dict[str, Any]:
        """The verdict and the check's own keys: ``valid``, ``kind``, :meth:`subject_json`, ``failures``, ``checked``,
        ``not_checked``, ``proved``, ``scope``."""
        core = self._core()
        return {"valid": core["valid"], "kind": core["kind"], **self.subject_json(),
                **{key: core[key] for key in VERDICT_KEYS[2:]}}

    def to_text(self, *, width: int = 100) -> str:
        """``TITLE: VALID|INVALID``, :meth:`subject_lines`, ``scope:``, :meth:`claim_lines`, ``checked exactly:``, the
        ``proved:`` lines (when valid), a ``FAIL claim: message`` line per failure and the ``not checked:`` lines."""
        counts = ", ".join(f"{value} {name.replace('_', ' ')}" for name, value in self.checked) or "nothing"
        lines = [f"{self.title}: {'VALID' if self.valid else 'INVALID'}", *self.subject_lines(),
                 f"scope: {self.scope or 'not stated'}", *self.claim_lines(), f"checked exactly: {counts}"]
        if self.valid:
            lines.extend(f"proved: {statement}" for statement in self.proved)
        lines.extend(f"FAIL {failure}" for failure in self.failures)
        lines.extend(f"not checked: {item}" for item in self.not_checked)
        return "\n".join(lines) + "\n"

    def _core(self) -> dict[str, Any]:
        return {"valid": bool(self.valid), "kind": self.kind, "failures": [f.to_json() for f in self.failures],
                "checked": dict(self.checked), "not_checked": list(self.not_checked),
                "proved": list(self.proved) if self.valid else [], "scope": self.scope}
