"""An identification as people read it: the report's lines and the materials file it writes.

The materials file is the shipped one's form (`elastic.materials`), with a
`[damping]` table and the fit's figures as comments above each constant, so
every command that builds the elastic body reads it with `--materials`.
"""

from __future__ import annotations

import math

import numpy as np

from hitogata.elastic.materials import Materials
from hitogata.validation.identify import PARAMETERS, PINNED, Identification

DISPLAY = {  # constant → (unit shown, factor from SI)
    "youngs_modulus": ("kPa", 1e-3),
    "poissons_ratio": ("", 1.0),
    "density": ("kg/m3", 1.0),
    "alpha": ("1/s", 1.0),
    "beta": ("s", 1.0),
}


def _shown(name: str, value: float) -> str:
    unit, factor = DISPLAY[name.split(".")[1]]
    return f"{value * factor:.4g}{(' ' + unit) if unit else ''}"


def _rms(z: np.ndarray) -> float:
    z = z[np.isfinite(z)]
    return float(np.sqrt(np.mean(z ** 2))) if z.size else math.nan


def _within(z: np.ndarray, limit: float = 2.0) -> str:
    z = z[np.isfinite(z)]
    return f"{int(np.sum(np.abs(z) <= limit))}/{z.size}" if z.size else "—"


def report_lines(fit: Identification) -> list[str]:
    """The fit in words and numbers: constants with intervals, rows with residuals and what they pin."""
    lines = [f"identified from {len(fit.rows)} rows in {fit.rounds} rounds of the full model:"]
    for k, p in enumerate(PARAMETERS):
        value = _shown(p.name, fit.constants[k])
        start = _shown(p.name, fit.start[k])
        if not fit.pinned[k]:
            lines.append(f"  {p.name:24s} {value:>12s}  not pinned by these rows (left at its start)")
            continue
        ci = fit.interval[k]
        span = "" if ci is None else f"  95 % {_shown(p.name, max(ci[0], 0.0))} … {_shown(p.name, ci[1])}"
        edge = "  (at the literature's bound)" if np.isclose(fit.constants[k], [p.low, p.high], rtol=1e-3).any() else ""
        lines.append(f"  {p.name:24s} {value:>12s}  (from {start}){span}{edge}")
    lines.append(f"rows: error in SD  (fit: RMS {_rms(fit.z):.2f}, within 2 SD {_within(fit.z)}; "
                 f"start: RMS {_rms(fit.z_start):.2f}; leave one source out: RMS {_rms(fit.cross_validated):.2f}, "
                 f"within 2 SD {_within(fit.cross_validated)})")
    for k, row in enumerate(fit.rows):
        strongest = int(np.argmax(np.abs(fit.sensitivity[k])))
        pins = fit.sensitivity[k, strongest]
        cv = fit.cross_validated[k]
        what = (f"pins {PARAMETERS[strongest].name} ({pins:+.2f} SD per +10 %)" if abs(pins) >= PINNED
                else "pins nothing (no constant moves it by 0.05 SD per +10 %)")
        lines.append(f"  {row.id:34s} {row.mean:8.3g} ± {row.sd:<6.2g} {row.unit:5s} model {fit.fitted[k]:8.3g}  "
                     f"z {fit.z[k]:+5.1f}  left out {'—' if not np.isfinite(cv) else f'{cv:+5.1f}'}  {what}")
    if fit.held_out:
        lines.append(f"held-out rows (not used in the fit): RMS {_rms(fit.z_held_out):.2f}, "
                     f"within 2 SD {_within(fit.z_held_out)}")
        lines += [f"  {r.id:34s} z {z:+5.1f}" for r, z in zip(fit.held_out, fit.z_held_out)]
    return lines


def materials_toml(fit: Identification, base: Materials, data: str) -> str:
    """The identified materials as a materials file, the fit's figures in its comments."""
    m = fit.materials(base)
    lines = ["# Tissue materials identified from published measurements of living people by",
             f"# `hitogata identify` (bounded least squares; rows: {data}).",
             "# Units: density kg/m^3, youngs_modulus Pa, alpha 1/s, beta s. The report:"]
    lines += [f"#   {line}" for line in report_lines(fit)]
    for region in ("bone", "viscera", "muscle", "skin"):
        r = m.regions[region]
        lines += ["", f"[{region}]", f"density = {r.rho:.6g}", f"youngs_modulus = {r.E:.6g}",
                  f"poissons_ratio = {r.nu:.6g}"]
    alpha, beta = m.rayleigh or (0.0, 0.0)
    lines += ["", "# Rayleigh damping of the soft tissue: C = alpha M + beta K", "[damping]", f"alpha = {alpha:.6g}",
              f"beta = {beta:.6g}", ""]
    return "\n".join(lines)
