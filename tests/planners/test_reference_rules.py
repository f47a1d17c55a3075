"""Murooka Sec. V-C's CoM reference rules on multi-contact phases (`planners.reference`)."""

import numpy as np
import pytest

from planners.reference import support_centre
from robots.scene import Contact, ContactPhase, Scenario, Scene

LEFT = Contact("left_foot", (0.0, 0.1, 0.15))
RIGHT = Contact("right_foot", (0.3, -0.1, 0.3))
HANDS = (
    Contact("left_hand", (0.4, 0.45, 1.0)),
    Contact("right_hand", (0.6, -0.45, 1.2)),
)


def test_a_phase_offset_moves_the_horizontal_reference_only():
    """Sec. V-C (B): "offset inward by 50 mm" in single support."""
    phases = (
        ContactPhase(0.0, 1.0, (LEFT, RIGHT, *HANDS)),
        ContactPhase(1.0, 2.0, (LEFT, *HANDS), (0.0, -0.05)),
    )
    scenario = Scenario("t", 2.0, Scene(), phases, ())
    centre, height = support_centre(scenario, 0.5)  # hands do not count with feet down
    np.testing.assert_allclose(centre, (0.15, 0.0), atol=1e-15)
    assert height == pytest.approx(0.225, abs=1e-15)
    centre, height = support_centre(scenario, 1.5)
    np.testing.assert_allclose(centre, (0.0, 0.05), atol=1e-15)
    assert height == pytest.approx(0.15, abs=1e-15)


def test_on_the_hands_alone_the_height_is_the_last_feets():
    """Sec. V-C: "the CoM vertical position is determined by adding a constant offset to the
    mean of the foot contact positions"; on the hands alone (Fig. 4 D's swing of both feet),
    the horizontal reference is the hands' centre and the height the last feet's."""
    phases = (
        ContactPhase(0.0, 1.0, (LEFT, RIGHT, *HANDS)),
        ContactPhase(1.0, 2.0, HANDS),
    )
    scenario = Scenario("t", 2.0, Scene(), phases, ())
    centre, height = support_centre(scenario, 1.5)
    np.testing.assert_allclose(centre, (0.5, 0.0), atol=1e-15)
    assert height == pytest.approx(0.225, abs=1e-15)
