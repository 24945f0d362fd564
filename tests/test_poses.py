"""Many poses at once (:func:`game.poses.poses`) equal :func:`core.transform.pose`'s, bit for bit."""

import numpy as np

from across_dimensions.core.transform import PLANES, pose
from across_dimensions.game.poses import poses


def test_poses_in_one_pass_are_each_pose_to_the_bit():
    rng = np.random.default_rng(11)
    n = 60
    positions = rng.normal(size=(n, 4)) * 5.0
    scales = rng.uniform(0.2, 3.0, size=(n, 4))
    angles = rng.uniform(-7.0, 7.0, size=(n, 6))
    angles[::3, 1] = 0.0  # some rows leave a plane out, others turn in it
    angles[:, 4] = 0.0  # no row turns in this plane
    angles[5, :4] = 0.0  # this one turns in one plane only, the one every row turns in
    out = poses(positions, angles, scales)
    for i in range(n):
        one = pose(positions[i], dict(zip(PLANES, angles[i])), scales[i])
        assert one.tobytes() == out[i].tobytes(), i
