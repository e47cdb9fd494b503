"""Cases from Python: reading, setting keys, and the errors of bad input (CaseError with
the key, the value and the command line's text)."""

import copy
import math
import subprocess

import numpy as np
import pytest

import hopperflow as hf


def test_paper_case_is_the_base_case():
    case = hf.Case.paper()
    # Table 1 of the paper: D = 30 mm, L = 100 mm, 3000 spheres of 3 mm.
    assert case["geometry.outlet_width"] == 0.03
    assert case["geometry.width"] == 0.1
    assert case["particles.count"] == 3000
    assert case["particles"]["diameter"] == 0.003


def test_setting_a_key_changes_the_case_and_is_kept_as_an_override():
    case = hf.Case.paper()
    case["geometry.outlet_width"] = 0.045
    assert case["geometry.outlet_width"] == 0.045
    assert case.overrides == ["geometry.outlet_width=0.045"]
    # The resolved text reads back to an equal case.
    assert hf.Case.from_toml(case.to_toml()) == case


def test_numpy_scalars_are_accepted_as_their_python_values():
    case = hf.Case.paper()
    case["geometry.outlet_width"] = np.float64(0.04)
    case["particles.count"] = np.int64(2000)
    case["contact.normal_clamp"] = np.bool_(True)
    assert case["geometry.outlet_width"] == 0.04
    assert case["particles.count"] == 2000
    assert case["contact.normal_clamp"] is True


def test_gravity_reads_for_every_case_and_sets_like_any_key():
    # The resolved text leaves out the default g; the case still answers it.
    case = hf.Case.paper()
    assert case["gravity"] == 9.81
    assert "gravity" not in case.to_toml()
    case["gravity"] = 9.8
    assert case["gravity"] == 9.8
    assert "gravity = 9.8" in case.to_toml()
    assert hf.Case.from_dict(case.to_dict()) == case
    with pytest.raises(hf.CaseError) as info:
        case["gravity"] = -9.81
    assert info.value.key == "gravity" and "(0, 1000]" in str(info.value)


def test_from_dict_takes_nested_and_dotted_keys():
    case = hf.Case.from_dict({"geometry": {"outlet_width": 0.04}, "particles.count": 500})
    assert case["geometry.outlet_width"] == 0.04
    assert case["particles.count"] == 500


def test_load_reads_a_case_file(tiny):
    case = hf.Case.load(str(tiny))
    assert case["particles.count"] == 250
    assert case.check() is case


def test_to_toml_matches_the_cli_check(cli, tiny):
    # `hopperflow check FILE` prints the resolved case: the same text.
    out = subprocess.run([str(cli), "check", str(tiny)], check=True, capture_output=True, text=True).stdout
    assert hf.Case.load(str(tiny)).to_toml() == out


def test_update_sets_dependent_keys_together():
    case = hf.Case.paper()
    # A 150 mm outlet fits only a wider hopper: one at a time, the first would be refused.
    with pytest.raises(hf.CaseError):
        case["geometry.outlet_width"] = 0.15
    case.update({"geometry.width": 0.2, "geometry.outlet_width": 0.15})
    assert case["geometry.outlet_width"] == 0.15


def test_a_refused_value_leaves_the_case_unchanged():
    case = hf.Case.paper()
    with pytest.raises(hf.CaseError):
        case["geometry.outlet_width"] = -1.0
    assert case["geometry.outlet_width"] == 0.03
    assert case.overrides == []


def test_copy_is_independent():
    case = hf.Case.paper()
    other = copy.deepcopy(case)
    other["particles.count"] = 100
    assert case["particles.count"] == 3000


@pytest.mark.parametrize(
    "key, value, words",
    [
        ("geometry.outlet_width", -1.0, "must be a finite number > 0"),
        ("geometry.outlet_width", math.nan, "must be a finite number > 0"),
        ("geometry.outlet_width", math.inf, "must be a finite number > 0"),
        ("geometry.outlet_width", 0.2, "must be < geometry.width"),
        ("geometry.outlet_width", "abc", "expected a number"),
        ("geometry.outlet_width", [1.0, 2.0], "expected a number"),
        ("particles.count", 2.5, "integer"),
        ("particles.count", 10**30, "signed 64-bit"),
        ("seed", None, "no TOML form"),
        ("seed", object(), "no TOML form"),
        ("contact.normal_clamp", "yes", "expected true or false"),
        ("geometry.nope", 1.0, "unknown key"),
        ("particles.coarse_graining", 0.5, "must lie in [1, 20]"),
        ("particles.coarse_graining", 30.0, "must lie in [1, 20]"),
        ("geometry.outlet_width=0.04", 1.0, "dotted name"),
        ("geometry..outlet_width", 1.0, "not a dotted key"),
    ],
)
def test_bad_values_raise_case_error_naming_the_key(key, value, words):
    case = hf.Case.paper()
    with pytest.raises(hf.CaseError) as info:
        case[key] = value
    err = info.value
    assert err.key == key
    assert words in str(err), str(err)
    assert err.message and err.message in str(err)
    assert isinstance(err, ValueError)
    assert err.errors and err.errors[0]["key"] == key


