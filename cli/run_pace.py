"""How many ticks each engine call of a run takes: about STOP_SECONDS of work, so that Ctrl-C or SIGTERM
is answered promptly even when one tick is slow (many bodies, a high precision), and whole blocks of
frames when ticks are fast. Frames stay at the ticks `every` asks for: a call that records ends on one."""

from __future__ import annotations

from dataclasses import dataclass

from .limits import STOP_SECONDS


@dataclass
class Pace:
    every: int  # the run's recording interval
    most: int  # ticks per call at most (the frame buffer's rows times `every`)
    budget: int = 1  # ticks the next call may take; the first call measures a single tick

    def next_call(self, tick: int, ticks: int) -> tuple[int, int]:
        """(ticks to step, `every` for that call: 0 records nothing) from `tick` towards `ticks`."""
        remaining = ticks - tick
        if tick % self.every == 0 and self.budget >= self.every:
            return min(self.most, self.budget // self.every * self.every, remaining), self.every
        boundary = min((tick // self.every + 1) * self.every, ticks)  # the next recorded tick
        if boundary - tick <= self.budget:
            return boundary - tick, boundary - tick
        return self.budget, 0

    def took(self, count: int, seconds: float) -> None:
        """Adjust the budget after a call of `count` ticks that took `seconds`."""
        per_tick = seconds / max(count, 1)
        fits = int(STOP_SECONDS / per_tick) if per_tick > 0 else self.most
        self.budget = max(1, min(self.most, fits))
