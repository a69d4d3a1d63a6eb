"""The viewer's scene: its creatures (one :class:`~app.ui.session.CreatureSession`
each, in file order) on one ground, the selected one shown in the panels."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ..cast import Actor, Cast
from ..errors import GaitlabError
from ..kinematics.motion import Pose
from ..kinematics.world import World
from ..spec import CreatureSpec
from .base import StateBase
from .session import CreatureSession


class SceneMixin(StateBase):
    """Adding, selecting and picking the scene's creatures."""

    def add_creature(self, spec: CreatureSpec, world: World) -> bool:
        """Another creature of the scene, walking its own path on the same ground."""
        from dataclasses import replace

        try:
            session = CreatureSession.start(spec, replace(world, terrain=self.world.terrain),
                                            file_path=self._save_path_for(spec))
        except GaitlabError as exc:
            self.error = str(exc)
            return False
        self.sessions.append(session)
        return True

    @property
    def others(self) -> list[CreatureSession]:
        """The scene's creatures other than the selected one, in file order."""
        return [s for i, s in enumerate(self.sessions) if i != self.selected]

    @property
    def names(self) -> list[str]:
        """Every scene creature's name in file order (just this one outside a scene)."""
        return [s.spec.name for s in self.sessions]

    def cast(self) -> Cast:
        """What the view shows, as a recording or an export films it: every creature as
        edited, on its world, with its herd (the selected one first: the camera follows it)."""
        order = [self.selected] + [i for i in range(len(self.sessions)) if i != self.selected]
        return tuple(Actor(s.spec, s.world, herd=1 if s.herd is None else s.herd.count + 1)
                     for s in (self.sessions[i] for i in order))

    def select(self, index: int) -> bool:
        """Put scene creature ``index`` (file order) in the panels; the one there walks on."""
        if not 0 <= index < len(self.sessions):
            self.error = f"no creature {index + 1} in this scene"
            return False
        if index == self.selected:
            return True
        if self.driver is not None:
            self.stop_driving()
        self.selected = index
        self._last_edit = ("", 0.0)  # a new creature's edits never merge with the last one's
        self.footprints.clear()
        self.arcs.clear()
        self._last_pose = None
        self.status = f"selected {self.spec.name} ({index + 1} of {len(self.sessions)})"
        self.frame_view()
        return True

    def creature_poses(self) -> list[tuple[Pose, CreatureSession]]:
        """Poses of the scene's other creatures (file order, the selected one left out)."""
        return [(s.live.pose(), s) for s in self.others]

    def pick_creature(self, origin: NDArray[np.float64], direction: NDArray[np.float64]) -> int | None:
        """The scene creature (file order) a ray from ``origin`` along unit ``direction``
        points at: of the bodies it meets (each a sphere of half its length plus a third
        of its hip height around its root), the one it passes most nearly through the
        middle of (bodies overlap on screen: the nearest would hide the one clicked);
        None when it meets none."""
        best, best_fit = None, np.inf
        for index, session in enumerate(self.sessions):
            rig = session.live.rig
            rel = session.live.pose().root[:3, 3] - origin
            t = float(rel @ direction)
            radius = 0.5 * rig.body_length + 0.3 * rig.hip_height
            fit = float(np.linalg.norm(rel - t * direction)) / radius  # 0: straight through its middle
            if t > 0 and fit <= 1.0 and fit < best_fit:
                best, best_fit = index, fit
        return best
