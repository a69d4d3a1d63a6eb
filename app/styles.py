"""Walk styles: sets of key-pose values an animator starts a walk from.

A walk step has four key poses (the animator's contact, down, pass and up; the next
contact begins the other foot's step). A style gives the body's height at each, as a
fraction of the creature's hip height above or below its rest height (what the legs'
reach allows caps it: a long stride lowers the contact pose), and the rest
of the pose: stride (leg rest lengths), the foot's angle at contact (degrees, heel
down), the arms' swing (degrees either way) and the torso's lean (degrees forward).
Choosing a style writes its values into the creature's ``[poses]`` table (in metres) and
``gait.stride``, where each can then be edited.

The styles follow the animation literature (Williams, *The Animator's Survival Kit*):

- **normal**: down low just after contact, up high just before the next one;
- **double-bounce**: two ups and two downs a step (a jaunty, bouncing walk);
- **sneak**: low, long reach, landing on the ball of the foot (a negative foot angle:
  toes first), leaning in, arms tucked;
- **proud**: chest out (leaning back), high, long confident steps, big arm swing;
- **tired**: low, short dragging steps, leaning forward, arms hanging.

A leaf module: it imports nothing from Gaitlab.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal, get_args

WalkStyleName = Literal["normal", "double-bounce", "sneak", "proud", "tired"]
WALK_STYLES: tuple[str, ...] = get_args(WalkStyleName)
KEY_POSES: tuple[str, ...] = ("contact", "down", "pass", "up")
KEY_POSE_TIMES: tuple[float, ...] = (0.0, 0.25, 0.5, 0.75)  # fraction of a step at which each key pose falls
DEFAULT_TIMING_FPS = 24.0  # the frame rate frames per cycle count in when a creature gives none (film)


@dataclass(frozen=True)
class WalkStyle:
    """Key-pose values. heights: body height at contact, down, pass, up (fractions of the
    hip height, + up); stride in leg rest lengths; angles in degrees."""

    name: str
    description: str
    heights: tuple[float, float, float, float]
    stride: float
    foot_angle: float
    arm_swing: float
    torso_lean: float


def style_heights(name: str, hip_height: float) -> tuple[float, float, float, float]:
    """A style's key-pose heights (contact, down, pass, up) in metres for a hip height (m)."""
    return tuple(h * hip_height for h in STYLES[name].heights)  # type: ignore[return-value]


STYLES: dict[str, WalkStyle] = {s.name: s for s in (
    WalkStyle("normal", "down just after contact, up before the next: the everyday walk",
              (-0.07, -0.085, -0.02, -0.005), stride=0.7, foot_angle=16.0, arm_swing=22.0, torso_lean=3.0),
    WalkStyle("double-bounce", "two ups and two downs each step: a jaunty, bouncing walk",
              (-0.07, -0.1, -0.02, -0.08), stride=0.65, foot_angle=18.0, arm_swing=26.0, torso_lean=2.0),
    WalkStyle("sneak", "low and long, landing on the toes, leaning in, arms tucked",
              (-0.22, -0.25, -0.2, -0.21), stride=0.85, foot_angle=-10.0, arm_swing=8.0, torso_lean=22.0),
    WalkStyle("proud", "chest out and high, long confident steps, big arm swing",
              (-0.06, -0.075, -0.01, 0.0), stride=0.75, foot_angle=24.0, arm_swing=30.0, torso_lean=-6.0),
    WalkStyle("tired", "low, short dragging steps, leaning forward, arms hanging",
              (-0.09, -0.13, -0.08, -0.07), stride=0.5, foot_angle=8.0, arm_swing=6.0, torso_lean=14.0),
)}
