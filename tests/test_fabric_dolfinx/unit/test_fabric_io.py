"""Reading the RVE force-strain curve that the tension command plots beside its own."""

import json

import numpy as np
import pytest

from fabric_dolfinx.io.rve_curve import read_rve_curve
from rve_rod.errors import InputError


def test_rve_curve_round_trip(tmp_path):
    path = tmp_path / "rve.json"
    path.write_text(json.dumps({"strain": [0, 0.1, 0.2], "force_gf_per_cm": [0, 12.5, 80.0]}))
    curve = read_rve_curve(path)
    np.testing.assert_array_equal(curve.strain, [0, 0.1, 0.2])
    np.testing.assert_array_equal(curve.force_gf_per_cm, [0, 12.5, 80.0])


@pytest.mark.parametrize(
    ("content", "message"),
    [
        (None, "does not exist"),
        ("{not json", "is not a JSON object"),
        ('{"strain": [0, 1]}', "is not a JSON object"),
        ('{"strain": [0, 0.1], "force_gf_per_cm": [0]}', "must be lists of equal length"),
        ('{"strain": [0, "x"], "force_gf_per_cm": [0, 1]}', "is not a JSON object"),
    ],
)
def test_bad_rve_curve_is_an_input_error(tmp_path, content, message):
    path = tmp_path / "rve.json"
    if content is not None:
        path.write_text(content)
    with pytest.raises(InputError) as error:
        read_rve_curve(path)
    assert message in str(error.value)
