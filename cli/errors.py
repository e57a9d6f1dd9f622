"""User-facing errors: one clear message per problem, exit code 2, never a traceback."""

from __future__ import annotations


class UserError(Exception):
    """Invalid input from the user (bad scene, missing file, bad option value).

    Carries one message per problem; the program prints each on its own line on stderr
    and exits with `exit_code` (2 unless stated).
    """

    def __init__(self, messages: str | list[str], exit_code: int = 2):
        self.messages = [messages] if isinstance(messages, str) else list(messages)
        self.exit_code = exit_code
        super().__init__("\n".join(self.messages))
