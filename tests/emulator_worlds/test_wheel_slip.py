"""The emulator's wheels slip a little and their counters are a little noisy, as a real
e-puck's: odometry from the step counters drifts from the true pose over a long run,
stays within a centimetre over a short one, and a world file may set (or zero) both."""

from __future__ import annotations

import math
import time
from pathlib import Path

import pytest

from firmware_sim import World
from firmware_sim.wheels import WheelModel
from firmware_sim.worlds import load_world

STEP_S = 0.032
M_PER_STEP = 2 * math.pi * 0.0205 / 1000
AXLE_M = 0.052


def _odometry_drift(world: World, legs: list[tuple[int, int, float]]) -> tuple[float, float]:
    """Drive ``legs`` (left, right steps/s, seconds) on ``world``'s clock, integrating the
    step counters as a controller would every 32 ms; (odometry's error m, distance m)."""
    start = world.snapshot()
    x, y, theta = start.x_m, start.y_m, start.theta_rad
    now = time.monotonic() + 1.0  # ahead of any real-time advance of the world
    world.advance(now)
    last = world.steps_int16()
    distance = 0.0
    for left, right, seconds in legs:
        world.set_speeds(left, right)
        for _ in range(round(seconds / STEP_S)):
            now += STEP_S
            world.advance(now)
            counts = world.steps_int16()
            dl, dr = ((c - p) * M_PER_STEP for c, p in zip(counts, last, strict=True))
            last = counts
            theta += (dr - dl) / AXLE_M
            x += (dl + dr) / 2 * math.cos(theta)
            y += (dl + dr) / 2 * math.sin(theta)
            distance += abs(dl + dr) / 2
    world.set_speeds(0, 0)
    with world._lock:  # the pose at ``now``, without the real clock moving it on
        body = world._body
        truth = (body.x_m, body.y_m)
    return math.hypot(x - truth[0], y - truth[1]), distance


#: About 1.3 m in the open middle of a 4 m arena: straight, a turn, an arc, straight.
LONG_RUN = [(500, 500, 8.0), (300, -300, 1.0), (400, 600, 6.0), (500, 500, 6.0)]
#: About 10 cm, the published odometry script's arc.
SHORT_RUN = [(318, 477, 2.0)]


def _open_world(wheels: WheelModel | None = None, seed: int = 2) -> World:
    from firmware_sim.world import Arena

    return World(seed=seed, arena=Arena(half_size_m=2.0), blocks=[], wheels=wheels)


def test_odometry_drifts_from_the_truth_over_a_long_run_by_default() -> None:
    error, distance = _odometry_drift(_open_world(), LONG_RUN)
    assert distance > 1.0
    # A real e-puck's odometry is off by centimetres after a metre or so; so is this one's.
    assert 0.01 < error < 0.15, error


def test_odometry_stays_within_a_centimetre_over_a_short_arc_by_default() -> None:
    for seed in range(5):
        error, distance = _odometry_drift(_open_world(seed=seed), SHORT_RUN)
        assert distance > 0.05
        assert error < 0.005, (seed, error)


def test_ideal_wheels_give_odometry_equal_to_the_truth() -> None:
    error, _ = _odometry_drift(_open_world(WheelModel(slip=0, encoder_noise_steps=0)), LONG_RUN)
    assert error < 0.003  # only the counters' whole steps and the controller's sums


def test_the_counters_are_noisy_and_the_truth_slips() -> None:
    quiet = _open_world(WheelModel(slip=0.0, encoder_noise_steps=0.0))
    noisy = _open_world(WheelModel(slip=0.0, encoder_noise_steps=20.0))
    slipping = _open_world(WheelModel(slip=0.1, encoder_noise_steps=0.0))
    ends = []
    for world in (quiet, noisy, slipping):
        _odometry_drift(world, [(500, 500, 4.0)])
        with world._lock:
            ends.append((world._body.steps[0], world._body.x_m))
    (quiet_steps, quiet_x), (noisy_steps, noisy_x), (slip_steps, slip_x) = ends
    assert quiet_steps == pytest.approx(2000, abs=1)
    assert abs(noisy_steps - quiet_steps) > 0.5  # counted give or take some steps ...
    assert noisy_x == pytest.approx(quiet_x, abs=1e-9)  # ... while it drove the same
    assert slip_steps == pytest.approx(quiet_steps, abs=1e-6)  # slipping: counted the same ...
    assert slip_x < quiet_x - 0.0005  # ... but covered less ground


def test_the_same_seed_gives_the_same_wheels_and_the_same_sensor_noise() -> None:
    a, b = _open_world(seed=7), _open_world(seed=7)
    assert a.wheels.slip == b.wheels.slip and a.wheels.slip[0] != a.wheels.slip[1]
    ideal = _open_world(WheelModel(0.0, 0.0), seed=7)
    assert a.proximity() == ideal.proximity()  # the model draws from its own generator


def test_a_world_file_sets_the_wheels(tmp_path: Path) -> None:
    path = tmp_path / "w.toml"
    path.write_text("[wheels]\nslip = 0.05\nencoder_noise_steps = 0\n")
    assert load_world(path, seed=1).wheels.model == WheelModel(0.05, 0.0)
    path.write_text("box = []\n")
    assert load_world(path, seed=1).wheels.model == WheelModel()  # small by default


@pytest.mark.parametrize(
    ("text", "error"),
    [
        ("slip = -0.01", "slip = -0.01 is not a number in 0.0..0.5"),
        ("slip = 0.6", "slip = 0.6 is not a number in 0.0..0.5"),
        ("slip = nan", "slip = nan is not a number in 0.0..0.5"),
        ("slip = 'a little'", "slip = 'a little' is not a number"),
        ("encoder_noise_steps = inf", "encoder_noise_steps = inf is not a number in 0.0..100.0"),
        ("encoder_noise_steps = -1", "encoder_noise_steps = -1 is not a number"),
        ("grip = 1", "unknown key 'grip' in \\[wheels\\]"),
    ],
)
def test_bad_wheels_in_a_world_file_are_refused(tmp_path: Path, text: str, error: str) -> None:
    path = tmp_path / "bad.toml"
    path.write_text(f"[wheels]\n{text}\n")
    with pytest.raises(ValueError, match=error) as info:
        load_world(path)
    assert str(path) in str(info.value)


@pytest.mark.parametrize(
    ("kwargs", "error"),
    [
        ({"slip": -0.1}, "wheel slip -0.1 is outside 0..0.5"),
        ({"slip": math.nan}, "wheel slip nan is outside 0..0.5"),
        ({"encoder_noise_steps": math.inf}, "wheel encoder_noise_steps inf is outside 0..100"),
        ({"slip": "0.1"}, "wheel slip '0.1' is not a number"),
    ],
)
def test_a_bad_wheel_model_is_refused(kwargs: dict[str, object], error: str) -> None:
    with pytest.raises(ValueError, match=error):
        WheelModel(**kwargs)  # type: ignore[arg-type]
