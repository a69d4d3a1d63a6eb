"""Taking the animation elsewhere: a clip's skeleton and motion as BVH or glTF.

- :mod:`.formats`: which suffixes are written;
- :mod:`.bvh`: the BVH writer;
- :mod:`.gltf`: the binary glTF writer (skinned mesh, animation with root motion);
- :mod:`.clip`: ``gaitlab export`` (simulate as ``render`` does, then write).
"""

from .bvh import bvh_text, write_bvh
from .clip import ExportResult, export_clip
from .formats import EXPORT_FORMATS, export_format
from .gltf import gltf_document, write_glb

__all__ = ["EXPORT_FORMATS", "ExportResult", "bvh_text", "export_clip", "export_format", "gltf_document", "write_bvh", "write_glb"]
