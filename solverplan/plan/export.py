"""Plans out to robots: a plan's stages in world coordinates (the map frame), as waypoints, CSV or GeoJSON.

A plan speaks of segments of P′ and of headings measured from the wall the robot is on. A robot stack speaks of
the map frame: where on which wall the robot may be (metres), and which absolute headings it may leave with.
:func:`plan_in_world` translates each stage, for each wall piece the robot may be on at that stage (a *contact*):

- ``wall``: the wall's two end points (the environment's edge, world coordinates) and its edge id;
- ``contact``: the range of the contact point along that wall, in metres from the wall's first end
  (``from_m``, ``to_m``) and as two points (``a``, ``b``); consecutive segments of one wall are one contact
  (``segments`` lists them; ``segment`` is the id when there is one);
- ``heading``: the interval of absolute headings in the map frame, radians CCW from the map's +x axis and degrees:
  the wall's direction plus the plan's interval. ``lo`` lies in (−π, π]; ``hi = lo + width`` (it may pass π:
  the interval does not wrap);
- ``lands_on``: the wall pieces the stage lands on (the next stage's contacts), with their coordinates.

Formats (:func:`export_plan`): ``waypoints`` (JSON: one pose per contact at the middle of its range with the middle
heading as yaw and a quaternion, in the map frame, plus the ranges — what a waypoint follower reads), ``csv`` (one
row per contact) and ``geojson`` (a FeatureCollection: the free space, each contact range and each landing range
as LineStrings with their stage and headings as properties).
"""

from __future__ import annotations

import csv
import io
import json
import math
from typing import Any

from solverplan.choices import ExportFormat
from solverplan.environment import Environment
from solverplan.errors import InputError

__all__ = ["plan_in_world", "export_plan", "EXPORT_FORMATS"]

EXPORT_FORMATS: tuple[str, ...] = ExportFormat.values()


def _wall_piece(env: Environment, edge: int, t0: float, t1: float) -> dict:
    a, b = env.edge_start[edge], env.edge_end[edge]
    length = float(env.edge_lengths[edge])
    pa = a + (b - a) * t0
    pb = a + (b - a) * t1
    return {
        "edge": edge,
        "wall": [[float(a[0]), float(a[1])], [float(b[0]), float(b[1])]],
        "from_m": t0 * length,
        "to_m": t1 * length,
        "a": [float(pa[0]), float(pa[1])],
        "b": [float(pb[0]), float(pb[1])],
    }


def _heading(env: Environment, edge: int, lo: float, hi: float) -> dict:
    a, b = env.edge_start[edge], env.edge_end[edge]
    direction = math.atan2(float(b[1] - a[1]), float(b[0] - a[0]))
    start = math.remainder(direction + lo, 2 * math.pi)
    if start <= -math.pi:
        start += 2 * math.pi
    end = start + (hi - lo)
    return {"lo": start, "hi": end, "lo_deg": math.degrees(start), "hi_deg": math.degrees(end),
            "width": hi - lo, "wall_direction": direction}


def _runs(sources: list) -> list[tuple[list, int, float, float]]:
    """Pieces of one wall that follow one another, joined: a robot on any of them leaves with the same map-frame
    headings (the wall's direction is the same), so a contact is a whole run, listing its segments."""
    out: list[tuple[list, int, float, float]] = []
    for segment, edge, t0, t1 in sorted(sources, key=lambda item: (item[1], item[2])):
        ids = [] if segment is None else [segment]
        if out and out[-1][1] == edge and abs(out[-1][3] - t0) <= 1e-12:
            previous = out[-1]
            out[-1] = (previous[0] + ids, edge, previous[2], t1)
        else:
            out.append((ids, edge, t0, t1))
    return out


