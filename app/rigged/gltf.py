"""Reading a rigged glTF (``.glb`` or ``.gltf``) with pygltflib: the skin's joints (names,
hierarchy, rest pose in the world, inverse bind matrices) and its skinned mesh
(positions, normals, per-vertex colours from the base colour texture or factor,
triangles, four joints and weights a vertex).

Everything is in the file's own units and axes (glTF: y up; the node transforms above
the skeleton, such as a Z_UP node, are applied). A file that cannot be read, or that has
no skin, is a one-line :class:`RigError` naming the file.
"""

from __future__ import annotations

import binascii
import io
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from ..errors import GaitlabError, not_a_file

MAX_FACES = 2_000_000  # triangles a model may have (a larger mesh is refused before it is read)
MAX_TEXTURE_SIDE = 8192
MAX_TEXTURE_PIXELS = MAX_TEXTURE_SIDE * MAX_TEXTURE_SIDE  # a base colour texture (its declared size is checked first)
_COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}
_DTYPES = {5120: np.int8, 5121: np.uint8, 5122: np.int16, 5123: np.uint16, 5125: np.uint32, 5126: np.float32}


class RigError(GaitlabError):
    """A rigged model that cannot be used (unreadable, no skin, no legs found)."""


@dataclass(frozen=True)
class RiggedModel:
    """A skinned model in its rest pose. J joints, V vertices, F triangles.

    ``names`` (J,) joint names; ``parents`` (J,) each joint's parent among the joints (-1:
    none); ``rest`` (J, 4, 4) each joint's world transform at rest; ``inverse_bind``
    (J, 4, 4); ``positions`` (V, 3) and ``normals`` (V, 3) in the bind pose; ``colors``
    (V, 3) display RGB 0-1; ``faces`` (F, 3); ``joints`` (V, 4) and ``weights`` (V, 4),
    the weights summing to one. ``notes``: what was read in part (a texture file that
    is missing, say), one sentence each, for the user to be told."""

    path: Path
    names: tuple[str, ...]
    parents: NDArray[np.int64]
    rest: NDArray[np.float64]
    inverse_bind: NDArray[np.float64]
    positions: NDArray[np.float64]
    normals: NDArray[np.float64]
    colors: NDArray[np.float64]
    faces: NDArray[np.int64]
    joints: NDArray[np.int64]
    weights: NDArray[np.float64]
    notes: tuple[str, ...] = ()

    @property
    def rest_points(self) -> NDArray[np.float64]:
        """Each joint's position at rest (J, 3)."""
        return self.rest[:, :3, 3]

    def rest_mesh(self) -> NDArray[np.float64]:
        """The mesh skinned to the rest pose (V, 3), in the world (its own units)."""
        skin = self.rest @ self.inverse_bind
        vertices = np.concatenate([self.positions, np.ones((len(self.positions), 1))], axis=1)
        return np.einsum("vk,vkab,vb->va", self.weights, skin[self.joints], vertices)[:, :3]


