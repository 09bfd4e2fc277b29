"""The surface file: exact round trip, a clear error for every kind of bad file, atomic writes."""

import json
import subprocess
import sys
import textwrap

import h5py
import numpy as np
import pytest

from rve_rod.errors import InputError
from rve_rod.geometry.bspline import open_knot_vector
from rve_rod.surface import (
    FitSamples,
    ResponseSurface,
    Spline1D,
    Spline2D,
    SurfaceFileError,
    energy_surface,
    read_surface,
    write_surface,
)
from rve_rod.surface import hdf5 as surface_file

RNG = np.random.default_rng(3)
DOMAIN = ((-0.1, 0.2), (-0.05, 0.25))


def spline2d(orders=(1, 1), degrees=(2, 2), shape=(6, 7)):
    knots = tuple(open_knot_vector(p, n, d) for p, n, d in zip(degrees, shape, DOMAIN, strict=True))
    return Spline2D(degrees, knots, RNG.normal(size=shape), orders)


def samples(width, m=25):
    inputs = RNG.uniform(-0.05, 0.2, (m, width))
    values = RNG.normal(size=m)
    return FitSamples(inputs, values, 1e-3 * RNG.normal(size=m))


def stress_surface():
    s12 = Spline1D(2, open_knot_vector(2, 8, (-0.3, 0.3)), RNG.normal(size=8))
    return ResponseSurface(
        kind="stress",
        s11=spline2d(),
        s22=spline2d(),
        s12=s12,
        samples={"S11": samples(2), "S22": samples(2), "S12": samples(1, 16)},
        parameters={"fabric": {"wale_width": 1.33, "course_height": 1.26}, "rays": 13},
    )


def energy_kind_surface():
    psi = spline2d(orders=(2, 2), degrees=(3, 3))
    psi_shear = Spline1D(3, open_knot_vector(3, 9, (-0.3, 0.3)), RNG.normal(size=9), 2)
    return energy_surface(psi, psi_shear, samples={"S11": samples(2)}, parameters={"kind": 1})


def assert_same_spline(a, b):
    assert type(a) is type(b)
    if isinstance(a, Spline1D):
        assert (a.degree, a.extension_order) == (b.degree, b.extension_order)
        np.testing.assert_array_equal(a.knots, b.knots)
    else:
        assert (a.degrees, a.extension_orders) == (b.degrees, b.extension_orders)
        for ka, kb in zip(a.knots, b.knots, strict=True):
            np.testing.assert_array_equal(ka, kb)
    np.testing.assert_array_equal(a.coefficients, b.coefficients)


@pytest.mark.parametrize("make", [stress_surface, energy_kind_surface])
def test_round_trip_is_exact(tmp_path, make):
    original = make()
    path = write_surface(tmp_path / "surface.h5", original)
    loaded = read_surface(path)
    assert loaded.kind == original.kind
    assert loaded.parameters == original.parameters
    assert loaded.generator["package"] == "knitmech" and "version" in loaded.generator
    assert loaded.created.endswith("+00:00")
    for name, spline in original.groups().items():
        assert_same_spline(spline, loaded.groups()[name])
    assert set(loaded.samples) == set(original.samples)
    for name, group_samples in original.samples.items():
        for member in ("inputs", "values", "residuals"):
            np.testing.assert_array_equal(
                getattr(loaded.samples[name], member), getattr(group_samples, member)
            )
    E = RNG.uniform(-0.5, 0.5, (50, 3))
    np.testing.assert_array_equal(loaded.stress(E).S, original.stress(E).S)
    with h5py.File(path) as h5:
        assert h5.attrs["units"].startswith("E: 1 (Green-Lagrange)")
        group = h5["S11"]
        stats = original.samples["S11"].stats()
        assert group.attrs["residual_max_abs"] == stats.max_abs
        expected_max_rel = (
            np.abs(original.samples["S11"].residuals).max()
            / np.abs(original.samples["S11"].values).max()
        )
        assert group.attrs["residual_max_rel"] == pytest.approx(expected_max_rel, rel=1e-14)
        np.testing.assert_array_equal(group["domain"][()], np.array(DOMAIN))


def write_then_edit(tmp_path, edit):
    path = write_surface(tmp_path / "surface.h5", stress_surface())
    with h5py.File(path, "r+") as h5:
        edit(h5)
    return path


def expect_error(path, *fragments):
    with pytest.raises(SurfaceFileError) as info:
        read_surface(path)
    message = str(info.value)
    assert str(path) in message
    for fragment in fragments:
        assert fragment in message
    assert isinstance(info.value, InputError)


