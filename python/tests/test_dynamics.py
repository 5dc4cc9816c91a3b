"""The Python module against the mathematics of the step (docs/design.md#dynamics): semi-implicit
Euler in free flight, forces and torques added to gravity, and contact impulses that carry the
weight of what rests on them."""
import json
import math

import numpy as np
import pytest

import rbpart

G = 9.81


def ball_scene(gravity=(0.0, 0.0, -G), velocity=(0.0, 0.0, 0.0), dt=0.01):
    """One 2 kg ball of radius 0.1 m, alone in the world."""
    return {
        "name": "ball",
        "gravity": list(gravity),
        "dt": dt,
        "bodies": [
            {"name": "ball", "shape": {"type": "sphere", "radius": 0.1}, "mass": 2.0,
             "position": [0.0, 0.0, 10.0], "velocity": list(velocity)},
        ],
    }


def euler_position(x0, v0, a, h, n):
    """x_n of semi-implicit Euler (v_k = v_{k-1} + h a, x_k = x_{k-1} + h v_k) under constant a."""
    return np.asarray(x0) + n * h * np.asarray(v0) + h * h * np.asarray(a) * n * (n + 1) / 2


def test_free_fall_follows_semi_implicit_euler():
    h, n, v0 = 0.01, 50, np.array([1.0, -0.5, 2.0])
    world = rbpart.World(ball_scene(velocity=v0, dt=h))
    x0 = world.positions[0].copy()
    stats = world.step(n)
    g = np.array([0.0, 0.0, -G])
    assert stats["contacts"] == 0
    np.testing.assert_allclose(world.positions[0], euler_position(x0, v0, g, h, n), rtol=0, atol=1e-12)
    np.testing.assert_allclose(world.velocities[0], v0 + n * h * g, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(world.orientations[0], [1.0, 0.0, 0.0, 0.0])
    np.testing.assert_array_equal(world.angular_velocities[0], [0.0, 0.0, 0.0])
    assert world.time == pytest.approx(n * h)
    # The kinetic energy the step reports is m |v|^2 / 2 of that velocity.
    assert stats["kinetic_energy"] == pytest.approx(0.5 * 2.0 * np.sum((v0 + n * h * g) ** 2), rel=1e-12)


def test_a_force_applied_every_step_adds_to_gravity():
    h, n, m = 0.01, 40, 2.0
    force = np.array([3.0, -1.0, 5.0])
    world = rbpart.World(ball_scene(dt=h))
    x0 = world.positions[0].copy()
    for _ in range(n):
        world.apply_force(0, force)
        world.step()
    a = np.array([0.0, 0.0, -G]) + force / m
    np.testing.assert_allclose(world.positions[0], euler_position(x0, np.zeros(3), a, h, n), rtol=0, atol=1e-12)
    # Forces last one step: the next step is gravity alone.
    world.step()
    np.testing.assert_allclose(world.velocities[0], n * h * a + h * np.array([0.0, 0.0, -G]), rtol=0, atol=1e-12)


def test_a_force_off_the_centre_also_turns_the_body():
    # A sphere's inertia is isotropic (2/5 m r^2), so its gyroscopic term vanishes and a constant
    # torque r x F raises the angular velocity by h (r x F) / I every step.
    h, n, m, r = 0.01, 30, 2.0, 0.1
    force, arm = np.array([0.0, 4.0, 0.0]), np.array([0.1, 0.0, 0.0])
    world = rbpart.World(ball_scene(gravity=(0.0, 0.0, 0.0), dt=h))
    for _ in range(n):
        world.apply_force(0, force, point=world.positions[0] + arm)
        world.step()
    inertia = 0.4 * m * r * r
    np.testing.assert_allclose(world.angular_velocities[0], n * h * np.cross(arm, force) / inertia, rtol=1e-12)
    np.testing.assert_allclose(world.velocities[0], n * h * force / m, rtol=1e-12)


def test_a_torque_about_z_turns_the_orientation_as_the_quaternion_update_says():
    # q <- normalise(q + h/2 (0, w) q) about a fixed axis turns the angle by 2 atan(h w / 2).
    h, n, m, r, tau = 0.01, 25, 2.0, 0.1, 0.3
    world = rbpart.World(ball_scene(gravity=(0.0, 0.0, 0.0), dt=h))
    inertia = 0.4 * m * r * r
    angle = 0.0
    for k in range(1, n + 1):
        world.apply_torque(0, [0.0, 0.0, tau])
        world.step()
        angle += 2 * math.atan(h * (k * h * tau / inertia) / 2)
    np.testing.assert_allclose(world.orientations[0], [math.cos(angle / 2), 0, 0, math.sin(angle / 2)], atol=1e-12)
    np.testing.assert_allclose(world.angular_velocities[0], [0, 0, n * h * tau / inertia], rtol=1e-12)


def box_on_floor(mass):
    return {
        "name": "resting box",
        "dt": 1 / 60,
        "bodies": [
            {"name": "floor", "static": True, "shape": {"type": "box", "half_extents": [5, 5, 0.1]},
             "position": [0, 0, -0.1]},
            {"name": "box", "shape": {"type": "box", "half_extents": [0.3, 0.2, 0.1]}, "mass": mass,
             "position": [0, 0, 0.1]},
        ],
    }


def impulses_on(body, contacts, partner=None):
    """Total contact impulse on `body` over the last step (from `partner` alone if given): body a
    receives +impulse, body b -impulse."""
    total = np.zeros(3)
    for a, b, impulse in zip(contacts["body_a"], contacts["body_b"], contacts["impulse"]):
        if a == body and partner in (None, b):
            total += impulse
        elif b == body and partner in (None, a):
            total -= impulse
    return total


def check_momentum_balance(world, velocities_before):
    """Impulse-momentum over one step of semi-implicit Euler, for every dynamic body:
    m (v+ - v) = m g h + the contact impulses on it (the contacts reported are those applied)."""
    c, h, g = world.contacts(), world.dt, np.array([0.0, 0.0, -G])
    for body in np.flatnonzero(~world.is_static):
        m = world.masses[body]
        expected = m * (world.velocities[body] - velocities_before[body]) - m * h * g
        np.testing.assert_allclose(impulses_on(body, c), expected, rtol=1e-9, atol=1e-12 * m)


# At rest the contact impulses carry the weight, m g h a step, to within the regularisation floor
# (sigma_floor = 1e-6 of each row's diagonal lets a resting contact creep at ~1e-6 g h).
REST_RTOL = 1e-5


@pytest.mark.parametrize("mass", [1.0, 750.0])
def test_a_resting_box_contact_impulses_sum_to_m_g_h(mass):
    world = rbpart.World(box_on_floor(mass))
    h = world.dt
    world.step(59)
    before = world.velocities
    world.step()
    check_momentum_balance(world, before)
    c = world.contacts()
    assert len(c["normal_impulse"]) >= 4  # a face on the floor: its corners
    assert set(c["body_a"]) == {1} and set(c["body_b"]) == {0}
    np.testing.assert_allclose(c["normal"], np.tile([0.0, 0.0, 1.0], (len(c["normal"]), 1)), atol=1e-9)
    assert np.all(c["normal_impulse"] >= 0)
    np.testing.assert_allclose(c["impulse"].sum(axis=0), [0.0, 0.0, mass * G * h], rtol=REST_RTOL,
                               atol=REST_RTOL * mass * G * h)
    np.testing.assert_allclose(c["friction_impulse"], 0.0, atol=1e-9 * mass)
    np.testing.assert_allclose(c["impulse"], c["normal_impulse"][:, None] * c["normal"] + c["friction_impulse"])
    np.testing.assert_allclose(world.velocities[1], 0.0, atol=REST_RTOL * G * h)


# PGS converges linearly, at a rate that depends on its rows' order (which the contact points'
# order sets): on this stack 2000 sweeps leave friction impulses of ~1e-8 of the weight above each
# box, 400 to 600 sweeps up to 2e-3.
STACK_SOLVERS = [
    ({}, 1.0, 1000.0, REST_RTOL),
    ({"solver": "substructured", "partitioner": "mix", "refiner": "fm", "nmax": 2}, 1.0, 1000.0, REST_RTOL),
    ({"solver": "pgs", "pgs_iterations": 2000}, 125.0, 125.0, 1e-3),
]


@pytest.mark.parametrize("options,light,heavy,rtol", STACK_SOLVERS)
def test_each_box_of_a_stack_rests_on_the_weight_above_it(options, light, heavy, rtol):
    world = rbpart.World("box_stack", {"boxes": 4, "mass_even": light, "mass_odd": heavy}, **options)
    for key, value in options.items():
        assert world.options[key] == str(value)
    h = world.dt
    world.step(59)
    before = world.velocities
    world.step()
    check_momentum_balance(world, before)
    masses, c = world.masses, world.contacts()
    for box in range(1, world.body_count):
        on_box = impulses_on(box, c, partner=box - 1)  # from the box below it, or the ground (body 0)
        weight_above = masses[box:].sum() * G * h
        np.testing.assert_allclose(on_box, [0.0, 0.0, weight_above], rtol=rtol, atol=rtol * weight_above)


def test_scene_file_loads_the_poses_it_gives(tmp_path):
    scene = box_on_floor(2.0)
    scene["bodies"][1]["orientation"] = [math.cos(0.3), 0.0, 0.0, math.sin(0.3)]
    scene["bodies"][1]["velocity"] = [0.5, 0.0, 0.0]
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(scene))
    world = rbpart.World(str(path))
    assert world.names == ["floor", "box"]
    np.testing.assert_array_equal(world.is_static, [True, False])
    np.testing.assert_allclose(world.positions, [[0, 0, -0.1], [0, 0, 0.1]], atol=1e-15)
    np.testing.assert_allclose(world.orientations[1], [math.cos(0.3), 0, 0, math.sin(0.3)], atol=1e-15)
    np.testing.assert_allclose(world.velocities[1], [0.5, 0, 0])
    # The mass of a box given by density is density x volume.
    scene["bodies"][1].pop("mass")
    scene["bodies"][1]["density"] = 500.0
    assert rbpart.World(scene).masses[1] == pytest.approx(500.0 * 0.6 * 0.4 * 0.2, rel=1e-12)


