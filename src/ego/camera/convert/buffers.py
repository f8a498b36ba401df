"""Working arrays kept between conversions: per thread, per geometry, the eight most recent."""

from __future__ import annotations

import threading
from collections import OrderedDict
from typing import Any

import numpy as np
import numpy.typing as npt

__all__ = ["CACHE_SIZE", "Buffers", "buffers"]


class Buffers:
    """Working arrays for one geometry, made on first use."""

    def __init__(self) -> None:
        self.arrays: dict[str, np.ndarray] = {}

    def get(self, name: str, shape: tuple[int, ...], dtype: npt.DTypeLike) -> np.ndarray:
        array = self.arrays.get(name)
        if array is None or array.shape != shape or array.dtype != np.dtype(dtype):
            array = self.arrays[name] = np.empty(shape, dtype=dtype)
        return array


#: How many geometries' buffers (and RGB565 plans) each thread keeps.
CACHE_SIZE = 8
_LOCAL = threading.local()


def buffers(key: tuple[Any, ...]) -> Buffers:
    """The working buffers for ``key`` in this thread (the eight most recent are kept)."""
    cache: OrderedDict[tuple[Any, ...], Buffers] | None = getattr(_LOCAL, "cache", None)
    if cache is None:
        cache = _LOCAL.cache = OrderedDict()
    found = cache.get(key)
    if found is None:
        found = cache[key] = Buffers()
        if len(cache) > CACHE_SIZE:
            cache.popitem(last=False)
    else:
        cache.move_to_end(key)
    return found
