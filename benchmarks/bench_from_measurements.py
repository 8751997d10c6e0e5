"""Made-to-measure benchmark: a body from 6 measurements (goal ≤ 2 s, issue 15).

The request is the issue's example with a mass: a woman of 165 cm, chest 92, waist
74, hip 100, inside leg 76 cm, 60 kg. Printed: the first solve in the process
(it loads the data and finds the reference landmarks), then the median of later
solves, with the bodies measured and the Jacobians found per solve (each body
measured costs one `measure`, each Jacobian one `measurement_paths`), and the
worst residual in allowances.
"""

from __future__ import annotations

import statistics

from timing import timed

import hitogata.made_to_measure.solve as made
import hitogata.made_to_measure.measurement_rates as rates
from hitogata.made_to_measure.solve import allowance, body_to_measure

SIX = {"stature": 1.65, "chest": 0.92, "waist": 0.74, "hip": 1.00, "inside_leg": 0.76, "mass": 60.0}


def main() -> None:
    counts = {"measure": 0, "paths": 0}
    measure, paths = made.measure, rates.measurement_paths

    def counted_measure(body):  # type: ignore[no-untyped-def]
        counts["measure"] += 1
        return measure(body)

    def counted_paths(body):  # type: ignore[no-untyped-def]
        counts["paths"] += 1
        return paths(body)

    made.measure, rates.measurement_paths = counted_measure, counted_paths  # type: ignore[assignment]
    first = timed(lambda: body_to_measure("female", SIX), 1)[0]
    print(f"first solve in the process (data loaded, reference landmarks found): {first:.2f} s")
    print(f"  bodies measured {counts['measure']}, Jacobians found {counts['paths']}")
    times = timed(lambda: body_to_measure("female", SIX), 3)
    fit = body_to_measure("female", SIX)
    worst = max(abs(r) / allowance(n, fit.requested[n]) for n, r in fit.residuals.items())
    print(f"a body from 6 measurements: median {statistics.median(times):.2f} s of {len(times)} "
          f"(goal ≤ 2 s); worst residual {worst:.3f} allowances")
    for line in fit.lines():
        print("  " + line)


if __name__ == "__main__":
    main()
