"""`python -m knitmech.jobs KIND REQUEST.json FOLDER SUMMARY.json` (see `knitmech.jobs`)."""

import json
import sys
from pathlib import Path

from knitmech.jobs.launch import job_runner


def main(argv: list[str]) -> int:
    """Run the job `kind` of the request file on every rank; rank 0 writes the summary."""
    from mpi4py import MPI  # noqa: PLC0415 (MPI only in the job's processes)

    kind, request, folder, summary_path = argv
    summary = job_runner(kind)(json.loads(Path(request).read_text()), Path(folder), MPI.COMM_WORLD)
    if MPI.COMM_WORLD.rank == 0:
        Path(summary_path).write_text(json.dumps(summary))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
