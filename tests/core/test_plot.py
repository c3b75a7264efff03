"""The --plot figure: the plan view and, beside it, each foot's height over time."""

import pytest

import footnav

pytest.importorskip("matplotlib")


@pytest.mark.filterwarnings("ignore::footnav.DataQualityWarning")
def test_the_figure_has_a_height_panel_with_the_truth_and_the_floors(tmp_path, monkeypatch):
    from footnav.analysis import plot

    saved = {}
    monkeypatch.setattr(plot, "_save", lambda fig, path, dpi: saved.update(fig=fig))
    segments = [(1.4, 0.0), ("stairs", 12, 0.17), (2.8, 180.0), ("stairs", 12, -0.17), (1.4, 0.0)]
    rec = footnav.simulate("path", seed=0, rate_hz=200.0, segments=segments)
    result = footnav.make_pipeline().run(rec.left, rec.right)
    plot.plot_trajectories(result, rec, tmp_path / "f.png")
    plan, height = saved["fig"].axes
    assert plan.get_xlabel() == "x (m)" and height.get_xlabel() == "time (s)"
    labels = [t.get_text() for t in height.get_legend().get_texts()]
    assert labels[0] == "left truth" and "floors up 1, down 1" in labels[1]
    # the estimate's line spans the storey: up about 2 m and back
    z = height.get_lines()[1].get_ydata()
    assert 1.9 < z.max() - z[0] < 2.3 and abs(z[-1] - z[0]) < 0.1
