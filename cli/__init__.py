"""rustycs_cli: the application around the engine (scene files, HDF5 trajectories, the `rustycs` program)."""
