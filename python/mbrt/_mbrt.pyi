"""Type stubs of the compiled part of mbrt (python/src/*.cpp)."""
from __future__ import annotations

from types import ModuleType
from typing import Any, Iterable, Iterator, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

ArrayLike = npt.ArrayLike
Scalar = Union[float, int]

class Error(RuntimeError):
    """Every error mbrt reports: bad scenes, options, rays arrays, files; the
    message is the library's."""

def kinds() -> list[str]:
    """The accel kinds this build can construct."""

class Scene:
    """Moving triangle meshes, round segments and instances from numpy arrays."""

    def __init__(self) -> None: ...
    def add_triangle_mesh(self, indices: ArrayLike, steps: ArrayLike,
                          time_range: Tuple[float, float] = (0.0, 1.0), share: bool = True) -> int:
        """indices (M, 3) uint32; steps (S, N, 3) float32 (shared) or (N, 3). Returns the geometry id."""
    def add_segments(self, indices: ArrayLike, steps: ArrayLike, radii: ArrayLike,
                     time_range: Tuple[float, float] = (0.0, 1.0), share: bool = True) -> int:
        """indices (M, 2) uint32; steps (S, N, 3); radii (N,). Returns the geometry id."""
    def add_instance(self, scene: Scene, transforms: ArrayLike,
                     time_range: Tuple[float, float] = (0.0, 1.0)) -> int:
        """transforms (S, 3, 4) or (S, 4, 4) row-major object-to-world keys."""
    def add_instance_srt(self, scene: Scene, scale: ArrayLike, rotation: ArrayLike, translation: ArrayLike,
                         time_range: Tuple[float, float] = (0.0, 1.0)) -> int:
        """scale (S, 3), rotation (S, 4) quaternions w x y z, translation (S, 3)."""
    def set_mask(self, geom_id: int, mask: int) -> None: ...
    @property
    def num_geometries(self) -> int: ...
    @property
    def num_primitives(self) -> int: ...
    @property
    def name(self) -> str: ...
    @property
    def version(self) -> int: ...
    def geometry(self, geom_id: int) -> dict[str, Any]: ...
    def bounds(self) -> npt.NDArray[np.float32]:
        """(2, 3): lower and upper corner over the whole shutter."""
    def validate(self) -> None: ...
    def __len__(self) -> int: ...

class Hits:
    """Closest hits, one entry per ray; misses have t = inf and ids 0xFFFFFFFF."""

    t: npt.NDArray[np.float32]
    geom_id: npt.NDArray[np.uint32]
    prim_id: npt.NDArray[np.uint32]
    inst_id: npt.NDArray[np.uint32]
    u: npt.NDArray[np.float32]
    v: npt.NDArray[np.float32]
    ng: npt.NDArray[np.float32]  # (N, 3)
    @property
    def hit(self) -> npt.NDArray[np.bool_]: ...
    def __len__(self) -> int: ...

class Accel:
    """An acceleration structure over a Scene (which it keeps alive)."""

    def __init__(self, scene: Scene, kind: str = "auto", *, branching: int = 8, max_leaf_size: int = 8,
                 sah_bins: int = 32, traversal_cost: float = 1.0, frozen_time: float = 0.5,
                 memory_budget: int = 0, max_instance_depth: int = 8, embree_mode: str = "robust",
                 auto_fit_tolerance: float = 1e-5, auto_leaf_kind: Optional[str] = None) -> None: ...
    def intersect(self, rays: Optional[ArrayLike] = None, *, org: Optional[ArrayLike] = None,
                  dir: Optional[ArrayLike] = None, tnear: Union[None, Scalar, ArrayLike] = None,
                  tfar: Union[None, Scalar, ArrayLike] = None, time: Union[None, Scalar, ArrayLike] = None,
                  mask: Union[None, int, ArrayLike] = None, out: Optional[Hits] = None) -> Hits:
        """rays (N, 9) float32 (org, dir, tnear, tfar, time) or org/dir (N, 3) and the rest;
        out: an earlier Hits of as many rays to write into."""
    def occluded(self, rays: Optional[ArrayLike] = None, *, org: Optional[ArrayLike] = None,
                 dir: Optional[ArrayLike] = None, tnear: Union[None, Scalar, ArrayLike] = None,
                 tfar: Union[None, Scalar, ArrayLike] = None, time: Union[None, Scalar, ArrayLike] = None,
                 mask: Union[None, int, ArrayLike] = None) -> npt.NDArray[np.bool_]: ...
    def rebuild(self) -> None: ...
    def refit(self) -> bool: ...
    def stats(self) -> dict[str, Any]: ...
    @property
    def kind(self) -> str: ...
    @property
    def scene(self) -> Scene: ...

class Timeline:
    """An input's timeline in seconds (end is inf for a glTF file without a clip)."""

    start: float
    end: float
    what: str

class Frame:
    """One frame of Document.frames()."""

    index: int
    shutter: Tuple[float, float]  # seconds of the timeline
    scene: Scene  # the frames' scene: the same object every frame, updated in place
    accel: Optional[Accel]  # the accel following the frames (the same object), or None
    update: Optional[dict[str, Any]]  # what, refitted, seconds, sah_cost
    scene_seconds: float
    change: str  # "vertices" (replaced in place) or "layout" (geometries replaced)

class Frames(Iterator[Frame]):
    def __iter__(self) -> Frames: ...
    def __next__(self) -> Frame: ...
    def __len__(self) -> int: ...

class Document(Scene):
    """What load() returns: a Scene over one shutter, with the input's timeline and frames."""

    @property
    def timeline(self) -> Timeline: ...
    def frame_range(self, *, fps: float = 24.0, shutter_angle: float = 180.0) -> range: ...
    def frames(self, *, fps: float = 24.0, shutter_angle: float = 180.0, frames: Optional[Iterable[int]] = None,
               accel: Optional[str] = None, update: str = "auto", rebuild_factor: float = 1.5) -> Frames: ...

def load(path: str, *, shutter: Optional[Tuple[float, float]] = None, steps: Union[None, int, str] = None,
         clip: str = "", fps: float = 24.0, motion: str = "", size: float = 1.0, seed: int = 1,
         stage: bool = False) -> Document: ...

def render(scene: Scene, accel: Optional[Accel] = None, *, width: int = 640, height: int = 360, spp: int = 16,
           integrator: str = "ao", shutter: Tuple[float, float] = (0.0, 1.0), seed: int = 1,
           ao_samples: int = 2, ao_distance: float = 0.0, max_depth: int = 4, heat_max: float = 0.0,
           color_bar: bool = True, tonemap: bool = False, exposure: float = 0.0,
           eye: Optional[ArrayLike] = None, target: Optional[ArrayLike] = None, up: Optional[ArrayLike] = None,
           fov: Optional[float] = None) -> npt.NDArray[np.float32]:
    """(H, W, 3) float32 linear RGB."""

def bench(scenes: Optional[Sequence[Union[str, Scene]]] = None, accels: Sequence[str] = (), *,
          quick: bool = False, size: Optional[float] = None, width: Optional[int] = None,
          height: Optional[int] = None, repeats: Optional[int] = None, frozen_times: Optional[int] = None,
          brute_sample: Optional[int] = None, seed: Optional[int] = None,
          progress: bool = False) -> list[dict[str, Any]]: ...

scenes: ModuleType
