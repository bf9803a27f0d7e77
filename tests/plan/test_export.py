"""Plans out to robots: the world-frame export agrees with the plan, and heading accuracy constrains the plans."""

from __future__ import annotations

import csv
import io
import json
import math
import re

import pytest
from typer.testing import CliRunner

from solverplan.cli import app
from solverplan.environment import Environment, load_environment
from solverplan.errors import InputError
from solverplan.plan import export_plan, find_plan, plan_in_world
from solverplan.simulate import simulate_plan

runner = CliRunner()
ROOM = Environment.from_coords([[0, 0], [4, 0], [6, 3], [-2, 3]], name="room")
ELL = Environment.from_coords([[0, 0], [10, 0], [10, 4], [4, 4], [4, 10], [0, 10]], name="ell")


def test_the_world_frame_headings_are_the_wall_direction_plus_the_interval():
    plan = find_plan(ELL, "e5", "e0:0:0.3", objective="tolerance")
    stages = plan_in_world(plan, ELL)
    assert len(stages) == plan.bounces
    for stage, original in zip(stages, plan.stages):
        for contact in stage["contacts"]:
            (x0, y0), (x1, y1) = contact["wall"]
            direction = math.atan2(y1 - y0, x1 - x0)
            h = contact["heading"]
            assert h["hi"] - h["lo"] == pytest.approx(original.interval.width)
            assert math.remainder(h["lo"] - direction - original.interval.lo, 2 * math.pi) == pytest.approx(0, abs=1e-12)
            assert -math.pi < h["lo"] <= math.pi and h["lo_deg"] == pytest.approx(math.degrees(h["lo"]))
            length = math.hypot(x1 - x0, y1 - y0)
            assert 0 <= contact["from_m"] < contact["to_m"] <= length + 1e-12
            # the contact points lie on the wall, at the distances said
            ax, ay = contact["a"]
            assert math.hypot(ax - x0, ay - y0) == pytest.approx(contact["from_m"])
        # each stage lands where the next one leaves from
        if stage["stage"] + 1 < len(stages):
            nxt = stages[stage["stage"] + 1]
            landed = {s["segment"] for s in stage["lands_on"]}
            assert landed == {s for c in nxt["contacts"] for s in c["segments"]}


def test_a_robot_that_follows_the_waypoints_reaches_the_goal():
    plan = find_plan(ELL, "e5", "e0:0:0.3", objective="tolerance")
    document = json.loads(export_plan(plan, ELL, "waypoints"))
    assert document["frame_id"] == "map" and len(document["waypoints"]) >= plan.bounces
    for waypoint in document["waypoints"]:
        yaw = waypoint["yaw"]
        q = waypoint["pose"]["orientation"]
        assert math.atan2(2 * q["w"] * q["z"], 1 - 2 * q["z"] ** 2) == pytest.approx(math.remainder(yaw, 2 * math.pi))
        lo, hi = waypoint["yaw_range"]
        assert lo < yaw < hi
    # the exported intervals are the plan's: a Monte Carlo run of the plan itself succeeds
    assert simulate_plan(ELL, plan, trials=300, seed=1).success_rate == 1.0


def test_csv_and_geojson_carry_every_contact():
    plan = find_plan(ROOM, "e0", "e2")
    rows = list(csv.DictReader(io.StringIO(export_plan(plan, ROOM, "csv"))))
    stages = plan_in_world(plan, ROOM)
    assert len(rows) == sum(len(s["contacts"]) for s in stages)
    assert float(rows[0]["heading_hi_rad"]) - float(rows[0]["heading_lo_rad"]) == pytest.approx(plan.min_width)
    collection = json.loads(export_plan(plan, ROOM, "geojson"))
    kinds = [f["properties"]["kind"] for f in collection["features"]]
    assert kinds[0] == "free_space" and kinds.count("contact") == len(rows) and "landing" in kinds
    assert collection["features"][0]["geometry"]["coordinates"][0][0] == [0.0, 0.0]
    with pytest.raises(InputError, match="unknown export format"):
        export_plan(plan, ROOM, "kml")