def plan_in_world(plan: Any, env: Environment) -> list[dict]:
    """The stages of a found plan in world coordinates (module docstring).

    Parameters
    ----------
    plan
        A :class:`~solverplan.plan.result.Plan` (found), made in ``env``.
    env
        Its environment (world coordinates: metres for imported maps).

    Returns
    -------
    list of dict
        Per stage: ``stage`` (0-based), ``interval`` (the plan's, radians from the wall), ``contacts`` (a dict
        per wall piece the robot may be on: ``segment``, the wall, the contact range and the map-frame heading
        interval) and ``lands_on`` (the wall pieces it lands on).

    Raises
    ------
    InputError
        When the plan was not found, or was made in another environment.

    Examples
    --------
    >>> from solverplan.plan import find_plan
    >>> room = Environment.from_coords([[0, 0], [4, 0], [6, 3], [-2, 3]], name="room")
    >>> stage = plan_in_world(find_plan(room, "e0", "e2"), room)[0]
    >>> contact = stage["contacts"][0]
    >>> contact["wall"], contact["from_m"], contact["to_m"], round(contact["heading"]["lo_deg"], 2)
    ([[0.0, 0.0], [4.0, 0.0]], 0.0, 4.0, 56.32)
    >>> stage["lands_on"][0]["wall"]
    [[6.0, 3.0], [-2.0, 3.0]]
    """
    from solverplan.bounce.partitions import partition

    if not getattr(plan, "found", False):
        raise InputError(f"only a found plan can be exported, this one is {plan.status.value!r}")
    part = partition(env)
    plan.check_environment(env, len(part.segments))
    out = []
    for k, stage in enumerate(plan.stages):
        lo, hi = stage.interval.lo, stage.interval.hi
        if stage.sources:
            # a piece of a segment (a start set or a landing unit ending inside it) names the segment it lies on
            seen: set = set()
            sources = []
            for p in stage.sources:
                if (p.edge, p.t0, p.t1) not in seen:
                    seen.add((p.edge, p.t0, p.t1))
                    on = [s for s in part.edge_segments[p.edge] if part.segments[s].t0 < p.t1 and p.t0 < part.segments[s].t1]
                    sources.append((on[0] if len(on) == 1 else None, p.edge, float(p.t0), float(p.t1)))
        else:
            sources = [(s, part.segments[s].edge, float(part.segments[s].t0), float(part.segments[s].t1))
                       for s in stage.from_segments]
        contacts = []
        for segments, edge, t0, t1 in _runs(sources):
            contact: dict = {"segment": segments[0] if len(segments) == 1 else None, "segments": segments,
                       **_wall_piece(env, edge, t0, t1), "heading": _heading(env, edge, lo, hi)}
            contacts.append(contact)
        lands = []
        for s in stage.to_segments:
            seg = part.segments[s]
            lands.append({"segment": s, **_wall_piece(env, seg.edge, float(seg.t0), float(seg.t1))})
        out.append({"stage": k, "interval": [lo, hi], "width": hi - lo, "contacts": contacts, "lands_on": lands})
    return out


