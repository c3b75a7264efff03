import pytest

from footnav import DataNotFoundError
from footnav.cli import main
from footnav.core.errors import UnknownDatasetError
from footnav.data.datasets import data_dir, dataset_names, load_dataset


def test_missing_data_folder_says_where_it_looked(tmp_path):
    with pytest.raises(DataNotFoundError, match="FOOTNAV_DATA"):
        data_dir(tmp_path / "nowhere")


def test_unknown_dataset_lists_names(shared_data):
    with pytest.raises(UnknownDatasetError, match="azure_fgo"):
        load_dataset("azure", shared_data)


@pytest.mark.filterwarnings("ignore::footnav.DataQualityWarning")
def test_every_dataset_loads_with_its_name(shared_data):
    names = dataset_names(shared_data)
    assert {"azure_fgo", "gaitmap", "xio_short", "xio_long", "openshoe"} <= set(names)
    assert sum(n.startswith("pyshoe_") for n in names) == 14
    assert dataset_names(str(shared_data)) == names  # the folder as a str (was a TypeError)
    rec = load_dataset("xio_short", shared_data)
    assert rec.name == "xio_short" and rec.truth_left.closed_loop


@pytest.mark.filterwarnings("ignore::footnav.DataQualityWarning")
def test_cli_evaluate_prints_one_table(shared_data, tmp_path, capsys):
    csv = tmp_path / "r.csv"
    code = main(
        [
            "evaluate",
            "--dataset",
            "azure_fgo",
            "--dataset",
            "xio_short",
            "--data-dir",
            str(shared_data),
            "--csv",
            str(csv),
        ]
    )
    assert code == 0
    out = capsys.readouterr().out
    rows = [l.split() for l in out.splitlines()]
    assert ["azure_fgo", "ate_2d", "left", "m"] == rows[
        2 + [r[:3] for r in rows[2:]].index(["azure_fgo", "ate_2d", "left"])
    ][:4]
    assert any(r[:2] == ["xio_short", "loop_closure_2d"] for r in rows)
    assert csv.read_text().startswith("recording,pipeline,foot,name,value,unit")


def test_cli_evaluate_without_data_exits_2_unless_the_recording_is_bundled(tmp_path, capsys):
    assert main(["evaluate", "--dataset", "xio_short", "--data-dir", str(tmp_path / "none")]) == 2
    assert "not found" in capsys.readouterr().err


@pytest.mark.filterwarnings("ignore::footnav.DataQualityWarning")
def test_ipol_and_gaitdriven_trials_are_listed_and_load(shared_data):
    names = dataset_names(shared_data)
    ipol = [n for n in names if n.startswith("ipol_")]
    assert len(ipol) == 46 and ipol[0] == "ipol_1-1" and "ipol_8-6" in ipol
    gd = [n for n in names if n.startswith("gaitdriven_")]
    assert gd == [f"gaitdriven_{nn}" for nn in (31, 33, 35, 37, 39, 41, 43, 45)]
    rec = load_dataset("ipol_1-1", shared_data)
    assert rec.name == "ipol_1-1" and rec.n_feet == 2 and rec.truth_right.meta["uturn_boundaries"] is not None
    rec = load_dataset("gaitdriven_35", shared_data)
    assert rec.name == "gaitdriven_35" and rec.truth_left.frame == "footprints"
    with pytest.raises(UnknownDatasetError):
        load_dataset("ipol_99-1", shared_data)
