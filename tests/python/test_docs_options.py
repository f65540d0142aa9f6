"""--help and docs/commands.md agree: every long option a command's --help
lists is in that command's option table in docs/commands.md, and every
option a table documents is one the command has. Both sides are read as a
user reads them: the option names of CLI11's help text, and the first column
of the tables under each command's `## <command>` heading."""
import re

import pytest

from conftest import ROOT, run_cli

COMMANDS_MD = ROOT / "docs" / "commands.md"
LONG_OPTION = re.compile(r"--[a-z][a-z0-9-]*")


def help_commands():
    """The subcommands `texbake --help` lists, `cameras` as `cameras check`."""
    r = run_cli("--help")
    assert r.returncode == 0, r.stderr
    section = r.stdout[r.stdout.lower().index("subcommands:"):]
    names = re.findall(r"^  ([a-z]+)\s", section, re.M)
    assert names, r.stdout
    return ["cameras check" if n == "cameras" else n for n in names]


def help_options(command):
    """The long options of `texbake <command> --help` (--help itself left out)."""
    r = run_cli(*command.split(), "--help")
    assert r.returncode == 0, r.stderr
    options = set()
    for line in r.stdout.splitlines():
        # An option line starts with its names: "  -o,--output TEXT ..." or
        # "  --size N ..."; descriptions and wrapped lines do not start with "-".
        m = re.match(r"  (-[^\s]*(?:,\s*-[^\s]*)*)", line)
        if m:
            options.update(LONG_OPTION.findall(m.group(1)))
    options.discard("--help")
    return options


def doc_sections():
    """{command: set of long options in the first column of its tables}."""
    sections = {}
    current = None
    for line in COMMANDS_MD.read_text().splitlines():
        heading = re.match(r"## (.+)$", line)
        if heading:
            current = heading.group(1).strip().strip("`")
            sections[current] = set()
        elif current and line.startswith("|") and not line.startswith("|---"):
            first_cell = re.split(r"(?<!\\)\|", line)[1]  # "\|" is a | in a cell
            sections[current].update(LONG_OPTION.findall(first_cell))
    return sections


def test_every_command_has_a_section():
    sections = doc_sections()
    missing = [c for c in help_commands() if c not in sections]
    assert not missing, f"no `## <command>` section in docs/commands.md for {missing}"


@pytest.mark.parametrize("command", ["bake", "fit", "map", "render", "compare", "info", "batch",
                                     "cameras check"])
def test_help_and_docs_list_the_same_options(command):
    documented = doc_sections()[command]
    helped = help_options(command)
    assert helped, f"texbake {command} --help lists no options"
    assert not helped - documented, (
        f"texbake {command}: options in --help but not in docs/commands.md: "
        f"{sorted(helped - documented)}")
    assert not documented - helped, (
        f"texbake {command}: options in docs/commands.md that --help does not have: "
        f"{sorted(documented - helped)}")


def test_the_parametrised_list_is_every_command():
    # A new command must be added to the list above (and to the docs).
    assert sorted(help_commands()) == sorted(
        ["bake", "fit", "map", "render", "compare", "info", "batch", "cameras check"])
