"""A knitted garment as a membrane: the fabric's tensile curve along its course and its wale.

Each triangle of the garment has a rest (relaxed, as sewn) shape and two
fabric directions in it: the course (round the body) and the wale (along
it). With F the triangle's deformation gradient (3×2, rest frame: course,
wale), f = F e_c and g = F e_w are where the course and wale unit vectors
go; the stretches are λ = |f|, |g|, the shear γ = f·g. The energy per rest
area is

    W = Φ_c(|f| − 1) + Φ_w(|g| − 1) + ½ G γ²,    Φ(ε) = ∫₀^ε T(e) de,

T the fabric's tension (N/m, per unit relaxed width) at engineering strain
(`Fabric.tension`: zero in compression, where a knit buckles) and G its
shear stiffness (N/m per radian). The course and wale are uncoupled (a
biaxial test of a knit is rarely given; the uniaxial curves are what a
laboratory measures), so the tension along the course is T_c(ε_c) whatever
the wale does. Gradient and Hessian are exact but for the shear's γ∇²γ
term (Gauss–Newton: the Hessian stays positive semi-definite).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from hitogata.errors import HitogataError
from hitogata.garment.fabric import Fabric


def fabric_terms(fabric: Fabric, strain: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Φ(ε) (J/m²), T(ε) (N/m) and dT/dε (N/m) of a fabric's piecewise-linear curve, zero at ε ≤ 0."""
    x = np.asarray(fabric.strains, dtype=float)
    y = np.asarray(fabric.tensions, dtype=float)
    e = np.asarray(strain, dtype=float)
    slopes = np.diff(y) / np.diff(x)
    at_knots = np.concatenate([[0.0], np.cumsum(0.5 * (y[1:] + y[:-1]) * np.diff(x))])  # Φ at x[k] (x[0] = 0)
    k = np.clip(np.searchsorted(x, e, side="right") - 1, 0, len(x) - 2)
    d = e - x[k]
    tension = y[k] + slopes[k] * d
    phi = at_knots[k] + y[k] * d + 0.5 * slopes[k] * d * d
    stiffness = slopes[k].copy()
    slack = e <= 0.0
    return np.where(slack, 0.0, phi), np.where(slack, 0.0, tension), np.where(slack, 0.0, np.maximum(stiffness, 0.0))


