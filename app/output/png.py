"""Single frames as PNG, atomically."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from .files import AtomicPath


def write_png(path: str | os.PathLike[str], image: NDArray[np.uint8]) -> Path:
    """Save one (H, W, 3) uint8 image as PNG, atomically."""
    from PIL import Image

    with AtomicPath(path) as out:
        Image.fromarray(image).save(out.tmp, format="PNG", optimize=False)
    return Path(path)
