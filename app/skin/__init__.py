"""One smooth skinned body per creature: a closed surface around the parts the renderer
draws (trunk segments, neck, head, tail, limb bones as tapered capsules and ellipsoids),
joined by a smooth union of their signed distances, polygonised by marching cubes and
simplified, with skin weights to the export skeleton's joints.

- :mod:`app.skin.sdf`: signed distances of the parts and their smooth union;
- :mod:`app.skin.body`: :func:`build_body` (the mesh, its colours and weights) and
  :class:`SkinnedBody` (linear blend skinning to any frame of a skeleton clip);
- :mod:`app.skin.features`: the eyes, nose and mane the body carries as a second mesh.

Pure numpy, scipy, scikit-image and fast-simplification; no GL.
"""

from __future__ import annotations

from .body import SkinnedBody, build_body

__all__ = ["SkinnedBody", "build_body"]
