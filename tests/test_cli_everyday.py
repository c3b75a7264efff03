"""The CLI in the user's language: a plugins table that fits a terminal, one component's
parameters, --plot without matplotlib refused before any work; components work with
scikit-learn's clone."""

import sys

import numpy as np
import pytest

import footnav
from footnav.cli import PLUGINS_WIDTH, main


def test_plugins_fits_a_terminal_and_describes_every_component(capsys):
    assert main(["plugins"]) == 0
    out = capsys.readouterr().out
    assert max(len(line) for line in out.splitlines()) <= PLUGINS_WIDTH == 120
    for names in footnav.list_components().values():
        for name in names:
            assert f" {name} " in out
    assert "Closed-loop error-state ZUPT EKF" in out  # the docstring's summary, not the parameters
    assert "zupt_std_mps" not in out


def test_plugins_name_lists_its_parameters(capsys):
    assert main(["plugins", "ekf"]) == 0
    out = capsys.readouterr().out
    assert max(len(line) for line in out.splitlines()) <= PLUGINS_WIDTH
    for p in footnav.make_estimator("ekf").parameter_info():
        assert p.name in out
    assert main(["plugins", "ekff"]) == 2
    assert "no component named 'ekff'" in capsys.readouterr().err


def test_plot_without_matplotlib_is_an_error_before_any_work(tmp_path, monkeypatch, capsys):
    rec = footnav.simulate("straight", seed=0, distance_m=5.0)
    from footnav.data.io import write_footnav_csv

    csv = write_footnav_csv(rec.left, tmp_path / "l.csv")
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # import matplotlib now raises ImportError
    code = main(["run", "--left", str(csv), "--out", str(tmp_path / "o"), "--plot", str(tmp_path / "f.png")])
    assert code == 2
    assert "pip install 'footnav[plot]'" in capsys.readouterr().err
    assert not (tmp_path / "o").exists() and not (tmp_path / "f.png").exists()


@pytest.mark.parametrize("name", ["threshold", "ekf", "step-vector"])
def test_sklearn_clone_makes_an_equal_unfitted_component(name):
    from sklearn.base import clone

    kind = {"threshold": "detector", "ekf": "estimator", "step-vector": "fusion"}[name]
    comp = footnav.plugins.manager.get_registry().get(kind, name).cls()
    params = comp.get_params()
    key = next(iter(params))
    twin = clone(comp)
    assert type(twin) is type(comp) and twin is not comp
    assert twin.get_params(deep=False) == comp.get_params(deep=True) == params
    np.testing.assert_equal(repr(twin), repr(comp))
    assert key in twin.get_params()


def test_compiling_is_announced_and_timed(capsys):
    import numba

    from footnav.cli import _compile_notice

    notice = _compile_notice()
    with notice.listening():

        @numba.njit(cache=False)
        def twice(x):
            return 2 * x

        assert twice(21) == 42  # compiled here, on the first call
        assert twice(1) == 2  # already compiled: no second notice
    notice.report()
    err = capsys.readouterr().err
    assert err.count("compiling the numerical kernels") == 1
    assert "compiled in" in err and notice.seconds > 0


def test_nothing_is_said_when_nothing_compiles(capsys):
    from footnav.cli import _compile_notice

    notice = _compile_notice()
    with notice.listening():
        pass
    notice.report()
    assert capsys.readouterr().err == ""


def test_simulate_path_runs_from_the_command_line(tmp_path, capsys):
    out = tmp_path / "p"
    assert main(["simulate", "path", "--segments", "10:90,5:-90,3:0", "--set", "noise=false", "--out", str(out)]) == 0
    truth = np.loadtxt(out / "left_truth.csv", delimiter=",", comments="#", skiprows=1)
    rec = footnav.simulate("path", seed=0, segments=[(10, 90), (5, -90), (3, 0)], noise=False)
    # the same walk as the library's: same length, same end
    assert len(truth) == rec.truth_left.t.size
    assert main(["simulate", "path", "--out", str(tmp_path / "q")]) == 2
    assert "--segments" in capsys.readouterr().err
    assert main(["simulate", "straight", "--set", "distnce_m=3", "--out", str(tmp_path / "r")]) == 2
    assert "did you mean 'distance_m'" in capsys.readouterr().err
