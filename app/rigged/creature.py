"""A Gaitlab creature with a rigged model's proportions: the base preset for its kind
(a dog for four legs, a person for two) with the model's own leg segment lengths, girdle
spacing and hip width, and the rest of the body scaled with the legs. The creature's
motion then drives the model's skeleton (:mod:`.drive`)."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..spec import LEG_TYPE_SHAPES, SCALED_BODY_KEYS, CreatureSpec, LegType, creature_from_dict, leg_type, load_creature
from .gltf import RigError, RiggedModel
from .legs import ARM_WORDS, ModelLegs, chain_lengths, limbs, model_scale
from .loaded import load_model

BASE = {1: "human", 2: "dog"}  # leg pairs -> the preset a model's creature starts from


def creature_from_model(model: RiggedModel, legs: ModelLegs) -> tuple[CreatureSpec, float]:
    """The creature that moves like ``model`` would (see the module docstring), and the
    model's scale (metres per unit)."""
    pairs = len(legs.pairs)
    if pairs not in BASE:
        raise RigError(f"{model.path}: {pairs} pairs of legs found; models with one (a biped) or two (a "
                       "quadruped) are driven")
    scale = model_scale(model, legs)
    doc: dict[str, Any] = load_creature(BASE[pairs]).to_dict()
    doc["name"] = model.path.stem
    doc["description"] = f"the rigged model {model.path.name}, walking on its own legs (its bones' lengths are its own)"
    tables = list(doc["legs"])
    ratios = []
    own_toes = set()  # the tables whose toe is the model's own
    points = model.rest_points * scale
    mesh = model.rest_mesh() * scale
    sole = float(mesh[:, 1].min()) if len(mesh) else float(points[:, 1].min())
    for k, (left, right) in enumerate(legs.pairs):
        table = doc["legs"][tables[0] if k == 0 else tables[-1]]
        bones = 0.5 * (chain_lengths(model, left) + chain_lengths(model, right)) * scale
        femur, tibia = float(bones[0]), float(bones[1])
        if len(bones) >= 3:
            metatarsus = float(bones[2])
        else:  # the chain ends at the wrist (a fox's fore leg): the paw below it
            metatarsus = max(float(points[left.joints[-1], 1] - sole), 0.1 * (femur + tibia))
        old = table["femur"] + table["tibia"] + table["metatarsus"]
        ratios.append((femur + tibia + metatarsus) / old)
        table["femur"], table["tibia"], table["metatarsus"] = round(femur, 4), round(tibia, 4), round(metatarsus, 4)
        if len(bones) >= 4:
            table["toe"] = round(float(bones[3]), 4)
            own_toes.add(id(table))
        elif len(bones) == 3:  # the chain ends at the ball: the toes are the vertices it moves, ahead of it
            toe = _toes_ahead(model, mesh, points, left.joints[-1])
            if toe > 0.2 * metatarsus:
                table["toe"] = round(toe, 4)
                own_toes.add(id(table))
        if len(bones) >= 3:  # the leg's type from its foot: a heel on the ground is plantigrade
            kind = foot_kind(model, mesh, points, left.joints[2], sole, metatarsus)
            if (kind == "plantigrade") != (leg_type(float(table["ankle_lift"])) == "plantigrade"):
                lift, toe_ratio = LEG_TYPE_SHAPES[kind]
                table["ankle_lift"] = lift
                if id(table) not in own_toes:
                    table["toe"] = round(toe_ratio * metatarsus, 4)
                    own_toes.add(id(table))
        # The legs hang from the model's own hip (or shoulder) joints.
        table["hip_offset"] = round(0.5 * float(np.linalg.norm(points[left.joints[0]] - points[right.joints[0]])), 4)
    ratio = float(np.mean(ratios))
    body = doc["body"]
    for key in SCALED_BODY_KEYS:
        if isinstance(body.get(key), (int, float)):
            body[key] = round(body[key] * ratio, 4)
    body["radius"] = [round(r * ratio, 4) for r in body["radius"]]
    for table in doc["legs"].values():
        for key in ("toe", "heel", "radius"):
            if key in table and not (key == "toe" and id(table) in own_toes):
                table[key] = round(table[key] * ratio, 4)
    hind_left, hind_right = legs.pairs[-1]
    body["width"] = round(float(np.linalg.norm(points[hind_left.joints[0]] - points[hind_right.joints[0]])), 4)
    if pairs == 2:
        fore, hind = legs.pairs[0][0].joints[0], legs.pairs[-1][0].joints[0]
        body["length"] = round(float(abs(points[fore, 2] - points[hind, 2])), 4)
    else:  # a biped's trunk rises from its hips to its shoulders (the arms' tops), as tall as the model's
        arms = limbs(model, ARM_WORDS, ("upleg", "thigh", "foot", "toe", "shin", "calf"))
        if len(arms["L"]) == 1 and len(arms["R"]) == 1:
            shoulders = 0.5 * (points[arms["L"][0][0], 1] + points[arms["R"][0][0], 1])
            hips = 0.5 * (points[hind_left.joints[0], 1] + points[hind_right.joints[0], 1])
            if shoulders > hips:
                body["length"] = round(float(shoulders - hips), 4)
    # The model's trunk moves as one piece (its spine joints are carried, not bent): the
    # creature's hips and shoulders do not turn, tilt or flex against each other.
    motion = doc.setdefault("motion", {})
    motion["yaw"], motion["pelvis_tilt"], motion["spine_flex"] = 0, 0, 0
    if "arms" in doc:
        for key in ("upper", "fore", "hand", "shoulder_width", "radius"):
            if isinstance(doc["arms"].get(key), (int, float)):
                doc["arms"][key] = round(doc["arms"][key] * ratio, 4)
        if legs.arms:  # the model's own upper arm and forearm, and its shoulders' width
            bones = 0.5 * (chain_lengths(model, legs.arms[0]) + chain_lengths(model, legs.arms[1])) * scale
            doc["arms"]["upper"], doc["arms"]["fore"] = round(float(bones[0]), 4), round(float(bones[1]), 4)
            tops = points[[legs.arms[0].joints[0], legs.arms[1].joints[0]]]
            doc["arms"]["shoulder_width"] = round(float(np.linalg.norm(tops[0] - tops[1])), 4)
    return creature_from_dict(doc, source=str(model.path)), scale


