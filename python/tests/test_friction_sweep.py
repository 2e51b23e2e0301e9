"""The example python/examples/friction_sweep.py: K_II of the closed 45° crack of
examples/inclined_crack_friction_2d.toml (2a = 0.4, σ = 1, plate [-2, 2]², quad4 161²)
against the closed form −σ√(πa)(sinβcosβ − μcos²β), 0 for μ ≥ tanβ, within 1.5% of
σ√(πa) sinβcosβ (the plate is finite: 0.93% measured at μ = 0), every point slipping
below tanβ and sticking above; on four μ of the example's eight (about 25 s)."""

import importlib.util
import math

from conftest import REPO

spec = importlib.util.spec_from_file_location("friction_sweep", REPO / "python" / "examples" / "friction_sweep.py")
friction_sweep = importlib.util.module_from_spec(spec)
spec.loader.exec_module(friction_sweep)


def test_closed_form_sign_and_stick_threshold():
    b = math.radians(45.0)
    e1, e2 = (math.cos(b), math.sin(b)), (-math.sin(b), math.cos(b))
    k = friction_sweep.closed_form_kii
    assert k(0.0, e1, e2, 1.0, 0.2) == -math.sqrt(math.pi * 0.2) * 0.5
    assert math.isclose(k(0.3, e1, e2, 1.0, 0.2), -math.sqrt(math.pi * 0.2) * (0.5 - 0.3 * 0.5))
    assert k(1.0, e1, e2, 1.0, 0.2) == 0.0 and k(1.1, e1, e2, 1.0, 0.2) == 0.0
    # The other tip's frame (e1 and e2 both reversed) gives the same K_II.
    assert k(0.3, [-v for v in e1], [-v for v in e2], 1.0, 0.2) == k(0.3, e1, e2, 1.0, 0.2)


def test_friction_sweep_matches_the_closed_form(tmp_path):
    png = friction_sweep.main(tmp_path, mus=[0.0, 0.3, 0.6, 1.1])
    assert png.is_file() and png.stat().st_size > 10_000
    with open(png, "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"
