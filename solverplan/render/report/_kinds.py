"""The kinds of answer a report shows, and reading answer files (any kind, told by its ``kind``)."""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from pathlib import Path


from solverplan.environment import read_json
from solverplan.errors import MalformedFile
from solverplan.limits import read_text_within_limits


ANSWER_KINDS: dict[str, str] = {
    "plan": "a plan (solverplan plan -o)",
    "pareto": "a Pareto front (solverplan plan --pareto -o)",
    "patrol": "a patrol cycle (solverplan patrol -o)",
    "funnel": "a funnel (solverplan funnel -o)",
    "localize": "a localisation strategy (solverplan localize -o)",
    "cycle": "a limit cycle (solverplan cycle -o)",
    "controller": "a constant controller (solverplan cycle --theta auto -o)",
    "study": "a study (solverplan study -o, or the study's NAME.json)",
    "rooms": "a rooms decomposition (solverplan rooms -o)",
    "rooms-simulation": "a rooms simulation of one rule (solverplan rooms --simulate -o)",
    "rooms-rules": "a rooms simulation of every rule (solverplan rooms --simulate --rule all -o)",
    "exploration": "an exploration (solverplan explore -o)",
    "range-exploration": "a range-limited exploration (solverplan explore --range R -o)",
    "cut-ordering": "a cut ordering (solverplan wallfollow --cut-ordering -o)",
    "learned-ordering": "a learned cut ordering (solverplan wallfollow --learn -o)",
    "vertex-count": "a vertex count (solverplan wallfollow --count -o)",
    "pursuit": "a pursuit-evasion plan (solverplan wallfollow --pursuit -o)",
    "fields": "composed potential fields (solverplan fields -o)",
    "simulation": "a Monte Carlo simulation (solverplan simulate -o)",
    "import": "an import summary (solverplan import)",
}
"""The kinds of answer a report can show, and what writes them."""

REPORT_OPTIONS: dict[str, tuple[str, ...]] = {
    "plan": ("plan", "pareto"),
    "patrol": ("patrol",),
    "funnel": ("funnel", "localize"),
    "cycle": ("cycle", "controller"),
    "study": ("study",),
}
"""The ``solverplan report`` option that takes each kind of answer (``--plan`` takes plans and Pareto fronts, ...)."""

NEEDS_ENVIRONMENT: frozenset[str] = frozenset(
    {"plan", "pareto", "patrol", "funnel", "localize", "cycle", "controller", "exploration", "range-exploration",
     "pursuit"})
"""The kinds whose picture needs the environment (they name its edges or are drawn over it); the others draw from
their own JSON (rooms, cells) and show the environment only when it is known."""

_CERTIFICATE_KINDS = {"plan": "plan", "pareto": "plan", "patrol": "cycle", "funnel": "funnel", "localize": "localize"}

_WIDTH, _MAX_HEIGHT, _PAD = 780.0, 600.0, 30.0
_EXACT_CELL = ' class="exact"'  # table cells holding exact numbers: monospace, wrapped anywhere
HOLE_COLOR = "#d9dfe6"  # the holes of the environment (obstacles)


# ====================================================================== reading answers
@dataclass(frozen=True)
class AnswerFile:
    """An answer as the CLI wrote it: where it came from (``path``, for messages and the page), its ``kind``
    (a key of :data:`ANSWER_KINDS`) and its JSON ``data``."""

    path: str
    kind: str
    data: dict


