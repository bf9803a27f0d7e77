"""The HTML report (solverplan.render.report, ``solverplan report``): well-formed, self-contained, escaped, and
showing what the answer and its certificate say — the certificate checked, never trusted."""

from __future__ import annotations

import base64
import hashlib
import html
import json
import re
import shlex
import xml.etree.ElementTree as ET
from html.parser import HTMLParser
from pathlib import Path

import pytest

from solverplan.certify.schema import load_certificate
from solverplan.environment import Environment, load_environment
from solverplan.errors import InputError, MalformedFile
from solverplan.render.report import AnswerFile, detect_answer_kind, html_report, load_answer

from .conftest import ANSWER_COMMANDS, CERTIFICATES, ENVIRONMENTS, report_args, run

VOID = {"area", "base", "br", "col", "embed", "hr", "img", "input", "link", "meta", "source", "track", "wbr"}
SVG_NS = "{http://www.w3.org/2000/svg}"


class _Checker(HTMLParser):
    """Every element closed, in order (HTML void elements and self-closed SVG elements aside); attributes kept."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.stack: list[str] = []
        self.errors: list[str] = []
        self.elements: list[tuple[str, dict[str, str | None]]] = []

    def handle_starttag(self, tag, attrs):
        self.elements.append((tag, dict(attrs)))
        if tag not in VOID:
            self.stack.append(tag)

    def handle_startendtag(self, tag, attrs):
        self.elements.append((tag, dict(attrs)))

    def handle_endtag(self, tag):
        if not self.stack or self.stack[-1] != tag:
            self.errors.append(f"</{tag}> closes {self.stack[-1:] or 'nothing'} at {self.getpos()}")
        else:
            self.stack.pop()


def parse(text: str) -> _Checker:
    checker = _Checker()
    checker.feed(text)
    checker.close()
    assert not checker.errors, checker.errors[:3]
    assert not checker.stack, f"unclosed: {checker.stack}"
    return checker


def svgs(text: str) -> list[ET.Element]:
    """Every inline <svg>, parsed as XML (it must be well-formed XML on its own)."""
    return [ET.fromstring(m) for m in re.findall(r"<svg\b.*?</svg>", text, flags=re.S)]


def ids(checker: _Checker) -> set[str]:
    return {a["id"] for _, a in checker.elements if a.get("id")}


# ---------------------------------------------------------------------- every kind of answer
@pytest.mark.parametrize("kind", list(ANSWER_COMMANDS))
def test_report_is_well_formed_and_self_contained(kind, reports):
    text = reports[kind].read_text(encoding="utf-8")
    assert text.startswith("<!DOCTYPE html>")
    page = parse(text)
    for tag, attrs in page.elements:  # nothing is fetched from anywhere: no URL in src or href, no external files
        for name in ("src", "href", "xlink:href"):
            assert not re.match(r"\s*(https?:)?//", attrs.get(name) or ""), (tag, name, attrs[name])
        assert tag not in ("link", "img", "iframe", "object", "embed"), tag
    scripts = [a for t, a in page.elements if t == "script"]
    assert len(scripts) == 1 and "src" not in scripts[0]
    pictures = svgs(text)
    assert pictures and all(p.tag == f"{SVG_NS}svg" for p in pictures)
    expected = {"picture", "details", "certificate", "numbers", "reproduce", "command", "made-with", "summary"}
    if kind == "study":  # a study has no certificate, no single environment picture
        expected.discard("certificate")
    assert expected <= ids(page)


def test_the_page_runs_only_its_own_script_and_style(reports):
    """The Content-Security-Policy forbids the network and names the page's one script and style by their SHA-256."""
    text = reports["plan"].read_text(encoding="utf-8")
    csp = next(a["content"] for t, a in parse(text).elements if a.get("http-equiv") == "Content-Security-Policy")
    assert "default-src 'none'" in csp
    for tag, directive in (("script", "script-src"), ("style", "style-src")):
        body = re.search(rf"<{tag}>(.*?)</{tag}>", text, flags=re.S).group(1)
        digest = base64.b64encode(hashlib.sha256(body.encode()).digest()).decode()
        assert f"{directive} 'sha256-{digest}'" in csp


