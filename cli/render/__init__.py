"""Pictures of a run: PNG frames, GIF/MP4 animations, a self-contained HTML player and observable plots.

Modules, one job each: `bodies` (the static table of a trajectory), `frames` (block reading of frames),
`geometry` (bodies in world coordinates for one frame), `view` (world -> pixel), `raster` (one frame
with Pillow), `animate` (GIF and MP4), `player` (the HTML player), `plot` (matplotlib), `output`
(atomic writes).
"""
