"""A stretch garment as a membrane of its fabric, in contact (IPC) with the rigid or soft body.

- `membrane`: the fabric's tensile curve along course and wale on a triangle mesh;
- `tube`: a tubular garment's rings along a segment;
- `spec`: garment files (TOML) and the shipped examples; `garment_mesh`: a garment given as its rest mesh (OBJ/PLY);
- `equilibrium`: the garment's (and a soft body's) equilibrium with the barrier;
- `pressure`: the contact forces as pressure on the skin;
- `readings`: what a user reads at the levels (pressure, indentation), which Newton stops on;
- `verify`: bodies with known answers (cylinders, ellipses, Lamé's thick-walled cylinder);
- `segments`: the levels and stations of a body segment;
- `dressing`: a garment put on the body; `answers`: its pressure at the levels and on the skin
  (its tables, GLB and picture: `hitogata.export.garment_files`); `motion`: the garment through a motion,
  each frame solved from the last.

`dress_garment(body, "legging")` is the one call from a body and a garment to its answers.
"""

from hitogata.garment.contact.answers import GarmentContact, LevelContact, dress_garment
from hitogata.garment.contact.equilibrium import ContactBody, Equilibrium, settle
from hitogata.garment.contact.membrane import Membrane
from hitogata.garment.contact.spec import GarmentSpec, load_garment, shipped_garments
from hitogata.garment.contact.tube import Stations, Tube, build_tube

__all__ = ["ContactBody", "Equilibrium", "GarmentContact", "GarmentSpec", "LevelContact", "dress_garment", "Membrane", "Stations", "Tube", "build_tube", "load_garment",
           "settle", "shipped_garments"]