def _owned(model: RiggedModel, mesh: np.ndarray, joint: int) -> np.ndarray:
    """Which vertices (V,) ``joint`` moves most (its heaviest weight; none when the mesh
    and weights do not match)."""
    if len(model.joints) != len(mesh) or not len(mesh):
        return np.zeros(len(mesh), dtype=bool)
    return model.joints[np.arange(len(mesh)), np.argmax(model.weights, axis=1)] == joint


HEEL_DOWN = 0.15  # of the metatarsus: an ankle whose own vertices come this near the sole stands on its heel


def foot_kind(model: RiggedModel, mesh: np.ndarray, points: np.ndarray, ankle: int, sole: float,
              metatarsus: float) -> LegType:
    """Whether a leg stands on its heel (plantigrade: the vertices its ankle moves most
    reach down to the sole behind it, as a person's heel) or on its toes (digitigrade:
    they stay well above it, as a fox's hock). ``mesh`` (V, 3) and ``points`` (J, 3) in
    the rest pose, in the same units as ``sole`` and ``metatarsus``."""
    # Only the vertices behind the ankle count: a digitigrade ankle can own the whole
    # metatarsus down to the pads, but they lie ahead of it.
    behind = _owned(model, mesh, ankle) & (mesh[:, 2] <= points[ankle, 2])
    if not np.any(behind):
        return "digitigrade"
    return "plantigrade" if float(mesh[behind, 1].min()) - sole <= HEEL_DOWN * metatarsus else "digitigrade"


def _toes_ahead(model: RiggedModel, mesh: np.ndarray, points: np.ndarray, joint: int) -> float:
    """How far (m) the vertices that follow ``joint`` most reach ahead of it (+z) in the
    rest pose: the length of the toes a ball joint carries (0 when none follow it)."""
    own = _owned(model, mesh, joint)
    if not np.any(own):
        return 0.0
    return max(float(mesh[own, 2].max() - points[joint, 2]), 0.0)


def model_creature(path: str) -> CreatureSpec:
    """The creature that drives the model at ``path`` (its source is the model's path, so
    its rig draws the model)."""
    loaded = load_model(path)
    return creature_from_model(loaded.model, loaded.legs)[0]
