"""Body type codes: static bodies never move, dynamic ones obey forces and contacts, kinematic ones
move with their own velocity and push dynamic bodies."""

STATIC, DYNAMIC, KINEMATIC = 0, 1, 2
BODY_TYPE_NAMES = ("static", "dynamic", "kinematic")
