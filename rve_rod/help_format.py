"""The `--help` format of the three command-line tools (`rve-rod`, `fabric-dolfinx`,
`knitmech`): every option's default is shown."""

import argparse

__all__ = [
    "HelpFormatter",
]


class HelpFormatter(argparse.HelpFormatter):
    """`--help` shows the default of every option that has one (not None, not a flag's False),
    unless its help text names it already; the formatter of all three tools."""

    def _get_help_string(self, action: argparse.Action) -> str:
        text = action.help or ""
        default = action.default
        if (
            "%(default)" in text
            or "default" in text
            or default is None
            or default is False
            or default is argparse.SUPPRESS
            or not action.option_strings
        ):
            return text
        return f"{text} (default: %(default)s)"
