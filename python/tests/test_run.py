"""The Python bindings against what the library writes and against analytic references.

Cases:
- the edge crack of examples/edge_crack_2d.toml (strip W = 100 mm × 400 mm, crack a = 30 mm
  from the left edge, steel E = 210 000 MPa, ν = 0.3, plane strain, σ = 100 MPa in two load
  steps), on cells of 2.5 mm (`--set mesh.divisions=[40, 160]`, 0.6 s) instead of 1.25 mm:
  K_I = σ√(πa)·F(0.3) = 1613.7 MPa√mm (Tada's handbook, F = 1.6622), within 1% here
  (0.43% measured);
- the closed inclined crack of examples/inclined_crack_friction_2d.toml at μ = 0.3 (its
  own mesh, 6 s): pressure on the faces σcos²β = 0.5 within 1%, every contact point
  slipping with |Λ| = 1 (the Coulomb limit).
The arrays returned must equal the figures of summary.json written by the same run
(to 1e-12 relative: the same numbers through JSON).
"""

import json
import math
import tomllib

import numpy as np
import pytest

import fissure
from conftest import EXAMPLES

EDGE = EXAMPLES / "edge_crack_2d.toml"
COARSE = {"mesh.divisions": [40, 160]}
KI_TADA = 100.0 * math.sqrt(30.0 * math.pi) * 1.6622


@pytest.fixture(scope="module")
def edge(tmp_path_factory):
    out = tmp_path_factory.mktemp("edge")
    return fissure.run(EDGE, out=out, overrides=COARSE)


def test_edge_crack_summary_is_the_written_summary_json(edge):
    on_disk = json.loads((edge.out / "summary.json").read_text())
    assert edge.summary == on_disk
    assert edge.summary["status"] == "ok"
    assert edge.steps == [s["index"] for s in on_disk["steps"]] == [1, 2]
    assert (edge.out / "sif.csv").is_file() and (edge.out / "edge_crack_2d.pvd").is_file()


