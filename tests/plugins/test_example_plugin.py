"""The shipped example plugin, installed for real into a fresh virtual environment."""

import os
import subprocess
import sys
import venv
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "footnav-plugin-example"


@pytest.mark.slow
def test_example_plugin_installs_lists_and_runs(tmp_path):
    env_dir = tmp_path / "venv"
    # system site packages: footnav's own dependencies come from the test environment, so only
    # the example and footnav (from this tree, no index access) are installed
    venv.EnvBuilder(system_site_packages=True, with_pip=True).create(env_dir)
    py = env_dir / ("Scripts" if os.name == "nt" else "bin") / "python"
    env = {k: v for k, v in os.environ.items() if k != "FOOTNAV_DISABLE_PLUGIN_AUTOLOAD"}
    pip = [str(py), "-m", "pip", "install", "--quiet", "--no-deps", "--no-build-isolation", "--no-index"]
    subprocess.run(pip + [str(ROOT)], check=True, env=env, capture_output=True)
    subprocess.run(pip + [str(EXAMPLE)], check=True, env=env, capture_output=True)

    listing = subprocess.run(
        [str(py), "-m", "footnav.cli", "plugins"], check=True, env=env, capture_output=True, text=True
    ).stdout
    line = next(l for l in listing.splitlines() if "example-gyro" in l)
    assert line.split()[:3] == ["detector", "example-gyro", "footnav-plugin-example"]
    assert "threshold_radps=0.6 [rad/s]" in line

    code = (
        "import footnav, numpy as np;"
        "p = footnav.make_pipeline(detector='example-gyro', detector_params={'threshold_radps': 0.5});"
        "rec = footnav.simulate('straight', distance_m=10.0);"
        "r = p.run(rec.left, rec.right);"
        "print(type(p.detector).__module__, r.stance_left.n_stances)"
    )
    out = subprocess.run([str(py), "-c", code], check=True, env=env, capture_output=True, text=True).stdout.split()
    assert out[0] == "footnav_plugin_example" and int(out[1]) >= 5
