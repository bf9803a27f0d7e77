"""The named options of the library's functions, one enumeration per choice.

Every function that takes one of these options accepts the member or its string (``objective="tolerance"`` and
``objective=Objective.TOLERANCE`` are the same call), and reads it through :meth:`Choice.parse`, so a wrong
value is one line naming the option and its values. The command line builds its ``--objective``,
``--sampling``, … options from these classes: the values are written once, here.

This module imports nothing heavy, so the command line can build its options without loading the planners.

>>> from solverplan.choices import Objective
>>> Objective.parse("tolerance", "objective") is Objective.TOLERANCE
True
>>> Objective.values()
('fewest', 'tolerance', 'sum', 'constant')
>>> Objective.parse("fastest", "objective")
Traceback (most recent call last):
...
solverplan.errors.InputError: unknown objective 'fastest': use fewest, tolerance, sum, constant
"""

from __future__ import annotations

from enum import StrEnum
from typing import Iterable, TypeVar

from solverplan.errors import InputError

__all__ = [
    "Choice", "Objective", "PatrolObjective", "CycleMethod", "Sampling", "Ties", "ExportFormat", "ViewChoice",
    "RoomRule", "ThetaMode", "DoorPolicy", "Sensor", "Comparisons", "RobotKind", "ScenarioName", "CellKind",
    "Reflections", "StartMode", "StudyGenerator", "EnvironmentFormat", "GraphFormat", "FloorplanFormat", "named_choice", "or_all",
]

C = TypeVar("C", bound="Choice")


class Choice(StrEnum):
    """The base of every option set: members are strings, and :meth:`parse` reads a member or its string."""

    @classmethod
    def parse(cls: type[C], value: object, what: str) -> C:
        """``value`` (a member or its string) as a member; anything else is an :class:`InputError` naming ``what``
        and the values allowed."""
        if isinstance(value, cls):
            return value
        if isinstance(value, str) and value in cls._value2member_map_:
            return cls(value)
        raise InputError(f"unknown {what} {value!r}: use {', '.join(cls.values())}")

    @classmethod
    def values(cls) -> tuple[str, ...]:
        """The strings of the members, in their order."""
        return tuple(member.value for member in cls)


# ---------------------------------------------------------------- the bouncing robot (plan, patrol, simulate)
class Objective(Choice):
    """What :func:`~solverplan.plan.search.find_plan` optimises."""

    FEWEST = "fewest"
    TOLERANCE = "tolerance"
    SUM = "sum"
    CONSTANT = "constant"


class PatrolObjective(Choice):
    """What :func:`~solverplan.plan.patrols.patrol` optimises."""

    CONTRACTION = "contraction"
    TOLERANCE = "tolerance"
    RATE = "rate"


class CycleMethod(Choice):
    """How :func:`~solverplan.bounce.cycles.limit_cycle` finds the cycle."""

    AUTO = "auto"
    THEOREM1 = "theorem1"
    ITERATE = "iterate"
    EDGES = "edges"


class Sampling(Choice):
    """How a rollout draws a heading from an interval."""

    UNIFORM = "uniform"
    ENDPOINTS = "endpoints"
    LO = "lo"
    HI = "hi"
    MID = "mid"


class Ties(Choice):
    """What a rollout does with a ray the float caster cannot call: ``exact`` re-resolves it, ``flag`` stops."""

    FLAG = "flag"
    EXACT = "exact"


class ExportFormat(Choice):
    """The files :func:`~solverplan.plan.export.export_plan` writes."""

    WAYPOINTS = "waypoints"
    CSV = "csv"
    GEOJSON = "geojson"


# ---------------------------------------------------------------- exploration
class ViewChoice(Choice):
    """Which unexplored constructed edge the next view is taken on."""

    FIRST = "first"
    RANDOM = "random"
    FAR = "far"


