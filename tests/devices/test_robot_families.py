"""The Robot's typed family attributes are the families the device table made."""

from __future__ import annotations

import ego


def test_the_robot_s_family_attributes_are_its_families(sim_robot: ego.Robot) -> None:
    names = []
    for family in sim_robot.families:
        name = type(family).table_family
        names.append(name)
        assert getattr(sim_robot, name) is family is sim_robot.family(name)
    assert len(set(names)) == len(names) == len(ego.devices.table.TABLE.families)
