"""rnea, bias, crba, aba on numpy arrays: the identities that tie them together, and one closed form."""

import numpy as np
import pytest

import tumble
from conftest import SCENES


@pytest.fixture(scope="module")
def panda():
    return tumble.Model.from_urdf(SCENES / "robots" / "panda.urdf")


def random_state(model, seed):
    rng = np.random.default_rng(seed)
    nv = model.nv()
    return rng.uniform(-1, 1, model.nq()), rng.normal(0, 1, nv), rng.normal(0, 1, nv)


def test_the_four_functions_agree(panda):
    for seed in range(5):
        q, v, a = random_state(panda, seed)
        m = tumble.crba(panda, q)
        b = tumble.bias(panda, q, v)
        tau = tumble.rnea(panda, q, v, a)
        assert m.shape == (panda.nv(), panda.nv())
        assert np.array_equal(m, m.T) and np.all(np.linalg.eigvalsh(m) > 0)
        # RNEA = M a + b;  ABA inverts RNEA
        assert np.allclose(tau, m @ a + b, rtol=1e-12, atol=1e-12)
        assert np.allclose(tumble.aba(panda, q, v, tau), a, rtol=1e-10, atol=1e-10)
        assert np.array_equal(tumble.rnea(panda, q, v, np.zeros(panda.nv())), b)


def test_double_pendulum_mass_matrix_closed_form():
    """Two rods (m = 1 kg, l = 1 m, centres at l/2, I = m l²/12):
    M11 = I1 + I2 + m l²/4 + m (l² + l²/4 + l² cos q2),  M12 = I2 + m (l²/4 + l²/2 cos q2),  M22 = I2 + m l²/4."""
    m = tumble.Model.from_urdf(SCENES / "robots" / "double_pendulum.urdf")
    i = 0.0833333333333333
    for q2 in (0.0, 0.7, -2.1):
        mm = tumble.crba(m, [0.3, q2])
        c = np.cos(q2)
        assert mm[0, 0] == pytest.approx(2 * i + 0.25 + 1.25 + c, rel=1e-14)
        assert mm[0, 1] == pytest.approx(i + 0.25 + 0.5 * c, rel=1e-14)
        assert mm[1, 1] == pytest.approx(i + 0.25, rel=1e-14)
    # gravity torque of the hanging pendulum turned by q1 = π/2 (both rods horizontal): 9.81 (0.5 + 1.5)
    g = tumble.bias(m, [np.pi / 2, 0.0], [0.0, 0.0])
    assert g[0] == pytest.approx(9.81 * 2.0, rel=1e-14) and g[1] == pytest.approx(9.81 * 0.5, rel=1e-14)


def test_bad_arrays_are_named(panda):
    q, v, a = random_state(panda, 0)
    with pytest.raises(tumble.TumbleError, match=rf"q: shape \(3,\), expected \({panda.nq()},\)"):
        tumble.rnea(panda, q[:3], v, a)
    with pytest.raises(tumble.TumbleError, match="v: dtype float32"):
        tumble.bias(panda, q, v.astype(np.float32))
    with pytest.raises(tumble.TumbleError, match="a: entry 2 is not finite"):
        a[2] = np.nan
        tumble.rnea(panda, q, v, a)
    with pytest.raises(tumble.TumbleError, match="no robot"):
        tumble.crba(tumble.Model.from_file(SCENES / "projectile.toml"), q)
