"""`rustycs validate` (not yet implemented)."""

NAME = "validate"


def command() -> None:
    """Not yet implemented."""
    raise NotImplementedError
