"""Many worlds stepped together: one compiled call over all of them, split over threads.

A sweep's variants, Monte-Carlo repeats or the environments of a learning task are small worlds stepped
side by side. Stepped one by one, each `World.step` call costs about 2 us of Python and unboxing beyond
its ticks, more than a five-body tick itself; a `WorldBatch` steps them all in one compiled call
(`rustycs.step.step_worlds`), each of `threads` threads taking a contiguous share of the worlds (the
step releases the GIL). Every world steps exactly as it would alone, so its trajectory is bitwise the
same for any thread count and any batch it is in.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from rustycs.step import BAD_BODY, FRAMES, STATUS_FIELDS, step_worlds
from rustycs.stepper import CLOCK_FIELDS, add_stepper, stepper_list
from rustycs.world import SimulationDiverged, World


class WorldBatch:
    """Worlds stepped together (`step`), each as it would be alone. A world of a batch can still be
    changed, read and stepped on its own between the batch's steps."""

    def __init__(self, worlds: Sequence[World], threads: int = 1):
        if not worlds:
            raise ValueError("a batch needs at least one world")
        if len({id(world) for world in worlds}) != len(worlds):
            raise ValueError("a world can be in a batch once")
        if not 1 <= int(threads) <= 256:
            raise ValueError("threads must be from 1 to 256")
        self.worlds = list(worlds)
        self.threads = int(threads)
        count = len(self.worlds)
        # the worlds' status and clock are rows of these, so that a block's outcome is read for all at once
        self._status = np.zeros((count, STATUS_FIELDS), np.int64)
        self._clock = np.zeros((count, CLOCK_FIELDS), np.int64)
        for i, world in enumerate(self.worlds):
            self._status[i] = world._status
            self._clock[i] = world._clock
            world._status, world._clock = self._status[i], self._clock[i]
            world._forget_stepper()  # its stepper is made again with these rows
        self._replaced = np.zeros(count, np.bool_)
        self._steppers = None  # numba typed List of the worlds' steppers
        self._listed: list = []  # the steppers in it
        self._pool = None
        self._ready = -1  # `World.edits` when every world's stepper was last found ready to step unrecorded
        if self.threads > 1:  # imported here: `import rustycs` loads only numpy and numba
            from concurrent.futures import ThreadPoolExecutor

            self._pool = ThreadPoolExecutor(self.threads - 1)
        bounds = np.linspace(0, count, self.threads + 1).round().astype(np.int64)
        self._shares = [(int(a), int(b)) for a, b in zip(bounds[:-1], bounds[1:], strict=True) if b > a]

    @property
    def ticks(self) -> np.ndarray:
        """Each world's tick."""
        return self._clock[:, 0].copy()

    def step(self, n: int = 1, records: Sequence[dict[str, np.ndarray]] | None = None,
             every: int = 1) -> np.ndarray:
        """Advance every world n ticks (`World.step`), recording into `records` (one frame buffer per world,
        from row 0) when given; returns the frames each world recorded. Raises `SimulationDiverged` for
        the first world whose state became non-finite, after every world's block."""
        if n <= 0:
            return np.zeros(len(self.worlds), np.int64)
        if records is not None and len(records) != len(self.worlds):
            raise ValueError(f"a batch of {len(self.worlds)} worlds takes as many frame buffers")
        if records is None:
            every = 0
        if records is not None or self._ready != World.edits:
            for i, world in enumerate(self.worlds):
                frames = world._no_frames if records is None else world._frames(records[i], -(-n // every))
                if frames is not world._stepper_frames:
                    world._prepare(frames)
            self._list()
            self._ready = World.edits if records is None else -1
        self._run(n, every)
        for i in np.flatnonzero(self._replaced):
            self.worlds[i]._workspace_replaced()
        bad = np.flatnonzero(self._status[:, BAD_BODY] >= 0)
        if len(bad):
            raise self.worlds[bad[0]]._divergence()
        return self.frames

    @property
    def frames(self) -> np.ndarray:
        """The frames each world recorded in the last `step`."""
        return self._status[:, FRAMES].copy()

    def divergences(self) -> dict[int, SimulationDiverged]:
        """The error of each world whose state became non-finite in the last `step`, by its index."""
        return {int(i): self.worlds[i]._divergence() for i in np.flatnonzero(self._status[:, BAD_BODY] >= 0)}

    def _list(self) -> None:
        """The typed list of the worlds' steppers, made again when one of them was."""
        if self._steppers is not None and all(
                world._stepper is listed for world, listed in zip(self.worlds, self._listed, strict=True)):
            return
        first = self.worlds[0]._stepper
        steppers = stepper_list(first)
        for world in self.worlds[1:]:
            if world._stepper._type != first._type:
                raise ValueError("the worlds of a batch must have the same make-up of records (they differ "
                                 "in the layout of their arrays)")
            add_stepper(steppers, world._stepper)
        self._steppers = steppers
        self._listed = [world._stepper for world in self.worlds]

    def _run(self, n: int, every: int) -> None:
        """One block in every world, each thread stepping its share."""
        shares = [(self._steppers, a, b, n, every, self._replaced) for a, b in self._shares]
        if self._pool is None:
            for share in shares:
                step_worlds(*share)
            return
        futures = [self._pool.submit(step_worlds, *share) for share in shares[1:]]
        step_worlds(*shares[0])
        for future in futures:
            future.result()

    def close(self) -> None:
        """Stop the batch's threads."""
        if self._pool is not None:
            self._pool.shutdown()
            self._pool = None

    def __enter__(self) -> WorldBatch:
        return self

    def __exit__(self, *exc) -> None:
        self.close()
