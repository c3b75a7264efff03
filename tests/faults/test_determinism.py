"""Same input and seed, bit-identical output: every registered component, in two processes."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

SCRIPT = r"""
import hashlib, json, warnings
import numpy as np
import footnav

warnings.simplefilter("ignore")
rec = footnav.simulate("rectangle", seed=7, width_m=12.0, height_m=6.0)
comps = footnav.list_components()
out = {}

def digest(*arrays):
    h = hashlib.sha256()
    for a in arrays:
        h.update(np.ascontiguousarray(a).tobytes())
    return h.hexdigest()

for name in comps["detector"]:
    det = footnav.make_detector(name)
    left, right = det.detect_pair(rec.left, rec.right)
    out["detector:" + name] = digest(left.mask, right.mask, *(np.asarray(v) for v in left.events.values()))
for name in comps["estimator"]:
    for params in ({}, {"bias_states": True, "zaru_std_radps": 0.005, "smoother": "step"}):
        traj = (
            footnav.make_estimator(name, **params).estimate(rec.left, footnav.StanceResult(rec.truth_left.stance))
            if not params or name == "ekf"
            else None
        )
        if traj is not None:
            out["estimator:" + name + json.dumps(params)] = digest(traj.position, traj.quaternion, traj.position_std)
for name in comps["fusion"]:
    res = footnav.make_pipeline("threshold", "ekf", name).run(rec)
    out["fusion:" + name] = digest(res.left.position, res.right.position, res.path.position)
print(json.dumps(out))
"""


def _hashes():
    env = {k: v for k, v in os.environ.items()}
    env["FOOTNAV_DISABLE_PLUGIN_AUTOLOAD"] = "1"
    proc = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True, env=env)
    assert proc.returncode == 0, proc.stderr[-2000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


@pytest.mark.slow
def test_every_component_is_bit_identical_across_two_processes():
    first, second = _hashes(), _hashes()
    assert first == second
    kinds = {k.split(":")[0] for k in first}
    assert kinds == {"detector", "estimator", "fusion"} and len(first) >= 10
