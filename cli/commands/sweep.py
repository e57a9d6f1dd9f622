"""`rustycs sweep` (not yet implemented)."""

NAME = "sweep"


def command() -> None:
    """Not yet implemented."""
    raise NotImplementedError
