"""Errors come out as Python exceptions naming the key (and the line when there is one);
no bad input panics, and a panic itself is caught before it can abort the interpreter."""

import math
import tomllib

import pytest

import fissure
from conftest import EXAMPLES

EDGE = EXAMPLES / "edge_crack_2d.toml"


def small_case():
    """The edge-crack case as a dict on a coarse mesh (0.6 s)."""
    case = tomllib.loads(EDGE.read_text())
    case["mesh"]["divisions"] = [20, 80]
    return case


def test_wrong_value_in_a_file_names_its_key_and_line(tmp_path):
    text = EDGE.read_text().replace("nu = 0.3", "nu = 0.7")
    line = text.splitlines().index("nu = 0.7") + 1
    bad = tmp_path / "bad.toml"
    bad.write_text(text)
    with pytest.raises(fissure.CaseError) as e:
        fissure.run(bad, out=tmp_path / "out")
    err = e.value
    assert err.key == "materials[0].nu"
    assert err.line == line
    assert err.file == str(bad)
    assert f"{bad}:{line}: key 'materials[0].nu'" in str(err)
    assert isinstance(err, fissure.FissureError) and not isinstance(err, fissure.PanicError)


def test_unknown_key_in_a_dict_names_it_and_its_line_in_the_written_text(tmp_path):
    case = small_case()
    case["cracks"][0]["sif_raduis"] = 6.0
    with pytest.raises(fissure.CaseError) as e:
        fissure.run(case, out=tmp_path, name="typo")
    err = e.value
    assert err.key == "cracks[0].sif_raduis"
    assert "sif_radius" in err.message  # the suggestion
    written = (tmp_path / "typo.toml").read_text().splitlines()
    assert err.line is not None and written[err.line - 1].startswith("sif_raduis")


def test_override_with_a_wrong_type_names_the_override(tmp_path):
    with pytest.raises(fissure.CaseError) as e:
        fissure.run(EDGE, out=tmp_path, overrides={"cracks.0.tip_radius": "wide"})
    assert e.value.key == "cracks[0].tip_radius"
    assert str(e.value).startswith("--set cracks.0.tip_radius=")
    assert e.value.line is None


def test_override_of_an_unknown_key_names_it(tmp_path):
    with pytest.raises(fissure.CaseError) as e:
        fissure.run(EDGE, out=tmp_path, overrides={"cracks.0.contact.frction": 0.3})
    assert "cracks[0].contact" in e.value.key
    assert "frction" in str(e.value)
    with pytest.raises(fissure.CaseError) as e:
        fissure.run(EDGE, out=tmp_path, overrides={"cracks.3.tip_radius": 1.0})
    assert "cracks.3" in str(e.value)


def test_missing_case_file(tmp_path):
    with pytest.raises(fissure.CaseError, match="cannot read the case file"):
        fissure.run(tmp_path / "nowhere.toml", out=tmp_path)


@pytest.mark.parametrize(
    "edit, key",
    [
        (lambda c: c["mesh"].update(divisions=[0, 80]), "mesh.divisions"),
        (lambda c: c["mesh"].update(divisions=[10**30, 80]), "mesh.divisions[0]"),
        (lambda c: c["mesh"].update(upper=[math.nan, 200.0]), "mesh.upper"),
        (lambda c: c["materials"][0].update(E=-1.0), "materials[0].E"),
        (lambda c: c["materials"][0].update(E=None), "materials[0].E"),
        (lambda c: c["materials"][0].update(E=object()), "materials[0].E"),
        (lambda c: c["traction"][0].update(value=[0.0, "sigma *"]), "traction[0].value"),
        (lambda c: c["cracks"][0].update(tip=[30.0]), "cracks[0].tip"),
        (lambda c: c["cracks"][0].update(direction=[0.0, 0.0]), "cracks[0]"),
        (lambda c: c["cracks"][0].update(sif_radius=-1.0), "cracks[0].sif_radius"),
        (lambda c: c["cracks"][0].update(shape="circle"), "cracks[0].shape"),
        (lambda c: c["dirichlet"][0].update(group="nowhere"), "dirichlet[0].group"),
        (lambda c: c.update(steps={"count": 10**9}), "steps.count"),
    ],
)
def test_bad_input_raises_a_case_error_naming_the_key_never_a_panic(tmp_path, edit, key):
    case = small_case()
    edit(case)
    with pytest.raises(fissure.CaseError) as e:
        fissure.run(case, out=tmp_path)
    assert e.value.key.startswith(key), (e.value.key, str(e.value))
    assert not isinstance(e.value, fissure.PanicError)


def test_an_unconstrained_model_is_a_solve_error(tmp_path):
    case = small_case()
    del case["dirichlet"]
    with pytest.raises(fissure.SolveError, match="rigid"):
        fissure.run(case, out=tmp_path)


def test_a_rust_panic_becomes_a_python_exception():
    with pytest.raises(fissure.PanicError, match="guard check"):
        fissure._native._panic_for_test("guard check")
    # The interpreter and the library go on working after it.
    assert fissure.to_toml({"a": {"b": 1}}) == "[a]\nb = 1\n"


def test_to_toml_maps_dicts_lists_and_scalars():
    text = fissure.to_toml({"mesh": {"divisions": [2, 3], "cell": "quad4"}, "cracks": [{"name": "a"}, {"name": "b"}],
                            "output": {"vtu": False}, "parameters": {"p": 1.5}})
    assert tomllib.loads(text) == {"mesh": {"divisions": [2, 3], "cell": "quad4"},
                                   "cracks": [{"name": "a"}, {"name": "b"}],
                                   "output": {"vtu": False}, "parameters": {"p": 1.5}}
    with pytest.raises(fissure.CaseError) as e:
        fissure.to_toml({"mesh": {1: 2}})
    assert e.value.key == "mesh"