def detect_answer_kind(data: object) -> str | None:
    """The kind of answer ``data`` is (a key of :data:`ANSWER_KINDS`), told by the fields each answer always has;
    ``None`` for anything else (a certificate, an environment, a verify report, ...).

    >>> detect_answer_kind({"status": "found", "objective": "fewest", "stages": []})
    'plan'
    >>> detect_answer_kind({"outer": []}) is None  # an environment
    True
    """
    if not isinstance(data, dict):
        return None
    if data.get("schema") == "solverplan-certificate" or "valid" in data:
        return None  # a certificate, or a checker's verdict (its kind is the certificate's)
    if isinstance(data.get("kind"), str) and data["kind"] in ANSWER_KINDS:
        return str(data["kind"])  # every answer written since the kinds were introduced says what it is
    if isinstance(data.get("study"), dict) and isinstance(data.get("cells"), list):
        return "study"
    if "status" not in data:
        return None
    if isinstance(data.get("cycles"), list) and "tried" in data:
        return "controller"
    if "visit" in data and isinstance(data.get("cycle"), list):
        return "patrol"
    if isinstance(data.get("cycle"), list) and "fixed_point" in data and "theta" in data:
        return "cycle"
    if data.get("kind") in ("funnel", "localize") and isinstance(data.get("stages"), list):
        return str(data["kind"])
    if isinstance(data.get("front"), list) and isinstance(data.get("points"), list):
        return "pareto"
    if isinstance(data.get("stages"), list) and "objective" in data:
        return "plan"
    return None


def load_answer(path: str | os.PathLike[str], *, option: str | None = None) -> AnswerFile:
    """Read an answer file the CLI wrote (or an answer's ``to_json()``), and tell which kind of answer it is.

    Parameters
    ----------
    path
        The answer file (JSON) of any kind: its ``kind`` says which (an answer written before kinds existed is
        recognised by its fields).
    option
        A key of :data:`REPORT_OPTIONS` (``"plan"``, ``"patrol"``, ...): the older ``solverplan report ENV --plan``
        form; the answer must be of a kind that option takes.

    Returns
    -------
    AnswerFile
        Its ``path``, ``kind`` (a key of :data:`ANSWER_KINDS`) and JSON ``data``.

    Raises
    ------
    MalformedFile
        A missing or unreadable file, bad JSON, a file past the input limits, a file that is no answer, or an
        answer of a kind ``option`` does not take (the message names the option that does).

    Examples
    --------
    >>> import json, pathlib, tempfile
    >>> import solverplan as sp
    >>> funnel = sp.funnel(sp.load_environment("square"), "e0", "e1:0.4:0.6")
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "funnel.json"
    >>> _ = path.write_text(json.dumps(funnel.to_json()))
    >>> sp.load_answer(path).kind
    'funnel'
    >>> sp.load_answer(path, option="plan")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    solverplan.errors.MalformedFile: .../funnel.json: is a funnel (solverplan funnel -o), not what --plan takes: give it with --funnel
    """
    file = Path(path)
    text = read_text_within_limits(file)
    try:
        data = read_json(text, exact=False)
    except json.JSONDecodeError as exc:
        raise MalformedFile(f"{file}: not valid JSON ({exc.msg} at line {exc.lineno} column {exc.colno})") from None
    except MalformedFile as exc:
        raise MalformedFile(f"{file}: {exc}") from None
    kind = detect_answer_kind(data)
    if kind is None:
        if isinstance(data, dict) and data.get("schema") == "solverplan-certificate":
            raise MalformedFile(f"{file}: is a certificate, not an answer: give it with --certificate")
        raise MalformedFile(f"{file}: is no answer solverplan writes (a report shows the answers of every command: "
                            f"{', '.join(ANSWER_KINDS)})")
    if option is not None and kind not in REPORT_OPTIONS[option]:
        if not any(kind in kinds for kinds in REPORT_OPTIONS.values()):
            raise MalformedFile(f"{file}: is {ANSWER_KINDS[kind]}: give it as the answer itself (solverplan report "
                                f"{file}), not with --{option}")
        wanted = next(name for name, kinds in REPORT_OPTIONS.items() if kind in kinds)
        raise MalformedFile(f"{file}: is {ANSWER_KINDS[kind]}, not what --{option} takes: give it with --{wanted}")
    assert isinstance(data, dict)
    return AnswerFile(str(path), kind, data)
