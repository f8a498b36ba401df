"""The bridge's messages read field by field with the tests' own CDR reader
(tests/ros2/ros2_support.py, written from the OMG CDR rules, not rosbags), following
the .msg definitions of sensor_msgs, nav_msgs, tf2_msgs and geometry_msgs."""

from __future__ import annotations

from typing import Any

from tests.ros2.ros2_support import CdrReader


def header(r: CdrReader) -> dict[str, Any]:
    sec, nanosec = r.read("int32"), r.read("uint32")
    return {"stamp": sec * 10**9 + nanosec, "frame_id": r.string()}


def vec(r: CdrReader, n: int) -> list[float]:
    return r.array("float64", n)


def range_(payload: bytes, distro: str) -> dict[str, Any]:
    r = CdrReader(payload)
    out = header(r)
    out["radiation_type"] = r.read("uint8")
    out["field_of_view"], out["min_range"], out["max_range"], out["range"] = r.array("float32", 4)
    if distro != "humble":  # Humble's Range has no variance
        out["variance"] = r.read("float32")
    assert r.done()
    return out


def illuminance(payload: bytes, distro: str) -> dict[str, Any]:
    r = CdrReader(payload)
    out = header(r)
    out["illuminance"], out["variance"] = r.read("float64"), r.read("float64")
    assert r.done()
    return out


def scan(payload: bytes, distro: str) -> dict[str, Any]:
    r = CdrReader(payload)
    out = header(r)
    names = ("angle_min", "angle_max", "angle_increment", "time_increment", "scan_time",
             "range_min", "range_max")  # fmt: skip
    out.update(zip(names, r.array("float32", 7), strict=True))
    out["ranges"], out["intensities"] = r.sequence("float32"), r.sequence("float32")
    assert r.done()
    return out


def imu(payload: bytes, distro: str) -> dict[str, Any]:
    r = CdrReader(payload)
    out = header(r)
    out["orientation"], out["orientation_covariance"] = vec(r, 4), vec(r, 9)
    out["angular_velocity"], out["angular_velocity_covariance"] = vec(r, 3), vec(r, 9)
    out["linear_acceleration"], out["linear_acceleration_covariance"] = vec(r, 3), vec(r, 9)
    assert r.done()
    return out


def odometry(payload: bytes, distro: str) -> dict[str, Any]:
    r = CdrReader(payload)
    out = header(r)
    out["child_frame_id"] = r.string()
    out["position"], out["orientation"], out["pose_covariance"] = vec(r, 3), vec(r, 4), vec(r, 36)
    out["linear"], out["angular"], out["twist_covariance"] = vec(r, 3), vec(r, 3), vec(r, 36)
    assert r.done()
    return out


def transforms(payload: bytes, distro: str) -> list[dict[str, Any]]:
    r = CdrReader(payload)
    found = []
    for _ in range(r.read("uint32")):
        out = header(r)
        out["child_frame_id"] = r.string()
        out["translation"], out["rotation"] = vec(r, 3), vec(r, 4)
        found.append(out)
    assert r.done()
    return found


def joint_states(payload: bytes, distro: str) -> dict[str, Any]:
    r = CdrReader(payload)
    out = header(r)
    out["name"] = [r.string() for _ in range(r.read("uint32"))]
    out["position"], out["velocity"] = r.sequence("float64"), r.sequence("float64")
    out["effort"] = r.sequence("float64")
    assert r.done()
    return out


def image(payload: bytes, distro: str) -> dict[str, Any]:
    r = CdrReader(payload)
    out = header(r)
    out["height"], out["width"] = r.read("uint32"), r.read("uint32")
    out["encoding"], out["is_bigendian"] = r.string(), r.read("uint8")
    out["step"] = r.read("uint32")
    n = r.read("uint32")
    out["data"] = r.data[r.at : r.at + n]
    r.at += n
    assert r.done()
    return out


def compressed(payload: bytes, distro: str) -> dict[str, Any]:
    r = CdrReader(payload)
    out = header(r)
    out["format"] = r.string()
    n = r.read("uint32")
    out["data"] = r.data[r.at : r.at + n]
    r.at += n
    assert r.done()
    return out


def camera_info(payload: bytes, distro: str) -> dict[str, Any]:
    r = CdrReader(payload)
    out = header(r)
    out["height"], out["width"] = r.read("uint32"), r.read("uint32")
    out["distortion_model"], out["d"] = r.string(), r.sequence("float64")
    out["k"], out["r"], out["p"] = vec(r, 9), vec(r, 9), vec(r, 12)
    out["binning"] = (r.read("uint32"), r.read("uint32"))
    out["roi"] = [r.read("uint32") for _ in range(4)] + [r.read("bool")]
    assert r.done()
    return out
