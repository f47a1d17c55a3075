"""The gains of centroidal_feedback: Murooka's Appendix relation (eq. 19) and Table III."""

import numpy as np
import pytest

from stabilizers.centroidal_feedback import TABLE_III, appendix_gains, scaled_table_iii


def test_appendix_relation_reproduces_the_papers_numbers():
    # Appendix: m = 105, omega^2 = 10.3, K_xi = 2 -> K_PL about 2163, K_DL about 674
    kp, kd = appendix_gains(105.0, 10.3, 2.0)
    assert kp == pytest.approx(2163, abs=1)
    assert kd == pytest.approx(674, abs=1)


def test_scaling_returns_table_iii_for_hrp5p():
    kp, kd = scaled_table_iii(105.0, 0.95 * 9.81 / 9.8)  # HRP-5P: omega^2 = 9.8 / 0.95
    np.testing.assert_allclose(kp, TABLE_III["kp"], rtol=1e-9)
    np.testing.assert_allclose(kd, TABLE_III["kd"], rtol=1e-9)


def test_scaling_follows_m_omega_squared():
    kp_a, kd_a = scaled_table_iii(60.0, 0.8)
    kp_b, kd_b = scaled_table_iii(120.0, 0.8)  # twice the mass: twice the gains
    np.testing.assert_allclose(kp_b, 2 * kp_a)
    np.testing.assert_allclose(kd_b, 2 * kd_a)
    kp_c, kd_c = scaled_table_iii(60.0, 0.2)  # 4x omega^2 (2x omega)
    np.testing.assert_allclose(kp_c[:3], 4 * kp_a[:3])
    np.testing.assert_allclose(kd_c[:3], 2 * kd_a[:3])
    assert kp_a[3:].tolist() == [0, 0, 0]  # Table III: no angular feedback
