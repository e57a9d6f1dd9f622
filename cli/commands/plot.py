"""`rustycs plot` (not yet implemented)."""

NAME = "plot"


def command() -> None:
    """Not yet implemented."""
    raise NotImplementedError
