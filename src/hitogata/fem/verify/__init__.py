"""Reference solutions and test meshes that check the FEM core; used only by tests and benchmarks.

Nothing in the pipeline imports this package. It holds what an independent
check needs: structured box and cantilever meshes (`box_mesh`,
`cantilever_system`), a direct time integrator and the exact response of a
damped linear system to compare the modal dynamics with (`newmark`,
`exact_response`), a static solver (`StaticSolver`, `solve_static`) and the
Poisson-ratio sweep that shows why the body uses quadratic elements
(`poisson_sweep`: linear tets lock as nu -> 0.5).
"""

from hitogata.fem.verify.box_mesh import box_mesh, cantilever_system
from hitogata.fem.verify.direct import exact_response, newmark
from hitogata.fem.verify.locking import PoissonSweep, poisson_sweep
from hitogata.fem.verify.static import StaticSolver, solve_static

__all__ = [
    "PoissonSweep",
    "StaticSolver",
    "box_mesh",
    "cantilever_system",
    "exact_response",
    "newmark",
    "poisson_sweep",
    "solve_static",
]
