"""Issue 32, item 8: what ROS 2's tools check of the bridge's messages and names.

- sensor_msgs/Range: ``min_range`` below ``max_range`` (epuck_ros2's driver at 91ff8a1,
  ``driver.cpp:69-74``: IR 0.009..0.025 m, ToF 0.005..1.0 m, ground 0..0.016 m), in the
  bridge's messages and in the bags ego writes;
- a node's namespace: a relative one is put under the root, as rcl does
  (``rcl/src/rcl/node.c``, ``rcl_node_init``: ``""`` is ``/``, ``epuck`` is ``/epuck``),
  and an invalid one is still refused.
"""

from __future__ import annotations

import pytest

from ego.errors import FrameError
from ego.servers.ros2_node.build import Messages
from ego.servers.ros2_node.reading import Reading


@pytest.mark.parametrize("distro", ["humble", "jazzy", "kilted"])
def test_every_range_the_bridge_publishes_has_min_below_max(distro: str) -> None:
    messages = Messages(distro)
    reading = Reading(10**9, proximity=(300,) * 8, floor=(500,) * 3, tof_m=0.2)
    ranges = [*(messages.proximity(reading, i) for i in range(8)),
              *(messages.ground(reading, i) for i in range(3)), messages.tof(reading)]  # fmt: skip
    for message in ranges:
        assert 0.0 <= message.min_range < message.max_range, message.header.frame_id
    assert (ranges[0].min_range, ranges[0].max_range) == pytest.approx((0.009, 0.025))
    assert (ranges[-1].min_range, ranges[-1].max_range) == pytest.approx((0.005, 1.0))
    assert messages.scan(reading, 0.064).range_min == pytest.approx(0.009 + 0.035)


def test_the_bags_ranges_have_min_below_max() -> None:
    from ego.recording import ros2_topics

    models = {**ros2_topics._RANGE_BY_FAMILY, **ros2_topics._RANGE_BY_UNITS}
    for kind, model in models.items():
        assert 0.0 <= model.min_range < model.max_range, kind
    assert (models["proximity"].min_range, models["mm"].min_range) == (0.009, 0.005)


@pytest.mark.parametrize(("given", "made"), [("epuck", "/epuck"), ("", "/"), ("/", "/"),
                                             ("a/b", "/a/b"), ("/robot", "/robot")])  # fmt: skip
def test_a_relative_namespace_goes_under_the_root_as_rcl_does(given: str, made: str) -> None:
    from ego.ros2.names import node_namespace

    assert node_namespace(given) == made


@pytest.mark.parametrize("bad", ["1epuck", "epuck/", "a//b", "~/x", "e-puck", "/epuck/"])
def test_an_invalid_namespace_is_still_refused(bad: str) -> None:
    from ego.ros2.names import node_namespace

    with pytest.raises(FrameError):
        node_namespace(bad)
