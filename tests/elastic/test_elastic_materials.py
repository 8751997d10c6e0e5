"""The materials TOML: shipped defaults load; every kind of mistake is a one-line error naming the entry."""

from pathlib import Path

import pytest

from hitogata.elastic import default_materials_path, load_materials
from hitogata.errors import HitogataError
from hitogata.volume import REGIONS

GOOD = """
[bone]
density = 1900.0
youngs_modulus = "10GPa"
poissons_ratio = 0.3

[viscera]
density = 1040.0
youngs_modulus = 5000.0
poissons_ratio = 0.45

[muscle]
density = 1060
youngs_modulus = "25 kPa"
poissons_ratio = 0.49

[skin]
density = 920.0
youngs_modulus = "0.005MPa"
poissons_ratio = 0.49
"""


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "materials.toml"
    path.write_text(text)
    return path


def test_shipped_defaults_are_plausible():
    m = load_materials()
    assert m.source == str(default_materials_path())
    assert tuple(m.regions) == REGIONS
    soft = [m.regions[r] for r in ("viscera", "muscle", "skin")]
    assert all(1e3 <= x.E <= 1e5 for x in soft)  # soft tissue: kPa
    assert m.regions["bone"].E >= 1e9  # bone: GPa
    assert all(850 <= x.rho <= 1100 for x in soft) and 1500 <= m.regions["bone"].rho <= 2100
    assert all(0.3 <= x.nu < 0.5 for x in m.regions.values())


def test_units_and_plain_numbers(tmp_path):
    m = load_materials(write(tmp_path, GOOD))
    assert m.regions["bone"].E == 1e10
    assert m.regions["muscle"].E == pytest.approx(25e3) and m.regions["muscle"].rho == 1060.0
    assert m.regions["skin"].E == pytest.approx(5e3) and m.regions["viscera"].E == 5e3
    assert m.table(REGIONS)[2] is m.regions["muscle"]


@pytest.mark.parametrize("old, new, words", [
    ('youngs_modulus = "25 kPa"', "youngs_modulus = -25.0", ["[muscle]", "youngs_modulus", "-25.0", "> 0"]),
    ('youngs_modulus = "25 kPa"', "youngs_modulus = 0", ["[muscle]", "youngs_modulus", "> 0"]),
    ("poissons_ratio = 0.49\n\n[skin]", "poissons_ratio = 0.5\n\n[skin]",
     ["[muscle]", "poissons_ratio", "0.5", "nu < 0.5"]),
    ("poissons_ratio = 0.3", "poissons_ratio = -0.1", ["[bone]", "poissons_ratio", "-0.1"]),
    ("density = 920.0", "density = 0.0", ["[skin]", "density", "0.0", "> 0"]),
    ("density = 920.0", 'density = "heavy"', ["[skin]", "density", "heavy", "number"]),
    ('youngs_modulus = "10GPa"', 'youngs_modulus = "10 furlongs"', ["[bone]", "youngs_modulus", "furlongs", "GPa"]),
    ("[viscera]", "[liver]", ["[liver]", "unknown region", "viscera"]),
    ("density = 1040.0\n", "", ["[viscera]", "missing key 'density'"]),
    ("poissons_ratio = 0.45\n", "poissons_ratio = 0.45\nshear_modulus = 3\n",
     ["[viscera]", "unknown key 'shear_modulus'"]),
    ("[skin]", "[skin_and_fat]", ["[skin_and_fat]", "unknown region"]),
])
def test_each_mistake_is_one_line_naming_file_entry_and_value(tmp_path, old, new, words):
    assert old in GOOD
    path = write(tmp_path, GOOD.replace(old, new, 1))
    with pytest.raises(HitogataError) as info:
        load_materials(path)
    message = str(info.value)
    assert "\n" not in message
    assert str(path) in message
    for word in words:
        assert word in message


def test_missing_region_table(tmp_path):
    text = GOOD[: GOOD.index("[skin]")]
    with pytest.raises(HitogataError, match=r"no \[skin\] table"):
        load_materials(write(tmp_path, text))


def test_missing_and_malformed_files(tmp_path):
    with pytest.raises(HitogataError, match="no such file"):
        load_materials(tmp_path / "absent.toml")
    with pytest.raises(HitogataError, match="not valid TOML"):
        load_materials(write(tmp_path, "[bone\ndensity = 1"))
