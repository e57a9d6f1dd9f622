"""`rustycs schema`: the JSON Schema of the scene format, for editors."""

from __future__ import annotations

from pathlib import Path

import typer

NAME = "schema"


def command(
    out: Path = typer.Option(None, "--out", "-o", help="Write the schema to this file (default: stdout)."),
) -> None:
    """Print the JSON Schema of the scene format (or write it to a file), for editor completion and checks.

    Scene files point at it with a first line `# yaml-language-server: $schema=../rustycs.schema.json`.

    Example: rustycs schema -o rustycs.schema.json
    """
    import json

    from ..errors import UserError
    from ..scene import Scene
    from ..summary import write_text_atomic

    schema = {"$schema": "https://json-schema.org/draft/2020-12/schema", **Scene.model_json_schema()}
    text = json.dumps(schema, indent=2) + "\n"
    if out is None:
        print(text, end="")
        return
    try:
        write_text_atomic(out, text)
    except OSError as err:
        raise UserError(f"{out}: cannot write the schema: {err.strerror or err}") from None
