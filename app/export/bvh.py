"""BVH export: the skeleton's hierarchy and motion as a Biovision file.

Y up, metres (BVH has no unit field; ``gaitlab analyze`` detects metres from the hip
height, and Blender's importer takes a scale). Rotations are Euler angles in degrees,
applied in the order the channels are listed (ZXY: R = Rz Rx Ry); each joint uses the
axis order that keeps it away from gimbal lock over the clip (ZXY wherever it can), and
angles are continuous from frame to frame, so retiming or thinning keys never spins a
joint. Joints whose offset from
their parent changes over the clip (the trunk's joints, the hips, the neck and tail
bases) carry position channels, which replace their OFFSET; leg bones, whose lengths
are constant, carry rotations only. Every named joint is a JOINT (toe tips and the nose
too, each closed by a short End Site), so readers give back every position.
"""

from __future__ import annotations

import io
import os
import warnings
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from ..kinematics.skeleton import SkeletonClip
from ..output import AtomicPath

ROTATION_ORDERS = ("ZXY", "ZYX", "YXZ", "YZX", "XYZ", "XZY")  # ZXY first: the common choice
END_SITE = 0.01  # m: the End Site's offset along a leaf joint's +Y
SAFE_MARGIN = 20.0  # degrees the middle Euler angle keeps from +-90 for ZXY to be kept


def joint_eulers(rotation: np.ndarray) -> tuple[str, np.ndarray]:
    """One joint's rotations (T, 3, 3) as Euler angles (T, 3) in degrees, in the axis order
    whose middle angle stays farthest from +-90 degrees over the clip (where Euler angles
    lock and the other two swing by 180 from one frame to the next), unwrapped so that
    the angles change continuously."""
    best: tuple[float, str, np.ndarray] | None = None
    with warnings.catch_warnings():  # at gimbal lock scipy picks one of the equal answers: still exact
        warnings.simplefilter("ignore", UserWarning)
        for order in ROTATION_ORDERS:
            angles = Rotation.from_matrix(rotation).as_euler(order, degrees=True)
            margin = float(90.0 - np.abs(angles[:, 1]).max())
            if best is None or margin > best[0] + 1e-6:
                best = (margin, order, angles)
            if order == ROTATION_ORDERS[0] and margin >= SAFE_MARGIN:
                break  # the usual order is safe for this joint
    assert best is not None
    return best[1], np.unwrap(best[2], period=360.0, axis=0)


def _channels(clip: SkeletonClip) -> list[bool]:
    """Per joint: True if it needs position channels (its offset is not constant)."""
    spread = np.ptp(clip.local_translation, axis=0).max(axis=-1)  # (J,)
    return [j == 0 or bool(spread[j] > 1e-9) for j in range(clip.skeleton.count)]


def bvh_text(clip: SkeletonClip) -> str:
    """The whole BVH file as text."""
    skeleton = clip.skeleton
    positional = _channels(clip)
    eulers = [joint_eulers(clip.local_rotation[:, j]) for j in range(skeleton.count)]
    orders = [order for order, _ in eulers]
    out = io.StringIO()
    out.write("HIERARCHY\n")
    order: list[int] = []  # joints in file order (depth first), for the motion columns

    def write_joint(j: int, depth: int) -> None:
        pad = "  " * depth
        keyword = "ROOT" if skeleton.parents[j] < 0 else "JOINT"
        offset = np.zeros(3) if j == 0 else clip.local_translation[0, j]
        out.write(f"{pad}{keyword} {skeleton.names[j]}\n{pad}{{\n")
        out.write(f"{pad}  OFFSET {offset[0]:.6f} {offset[1]:.6f} {offset[2]:.6f}\n")
        rotations = " ".join(f"{axis}rotation" for axis in orders[j])
        if positional[j]:
            out.write(f"{pad}  CHANNELS 6 Xposition Yposition Zposition {rotations}\n")
        else:
            out.write(f"{pad}  CHANNELS 3 {rotations}\n")
        order.append(j)
        children = skeleton.children(j)
        for child in children:
            write_joint(child, depth + 1)
        if not children:
            out.write(f"{pad}  End Site\n{pad}  {{\n{pad}    OFFSET 0.000000 {END_SITE:.6f} 0.000000\n{pad}  }}\n")
        out.write(f"{pad}}}\n")

    write_joint(0, 0)
    T = clip.frame_count
    columns = []
    for j in order:
        if positional[j]:
            columns.append(clip.local_translation[:, j])
        columns.append(eulers[j][1])
    values = np.concatenate(columns, axis=1)
    out.write(f"MOTION\nFrames: {T}\nFrame Time: {1.0 / clip.fps:.8f}\n")
    np.savetxt(out, values, fmt="%.6f", delimiter=" ")
    return out.getvalue()


def write_bvh(path: str | os.PathLike[str], clip: SkeletonClip) -> Path:
    """Write ``clip`` as BVH, atomically."""
    text = bvh_text(clip)
    with AtomicPath(path) as out:
        out.tmp.write_text(text, encoding="utf-8")
    return Path(path)