def test_plan_report_draws_every_stage_and_segment(reports, answers):
    plan = json.loads((answers / "plan.json").read_text())
    text = reports["plan"].read_text(encoding="utf-8")
    scene = svgs(text)[0]
    assert scene.get("id") == "scene"
    everything = list(scene.iter())
    cones = [e for e in everything if "cone" in (e.get("class") or "").split()]
    stages = {int(e.get("data-stage")) for e in cones}
    assert stages == set(range(plan["bounces"]))  # a cone per stage (each of its moves), tagged with it
    assert len(cones) == sum(len(s["moves"]) for s in plan["stages"])
    for cone in cones:  # hover details: the stage, its move and its interval
        title = cone.find(f"{SVG_NS}title").text
        assert title.startswith(f"stage {int(cone.get('data-stage')) + 1}, move ") and "heading interval [" in title
    segments = {int(e.get("data-segment")) for e in everything if e.get("data-segment") is not None}
    assert segments == set(range(plan["environment"]["n_segments"]))
    walls = {int(e.get("data-edge")) for e in everything if e.get("data-edge") is not None}
    assert walls == set(range(len(load_environment("two_rooms").edges)))
    # the stage table has one row per stage, highlighted with the picture
    page = parse(text)
    rows = [a for t, a in page.elements if t == "tr" and a.get("data-stage") is not None]
    assert [int(a["data-stage"]) for a in rows] == list(range(plan["bounces"]))
    assert 'id="certificate-status">VALID<' in text


def test_cycle_answers_show_contact_points_with_exact_parameters(reports, answers):
    for kind in ("patrol", "cycle", "controller"):
        data = json.loads((answers / f"{kind}.json").read_text())
        cycles = data["cycles"] if kind == "controller" else [data]
        scene = svgs(reports[kind].read_text(encoding="utf-8"))[0]
        contacts = [e for e in scene.iter() if "contact" in (e.get("class") or "").split()]
        assert len(contacts) == sum(len(c["fixed_point"]) for c in cycles)
        first = cycles[0]["fixed_point"][0]
        assert f"t = {first['t_exact']}" in contacts[0].find(f"{SVG_NS}title").text
    patrol = json.loads((answers / "patrol.json").read_text())
    fans = [e for e in svgs(reports["patrol"].read_text())[0].iter() if "fan" in (e.get("class") or "").split()]
    assert len(fans) == len(patrol["cycle"])  # each cycle stage's heading interval, with its exact map
    assert all("exact map t ↦" in f.find(f"{SVG_NS}title").text for f in fans)


def test_funnel_report_shows_every_position_set(reports, answers):
    for kind in ("funnel", "localize"):
        data = json.loads((answers / f"{kind}.json").read_text())
        scene = svgs(reports[kind].read_text(encoding="utf-8"))[0]
        lines = [e for e in scene.iter() if "positions" in (e.get("class") or "").split()]
        assert len(lines) == sum(len(s["positions"]) for s in data["stages"])
        last = data["stages"][-1]["positions"][0]
        assert any(f"[{last['t0_exact']}, {last['t1_exact']}]" in e.find(f"{SVG_NS}title").text for e in lines)


def test_study_report_has_a_heatmap_per_metric(reports, answers):
    data = json.loads((answers / "study.json").read_text())
    text = reports["study"].read_text(encoding="utf-8")
    maps = [s for s in svgs(text) if "heat" in (s.get("class") or "")]
    assert {m.get("aria-label") for m in maps} >= {"segments", "safe_arcs", "unreachable"}
    cells = [e for e in maps[0].iter() if "cell" in (e.get("class") or "").split()]
    assert len(cells) == len(data["cells"])  # two axes vary: one rect per cell
    assert 'id="certificate"' not in text


# ---------------------------------------------------------------------- the numbers and the command
def _without_stats(value):
    """An answer without its ``stats`` (times and counts, recorded but not part of the answer), at every depth."""
    if isinstance(value, dict):
        return {k: _without_stats(v) for k, v in value.items() if k != "stats"}
    if isinstance(value, list):
        return [_without_stats(v) for v in value]
    return value


