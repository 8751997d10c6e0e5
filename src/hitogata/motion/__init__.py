"""Motion in: scenario files (their format, their body and their check against it), BVH files
retargeted onto the 65-part skeleton, scenarios as BVH (docs/motion.md, docs/scenarios.md). Above the
dynamics, which a scenario drives; a scenario is run, and its files written, by `hitogata.simulation`.
The names below are imported on first use (`hitogata.lazy`)."""

from typing import TYPE_CHECKING

from hitogata.lazy import lazy_names

if TYPE_CHECKING:
    from hitogata.motion.scenario import Scenario, load_scenario, shipped_scenarios

__all__ = ["Scenario", "load_scenario", "shipped_scenarios"]
__getattr__, __dir__ = lazy_names(globals(), {
    "Scenario": "hitogata.motion.scenario",
    "load_scenario": "hitogata.motion.scenario",
    "shipped_scenarios": "hitogata.motion.scenario",
})
