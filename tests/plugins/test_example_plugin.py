"""The shipped example plugin, installed for real (pip, no index) and found through its entry point."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "footnav-plugin-example"


def _run(cmd, **kw):
    proc = subprocess.run(cmd, capture_output=True, text=True, **kw)
    assert proc.returncode == 0, f"{' '.join(map(str, cmd))} failed:\n{proc.stdout}\n{proc.stderr}"
    return proc.stdout


@pytest.mark.slow
def test_example_plugin_installs_lists_and_runs(tmp_path):
    site = tmp_path / "site"
    # install the example alone into its own folder; footnav and its dependencies are the ones
    # of this environment, so no package index is needed
    _run(
        [
            sys.executable,
            "-m",
            "pip",
            "install",
            "--quiet",
            "--no-deps",
            "--no-build-isolation",
            "--no-index",
            "--target",
            str(site),
            str(EXAMPLE),
        ]
    )
    env = {k: v for k, v in os.environ.items() if k != "FOOTNAV_DISABLE_PLUGIN_AUTOLOAD"}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(site), env.get("PYTHONPATH")]))

    listing = _run([sys.executable, "-m", "footnav.cli", "plugins"], env=env)
    line = next(l for l in listing.splitlines() if "example-gyro" in l)
    assert line.split()[:3] == ["detector", "example-gyro", "footnav-plugin-example"]
    assert "Stance wherever the angular-rate norm is below a threshold" in line  # its docstring summary
    params = _run([sys.executable, "-m", "footnav.cli", "plugins", "example-gyro"], env=env)
    row = next(l for l in params.splitlines() if l.startswith("threshold_radps"))
    assert row.split()[:3] == ["threshold_radps", "0.6", "rad/s"]

    code = (
        "import footnav;"
        "p = footnav.make_pipeline(detector='example-gyro', detector_params={'threshold_radps': 0.5});"
        "rec = footnav.simulate('straight', distance_m=10.0);"
        "r = p.run(rec.left, rec.right);"
        "print(type(p.detector).__module__, r.stance_left.n_stances)"
    )
    out = _run([sys.executable, "-c", code], env=env).split()
    assert out[0] == "footnav_plugin_example" and int(out[1]) >= 5


def test_example_plugin_passes_the_detector_contract():
    sys.path.insert(0, str(EXAMPLE))
    try:
        from footnav_plugin_example import GyroNormDetector
    finally:
        sys.path.remove(str(EXAMPLE))
    from footnav.testing import DetectorContract

    class Contract(DetectorContract):
        component = GyroNormDetector

    # run the contract's checks directly: the class is defined inside this test
    c = Contract()
    for name in dir(c):
        if name.startswith("test_"):
            getattr(c, name)()
