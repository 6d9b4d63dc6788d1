"""Each command module has its own ``main(argv) -> int`` (the brief's CLI shape; issue
37's note on ``cli/wear.py``): the command alone, with the parsing, errors and exit
statuses of ``express.cli.main``."""

from __future__ import annotations

import pytest

from cli_support import CONVENTIONAL
from express import cli
from express.cli.runner import run_command


@pytest.mark.parametrize("module", cli.COMMANDS, ids=[m.__name__.rsplit(".", 1)[-1] for m in cli.COMMANDS])
def test_every_command_module_runs_its_command_alone(module, capsys):
    name = module.__name__.rsplit(".", 1)[-1].replace("_", "-")
    assert module.main(["--help"]) == 0
    out = capsys.readouterr().out
    assert out.startswith(f"usage: express {name} ")
    assert module.main(["--no-such-option"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: express") and "Traceback" not in err


def test_a_commands_main_is_the_express_command(capsys):
    from express.cli import eigen

    assert eigen.main([CONVENTIONAL, "--json"]) == 0
    alone = capsys.readouterr().out
    assert cli.main(["eigen", CONVENTIONAL, "--json"]) == 0
    assert capsys.readouterr().out == alone
    assert run_command(eigen, [CONVENTIONAL, "--speed", "-3"]) == 2
    assert "--speed" in capsys.readouterr().err
