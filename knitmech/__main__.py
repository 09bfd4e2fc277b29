"""`python -m knitmech ...` is the `knitmech` command (e.g. under
`mpirun -n N python -m mpi4py.futures -m knitmech run scene.toml --executor mpi`)."""

import sys

from knitmech.cli import main

sys.exit(main())
