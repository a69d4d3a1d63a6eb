"""Images from files a user gives (heightmaps, a model's textures), opened so that the
size an image declares can be checked before a byte of it is decoded, and Pillow's own
warnings (a decompression bomb, a palette's transparency, a damaged tag), which would
print lines of their own around Gaitlab's one-line error or result, never show. Pillow
still refuses (``Image.DecompressionBombError``) an image declaring more than twice its
``MAX_IMAGE_PIXELS``, before the caller can look."""

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
    afterwards; while it is open, Pillow's warnings about the file (a bomb's size, a
    palette's transparency, a damaged APNG or TIFF tag) are held back: the caller says
    in one line what it makes of the image. Raises what ``Image.open`` raises for a file
    that is not an image."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with Image.open(source) as image:
            yield image
