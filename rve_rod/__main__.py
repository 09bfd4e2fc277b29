"""`python -m rve_rod ...` is the `rve-rod` command (e.g. under
`mpirun -n N python -m mpi4py.futures -m rve_rod surface ... --executor mpi`)."""

import sys

from rve_rod.cli import main

sys.exit(main())
