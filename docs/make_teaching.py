"""Regenerate docs/teaching-detectors.md and its figures: every stance detector compared on a
simulated walk, the gaitmap example (mocap-derived events), a running trial (pyshoe VICON), a fast
hallway walk (gait-driven set, footprints) and an IPOL walk with a U-turn (hand-checked steps).

Run:  python docs/make_teaching.py [--data-dir ../shared/data]
"""

from __future__ import annotations

import argparse
import warnings
from pathlib import Path

import footnav
from footnav.analysis.comparison import compare_detectors
from footnav.data.datasets import load_dataset

HERE = Path(__file__).parent

INTRO = """# Teaching: comparing gait segmentation methods

A foot-mounted IMU navigates only as well as it knows when the foot stands still. This page puts
footnav's stance detectors side by side, the way a class would: the same recording, each
detector's stance phases stacked under the angular-rate signal, and a table of what each got
right. Everything here is produced by `python docs/make_teaching.py`; run the same comparison
yourself with

```
footnav compare-detectors --simulate straight --plot detectors-sim.png --seconds 0 10
footnav compare-detectors --dataset gaitmap --plot detectors-gaitmap.png --seconds 5 15
footnav compare-detectors --dataset ipol_4-4 --plot detectors-ipol.png --seconds 10 16
```

or in Python:

```python
import footnav
cmp = footnav.compare_detectors(footnav.simulate("straight", distance_m=30))
print(cmp.to_text())
cmp.plot("detectors.png", seconds=(0, 10))
```

What the rows mean: `cycles_without_stance` and `stances_over_swing` need no reference: the
strides are the swing peaks of the angular rate, and a stride with no stance in it, or a stance
holding a swing, is a detector's mistake (the check every pipeline run makes);
`steps_found / missed / false` match each detected stance phase one to one with a reference
stance (seed 003 Table 1); `f1` is the per-sample F1 of the stance mask against
the simulator's exact zero-velocity truth; `*_error` rows are mean absolute timing errors of gait
events in ms; `runtime` includes numba compilation the first time a detector runs in a process.
"""


#: Beyond ordinary walking: (dataset, title, figure window in s, what to look at).
GAITS = [
    (
        "pyshoe_2017-11-27-11-13-41",
        "Running (pyshoe VICON trial 2017-11-27-11-13-41, 200 Hz, one foot)",
        (2.0, 8.0),
        "A running foot never stops turning: at its stillest it still turns at 0.3-1 rad/s, above "
        "every walking bound. `threshold` and `glrt` find 3 stances in 19 strides and the trajectory "
        "drifts by metres; `cycles_without_stance` (no reference needed: the swing peaks of the angular "
        "rate mark the strides) says so for every detector. `adaptive` sets its bound per gait cycle. "
        "The reference here is the dataset's proxy label (a motion-capture speed threshold, not hand "
        "labels): it splits many stances in two, so `steps_reference` is larger than the strides.",
    ),
    (
        "gaitdriven_35",
        "Fast hallway walking (gait-driven set, trial 35, 200 Hz, one foot)",
        (4.0, 10.0),
        "Reference: every footprint, the sample where the foot is on the ground at the end of each "
        "stride, marked on a floor-tile grid; a footprint is found when it lies inside a detected "
        "stance. At this pace the walking bound misses most stances.",
    ),
    (
        "ipol_4-4",
        "Fast walking with a U-turn (IPOL subject 4, trial 4, both feet, 100 Hz)",
        (10.0, 16.0),
        "Reference: hand-checked swings (toe off to heel strike); stance is the gap between two swings "
        "of a foot, compared only inside the trial's boundaries. Subject 4 walks fast, and the U-turn "
        "has small shuffling steps and pivots on the spot: a pivot turns as fast as a swing but the "
        "foot stays down.",
    ),
]


def section(title: str, cmp, figure: str, note: str) -> str:
    return f"""
## {title}

{note}

![{title}](figures/{figure})

```
{cmp.to_text()}
```
"""


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--data-dir")
    args = ap.parse_args()
    parts = [INTRO]
    sim = footnav.simulate("straight", seed=0, rate_hz=100.0, distance_m=30.0)
    cmp = compare_detectors(sim)
    cmp.plot(HERE / "figures" / "detectors-sim.png", seconds=(0.0, 10.0))
    parts.append(
        section(
            "A simulated walk (30 m, 100 Hz)",
            cmp,
            "detectors-sim.png",
            "The simulator knows exactly when each foot is still, so every detector can be scored per sample.",
        )
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # clipping is recorded in meta
        rec = load_dataset("gaitmap", args.data_dir)
        cmp = compare_detectors(rec)
    cmp.plot(HERE / "figures" / "detectors-gaitmap.png", seconds=(5.0, 15.0))
    parts.append(
        section(
            "The gaitmap example (both feet, 204.8 Hz, 2 x 20 m)",
            cmp,
            "detectors-gaitmap.png",
            "Reference: the 28 + 29 strides of the motion-capture event file; a stride is found when its "
            "minimum-velocity (mid-stance) sample lies inside a detected stance. Detectors that report heel "
            "strike or toe off are timed against the mocap initial and terminal contacts; threshold and GLRT "
            "report only the start and end of stance, which the mocap file does not give. The one extra "
            "left-foot stance both find (near sample 3620) is the turn at the end of the first 20 m: the "
            "stride file labels the turn as one stride from mid-stance 3359 to 3826, but the mocap heel "
            "speed in the detected stance is 0.014 m/s (median), the same as in a normal stance: the foot "
            "really stood still there. Use this as a discussion point: a reference is a method too.",
        )
    )
    for name, title, seconds, note in GAITS:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # refits and data oddities are recorded in meta
            cmp = compare_detectors(load_dataset(name, args.data_dir))
        figure = f"detectors-{name.split('_')[0]}.png"
        cmp.plot(HERE / "figures" / figure, seconds=seconds)
        parts.append(section(title, cmp, figure, note))
    (HERE / "teaching-detectors.md").write_text("".join(parts), encoding="utf-8")
    print("wrote", HERE / "teaching-detectors.md")


if __name__ == "__main__":
    main()
