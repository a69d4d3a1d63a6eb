"""The world's axes, declared once: Y up, the creature facing +Z, +X its left."""

from __future__ import annotations

import numpy as np

UP = np.array([0.0, 1.0, 0.0])  # the world's up axis
UP.flags.writeable = False
FORWARD = np.array([0.0, 0.0, 1.0])  # where a creature faces at the start of a straight path
FORWARD.flags.writeable = False
