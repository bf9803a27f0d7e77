"""solverplan: planning with proofs for minimal bouncing robots.

Robots that drive straight until they hit a wall and then turn by a bounce rule: give solverplan a floor plan
and it answers with the most robust plan that exists, a certificate an independent checker verifies in exact
rational arithmetic, and a picture. Every answer follows one result protocol (:mod:`solverplan.result`):
a ``status`` (:class:`Status`), an ``optimality`` claim with its bound and scope, ``stats``, the
``environment`` it was made in, ``to_json()`` and ``to_text()``.

>>> import solverplan as sp
>>> env = sp.load_environment("two_rooms")                 # a shipped model, or a path to a JSON/GeoJSON/WKT file
>>> plan = sp.find_plan(env, "e0:0.2:0.8", "e4:0.5:1", objective="tolerance")
>>> plan.status, plan.status.group.value, plan.optimality.proved
(<Status.FOUND: 'found'>, 'answered', True)
>>> report = sp.check_certificate(sp.certificate(plan, env=env))   # exact rational arithmetic, stdlib only
>>> report.valid
True
>>> runs = sp.simulate_plan(env, plan, trials=1000, seed=1, sampling="endpoints")
>>> runs.success_rate
1.0

Headings are radians in (0, π), measured counter-clockwise from the wall the robot is on; boundary sets are
strings such as ``"e3:0.25:0.75,e4"`` (edge 3 from t = 0.25 to 0.75, and all of edge 4). The command line
(``solverplan --help``) answers the same questions; ``docs/contract.md`` describes files, answers and exit codes.

Names are loaded on first use, so ``import solverplan`` stays cheap (the planners' solvers load when needed).
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

__version__ = "0.1.0"

# public name → module that defines it (loaded on first attribute access)
_EXPORTS: dict[str, str] = {
    # environments and boundary sets
    "Environment": "solverplan.environment",
    "BoundarySet": "solverplan.environment",
    "BoundaryPiece": "solverplan.environment",
    "load_environment": "solverplan.environment",
    "Interval": "solverplan.interval",
    "models": "solverplan.models",
    # the named options of the library's functions: each takes the member or its string
    "choices": "solverplan.choices",
    # run-time settings: the graph cache and the memory limit
    "config": "solverplan.runtime",
    "watching": "solverplan.progress",
    "Stopped": "solverplan.progress",
    "configure": "solverplan.runtime",
    "settings": "solverplan.runtime",
    "Settings": "solverplan.runtime",
    # model structures of the main paper
    "partition": "solverplan.bounce.partitions",
    "bounce_visibility_graph": "solverplan.bounce.bvg",
    "safe_bounce_visibility_graph": "solverplan.bounce.bvg",
    "limit_cycle": "solverplan.bounce.cycles",
    "constant_controller": "solverplan.bounce.controller",
    # rooms and doors of rectilinear polygons (Çağırıcı, Bahoo and LaValle)
    "decompose_rooms": "solverplan.rectilinear.decomposition",
    "simulate_rooms": "solverplan.rectilinear.simulation",
    "compare_rules": "solverplan.rectilinear.simulation",
    # online exploration with discrete views (Ghosh, Burdick, Bhattacharya and Sarkar)
    "explore_depth_first": "solverplan.explore.depth_first",
    "Exploration": "solverplan.explore.depth_first",
    "explore_range_limited": "solverplan.explore.range_limited",
    "RangeExploration": "solverplan.explore.range_limited",
    "range_visibility": "solverplan.explore.range_view",
    "RangeView": "solverplan.explore.range_view",
    # the wall-following robot (Yershova, Tovar, Katsev, Ghrist and LaValle)
    "cut_ordering": "solverplan.wallfollow.cut",
    "CutOrdering": "solverplan.wallfollow.ordering",
    "WallWorld": "solverplan.wallfollow.world",
    "learn_cut_ordering": "solverplan.wallfollow.learning",
    "pursuit_plan": "solverplan.wallfollow.pursuit",
    "PursuitPlan": "solverplan.wallfollow.pursuit",
    "check_pursuit": "solverplan.wallfollow.pursuit_check",
    "PursuitCheck": "solverplan.wallfollow.pursuit_check",
    "learn_bitangents": "solverplan.wallfollow.pebble",
    "PebbleWorld": "solverplan.wallfollow.pebble",
    # composed potential fields with reflection (Stager and Tanner)
    "decompose_free_space": "solverplan.reflection.cells",
    "compose_fields": "solverplan.reflection.compose",
    "simulate_scenarios": "solverplan.reflection.simulate",
    "FieldRobotDynamics": "solverplan.reflection.simulate",
    "navigate_fields": "solverplan.reflection.navigation",
    "flows_through": "solverplan.reflection.fields",
    "FlowCheck": "solverplan.reflection.fields",
    "FieldNavigation": "solverplan.reflection.navigation",
    # floor plans in: ROS occupancy maps, DXF and SVG drawings
    "import_floorplan": "solverplan.floorplan.importer",
    "FloorplanImport": "solverplan.floorplan.importer",
    "read_occupancy_map": "solverplan.floorplan.occupancy",
    "read_keepout_mask": "solverplan.floorplan.occupancy",
    # planners
    "find_plan": "solverplan.plan.search",
    "pareto_front": "solverplan.plan.search",
    "patrol": "solverplan.plan.patrols",
    "funnel": "solverplan.plan.funnels",
    "localize": "solverplan.plan.localization",
    "load_plan": "solverplan.plan.result",
    "export_plan": "solverplan.plan.export",
    "plan_in_world": "solverplan.plan.export",
    # the result protocol
    "Status": "solverplan.result",
    "StatusGroup": "solverplan.result",
    "Method": "solverplan.result",
    "Optimality": "solverplan.result",
    "Stats": "solverplan.result",
    "Stage": "solverplan.result",
    "Plan": "solverplan.plan.result",
    "ParetoFront": "solverplan.plan.result",
    "Patrol": "solverplan.plan.patrols",
    "Funnel": "solverplan.plan.funnels",
    "LimitCycle": "solverplan.bounce.cycles",
    # ground truth and proofs
    "simulate_plan": "solverplan.simulate",
    "simulate_rule": "solverplan.simulate",
    "certificate": "solverplan.certify.build",
    "write_certificate": "solverplan.certify.build",
    "check_certificate": "solverplan.certify.check",
    "CheckReport": "solverplan.certify.check",
    # the one verdict every check gives (certificates, pursuit replays, flow-through tests)
    "Verdict": "solverplan.verdict",
    "Failure": "solverplan.verdict",
    "load_certificate": "solverplan.certify.schema",
    # HTML reports of answers (solverplan report)
    "load_answer": "solverplan.render.report",
    "html_report": "solverplan.render.report",
    "write_report": "solverplan.render.report",
    "HtmlReport": "solverplan.render.report",
    "make_report": "solverplan.render.report",
    # every answer kind, read back (solverplan.answers)
    "Answer": "solverplan.result",
    "read_answer": "solverplan.answers",
    "load_answer_file": "solverplan.answers",
    # errors
    "SolverplanError": "solverplan.errors",
    "InputError": "solverplan.errors",
    "InvalidEnvironment": "solverplan.errors",
    "InvalidBoundarySet": "solverplan.errors",
    "MalformedFile": "solverplan.errors",
    "SolverFailed": "solverplan.errors",
}

__all__ = sorted(_EXPORTS)

if TYPE_CHECKING:  # what type checkers and readers see; at run time the names load lazily
    from solverplan import choices, models
    from solverplan.runtime import Settings, config, configure, settings
    from solverplan.progress import Stopped, watching
    from solverplan.bounce.bvg import bounce_visibility_graph, safe_bounce_visibility_graph
    from solverplan.bounce.controller import constant_controller
    from solverplan.bounce.cycles import LimitCycle, limit_cycle
    from solverplan.bounce.partitions import partition
    from solverplan.certify.build import certificate, write_certificate
    from solverplan.certify.check import CheckReport, check_certificate
    from solverplan.certify.schema import load_certificate
    from solverplan.environment import BoundaryPiece, BoundarySet, Environment, load_environment
    from solverplan.errors import (InputError, InvalidBoundarySet, InvalidEnvironment, MalformedFile, SolverFailed,
                                   SolverplanError)
    from solverplan.explore.depth_first import Exploration, explore_depth_first
    from solverplan.floorplan.importer import FloorplanImport, import_floorplan
    from solverplan.floorplan.occupancy import read_keepout_mask, read_occupancy_map
    from solverplan.explore.range_limited import RangeExploration, explore_range_limited
    from solverplan.explore.range_view import RangeView, range_visibility
    from solverplan.interval import Interval
    from solverplan.plan.funnels import Funnel, funnel
    from solverplan.plan.localization import localize
    from solverplan.plan.patrols import Patrol, patrol
    from solverplan.plan.export import export_plan, plan_in_world
    from solverplan.plan.result import ParetoFront, Plan, load_plan
    from solverplan.plan.search import find_plan, pareto_front
    from solverplan.rectilinear.decomposition import decompose_rooms
    from solverplan.answers import load_answer_file, read_answer
    from solverplan.render.report import HtmlReport, html_report, load_answer, make_report, write_report
    from solverplan.result import Answer, Method, Optimality, Stage, Stats, Status, StatusGroup
    from solverplan.simulate import simulate_plan, simulate_rule
    from solverplan.wallfollow.cut import cut_ordering
    from solverplan.wallfollow.learning import learn_cut_ordering
    from solverplan.wallfollow.ordering import CutOrdering
    from solverplan.wallfollow.pursuit import PursuitPlan, pursuit_plan
    from solverplan.wallfollow.pursuit_check import PursuitCheck, check_pursuit
    from solverplan.wallfollow.pebble import PebbleWorld, learn_bitangents
    from solverplan.wallfollow.world import WallWorld
    from solverplan.reflection.cells import decompose_free_space
    from solverplan.reflection.compose import compose_fields
    from solverplan.reflection.fields import FlowCheck, flows_through
    from solverplan.reflection.navigation import FieldNavigation, navigate_fields
    from solverplan.verdict import Failure, Verdict
    from solverplan.reflection.simulate import FieldRobotDynamics, simulate_scenarios
    from solverplan.rectilinear.simulation import compare_rules, simulate_rooms


def __getattr__(name: str) -> Any:
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'solverplan' has no attribute {name!r}")
    value = importlib.import_module(module)
    if module != f"solverplan.{name}":  # a name defined in the module (not the module itself: ``models``)
        value = getattr(value, name)
    globals()[name] = value  # later look-ups skip this function
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