def test_edge_crack_sif_table_matches_summary_and_tada(edge):
    sif = edge.sif("edge")
    assert sif.shape == (2,)  # two steps, one tip
    assert list(sif.dtype.names) == list(fissure.SIF_COLUMNS)
    for row, step in zip(sif, edge.summary["steps"]):
        p = step["cracks"][0]["front"][0]
        assert row["step"] == step["index"] and row["point"] == 1
        for col, key in [("K_I", "KI"), ("K_II", "KII"), ("K_III", "KIII"), ("G", "G")]:
            assert row[col] == pytest.approx(p[key], rel=1e-12, abs=1e-12 * abs(p["KI"]))
        assert [row["x"], row["y"]] == pytest.approx(p["x"][:2], rel=1e-12)
    # Linear elasticity: the second step (full load) is twice the first.
    assert sif["K_I"][1] == pytest.approx(2 * sif["K_I"][0], rel=1e-9)
    assert abs(sif["K_I"][1] - KI_TADA) <= 0.01 * KI_TADA
    # The same table by position as by name, and the sif.csv file holds the same numbers.
    assert np.array_equal(edge.sif(0), sif)
    csv = np.genfromtxt(edge.out / "sif.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
    assert np.allclose(csv["K_I"], sif["K_I"], rtol=1e-9)


def test_edge_crack_nodal_displacements(edge):
    mesh = edge.summary["mesh"]
    nodes = edge.nodes
    assert nodes.shape == (mesh["nodes"], 2) == (41 * 161, 2)
    assert nodes[:, 0].min() == 0.0 and nodes[:, 0].max() == 100.0
    assert nodes[:, 1].min() == -200.0 and nodes[:, 1].max() == 200.0
    for step in edge.summary["steps"]:
        u = edge.displacement(step["index"])
        assert u.shape == nodes.shape and np.isfinite(u).all()
        assert np.linalg.norm(u, axis=1).max() == pytest.approx(step["max_displacement"], rel=1e-12)
    assert np.array_equal(edge.displacement(), edge.displacement(2))
    # The supports hold exactly (pin at (0, −200), roller in y at (100, −200)), and the
    # strip stretches: the top edge moves up past every point of the bottom one.
    u = edge.displacement()
    pin = np.flatnonzero((nodes[:, 0] == 0.0) & (nodes[:, 1] == -200.0))
    roller = np.flatnonzero((nodes[:, 0] == 100.0) & (nodes[:, 1] == -200.0))
    assert np.abs(u[pin]).max() == 0.0 and u[roller, 1] == 0.0
    top, bottom = nodes[:, 1] == 200.0, nodes[:, 1] == -200.0
    assert u[top, 1].min() > u[bottom, 1].max()
    with pytest.raises(IndexError):
        edge.displacement(3)


def test_edge_crack_lip_fields_are_consistent(edge):
    f = edge.lip_fields("edge")
    n = f["x"].shape[0]
    assert n > 0
    for name in ["x", "displacement", "jump", "normal"]:
        assert f[name].shape == (n, 2), name
    for name in ["lip", "normal_opening", "tangential_slip"]:
        assert f[name].shape == (n,), name
    assert "pressure" not in f  # no contact on this crack
    plus, minus = f["lip"] == 1, f["lip"] == -1
    assert plus.sum() == minus.sum() == n // 2
    # The same vertices on both lips; the jump is the + displacement minus the − one.
    assert np.allclose(f["x"][plus], f["x"][minus])
    assert np.allclose(f["jump"][plus], f["displacement"][plus] - f["displacement"][minus], atol=1e-15)
    opening = np.einsum("ij,ij->i", f["jump"], f["normal"])
    assert np.allclose(f["normal_opening"], opening, atol=1e-15)
    # Mode I under tension: the crack is open and opens most at the mouth (x = 0).
    scale = np.abs(edge.displacement()).max()
    assert (f["normal_opening"] > -1e-9 * scale).all()
    assert f["x"][np.argmax(f["normal_opening"]), 0] == pytest.approx(0.0, abs=2.5)
    assert edge.lip_fields(0, 1)["normal_opening"].max() == pytest.approx(0.5 * f["normal_opening"].max(), rel=1e-9)


def test_override_changes_the_case_like_set(tmp_path, edge):
    # σ halved by the parameter: K_I halves (linear elasticity).
    r = fissure.run(EDGE, out=tmp_path, overrides={**COARSE, "parameters.sigma": 50.0})
    assert r.sif("edge")["K_I"][-1] == pytest.approx(0.5 * edge.sif("edge")["K_I"][-1], rel=1e-9)


def test_dict_case_runs_like_the_file(tmp_path, edge):
    case = tomllib.loads(EDGE.read_text())
    case["mesh"]["divisions"] = [40, 160]
    r = fissure.run(case, out=tmp_path / "dict", name="edge_dict")
    assert r.summary["status"] == "ok"
    assert r.summary["case"] == str(tmp_path / "dict" / "edge_dict.toml")
    assert (tmp_path / "dict" / "edge_dict.pvd").is_file()
    assert np.allclose(r.sif("edge")["K_I"], edge.sif("edge")["K_I"], rtol=1e-12)
    assert np.array_equal(r.displacement(), edge.displacement())
    # The written text is the case: read back, it is the dict.
    assert tomllib.loads((tmp_path / "dict" / "edge_dict.toml").read_text()) == case
    # Overrides apply to dict cases too.
    r2 = fissure.run(case, out=tmp_path / "dict2", overrides={"parameters.sigma": 200.0})
    assert r2.sif(0)["K_I"][-1] == pytest.approx(2 * edge.sif(0)["K_I"][-1], rel=1e-9)


@pytest.fixture(scope="module")
def inclined(tmp_path_factory):
    out = tmp_path_factory.mktemp("inclined")
    return fissure.run(EXAMPLES / "inclined_crack_friction_2d.toml", out=out,
                       overrides={"cracks.0.contact.friction": 0.3})


def test_inclined_crack_contact_lip_fields_and_table(inclined):
    s = inclined.summary["steps"][-1]["contact"]
    assert s["slip"] == s["points"] > 0 and s["stick"] == 0
    f = inclined.lip_fields("inclined")
    for name in ["lambda", "pressure", "Lambda_norm", "status"]:
        assert f[name].shape == f["lip"].shape, name
    assert f["Lambda"].shape == (f["lip"].shape[0], 2)
    # σ cos²β = 0.5 everywhere on the closed faces, all slipping at the Coulomb limit.
    assert np.allclose(f["pressure"], 0.5, rtol=0.01)
    assert np.allclose(f["lambda"], -f["pressure"])
    assert (f["status"] == 2).all()
    assert np.allclose(f["Lambda_norm"], 1.0, rtol=1e-6)
    assert (np.abs(f["normal_opening"]) < 1e-3 * f["tangential_slip"].max()).all()
    c = inclined.contact("inclined")
    assert c.shape == (1,)
    assert c["slip"][0] == s["slip"] and c["points"][0] == s["points"]
    assert c["lambda_min"][0] == s["lambda_min"] and c["lambda_max"][0] == s["lambda_max"]
    assert c["newton_iterations"][0] == s["iterations"]["newton"]


def test_dict_case_paths_start_from_base(tmp_path, monkeypatch):
    # examples/plate_with_hole.toml reads "../meshes/plate_with_hole.msh", relative to
    # examples/: as a dict, with base = examples/, it runs exactly like the file.
    path = EXAMPLES / "plate_with_hole.toml"
    case = tomllib.loads(path.read_text())
    from_file = fissure.run(path, out=tmp_path / "file")
    from_dict = fissure.run(case, out=tmp_path / "dict", base=EXAMPLES)
    assert np.array_equal(from_dict.displacement(), from_file.displacement())
    assert from_dict.summary["mesh"] == from_file.summary["mesh"]
    # Without base the path starts from the current directory, where there is no mesh.
    monkeypatch.chdir(tmp_path)
    with pytest.raises(fissure.CaseError) as e:
        fissure.run(case, out=tmp_path / "nomesh")
    assert e.value.key == "mesh.file"
    assert "plate_with_hole.msh" in str(e.value)
