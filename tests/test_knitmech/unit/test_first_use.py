"""First use (issue 19): `--help` shows every option's default and the valid stitch values, and
the README and docs link only to files a clone has (they once sent readers to
`../shared/reference`, which exists only beside the developers' checkout)."""

import argparse
import re
from pathlib import Path

import pytest

import fabric_dolfinx.cli
import knitmech.cli
import rve_rod.cli
from rve_rod.presets import preset_names, stitch_values

ROOT = Path(__file__).resolve().parents[3]
PARSERS = {
    "rve-rod": rve_rod.cli.build_parser,
    "fabric-dolfinx": fabric_dolfinx.cli.build_parser,
    "knitmech": knitmech.cli.build_parser,
}


def subcommands(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    found = {}
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            found.update(action.choices)
    return found


COMMANDS = [
    (tool, name, sub)
    for tool, build in PARSERS.items()
    for name, sub in subcommands(build()).items()
]


@pytest.mark.parametrize("tool, name, parser", COMMANDS, ids=[f"{t} {n}" for t, n, _ in COMMANDS])
def test_help_shows_the_default_of_every_option(tool, name, parser):
    text = " ".join(parser.format_help().split())
    for action in parser._actions:
        default = action.default
        if not action.option_strings or default in (None, False, argparse.SUPPRESS):
            continue
        option = max(action.option_strings, key=len)
        shown = f"(default: {default})" in text or "default" in (action.help or "")
        assert shown, f"{tool} {name} --help: {option} does not show its default {default!r}"


def test_help_lists_the_valid_stitch_values():
    parser = subcommands(rve_rod.cli.build_parser())["geometry"]
    text = " ".join(parser.format_help().split())
    listed = [preset for preset in preset_names() if stitch_values(preset)]
    assert listed
    for preset in listed:
        values = ", ".join(f"{value:g}" for value in stitch_values(preset))
        assert f"{preset}: {values}" in text


LINK = re.compile(r"\]\(([^)\s]+)\)")


@pytest.mark.parametrize(
    "document",
    [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))],
    ids=lambda path: path.name,
)
def test_every_relative_link_of_the_docs_exists_in_a_clone(document):
    text = document.read_text()
    assert "shared/reference" not in text
    for target in LINK.findall(text):
        if re.match(r"[a-z]+:", target) or target.startswith("#"):
            continue
        path = (document.parent / target.split("#")[0]).resolve()
        assert path.exists(), f"{document.name} links to {target}, which a clone does not have"
        assert ROOT in path.parents, f"{document.name} links outside the project: {target}"
