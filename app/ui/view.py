"""The view: camera presets framing the selected creature, orbit, pan and zoom, the
follow camera, and what is drawn besides the creatures (ground, overlays, ghosts)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ..choices import CAMERA_PRESETS, DEFAULT_CAMERA
from ..errors import GaitlabError
from ..kinematics.ghosts import key_pose_ghosts, shift_pose
from ..kinematics.motion import Pose
from ..kinematics.overlays import inside_polygon, planted_points, support_polygon, touchdown_targets, trunk_centre
from ..kinematics.poses import reference_foot
from ..kinematics.world import World
from ..render.camera import CHASE_LOOK_AHEAD, clear_elevations, frame_points, look_ahead, point3
from ..render.options import GroundView, nice_grid_spacing, path_half_width
from ..render.overlays import Overlays
from ..render.scene import leg_colors
from .base import StateBase
from .playback import MAX_FRAME_TIME

LOWER_AFTER = 0.5  # s the follow camera holds a raised view before easing down (no juddering over bumps)
FOLLOW_EASE = 0.2  # s: the follow camera's height and a raised view's descent close on their goal with this time
# constant, whatever the frame rate (once 8 % a frame: at 12 fps a climbing creature outran the view by 0.6 m)


class ViewMixin(StateBase):
    """Cameras, overlays, ghosts and the ground under the creatures."""

    def frame_view(self, preset: str | None = None, ortho: bool = False) -> None:
        """Point a camera preset at the creature, framing a whole gait cycle (around where
        the creature is now, at the preset's angle to its heading). Each preset sets its
        own projection: perspective, unless ``ortho``."""
        from ..kinematics.clip import clip_motion
        from ..render.scene import motion_bounds

        preset = preset or self.camera_preset
        if preset not in CAMERA_PRESETS:
            self.error = f"unknown camera {preset!r}"
            return
        self.camera_preset = preset
        motion, _ = clip_motion(self.live.rig, 30.0, cycles=1.0, world=World(in_place=True))
        length = self.live.rig.body_length
        cam = frame_points(look_ahead(motion_bounds(motion), preset, length), preset, aspect=self.aspect)
        preset_elevation = cam.elevation  # before any rise over the ground in between
        # The chase camera aims ahead of the creature (the framed box reaches forward).
        self._follow_ahead = 0.5 * CHASE_LOOK_AHEAD * length if preset == "chase" else 0.0
        if not self.world.in_place:
            root = self.live.pose().root
            heading = float(np.degrees(np.arctan2(root[0, 2], root[2, 2])))
            tx, ty, tz = cam.target
            c, s = np.cos(np.radians(heading)), np.sin(np.radians(heading))
            # On the ground where the creature is now (a flight of stairs up, a hill down).
            x, z = float(root[0, 3] + c * tx + s * tz), float(root[2, 3] - s * tx + c * tz)
            ground = float(self.world.terrain.height(np.array([[root[0, 3], root[2, 3]]]))[0])
            cam = replace(cam, target=(x, ty + ground, z), azimuth=cam.azimuth + heading)
            if not self.world.terrain.flat and not cam.top_down:  # over the steps or hills in between
                need = clear_elevations(np.array([cam.target]), np.array([cam.azimuth]), cam.elevation, cam.distance,
                                        self.world.terrain.height, margin=0.1 * self.live.rig.hip_height)[0]
                cam = replace(cam, elevation=max(cam.elevation, float(need)))
        if self.herd is not None:  # back off so the group behind the creature is in view
            extent = float(np.abs(self.herd.slot).max()) + length
            cam = replace(cam, distance=cam.distance * max(1.0, 0.4 * extent / length))
        self.camera = replace(cam, ortho=ortho)
        self._follow_height = None
        # The follow camera eases back to the preset's own elevation once the ground allows.
        self._elevation = preset_elevation
        self.options = replace(self.options, grid_spacing=nice_grid_spacing(self.live.rig.hip_height * 1.6))

    def default_view(self) -> None:
        """The view the viewer starts with (R): the default preset, in perspective."""
        self.frame_view(DEFAULT_CAMERA)

    def side_ortho(self) -> None:
        """The animator's view: orthographic, from the side."""
        self.frame_view("side", ortho=True)

    def set_ortho(self, ortho: bool) -> None:
        self.camera = replace(self.camera, ortho=ortho)

    def orbit(self, dx_pixels: float, dy_pixels: float) -> None:
        self.camera = self.camera.orbit(-0.3 * dx_pixels, 0.3 * dy_pixels)
        self._elevation = self.camera.elevation

    def pan(self, dx_pixels: float, dy_pixels: float, view_height: float) -> None:
        self.camera = self.camera.pan(dx_pixels / max(view_height, 1.0), dy_pixels / max(view_height, 1.0))

    def zoom(self, wheel: float) -> None:
        self.camera = self.camera.zoom(0.88 ** wheel)

    def focus(self, point: tuple[float, float, float] | None) -> None:
        """Aim at ``point`` (world), or at the creature when it is ``None``."""
        if point is None:
            root = self.pose().root[:3, 3]
            point = (float(root[0]), float(root[1]), float(root[2]))
        self.camera = replace(self.camera, target=point3(point))

    def follow_creature(self, dt: float, pose: Pose | None = None) -> None:
        """Keep the camera on the creature, ``dt`` seconds after it last did: the target
        over its root, its height eased towards the root's (stairs, hills; time constant
        :data:`FOLLOW_EASE`), and the view turning with the path's heading (not while
        waypoints are edited)."""
        pose = pose or self.pose()
        dt = min(max(dt, 0.0), MAX_FRAME_TIME)  # as the animation moves on (a stalled frame)
        ease = 1.0 - math.exp(-dt / FOLLOW_EASE)
        root = pose.root[:3, 3]
        _, tangent = self.world.path.sample(np.array([pose.travel]))
        heading = float(np.degrees(np.arctan2(tangent[0, 0], tangent[0, 1])))
        previous = heading if self._heading is None else self._heading
        self._heading = heading
        if not self.follow:
            return
        _tx, ty, _tz = self.camera.target
        offset = self._follow_height
        if offset is None:
            offset = self._follow_height = ty - float(root[1])
        ty = ty + (float(root[1]) + offset - ty) * ease
        turn = (heading - previous + 180.0) % 360.0 - 180.0
        ahead = self._follow_ahead * tangent[0] if not self.world.in_place else np.zeros(2)
        if self.herd is not None:  # aim between the creature and its herd's middle
            ahead = ahead + 0.5 * (self.herd.position.mean(axis=0) - root[[0, 2]])
        # While waypoints are edited the view does not turn: the ground stays put under the cursor.
        turning = not (self.world.in_place or self.waypoint_edit)
        camera = replace(self.camera, target=(float(root[0] + ahead[0]), ty, float(root[2] + ahead[1])),
                         azimuth=self.camera.azimuth + (turn if turning else 0.0))
        if not self.world.terrain.flat and not camera.top_down:
            # Rise over hills that would hide the creature, easing back down after them.
            base = camera.elevation if self._elevation is None else self._elevation
            self._elevation = base
            # The sight line to the creature's body (not only to the target above it) clears the ground.
            hip = self.live.rig.hip_height
            body = np.array([[camera.target[0], min(camera.target[1], float(root[1])), camera.target[2]]])
            need = clear_elevations(body, np.array([camera.azimuth]), base, camera.distance,
                                    self.world.terrain.height, margin=0.1 * hip)[0]
            # Up at once where the ground would come between (a step rising into the view),
            # easing back down after it.
            goal = max(base, need)
            if goal > camera.elevation - 1e-9:
                self._lowering_in = LOWER_AFTER  # risen: hold a moment before easing down again
                camera = replace(camera, elevation=goal)
            elif self._lowering_in > 0.0:
                self._lowering_in -= dt
            else:
                camera = replace(camera, elevation=camera.elevation + (goal - camera.elevation) * ease)
        self.camera = camera

    def overlays(self, pose: Pose) -> Overlays | None:
        """The View panel's overlays for ``pose`` (None when all are off): the last
        footprints (recorded here, every frame), the swinging feet's touchdown targets and
        the support polygon with the trunk's centre."""
        o = self.options
        marks = self.waypoints if (self.waypoint_edit or self.path_kind == "waypoints") else []
        if not (o.footprints or o.targets or o.support or marks or self.herd is not None):
            return None
        rig = self.live.rig
        size = 0.12 * float(np.mean(rig.l_rest))
        parts: dict = {}
        if o.footprints:
            points, legs, age = self.footprints.recent(o.footprint_count, pose.ground_offset)
            parts.update(footprints=points, footprint_age=age, footprint_colors=leg_colors(rig)[legs] * 0.55)
        if o.targets:
            targets = touchdown_targets(self.live)[0]
            parts["targets"] = targets - np.array([0.0, 0.0, pose.ground_offset])  # in place: the ground moved
        if o.support:
            hull = support_polygon(planted_points(pose)[:, [0, 2]])
            centre = trunk_centre(pose)[[0, 2]]
            parts.update(support=hull, centre=centre, stable=inside_polygon(centre, hull))
        if marks:
            parts["waypoints"] = np.column_stack([np.array(marks)[:, 0], np.zeros(len(marks)), np.array(marks)[:, 1]])
        if self.herd is not None:  # the one the panels edit, leading its herd: a ring around its feet
            centre = trunk_centre(pose)
            parts.update(leader=np.array([centre[0], 0.0, centre[2]]),
                         leader_radius=0.6 * max(rig.body_length, rig.hip_height))
        return Overlays(size=size, **parts)

    def ground(self, pose: Pose) -> GroundView:
        """What the renderer draws under ``pose``."""
        return GroundView(terrain=self.world.terrain, offset=pose.ground_offset,
                          path=None if self.world.in_place else self.world.path, travel=pose.travel,
                          path_width=path_half_width(self.live.rig.hip_height, self.live.rig.body_length))

    def ghost_poses(self) -> list[Pose]:
        """The key poses of the step the creature is in, along its path (Key poses panel's
        ghosts); none unless asked for. Solved once a step; in place, where the ground has
        carried them since."""
        if not self.show_ghosts:
            return []
        live = self.live
        ref = reference_foot(live.rig)
        phase = float(live.foot_phase()[ref])
        step = (round(live.clock - phase, 6), phase < 0.5)
        cached = self._ghosts
        if cached is None or cached[0] is not live.rig or cached[1] is not live.world or cached[2] != step:
            try:
                motion = key_pose_ghosts(live.rig, live.world, live.clock, live.travel, phase)
            except GaitlabError:
                return []
            cached = self._ghosts = (live.rig, live.world, step, live.travel,
                                     [motion.pose(i) for i in range(motion.frame_count)])
        poses = cached[4]
        if live.world.in_place and live.travel != cached[3]:  # the ground has moved on under them
            back = np.array([0.0, 0.0, cached[3] - live.travel])
            poses = [shift_pose(p, back) for p in poses]
        return poses
