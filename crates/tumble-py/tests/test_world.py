"""World: stepping, state in and out (checked), energy and momenta, robot controls, links, contacts."""

import threading
import tracemalloc

import numpy as np
import pytest

import tumble
from conftest import SCENES

FREE_BODY = """
version = 1
[world]
gravity = [0.0, 0.0, 0.0]
integrator = "splitting"
[[body]]
name = "racket"
mass = 1.5
inertia = [1.0, 2.0, 3.0]
velocity = [0.3, -0.2, 0.1]
angular_velocity = [0.01, 5.0, 0.01]
"""


def test_step_and_time(projectile):
    w = tumble.World(projectile)
    assert w.time == 0.0 and w.steps == 0
    w.step()
    w.step(99)
    assert w.steps == 100 and w.time == pytest.approx(0.1, abs=1e-15)
    x = w.state()
    # the ball follows the parabola: x = v0x t, z = v0z t − g t²/2 (rk4 is exact on it)
    assert x[0] == pytest.approx(1.0, rel=1e-12)
    assert x[2] == pytest.approx(10 * 0.1 - 0.5 * 9.81 * 0.01, rel=1e-12)


def test_state_into_out_allocates_nothing(demo):
    w = tumble.World(demo)
    out = np.empty(demo.nstate)
    assert w.state(out=out) is out
    assert np.array_equal(out, w.state())
    w.state(out=out)  # warm up
    tracemalloc.start()
    start, _ = tracemalloc.get_traced_memory()
    tracemalloc.reset_peak()
    for _ in range(1000):
        w.state(out=out)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    # numpy reports its data buffers to tracemalloc: one temporary copy of the state would raise the
    # peak by 8 · nstate bytes
    assert peak - start < 8 * demo.nstate, f"{peak - start} bytes at the peak"


@pytest.mark.parametrize(
    "bad, message",
    [
        (np.zeros((2, 78)), r"shape \(2, 78\), expected \(78,\)"),
        (np.zeros(77), r"shape \(77,\), expected \(78,\)"),
        (np.zeros(78, dtype=np.float32), "dtype float32, expected float64"),
        ("abc", "expected a float64 numpy array, got str"),
    ],
)
def test_out_and_set_state_reject_wrong_shapes_and_dtypes(demo, bad, message):
    w = tumble.World(demo)
    with pytest.raises(tumble.TumbleError, match=message):
        w.set_state(bad)
    if isinstance(bad, np.ndarray) and bad.dtype == np.float64:
        with pytest.raises(tumble.TumbleError, match="out: shape"):
            w.state(out=bad)
    with pytest.raises(tumble.TumbleError, match="C-contiguous"):
        w.state(out=np.zeros((78, 2))[:, 0])


def test_set_state_checks_every_entry_and_changes_nothing_on_error(demo):
    w = tumble.World(demo)
    w.step(10)
    x = w.state()
    name = demo.body_names[1]
    for index, value, message in [
        (13 + 1, np.nan, rf"state\[14\] \(body `{name}`: position\) is not finite"),
        (13 + 8, np.inf, rf"state\[21\] \(body `{name}`: velocity\) is not finite"),
        (13 + 12, 1e11, r"angular velocity\) has magnitude 1e11"),
    ]:
        y = x.copy()
        y[index] = value
        with pytest.raises(tumble.TumbleError, match=message):
            w.set_state(y)
    y = x.copy()
    y[13 + 3 : 13 + 7] *= 1.01
    with pytest.raises(tumble.TumbleError, match=rf"body `{name}`: orientation\) is not a unit quaternion: \|q\| = 1.01"):
        w.set_state(y)
    with pytest.raises(tumble.TumbleError, match="int64, expected float64"):
        w.set_state(x.astype(np.int64))
    assert np.array_equal(w.state(), x), "a rejected state changes nothing"
    assert w.steps == 10


def test_set_state_accepts_lists_and_strided_arrays_and_reads_back(pendulum, demo):
    w = tumble.World(pendulum)
    w.set_state([0.5, -0.25, 1.0, 2.0])
    assert np.array_equal(w.state(), [0.5, -0.25, 1.0, 2.0])  # robot coordinates are stored as given
    strided = np.zeros((4, 2))
    strided[:, 1] = [0.1, 0.2, 0.3, 0.4]
    w.set_state(strided[:, 1])
    assert np.array_equal(w.state(), [0.1, 0.2, 0.3, 0.4])
    # free bodies are stored in their principal axes with a body-frame angular velocity:
    # the state reads back to round-off
    d = tumble.World(demo)
    d.step(200)
    x = d.state()
    e = tumble.World(demo)
    e.set_state(x)
    assert np.allclose(e.state(), x, rtol=1e-14, atol=1e-14)
    assert e.energy() == pytest.approx(d.energy(), rel=1e-13)