@dataclass(frozen=True, eq=False)
class Membrane:
    """The garment's triangles with their rest shapes and fabric directions (see the module note)."""

    faces: np.ndarray  # (F, 3)
    rest_area: np.ndarray  # (F,) m²
    shape: np.ndarray  # (F, 3, 2): ∂F[:, a]/∂x_k for the face's corners k and directions a (course, wale)
    course: Fabric
    wale: Fabric
    shear: float  # N/m per radian
    n_vertices: int

    @classmethod
    def build(cls, rest: np.ndarray, faces: np.ndarray, course_direction: np.ndarray, course: Fabric,
              wale: Fabric, shear: float) -> Membrane:
        """A membrane from its rest shape (V, 3), faces (F, 3) and each face's course direction (F, 3)
        (projected into the face; the wale is the face normal × course)."""
        rest = np.asarray(rest, dtype=float)
        faces = np.asarray(faces, dtype=np.int64)
        e1, e2 = rest[faces[:, 1]] - rest[faces[:, 0]], rest[faces[:, 2]] - rest[faces[:, 0]]
        normal = np.cross(e1, e2)
        double_area = np.linalg.norm(normal, axis=1)
        if not (np.all(np.isfinite(double_area)) and np.all(double_area > 0)):
            raise HitogataError("garment mesh: a triangle of zero area in its rest shape; allowed non-degenerate triangles")
        normal /= double_area[:, None]
        c = np.asarray(course_direction, dtype=float)
        c = c - np.einsum("fi,fi->f", c, normal)[:, None] * normal
        length = np.linalg.norm(c, axis=1)
        if not np.all(length > 1e-9):
            raise HitogataError("garment mesh: a course direction normal to its triangle; allowed directions in the fabric")
        c /= length[:, None]
        w = np.cross(normal, c)
        dm = np.stack([np.stack([np.einsum("fi,fi->f", c, e1), np.einsum("fi,fi->f", c, e2)], axis=1),
                       np.stack([np.einsum("fi,fi->f", w, e1), np.einsum("fi,fi->f", w, e2)], axis=1)], axis=1)
        inverse = np.linalg.inv(dm)  # (F, 2, 2): F = [e1, e2] Dm⁻¹
        shape = np.zeros((len(faces), 3, 2))
        shape[:, 1], shape[:, 2] = inverse[:, 0], inverse[:, 1]
        shape[:, 0] = -inverse[:, 0] - inverse[:, 1]
        if not (np.isfinite(shear) and shear >= 0):
            raise HitogataError(f"fabric shear stiffness {shear!r} N/m: allowed a finite number ≥ 0")
        return cls(faces, 0.5 * double_area, shape, course, wale, float(shear), len(rest))

    def directions(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Where each face's course and wale unit vectors go at x (V, 3): f, g (F, 3) each."""
        corners = x[self.faces]  # (F, 3, 3)
        grad = np.einsum("fka,fki->fai", self.shape, corners)
        return grad[:, 0], grad[:, 1]

    def strains(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Engineering strain of each face along its course and its wale (F,) at x."""
        f, g = self.directions(x)
        return np.linalg.norm(f, axis=1) - 1.0, np.linalg.norm(g, axis=1) - 1.0

    def tensions(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Tension (N/m) of each face along its course and its wale (F,) at x."""
        ec, ew = self.strains(x)
        return fabric_terms(self.course, ec)[1], fabric_terms(self.wale, ew)[1]

    def energy(self, x: np.ndarray) -> float:
        f, g = self.directions(x)
        phi_c = fabric_terms(self.course, np.linalg.norm(f, axis=1) - 1.0)[0]
        phi_w = fabric_terms(self.wale, np.linalg.norm(g, axis=1) - 1.0)[0]
        gamma = np.einsum("fi,fi->f", f, g)
        return float(self.rest_area @ (phi_c + phi_w + 0.5 * self.shear * gamma ** 2))

    def derivatives(self, x: np.ndarray) -> tuple[float, np.ndarray, sp.csr_matrix]:
        """Energy (J), gradient (V, 3) and the positive semi-definite Hessian (3V × 3V, vertex-major) at x."""
        f, g = self.directions(x)
        lf, lg = np.linalg.norm(f, axis=1), np.linalg.norm(g, axis=1)
        phi_c, t_c, k_c = fabric_terms(self.course, lf - 1.0)
        phi_w, t_w, k_w = fabric_terms(self.wale, lg - 1.0)
        gamma = np.einsum("fi,fi->f", f, g)
        energy = float(self.rest_area @ (phi_c + phi_w + 0.5 * self.shear * gamma ** 2))
        fh, gh = f / lf[:, None], g / lg[:, None]
        # dW/dF: (F, 2, 3), rows course and wale
        dw = np.stack([t_c[:, None] * fh + self.shear * gamma[:, None] * g,
                       t_w[:, None] * gh + self.shear * gamma[:, None] * f], axis=1) * self.rest_area[:, None, None]
        gradient = np.zeros((self.n_vertices, 3))
        np.add.at(gradient, self.faces, np.einsum("fka,fai->fki", self.shape, dw))
        # d²W/dF²: (F, 2, 2, 3, 3); tension terms T/λ (I − uuᵀ) + dT uuᵀ, shear G ∇γ∇γᵀ with ∇γ = (g, f)
        eye = np.eye(3)
        hff = (k_c[:, None, None] * np.einsum("fi,fj->fij", fh, fh)
               + (t_c / lf)[:, None, None] * (eye - np.einsum("fi,fj->fij", fh, fh)))
        hgg = (k_w[:, None, None] * np.einsum("fi,fj->fij", gh, gh)
               + (t_w / lg)[:, None, None] * (eye - np.einsum("fi,fj->fij", gh, gh)))
        grad_gamma = np.stack([g, f], axis=1)  # (F, 2, 3)
        hF = self.shear * np.einsum("fai,fbj->fabij", grad_gamma, grad_gamma)
        hF[:, 0, 0] += hff
        hF[:, 1, 1] += hgg
        hF *= self.rest_area[:, None, None, None, None]
        # contracted pairwise (optimize): five times faster than einsum's one loop over all seven indices
        blocks = np.einsum("fka,fabij,flb->fkilj", self.shape, hF, self.shape,
                           optimize=True).reshape(len(self.faces), 9, 9)
        dofs = (3 * self.faces[:, :, None] + np.arange(3)).reshape(-1, 9)
        rows = np.repeat(dofs, 9, axis=1).ravel()
        cols = np.tile(dofs, (1, 9)).ravel()
        n = 3 * self.n_vertices
        hessian = sp.csr_matrix((blocks.ravel(), (rows, cols)), shape=(n, n))
        return energy, gradient, hessian
