"""`rustycs --version`, and every command's --help: its options and an example of the command."""

from __future__ import annotations

import inspect
import re
from importlib.metadata import version

import pytest

from rustycs_cli.app import app

COMMANDS = [command.name for command in app.registered_commands]


def test_version(cli):
    result = cli("--version")
    assert result.exit_code == 0 and result.stdout == f"rustycs {version('rustycs')}\n"


def test_every_command_is_listed_in_the_help(cli):
    result = cli("--help")
    assert result.exit_code == 0 and "--version" in result.stdout
    assert COMMANDS and all(re.search(rf"│ {name}\s", result.stdout) for name in COMMANDS)


@pytest.mark.parametrize("name", COMMANDS)
def test_every_command_has_help_with_its_options_and_an_example(cli, name: str):
    result = cli(name, "--help")
    assert result.exit_code == 0
    text = " ".join(result.stdout.split())
    assert re.search(rf"Examples?: rustycs {name} ", text), f"{name} --help has no example"
    command = next(c for c in app.registered_commands if c.name == name)
    for parameter in inspect.signature(command.callback).parameters.values():
        option = parameter.default
        for flag in getattr(option, "param_decls", ()) or ():
            if flag.startswith("--"):
                assert flag.split("/")[0] in text, f"{name} --help does not show {flag}"
