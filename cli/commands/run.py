"""`rustycs run` (not yet implemented)."""

NAME = "run"


def command() -> None:
    """Not yet implemented."""
    raise NotImplementedError
