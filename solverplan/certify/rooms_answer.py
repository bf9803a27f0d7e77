"""The exact check of a rooms answer (the JSON of ``solverplan rooms``) against its polygon — the ``rooms``
certificate's checker, reading the answer's own claims.

:func:`check_rooms_answer` turns the answer into the claims of a ``rooms`` certificate (rooms with their exact areas,
doors with their exact escapability Φ from both sides, the tree) and runs the independent exact checker on them
(:mod:`solverplan.certify.check_rooms`: doors through the interior from reflex vertices, rooms tiling the polygon,
the tree, Φ). The verdict is the :class:`~solverplan.certify.check.CheckReport` every certificate gets; numbers the
answer does not state exactly (door lengths, Ψ) are listed under ``not_checked``.

>>> from solverplan.environment import load_environment
>>> from solverplan.rectilinear.decomposition import decompose_rooms
>>> env = load_environment("three_chambers")
>>> answer = decompose_rooms(env).to_json()
>>> check_rooms_answer(env, answer).valid
True
>>> answer["doors"][0]["b"] = [30, 16]
>>> print(check_rooms_answer(env, answer).failures[0])
claims.doors[0]: (30, 14.5)–(30, 16) does not run through the interior of the polygon
"""

from __future__ import annotations

from os import PathLike
from pathlib import Path
from decimal import Decimal
from typing import Any

from solverplan.certify.check import CheckReport
from solverplan.certify.check_models import check_model_certificate
from solverplan.certify.schema import EnvironmentRecord, ModelCertificate
from solverplan.environment import Environment, read_json
from solverplan.errors import MalformedFile
from solverplan.limits import read_text_within_limits

__all__ = ["check_rooms_answer", "load_rooms_answer", "rooms_claims"]


def load_rooms_answer(path: str | PathLike[str]) -> dict:
    """Read a rooms answer file (the JSON of ``solverplan rooms -o FILE``), numbers exact, within the input
    limits; :class:`~solverplan.errors.MalformedFile` for a missing, unreadable or non-JSON file."""
    file = Path(path)
    text = read_text_within_limits(file)
    try:
        data = read_json(text)
    except ValueError as exc:  # json.JSONDecodeError
        raise MalformedFile(f"{file}: not valid JSON ({str(exc).splitlines()[0][:80]})") from None
    if not isinstance(data, dict) or "rooms" not in data or "doors" not in data:
        raise MalformedFile(f"{file}: not a rooms answer (expected an object with rooms and doors)")
    return data


def rooms_claims(answer: dict) -> dict:
    """The claims of a ``rooms`` certificate that a rooms answer states (exact fields only: ``area_exact``,
    ``escapability_by_room_exact``; the float ``length`` and ``area`` are not exact claims). Malformed parts are
    passed on as they are: the checker names them."""
    def room(k: int, r: Any) -> Any:
        if not isinstance(r, dict):
            return r
        out = {"id": r.get("id", k), "polygon": r.get("polygon")}
        if "area_exact" in r:
            out["area"] = r["area_exact"]
        return out

    def door(k: int, d: Any) -> Any:
        if not isinstance(d, dict):
            return d
        out = {"id": d.get("id", k), "a": d.get("a"), "b": d.get("b"), "rooms": d.get("rooms")}
        if "escapability_by_room_exact" in d:
            out["escapability"] = d["escapability_by_room_exact"]
        return out

    answer = _decimal_text(answer)
    rooms, doors = answer.get("rooms"), answer.get("doors")
    claims: dict = {
        "rooms": [room(k, r) for k, r in enumerate(rooms)] if isinstance(rooms, list) else rooms,
        "doors": [door(k, d) for k, d in enumerate(doors)] if isinstance(doors, list) else doors,
    }
    if "tree" in answer:
        claims["tree"] = answer["tree"]
    elif isinstance(doors, list):
        claims["tree"] = sorted(sorted(d.get("rooms", [])) for d in doors if isinstance(d, dict))
    return claims


def _decimal_text(value: Any) -> Any:
    """Floats as the decimal text they print as (``4.9`` → ``"4.9"``): an answer in memory, read as its file would be."""
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, dict):
        return {k: _decimal_text(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_decimal_text(v) for v in value]
    return value


def _check_shape(answer: Any, env: Environment) -> None:
    """Every field of a rooms answer has its type, and its counts fit the polygon: else
    :class:`~solverplan.errors.MalformedFile` naming the first malformed field (a file that is not a rooms answer
    is bad input, exit 2; an answer whose claims are false is invalid, exit 1)."""
    def fail(where: str, expected: str) -> MalformedFile:
        return MalformedFile(f"rooms answer: {where}: expected {expected}")

    def point(value: Any, where: str) -> None:
        if not isinstance(value, (list, tuple)) or len(value) != 2 or not all(
                isinstance(x, (int, float, str, Decimal)) and not isinstance(x, bool) for x in value):
            raise fail(where, "[x, y]")

    if not isinstance(answer, dict):
        raise fail("the answer", "an object with rooms and doors")
    raw_doors, raw_rooms = answer.get("doors"), answer.get("rooms")
    if not isinstance(raw_doors, list):
        raise fail("doors", "a list")
    if not isinstance(raw_rooms, list):
        raise fail("rooms", "a list")
    most = env.n_vertices + 1  # a decomposition has at most one room more than the polygon has vertices
    if len(raw_rooms) > most or len(raw_doors) > most:
        raise MalformedFile(f"rooms answer: {len(raw_rooms):,} rooms and {len(raw_doors):,} doors for a polygon of "
                            f"{env.n_vertices:,} vertices")
    for k, d in enumerate(raw_doors):
        if not isinstance(d, dict) or not isinstance(d.get("rooms"), list) or len(d["rooms"]) != 2 \
                or not all(isinstance(r, int) and not isinstance(r, bool) for r in d["rooms"]):
            raise fail(f"doors[{k}]", "an object with a, b and rooms (two room numbers)")
        claimed = d.get("escapability_by_room_exact")
        if claimed is not None and (not isinstance(claimed, list) or len(claimed) != 2):
            raise fail(f"doors[{k}].escapability_by_room_exact", "two numbers, one per room")
        point(d.get("a"), f"doors[{k}].a")
        point(d.get("b"), f"doors[{k}].b")
    for k, r in enumerate(raw_rooms):
        if not isinstance(r, dict) or not isinstance(r.get("polygon"), list) or ("area_exact" not in r and "area" not in r):
            raise fail(f"rooms[{k}]", "an object with polygon (a list of [x, y]) and area")
        if len(r["polygon"]) > env.n_vertices:
            raise MalformedFile(f"rooms answer: rooms[{k}].polygon: {len(r['polygon']):,} vertices, more than the polygon's")
        for p in r["polygon"]:
            point(p, f"rooms[{k}].polygon")


def check_rooms_answer(env: Environment, answer: dict) -> CheckReport:
    """Check a rooms answer (``Decomposition.to_json()`` or the JSON of ``solverplan rooms``) against ``env``
    exactly: the ``rooms`` certificate's checker on the answer's claims (module docstring). A malformed answer
    (a field of the wrong type, more rooms or doors than the polygon allows) is
    :class:`~solverplan.errors.MalformedFile`."""
    _check_shape(answer, env)
    cert = ModelCertificate("rooms", EnvironmentRecord(env.rings, env.name), rooms_claims(answer), "rooms answer")
    return check_model_certificate(cert, partial=True)
