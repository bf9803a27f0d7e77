"""`solverplan rooms`: the decomposition answer, the simulation answers (one rule, all three), pictures, errors."""

from __future__ import annotations

import json


from tests.cli_runs import run



def one_line_error(result, fragment: str) -> None:
    assert result.exit_code == 2, (result.exit_code, result.stdout, result.stderr)
    assert result.stdout == "" and len(result.stderr.splitlines()) == 1
    assert result.stderr.startswith("error: ") and fragment in result.stderr, result.stderr


def test_rooms_answer_has_rooms_doors_and_tree():
    result = run("rooms", "three_chambers")
    assert result.exit_code == 0, result.stderr
    data = json.loads(result.stdout)
    assert [room["id"] for room in data["rooms"]] == [0, 1, 2, 3, 4]
    assert data["rooms"][0]["polygon"] == [[0, 0], [30, 0], [30, 30], [0, 30]] and data["rooms"][0]["area"] == 900
    door = data["doors"][0]
    assert door["a"] == [30, 14.5] and door["b"] == [30, 15.5] and door["rooms"] == [0, 4]
    assert door["escapability_by_room_exact"] == ["1/30", "1"] and door["escapability_exact"] == "1/30"
    assert sorted(map(tuple, data["tree"])) == [(0, 4), (1, 3), (1, 4), (2, 3)]
    assert data["status"] == "found" and data["environment"]["name"] == "three_chambers"


def test_warehouse_rooms_as_text():
    result = run("rooms", "warehouse", "--format", "text")
    assert result.exit_code == 0, result.stderr
    assert result.stdout.startswith("15 rooms and 14 doors in warehouse")


def test_simulate_one_rule_gives_the_contract_fields():
    result = run("rooms", "three_chambers", "--simulate", "--from", 0, "--to", 2, "--rule", "smart", "--trials", 5, "--seed", 3)
    assert result.exit_code == 0, result.stderr
    data = json.loads(result.stdout)
    assert {"rule", "trials", "success", "bounces_mean", "bounces_median", "trapped"} <= set(data)
    assert data["rule"] == "smart" and data["trials"] == 5 and data["success"] == 1.0 and data["rooms"] == [0, 4, 1, 3, 2]
    assert data["recommended"] == "smart" and data["reachability_exact"] == "1/300"


def test_simulate_a_tour_of_every_room():
    result = run("rooms", "three_chambers", "--simulate", "--from", 1, "--tour", "--trials", 3, "--max-bounces", 20000)
    assert result.exit_code == 0, result.stderr
    data = json.loads(result.stdout)
    assert data["rooms"] == [1, 3, 2, 3, 1, 4, 0] and data["to"] == 0 and data["success"] == 1.0


def test_simulate_all_rules_side_by_side_with_a_picture(tmp_path):
    picture = tmp_path / "rules.png"
    result = run("rooms", "three_chambers", "--simulate", "--from", 2, "--to", 0, "--rule", "all", "--trials", 4,
                 "--max-bounces", 3000, "--picture", picture)
    assert result.exit_code == 0, result.stderr
    data = json.loads(result.stdout)
    assert set(data["rules"]) == {"smart", "smart-paper", "smart-per-room", "random", "billiard"}
    assert data["rooms"] == [2, 3, 1, 4, 0]
    advice = data["recommendation"]
    assert data["recommended"] == advice["rule"] and data["paper_recommendation"] in ("smart", "random")
    arrived = [name for name, row in data["rules"].items() if row["success"] == 1.0 and not row["trapped"]]
    assert sorted(advice["always_arrived"]) == sorted(arrived)
    fastest = min(data["rules"][name]["bounces_mean"] for name in arrived)
    assert data["rules"][data["recommended"]]["bounces_mean"] <= 1.2 * fastest
    assert picture.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    text = run("rooms", "three_chambers", "--simulate", "--from", 2, "--to", 0, "--rule", "all", "--trials", 4,
               "--max-bounces", 3000, "--format", "text")
    rows = [line.split()[0] for line in text.stdout.splitlines()[2:7]]
    assert rows == ["smart", "smart-paper", "smart-per-room", "random", "billiard"]


def test_rooms_picture_without_simulation(tmp_path):
    picture = tmp_path / "rooms.svg"
    result = run("rooms", "warehouse", "--picture", picture)
    assert result.exit_code == 0, result.stderr
    svg = picture.read_text()
    assert 'id="doors"' in svg and 'id="room-14"' in svg


def test_bad_rooms_requests_are_one_line_errors():
    one_line_error(run("rooms", "one_hole"), "rooms need a polygon without holes")
    one_line_error(run("rooms", "two_rooms"), "rooms need a rectilinear polygon: edge")
    one_line_error(run("rooms", "three_chambers", "--from", 0), "--from, --to and --tour choose the rooms of --simulate")
    one_line_error(run("rooms", "three_chambers", "--simulate", "--from", 0), "--simulate needs --from ROOM and either --to ROOM or --tour")
    one_line_error(run("rooms", "three_chambers", "--simulate", "--from", 0, "--to", 2, "--tour"), "either --to ROOM or --tour")
    one_line_error(run("rooms", "three_chambers", "--simulate", "--from", 0, "--to", 9), "unknown room 9: rooms are 0..4")
    one_line_error(run("rooms", "three_chambers", "--picture", "x.gif"), "gif")


def test_generate_polyomino_then_rooms(tmp_path):
    env = tmp_path / "poly.json"
    result = run("generate", "polyomino", "--cells", 14, "--max-size", 3, "--seed", 5, "-o", env)
    assert result.exit_code == 0, result.stderr
    rooms = run("rooms", env)
    assert rooms.exit_code == 0, rooms.stderr
    data = json.loads(rooms.stdout)
    assert len(data["rooms"]) == len(data["doors"]) + 1 >= 1
    one_line_error(run("generate", "polyomino", "--cells", 0), "--cells")


def test_check_a_rooms_answer_file(tmp_path):
    answer = tmp_path / "rooms.json"
    assert run("rooms", "warehouse", "-o", answer).exit_code == 0
    result = run("rooms", "warehouse", "--check", answer)
    assert result.exit_code == 0, result.stderr
    assert json.loads(result.stdout)["valid"] is True
    data = json.loads(answer.read_text())
    data["rooms"][0]["area_exact"] = "63"
    answer.write_text(json.dumps(data))
    bad = run("rooms", "warehouse", "--check", answer)
    assert bad.exit_code == 1 and json.loads(bad.stdout)["valid"] is False
    assert bad.stderr.startswith("error: rooms answer invalid: claims.rooms[0].area: claims 63, the room's area is 64")
    one_line_error(run("rooms", "warehouse", "--check", tmp_path / "none.json"), "no such file")
    (tmp_path / "junk.json").write_text("{")
    one_line_error(run("rooms", "warehouse", "--check", tmp_path / "junk.json"), "not valid JSON")
    one_line_error(run("rooms", "warehouse", "--check", answer, "--simulate"), "--check checks an answer file")