def test_builtin_scene_parameters_shape_the_scene():
    assert "box_stack" in rbpart.scenes()
    world = rbpart.World("box_stack", {"boxes": 3, "size": 0.4}, dt=0.005)
    assert world.dt == 0.005
    np.testing.assert_allclose(world.positions[1:, 2], [0.2, 0.6, 1.0])


@pytest.mark.parametrize("scene,parameters,options", [
    ("box_stack", None, {"erp": 0.0}),
    ("box_stack", None, {"nmax": 1.5}),
    ("box_stack", None, {"solver": "simplex"}),
    ("box_stack", None, {"solver": "newton"}),  # the direct solver is the Newton solver
    ("box_stack", None, {"sigma_floor": 0.0}),  # which divides by every row's regularisation
    ("box_stack", None, {"contact_prox": -1e-3}),
    ("box_stack", None, {"solver": "substructured"}),  # needs a partitioner
    ("box_stack", None, {"no_such_option": 1}),
    ("box_stack", {"boxes": -2}, {}),
    ("no_such_scene", None, {}),
])
def test_bad_scenes_and_options_raise_value_error(scene, parameters, options):
    with pytest.raises(ValueError):
        rbpart.World(scene, parameters, **options)


def test_forces_on_static_or_missing_bodies_are_refused():
    world = rbpart.World(box_on_floor(1.0))
    with pytest.raises(ValueError):
        world.apply_force(0, [0.0, 0.0, 1.0])
    with pytest.raises(IndexError):
        world.apply_torque(2, [0.0, 0.0, 1.0])
