"""Webots' node types (``WbNodeType`` in webots/nodes.h, R2023a on), the numbers
``Device.getNodeType()`` returns and ``Node.DISTANCE_SENSOR`` and its kind name.

Webots numbers the types in the order of its enum, so the order below is the API: it
follows the header of Webots R2023a and later (the ``Pose`` node is R2023a's).
"""

from __future__ import annotations

import re

__all__ = ["NODE_TYPES", "node_type"]

NODE_TYPES: tuple[str, ...] = (
    "NO_NODE",
    # 3D rendering
    "APPEARANCE", "BACKGROUND", "BILLBOARD", "BOX", "CAD_SHAPE", "CAPSULE", "COLOR",
    "CONE", "COORDINATE", "CYLINDER", "DIRECTIONAL_LIGHT", "ELEVATION_GRID", "FOG",
    "GROUP", "IMAGE_TEXTURE", "INDEXED_FACE_SET", "INDEXED_LINE_SET", "MATERIAL", "MESH",
    "MUSCLE", "NORMAL", "PBR_APPEARANCE", "PLANE", "POINT_LIGHT", "POINT_SET", "POSE",
    "SHAPE", "SPHERE", "SPOT_LIGHT", "TEXTURE_COORDINATE", "TEXTURE_TRANSFORM",
    "TRANSFORM", "VIEWPOINT",
    # robots
    "ROBOT",
    # devices
    "ACCELEROMETER", "ALTIMETER", "BRAKE", "CAMERA", "COMPASS", "CONNECTOR", "DISPLAY",
    "DISTANCE_SENSOR", "EMITTER", "GPS", "GYRO", "INERTIAL_UNIT", "LED", "LIDAR",
    "LIGHT_SENSOR", "LINEAR_MOTOR", "PEN", "POSITION_SENSOR", "PROPELLER", "RADAR",
    "RANGE_FINDER", "RECEIVER", "ROTATIONAL_MOTOR", "SKIN", "SPEAKER", "TOUCH_SENSOR",
    "VACUUM_GRIPPER",
    # misc
    "BALL_JOINT", "BALL_JOINT_PARAMETERS", "CHARGER", "CONTACT_PROPERTIES", "DAMPING",
    "FLUID", "FOCUS", "HINGE_JOINT", "HINGE_JOINT_PARAMETERS", "HINGE_2_JOINT",
    "IMMERSION_PROPERTIES", "JOINT_PARAMETERS", "LENS", "LENS_FLARE", "PHYSICS",
    "RECOGNITION", "SLIDER_JOINT", "SLOT", "SOLID", "SOLID_REFERENCE", "TRACK",
    "TRACK_WHEEL", "WORLD_INFO", "ZOOM",
    # experimental
    "MICROPHONE", "RADIO",
)  # fmt: skip
_NUMBERS = {name: number for number, name in enumerate(NODE_TYPES)}


#: The device table's node kinds whose Webots constant is not their name in capitals.
_KIND_CONSTANT = {"Motor": "ROTATIONAL_MOTOR"}


def node_type(kind: str) -> int:
    """The number Webots gives a node type, named as the device table names it
    (``"DistanceSensor"``) or as Webots' constant (``"DISTANCE_SENSOR"``)."""
    constant = _KIND_CONSTANT.get(kind) or re.sub(r"(?<=[a-z])(?=[A-Z])", "_", kind).upper()
    return _NUMBERS[constant]
