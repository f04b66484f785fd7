# SPDX-License-Identifier: AGPL-3.0-or-later
"""palpa.Material and palpa.quantity: the registry's models from Python,
round trips through material files, and every bad input a clear exception."""
import json
import math

import numpy as np
import pytest

import palpa


def test_quantity_converts_to_si():
    assert palpa.quantity("12 kPa") == 12000.0
    assert palpa.quantity("3 mm", "length") == pytest.approx(3e-3)
    assert palpa.quantity("0.45") == 0.45
    with pytest.raises(palpa.InputError, match="pressure"):
        palpa.quantity("3 mm", "pressure")
    with pytest.raises(palpa.InputError, match="unknown unit"):
        palpa.quantity("3 furlongs")


def test_material_from_parameters_with_units_or_si():
    a = palpa.Material("neo-hookean", E="12 kPa", nu=0.45)
    b = palpa.Material("neo-hookean", E=12000.0, nu=0.45)
    assert a.parameters == b.parameters == {"E": 12000.0, "nu": 0.45}
    small = a.small_strain()
    assert small["E"] == pytest.approx(12000.0, rel=1e-9)
    assert small["nu"] == pytest.approx(0.45, rel=1e-9)
    v = palpa.Material("neo-hookean-volume", E="10 kPa", nu=0.45)
    assert v.parameters["volume_share"] == 0.5  # the default
    o = palpa.Material("ogden", mu=["6 kPa", "-0.5 kPa"], alpha=[4.7, -2], nu=0.45)
    np.testing.assert_array_equal(o.parameters["mu"], [6000.0, -500.0])
    i = palpa.Material("neo-hookean-isochoric", E="13 kPa", nu=0.3)
    assert i.parameters["C10"] == pytest.approx(2500.0)
    assert set(palpa.models()) >= {"neo-hookean", "ogden", "spline", "yeoh"}
    assert palpa.models()["stvk"]["fittable"] is False


def test_material_file_round_trip_is_exact(tmp_path):
    m = palpa.Material("mooney-rivlin", C10="1.5 kPa", C01="0.4 kPa", D1="2e-5 1/Pa")
    path = tmp_path / "m.json"
    m.save(path)  # a pathlib.Path, as a str below
    back = palpa.Material.load(path)
    assert back.model == "mooney-rivlin"
    assert back.parameters == m.parameters
    assert json.loads(path.read_text())["parameters"]["C10"] == "1.5 kPa"
    # A spline material round-trips through its knots and values too.
    s = palpa.Material.load(str(tmp_path / "m.json"))
    knots = np.array([0.5, 0.8, 1.0, 1.3, 2.0])
    spline = palpa.Material("spline", f={"knots": knots, "values": 1e3 * (knots - 1) ** 2},
                            g={"knots": knots, "values": 0 * knots}, h={"knots": knots, "values": 5e3 * (knots - 1) ** 2})
    spline.save(str(tmp_path / "s.json"))
    again = palpa.Material.load(str(tmp_path / "s.json"))
    np.testing.assert_array_equal(again.parameters["f"]["values"], spline.parameters["f"]["values"])
    assert s.model == "mooney-rivlin"


def test_energy_and_stress_are_vectorized_and_consistent():
    m = palpa.Material("yeoh", C10="2 kPa", C20="0.3 kPa", D1="1e-5 1/Pa")
    rng = np.random.default_rng(3)
    stretches = rng.uniform(0.7, 1.4, size=(50, 3))
    psi = m.energy(stretches)
    stress = m.stress(stretches)
    assert psi.shape == (50,) and stress.shape == (50, 3)
    assert m.energy([[1.0, 1.0, 1.0]])[0] == pytest.approx(0.0, abs=1e-9)
    # The stress is the energy's derivative (central differences, h = 1e-6).
    h = 1e-6
    for k in range(3):
        e = np.zeros(3)
        e[k] = h
        fd = (m.energy(stretches + e) - m.energy(stretches - e)) / (2 * h)
        np.testing.assert_allclose(stress[:, k], fd, rtol=1e-6, atol=1e-6)
    # Fortran order, a strided view and int arrays read the same numbers.
    np.testing.assert_array_equal(m.energy(np.asfortranarray(stretches)), psi)
    np.testing.assert_array_equal(m.energy(np.repeat(stretches, 2, axis=0)[::2]), psi)
    np.testing.assert_array_equal(m.energy(np.ones((2, 3), dtype=np.int32)), [0.0, 0.0])
    np.testing.assert_array_equal(m.energy(stretches.astype(np.float32)), m.energy(stretches.astype(np.float32).astype(np.float64)))


