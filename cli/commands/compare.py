"""`rustycs compare` (not yet implemented)."""

NAME = "compare"


def command() -> None:
    """Not yet implemented."""
    raise NotImplementedError
