"""Default values of the World's settings and of a body's keys: the one place they are written.

The application's scene format reads its defaults from here, so a scene that leaves a key out and a
World built in Python without it behave the same.
"""

from __future__ import annotations

# World
TICK_RATE = 60.0  # ticks per second
PRECISION = 10  # solver substeps per tick
MAX_PRECISION = 1000  # more substeps than this buy nothing and make one tick take minutes
GRAVITATIONAL_CONSTANT = 1.0  # G of the attractors
RESTITUTION_THRESHOLD = 1.0  # m/s: contacts approaching slower do not bounce (Box2D's default)
MIN_DISTANCE = 0.01  # m: an attractor's softening, d is taken as max(d, min_distance)
SLEEP = False  # islands at rest sleep (off: results are those of a world that never sleeps)
SLEEP_TIME = 0.5  # s an island rests before it sleeps (Box2D's b2_timeToSleep)
THREADS = 1  # threads inside one world (`rustycs.threads`)
MAX_THREADS = 256

# Bodies
BODY_TYPE = "dynamic"
MATERIAL = "default"
LINEAR_DAMPING = 0.0  # 1/s
ANGULAR_DAMPING = 0.0  # 1/s
GRAVITY_SCALE = 1.0
COLLISION_GROUP = 0  # 0: no group
COLLISION_CATEGORY = 1  # bits
COLLISION_MASK = -1  # bits: -1 collides with every category