def node_matrix(node) -> NDArray[np.float64]:
    """A node's local transform (4, 4)."""
    if node.matrix is not None:
        return np.array(node.matrix, dtype=np.float64).reshape(4, 4).T  # glTF stores columns
    m = np.eye(4)
    if node.scale is not None:
        m = np.diag([*node.scale, 1.0]) @ m
    if node.rotation is not None:
        x, y, z, w = node.rotation
        r = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                      [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                      [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
        turn = np.eye(4)
        turn[:3, :3] = r
        m = turn @ m
    if node.translation is not None:
        move = np.eye(4)
        move[:3, 3] = node.translation
        m = move @ m
    return m


class _Reader:
    """Accessor data of one glTF document."""

    def __init__(self, gltf, path: Path) -> None:
        self.gltf = gltf
        self.path = path
        self.blob = gltf.binary_blob()
        self._buffers: dict[int, bytes] = {}
        self.notes: list[str] = []  # what could be read only in part (RiggedModel.notes)

    def _buffer(self, index: int) -> bytes:
        if index not in self._buffers:
            buffer = self.gltf.buffers[index]
            if buffer.uri is None:
                if self.blob is None:
                    raise RigError(f"{self.path}: buffer {index} has no data")
                self._buffers[index] = self.blob
            elif buffer.uri.startswith("data:"):
                import base64

                self._buffers[index] = base64.b64decode(buffer.uri.split(",", 1)[1])
            else:
                file = (self.path.parent / buffer.uri).resolve()
                if not file.is_file():
                    raise RigError(f"{self.path}: its buffer file {buffer.uri} is missing")
                self._buffers[index] = file.read_bytes()
        return self._buffers[index]

    def view_bytes(self, index: int) -> bytes:
        view = self.gltf.bufferViews[index]
        data = self._buffer(view.buffer)
        start = view.byteOffset or 0
        return data[start:start + view.byteLength]

    def accessor(self, index: int) -> NDArray:
        acc = self.gltf.accessors[index]
        dtype = np.dtype(_DTYPES[acc.componentType])
        width = _COMPONENTS[acc.type]
        if acc.bufferView is None:
            return np.zeros((acc.count, width), dtype=dtype)
        view = self.gltf.bufferViews[acc.bufferView]
        data = self._buffer(view.buffer)
        start = (view.byteOffset or 0) + (acc.byteOffset or 0)
        stride = view.byteStride or dtype.itemsize * width
        rows = np.ndarray((acc.count, width), dtype=dtype, buffer=data, offset=start,
                          strides=(stride, dtype.itemsize)).copy()
        if acc.normalized and dtype.kind in "ui":
            rows = rows.astype(np.float64) / float(np.iinfo(dtype.type).max)
        return rows


def load_rigged_model(path: str | Path) -> RiggedModel:
    """The first skinned mesh of the glTF at ``path`` with its skin, in the rest pose."""
    import pygltflib

    path = Path(path)
    if not path.is_file():
        raise RigError(f"{path}: {not_a_file(path)}")
    try:
        with warnings.catch_warnings():  # pygltflib warns of what it reads anyway (an old GLB version)
            warnings.simplefilter("ignore")
            gltf = pygltflib.GLTF2().load(str(path))
    except Exception as exc:  # pygltflib raises many kinds on bad files
        raise RigError(f"{path}: not a readable glTF file ({type(exc).__name__})") from None
    if gltf is None:
        raise RigError(f"{path}: not a readable glTF file")
    required = [e for e in (gltf.extensionsRequired or []) if e not in ("KHR_materials_unlit", "KHR_texture_transform")]
    if required:
        raise RigError(f"{path}: needs the glTF extension {required[0]} (compressed or extended data); export it "
                       "without it")
    skinned = [i for i, node in enumerate(gltf.nodes) if node.skin is not None and node.mesh is not None]
    if not gltf.skins or not skinned:
        raise RigError(f"{path}: has no skinned mesh (a glTF with a skin: a skeleton and a mesh weighted to it)")
    try:
        with np.errstate(all="ignore"):  # what a damaged file's numbers give is checked below, not warned of
            model = _read_model(gltf, gltf.nodes[skinned[0]], path)
    except RigError as exc:
        text = str(exc)
        raise RigError(text if text.startswith(str(path)) else f"{path}: {text}") from None
    except (ValueError, TypeError, KeyError, IndexError, AttributeError, ArithmeticError, np.linalg.LinAlgError,
            binascii.Error) as exc:  # an index past a list's end, a buffer too short for its accessor, ...
        raise RigError(f"{path}: a damaged glTF ({type(exc).__name__} while reading its skin and mesh); "
                       "export it again from the modelling tool") from None
    if not all(np.all(np.isfinite(a)) for a in (model.rest, model.inverse_bind, model.positions, model.weights,
                                                model.colors)):
        raise RigError(f"{path}: its skeleton or mesh holds values that are not finite numbers (NaN or infinity)")
    if model.faces.size and (model.faces.min() < 0 or model.faces.max() >= len(model.positions)):
        raise RigError(f"{path}: its mesh's triangles name vertex {int(model.faces.max())} of "
                       f"{len(model.positions)}; the file is damaged")
    return model


def _read_model(gltf, node, path: Path) -> RiggedModel:
    """The model of ``gltf``'s skinned mesh ``node`` (opened from ``path``), read as
    :func:`load_rigged_model` says."""
    reader = _Reader(gltf, path)
    world = world_matrices(gltf)
    skin = gltf.skins[node.skin]
    joints = list(skin.joints)
    names = tuple(gltf.nodes[j].name or f"joint{k}" for k, j in enumerate(joints))
    index = {node_index: k for k, node_index in enumerate(joints)}
    parent_of = {child: p for p, n in enumerate(gltf.nodes) for child in (n.children or [])}
    parents = np.array([index.get(parent_of.get(j, -1), -1) for j in joints], dtype=np.int64)
    if skin.inverseBindMatrices is not None:
        inverse_bind = reader.accessor(skin.inverseBindMatrices).astype(np.float64).reshape(-1, 4, 4).transpose(0, 2, 1)
    else:
        inverse_bind = np.tile(np.eye(4), (len(joints), 1, 1))
    rest = np.array([world[j] for j in joints])
    mesh = gltf.meshes[node.mesh]
    parts = [_primitive(reader, prim, gltf, path) for prim in mesh.primitives
             if prim.attributes.JOINTS_0 is not None and prim.attributes.WEIGHTS_0 is not None]
    if not parts:
        raise RigError(f"{path}: its mesh {mesh.name or node.mesh} has no joint weights (JOINTS_0 and WEIGHTS_0)")
    offsets = np.cumsum([0] + [len(p[0]) for p in parts[:-1]])
    positions = np.concatenate([p[0] for p in parts])
    faces = np.concatenate([p[3] + o for p, o in zip(parts, offsets)])
    normals = np.concatenate([p[1] for p in parts])
    colors = np.concatenate([p[2] for p in parts])
    vertex_joints = np.concatenate([p[4] for p in parts])
    weights = np.concatenate([p[5] for p in parts])
    if vertex_joints.max(initial=0) >= len(joints):
        raise RigError(f"{path}: its mesh names joint {int(vertex_joints.max())} of a skin of {len(joints)}")
    total = weights.sum(axis=1, keepdims=True)
    weights = np.where(total > 0, weights / np.maximum(total, 1e-12), np.array([1.0, 0.0, 0.0, 0.0]))
    return RiggedModel(path=path, names=names, parents=parents, rest=rest, inverse_bind=inverse_bind,
                       positions=positions, normals=normals, colors=colors, faces=faces,
                       joints=vertex_joints, weights=weights, notes=tuple(dict.fromkeys(reader.notes)))


def world_matrices(gltf) -> dict[int, NDArray[np.float64]]:
    """Every node's world transform, from the scene roots down."""
    children = {c for n in gltf.nodes for c in (n.children or [])}
    roots = [i for i in range(len(gltf.nodes)) if i not in children]
    world: dict[int, NDArray[np.float64]] = {}
    stack = [(i, np.eye(4)) for i in roots]
    while stack:
        i, above = stack.pop()
        if i in world:  # a node reached twice: two parents, or its own ancestor (no end to the walk)
            raise RigError(f"its node {i} ({gltf.nodes[i].name or 'unnamed'}) has two parents or is its own "
                           "ancestor; the nodes must form a tree")
        world[i] = above @ node_matrix(gltf.nodes[i])
        stack.extend((c, world[i]) for c in (gltf.nodes[i].children or []))
    return world


def _primitive(reader: _Reader, prim, gltf, path: Path) -> tuple:
    """One skinned triangle primitive: positions, normals, colours, faces, joints, weights."""
    attrs = prim.attributes
    positions = reader.accessor(attrs.POSITION).astype(np.float64)
    if prim.indices is not None:
        count = gltf.accessors[prim.indices].count
        if count // 3 > MAX_FACES:
            raise RigError(f"{path}: {count // 3} triangles; the most a model may have is {MAX_FACES}")
        faces = reader.accessor(prim.indices).astype(np.int64).reshape(-1, 3)
    else:  # not indexed: every three vertices a triangle
        faces = np.arange(len(positions) - len(positions) % 3, dtype=np.int64).reshape(-1, 3)
    if prim.mode not in (None, 4):
        raise RigError(f"{path}: a primitive drawn as mode {prim.mode}; only triangles are read")
    if attrs.NORMAL is not None:
        normals = reader.accessor(attrs.NORMAL).astype(np.float64)
    else:
        normals = _vertex_normals(positions, faces)
    colors = _colors(reader, prim, gltf, len(positions))
    if attrs.COLOR_0 is not None:  # vertex colours (linear) multiply the material's (a Gaitlab export's coat)
        shade = reader.accessor(attrs.COLOR_0).astype(np.float64)[:, :3]
        if len(shade) == len(positions):
            base = colors if prim.material is not None else np.ones_like(colors)  # glTF's default material is white
            colors = base * np.sqrt(np.clip(shade, 0.0, 1.0))
    return (positions, normals, colors, faces, reader.accessor(attrs.JOINTS_0).astype(np.int64),
            reader.accessor(attrs.WEIGHTS_0).astype(np.float64))


def _vertex_normals(positions: NDArray[np.float64], faces: NDArray[np.int64]) -> NDArray[np.float64]:
    """Area-weighted vertex normals (V, 3)."""
    import trimesh

    mesh = trimesh.Trimesh(positions, faces, process=False)
    return np.asarray(mesh.vertex_normals, dtype=np.float64)


def _colors(reader: _Reader, prim, gltf, count: int) -> NDArray[np.float64]:
    """Per-vertex display colours: the base colour texture at each vertex's texture
    coordinate (nearest texel), times the base colour factor; grey without a material
    (vertex colours, ``COLOR_0``, multiply these afterwards)."""
    if prim.material is None:
        return np.full((count, 3), 0.7)
    pbr = gltf.materials[prim.material].pbrMetallicRoughness
    factor = np.array((pbr.baseColorFactor if pbr and pbr.baseColorFactor else [1, 1, 1, 1])[:3], dtype=np.float64)
    texture = pbr.baseColorTexture if pbr else None
    if texture is None or prim.attributes.TEXCOORD_0 is None:
        return np.tile(factor, (count, 1))
    source = gltf.textures[texture.index].source
    if source is None:  # an image only an extension gives (KTX2, WebP): the factor alone
        return np.tile(factor, (count, 1))
    image = gltf.images[source]
    from PIL import Image, UnidentifiedImageError

    from ..images import opened_image

    if image.bufferView is not None:
        data = reader.view_bytes(image.bufferView)
    elif image.uri and not image.uri.startswith("data:"):
        file = (reader.path.parent / image.uri).resolve()
        if not file.is_file():
            reader.notes.append(f"its texture {image.uri} is missing (looked for {file}); that part is drawn in "
                                "its material's plain colour")
            return np.tile(factor, (count, 1))
        data = file.read_bytes()
    else:
        import base64

        data = base64.b64decode((image.uri or ",").split(",", 1)[1])
    limit = f"a texture may have at most {MAX_TEXTURE_PIXELS:,} pixels ({MAX_TEXTURE_SIDE}x{MAX_TEXTURE_SIDE})"
    try:
        with opened_image(io.BytesIO(data)) as img:
            cols, rows = img.size  # checked before a byte of it is decoded
            if cols * rows > MAX_TEXTURE_PIXELS:
                raise RigError(f"{reader.path}: image {source} declares {cols}x{rows} pixels; {limit}")
            pixels = np.asarray(img.convert("RGB"))  # one byte a channel: only the texels read become floats
    except Image.DecompressionBombError:
        raise RigError(f"{reader.path}: image {source} declares more pixels than Pillow will decode; {limit}") from None
    except (UnidentifiedImageError, OSError, SyntaxError, ValueError) as exc:
        raise RigError(f"{reader.path}: image {source} is not an image Gaitlab can read ({type(exc).__name__}); "
                       "give a PNG or JPEG base colour texture") from None
    uv = reader.accessor(prim.attributes.TEXCOORD_0).astype(np.float64)
    h, w = pixels.shape[:2]
    x = np.clip((uv[:, 0] % 1.0) * w, 0, w - 1).astype(np.int64)
    y = np.clip((uv[:, 1] % 1.0) * h, 0, h - 1).astype(np.int64)
    return pixels[y, x].astype(np.float64) / 255.0 * factor
