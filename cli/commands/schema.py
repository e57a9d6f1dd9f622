"""`rustycs schema` (not yet implemented)."""

NAME = "schema"


def command() -> None:
    """Not yet implemented."""
    raise NotImplementedError
