"""The IPC Toolkit (`ipctk`, MIT licence) set up once for hitogata's contact solves: the skin's self-contact
(`geometry.barrier_contact`) and the garment on the body (`garment.contact`).

- **One thread.** The toolkit's parallel loops (TBB) share out the sums of its barrier gradient and Hessian
  and its CCD's pairs among threads in an order that changes from run to run. A solve stopped at its
  iteration cap carries that round-off into its answer: the male's crossed arms moved 50 mm between two
  runs of one code on one machine (decision 0054). On one thread every answer repeats bit for bit; the
  parallelism is hitogata's own (a motion's frames in worker processes, the tests' workers).
- **Its log kept to errors.** Its one warning in a solve ("Initial distance … ≤ d_min, returning toi=0")
  says a pair starts a step within CCD's gap, so CCD allows the step no move; the solves answer that
  themselves (a stuck step, not convergence). Printed to the user it is noise.
"""

from __future__ import annotations

from functools import cache


@cache
def prepare_toolkit() -> None:
    """Set the toolkit to one thread and a log of errors only (once per process; imports it: half a second)."""
    import ipctk

    ipctk.set_num_threads(1)
    ipctk.set_logger_level(ipctk.LoggerLevel.error)