def export_plan(plan: Any, env: Environment, fmt: str = "waypoints") -> str:
    """A found plan as text a robot stack reads: ``waypoints`` (JSON), ``csv`` or ``geojson`` (module docstring).

    Parameters
    ----------
    plan
        A found :class:`~solverplan.plan.result.Plan`, made in ``env``.
    env
        Its environment (world coordinates: metres for imported maps).
    fmt
        ``waypoints`` (JSON poses in the map frame with their yaw ranges and contact ranges), ``csv`` (a row per
        contact) or ``geojson`` (a FeatureCollection).

    Returns
    -------
    str
        The text of the file (UTF-8), ending with a newline.

    Raises
    ------
    InputError
        An unknown format, a plan not found, or a plan made in another environment.

    Examples
    --------
    >>> from solverplan.plan import find_plan
    >>> room = Environment.from_coords([[0, 0], [4, 0], [6, 3], [-2, 3]], name="room")
    >>> print(export_plan(find_plan(room, "e0", "e2"), room, "csv").splitlines()[0])
    stage,segments,edge,wall_x0,wall_y0,wall_x1,wall_y1,from_m,to_m,contact_x0,contact_y0,contact_x1,contact_y1,heading_lo_rad,heading_hi_rad,heading_lo_deg,heading_hi_deg,width_rad,lands_on
    """
    fmt = ExportFormat.parse(fmt, "export format").value
    stages = plan_in_world(plan, env)
    if fmt == "csv":
        buffer = io.StringIO()
        writer = csv.writer(buffer, lineterminator="\n")
        writer.writerow(["stage", "segments", "edge", "wall_x0", "wall_y0", "wall_x1", "wall_y1", "from_m", "to_m",
                         "contact_x0", "contact_y0", "contact_x1", "contact_y1", "heading_lo_rad", "heading_hi_rad",
                         "heading_lo_deg", "heading_hi_deg", "width_rad", "lands_on"])
        for stage in stages:
            lands = " ".join(str(p["segment"]) for p in stage["lands_on"])
            for c in stage["contacts"]:
                h = c["heading"]
                writer.writerow([stage["stage"], " ".join(map(str, c["segments"])), c["edge"],
                                 *c["wall"][0], *c["wall"][1], repr(c["from_m"]), repr(c["to_m"]), *c["a"], *c["b"],
                                 repr(h["lo"]), repr(h["hi"]), repr(h["lo_deg"]), repr(h["hi_deg"]), repr(h["width"]),
                                 lands])
        return buffer.getvalue()
    if fmt == "geojson":
        features: list[dict] = [{"type": "Feature", "properties": {"kind": "free_space", "name": env.name},
                                 "geometry": _polygon_json(env)}]
        for stage in stages:
            for c in stage["contacts"]:
                features.append({"type": "Feature", "geometry": {"type": "LineString", "coordinates": [c["a"], c["b"]]},
                                 "properties": {"kind": "contact", "stage": stage["stage"], "segments": c["segments"],
                                                "edge": c["edge"], "from_m": c["from_m"], "to_m": c["to_m"],
                                                "heading_lo_rad": c["heading"]["lo"], "heading_hi_rad": c["heading"]["hi"],
                                                "heading_lo_deg": c["heading"]["lo_deg"],
                                                "heading_hi_deg": c["heading"]["hi_deg"]}})
            for p in stage["lands_on"]:
                features.append({"type": "Feature", "geometry": {"type": "LineString", "coordinates": [p["a"], p["b"]]},
                                 "properties": {"kind": "landing", "stage": stage["stage"], "segment": p["segment"],
                                                "edge": p["edge"], "from_m": p["from_m"], "to_m": p["to_m"]}})
        return json.dumps({"type": "FeatureCollection", "features": features}, indent=1) + "\n"
    waypoints = []
    for stage in stages:
        for c in stage["contacts"]:
            h = c["heading"]
            yaw = (h["lo"] + h["hi"]) / 2
            x, y = (c["a"][0] + c["b"][0]) / 2, (c["a"][1] + c["b"][1]) / 2
            waypoints.append({
                "stage": stage["stage"],
                "pose": {"position": {"x": x, "y": y, "z": 0.0},
                         "orientation": {"x": 0.0, "y": 0.0, "z": math.sin(yaw / 2), "w": math.cos(yaw / 2)}},
                "yaw": yaw,
                "yaw_range": [h["lo"], h["hi"]],
                "contact": {"edge": c["edge"], "segments": c["segments"], "wall": c["wall"], "from_m": c["from_m"],
                            "to_m": c["to_m"], "a": c["a"], "b": c["b"]},
                "lands_on": [{"edge": p["edge"], "segment": p["segment"], "a": p["a"], "b": p["b"]}
                             for p in stage["lands_on"]],
            })
    document = {"frame_id": "map", "environment": env.name, "bounces": len(stages),
                "note": "each stage: from anywhere on a contact range, leave with any yaw in yaw_range (radians, map "
                        "frame) and drive straight until the bump; pose is the middle of both",
                "waypoints": waypoints, "stages": stages}
    return json.dumps(document, indent=1) + "\n"


def _polygon_json(env: Environment) -> dict:
    rings = []
    for ring in env.rings:
        points = [[float(x), float(y)] for x, y in ring]
        rings.append(points + points[:1])
    return {"type": "Polygon", "coordinates": rings}