def test_nearly_unit_quaternion_is_renormalised(projectile):
    w = tumble.World(projectile)
    x = w.state()
    x[3:7] = [1.0 + 5e-7, 0.0, 0.0, 0.0]
    w.set_state(x)
    assert w.state()[3] == 1.0


def test_reset_returns_to_the_start(pendulum):
    w = tumble.World(pendulum)
    x0 = w.state()
    w.set_torque("pendulum", [1.0, 0.0])
    w.step(100)
    w.reset()
    assert w.time == 0.0 and np.array_equal(w.state(), x0)
    w.step(100)
    fresh = tumble.World(pendulum)
    fresh.step(100)
    assert np.array_equal(w.state(), fresh.state()), "reset clears the torque too"


def test_energy_and_momentum_of_a_free_body():
    m = tumble.Model.from_str(FREE_BODY)
    w = tumble.World(m)
    e0, p0, l0 = w.energy(), w.linear_momentum(), w.angular_momentum()
    assert e0 == pytest.approx(0.5 * 1.5 * (0.09 + 0.04 + 0.01) + 0.5 * (0.01**2 + 2 * 25 + 3 * 0.01**2))
    assert np.allclose(p0, 1.5 * np.array([0.3, -0.2, 0.1]))
    w.step(5000)  # the intermediate-axis spin flips; splitting keeps L to round-off
    assert np.allclose(w.linear_momentum(), p0, rtol=1e-14)
    assert np.linalg.norm(w.angular_momentum() - l0) < 1e-12 * np.linalg.norm(l0)
    assert w.energy() == pytest.approx(e0, rel=1e-9)


def test_set_torque_adds_to_the_scene_torque(pendulum):
    """A torque set from Python acts exactly as the same torque written in the scene."""
    text = (SCENES / "double_pendulum.toml").read_text()
    with_torque = tumble.Model.from_str(text + "torque = { shoulder = 0.7 }\n", base_dir=SCENES)
    a, b = tumble.World(pendulum), tumble.World(with_torque)
    a.set_torque("pendulum", np.array([0.7, 0.0]))
    a.step(1000)
    b.step(1000)
    assert np.array_equal(a.state(), b.state())
    c = tumble.World(with_torque)
    c.set_torque(0, [-0.7, 0.0])  # cancels the scene's
    free = tumble.World(pendulum)
    c.step(1000)
    free.step(1000)
    assert np.allclose(c.state(), free.state(), rtol=0, atol=1e-12)
    with pytest.raises(tumble.TumbleError, match=r"tau: shape \(3,\), expected \(2,\)"):
        a.set_torque("pendulum", [1.0, 2.0, 3.0])
    with pytest.raises(tumble.TumbleError, match="tau: entry 1 is not finite"):
        a.set_torque("pendulum", [1.0, np.nan])


def test_torque_does_the_work_it_should(pendulum):
    """Energy gained = ∫ τ · v dt (RK4 at 1 ms: to 1e-6 of the work)."""
    w = tumble.World(pendulum)
    tau = np.array([2.0, -1.0])
    w.set_torque("pendulum", tau)
    e0, work = w.energy(), 0.0
    v_prev = w.state()[2:]
    for _ in range(2000):
        w.step()
        v = w.state()[2:]
        work += 0.5 * (tau @ v_prev + tau @ v) * pendulum.dt
        v_prev = v
    assert w.energy() - e0 == pytest.approx(work, rel=1e-5)


def test_pd_target_holds_the_pendulum(pendulum):
    w = tumble.World(pendulum)
    with pytest.raises(tumble.TumbleError, match="has no PD gains"):
        w.set_pd_target("pendulum", [0.3, 0.2])
    w.set_pd_target("pendulum", [0.3, 0.2], kp=[400.0, 400.0], kd=[40.0, 40.0])
    w.step(5000)
    q = w.state()[:2]
    # a PD controller without gravity compensation settles near, not at, the target
    assert np.all(np.abs(q - [0.3, 0.2]) < 0.05), q
    assert np.all(np.abs(w.state()[2:]) < 1e-3)
    with pytest.raises(tumble.TumbleError, match="kp: entry 0 is negative"):
        w.set_pd_target("pendulum", [0.3, 0.2], kp=[-1.0, 1.0])


def test_link_states_follow_the_kinematics(pendulum):
    w = tumble.World(pendulum)
    names = pendulum.link_names()
    assert names == ["pendulum/upper", "pendulum/lower", "pendulum/tip"]
    w.set_state([0.0, 0.0, 0.0, 0.0])
    links = w.link_states()
    assert links.shape == (3, 13)
    assert np.allclose(links[:, 2], [2.5, 1.5, 0.5])  # hanging from 2.5 m, links of 1 m
    q1, q2 = 0.4, -0.9
    w.set_state([q1, q2, 0.0, 0.0])
    tip = w.link_states("pendulum")[2, :3]
    # rotation about +x: a point at −z goes to (0, sin q, −cos q)
    expected = np.array([0.0, np.sin(q1) + np.sin(q1 + q2), 2.5 - np.cos(q1) - np.cos(q1 + q2)])
    assert np.allclose(tip, expected, atol=1e-14)