def test_truncated_file(tmp_path):
    path = write_surface(tmp_path / "surface.h5", stress_surface())
    data = path.read_bytes()
    for size in (len(data) // 2, len(data) - 100):
        cut = tmp_path / f"cut{size}.h5"
        cut.write_bytes(data[:size])
        expect_error(cut, "truncated or corrupt")
    tiny = tmp_path / "tiny.h5"
    tiny.write_bytes(data[:4])
    expect_error(tiny, "not an HDF5 file")


def test_other_formats(tmp_path):
    text = tmp_path / "surface.json"
    text.write_text(json.dumps({"S11": [1, 2, 3]}))
    expect_error(text, "not an HDF5 file")
    plain = tmp_path / "plain.h5"
    with h5py.File(plain, "w") as h5:
        h5["data"] = np.arange(3)
    expect_error(plain, "not a response-surface file", "no 'format' attribute")
    other = write_then_edit(tmp_path, lambda h5: h5.attrs.__setitem__("format", "xdmf-mesh"))
    expect_error(other, "not a response-surface file", "xdmf-mesh")
    expect_error(tmp_path / "missing.h5", "no such file")


def test_wrong_version(tmp_path):
    path = write_then_edit(tmp_path, lambda h5: h5.attrs.__setitem__("version", 2))
    expect_error(path, "version 2 is not supported", "version 1")


def test_missing_group_member_and_attribute(tmp_path):
    path = write_then_edit(tmp_path, lambda h5: h5.__delitem__("S22"))
    expect_error(path, "missing group 'S22'")
    path = write_then_edit(tmp_path, lambda h5: h5["S12"].__delitem__("coefficients"))
    expect_error(path, "group S12", "missing member 'coefficients'")
    path = write_then_edit(tmp_path, lambda h5: h5["S11"].__delitem__("samples"))
    expect_error(path, "group S11", "missing member 'samples'")
    path = write_then_edit(tmp_path, lambda h5: h5.attrs.__delitem__("parameters"))
    expect_error(path, "missing attribute 'parameters'")
    path = write_then_edit(tmp_path, lambda h5: h5.attrs.__setitem__("kind", "energy"))
    expect_error(path, "missing group 'psi'")
    path = write_then_edit(tmp_path, lambda h5: h5.attrs.__setitem__("parameters", "[1, 2]"))
    expect_error(path, "must hold JSON objects")
    path = write_then_edit(tmp_path, lambda h5: h5.attrs.__setitem__("generator", "{oops"))
    expect_error(path, "not valid JSON")


def test_inconsistent_members(tmp_path):
    def bad_knots(h5):
        del h5["S11/knots_E11"]
        h5["S11/knots_E11"] = np.linspace(0, 1, 9)

    expect_error(write_then_edit(tmp_path, bad_knots), "group S11", "open")

    def bad_shape(h5):
        del h5["S22/coefficients"]
        h5["S22/coefficients"] = np.zeros((6, 6))

    expect_error(write_then_edit(tmp_path, bad_shape), "group S22", "shape (6, 6)")

    def bad_domain(h5):
        h5["S12/domain"][...] = [[-0.3, 0.31]]

    expect_error(write_then_edit(tmp_path, bad_domain), "group S12", "domain")

    def bad_order(h5):
        h5["S11"].attrs["extension_order"] = np.array([1, 2])

    expect_error(write_then_edit(tmp_path, bad_order), "extension orders (1, 2)")


def test_energy_file_with_tampered_stress_is_rejected(tmp_path):
    path = write_surface(tmp_path / "energy.h5", energy_kind_surface())
    with h5py.File(path, "r+") as h5:
        h5["S11/coefficients"][0, 0] += 1.0
    expect_error(path, "S11 is not the derivative of the potential")


def test_exception_while_writing_leaves_old_file_and_no_temporary(tmp_path, monkeypatch):
    path = tmp_path / "surface.h5"
    first = stress_surface()
    write_surface(path, first)
    before = path.read_bytes()

    def failing_group(group, name, spline, samples):
        raise RuntimeError("disk full")

    monkeypatch.setattr(surface_file, "_write_group", failing_group)
    with pytest.raises(RuntimeError, match="disk full"):
        write_surface(path, stress_surface())
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["surface.h5"]
    with pytest.raises(RuntimeError):
        write_surface(tmp_path / "new.h5", stress_surface())
    assert not (tmp_path / "new.h5").exists()


def test_writer_killed_midway_leaves_no_final_file(tmp_path):
    # The child process SIGKILLs itself after writing the first group: no final file appears.
    code = textwrap.dedent(
        """
        import os, signal, sys
        import numpy as np
        from rve_rod import surface
        from rve_rod.geometry.bspline import open_knot_vector
        from rve_rod.surface import hdf5

        original = hdf5._write_group

        def write_then_die(group, name, spline, samples):
            original(group, name, spline, samples)
            group.file.flush()
            os.kill(os.getpid(), signal.SIGKILL)

        hdf5._write_group = write_then_die
        knots = open_knot_vector(2, 5, (0.0, 0.2))
        s11 = surface.Spline2D((2, 2), (knots, knots), np.ones((5, 5)))
        s12 = surface.Spline1D(2, open_knot_vector(2, 5, (-0.3, 0.3)), np.zeros(5))
        result = surface.ResponseSurface("stress", s11, s11, s12)
        surface.write_surface(sys.argv[1], result)
        """
    )
    target = tmp_path / "surface.h5"
    completed = subprocess.run([sys.executable, "-c", code, str(target)], check=False)
    assert completed.returncode == -9
    assert not target.exists()
    leftovers = list(tmp_path.iterdir())
    assert len(leftovers) == 1 and leftovers[0].name.startswith(".surface.h5.")


def test_parameters_must_be_json(tmp_path):
    surface = stress_surface()
    bad = ResponseSurface(
        kind="stress",
        s11=surface.s11,
        s22=surface.s22,
        s12=surface.s12,
        parameters={"value": np.nan},
    )
    with pytest.raises(InputError, match="JSON"):
        write_surface(tmp_path / "bad.h5", bad)
    assert list(tmp_path.iterdir()) == []


def test_reader_imports_without_numba_matplotlib_dolfinx():
    code = (
        "import sys, rve_rod.surface; "
        "print(sorted(m for m in ('numba', 'matplotlib', 'dolfinx', 'ufl') if m in sys.modules))"
    )
    output = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    )
    assert output.stdout.strip() == "[]"
