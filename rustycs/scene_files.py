"""Scene files and trajectories from Python: thin doors into the application (`rustycs_cli`).

The engine itself reads no files. These two functions import the application's YAML, pydantic and h5py
code only when called, so that `import rustycs` stays numpy and numba alone.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from rustycs.world import World


class SceneError(ValueError):
    """A scene that cannot be loaded: `messages` holds one `FILE:LINE:COLUMN: message` per problem (the
    exception's text is those lines)."""

    def __init__(self, messages: Sequence[str]):
        self.messages = list(messages)
        super().__init__("\n".join(self.messages))


def load_scene(path: str | Path, overrides: Sequence[str] = ()) -> World:
    """The World a scene file describes (a YAML scene, or a trajectory's stored scene), its bodies named
    as in the scene, generators expanded; `overrides` are `KEY=VALUE` texts as `rustycs run -s` takes
    them. Raises SceneError with every problem found."""
    from rustycs_cli.python_api import load_world

    return load_world(path, overrides)


def open_trajectory(path: str | Path):
    """A reader of a trajectory written by `rustycs run` (`rustycs_cli.reader.Trajectory`): names, times,
    positions and the rest as numpy arrays, `to_dataframe()`, `to_xarray()`, an inline player in Jupyter.
    Raises FileNotFoundError or ValueError for a file that is not a rustycs trajectory."""
    from rustycs_cli.reader import Trajectory

    return Trajectory(path)