def test_cohesion_is_a_table_of_keys_like_any_other():
    # docs/physics.md §2.4–2.7: the law and its parameters, set together or key by key.
    case = hf.Case.paper()
    case["contact.cohesion"] = {"law": "jkr", "work_of_adhesion": 0.05}
    assert case["contact.cohesion"] == {"law": "jkr", "work_of_adhesion": 0.05}
    case["wall.cohesion"] = {
        "law": "liquid_bridge",
        "volume": 1e-12,
        "surface_tension": 0.072,
        "contact_angle_deg": 20.0,
    }
    # The resolved case gives the angle in radians and reads back to an equal case.
    assert math.isclose(case["wall.cohesion.contact_angle"], math.radians(20.0))
    assert hf.Case.from_toml(case.to_toml()) == case
    # Bad values are refused naming the key and the allowed range, the case unchanged.
    for key, value, words in [
        ("wall.cohesion.volume", 1e-9, "holds at most 0.1 R³"),
        ("wall.cohesion.contact_angle_deg", 120.0, "must lie in [0°, 90°]"),
        ("contact.cohesion.work_of_adhesion", -1.0, "must be a finite number > 0"),
        ("contact.cohesion.law", "glue", 'must be one of "none", "jkr"'),
    ]:
        before = case.to_toml()
        with pytest.raises(hf.CaseError) as info:
            case[key] = value
        assert info.value.key == key, str(info.value)
        assert words in str(info.value), str(info.value)
        assert case.to_toml() == before


def test_set_error_text_is_the_command_lines(cli, tiny):
    # `hopperflow check FILE --set geometry.outlet_width=-1` prints the same error text.
    proc = subprocess.run(
        [str(cli), "check", str(tiny), "--set", "geometry.outlet_width=-1.0"], capture_output=True, text=True
    )
    assert proc.returncode == 2
    case = hf.Case.load(str(tiny))
    with pytest.raises(hf.CaseError) as info:
        case["geometry.outlet_width"] = -1.0
    assert str(info.value) == proc.stderr.strip()


def test_file_errors_carry_the_line(tmp_path, cli):
    path = tmp_path / "bad.toml"
    path.write_text("version = 1\n[geometry]\noutlet_width = -0.03\n")
    with pytest.raises(hf.CaseError) as info:
        hf.Case.load(str(path))
    err = info.value
    assert (err.key, err.line) == ("geometry.outlet_width", 3)
    proc = subprocess.run([str(cli), "check", str(path)], capture_output=True, text=True)
    assert str(err) == proc.stderr.strip()


def test_every_error_of_a_file_is_listed(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text("version = 1\n[geometry]\noutlet_width = -0.03\nwidht = 0.1\n")
    with pytest.raises(hf.CaseError) as info:
        hf.Case.load(str(path))
    keys = {e["key"] for e in info.value.errors}
    assert {"geometry.outlet_width", "geometry.widht"} <= keys


def test_syntax_errors_and_empty_text():
    with pytest.raises(hf.CaseError) as info:
        hf.Case.from_toml("version = 1\n[geometry\n")
    assert info.value.line == 2
    with pytest.raises(hf.CaseError):
        hf.Case.from_toml("")
    with pytest.raises(hf.CaseError) as info:
        hf.Case.from_toml("version = 2\n")
    assert info.value.key == "version"


def test_from_dict_errors_name_the_key():
    with pytest.raises(hf.CaseError) as info:
        hf.Case.from_dict({"geometry": {"outlet_width": math.nan}})
    assert info.value.key == "geometry.outlet_width"
    with pytest.raises(TypeError):
        hf.Case.from_dict("geometry.outlet_width=0.04")  # type: ignore[arg-type]  # the misuse tested


def test_missing_file_and_wrong_key_types():
    with pytest.raises(FileNotFoundError):
        hf.Case.load("/nonexistent/case.toml")
    case = hf.Case.paper()
    with pytest.raises(TypeError):
        case[3] = 1.0  # type: ignore[index]  # the misuse tested
    with pytest.raises(KeyError):
        case["geometry.nope"]
    with pytest.raises(KeyError):
        case["geometry.width.x"]


def test_coarse_graining_simulates_parcels_and_keeps_the_grains_in_the_case():
    # docs/physics.md §2.8: 3000 grains of 3 mm at κ = 2 are 375 parcels of 6 mm; the case
    # keeps the grains and κ, and the estimate counts the parcels it would simulate. The
    # paper's slab is 1.01 grains thick: the parcels need one 1.01 parcels thick, and are
    # refused from the grains' slab with the keys that clash.
    case = hf.Case.paper()
    with pytest.raises(hf.CaseError) as info:
        case["particles.coarse_graining"] = 2.0
    assert "geometry.thickness" in str(info.value)
    assert "particles.coarse_graining = 2" in str(info.value)
    case["geometry.thickness"] = 0.00606
    case["particles.coarse_graining"] = 2.0
    assert case["particles.count"] == 3000
    assert case["particles.diameter"] == 0.003
    assert case["particles.coarse_graining"] == 2.0
    cost = hf.estimate(case)
    assert cost["particles"] == 375
