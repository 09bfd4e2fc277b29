"""`python -m rve_rod ...` is the `rve-rod` command (e.g. under
`mpirun -n N python -m mpi4py.futures -m rve_rod surface ... --executor mpi`)."""

import sys

from rve_rod.cli import main

# the guard: mpi4py.futures workers import the driver's main module as "__mp_main__"
if __name__ == "__main__":
    sys.exit(main())
