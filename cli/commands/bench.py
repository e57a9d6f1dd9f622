"""`rustycs bench` (not yet implemented)."""

NAME = "bench"


def command() -> None:
    """Not yet implemented."""
    raise NotImplementedError
