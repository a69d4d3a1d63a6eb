"""Finding a rigged model's legs: pairs of joint chains, left and right, from the hip (or
shoulder) down to the last joint of the foot, front pair first.

Names first, in the common conventions: Mixamo (``mixamorig:LeftUpLeg``, with any
``mixamorigN:`` or other namespace), Blender (``thigh.L``, ``shin.R``), ``Left``/``Right``,
``L_``/``_R``/``.l`` with Thigh, UpLeg, Leg, Shin, Calf, Foot, Toe, and numbered chains
(``b_LeftLeg01``, ``leg_joint_L_1``), 3ds Max Biped (``Bip01 L Thigh``) and ASF
(``lfemur``). A chain starts at the highest joint of its side
named for the leg and runs down its children to the end. Arms become the front legs when
their hands reach down near the ground at rest (a quadruped's fore legs); a biped's arms
stay arms. Failing names, by the skeleton's shape (:func:`legs_by_shape`): mirrored
chains that branch off the trunk and run down to the ground. A model whose legs cannot be
found is a one-line :class:`RigError` naming the joints it has.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from .gltf import RigError, RiggedModel

LEG_WORDS = ("upleg", "upperleg", "thigh", "femur", "leg", "shin", "calf", "tibia", "knee", "foot", "ankle", "toe",
             "ball", "hip")
ARM_WORDS = ("upperarm", "uparm", "arm", "humerus", "forearm", "radius", "elbow", "hand", "wrist", "finger",
             "shoulder", "clavicle")
NECK_WORDS, HEAD_WORDS, TAIL_WORDS = ("neck",), ("head",), ("tail",)
NEAR_GROUND = 0.25  # a hand within this fraction of the hip height of the ground makes the arm a leg
CENTIMETRES = 5.0  # a model whose hips stand higher than this (in its units) is taken to be in centimetres


@dataclass(frozen=True)
class LegChain:
    """One leg: its side ("L" or "R") and its joints (indices into the model's joints),
    from the top of the leg down to the end of the foot."""

    side: str
    joints: tuple[int, ...]


@dataclass(frozen=True)
class ModelLegs:
    """A model's leg pairs, front first (each pair left, right), whether its arms are its
    front legs, a biped's arms (left, right: upper arm, forearm and wrist joints; empty
    when it has none it can name, or they are legs), and its neck and tail chains (they
    turn as the creature's do)."""

    pairs: tuple[tuple[LegChain, LegChain], ...]
    arms_as_legs: bool
    arms: tuple[LegChain, ...] = ()
    neck: tuple[int, ...] = ()  # joints from the neck's base to the head (the last), or none
    tail: tuple[int, ...] = ()  # joints from the tail's base to its tip, or none

    @property
    def chains(self) -> tuple[LegChain, ...]:
        return tuple(chain for pair in self.pairs for chain in pair)


def _words(name: str) -> tuple[str, str | None, str]:
    """A joint name as (lower-case words joined by spaces, side "L"/"R"/None, the words
    without the side): namespaces dropped, camel case and digits split."""
    base = name.rsplit(":", 1)[-1]
    base = re.sub(r"([a-z])([A-Z])", r"\1 \2", base)
    base = re.sub(r"([A-Za-z])(\d)", r"\1 \2", base)
    tokens = [t for t in re.split(r"[\s_.\-|]+", base.lower()) if t]
    side = None
    rest = []
    for t in tokens:
        if t in ("l", "left", "lft") and side is None:
            side = "L"
        elif t in ("r", "right", "rt", "rgt") and side is None:
            side = "R"
        elif t.startswith("left") and side is None:
            side, t = "L", t[4:]
            if t:
                rest.append(t)
        elif t.startswith("right") and side is None:
            side, t = "R", t[5:]
            if t:
                rest.append(t)
        else:
            rest.append(t)
    if side is None and tokens:  # lthigh, rfoot (ASF-style): a single-letter prefix on a limb word
        first = tokens[0]
        for words in (LEG_WORDS, ARM_WORDS):
            for word in words:
                if first in ("l" + word, "r" + word):
                    side = first[0].upper()
                    rest = [word, *tokens[1:]]
    return " ".join(rest), side, " ".join(tokens)


def _has(words: str, vocabulary: tuple[str, ...]) -> bool:
    return any(w in vocabulary or any(w.startswith(v) for v in vocabulary) for w in words.split())


def _chain_from(model: RiggedModel, top: int) -> tuple[int, ...]:
    """``top`` and its descendants straight down: at each joint the child whose subtree
    reaches lowest (a foot before a stray twist bone)."""
    children: dict[int, list[int]] = {}
    for j, p in enumerate(model.parents):
        children.setdefault(int(p), []).append(j)
    points = model.rest_points

    def lowest(j: int) -> float:
        stack, low = [j], np.inf
        while stack:
            k = stack.pop()
            low = min(low, float(points[k, 1]))
            stack.extend(children.get(k, []))
        return low

    chain = [top]
    while children.get(chain[-1]):
        chain.append(min(children[chain[-1]], key=lowest))
    return tuple(chain)


def limbs(model: RiggedModel, vocabulary: tuple[str, ...], avoid: tuple[str, ...]) -> dict[str, list[tuple[int, ...]]]:
    """Chains per side whose top joint is named for the limb (``vocabulary``, not
    ``avoid``) and whose parent is not."""
    named = {}
    for j, name in enumerate(model.names):
        words, side, _ = _words(name)
        if side is not None and _has(words, vocabulary) and not _has(words, avoid):
            named[j] = side
    tops: dict[str, list[tuple[int, ...]]] = {"L": [], "R": []}
    for j, side in named.items():
        parent = int(model.parents[j])
        if parent in named and named[parent] == side:
            continue
        chain = _chain_from(model, j)
        if len(chain) >= 3:
            tops[side].append(chain)
    return tops


def appendage(model: RiggedModel, words: tuple[str, ...], end: tuple[str, ...] = ()) -> tuple[int, ...]:
    """The chain of joints named for ``words`` (no side: ``b_Tail01``, ``neck_1``), from
    the highest whose parent is not, down through children named for ``words`` and then
    at most one named for ``end`` (a neck's head; without one, the neck's last joint turns
    as the head does); empty unless it has a bone."""
    def named(j: int, vocabulary: tuple[str, ...]) -> bool:
        text, side, _ = _words(model.names[j])
        return side is None and _has(text, vocabulary)

    children: dict[int, list[int]] = {}
    for j, p in enumerate(model.parents):
        children.setdefault(int(p), []).append(j)
    tops = [j for j in range(len(model.names)) if named(j, words) and not (
        model.parents[j] >= 0 and named(int(model.parents[j]), words))]
    if not tops:
        return ()
    chain = [min(tops, key=lambda j: _depth(model.parents, j))]
    while True:
        more = [c for c in children.get(chain[-1], []) if named(c, words)]
        if not more:
            break
        chain.append(more[0])
    head = [c for c in children.get(chain[-1], []) if end and named(c, end)]
    chain += head[:1]
    return tuple(chain) if len(chain) >= 2 else ()


def find_legs(model: RiggedModel) -> ModelLegs:
    """The model's legs by their joints' names (see the module docstring), and its neck
    and tail (:func:`appendage`)."""
    legs = limbs(model, LEG_WORDS, ARM_WORDS)
    arms = limbs(model, ARM_WORDS, ("upleg", "thigh", "foot", "toe", "shin", "calf"))
    if len(legs["L"]) != len(legs["R"]) or not legs["L"]:
        by_shape = legs_by_shape(model)
        if by_shape is not None:
            return by_shape
        found = ", ".join(model.names[:40]) + (" ..." if len(model.names) > 40 else "")
        raise RigError(f"{model.path}: no left and right legs found among its joints ({found}), by their names or "
                       "by their shape; name each leg's joints for its side and part, e.g. LeftUpLeg/RightUpLeg, "
                       "thigh.L/thigh.R or L_Thigh/R_Thigh, or list them in a map file (--rig)")
    points = model.rest_points
    pairs = []
    for left, right in zip(sorted(legs["L"], key=lambda c: -points[c[0], 2]),
                           sorted(legs["R"], key=lambda c: -points[c[0], 2])):
        pairs.append((LegChain("L", left), LegChain("R", right)))
    hip_height = float(np.mean([points[left.joints[0], 1] - points[left.joints[-1], 1] for left, _ in pairs]))
    ground = float(min(points[c.joints[-1], 1] for pair in pairs for c in pair))
    arms_as_legs = False
    in_legs = {j for side in ("L", "R") for chain in legs[side] for j in chain}
    arms = {side: [c for c in arms[side] if not in_legs & set(c)] for side in ("L", "R")}  # FrontLeg under Shoulder
    if len(arms["L"]) == 1 and len(arms["R"]) == 1:
        hands = [points[arms[s][0][-1], 1] - ground for s in ("L", "R")]
        if max(hands) < NEAR_GROUND * hip_height:
            arms_as_legs = True
            pairs.insert(0, (LegChain("L", arms["L"][0]), LegChain("R", arms["R"][0])))
    pairs.sort(key=lambda pair: -float(points[pair[0].joints[0], 2]))  # front first (+z forward)
    biped_arms: tuple[LegChain, ...] = ()
    if len(pairs) == 1 and len(arms["L"]) == 1 and len(arms["R"]) == 1:
        biped_arms = tuple(LegChain(s, _upper_arm_down(points, arms[s][0])) for s in ("L", "R"))
        if any(len(c.joints) < 3 for c in biped_arms):
            biped_arms = ()
    return ModelLegs(pairs=tuple(pairs), arms_as_legs=arms_as_legs, arms=biped_arms,
                     neck=appendage(model, NECK_WORDS, HEAD_WORDS), tail=appendage(model, TAIL_WORDS))


def _upper_arm_down(points: NDArray[np.float64], chain: tuple[int, ...]) -> tuple[int, ...]:
    """An arm chain's upper arm, forearm and wrist: a collarbone first (a bone much shorter
    than the next) is left to the trunk; the hand's joints below the wrist follow it."""
    bones = np.linalg.norm(np.diff(points[list(chain)], axis=0), axis=1)
    start = 1 if len(chain) >= 4 and bones[0] < 0.5 * bones[1] else 0
    return chain[start:start + 3]


SHAPE_GROUND = 0.15  # by shape: a leg's lowest joint within this fraction of the model's height of the ground
SHAPE_SIDE = 0.02  # ... its top this far (of the height) to a side of the middle
SHAPE_MIRROR = 0.05  # ... and its pair's top where the mirror puts it, within this much


def legs_by_shape(model: RiggedModel) -> ModelLegs | None:
    """Legs found by the skeleton's shape when their names say nothing: chains that
    branch off the trunk to one side (+x is left) and run down to the ground, in mirrored
    pairs (each pair's tops where a mirror across the middle puts them), front pair first;
    None unless one or two pairs are found and nothing else reaches the ground off the
    middle."""
    points = model.rest_points
    if len(points) < 7:
        return None
    children: dict[int, list[int]] = {}
    for j, p in enumerate(model.parents):
        children.setdefault(int(p), []).append(j)
    ground = float(points[:, 1].min())
    height = float(points[:, 1].max()) - ground
    if height <= 0:
        return None
    lowest = points[:, 1].copy()
    for j in sorted(range(len(points)), key=lambda k: -_depth(model.parents, k)):  # children before parents
        p = int(model.parents[j])
        if p >= 0:
            lowest[p] = min(lowest[p], lowest[j])
    tops = [c for branch, kids in children.items() if branch >= 0 and len(kids) >= 2 for c in kids
            if lowest[c] - ground < SHAPE_GROUND * height and abs(points[c, 0]) > SHAPE_SIDE * height]
    tops = [t for t in tops if not any(_below(model.parents, t, other) for other in tops if other != t)]
    left = [t for t in tops if points[t, 0] > 0]
    right = [t for t in tops if points[t, 0] < 0]
    if len(left) != len(right) or len(left) not in (1, 2):
        return None
    pairs = []
    for top in sorted(left, key=lambda t: -points[t, 2]):
        mirror = points[top] * np.array([-1.0, 1.0, 1.0])
        partner = min(right, key=lambda t: float(np.linalg.norm(points[t] - mirror)))
        if np.linalg.norm(points[partner] - mirror) > SHAPE_MIRROR * height:
            return None
        right.remove(partner)
        chains = _chain_from(model, top), _chain_from(model, partner)
        if min(len(c) for c in chains) < 3:
            return None
        pairs.append((LegChain("L", chains[0]), LegChain("R", chains[1])))
    return ModelLegs(pairs=tuple(pairs), arms_as_legs=False)


def _depth(parents: NDArray[np.int64], j: int) -> int:
    depth = 0
    while parents[j] >= 0:
        j, depth = int(parents[j]), depth + 1
    return depth


def _below(parents: NDArray[np.int64], j: int, top: int) -> bool:
    """Whether joint ``j`` hangs somewhere under ``top``."""
    j = int(parents[j])
    while j >= 0:
        if j == top:
            return True
        j = int(parents[j])
    return False


def chain_lengths(model: RiggedModel, chain: LegChain) -> NDArray[np.float64]:
    """Lengths of a chain's bones at rest (len(joints) - 1,), in the model's units."""
    points = model.rest_points[list(chain.joints)]
    return np.linalg.norm(np.diff(points, axis=0), axis=1)


def model_scale(model: RiggedModel, legs: ModelLegs) -> float:
    """Metres per model unit: glTF is metres, but many exports are in centimetres (hips
    tens of units up)."""
    points = model.rest_points
    hip = float(np.mean([points[c.joints[0], 1] - points[c.joints[-1], 1] for c in legs.chains]))
    return 0.01 if hip > CENTIMETRES else 1.0


def legs_from_map(model: RiggedModel, mapping: dict, where: str) -> ModelLegs:
    """The legs a mapping file names (``[legs]``: a list of joint names per leg, from the
    top of the leg down, front pair first, each pair left then right: keys starting L and
    R). Every mistake is one line naming ``where`` and the key."""
    table = mapping.get("legs")
    if not isinstance(table, dict) or not table:
        raise RigError(f"{where}: give a [legs] table, e.g. LH = [\"thigh.L\", \"shin.L\", \"foot.L\"], one list of "
                       "joint names per leg")
    unknown = sorted(set(mapping) - {"legs", "arms", "neck", "tail"})
    if unknown:
        raise RigError(f"{where}: unknown table {unknown[0]!r}; a rig map has [legs], for a biped [arms], and "
                       "[neck] and [tail]")
    chains = _mapped_chains(model, table, "legs", 3, "from the hip down to the foot", where)
    if len(chains) % 2 or any(a.side != "L" or b.side != "R" for a, b in zip(chains[::2], chains[1::2])):
        raise RigError(f"{where}: [legs] lists legs in pairs, left then right (LF, RF, LH, RH), front pair first")
    if len(chains) // 2 not in (1, 2):
        raise RigError(f"{where}: {len(chains)} legs; a biped (2) or a quadruped (4) is driven")
    pairs = tuple((chains[k], chains[k + 1]) for k in range(0, len(chains), 2))
    keys = list(table)
    for k, (left, right) in enumerate(pairs):
        _left_is_left(model, left, right, f"legs.{keys[2 * k]}", f"legs.{keys[2 * k + 1]}", where)
    arms: tuple[LegChain, ...] = ()
    if "arms" in mapping:
        if not isinstance(mapping["arms"], dict) or len(pairs) != 1:
            raise RigError(f"{where}: [arms] is for a biped: L and R, each [\"upper arm\", \"forearm\", \"wrist\"]")
        arms = tuple(_mapped_chains(model, mapping["arms"], "arms", 3, "upper arm, forearm and wrist", where, exact=True))
        if [a.side for a in arms] != ["L", "R"]:
            raise RigError(f"{where}: [arms] lists the left arm (L) then the right (R)")
        _left_is_left(model, arms[0], arms[1], "arms.L", "arms.R", where)
    neck, tail = (_mapped_appendage(model, mapping, part, where) for part in ("neck", "tail"))
    owner: dict[int, str] = {}  # each joint in one chain only (a leg listed twice was a baffling body size)
    labelled = [(f"legs.{key}", c.joints) for key, c in zip(table, chains)]
    labelled += [(f"arms.{key}", c.joints) for key, c in zip(mapping.get("arms", {}), arms)]
    labelled += [(f"{part}.joints", joints) for part, joints in (("neck", neck), ("tail", tail))]
    for label, joints in labelled:
        for j in joints:
            if j in owner:
                raise RigError(f"{where}: joint {model.names[j]!r} is in both {owner[j]} and {label}; each joint "
                               "belongs to one leg, arm, neck or tail")
            owner[j] = label
    return ModelLegs(pairs=pairs, arms_as_legs=False, arms=arms, neck=neck, tail=tail)


def _left_is_left(model: RiggedModel, left: LegChain, right: LegChain, left_key: str, right_key: str,
                  where: str) -> None:
    """Refuse a pair whose left chain stands on the model's right (+x is a model's left as
    it faces +z at rest, as glTF models do): driven, the legs would cross under the body."""
    x = model.rest_points[:, 0]
    left_x, right_x = float(np.mean(x[list(left.joints)])), float(np.mean(x[list(right.joints)]))
    if left_x < right_x:
        raise RigError(f"{where}: {left_key} ({model.names[left.joints[0]]!r}) is on the model's right and "
                       f"{right_key} ({model.names[right.joints[0]]!r}) on its left (+x is a model's left as it "
                       f"faces +z); swap their joint lists")


def _mapped_appendage(model: RiggedModel, mapping: dict, part: str, where: str) -> tuple[int, ...]:
    """The neck's or tail's joints a map names (``[neck] joints = [base, ..., head]``,
    ``[tail] joints = [base, ..., tip]``), each under the one before; none without it."""
    if part not in mapping:
        return ()
    table = mapping[part]
    what = "from its base to the head" if part == "neck" else "from its base to the tip"
    if not isinstance(table, dict) or set(table) != {"joints"}:
        raise RigError(f"{where}: [{part}] has one key, joints = [two or more joint names {what}]")
    return _named_chain(model, table["joints"], f"{part}.joints", 2, what, where)


def _mapped_chains(model: RiggedModel, table: dict, kind: str, least: int, order: str, where: str,
                   exact: bool = False) -> list[LegChain]:
    """The chains a map's table names (key: side first, L or R; value: joint names, each
    under the one before), in the table's order. Every mistake is one line."""
    chains: list[LegChain] = []
    for key, names in table.items():
        side = str(key)[:1].upper()
        if side not in ("L", "R"):
            raise RigError(f"{where}: {kind}.{key}: a key starts with L or R (its side), e.g. LF, RF, LH, RH")
        chains.append(LegChain(side, _named_chain(model, names, f"{kind}.{key}", least, order, where, exact)))
    return chains


def _named_chain(model: RiggedModel, names: object, label: str, least: int, order: str, where: str,
                 exact: bool = False) -> tuple[int, ...]:
    """The joints ``names`` lists (``label`` says where in the map), each under the one
    before. Every mistake is one line."""
    index = {name: j for j, name in enumerate(model.names)}
    count_ok = isinstance(names, list) and (len(names) == least if exact else len(names) >= least)
    if not isinstance(names, list) or not count_ok or not all(isinstance(n, str) for n in names):
        many = f"{least}" if exact else f"{least} or more"
        raise RigError(f"{where}: {label}: give {many} joint names: {order}")
    missing = [n for n in names if n not in index]
    if missing:
        shown = ", ".join(model.names[:30]) + (" ..." if len(model.names) > 30 else "")
        raise RigError(f"{where}: {label} names {missing[0]!r}, which {model.path.name} has not; its joints: "
                       f"{shown}")
    joints = tuple(index[n] for n in names)
    for upper, lower in zip(joints, joints[1:]):
        j = int(model.parents[lower])
        while j >= 0 and j != upper:
            j = int(model.parents[j])
        if j != upper:
            raise RigError(f"{where}: {label}: {model.names[lower]!r} does not hang below "
                           f"{model.names[upper]!r}; list each chain's joints from the top down")
    return joints