def test_contacts_of_bodies_on_the_floor(demo):
    w = tumble.World(demo)
    w.step(3000)  # the thrown bodies have landed
    contacts = w.contacts()
    assert contacts, "bodies resting on the floor touch it"
    assert w.collisions() > 0
    for c in contacts:
        assert "floor" in (c["a"], c["b"])
        assert c["point"].shape == (3,) and abs(np.linalg.norm(c["normal"]) - 1.0) < 1e-12
        assert abs(c["depth"]) < 0.01
        assert c["force"].shape == (3,)


RESTING_BOX = """
version = 1
[world]
dt = 0.004
integrator = "semi_implicit_euler"
sleep = {sleep}
[[body]]
name = "floor"
fixed = true
shape = {{ type = "plane" }}
[[body]]
name = "box"
mass = 2.0
shape = {{ type = "box", half_extents = [0.3, 0.2, 0.1] }}
position = [0.0, 0.0, 0.1]
"""


def test_contact_forces_hold_a_resting_box_up():
    # a 2 kg box on a plane, sleeping off: once at rest, the contact forces on it sum to its weight
    w = tumble.World(tumble.Model.from_str(RESTING_BOX.format(sleep="false")))
    w.step(500)
    contacts = w.contacts()
    assert len(contacts) >= 3
    total = sum(c["force"] if c["b"] == "box" else -c["force"] for c in contacts)
    assert np.allclose(total, [0.0, 0.0, 2.0 * 9.81], rtol=1e-6, atol=1e-9)
    assert w.asleep() == 0


def test_a_resting_box_falls_asleep_and_wakes_when_its_state_is_set():
    w = tumble.World(tumble.Model.from_str(RESTING_BOX.format(sleep="true")))
    w.step(500)
    # at rest for 1.5 s it is asleep: not moved; its kept contacts (those of its last awake step,
    # when it moved slower than 1 cm/s) still hold it up
    assert w.asleep() == 1
    contacts = w.contacts()
    total = sum(c["force"] if c["b"] == "box" else -c["force"] for c in contacts)
    weight = 2.0 * 9.81
    assert abs(total[2] - weight) < 1e-3 * weight
    assert np.all(np.abs(total[:2]) < 1e-6 * weight)  # friction left from that step (~5e-9 N)
    x = w.state()
    w.step(10)
    assert np.array_equal(w.state(), x)
    # a state set from Python wakes it: thrown up, it leaves the floor
    x[7:10] = [0.0, 0.0, 1.0]  # velocity (m/s)
    w.set_state(x)
    w.step(25)  # 0.1 s: up by 1 m/s × 0.1 s − ½ g (0.1 s)² = 0.051 m
    assert w.asleep() == 0 and w.state()[2] > 0.1 + 0.04


def test_divergence_raises_and_keeps_the_last_finite_state(projectile):
    w = tumble.World(projectile)
    x = w.state()
    x[0], x[7] = 1e10 - 4.5e6, 1e9  # 1e6 m per step: beyond 1e10 m in the 5th step
    w.set_state(x)
    with pytest.raises(tumble.DivergedError, match=r"body `ball`: \|position\| = .* at step 5") as e:
        w.step(10)
    assert isinstance(e.value, tumble.TumbleError)
    assert w.steps == 4 and np.all(np.isfinite(w.state()))


def test_step_releases_the_gil(pendulum):
    """While one thread steps, another runs Python: it finds the World borrowed (it could not run at
    all if the GIL were held for the step)."""
    w = tumble.World(pendulum)
    seen = []

    def run():
        w.step(400_000)

    t = threading.Thread(target=run)
    t.start()
    while t.is_alive():
        try:
            _ = w.time
        except RuntimeError as e:  # "Already borrowed": the step holds the World, not the GIL
            seen.append(str(e))
            break
    t.join()
    assert seen and "borrow" in seen[0].lower()
    assert w.steps == 400_000


def test_contacts_of_robot_links_are_listed():
    model = tumble.Model.from_file(SCENES / "go1_stand.toml")
    w = tumble.World(model)
    w.step(1000)  # landed 5 mm below its start, standing on its four feet
    contacts = w.contacts()
    assert {(c["a"], c["b"]) for c in contacts} == {("ground", f"go1/{leg}_foot") for leg in ("FR", "FL", "RR", "RL")}
    weight = 13.100529 * 9.81  # the total mass of `tumble model go1.urdf --balance-inertia`
    assert sum(c["force"][2] for c in contacts) == pytest.approx(weight, rel=0.05)
    assert all(c["normal"][2] == pytest.approx(1.0) and abs(c["depth"]) < 1e-3 for c in contacts)
