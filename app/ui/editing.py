"""Editing the selected creature: every control's value, changes checked as a creature
file is, undo and redo, the gait and leg type controls."""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from ..errors import GaitlabError
from ..gaits import GAIT_PRESETS
from ..kinematics.walker import SWING_KNEE
from ..rigging import apply_style, build_rig
from ..spec import LEG_TYPE_SHAPES, CreatureSpec, GaitSpec, LegType, leg_type, override_keys, spec_value, without_adjustment
from ..styles import DEFAULT_TIMING_FPS, style_heights
from .base import StateBase

UNDO_DEPTH = 200  # edits kept for undo
UNDO_MERGE_SECONDS = 0.75  # changes of one control closer together than this are one edit (arrow keys,
# a drag at any frame rate is one edit by itself: see drag_held)

# Gait keys whose value, when not set in the file, comes from the gait preset: the UI shows
# the resolved number.
_RESOLVED = {"gait.frequency", "gait.duty_factor", "gait.bias", "gait.step_height", "gait.stride",
             "gait.front_back", "gait.left_right", "motion.bob"}


def changed_keys(before: CreatureSpec, after: CreatureSpec, most: int = 3) -> str:
    """What differs between two creatures, for a message: up to ``most`` dotted keys with
    their new values ("gait.duty_factor 0.6"), then how many more; a creature of other legs
    or another name says so."""
    if [leg.name for leg in before.legs] != [leg.name for leg in after.legs] or before.name != after.name:
        return f"the creature ({before.name} -> {after.name})"
    def differs(key: str) -> bool:
        try:
            return bool(spec_value(before, key) != spec_value(after, key))
        except (KeyError, AttributeError):  # a key this creature does not have
            return False

    keys = [k for k in override_keys(after) if "." in k and differs(k)]
    if not keys:
        return "no visible change"

    def shown(value: Any) -> str:
        if value is None:  # a key left to the preset (or style) again
            return "back to the preset's"
        return f"{value:.4g}" if isinstance(value, float) else str(value)

    words = [f"{k} {shown(spec_value(after, k))}" for k in keys[:most]]
    return ", ".join(words) + (f" and {len(keys) - most} more" if len(keys) > most else "")