@pytest.mark.parametrize("kind", ["plan", "pareto", "patrol", "funnel", "localize", "cycle", "controller"])
def test_the_reproducing_command_reproduces_the_answer(kind, answers, reports, tmp_path):
    """Run the page's 'Reproduce it' command: the same answer comes out (stats aside)."""
    text = reports[kind].read_text(encoding="utf-8")
    command = re.search(r'<code id="command">(.*?)</code>', text).group(1)
    words = shlex.split(html.unescape(command))
    assert words[:2] == ["solverplan", ANSWER_COMMANDS[kind][0]]
    out = tmp_path / "again.json"
    words = [str(out) if w == str(answers / f"{kind}.json") else w for w in words]
    words = [str(tmp_path / "again_cert.json") if w.endswith("cert.json") else w for w in words]
    result = run(*words[1:])
    assert result.exit_code == 0, result.stderr
    again, before = json.loads(out.read_text()), json.loads((answers / f"{kind}.json").read_text())
    assert _without_stats(again) == _without_stats(before)


def test_the_summary_shows_the_answers_numbers(reports, answers):
    plan = json.loads((answers / "plan.json").read_text())
    text = reports["plan"].read_text(encoding="utf-8")
    assert f"<th>bounces</th><td>{plan['bounces']}</td>" in text
    assert f"{plan['min_width']:.6g} rad" in text and plan["environment"]["sha256"] in text


# ---------------------------------------------------------------------- the certificate is checked, not trusted
def test_tampered_certificate_is_reported_invalid_and_exits_1(answers, tmp_path):
    cert = json.loads((answers / "cert.json").read_text())
    cert["stages"][1]["interval"][1] = "3.14159"  # wider than the cone the moves prove
    bad = tmp_path / "bad_cert.json"
    bad.write_text(json.dumps(cert))
    out = tmp_path / "r.html"
    result = run("report", "two_rooms", "--plan", answers / "plan.json", "--certificate", bad, "-o", out)
    assert result.exit_code == 1
    assert result.stderr.startswith("error: certificate invalid: stages[1].interval.hi: claims 3.14159")
    assert len(result.stderr.splitlines()) == 1
    text = out.read_text(encoding="utf-8")  # the page is written, and says so
    assert 'id="certificate-status">INVALID<' in text and "stages[1].interval.hi" in text
    assert json.loads(result.stdout)["certificate"]["valid"] is False


def test_certificate_of_a_changed_claim_is_caught_by_the_checker(answers):
    """The claimed numbers of the certificate are re-derived: an inflated min_width is a failure in the page."""
    cert = json.loads((answers / "cert.json").read_text())
    cert["claims"]["min_width"] = "0.2"
    env = load_environment("two_rooms")
    from solverplan.certify.schema import Certificate

    page = html_report(load_answer(answers / "plan.json"), env, certificate=Certificate.from_json(cert))
    assert page.certificate["valid"] is False
    assert any(f["claim"] == "claims.min_width" for f in page.certificate["failures"])


def test_issue_22_an_infeasible_plan_with_its_certificate_shows_what_is_proved(tmp_path):
    plan, cert, out = tmp_path / "none.json", tmp_path / "none_cert.json", tmp_path / "none.html"
    made = run("plan", "comb", "--from", "e3:0.15:1,e4:0:0.25", "--to", "e3:0.4:1,e4:0:0.05", "--max-bounces", "4",
               "-o", plan, "--certificate", cert)
    assert made.exit_code == 0, made.stderr
    result = run("report", "comb", "--plan", plan, "--certificate", cert, "-o", out)
    assert result.exit_code == 0, result.stderr
    assert json.loads(result.stdout)["certificate"] == {**json.loads(result.stdout)["certificate"], "valid": True,
                                                        "kind": "infeasible"}
    text = out.read_text(encoding="utf-8")
    parse(text)
    assert 'id="certificate-status">VALID<' in text and "no plan with at most 4 stages takes the start set" in text
    other = run("report", "two_rooms", "--plan", tmp_path / "none.json", "--certificate", cert, "-o", out)
    assert other.exit_code == 2  # another environment


