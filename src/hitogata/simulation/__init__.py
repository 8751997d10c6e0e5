"""A scenario run: its motion simulated with contact, its figures checked, its files written
(`run_scenario`, `hitogata simulate`), and the paper's demo (`demo.run_demo`, `hitogata demo`). Above the
dynamics and the files it writes (`hitogata.export.motion_files`). The names below are imported on first
use (`hitogata.lazy`)."""

from typing import TYPE_CHECKING

from hitogata.lazy import lazy_names

if TYPE_CHECKING:
    from hitogata.simulation.run import run_scenario

__all__ = ["run_scenario"]
__getattr__, __dir__ = lazy_names(globals(), {"run_scenario": "hitogata.simulation.run"})
