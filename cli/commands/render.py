"""`rustycs render` (not yet implemented)."""

NAME = "render"


def command() -> None:
    """Not yet implemented."""
    raise NotImplementedError
