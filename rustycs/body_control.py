"""Moving and pushing bodies between steps: names, poses, forces, impulses and removal.

What pymunk's `Body` setters and Box2D's `b2Body_*` functions do, for a World whose bodies are rows of
structure-of-arrays buffers. A force or torque acts for one tick, as a pending force acts over the next
step in Box2D and pymunk: its impulse (F dt, T dt) is given at once, so it changes momentum by exactly
F dt. Only active dynamic bodies are pushed; static and kinematic ones have no mass to push.
"""

from __future__ import annotations

import math

import numpy as np

from rustycs.body_types import DYNAMIC, STATIC

Body = int | str  # a body's index, or its name


def _vector(value, what: str) -> np.ndarray:
    vector = np.asarray(value, dtype=np.float64).reshape(2)
    if not np.all(np.isfinite(vector)):
        raise ValueError(f"{what} must be finite")
    return vector


def _turn(angle: float, local: np.ndarray) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([c * local[0] - s * local[1], s * local[0] + c * local[1]])


class BodyControl:
    """The World's methods that name, place and push its bodies (mixed into `World`)."""

    _names: list[str]
    _name_rows: dict[str, int]

    @property
    def body_names(self) -> np.ndarray:
        """(N,) str: each body's name, unique (given to `add_body`, else `<shape type>-<index>`)."""
        return np.array(self._names, dtype=str)

    def body_index(self, name: str) -> int:
        """The index of the body called `name`; KeyError naming the closest names when there is none."""
        if name not in self._name_rows:
            import difflib

            close = difflib.get_close_matches(name, self._names, n=3)
            hint = f"; did you mean {', '.join(map(repr, close))}?" if close else ""
            raise KeyError(f"no body named {name!r}{hint}")
        return self._name_rows[name]

    def _new_name(self, name: str | None, kind: str, index: int) -> str:
        """The name body `index` will have (default `<shape type>-<index>`), checked unique before the body
        is added."""
        name = f"{kind}-{index}" if name is None else str(name)
        if name in self._name_rows:
            raise ValueError(f"a body named {name!r} exists already; names are unique")
        return name

    def _name_body(self, name: str, index: int) -> None:
        self._names.append(name)
        self._name_rows[name] = index

    def _row(self, body: Body) -> int:
        """The row of a body given by index or name."""
        if isinstance(body, str):
            return self.body_index(body)
        row = int(body)
        if not 0 <= row < self.body_count:
            raise IndexError(f"no body {row}: the world has {self.body_count}")
        return row

    def _pushable(self, row: int) -> bool:
        columns = self._bodies.columns
        return bool(columns["body_type"][row] == DYNAMIC and columns["active"][row])

    # ------------------------------------------------------------------ pose
    def set_position(self, body: Body, position) -> None:
        """Move a body's origin to `position` (its angle and velocities are kept), as Box2D's
        b2Body_SetTransform and pymunk's `body.position = ...` do. Moving a static body re-places it."""
        row = self._row(body)
        columns = self._bodies.columns
        columns["x"][row] = _vector(position, "a position") - _turn(columns["angle"][row],
                                                                   columns["origin"][row])
        self._moved(row)

    def set_angle(self, body: Body, angle: float) -> None:
        """Turn a body to `angle` (rad) about its origin, which stays where it is (Box2D, pymunk). A body
        of fixed rotation (an aabb) cannot be turned."""
        row = self._row(body)
        columns = self._bodies.columns
        if not math.isfinite(angle):
            raise ValueError("an angle must be finite")
        if columns["fixed_rotation"][row] and angle != columns["angle"][row]:
            raise ValueError(f"body {self._names[row]!r} has fixed rotation: it cannot be turned")
        origin = columns["x"][row] + _turn(columns["angle"][row], columns["origin"][row])
        columns["angle"][row] = angle
        columns["x"][row] = origin - _turn(angle, columns["origin"][row])
        self._moved(row)

    def _moved(self, row: int) -> None:
        """A static body's shapes are placed once per set of step buffers: make them again. Moving bodies
        are placed every tick (a jump out of its fat hitbox renews the broad phase's pairs); one asleep
        wakes, with its island."""
        if self._bodies.columns["body_type"][row] == STATIC:
            self._changed()
        self._wake_row(row)

    # ------------------------------------------------------------------ sleep
    @property
    def asleep(self) -> np.ndarray:
        """(N,) bool: the bodies whose island sleeps (a World made with `sleep=True`)."""
        return self._bodies.columns["asleep"][: self.body_count].copy()

    def wake(self, body: Body | None = None) -> None:
        """Wake the island of `body` (every body: None), as moving or pushing a body does."""
        columns = self._bodies.columns
        if body is None:
            columns["asleep"][:] = False
            columns["sleep_time"][:] = 0.0
        else:
            self._wake_row(self._row(body))

    def _wake_row(self, row: int) -> None:
        columns = self._bodies.columns
        if columns["asleep"][row]:
            island = columns["island"] == columns["island"][row]
            woken = island & columns["asleep"]
            columns["asleep"][woken] = False
            columns["sleep_time"][woken] = 0.0

    # ------------------------------------------------------------------ pushing
    def apply_impulse(self, body: Body, impulse, point=None) -> None:
        """Change a dynamic body's momentum by `impulse` (N s) applied at the world `point` (default: its
        centre of mass, so it does not turn it): dv = J / m, dw = (r x J) / I."""
        row = self._row(body)
        impulse = _vector(impulse, "an impulse")
        if not self._pushable(row):
            return
        self._wake_row(row)
        columns = self._bodies.columns
        columns["v"][row] += impulse * columns["inv_mass"][row]
        if point is not None:
            r = _vector(point, "a point") - columns["x"][row]
            columns["w"][row] += (r[0] * impulse[1] - r[1] * impulse[0]) * columns["inv_inertia"][row]

    def apply_force(self, body: Body, force, point=None) -> None:
        """Push a dynamic body with `force` (N) at the world `point` (default: its centre of mass) for one
        tick: its momentum changes by force x dt (and its angular momentum by r x force x dt)."""
        self.apply_impulse(body, _vector(force, "a force") * self.dt, point)

    def apply_torque(self, body: Body, torque: float) -> None:
        """Turn a dynamic body with `torque` (N m) for one tick: its angular momentum changes by
        torque x dt."""
        self.apply_angular_impulse(body, torque * self.dt)

    def apply_angular_impulse(self, body: Body, impulse: float) -> None:
        """Change a dynamic body's angular momentum by `impulse` (N m s): dw = impulse / I."""
        row = self._row(body)
        if not math.isfinite(impulse):
            raise ValueError("an angular impulse must be finite")
        if self._pushable(row):
            self._wake_row(row)
            self._bodies.columns["w"][row] += impulse * self._bodies.columns["inv_inertia"][row]

    # ------------------------------------------------------------------ removal
    def remove_body(self, body: Body) -> None:
        """Take a body out of the world: it stops moving and colliding, as a body that left the world's
        bounds does. Its row stays (indices and names of the others do not change), `active` false."""
        row = self._row(body)
        self._bodies.columns["active"][row] = False
        self._changed()
