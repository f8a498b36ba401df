"""One camera frame's work, $EGO_BENCH_STEPS times: convert a WIDTHxHEIGHT frame of
FORMAT (rgb565 or yuyv) to RGB888 with BACKEND (numpy or opencv), then encode it as JPEG
(quality 90): python camera_frames.py FORMAT WIDTH HEIGHT BACKEND [PART]; PART ``convert``
or ``encode`` does only that half (where a frame's instructions go). With $EGO_IMPORT_CV2
set, OpenCV is imported first, whatever the backend (what the import alone costs)."""

import os
import sys

import numpy as np

if os.environ.get("EGO_IMPORT_CV2"):
    import cv2  # noqa: F401

from ego.camera import rgb565_to_rgb888, yuyv_to_rgb888
from ego.camera.encode import encode_jpeg

fmt, width, height, backend = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
part = sys.argv[5] if len(sys.argv) > 5 else "both"
raw = np.random.default_rng(1).integers(0, 256, 2 * width * height, dtype=np.uint8).tobytes()
convert = rgb565_to_rgb888 if fmt == "rgb565" else yuyv_to_rgb888
image = convert(raw, width, height, backend=backend)
for _ in range(int(os.environ["EGO_BENCH_STEPS"])):
    if part != "encode":
        image = convert(raw, width, height, backend=backend, out=image)
    if part != "convert":
        encode_jpeg(image, 90)
if os.environ.get("EGO_BENCH_RSS"):  # count.sh's memory pass: the guest's resident pages
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from guest_memory import guest_rss_kb

    print(f"rss_kb {guest_rss_kb()} parent_kb 0", flush=True)
