"""A rigged model ready to drive: read once while its file is unchanged, its legs found,
its scale known, its mesh skinned to the rest pose in metres; and its skinning matrices
for a creature's motion. The renderer draws the mesh with them."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property, lru_cache
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from ..errors import not_a_file
from ..kinematics.appendages import Appendages
from .drive import drive_joints, rest_in_metres
from .gltf import RigError, RiggedModel, load_rigged_model
from .legs import ModelLegs, find_legs, legs_from_map, model_scale


@dataclass(frozen=True)
class LoadedModel:
    """A model, its legs, its scale (metres per unit) and its mesh in the rest pose in
    metres: ``mesh`` (V, 3), ``normals`` (V, 3), ``colors`` (V, 3, display RGB) and the
    rest transforms ``bind`` (J, 4, 4, metres) the skinning matrices are relative to."""

    model: RiggedModel
    legs: ModelLegs
    scale: float
    mesh: NDArray[np.float64]
    normals: NDArray[np.float64]
    bind: NDArray[np.float64]
    clearance: NDArray[np.float64]  # (L,) m each leg's last joint stands above the sole (0: a wrist, the paw below)

    def skin(self, leg_joints: NDArray[np.float64], root: NDArray[np.float64],
             foot_angle: NDArray[np.float64] | None = None,
             arms: NDArray[np.float64] | None = None, turns: Appendages | None = None) -> NDArray[np.float32]:
        """Skinning matrices (T, J, 4, 4) for the creature's leg joints (T, L, 5, 3), body
        transforms (T, 4, 4), flat-foot angles (L,) rad, arms (T, A, 4, 3) and neck, head
        and tail turns (see :func:`drive_joints`)."""
        world = drive_joints(self.model, self.legs, self.scale, leg_joints, root, self.clearance, foot_angle, arms,
                             turns)
        return (world @ self.inverse_bind).astype(np.float32)

    @cached_property
    def inverse_bind(self) -> NDArray[np.float64]:
        """The rest transforms' inverses (J, 4, 4)."""
        return np.asarray(np.linalg.inv(self.bind), dtype=np.float64)


_RIG_MAPS: dict[str, str] = {}  # model path (resolved) -> the --rig map file that names its legs


def use_rig_map(model_path: str, map_path: str) -> None:
    """Name the legs of the model at ``model_path`` with the map file at ``map_path`` (for
    this process: the command line's --rig; "" for none: the joint names decide), checked
    at once."""
    key = str(Path(model_path).resolve())
    if map_path:
        _RIG_MAPS[key] = map_path
    else:
        _RIG_MAPS.pop(key, None)
    load_model(model_path)


@lru_cache(maxsize=8)
def _load(path: str, stamp: float, rig_map: str, map_stamp: float) -> LoadedModel:
    import trimesh

    model = load_rigged_model(path)
    if rig_map:
        from ..tomlfile import TomlProblem, read_toml

        try:
            mapping = read_toml(rig_map)
        except TomlProblem as exc:
            raise RigError(f"--rig {rig_map}: {exc}") from None
        legs = legs_from_map(model, mapping, rig_map)
    else:
        legs = find_legs(model)
    scale = model_scale(model, legs)
    mesh = model.rest_mesh() * scale
    normals = np.asarray(trimesh.Trimesh(mesh, model.faces, process=False).vertex_normals)
    sole = float(mesh[:, 1].min()) if len(mesh) else 0.0
    ends = model.rest_points[[c.joints[-1] for c in legs.chains], 1] * scale
    clearance = np.array([max(float(y) - sole, 0.0) if len(c.joints) >= 4 else 0.0
                          for y, c in zip(ends, legs.chains)])
    return LoadedModel(model=model, legs=legs, scale=scale, mesh=mesh, normals=normals,
                       bind=rest_in_metres(model, scale), clearance=clearance)


def load_model(path: str) -> LoadedModel:
    """The model at ``path``, read once while the file is unchanged."""
    file = Path(path)
    if not file.is_file():
        raise RigError(f"{path}: {not_a_file(path)}")
    rig_map = _RIG_MAPS.get(str(file.resolve()), "")
    if rig_map and not Path(rig_map).is_file():
        raise RigError(f"--rig {rig_map}: {not_a_file(rig_map)}")
    return _load(str(file.resolve()), file.stat().st_mtime, rig_map, Path(rig_map).stat().st_mtime if rig_map else 0.0)


def model_notes(path: str) -> tuple[str, ...]:
    """What the model at ``path`` could be read only in part (:attr:`RiggedModel.notes`)."""
    return load_model(path).model.notes
