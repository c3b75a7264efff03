"""report.html (issue 39): the page parses, holds every figure and table for one and two feet,
with and without truth, shows the warnings, names no place on the machine, stays small for an
hour of two feet; run, follow and evaluate write it into their result folders."""

from __future__ import annotations

import dataclasses
import html.parser
import os
import warnings
from pathlib import Path

import numpy as np
import pytest

from footnav.cli import main
from footnav.core.types import FootTrajectory, StanceResult
from footnav.core.types import Path as NavPath
from footnav.data.simulate import simulate
from footnav.pipeline.factory import make_pipeline
from footnav.report import REPORT_NAME, result_html, write_html
from footnav.report import figures as report_figures
from footnav.report.evaluation import best_of_row
from footnav.report.page import scrub

SECTIONS = {"plan", "height", "stances", "strides", "checks", "provenance"}


class _Page(html.parser.HTMLParser):
    """What a page holds: section ids, the figures (svg), the tables, the text, and whether
    anything refers outside the file."""

    def __init__(self, text: str) -> None:
        super().__init__()
        self.ids: set[str] = set()
        self.svgs = self.tables = 0
        self.external: list[str] = []
        self.words: list[str] = []
        self.open: list[str] = []
        self.feed(text)
        self.close()
        self.text = " ".join(self.words)

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "section":
            self.ids.add(a.get("id"))
        self.svgs += tag == "svg"
        self.tables += tag == "table"
        if tag in ("script", "link", "img", "iframe") or (a.get("src") or "").startswith("http"):
            self.external.append(tag)
        href = a.get("href") or ""
        if href and not href.startswith("#"):
            self.external.append(href)

    def handle_data(self, data):
        if self.lasttag not in ("style", "script"):
            self.words.append(data)


@pytest.fixture(scope="module")
def walk():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rec = simulate("straight", seed=3, distance_m=15)
        two = make_pipeline().run(rec.left, rec.right)
        one = make_pipeline().run(rec.left)
    return rec, two, one


def _with_input(result, folder: Path, warning: str | None = None):
    """``result`` as if read from files in ``folder`` (absolute paths in its meta), with a warning
    naming one of them."""
    meta = dict(result.meta)
    inputs = {}
    for foot in ("left", "right") if result.right is not None else ("left",):
        src = folder / f"{foot}.csv"
        src.write_text(f"t,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z\n0,0,0,9.81,0,0,0 # {foot}\n")
        inputs[foot] = {"source": str(src), "format": "footnav_csv"}
    meta["input"] = inputs
    if warning:
        meta["warnings"] = [warning.format(src=inputs["left"]["source"])]
    return dataclasses.replace(result, meta=meta)


@pytest.mark.parametrize("feet", [1, 2])
@pytest.mark.parametrize("with_truth", [False, True])
def test_the_page_holds_every_figure_and_table(walk, tmp_path, feet, with_truth):
    pytest.importorskip("matplotlib")
    rec, two, one = walk
    result = _with_input(
        two if feet == 2 else one, tmp_path, warning="{src}: 3 accelerometer samples at full scale; try --acc-unit g"
    )
    page = _Page(
        result_html(result, recording=rec if with_truth else None, pipeline_toml="[detector]\nname = 'adaptive'\n")
    )
    assert page.ids == SECTIONS
    assert page.svgs == 3  # plan, height, stances
    assert page.tables == 3  # strides summary and table, inputs; the run's checks are sentences
    assert page.external == []
    assert "steady" in page.text and "SHA-256" in page.text and "left.csv" in page.text
    assert ("right" in page.text.split("Strides", 1)[1]) == (feet == 2)
    assert ("truth" in page.text) == with_truth
    assert "3 accelerometer samples at full scale" in page.text
    assert "stances" in page.text and "gait cycles" in page.text  # the stance self-check in words


def test_the_page_names_no_place_on_the_machine(walk, tmp_path):
    rec, two, _ = walk
    result = _with_input(two, tmp_path, warning="{src}: odd rate; see " + str(tmp_path / "other" / "notes.txt"))
    text = result_html(result, recording=rec)
    for place in (str(tmp_path), os.path.expanduser("~"), os.getcwd()):
        assert place not in text
    assert "left.csv: odd rate; see notes.txt" in text


def test_without_matplotlib_the_page_has_its_tables_and_says_how_to_get_figures(walk, monkeypatch):
    _, two, _ = walk
    monkeypatch.setattr(report_figures, "available", lambda: False)
    page = _Page(result_html(two))
    assert page.svgs == 0 and page.ids == SECTIONS and page.tables >= 2
    assert "pip install 'footnav[plot]'" in page.text


def _tiled(result, copies: int):
    """``result`` repeated ``copies`` times end to end: a long walk without computing one."""

    def foot(traj):
        n, span = len(traj.t), traj.t[-1] - traj.t[0] + (traj.t[1] - traj.t[0])
        shift = np.repeat(np.arange(copies), n)
        step = traj.position[-1] - traj.position[0]
        return FootTrajectory(
            t=np.tile(traj.t, copies) + shift * span,
            position=np.tile(traj.position, (copies, 1)) + shift[:, None] * step,
            velocity=np.tile(traj.velocity, (copies, 1)),
            quaternion=np.tile(traj.quaternion, (copies, 1)),
            position_std=np.tile(traj.position_std, (copies, 1)),
            steps=np.concatenate([traj.steps + k * n for k in range(copies)]),
            meta=traj.meta,
        )

    left, right = foot(result.left), foot(result.right)
    path = NavPath(t=left.t, position=0.5 * (left.position + right.position))
    stance = [StanceResult(mask=np.tile(s.mask, copies)) for s in (result.stance_left, result.stance_right)]
    return dataclasses.replace(result, left=left, right=right, path=path, stance_left=stance[0], stance_right=stance[1])


