"""`hitogata body --size-chart chart.csv --out sizes/`: one body per size of a size chart
(`hitogata.made_to_measure.size_chart` reads and checks it).

The whole chart is checked before any body is made. The folder gets `<size>.glb` per size and
`sizes.csv` (asked against made, cm and kg), written in a staging folder and renamed when all are done.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from hitogata.commands.args import BODY_DEFAULTS
from hitogata.errors import HitogataError
from hitogata.export.atomic import write_bytes_atomically
from hitogata.made_to_measure.size_chart import check_size_chart, read_size_chart


def write_size_chart(args: argparse.Namespace) -> None:
    """Check the chart and the options, then make, write and report one body per size."""
    from hitogata.commands.body import figures_line, solve_from_args
    from hitogata.export.body_files import write_body

    given = [options[-1] for name, options in args.measurement_options.items() if getattr(args, name) is not None]
    given += [option for option in ("--stature", "--mass") if getattr(args, BODY_DEFAULTS[option][0]) is not None]
    if given:
        raise HitogataError(f"{given[0]}: does not apply with --size-chart (the chart gives the measurements); "
                            f"leave out {', '.join(given)}")
    chart = read_size_chart(args.size_chart)
    check_size_chart(args.size_chart, chart, args.sex, args.age)  # before the first body is made
    lines = ["size,measurement,asked,made,difference,unit"]
    for size, asked, age in chart:
        try:
            body, fit = solve_from_args(argparse.Namespace(**{**vars(args), "age": args.age if age is None else age}),
                                        asked)
        except HitogataError as err:
            raise HitogataError(f"{args.size_chart}: size {size}: {err}") from None
        path = write_body(args.workdir / f"{size}.glb", body)
        print(figures_line(str(Path(args.out) / path.name), body))
        assert fit is not None
        for name, value in fit.requested.items():
            scale, unit = (1.0, "kg") if name == "mass" else (100.0, "cm")
            made = fit.achieved[name]
            lines.append(f"{size},{name},{value * scale:.2f},{made * scale:.2f},{(made - value) * scale:.2f},{unit}")
    write_bytes_atomically(args.workdir / "sizes.csv", ("\n".join(lines) + "\n").encode())
    print(f"{len(chart)} sizes; wrote {', '.join(f'{s}.glb' for s, _, _ in chart)} and sizes.csv in {Path(args.out)}/")