def test_the_export_command(tmp_path):
    plan_file = tmp_path / "plan.json"
    ROOM_FILE = tmp_path / "room.json"
    ROOM_FILE.write_text(json.dumps(ROOM.to_dict()))
    assert runner.invoke(app, ["plan", str(ROOM_FILE), "--from", "e0", "--to", "e2", "-o", str(plan_file)]).exit_code == 0
    for fmt in ("waypoints", "csv", "geojson"):
        result = runner.invoke(app, ["export", str(plan_file), "--env", str(ROOM_FILE), "--format", fmt])
        assert result.exit_code == 0, result.output
    out = tmp_path / "plan.csv"
    result = runner.invoke(app, ["export", str(plan_file), "--env", str(ROOM_FILE), "--format", "csv", "-o", str(out)])
    assert result.exit_code == 0 and out.read_text().startswith("stage,segments,edge")
    other = runner.invoke(app, ["export", str(plan_file), "--env", "square"])
    assert other.exit_code == 2 and "another environment" in other.stderr and other.stderr.count("\n") == 1


def test_heading_accuracy_plans_only_with_intervals_that_wide():
    best = find_plan(ELL, "e5", "e0:0:0.3", objective="tolerance")
    wide = find_plan(ELL, "e5", "e0:0:0.3", min_width=0.3)
    assert wide.found and all(s.interval.width >= 0.3 for s in wide.stages)
    assert wide.bounces >= find_plan(ELL, "e5", "e0:0:0.3").bounces
    assert not wide.optimality.proved and "at least 0.3 rad wide" in wide.optimality.scope
    too_wide = find_plan(ELL, "e5", "e0:0:0.3", min_width=best.min_width * 1.01)
    assert too_wide.status.value == "infeasible"
    said = float(re.search(r"best heading accuracy that would work is ([0-9.]+) rad", too_wide.reason).group(1))
    assert said == pytest.approx(best.min_width, rel=1e-5)
    assert "start pieces that block" in too_wide.reason and "segment" in too_wide.reason
    exact = find_plan(ELL, "e5", "e0:0:0.3", min_width=best.min_width * 0.999, objective="tolerance")
    assert exact.found and exact.min_width == pytest.approx(best.min_width)
    with pytest.raises(InputError, match="heading accuracy must be"):
        find_plan(ELL, "e5", "e0", min_width=4.0)
    with pytest.raises(InputError, match="applies to the fewest, tolerance and constant"):
        find_plan(ELL, "e5", "e0", min_width=0.1, objective="sum", max_bounces=3)


def test_the_plan_command_takes_a_heading_accuracy(tmp_path):
    result = runner.invoke(app, ["plan", "l_shape", "--from", "e5", "--to", "e0:0:0.3", "--heading-accuracy", "3"])
    assert result.exit_code == 0, result.output
    answer = json.loads(result.stdout)
    assert answer["status"] == "infeasible" and "best heading accuracy that would work" in answer["reason"]
    bad = runner.invoke(app, ["plan", "l_shape", "--from", "e5", "--to", "e0", "--heading-accuracy", "-1"])
    assert bad.exit_code == 2 and bad.stderr.count("\n") == 1


def test_a_contact_on_a_piece_of_a_segment_names_the_segment():
    """A stage that leaves from part of a segment (a start set ending inside it, or a landing unit) lists the piece
    as its contact, and names the segment the piece lies on (it named none)."""
    plan = find_plan(ELL, "e0:0.1:0.3", "e3", objective="tolerance")
    assert plan.found and plan.stages[0].sources
    contact = plan_in_world(plan, ELL)[0]["contacts"][0]
    assert contact["segment"] == 0 and contact["segments"] == [0]
    assert contact["from_m"] == pytest.approx(1.0) and contact["to_m"] == pytest.approx(3.0)
