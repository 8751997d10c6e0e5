"""The import paths the documentation once showed keep working: each hands over the same object from
its new package, with a DeprecationWarning that names the new path."""

import importlib
import sys

import pytest

# old module → (new package, names the documentation imported from the old path)
MOVED = {
    "hitogata.pose": ("hitogata.posing", ["PosedBody", "Poser", "pose_body", "poser_for"]),
    "hitogata.fit": ("hitogata.made_to_measure.scan_fit", ["Scan", "ScanFit", "detailed_body", "fit_scan", "make_scan"]),
    "hitogata.dynamics.single_pose": ("hitogata.skin.single_pose",
                                      ["ELEMENT_SIZE", "ElasticPose", "elastic_dynamics", "elastic_pose",
                                       "held_dynamics"]),
    "hitogata.measure.fine_skin": ("hitogata.skin.fine_skin",
                                   ["LEVELS", "FineSkin", "FineSkinning", "body_fine_skin", "body_fine_skinning",
                                    "fine_skinning", "subdivide"]),
}


@pytest.mark.parametrize("old", sorted(MOVED))
def test_an_old_documented_path_warns_and_hands_over_the_new_packages_names(old: str) -> None:
    new, names = MOVED[old]
    sys.modules.pop(old, None)
    with pytest.warns(DeprecationWarning, match=f"{old} is now {new}"):
        module = importlib.import_module(old)
    package = importlib.import_module(new)
    for name in names:
        assert getattr(module, name) is getattr(package, name), name
        assert name in dir(module)
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        module.nothing  # noqa: B018
