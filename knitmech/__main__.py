"""`python -m knitmech ...` is the `knitmech` command (e.g. under
`mpirun -n N python -m mpi4py.futures -m knitmech run scene.toml --executor mpi`)."""

import sys

from knitmech.cli import main

# the guard: mpi4py.futures workers import the driver's main module as "__mp_main__"
if __name__ == "__main__":
    sys.exit(main())
