"""Editing where the selected creature walks: the Terrain panel's ground (for every
creature of the scene) and the Path panel's route (straight, circle, figure-eight or
waypoints), always from where the body is, so nothing already walked moves."""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import GaitlabError
from ..kinematics.path import Path as GroundPath
from ..kinematics.path import SplicedPath, StraightPath, WaypointPath
from ..kinematics.world import World
from ..rigging import build_rig
from ..worlds.kinds import TERRAIN_KINDS
from .base import StateBase


class WorldMixin(StateBase):
    """The Terrain and Path panels."""

    def _init_terrain_values(self) -> None:
        """The Terrain panel's starting values: each kind's keys (the registry's defaults),
        the sizes sized to the creature, then the world's own."""
        rig = self.live.rig
        h, length = rig.hip_height, rig.body_length
        self.terrain_values = {name: {key.name: "" if key.name == "file" else key.default for key in kind.keys}
                               for name, kind in TERRAIN_KINDS.items()}
        sized = {"hills": {"amp": round(0.12 * h, 3), "wavelength": round(3.0 * length, 2)},
                 "stairs": {"rise": round(0.2 * h, 3), "run": round(max(0.6 * rig.leg_scale, 0.12), 3), "steps": 6,
                            "start": round(0.8 * length, 2)}}
        for name, values in sized.items():
            self.terrain_values[name].update(values)
        kind, _, rest = self.world.terrain.describe().partition(":")
        kind = {"grid": "heightmap"}.get(kind, kind)
        if kind in self.terrain_values:
            self.terrain_kind = kind
            for item in filter(None, rest.split(",")):
                key, _, value = item.partition("=")
                if key in self.terrain_values[kind]:
                    old = self.terrain_values[kind][key]
                    try:
                        self.terrain_values[kind][key] = value if isinstance(old, str) else type(old)(float(value))
                    except ValueError:
                        pass

    def terrain_text(self, kind: str | None = None) -> str:
        """The Terrain panel's ground as ``--terrain`` text."""
        kind = kind or self.terrain_kind
        values = self.terrain_values.get(kind, {})
        items = [f"{k}={v}" if isinstance(v, (str, int)) else f"{k}={v:g}" for k, v in values.items()
                 if not (k == "cell" and not v)]
        return kind + (":" + ",".join(items) if items else "")

    def set_terrain(self, kind: str | None = None, **values: Any) -> bool:
        """Regenerate the ground from the Terrain panel's kind and values (given ones
        replace the panel's) while the creature walks: planted feet stay where they stand
        until they lift, later footholds are on the new ground. A value out of range, a
        file that does not load or ground the creature cannot walk shows the error and
        changes nothing (the panel keeps its previous values)."""
        from ..worlds import parse_terrain

        kind = kind or self.terrain_kind
        if kind not in self.terrain_values:
            self.error = f"unknown terrain {kind!r}"
            return False
        saved = (self.terrain_kind, {k: dict(v) for k, v in self.terrain_values.items()})
        self.terrain_values[kind].update(values)
        text = self.terrain_text(kind)
        try:
            if kind in ("heightmap", "mesh") and not self.terrain_values[kind]["file"]:
                raise GaitlabError(f"{kind}: give the file to load")
            terrain = parse_terrain(text)
            world = World(path=self.world.path, terrain=terrain, in_place=self.world.in_place and terrain.flat)
            others = [(m, replace(m.world, terrain=terrain)) for m in self.others]
            for member, member_world in others:  # every creature of the scene must find footholds
                member.live.check_world(member_world)
            self.live.set_world(world)
            for member, member_world in others:
                member.live.set_world(member_world)
                member.world = member_world
        except GaitlabError as exc:
            self.terrain_kind, self.terrain_values = saved
            message = str(exc)
            self.error = message if text in message or message.startswith("--terrain") else f"terrain {text}: {message}"
            return False
        self.terrain_kind = kind
        self.world = world
        self.error = None
        return True

    def _here(self) -> tuple[NDArray[np.float64], float]:
        """The body's point on its path (x, z) and its heading (radians) now."""
        (point,), (tangent,) = self.world.path.sample(np.array([self.live.travel]))
        return point, float(np.arctan2(tangent[0], tangent[1]))

    def _take_route(self, route: GroundPath) -> bool:
        """Go on along ``route`` (which starts where the body is, along its heading) from
        now, the path behind kept; on a route the creature cannot take, say why and keep
        the current one."""
        try:
            path = SplicedPath(self.world.path, self.live.travel, route)
            world = World(path=path, terrain=self.world.terrain)
            self.live.set_world(world)  # checks first; changes nothing when it refuses
        except GaitlabError as exc:
            self.error = str(exc)
            return False
        if self.driver is not None:  # the route, not the keys, steers from now on
            self.driver = None
            self.drive_input = (0.0, 0.0)
            try:
                self.live.set_rig(build_rig(self.spec))
            except GaitlabError:
                pass
        self.world = world
        self.options = replace(self.options, path=True)
        self.error = None
        return True

    def set_path(self, kind: str | None = None, **values: Any) -> bool:
        """From here on, follow a path of ``kind`` (straight, circle, figure-eight, or the
        waypoints) with the Path panel's values (given ones replace them), starting where
        the body is, along its heading. Bad values show the error and change nothing."""
        from ..worlds import parse_path

        kind = kind or self.path_kind
        if kind not in self.path_values:
            self.error = f"unknown path {kind!r}; choose one of {', '.join(self.path_values)}"
            return False
        if kind == "waypoints":
            return self.set_waypoints(self.waypoints)  # (sets the kind when it succeeds)
        merged = {**self.path_values[kind], **values}
        text = kind + (":" + ",".join(f"{k}={v:g}" if not isinstance(v, str) else f"{k}={v}"
                                      for k, v in merged.items()) if merged else "")
        point, heading = self._here()
        try:
            route = parse_path(text)
        except GaitlabError as exc:
            self.error = str(exc)
            return False
        route.start, route.heading = (float(point[0]), float(point[1])), heading
        if not self._take_route(route):
            return False
        self.path_kind = kind
        self.path_values[kind] = merged
        self.waypoints, self._waypoint_s = [], []  # another kind of route: no waypoints ahead
        return True

    def leave_in_place(self) -> None:
        """Walk in the world (the view and the ground then agree, for picking on it)."""
        if self.world.in_place:
            world = replace(self.world, in_place=False)
            self.live.set_world(world)
            self.world = world

    def set_waypoints(self, points: list[tuple[float, float]]) -> bool:
        """Go through ``points`` (x, z, m) from here, in order; none: straight on. A first
        point within half a body length of the body counts as reached. The way to the
        first point turns no tighter than the creature can (:func:`turn_radius`): an arc
        towards it, then straight on (a point beside or behind gets a loop)."""
        from ..kinematics.path import turn_towards
        from ..worlds import waypoint_path

        point, heading = self._here()
        length = self.live.rig.body_length
        forward = np.array([np.sin(heading), np.cos(heading)])
        pts = [(float(p[0]), float(p[1])) for p in points]
        while pts and np.all(np.isfinite(pts[0])) and np.linalg.norm(np.asarray(pts[0]) - point) <= 0.5 * length:
            pts.pop(0)  # the next waypoint is under the creature: reached
        route: GroundPath
        knots: list[int] = []  # the route's knot at each waypoint
        try:
            if not pts:
                route = StraightPath(start=(float(point[0]), float(point[1])), heading=heading)
            else:
                if not all(np.all(np.isfinite(p)) and max(abs(p[0]), abs(p[1])) <= 1e4 for p in pts):
                    raise GaitlabError("a waypoint must be within 10 km of the origin")
                # Each leg of the way turns towards the next point from the way it arrived.
                radius = turn_radius(self.live.rig)
                legs, here, facing = [], np.asarray(point, dtype=np.float64), heading
                # First straight on for a stance, so that the feet down now finish it in reach.
                lead = max(float(np.max(self.live.rig.stride_length)), 0.5 * length)
                to_first = np.asarray(pts[0]) - point
                if to_first @ forward < np.cos(np.radians(20.0)) * np.linalg.norm(to_first):  # not dead ahead
                    here = here + lead * forward
                    legs.append(np.stack([np.asarray(point, dtype=np.float64), here]))
                for target in np.asarray(pts, dtype=np.float64):
                    way = turn_towards(here, facing, target, radius)
                    legs.append(way if not legs else way[1:])
                    knots.append(sum(len(leg) for leg in legs) - 1)
                    arrive = way[-1] - way[-2]
                    here, facing = target, float(np.arctan2(arrive[0], arrive[1]))
                route = waypoint_path(np.concatenate(legs), False, "waypoints", start_direction=forward)
        except GaitlabError as exc:
            self.error = str(exc)
            return False
        if not self._take_route(route):
            if self.error and "too tight" in self.error and pts:
                x, z = pts[0]
                self.error = (f"cannot route the {self.spec.name} to ({x:.1f}, {z:.1f}): the way there turns more "
                              "tightly than it can walk; put the next waypoints farther apart")
            return False
        self.waypoints = pts
        # Where along the path each waypoint lies (m), to drop those the body has passed.
        along = np.array([route.point_arc_lengths(k, 1)[0] for k in knots]) if isinstance(route, WaypointPath) \
            else np.zeros(0)
        self._waypoint_s = (self.live.travel + along).tolist()
        self.path_kind = "waypoints"
        return True

    def _drop_passed_waypoints(self) -> None:
        """Waypoints the body has reached are done: they leave the list (the route stays)."""
        passed = sum(1 for s in self._waypoint_s if s <= self.live.travel)
        if passed:
            del self.waypoints[:passed]
            del self._waypoint_s[:passed]

    def add_waypoint(self, x: float, z: float) -> bool:
        return self.set_waypoints([*self.waypoints, (x, z)])

    def move_waypoint(self, index: int, x: float, z: float) -> bool:
        """Move waypoint ``index``; False (nothing changes) when there is no such waypoint
        any more (reached, or dropped for being under the creature)."""
        if not 0 <= index < len(self.waypoints):
            return False
        points = list(self.waypoints)
        points[index] = (x, z)
        return self.set_waypoints(points)

    def delete_waypoint(self, index: int) -> bool:
        if not 0 <= index < len(self.waypoints):
            return False
        return self.set_waypoints([p for i, p in enumerate(self.waypoints) if i != index])

    def nearest_waypoint(self, x: float, z: float, within: float) -> int | None:
        """The waypoint nearest (x, z) if within ``within`` m, else None."""
        if not self.waypoints:
            return None
        d = np.linalg.norm(np.array(self.waypoints) - np.array([x, z]), axis=1)
        i = int(d.argmin())
        return i if d[i] <= within else None


def turn_radius(rig) -> float:
    """The radius (m) a route to a waypoint turns at: enough for the body (a spline through
    the turn keeps about 0.6 of it, well over the tightest turn a path may ask) and for the
    stride (a planted foot must stay in reach of its hip while the body turns about it)."""
    from ..kinematics.motion import TIGHTEST_TURN

    return max(5.0 * TIGHTEST_TURN * rig.body_length, 1.6 * float(np.max(rig.stride_length)))