# ---------------------------------------------------------------------- escaping
HOSTILE = '<script>alert("x")</script><img src=x onerror=alert(1)>'


def test_every_user_string_is_escaped(tmp_path):
    env_file = tmp_path / "room.json"
    env_file.write_text(json.dumps({"name": HOSTILE, "outer": [[0, 0], [4, 0], [4, 3], [0, 3]]}))
    answer = tmp_path / 'plan"><img src=x onerror=alert(2)>.json'
    assert run("plan", env_file, "--from", "e0", "--to", "e2", "-o", answer, "--certificate", tmp_path / "c.json").exit_code == 0
    out = tmp_path / "r.html"
    result = run("report", env_file, "--plan", answer, "--certificate", tmp_path / "c.json", "-o", out)
    assert result.exit_code == 0, result.stderr
    text = out.read_text(encoding="utf-8")
    page = parse(text)
    assert [t for t, _ in page.elements].count("script") == 1 and "img" not in [t for t, _ in page.elements]
    assert "<script>alert" not in text and "<img" not in text
    assert "&lt;script&gt;alert(&quot;x&quot;)&lt;/script&gt;" in text  # shown, as text
    assert not any(k.startswith("on") for _, a in page.elements for k in a)  # no event-handler attribute at all
    svgs(text)


def test_a_hostile_string_in_the_answer_is_escaped_too():
    env = Environment.from_coords([[0, 0], [4, 0], [4, 3], [0, 3]], name="box")
    data = {"status": "infeasible", "objective": "fewest", "stages": [], "reason": HOSTILE, "start": "e0", "goal": "e2",
            "optimality": {"method": "search-exhausted", "proved": True, "bound": None, "scope": HOSTILE}}
    text = html_report(AnswerFile(HOSTILE, "plan", data), env, env_label=HOSTILE).html
    assert "<script>alert" not in text and "<img" not in text
    parse(text)


# ---------------------------------------------------------------------- bad input: exit 2, one line, nothing written
def _bad(args, fragment, tmp_path):
    out = Path(args[args.index("-o") + 1])
    result = run(*args)
    assert result.exit_code == 2, (result.exit_code, result.stderr)
    assert result.stdout == ""
    lines = result.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and fragment in lines[0], result.stderr
    assert not out.exists()
    return lines[0]


def test_plan_for_another_environment_is_bad_input(answers, tmp_path):
    out = tmp_path / "r.html"
    _bad(["report", "square", "--plan", answers / "plan.json", "-o", out], "the answer was made in another environment", tmp_path)


def test_a_file_that_is_no_answer_is_bad_input(answers, tmp_path, models_dir):
    out = tmp_path / "r.html"
    _bad(["report", "two_rooms", "--plan", answers / "cert.json", "-o", out], "is a certificate, not an answer", tmp_path)
    _bad(["report", "two_rooms", "--plan", models_dir / "two_rooms.json", "-o", out], "is no answer solverplan writes", tmp_path)
    broken = tmp_path / "broken.json"
    broken.write_text('{"status": "found", ')
    _bad(["report", "two_rooms", "--plan", broken, "-o", out], "not valid JSON", tmp_path)
    _bad(["report", "two_rooms", "--patrol", answers / "plan.json", "-o", out], "give it with --plan", tmp_path)
    _bad(["report", "two_rooms", "--plan", tmp_path / "missing.json", "-o", out], "no such file", tmp_path)


def test_mismatched_certificate_is_bad_input(answers, tmp_path):
    out = tmp_path / "r.html"
    plan = answers / "plan.json"
    _bad(["report", "two_rooms", "--plan", plan, "--certificate", answers / "patrol_cert.json", "-o", out],
         "the certificate is about another environment", tmp_path)
    _bad(["report", "square", "--patrol", answers / "patrol.json", "--certificate", answers / "funnel_cert.json", "-o", out],
         "a funnel certificate does not certify a patrol", tmp_path)
    other = tmp_path / "other.json"  # another query in the same environment
    assert run("plan", "two_rooms", "--from", "e0:0.3:0.7", "--to", "e4:0.5:1", "-o", tmp_path / "p2.json",
               "--certificate", other).exit_code == 0
    _bad(["report", "two_rooms", "--plan", plan, "--certificate", other, "-o", out], "it certifies another answer", tmp_path)
    cert = json.loads((answers / "cert.json").read_text())
    cert["start"] = [{"edge": 0, "t0": "0.25", "t1": "0.8"}]  # the same plan, claimed for a smaller start set
    moved = tmp_path / "moved.json"
    moved.write_text(json.dumps(cert))
    _bad(["report", "two_rooms", "--plan", plan, "--certificate", moved, "-o", out], "it certifies another query", tmp_path)
    _bad(["report", "square", "--cycle", answers / "cycle.json", "--certificate", answers / "patrol_cert.json", "-o", out],
         "has no certificate", tmp_path)


