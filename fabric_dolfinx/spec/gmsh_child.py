"""`python -m fabric_dolfinx.spec.gmsh_child REQUEST RESULT`: the scene check's meshing of a
part in a process of its own (`fabric_dolfinx.spec.contents.part_contents`), so that gmsh
crashing does not take the tool with it. REQUEST is JSON (mesh: a MeshSpec's fields, plane);
RESULT an `.npz` file: `names` (JSON [curves, surfaces]), `centres_<i>` per surface and
`corners`. Exit 0, or 2 with the InputError's message as the last line of stderr.
"""

import json
import sys

import numpy as np

from fabric_dolfinx.spec.contents import read_part_contents
from fabric_dolfinx.spec.part import MeshSpec
from rve_rod.errors import InputError

__all__ = [
    "main",
]


def main(argv: list[str]) -> int:
    """Mesh and check the part of the request; write the result file. Returns the status."""
    request, result = json.loads(argv[0]), argv[1]
    try:
        contents = read_part_contents(MeshSpec(**request["mesh"]), plane=request["plane"])
    except InputError as error:
        print(str(error).replace("\n", " "), file=sys.stderr)
        return 2
    centres = {f"centres_{i}": contents.centres[s] for i, s in enumerate(contents.surfaces)}
    names = np.array(json.dumps([contents.curves, contents.surfaces]))
    np.savez(result, names=names, corners=contents.corners, **centres)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
