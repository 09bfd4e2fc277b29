"""Shared test settings: non-interactive plotting, Open MPI allowed as root."""

import os

os.environ.setdefault("MPLBACKEND", "Agg")
os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
