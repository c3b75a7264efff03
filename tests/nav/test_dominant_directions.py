"""footnav.nav.dominant_directions on hand-placed footprints: the refusal's reasons alone, the gate
on both sides of a grid direction, and a stretch of exactly ``min_stretch_strides``.

Footprints are placed stride by stride (1 m, at the headings given); a stride is straight when
its heading is within 20 deg of both neighbours', so the first and last stride of each run of
equal headings are not. Expected outcomes from the module's rules, worked out in the comments.
"""

from __future__ import annotations

import numpy as np

from footnav.core.types import FootTrajectory
from footnav.nav.dominant_directions import dominant_direction_correction


def _walk(headings_deg, lengths=None):
    lengths = np.ones(len(headings_deg)) if lengths is None else np.asarray(lengths, float)
    h = np.radians(headings_deg)
    fp = np.vstack([[0.0, 0.0], np.cumsum(np.column_stack([np.cos(h), np.sin(h)]) * lengths[:, None], axis=0)])
    pos = np.repeat(np.column_stack([fp, np.zeros(len(fp))]), 3, axis=0)  # 3 stance samples per footprint
    n = len(pos)
    steps = np.column_stack([np.arange(0, n, 3), np.arange(3, n + 1, 3)])
    return FootTrajectory(
        t=np.arange(n) * 0.1,
        position=pos,
        velocity=np.zeros((n, 3)),
        quaternion=np.tile([1.0, 0, 0, 0], (n, 1)),
        position_std=np.zeros((n, 3)),
        steps=steps,
    )


def test_too_few_straight_strides_alone_is_no_dominant_direction():
    # mutant: dd-refusal-and. All along x (strength 1), but only two strides longer than 0.4 m
    found = dominant_direction_correction(_walk([0.0] * 6, [0.2, 0.2, 1.2, 1.2, 0.2, 0.2]))
    assert not found.applied and found.reason.startswith("no dominant direction")
    assert found.strength > 0.99


def test_a_stretch_of_exactly_the_minimum_counts():
    # mutant: dd-stretch-length. Runs of 4 strides at 0 and 90 deg: 3 straight strides each (the
    # strides at the turn are not straight)
    found = dominant_direction_correction(_walk([0.0] * 4 + [90.0] * 4))
    assert found.applied and len(found.stretches) == 2
    assert [(s["first_stride"], s["last_stride"]) for s in found.stretches] == [(0, 2), (5, 7)]


def test_the_gate_holds_on_both_sides_of_a_grid_direction():
    # mutant: dd-gate-one-sided. Runs of 6 at 0, 90 and -30 deg: 5, 4 and 5 straight strides (the
    # walk's first and last strides have no turn on their outer side). The resultant of 4 x heading
    # is 9 + 5 exp(-120i deg) = 6.5 - 4.33i: the grid is at -33.7/4 = -8.4 deg, and the -30 deg
    # strides are 21.6 deg below it, outside the 15 deg gate: two stretches, not three. Mirrored
    # (+30 deg), the same holds above the grid.
    expected = np.degrees(np.angle(9.0 + 5.0 * np.exp(1j * np.radians(120.0)))) / 4.0  # +8.4 deg, for +30
    for sign in (-1.0, 1.0):
        found = dominant_direction_correction(_walk([0.0] * 6 + [90.0] * 6 + [sign * 30.0] * 6))
        assert abs(np.degrees(found.grid_rad) - sign * expected) < 1e-9
        assert found.applied and len(found.stretches) == 2, (sign, found.stretches)
