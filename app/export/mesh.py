"""The creature's mesh for export: its skinned body (:mod:`app.skin`), the same surface
the viewer and renders draw, in the clip's first frame, each vertex bound to up to four
joints."""

from __future__ import annotations

from ..kinematics.motion import Motion
from ..kinematics.skeleton import SkeletonClip
from ..skin import SkinnedBody, build_body


def creature_mesh(motion: Motion, clip: SkeletonClip) -> SkinnedBody:
    """The skinned body of ``motion``'s creature bound to ``clip``'s joints (its first
    frame is the bind pose)."""
    return build_body(motion, clip)
