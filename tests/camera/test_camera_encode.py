"""JPEG and PNG encoding: right size back, quality that means something, PNG lossless."""

from __future__ import annotations

import io

import numpy as np
import pytest
from PIL import Image as PILImage

from ego.camera import ImageFormatError, encode_jpeg, encode_png, save_image
from ego.errors import OutOfRangeError


def natural_image(height: int = 96, width: int = 128) -> np.ndarray:
    """Smooth gradients, a bright disc and a little sensor noise: a camera-like picture."""
    y, x = np.mgrid[0:height, 0:width].astype(float)
    rgb = np.stack([x / width * 220, y / height * 200, 80 + 60 * np.sin(x / 9) * np.cos(y / 7)], -1)
    rgb[(x - width / 3) ** 2 + (y - height / 2) ** 2 < (height / 5) ** 2] = (250, 230, 40)
    rgb += np.random.default_rng(7).normal(0, 3, rgb.shape)
    return np.clip(rgb, 0, 255).astype(np.uint8)


def decode(data: bytes) -> np.ndarray:
    return np.asarray(PILImage.open(io.BytesIO(data)).convert("RGB"))


def psnr(a: np.ndarray, b: np.ndarray) -> float:
    mse = np.mean((a.astype(float) - b.astype(float)) ** 2)
    return float("inf") if mse == 0 else 10 * np.log10(255**2 / mse)


@pytest.mark.parametrize("quality", [1, 10, 50, 90, 100])
def test_jpeg_decodes_back_to_the_image_size_at_every_quality(quality):
    image = natural_image()
    decoded = decode(encode_jpeg(image, quality))
    assert decoded.shape == image.shape
    assert psnr(decoded, image) > (18 if quality < 10 else 23)


def test_jpeg_psnr_and_size_rise_with_quality():
    image = natural_image()
    encoded = {q: encode_jpeg(image, q) for q in (10, 50, 90, 100)}
    quality_db = [psnr(decode(encoded[q]), image) for q in (10, 50, 90, 100)]
    sizes = [len(encoded[q]) for q in (10, 50, 90, 100)]
    # 4:2:0 chroma and the image's own noise cap it near 33 dB at 100.
    assert quality_db == sorted(quality_db) and quality_db[-1] > 31
    assert sizes == sorted(sizes)


def test_jpeg_keeps_the_colour_channels_in_rgb_order():
    image = np.zeros((32, 32, 3), dtype=np.uint8)
    image[..., 0] = 230  # pure red: a BGR mix-up would decode blue
    r, g, b = decode(encode_jpeg(image, 95))[16, 16]
    assert r > 200 and g < 30 and b < 30


def test_png_is_lossless():
    image = natural_image(31, 45)
    assert np.array_equal(decode(encode_png(image)), image)


@pytest.mark.parametrize(
    ("name", "magic"),
    [
        ("a.jpg", b"\xff\xd8\xff"),
        ("b.JPEG", b"\xff\xd8\xff"),
        ("c.png", b"\x89PNG"),
        ("d.PNG", b"\x89PNG"),
    ],
)
def test_save_image_picks_the_format_by_extension(tmp_path, name, magic):
    image = natural_image(20, 30)
    save_image(image, tmp_path / name, 80)
    data = (tmp_path / name).read_bytes()
    assert data.startswith(magic)
    assert decode(data).shape == image.shape


def test_save_image_refuses_an_unknown_extension(tmp_path):
    with pytest.raises(ImageFormatError, match=r"\.jpg, \.jpeg or \.png"):
        save_image(natural_image(8, 8), tmp_path / "frame.bmp")
    assert not (tmp_path / "frame.bmp").exists()


@pytest.mark.parametrize("quality", [0, 101, -5])
def test_jpeg_quality_outside_1_to_100_is_refused(quality):
    with pytest.raises(OutOfRangeError, match=r"1\.\.100"):
        encode_jpeg(natural_image(8, 8), quality)


def test_non_integer_quality_is_refused():
    with pytest.raises(TypeError):
        encode_jpeg(natural_image(8, 8), 50.5)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    "bad", [np.zeros((8, 8), np.uint8), np.zeros((8, 8, 4), np.uint8), np.zeros((8, 8, 3), float)]
)
def test_anything_but_an_rgb888_image_is_refused(bad):
    with pytest.raises(ValueError, match="RGB888"):
        encode_png(bad)
