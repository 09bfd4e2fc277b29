"""Design: from a target behaviour to the knit (`knitmech design`, docs/design.md).

- `family`: a knit's response surfaces interpolated in the stitch value (NumPy);
- `solve`: bounded least squares over the design variables (scipy), evaluations counted;
- `material`: the stitch value whose uniaxial curves fit target curves;
- `sleeve`: a compression sleeve's course bands on a limb and the Laplace model of its
  pressure; its design (stitch values and needles per band);
- `spec`: the design file ([design], [sleeve]); `run`: the job and its results folder;
  `plot`: target against achieved.

The contact model that verifies a sleeve (DOLFINx) is the `sleeve` job, `knitmech.jobs.sleeve`.
"""