class EditingMixin(StateBase):
    """Reading and changing the selected creature's keys, with undo."""

    def get(self, key: str) -> Any:
        """The value a control shows: the file's value, or the number the gait preset
        gives when the file leaves it open (e.g. the duty factor of a preset gait)."""
        gait = self.live.rig.gait
        if key.startswith("poses.") or key == "gait.frames_per_cycle":
            value = spec_value(self.spec, key)
            return value if value is not None else self._resolved_pose(key)
        if key in _RESOLVED or key.startswith("gait.phases."):
            if key.startswith("gait.phases."):
                return float(gait.offsets[self.live.rig.leg_names.index(key.rsplit(".", 1)[1])])
            if key in ("gait.front_back", "gait.left_right"):
                value = spec_value(self.spec, key)
                if value is not None:
                    return value
                preset = self.spec.gait.preset_spec
                return getattr(preset, key.split(".")[1]) if preset.symmetric else 0.0
            return {"gait.frequency": gait.frequency, "gait.duty_factor": gait.duty_factor, "gait.bias": gait.bias,
                    "gait.step_height": gait.step_height, "gait.stride": gait.stride, "motion.bob": gait.bob}[key]
        return spec_value(self.spec, key)

    def _resolved_pose(self, key: str) -> Any:
        """A key pose value the file leaves open: as the creature walks it; a height of a
        creature whose bob is not keyed shows the normal style's (where editing starts)."""
        rig = self.live.rig
        poses = rig.poses
        if key == "gait.frames_per_cycle":
            return (self.spec.gait.timing_fps or DEFAULT_TIMING_FPS) / rig.gait.frequency
        if key == "poses.style":
            return "normal"
        names = ("contact_height", "down_height", "pass_height", "up_height")
        name = key.split(".", 1)[1]
        if name in names:
            heights = poses.heights if poses.heights is not None else style_heights("normal", rig.hip_height)
            return float(heights[names.index(name)])
        if name == "swing_knee":
            return SWING_KNEE if poses.swing_knee is None else float(np.degrees(poses.swing_knee))
        return float(np.degrees({"foot_angle": poses.foot_angle, "arm_swing": poses.arm_swing,
                                 "torso_lean": poses.torso_lean}[name]))

    @property
    def style_edited(self) -> bool:
        """Whether the key poses differ from their style's values (the button shows a *)."""
        style = self.spec.poses.style
        if style is None:
            return False
        cached = self._style_check
        if cached is None or cached[0] is not self.spec:
            try:
                mine, styled = build_rig(self.spec), build_rig(apply_style(self.spec, style))
                a, b = mine.poses, styled.poses
                edited = (a.heights is None or b.heights is None or not np.allclose(a.heights, b.heights, atol=1e-4)
                          or not np.allclose([a.foot_angle, a.arm_swing, a.torso_lean, mine.gait.stride],
                                             [b.foot_angle, b.arm_swing, b.torso_lean, styled.gait.stride], atol=1e-4))
            except GaitlabError:
                edited = True
            cached = self._style_check = (self.spec, edited)
        return cached[1]

    def set_style(self, name: str) -> bool:
        """Start the key poses from a walk style (its heights, angles and stride)."""
        try:
            spec = apply_style(self.spec, name)
        except GaitlabError as exc:
            self.error = str(exc)
            return False
        return self._apply(spec, edit="style")

    def base_value(self, key: str) -> Any:
        return spec_value(self.base, key)

    def is_modified(self, key: str) -> bool:
        """True when ``key`` differs from the loaded creature (the reset button is live)."""
        return spec_value(self.spec, key) != spec_value(self.base, key)

    @property
    def creature_label(self) -> str:
        """The creature's name, with a * once it differs from the loaded one."""
        return self.spec.name + ("*" if self.spec != self.base else "")

    @property
    def gait_label(self) -> str:
        """The gait preset's name, with a * once any of its values is adjusted: against the
        loaded creature's own gait while it is that preset (a file that tunes its walk
        shows it as loaded, not as edited), against the preset's defaults otherwise."""
        gait, loaded = self.spec.gait, self.base.gait
        untouched = loaded if loaded.preset == gait.preset else GaitSpec(preset=gait.preset, wave=gait.wave)
        return gait.preset + ("*" if gait != untouched else "")

    @property
    def gait_is_symmetric(self) -> bool:
        return self.spec.gait.preset_spec.symmetric and self.spec.gait.phases is None

    def _apply(self, spec: CreatureSpec, blend: bool = True, edit: str | None = "") -> bool:
        """Walk with ``spec`` from now on; a creature the world cannot take (a path too tight
        for it) keeps the current one and shows why. ``edit`` names the change for undo
        (consecutive changes of one slider within a moment are one step); ``None`` for
        changes that are not edits (undo itself, loading)."""
        previous = self.spec
        try:
            rig = build_rig(spec)
            if self.driver is not None:  # the speed picks the gait; the rest of the creature applies
                self.driver.set_rig(rig)
            else:
                self.live.set_rig(rig, blend=blend)
            if self.herd is not None:
                self.herd.set_rig(rig)
        except GaitlabError as exc:
            self.error = str(exc)
            return False
        self.spec = spec
        self.error = None
        if edit is not None and spec != previous:
            now = time.monotonic()
            same_drag = edit and edit == self._last_edit[0] and (now - self._last_edit[1] < UNDO_MERGE_SECONDS
                                                                 or self.drag_held)
            if not same_drag:
                self._undo.append(previous)
                del self._undo[:-UNDO_DEPTH]
            self._redo.clear()
            self._last_edit = (edit, now)
        return True

    def undo(self) -> bool:
        """Take back the last edit (Ctrl+Z)."""
        return self._travel_history(self._undo, self._redo, "undo")

    def redo(self) -> bool:
        """Make an undone edit again (Ctrl+Y or Ctrl+Shift+Z)."""
        return self._travel_history(self._redo, self._undo, "redo")

    def _travel_history(self, source: list[CreatureSpec], target: list[CreatureSpec], word: str) -> bool:
        """Go to the newest creature of ``source``, keeping the current one on ``target``."""
        if not source:
            self.status = f"nothing to {word}"
            return False
        spec, current = source.pop(), self.spec
        if not self._apply(spec, edit=None):
            source.append(spec)
            return False
        target.append(current)
        self._last_edit = ("", 0.0)
        self.status = f"{word}ne: {changed_keys(current, spec)}"
        return True

    def set(self, key: str, value: Any) -> bool:
        """Set a creature key; on a rejected value keep the creature and show why."""
        return self.set_many({key: value})

    def set_many(self, overrides: dict[str, Any]) -> bool:
        try:
            spec = self.spec.with_overrides(overrides, origin="")
        except GaitlabError as exc:
            self.error = str(exc)
            return False
        return self._apply(spec, edit=",".join(sorted(overrides)))

    def reset(self, key: str) -> bool:
        """Give ``key`` its value from the loaded creature."""
        value = self.base_value(key)
        if value is not None:
            return self.set(key, value)
        try:
            spec = without_adjustment(self.spec, key)
        except GaitlabError as exc:
            self.error = str(exc)
            return False
        return self._apply(spec)

    def reset_all(self, confirmed: bool = False) -> bool:
        """Back to the loaded creature, blending the gait. Every change is lost, so the
        first call only asks (the button then reads "really reset"); a second call, or
        ``confirmed``, resets."""
        if not confirmed and not self.reset_pending:
            self.reset_pending = True
            self._asked_at = time.monotonic()
            self.error = "reset every change to the loaded creature? press reset again to do it"
            return False
        self.reset_pending = False
        return self._apply(self.base)

    def set_gait(self, name: str) -> bool:
        """Switch gait preset (its adjustments reset to the new preset's values)."""
        if name not in GAIT_PRESETS:
            self.error = f"unknown gait {name!r}"
            return False
        return self.set("gait.preset", name)

    def set_duty(self, duty: float) -> bool:
        """Set the duty factor; the bias b shown beside it follows (closed form)."""
        return self.set("gait.duty_factor", float(duty))

    def set_bias(self, bias: float) -> bool:
        """Set the seed's swing/stance bias b; the duty factor follows (closed form)."""
        return self.set("gait.bias", float(bias))

    def set_leg_type(self, pair: str, kind: LegType) -> bool:
        """Make a leg pair plantigrade, digitigrade or unguligrade: the loaded creature's
        own ankle lift and toe when it is of that type (the dog's 72 degrees, not a typical
        62), otherwise typical ones (both stay editable; a rigged model keeps its toes)."""
        own = self.base.leg(pair) if pair in {leg.name for leg in self.base.legs} else None
        if own is not None and leg_type(own.ankle_lift) == kind:
            change = {f"legs.{pair}.ankle_lift": own.ankle_lift, f"legs.{pair}.toe": own.toe}
        else:
            lift, toe_ratio = LEG_TYPE_SHAPES[kind]
            meta = self.spec.leg(pair).metatarsus
            change = {f"legs.{pair}.ankle_lift": lift, f"legs.{pair}.toe": round(meta * toe_ratio, 4)}
        if self.bones_from_model:  # a rigged model's toes are its own: only the ankle lift changes
            change.pop(f"legs.{pair}.toe")
        return self.set_many(change)

    @property
    def bones_from_model(self) -> bool:
        """Whether the creature is a rigged model's, whose bone lengths and girdle spacing
        are the model's own (the viewer greys their sliders: the model's skeleton cannot
        stretch to other lengths)."""
        from ..rigged import is_model_path

        return is_model_path(self.spec.source)

    def leg_type(self, pair: str) -> LegType:
        return leg_type(self.spec.leg(pair).ankle_lift)

    @property
    def creature_description(self) -> str:
        """The creature's one-line description, with what no longer holds of it said: a
        leg pair made another type than the loaded creature's ("fore legs now
        unguligrade")."""
        text = self.spec.description or self.spec.source
        loaded = {leg.name: leg_type(leg.ankle_lift) for leg in self.base.legs}
        changed = [f"{leg.name} legs now {leg_type(leg.ankle_lift)}" for leg in self.spec.legs
                   if leg.name in loaded and leg_type(leg.ankle_lift) != loaded[leg.name]]
        return text + (f" (edited: {', '.join(changed)})" if changed else "")
