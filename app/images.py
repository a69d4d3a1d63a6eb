"""Images from files a user gives (heightmaps, a model's textures), opened so that the
size an image declares can be checked before a byte of it is decoded: Pillow's own
decompression-bomb warning, which would print lines of its own before Gaitlab's one-line
error, never shows. Pillow still refuses (``Image.DecompressionBombError``) an image
declaring more than twice its ``MAX_IMAGE_PIXELS``, before the caller can look."""

from __future__ import annotations

import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import IO

from PIL import Image


@contextmanager
def opened_image(source: str | Path | IO[bytes]) -> Iterator[Image.Image]:
    """The image at ``source``, opened (its header read, nothing decoded) and closed
    afterwards. Raises what ``Image.open`` raises for a file that is not an image."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", Image.DecompressionBombWarning)
        image = Image.open(source)
    with image:
        yield image