def test_an_hour_of_two_feet_is_a_page_under_2_mb(walk, tmp_path):
    pytest.importorskip("matplotlib")
    _, two, _ = walk
    copies = int(np.ceil(3600 / (two.left.t[-1] - two.left.t[0])))
    long = _tiled(two, copies)
    assert long.left.t[-1] - long.left.t[0] > 3600
    path = write_html(long, tmp_path / REPORT_NAME)
    size = path.stat().st_size
    assert size < 2_000_000, size
    page = _Page(path.read_text(encoding="utf-8"))
    assert page.svgs == 3 and "strides.csv holds them all" in page.text


def test_scrub_and_best_of_row():
    assert scrub("/home/someone/walks/left.csv: clipping", ["/home/someone/walks/left.csv"]) == "left.csv: clipping"
    assert scrub("see /var/tmp/x/y.txt and 9.81 m/s^2") == "see y.txt and 9.81 m/s^2"
    assert best_of_row("ate_2d", [0.5, 0.2, float("nan")]) == {1}
    assert best_of_row("loop_closure_dz", [-0.1, 0.3]) == {0}  # the smallest in size
    assert best_of_row("stance_f1", [0.8, 0.9]) == {1}
    assert best_of_row("ate_2d", [0.2, 0.2001, 0.3]) == {0, 1}  # a tie as shown: both
    assert best_of_row("ate_2d", [0.2, 0.2]) == set()  # all tie: none better
    assert best_of_row("path_length", [10.0, 12.0]) == set()
    assert best_of_row("ate_2d", [0.5]) == set()


def test_decimation_keeps_the_last_sample_and_the_bound():
    idx = report_figures.decimate(100_001, 2500)
    assert len(idx) <= 2500 and idx[0] == 0 and idx[-1] == 100_000
    assert list(report_figures.decimate(10, 2500)) == list(range(10))


# --- the commands -------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def sim_folder(tmp_path_factory):
    out = tmp_path_factory.mktemp("report_cli") / "walk"
    assert main(["simulate", "straight", "--set", "distance_m=12", "--seed", "2", "--out", str(out)]) == 0
    return out


def test_run_follow_and_evaluate_write_report_html(sim_folder, tmp_path, capsys, monkeypatch):
    """follow with --view, headless: the view draws off-screen in its own process, says so, and
    the report at the end is what to open."""
    pytest.importorskip("matplotlib")
    for name in ("DISPLAY", "WAYLAND_DISPLAY"):
        monkeypatch.delenv(name, raising=False)
    left, right = str(sim_folder / "left.csv"), str(sim_folder / "right.csv")
    assert main(["run", "--left", left, "--right", right, "--out", str(tmp_path / "run")]) == 0
    assert (
        main(
            [
                "follow",
                "--left",
                left,
                "--right",
                right,
                "--idle-s",
                "0.2",
                "--poll-s",
                "0.01",
                "--view",
                "--out",
                str(tmp_path / "follow"),
            ]
        )
        == 0
    )
    assert "no display: --view draws off-screen" in capsys.readouterr().err
    assert main(["evaluate", str(sim_folder), "--out", str(tmp_path / "eval")]) == 0
    capsys.readouterr()
    for name in ("run", "follow"):
        page = _Page((tmp_path / name / REPORT_NAME).read_text(encoding="utf-8"))
        assert page.ids == SECTIONS and page.svgs == 3, name
        assert str(tmp_path) not in page.text and "left.csv" in page.text
        marker = (tmp_path / name / ".footnav-result").read_text()
        assert REPORT_NAME in marker  # footnav's, as every file it wrote: replaced only with the rest
    follow = _Page((tmp_path / "follow" / REPORT_NAME).read_text(encoding="utf-8")).text
    assert "complete (idle: no new row" in follow and "from the estimated orientation" in follow
    text = (tmp_path / "eval" / REPORT_NAME).read_text(encoding="utf-8")
    page = _Page(text)
    assert page.svgs == 1 and page.tables >= 1 and "ate_2d" in page.text and 'class="t best"' not in text
    assert "provenance" in page.ids and str(tmp_path) not in text


def test_the_live_view_takes_steps_and_ends_with_the_stream():
    pytest.importorskip("matplotlib")
    from types import SimpleNamespace

    from footnav.report.live import LiveView

    view = LiveView("test", every_s=0.05, window=False)
    assert view.wait_ready(120.0)  # a guard, as close() below
    steps = [
        SimpleNamespace(t=0.5 * i, foot=("left", "right")[i % 2], position=(0.4 * i, 0.1 * (i % 2), 0.0))
        for i in range(20)
    ]
    view.add(steps[:10])
    view.flush(force=True)
    view.add(steps[10:])
    view.close(wait_s=120)  # a guard against a hang: a loaded machine draws slower than the default 3 s
    assert view.sent == 20 and not view._process.is_alive() and view._process.exitcode == 0


def test_a_stream_with_nothing_final_writes_a_report_saying_so(tmp_path):
    import subprocess
    import sys

    out = tmp_path / "nothing"
    proc = subprocess.run(
        [sys.executable, "-m", "footnav.cli", "follow", "--left", "-", "--out", str(out)],
        check=False,
        stdin=subprocess.DEVNULL,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 2  # no sample: an error, with the folder written
    page = _Page((out / REPORT_NAME).read_text(encoding="utf-8"))
    assert page.ids == {"checks", "provenance"} and "before any step was final" in page.text
    assert str(tmp_path) not in page.text