def test_usage_mistakes_are_bad_input(answers, tmp_path):
    out = tmp_path / "r.html"
    _bad(["report", "two_rooms", "-o", out], "is an environment, not an answer", tmp_path)
    _bad(["report", "two_rooms", "--plan", answers / "plan.json", "--cycle", answers / "cycle.json", "-o", out],
         "give one answer", tmp_path)
    _bad(["report", "two_rooms", "--plan", answers / "plan.json", "-o", tmp_path / "r.png"], "a report is an .html file",
         tmp_path)
    _bad(["report", "two_rooms", "--study", answers / "study.json", "-o", out], "give no ENV with --study", tmp_path)
    _bad(["report", "--plan", answers / "plan.json", "--env", "two_rooms", "-o", out], "drop --env", tmp_path)


def test_the_environment_is_found_by_the_answers_name_or_its_certificate(answers, tmp_path):
    """``report ANSWER.json``: a shipped model named by the answer (same SHA-256), else the certificate's rings."""
    out = tmp_path / "r.html"
    assert run("report", answers / "plan.json", "-o", out).exit_code == 0 and out.exists()
    renamed = json.loads((answers / "plan.json").read_text())
    renamed["environment"]["name"] = "not a model"
    (tmp_path / "p.json").write_text(json.dumps(renamed))
    _bad(["report", tmp_path / "p.json", "-o", tmp_path / "q.html"], "give it (--env ENV)", tmp_path)
    result = run("report", tmp_path / "p.json", "--certificate", answers / "cert.json", "-o", out)
    assert result.exit_code == 0 and json.loads(result.stdout)["certificate"]["valid"] is True


def test_segment_ids_beyond_the_partition_are_bad_input(tmp_path):
    env = Environment.from_coords([[0, 0], [4, 0], [4, 3], [0, 3]], name="box")
    data = {"status": "found", "objective": "fewest", "stages": [{"from_segments": [0], "to_segments": [9],
                                                                  "interval": [0.5, 1.0]}]}
    with pytest.raises(InputError, match=r"names segment 9, but the partition of 'box' has segments 0\.\.3"):
        html_report(AnswerFile("p.json", "plan", data), env)
    patrol = {"status": "found", "visit": ["e0"], "cycle": [], "fixed_point": [{"edge": 7, "t": 0.5, "point": [1, 0]}]}
    with pytest.raises(InputError, match=r"fixed_point\[0\] names edge 7, but 'box' has edges 0\.\.3"):
        html_report(AnswerFile("p.json", "patrol", patrol), env)


def test_answer_kinds_are_told_apart(answers):
    for kind in ANSWER_COMMANDS:
        assert detect_answer_kind(json.loads((answers / f"{kind}.json").read_text())) == kind
    assert detect_answer_kind(json.loads((answers / "cert.json").read_text())) is None
    with pytest.raises(MalformedFile, match="is a localisation strategy .* not what --plan takes: give it with --funnel"):
        load_answer(answers / "localize.json", option="plan")


def test_report_text_format(answers, tmp_path):
    result = run(*report_args("plan", answers, tmp_path / "r.html"), "--format", "text")
    assert result.exit_code == 0
    assert result.stdout.startswith(f"wrote {tmp_path / 'r.html'} (") and "certificate VALID (checked exactly)" in result.stdout
    assert ENVIRONMENTS["plan"] in result.stdout and CERTIFICATES["plan"]
