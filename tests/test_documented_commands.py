"""Every ``python -m experiments.<name> ...`` command in the README, the docs and the experiments' docstrings
(their ``--help``) parses: run with ``--print-config`` in-process (the config resolved, every flag checked,
nothing trained), so a documented command cannot rot."""

import ast
import importlib
import re
import shlex
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
DOCUMENTS = [REPO / "README.md", *sorted((REPO / "docs").glob("**/*.md"))]
EXPERIMENTS = sorted((REPO / "experiments").glob("[!_]*.py"))
FENCE = re.compile(r"^[ \t]*```[^\n]*\n(.*?)^[ \t]*```", re.DOTALL | re.MULTILINE)
INLINE = re.compile(r"`([^`]+)`")
SHELL_OPERATORS = {"&&", "||", "|", ";", "&", ">", ">>", "<", "2>", "2>&1"}


def command_lines(markdown: str) -> list[str]:
    """The shell lines of a markdown text that may hold a command: each line of a fenced block (continued
    with a trailing ``\\``) and each inline code span (which may wrap over lines)."""
    lines = []
    for block in FENCE.findall(markdown):
        lines.extend(block.replace("\\\n", " ").splitlines())
    lines.extend(span.replace("\n", " ") for span in INLINE.findall(FENCE.sub("", markdown)))
    return lines


def experiment_argv(line: str) -> tuple[str, list[str]] | None:
    """``(experiment name, its arguments)`` of the ``python -m experiments.<name>`` command on a shell line
    (shell comments and what follows a shell operator dropped), or None."""
    try:
        words = shlex.split(line, comments=True)
    except ValueError:  # an unbalanced quote: prose, not a command
        return None
    for i, word in enumerate(words[:-2]):
        match = re.fullmatch(r"experiments\.([a-z0-9_]+)", words[i + 2])
        if re.fullmatch(r"python3?", word) and words[i + 1] == "-m" and match:
            rest = words[i + 3:]
            end = next((j for j, w in enumerate(rest) if w in SHELL_OPERATORS), len(rest))
            return match.group(1), rest[:end]
    return None


def docstring_lines(source: str) -> list[str]:
    """The lines of a module's docstring, continued with a trailing ``\\``."""
    return (ast.get_docstring(ast.parse(source)) or "").replace("\\\n", " ").splitlines()


def documented_commands() -> list[tuple[str, str, list[str]]]:
    found = []
    sources = [(doc, command_lines(doc.read_text())) for doc in DOCUMENTS]
    sources += [(module, docstring_lines(module.read_text())) for module in EXPERIMENTS]
    for path, lines in sources:
        for line in lines:
            command = experiment_argv(line)
            if command is not None:
                found.append((path.name, *command))
    return found


COMMANDS = documented_commands()


def test_commands_are_found_in_fenced_blocks_inline_spans_and_across_line_breaks():
    text = ("Run `python -m experiments.a --set\nx.y=1` or:\n\n```bash\n"
            "python -m experiments.b --profile smoke  # a comment\n"
            "ENV=1 \\\n  python -m experiments.c --set 'only=[\"a b\"]' && echo done\n"
            "python -m experiments.<name> [--profile smoke|cpu|paper]\n```\n")
    commands = [experiment_argv(line) for line in command_lines(text)]
    assert [c for c in commands if c] == [("b", ["--profile", "smoke"]), ("c", ["--set", 'only=["a b"]']),
                                           ("a", ["--set", "x.y=1"])]


def test_the_readme_real_data_command_and_every_experiments_usage_are_among_those_checked():
    assert ("README.md", "actor_uestc", ["--profile", "paper", "--data-root", "data/uestc", "--set",
                                         "table.data.name=uestc", "table.evaluator.dataset=uestc"]) in COMMANDS
    documented = {name for doc, name, _ in COMMANDS if doc.endswith(".py")}
    assert documented == {module.stem for module in EXPERIMENTS}


@pytest.mark.parametrize("doc, name, argv", COMMANDS, ids=[f"{d}:{n} {' '.join(a)}" for d, n, a in COMMANDS])
def test_documented_command_resolves_its_config(doc, name, argv, capsys):
    module = importlib.import_module(f"experiments.{name}")
    assert module.main([*argv, "--print-config"]) == {}
    assert capsys.readouterr().out.startswith("{")