# ---------------------------------------------------------------- rooms of rectilinear polygons
class RoomRule(Choice):
    """The bounce rules of the rooms model (the smart rule three ways, random, billiard)."""

    SMART = "smart"
    SMART_PAPER = "smart-paper"
    SMART_PER_ROOM = "smart-per-room"
    RANDOM = "random"
    BILLIARD = "billiard"


class ThetaMode(Choice):
    """The smart rule's θ: ``safe`` (tan θ = ℓ/2D), ``paper`` (Eq. 1) or ``per-room``."""

    SAFE = "safe"
    PAPER = "paper"
    PER_ROOM = "per-room"


class DoorPolicy(Choice):
    """Which doors a rooms simulation keeps open: the door-control policy of the room sequence, or every door."""

    CONTROL = "control"
    OPEN = "open"


# ---------------------------------------------------------------- the wall-following robot
class Sensor(Choice):
    """The pursuer's extra sensor in pursuit-evasion."""

    GAP = "gap"
    BITANGENT = "bitangent"
    PEBBLE = "pebble"
    CONTACT = "contact"


class Comparisons(Choice):
    """How Strategy 1 orders the end points on an edge: every pair (the paper), or a merge sort."""

    PAIRWISE = "pairwise"
    SORT = "sort"


# ---------------------------------------------------------------- composed fields with reflection
class RobotKind(Choice):
    """The fields robot: a single integrator, or inertial (acceleration cap, restitution, dead band)."""

    INTEGRATOR = "integrator"
    INERTIAL = "inertial"


class ScenarioName(Choice):
    """The fields model's scenarios: slow nominal fields, fast ones, fast ones with reflection zones."""

    CONSTRAINED = "constrained"
    UNCONSTRAINED = "unconstrained"
    REFLECTION = "reflection"


class CellKind(Choice):
    """The fields model's cells: Hertel–Mehlhorn convex cells, or with the reflex corners projected."""

    CONVEX = "convex"
    CORNERS = "corners"


class Reflections(Choice):
    """Where the fields model plans reflections: where they pay off, every zone the geometry allows, none."""

    PAYOFF = "payoff"
    ALL = "all"
    NONE = "none"


class StartMode(Choice):
    """Where a fields trial starts: the given start, or a uniform random point of the free space."""

    FIXED = "fixed"
    RANDOM = "random"


# ---------------------------------------------------------------- studies and files
class StudyGenerator(Choice):
    """The random environments a study runs over (the generators with a default grid)."""

    STAR = "star"
    HOLES = "holes"
    ROOMS = "rooms"
    RECTILINEAR = "rectilinear"


class EnvironmentFormat(Choice):
    """The environment file formats: the JSON of ``docs/contract.md``, GeoJSON, WKT."""

    JSON = "json"
    GEOJSON = "geojson"
    WKT = "wkt"


class GraphFormat(Choice):
    """How a safe bounce visibility graph is written: the JSON of ``docs/contract.md``, text, GraphML, Graphviz DOT."""

    JSON = "json"
    TEXT = "text"
    GRAPHML = "graphml"
    DOT = "dot"


class FloorplanFormat(Choice):
    """The floor plans :func:`~solverplan.floorplan.importer.import_floorplan` reads: ROS maps, DXF, SVG."""

    ROS = "ros"
    DXF = "dxf"
    SVG = "svg"


def named_choice(name: str, values: Iterable[str]) -> type[Choice]:
    """A :class:`Choice` of ``values`` made where they are kept (e.g. the keys of a registry of generators).

    >>> [member.value for member in named_choice("Colour", ["red", "dark-blue"])]
    ['red', 'dark-blue']
    """
    members = [(value.upper().replace("-", "_"), value) for value in values]
    return Choice(name, members, module=__name__)  # type: ignore[call-arg, return-value]


def or_all(cls: type[C]) -> type[Choice]:
    """``cls``'s members and ``all`` (every member at once), for an option that may ask for all of them.

    >>> [member.value for member in or_all(ScenarioName)]
    ['constrained', 'unconstrained', 'reflection', 'all']
    """
    return named_choice(f"{cls.__name__}OrAll", [*cls.values(), "all"])
