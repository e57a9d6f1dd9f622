"""Tuning constants of the collision and the solver, with their units and where they come from.

Lengths suit bodies of 0.1 to 10 m, as Box2D's do (its values, from its constants.h and core.h, unless
said otherwise); each was measured on the benchmark scenes where noted.
"""

from __future__ import annotations

LINEAR_SLOP = 0.005  # m: overlap the solver leaves alone, so resting contacts do not jitter (Box2D)
SPECULATIVE_DISTANCE = 4.0 * LINEAR_SLOP  # m: contact points are kept this far apart (Box2D)
REFERENCE_TOLERANCE = 0.1 * LINEAR_SLOP  # m: face B must beat face A by this to become the reference (Box2D)
FAT_MARGIN = 0.1  # m: how far a hitbox may move before its pairs are found again (0.05, 0.2: slower)
# share of the shapes that may leave their fat hitboxes, found again alone, before a whole search
MOST_DISPLACED = 0.25
CONTACT_HERTZ = 60.0  # Hz: stiffness of the soft contact, capped at a quarter of the substep rate (Box2D: 30)
CONTACT_DAMPING_RATIO = 10.0  # of the soft contact (Box2D)
# a rigid joint's position correction is as stiff as the soft step keeps stable: a quarter of the substep rate
# (Box2D takes 60 Hz; at the cap, a double pendulum kept its energy to 0.08 % over 20 s instead of 9 %)
JOINT_STIFFNESS = 0.25  # times the substep rate: the hertz of a rigid joint
JOINT_DAMPING_RATIO = 1.0  # of a rigid joint's position correction
# manifolds of a group of islands, solved before the next or beside it on threads (`contact_batches`):
# many_pyramids' 400 pyramids make 15 groups, its chunks 0.96 full (0.86 with groups of 1,024)
SOLVE_GROUP_MANIFOLDS = 4096
MAX_PUSH_SPEED = 3.0  # m/s: the fastest speed at which overlap is pushed apart (Box2D's contactSpeed)
# sine: a chain joint turning less is flat; a normal this near a neighbour segment's is that one's (Box2D)
CHAIN_ANGLE_TOLERANCE = 0.01
BOUNCE_PASSES = 512  # passes of the impact sequence at most (a cradle of n balls hit from its end: n - 1)
BOUNCE_SPEED_TOLERANCE = 1e-6  # m/s: slower approaches are no impact
AT_REST_SPEED = 1e-3  # m/s: a dynamic body slower than this (and AT_REST_ANGULAR_SPEED) is at rest
AT_REST_ANGULAR_SPEED = 1e-3  # rad/s
SLEEP_THRESHOLD = 0.05  # m/s: a body slower than this rests towards sleep (Box2D's sleepThreshold)
