"""`rustycs info` (not yet implemented)."""

NAME = "info"


def command() -> None:
    """Not yet implemented."""
    raise NotImplementedError
