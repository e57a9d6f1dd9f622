"""What `rustycs.load_scene` does: a scene file (or a trajectory's stored scene) into a World."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from .errors import UserError

if TYPE_CHECKING:
    import rustycs


def load_world(path: str | Path, overrides: Sequence[str] = ()) -> rustycs.World:
    """The scene's World, bodies named as in the scene; problems raised as one rustycs.SceneError."""
    from rustycs.scene_files import SceneError

    from .build import build_world
    from .simulation import load_source

    if isinstance(overrides, str):
        overrides = (overrides,)
    try:
        loaded = load_source(path, tuple(overrides))
    except UserError as err:
        raise SceneError(err.messages) from None
    return build_world(loaded.scene)
