"""The built-in procedural scene suite (translate, rotate, crowd, hairball,
hair, deform, skinned, demo, slide, ribbons): deterministic for a seed, with a size knob
(size 1 gives the suite's default sizes; tests use small ones)."""
from __future__ import annotations

from . import _mbrt

__all__ = ["make", "names"]


def make(name: str, size: float = 1.0, seed: int = 1) -> "_mbrt.Scene":
    """Builds the built-in scene `name` (see names()); raises mbrt.Error for an
    unknown name or size <= 0. The scene carries the suite's camera for render()."""
    return _mbrt.scenes.make(name, size, seed)


def names() -> list[str]:
    """The built-in scenes, in suite order."""
    return _mbrt.scenes.names()