def test_uniaxial_curve_is_traction_free_laterally():
    m = palpa.Material("neo-hookean", E="12 kPa", nu=0.45)
    c = m.curve("uniaxial", np.linspace(0.8, 1.2, 5))
    assert c["nominal"][2] == pytest.approx(0.0, abs=1e-6)  # stretch 1
    assert c["nominal"][-1] > 0 > c["nominal"][0]
    assert np.all(c["lateral"][:2] > 1.0)


@pytest.mark.parametrize("call, error, message", [
    (lambda: palpa.Material("rubber"), palpa.InputError, "unknown model 'rubber'"),
    (lambda: palpa.Material("neo-hookean", E="12 kPa"), palpa.InputError, "needs nu"),
    (lambda: palpa.Material("neo-hookean", E="12 kPa", nu=0.45, C10=1.0), palpa.InputError, "C10 does not apply"),
    (lambda: palpa.Material("neo-hookean", E="12 mm", nu=0.45), palpa.InputError, "not a pressure"),
    (lambda: palpa.Material("neo-hookean", E=-1.0, nu=0.45), palpa.InputError, "must be positive"),
    (lambda: palpa.Material("neo-hookean", E=float("nan"), nu=0.45), palpa.InputError, "finite"),
    (lambda: palpa.Material("neo-hookean", E=[1.0], nu=0.45), TypeError, "E"),
    (lambda: palpa.Material("neo-hookean", E=True, nu=0.45), TypeError, "bool"),
    (lambda: palpa.Material("ogden", mu="6 kPa", alpha=[2], nu=0.4), TypeError, "list"),
    (lambda: palpa.Material("spline", f=1.0, g={}, h={}), TypeError, "knots"),
    (lambda: palpa.Material.load("/nonexistent/m.json"), palpa.InputError, "m.json"),
])
def test_bad_material_input_raises_clearly(call, error, message):
    with pytest.raises(error, match=message):
        call()


@pytest.mark.parametrize("stretches, error, message", [
    (np.ones((4, 2)), palpa.InputError, r"shape \(4, 2\)"),
    (np.ones(3), palpa.InputError, r"shape \(3\)"),
    (np.ones((0, 3)), palpa.InputError, "empty"),
    (np.array([[1.0, math.nan, 1.0]]), palpa.InputError, "finite"),
    (np.array([[1 + 1j, 1, 1]]), TypeError, "complex"),
    (np.array([["a", "b", "c"]]), TypeError, "dtype"),
    (np.ones((2, 3), dtype=bool), TypeError, "bool"),
    ("1,1,1", TypeError, "dtype"),
])
def test_bad_arrays_are_refused_never_misread(stretches, error, message):
    m = palpa.Material("neo-hookean", E="12 kPa", nu=0.45)
    with pytest.raises(error, match=message):
        m.energy(stretches)


def test_threads_and_log_level_settings():
    palpa.set_threads(1)
    assert palpa.threads() == 1
    palpa.set_threads(0)
    assert palpa.threads() >= 1
    palpa.set_log_level("warning")
    palpa.set_log_level("info")
    with pytest.raises(palpa.InputError, match="unknown log level 'loud'"):
        palpa.set_log_level("loud")
    with pytest.raises(palpa.InputError, match="threads"):
        palpa.set_threads(-1)


def test_a_message_quoting_bytes_that_are_not_utf8_is_kept(tmp_path):
    path = tmp_path / "latin.json"
    path.write_bytes(b'{"palpa_material": 1, "model": "rub\xffber", "parameters": {}}')
    with pytest.raises(palpa.InputError) as caught:
        palpa.Material.load(path)
    message = str(caught.value)
    assert "latin.json" in message and "UTF-8" in message, message
    assert "\ufffd" in message  # the byte shown as a replacement character
