"""The gravitational acceleration that every controller, estimator and metric models.

One constant for the whole project: `robots.scene.Scene.gravity` defaults to it, and the
runner ends an episode whose scene has another gravity as a set-up error
(`check_modelled_gravity`), since the controllers' models (the LIPM's omega = sqrt(g / h), the
weight m g, the IMU's gravity-free acceleration) would not be the simulated world's.
"""

from __future__ import annotations

GRAVITY = 9.81
"""[m/s^2] along the world's -z."""


def check_modelled_gravity(gravity: float) -> None:
    """Raise ValueError unless `gravity` [m/s^2] (a scene's) is the modelled `GRAVITY`."""
    if gravity != GRAVITY:
        raise ValueError(
            f"the scene's gravity is {gravity:g} m/s^2, the controllers model {GRAVITY:g} "
            "(centroidal.gravity.GRAVITY)"
        )
