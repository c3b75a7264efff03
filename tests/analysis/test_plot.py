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


@pytest.mark.filterwarnings("ignore::footnav.DataQualityWarning")
def test_titles_name_the_input_file_legends_sit_below_and_no_truth_no_error_figure(tmp_path, monkeypatch):
    from dataclasses import replace

    from footnav.analysis import plot

    saved = {}
    monkeypatch.setattr(plot, "_save", lambda fig, path, dpi: saved.update(fig=fig))
    rec = footnav.simulate("straight", seed=1, distance_m=10.0)
    result = footnav.make_pipeline().run(rec.left, rec.right)
    sourced = replace(result, meta={**result.meta, "input": {"left": {"source": "/data/walk-07.csv"}, "right": None}})
    plot.plot_trajectories(sourced, None, tmp_path / "f.png")
    plan = saved["fig"].axes[0]
    assert plan.get_title().startswith("footnav walk-07.csv: ")
    unnamed = replace(result, meta={**result.meta, "input": {"left": {}, "right": None}})
    plot.plot_trajectories(unnamed, replace(rec, name=""), tmp_path / "f.png")
    assert saved["fig"].axes[0].get_title().startswith("footnav: ")  # no empty name
    for ax in saved["fig"].axes:  # each legend below its axes, outside the data
        legend_box = ax.get_legend().get_window_extent(saved["fig"].canvas.get_renderer())
        assert legend_box.y1 <= ax.get_window_extent().y0
    saved.clear()
    no_truth = replace(rec, truth_left=None, truth_right=None)
    assert not plot.has_path_truth(no_truth) and plot.has_path_truth(rec)
    assert plot.plot_position_errors(result, no_truth, tmp_path / "e.png") is None and not saved
