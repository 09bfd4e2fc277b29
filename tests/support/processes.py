"""The running processes a fault test looks for (what an interrupted run left behind)."""

from pathlib import Path


def processes_mentioning(text: str) -> dict[int, str]:
    """Process id: command line of the running processes whose command line contains `text`."""
    found = {}
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            command = (entry / "cmdline").read_bytes().replace(b"\0", b" ").decode()
        except OSError:
            continue
        if text in command:
            found[int(entry.name)] = command
    return found
